#include "truth_csv.hpp"

#include "gimbalsim/firmware/csv_rows.hpp"

namespace gimbalsim::firmware {

bool TruthCsv::open(const std::string& path) {
  f_ = std::fopen(path.c_str(), "w");
  if (!f_) return false;
  std::fputs(csv::header<TruthFields>().c_str(), f_);
  return true;
}

void TruthCsv::write(const Truth& t) {
  if (f_) csv::writeRow<TruthFields>(f_, t);
}

bool TruthCsv::close() {
  if (!f_) return true;
  const bool ok = std::fclose(f_) == 0;
  f_ = nullptr;
  return ok;
}

}  // namespace gimbalsim::firmware
