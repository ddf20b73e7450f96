// --truth-csv: every truth message as one CSV row (csv_rows.hpp: header
// `name[unit]`, %.17g, so a row round-trips exactly; gimbalsim_log2csv
// writes the same bytes from a log).
#pragma once

#include <cstdio>
#include <string>

#include "gimbalsim/firmware/messages.hpp"

namespace gimbalsim::firmware {

class TruthCsv {
 public:
  TruthCsv() = default;
  TruthCsv(const TruthCsv&) = delete;
  TruthCsv& operator=(const TruthCsv&) = delete;
  ~TruthCsv() { close(); }

  /// Creates the file and writes the header; false (errno set) when it cannot.
  bool open(const std::string& path);
  /// One row; nothing when no file is open.
  void write(const Truth& t);
  /// False when writing failed; true when no file was open.
  bool close();

 private:
  std::FILE* f_ = nullptr;
};

}  // namespace gimbalsim::firmware
