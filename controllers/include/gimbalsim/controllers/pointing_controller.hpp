// The project's pointing controller behind the contract's ControllerPort:
// what the in-process closed loop (firmware_sim/closed_loop.hpp) drives, the
// same answerStatus() that pointing_controller runs over LCM.
#pragma once

#include <cstdint>

#include "gimbalsim/contract/controller_port.hpp"
#include "gimbalsim/controllers/answer.hpp"

namespace gimbalsim::controllers {

class PointingController final : public contract::ControllerPort {
 public:
  /// c must outlive the controller.
  explicit PointingController(const ControllerConfig& c) : c_(c) {}

  double period() const noexcept override { return c_.period; }
  contract::Command answer(const contract::Status& st, const contract::Attitude& att,
                           contract::ControllerReport& report) noexcept override;
  void noteAttitude(const contract::Attitude& att) noexcept override { controllers::noteAttitude(s_, att); }
  void noteAntenna(const contract::Antenna& antenna) noexcept override { noteAntennaReading(s_.fusion, antenna); }

  const ControllerConfig& config() const noexcept { return c_; }

 private:
  const ControllerConfig& c_;
  ControllerState s_;
  std::int64_t next_seq_ = 0;
};

}  // namespace gimbalsim::controllers
