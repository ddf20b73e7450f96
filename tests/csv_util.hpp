// Test helper: a CSV with a `name[unit]` header (firmware_sim --truth-csv,
// gimbalsim_log2csv), kept as text (exact comparisons) with numeric access
// by column name.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace gimbalsim::test {

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  static Csv read(const std::string& path) {
    Csv c;
    std::ifstream in(path);
    std::string line;
    auto split = [](const std::string& l) {
      std::vector<std::string> f;
      std::stringstream ss(l);
      std::string x;
      while (std::getline(ss, x, ',')) f.push_back(x);
      return f;
    };
    if (std::getline(in, line)) c.header = split(line);
    while (std::getline(in, line)) c.rows.push_back(split(line));
    return c;
  }
  int col(const std::string& name) const {
    for (size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return static_cast<int>(i);
    }
    ADD_FAILURE() << "no column " << name;
    return 0;
  }
  double num(size_t row, int c) const { return std::strtod(rows[row][c].c_str(), nullptr); }
  long long integer(size_t row, int c) const { return std::strtoll(rows[row][c].c_str(), nullptr, 10); }
};

}  // namespace gimbalsim::test
