#include "gimbalsim/firmware_sim/fault_schedule.hpp"

namespace gimbalsim::firmware {

const char* faultTypeName(FaultKind k) {
  switch (k) {
    case FaultKind::EncoderDropout: return "encoder_dropout";
    case FaultKind::EncoderStuck: return "encoder_stuck";
    case FaultKind::EncoderBias: return "encoder_bias";
    case FaultKind::EncoderNoise: return "encoder_noise";
    case FaultKind::StatusDelay: return "status_delay";
    case FaultKind::StatusDrop: return "status_drop";
    case FaultKind::CommandDelay: return "command_delay";
    case FaultKind::CommandDrop: return "command_drop";
    case FaultKind::TorqueLimit: return "torque_limit";
    case FaultKind::MotorFailure: return "motor_failure";
    case FaultKind::StarTrackerOutage: return "star_tracker_outage";
    case FaultKind::GyroBiasJump: return "gyro_bias_jump";
    case FaultKind::BearingWear: return "bearing_wear";
    case FaultKind::FrictionRise: return "friction_rise";
    case FaultKind::TrackerOutage: return "tracker_outage";
    case FaultKind::TrackerBias: return "tracker_bias";
    case FaultKind::TrackerDropout: return "tracker_dropout";
  }
  return "?";
}

bool faultHasAxis(FaultKind k) {
  switch (k) {
    case FaultKind::EncoderDropout:
    case FaultKind::EncoderStuck:
    case FaultKind::EncoderBias:
    case FaultKind::EncoderNoise:
    case FaultKind::TorqueLimit:
    case FaultKind::MotorFailure: return true;
    default: return false;
  }
}

}  // namespace gimbalsim::firmware
