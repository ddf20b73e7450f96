#include "gimbalsim/dynamics/step_result.hpp"

namespace gimbalsim {

const char* describe(StepStatus s) {
  switch (s) {
    case StepStatus::Ok: return "ok";
    case StepStatus::NonFinite: return "non-finite value (NaN or Inf) in the state";
    case StepStatus::VelocityLimit: return "a velocity exceeded sim.velocity_limit (diverging)";
    case StepStatus::PenetrationLimit:
      return "contact penetration exceeded sim.penetration_limit (contact too soft, step too large, or a clearance "
             "below what the load presses into the contact)";
    case StepStatus::SubstepCap:
      return "more work in one step than sim.max_substeps allows (the automatic cap has room for 4 located "
             "contact switches per step; a journal rattling faster needs a higher sim.max_substeps)";
    case StepStatus::EventNotLocated:
      return "contact switch not located within sim.max_event_iters iterations";
    case StepStatus::SubstepTooLong:
      return "sim.substep too long for the contact: an impact spans fewer sub-steps than "
             "sim.min_substeps_per_impact (reduce sim.substep or use sim.substep_policy=adaptive)";
  }
  return "unknown";
}

const char* limitKey(StepStatus s) {
  switch (s) {
    case StepStatus::Ok:
    case StepStatus::NonFinite: return "";
    case StepStatus::VelocityLimit: return "sim.velocity_limit";
    case StepStatus::PenetrationLimit: return "sim.penetration_limit";
    case StepStatus::SubstepCap: return "sim.max_substeps";
    case StepStatus::EventNotLocated: return "sim.max_event_iters";
    case StepStatus::SubstepTooLong: return "sim.min_substeps_per_impact";
  }
  return "";
}

}  // namespace gimbalsim
