// What a step returns: a status code, when it stopped, which coordinate, and
// the scene key of the limit that stopped it. Tools read these fields; no
// caller parses message text.
#pragma once

#include <cstdint>

namespace gimbalsim {

/// Why a step stopped. Every value but Ok means the step did not reach its
/// end: the state is left at the last accepted sub-step inside the step (a
/// good state, but not at the step's end time); callers keep it as the last
/// good state and do not step it again.
enum class StepStatus : std::uint8_t {
  Ok,
  NonFinite,         ///< NaN or Inf in the state or its derivative
  VelocityLimit,     ///< a velocity coordinate beyond sim.velocity_limit
  PenetrationLimit,  ///< contact penetration beyond sim.penetration_limit
  SubstepCap,        ///< more sub-steps than sim.max_substeps in one step
  EventNotLocated,   ///< a switch not located within sim.max_event_iters
  SubstepTooLong,    ///< fixed policy: an impact shorter than sim.min_substeps_per_impact sub-steps
};

/// One line for people.
const char* describe(StepStatus s);
/// The scene key whose limit the status names ("" for Ok and NonFinite,
/// which no setting causes).
const char* limitKey(StepStatus s);

struct StepResult {
  StepStatus status = StepStatus::Ok;
  double time = 0.0;  ///< when the step stopped [s] (unset when Ok)
  /// NonFinite / VelocityLimit: the offending coordinate, an index into q
  /// (q_index) or v (v_index); -1 when none.
  int q_index = -1, v_index = -1;
  /// PenetrationLimit: the penetration reached [m]; SubstepTooLong: the
  /// estimated impact duration [s]; 0 otherwise.
  double detail = 0.0;
  /// PenetrationLimit: the joint (0 azimuth, 1 elevation) whose bearing it is; -1 otherwise.
  int joint = -1;

  bool ok() const noexcept { return status == StepStatus::Ok; }
  const char* key() const noexcept { return limitKey(status); }
};

}  // namespace gimbalsim
