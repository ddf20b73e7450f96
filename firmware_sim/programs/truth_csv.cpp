#include "truth_csv.hpp"

#include "gimbalsim/firmware_sim/csv_rows.hpp"

namespace gimbalsim::firmware {

namespace {
constexpr int kSharedFields = 2;  // the antenna message's utime and seq: the truth's own
}

bool TruthCsv::open(const std::string& path, const std::vector<std::string>& inputs, std::string* why, bool antenna) {
  try {
    out_.emplace(path, inputs);
  } catch (const io::OutputError& e) {
    if (why) *why = e.what();
    return false;
  }
  antenna_ = antenna;
  std::string h = csv::header<TruthFields>();
  if (antenna) h.back() = ',', h += csv::header<AntennaFields>(kSharedFields);
  return out_->write(h);
}

bool TruthCsv::write(const Truth& t, const Antenna* a) {
  if (!out_) return true;
  csv::writeRow<TruthFields>(out_->stream(), t, !antenna_);
  // Both loops hand the tick's antenna message with its truth; a default one keeps a row whole regardless.
  if (antenna_) csv::continueRow<AntennaFields>(out_->stream(), a != nullptr ? *a : Antenna{}, kSharedFields);
  return out_->ok();
}

}  // namespace gimbalsim::firmware
