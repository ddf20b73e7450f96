// The backlash guard of one axis (key <axis>.play_inertia):
// where a bearing's play lies between the motor and the antenna (a spatial
// elevation journal that tilts lets shaft 1 turn about the azimuth axis
// against the antenna), the motor alone is light. A rate gain kd made for the
// whole chain then gives kd Ts / J_play >> 1 inside the play: the loop is
// unstable there and limit-cycles across it at the torque limit. The guard
// watches the inertia its own commands move and, once it has seen the light
// side, steps that axis with a rate gain the light side can take for the rest
// of the run (docs/MODEL.md 11.5, "The controller across a play").
// No allocation, no exception; a fixed-size state.
#pragma once

#include <array>
#include <cmath>

#include "gimbalsim/dynamics/spatial.hpp"

namespace gimbalsim::controllers {

/// Memory of the guard, both axes (part of ControllerState).
struct PlayGuardState {
  Vec2 rate_prev = Vec2::Zero();      ///< rate the law used at the previous tick [rad/s]
  Vec2 tau_prev = Vec2::Zero();       ///< command of the previous tick [N m]
  Vec2 tau_prev2 = Vec2::Zero();      ///< command of the tick before: it acted over the last period [N m]
  int primed = 0;                     ///< ticks of history held (2: tau_prev2 is a command)
  std::array<bool, 2> seen{};         ///< the play was seen on this axis: its play gains from then on
};

/// On the play gains the rate gain is kappa J_play / Ts: with the bus's one
/// tick of latency the light side's rate error obeys e[k+2] = e[k+1] - g e[k],
/// g = kd Ts / J, whose roots have |z| = sqrt(g) (0.71 a tick at g = 0.5) and
/// which is unstable beyond g = 1.
inline constexpr double kPlayRateGain = 0.5;
/// Without the antenna's sensors (antennaHeard false) the law inside the
/// play sees only the motor, and a softer rate gain lets the antenna wander
/// less across the hidden play (docs/MODEL.md 11.5: paper_both_spatial at
/// 0.8 mm 3.3e-2 -> 2.8e-2 rad RMS). The light side under the chain's kp
/// stays stable down to about 0.31 (|z| 0.98 at 0.375, 0.96 at 0.5). With
/// the antenna's sensors 0.5 stays: it acts only while the loop at the
/// antenna is not engaged (paper_both_spatial, 0.8 mm: 1.7e-4 against 6.4e-4).
inline constexpr double kPlayRateGainEncoders = 0.375;
/// Evidence counts only for commands above this fraction of the torque limit:
/// below it the rate change is within what the chain's coupling explains.
inline constexpr double kPlayEvidenceTorque = 0.01;

/// Whether the last period's rate change shows the play: the command that
/// acted over it (the one sent two ticks ago, one tick of bus latency)
/// changed the rate by between half and twice what it would on the light
/// side alone (the whole chain, J_chain >> J_play, would take a small
/// fraction). A change beyond twice is not the command's: an impact's
/// friction kicked the shaft (a planar journal after a motor failure, a
/// rigid chain whose guard then held the light side's gains for the run).
inline bool playEvidence(double rate_change, double tau_acting, double period, double play_inertia,
                         double torque_limit) noexcept {
  if (std::fabs(tau_acting) < kPlayEvidenceTorque * torque_limit) return false;
  const double light_side_change = std::fabs(period * tau_acting / play_inertia);
  const double along = rate_change * std::copysign(1.0, tau_acting);
  return along > 0.5 * light_side_change && along < 2.0 * light_side_change;
}

}  // namespace gimbalsim::controllers
