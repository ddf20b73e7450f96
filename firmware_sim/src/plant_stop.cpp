#include "gimbalsim/firmware_sim/plant_stop.hpp"

#include "gimbalsim/dynamics/simulate.hpp"

namespace gimbalsim::firmware {

std::string describePlantStop(const Model& m, double last_good_s, const StepResult& st) {
  return "the plant stopped after t = " + describeStopWhen(last_good_s, st) + ": " + describeStopCause(m, st);
}

}  // namespace gimbalsim::firmware
