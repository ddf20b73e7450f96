#include "truth_csv.hpp"

#include "gimbalsim/firmware/csv_rows.hpp"

namespace gimbalsim::firmware {

bool TruthCsv::open(const std::string& path, const std::vector<std::string>& inputs, std::string* why) {
  return out_.open(path, why, inputs) && out_.puts(csv::header<TruthFields>().c_str());
}

bool TruthCsv::write(const Truth& t) {
  if (!out_.isOpen()) return true;
  csv::writeRow<TruthFields>(out_.file(), t);
  return out_.ok();
}

bool TruthCsv::close(std::string* why) {
  if (!out_.isOpen()) return true;
  return out_.commit(why);
}

}  // namespace gimbalsim::firmware
