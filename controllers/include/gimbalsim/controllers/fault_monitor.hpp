// What the pointing controller can see of a misbehaving gimbal, from the
// messages alone (never from the simulator's injected_faults field), and the
// state it keeps for that. answerStatus() (answer.hpp) runs it before
// the law and applies the reactions (docs/bench.md "Faults the
// controller detects"):
//  - stale status: the status is older than the newest attitude message by
//    monitor.stale_ticks or more (the attitude of every tick comes first and
//    is the controller's clock): hold the last command computed from a fresh
//    status, integral frozen; stale longer than monitor.hold_ticks: safe
//    torque (zero). A gap in the status seq is counted (dropped statuses).
//  - encoder suspect (stuck or dropped out), per axis: over each window of
//    monitor.stuck_window consecutive statuses the encoder angle moved by
//    more (or less) than the integral of the reported rate, by more than
//    monitor.stuck_tol: the position and integral terms of that axis are
//    dropped (rate feedback and feed-forward only: the rate sensor is
//    independent of the encoder) until a window shows the encoder moving
//    with the rate again. Blind when the axis is at rest (no motion to
//    compare), and a window straddling the onset may pass.
//  - star tracker outage: reported by the sensor itself; flagged, the
//    attitude estimate coasts on the gyro (inertial_reference.cpp).
// noexcept, no allocation.
#pragma once

#include <cstdint>

#include "gimbalsim/contract/controller_port.hpp"

namespace gimbalsim::controllers {

/// Keys monitor.* (config.cpp).
struct MonitorConfig {
  int stale_ticks = 40;       ///< status this many ticks older than the newest attitude: stale [ticks]
  int hold_ticks = 200;       ///< stale this many statuses in a row: safe torque [ticks]
  int stuck_window = 20;      ///< statuses per encoder/rate comparison [-]
  double stuck_tol = 5.0e-5;  ///< [rad] |encoder motion - integrated rate| above this: encoder suspect
};

/// What the monitor concluded for one status (part of the controller's report, the contract's).
using contract::MonitorFlags;

struct MonitorState {
  std::int64_t last_seq = -1;         ///< seq of the last status seen
  std::int64_t stale_run = 0;         ///< stale statuses in a row
  bool suspect[2] = {};
  // the current comparison window
  int window_n = 0;
  double window_theta0[2] = {}, window_rate_int[2] = {}, prev_rate[2] = {};
  double hold_tau[2] = {};            ///< [N m] the last command computed from a fresh status
  // counters (summary, tests)
  long long stale_statuses = 0, missing_statuses = 0, safe_statuses = 0;
  long long suspect_onsets[2] = {};
};

/// Observes status (seq, angles, rates) against the newest attitude seq.
MonitorFlags observeStatus(const MonitorConfig& c, MonitorState& s, double period, std::int64_t seq,
                           const double angle[2], const double rate[2], std::int64_t attitude_seq,
                           bool star_outage) noexcept;

}  // namespace gimbalsim::controllers
