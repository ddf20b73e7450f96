#include "gimbalsim/controllers/pointing_controller.hpp"

namespace gimbalsim::controllers {

contract::Command PointingController::answer(const contract::Status& st, const contract::Attitude& att,
                                             contract::ControllerReport& report) noexcept {
  const long long rejected_before = s_.rejected_readings;
  const Answer a = answerStatus(c_, s_, st, att, next_seq_);
  report.ref = a.out.ref;
  report.theta_meas = a.meas.theta;
  // The newest measured offset, not the rate-limited one the law is moving toward it: what it knows.
  report.antenna_offset = s_.fusion.measured ? s_.fusion.offset_measured : Vec2::Zero();
  report.tau_cmd = a.out.tau;
  report.q_WB_est = a.out.q_WB_est;
  report.star_outage = a.out.star_outage;
  report.saturated[0] = a.out.saturated[0];
  report.saturated[1] = a.out.saturated[1];
  report.in_play[0] = a.out.in_play[0];
  report.in_play[1] = a.out.in_play[1];
  report.flags = a.flags;
  report.reading_rejected = a.out.rejected || s_.rejected_readings != rejected_before;
  return a.cmd;
}

}  // namespace gimbalsim::controllers
