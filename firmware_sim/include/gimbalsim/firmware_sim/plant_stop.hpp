// The one sentence for a plant that stopped, shared by firmware_sim's
// summary and the in-process closed loop so that the bench and a sweep say
// the same thing of the same run.
#pragma once

#include <string>

#include "gimbalsim/dynamics/model.hpp"
#include "gimbalsim/dynamics/step_result.hpp"

namespace gimbalsim::firmware {

/// "the plant stopped after t = <describeStopWhen>: <describeStopCause>":
/// when (its last good state, last_good_s [s]) and why its step st failed.
std::string describePlantStop(const Model& m, double last_good_s, const StepResult& st);

}  // namespace gimbalsim::firmware
