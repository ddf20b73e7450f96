#include "truth_csv.hpp"

#include "gimbalsim/firmware_sim/csv_rows.hpp"

namespace gimbalsim::firmware {

bool TruthCsv::open(const std::string& path, const std::vector<std::string>& inputs, std::string* why) {
  try {
    out_.emplace(path, inputs);
  } catch (const io::OutputError& e) {
    if (why) *why = e.what();
    return false;
  }
  return out_->write(csv::header<TruthFields>());
}

bool TruthCsv::write(const Truth& t) {
  if (!out_) return true;
  csv::writeRow<TruthFields>(out_->stream(), t);
  return out_->ok();
}

}  // namespace gimbalsim::firmware
