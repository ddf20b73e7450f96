// Test helper: a CSV with a header row (firmware_sim --truth-csv and
// gimbalsim_log2csv with `name_unit` columns, gimbalsim_workprec), kept as
// text (exact comparisons) with numeric access by column name.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace gimbalsim::test {

struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  /// Fields of one line: split at the commas outside double quotes, the quotes
  /// dropped; a final comma ends an empty last field ("a," is two fields), as
  /// every CSV reader has it (an empty text cell is never quoted).
  static std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> f;
    std::string cur;
    bool quoted = false, open = false;  // open: a field has begun since the last comma
    for (char c : line) {
      if (c == '"') {
        quoted = !quoted;
      } else if (c == ',' && !quoted) {
        f.push_back(cur);
        cur.clear();
        open = false;
        continue;
      } else {
        cur += c;
      }
      open = true;
    }
    if (open || !f.empty()) f.push_back(cur);
    return f;
  }

  static Csv read(const std::string& path) {
    Csv c;
    std::ifstream in(path);
    std::string line;
    if (std::getline(in, line)) c.header = split(line);
    while (std::getline(in, line)) c.rows.push_back(split(line));
    return c;
  }
  /// The rows as maps column -> text.
  std::vector<std::map<std::string, std::string>> records() const {
    std::vector<std::map<std::string, std::string>> out;
    for (const auto& f : rows) {
      std::map<std::string, std::string> r;
      for (std::size_t i = 0; i < f.size() && i < header.size(); ++i) r[header[i]] = f[i];
      out.push_back(r);
    }
    return out;
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
