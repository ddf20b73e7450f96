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
/// Evidence counts only for commands above this fraction of the torque limit:
/// below it the rate change is within what the chain's coupling explains.
inline constexpr double kPlayEvidenceTorque = 0.01;

/// Whether the last period's rate change shows the play: the command that
/// acted over it (the one sent two ticks ago, one tick of bus latency)
/// changed the rate by more than half of what it would on the light side
/// alone (the whole chain, J_chain >> J_play, would take a small fraction).
inline bool playEvidence(double rate_change, double tau_acting, double period, double play_inertia,
                         double torque_limit) noexcept {
  if (std::fabs(tau_acting) < kPlayEvidenceTorque * torque_limit) return false;
  const double light_side_change = period * tau_acting / play_inertia;
  return rate_change * std::copysign(1.0, tau_acting) > 0.5 * std::fabs(light_side_change);
}

}  // namespace gimbalsim::controllers
