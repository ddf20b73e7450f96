// --truth-csv: every truth message as one CSV row, followed (a scene with the
// antenna's sensors) by the tick's antenna message without its utime and seq (csv_rows.hpp: header
// `name_unit`, round-trip numbers (io/csv_format.hpp); gimbalsim_log2csv
// writes the same bytes from a log). Written through io::OutputFile:
// checked writes into a temporary file renamed over the target at the end of
// the run (also after SIGINT/SIGTERM), together with --tick-log, so the file under the requested name
// is always whole rows of a finished run; never through a symbolic link, never
// over an input.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/contract/messages.hpp"

namespace gimbalsim::firmware {
// The bench messages are the contract's (lcmtypes/contract), shared with the controller.
using namespace gimbalsim::contract;  // NOLINT(google-build-using-namespace)

class TruthCsv {
 public:
  /// Creates the temporary file and writes the header (with the antenna's
  /// columns when `antenna`); false with *why.
  bool open(const std::string& path, const std::vector<std::string>& inputs, std::string* why, bool antenna);
  /// One row: the truth, then the same tick's antenna message (open with
  /// `antenna`: never null). Nothing when no file is open. False once a write failed.
  bool write(const Truth& t, const Antenna* a);
  /// The open file (null when none), committed with the run's other outputs
  /// as one io::CommitGroup (main.cpp).
  io::OutputFile* file() noexcept { return out_ ? &*out_ : nullptr; }

 private:
  std::optional<io::OutputFile> out_;
  bool antenna_ = false;
};

}  // namespace gimbalsim::firmware
