// The bench messages without LCM (Command, Status, Truth, Attitude, Antenna:
// the firmware core's view of gimbal_command_t, gimbal_status_t,
// gimbal_truth_t, gimbal_attitude_t, gimbal_antenna_t) and the one list
// of each message's fields.
//
// A field list names every field once, in message order, with its CSV
// columns (`name[unit]`, one per element; the CSV writes them `name_unit`,
// io::csvNameOf). It is a visitor over any number of
// objects that share the field names (the struct here and the lcm-gen type):
//   TruthFields::visit(f, a, b)  calls  f(Columns{"utime[us]"}, a.utime, b.utime), ...
// Everything that maps a message field by field goes through it: the copy
// into and out of the LCM types (firmware_sim/programs/lcm_bridge.cpp), the CSV
// header and rows (csv_rows.hpp, for --truth-csv and gimbalsim_log2csv), and
// the test that the list covers the encoded message (tests/lcm). A field added
// to a .lcm file is added here and nowhere else.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>

namespace gimbalsim::contract {

/// Fault bits of Status::faults; the same values as gimbal_status_t's
/// FAULT_* constants (lcm_bridge.cpp static_asserts it).
enum Fault : std::int32_t {
  kWatchdogTripped = 1,   ///< no valid command within the watchdog time: safe command applied
  kTorqueSaturated = 2,   ///< the requested torque was clipped to the motor limit
  kCommandRejected = 4,   ///< a command was rejected since the previous tick
  kPlantFault = 8,        ///< plant integration failed; state frozen (latched)
  kLockstepTimeout = 16,  ///< lockstep: no answer within the timeout (set by the loop)
};

/// Command modes (gimbal_command_t::MODE_*).
enum Mode : std::int8_t { kModeOff = 0, kModeTorque = 1 };

/// Answered statuses after which a plant that accepted none of a
/// controller's commands has had its chance: the run controlled nothing
/// (pointing_controller exits 3; the in-process loop is not ok).
inline constexpr long long kStatusesToJudge = 3;

/// Commands the plant rejected in a row after which a run ends, stopped: the
/// lockstep bench's count at its defaults (--start-timeout 30 s of
/// --lockstep-timeout-ms 1000 per rejected answer), so the in-process loop
/// ends where the bench does rather than report a run the plant mostly refused.
inline constexpr long long kRejectedInARow = 30;

/// A decoded command (gimbal_command_t without LCM).
struct Command {
  std::int64_t utime = 0;       ///< [us]
  std::int64_t seq = 0;         ///< [-]
  std::int64_t status_seq = 0;  ///< [-] status answered
  std::int8_t mode = kModeOff;
  double torque[2] = {0.0, 0.0};  ///< [N m] azimuth, elevation
};

/// The firmware's status report (gimbal_status_t without LCM).
struct Status {
  std::int64_t utime = 0;         ///< [us]
  std::int64_t seq = 0;           ///< [-] tick index
  double angle[2] = {0.0, 0.0};   ///< [rad] encoder angles theta1, theta2 (quantized)
  double rate[2] = {0.0, 0.0};    ///< [rad/s]
  double applied_torque[2] = {0.0, 0.0};  ///< [N m] from t_k over the next period
  std::int32_t faults = 0;        ///< Fault bits
  std::int64_t last_command_seq = -1;
  std::int64_t commands_received = 0, commands_rejected = 0, commands_missed = 0;
  std::int64_t injected_faults = 0; ///< fault_schedule.hpp injectedBit() of every scheduled fault active in this tick
};

/// Simulator-only truth at t_k (gimbal_truth_t without LCM).
struct Truth {
  std::int64_t utime = 0;          ///< [us]
  std::int64_t seq = 0;            ///< [-]
  double sim_time = 0.0;           ///< [s]
  double base_position[3] = {};    ///< [m] inertial
  double base_quaternion[4] = {1.0, 0.0, 0.0, 0.0};  ///< (w, x, y, z), base -> inertial
  double base_rate[3] = {};        ///< [rad/s] base frame
  double base_velocity[3] = {};    ///< [m/s] inertial
  double joint_angle[2] = {};      ///< [rad]
  double joint_rate[2] = {};       ///< [rad/s]
  double applied_torque[2] = {};   ///< [N m]
  double eccentricity[4] = {};     ///< [m] joint 1 (x, y), joint 2 (x, y), each in its joint plane basis
  double penetration[2] = {};      ///< [m] joint 1, joint 2 (a spatial joint's deeper end)
  double contact_normal_force[2] = {}, contact_tangential_force[2] = {};  ///< [N] joint 1, joint 2 (summed over ends)
  double joint2_force = 0.0;       ///< [N]
  double tilt[2] = {};             ///< [rad] gamma of each spatial joint's journal
  double end_penetration[4] = {};  ///< [m] joint 1 at -L/2, +L/2, then joint 2
  double end_normal_force[4] = {}; ///< [N] the same ends
  double boresight[3] = {};        ///< unit, inertial
  double target_boresight[3] = {}; ///< unit, inertial
  double pointing_error = 0.0;     ///< [rad]
  double momentum_linear[3] = {};  ///< [N s] inertial
  double momentum_angular[3] = {}; ///< [N m s] about the inertial origin
  double energy = 0.0;             ///< [J]
  std::int32_t faults = 0;
  std::int64_t injected_faults = 0; ///< as Status::injected_faults
};

/// The base attitude sensors of tick k (gimbal_attitude_t without LCM;
/// attitude_sensors.hpp). Star tracker fields hold the last delivered sample
/// when star_valid is 0.
struct Attitude {
  std::int64_t utime = 0;           ///< [us]
  std::int64_t seq = 0;             ///< [-] tick index
  double gyro_time = 0.0;           ///< [s] sample time of gyro_rate (t_k)
  double gyro_rate[3] = {};         ///< [rad/s] base angular rate, base frame (bias and noise included)
  std::int8_t star_valid = 0;       ///< [-] 1: a new star tracker sample was delivered this tick
  double star_time = -1.0;          ///< [s] sample time t_s of star_quaternion (-1: none delivered yet)
  double star_quaternion[4] = {1.0, 0.0, 0.0, 0.0};  ///< (w, x, y, z), base -> inertial
  std::int8_t star_outage = 0;      ///< [-] 1: star tracker outage at t_k
};

/// The antenna's own sensors at tick k (gimbal_antenna_t without LCM;
/// firmware_sim/antenna_sensors.hpp): a two-axis boresight tracker (the
/// rotation that takes the boresight onto the target's line of sight, in the
/// antenna frame, on its axes u = the elevation axis and v = boresight x u, as
/// a monopulse tracker reports the target's offset) and a rate gyro on the
/// antenna. Tracker fields hold the last delivered sample when tracker_valid is 0.
struct Antenna {
  std::int64_t utime = 0;            ///< [us]
  std::int64_t seq = 0;              ///< [-] tick index
  std::int8_t tracker_valid = 0;     ///< [-] 1: a new tracker sample was delivered this tick
  double tracker_time = -1.0;        ///< [s] sample time of tracker_error (-1: none delivered yet)
  double tracker_error[2] = {};      ///< [rad] rotation boresight -> target about u (elevation axis) and v, antenna frame
  std::int8_t tracker_outage = 0;    ///< [-] 1: tracker outage at t_k (no sample taken or delivered)
  double gyro_time = 0.0;            ///< [s] sample time of gyro_rate (t_k)
  double gyro_rate[3] = {};          ///< [rad/s] antenna angular rate, antenna frame (bias and noise included)
};

/// CSV column names of one field, one per element.
using Columns = std::initializer_list<const char*>;

/// gimbal_truth_t / Truth.
struct TruthFields {
  template <class F, class... M>
  static void visit(F&& f, M&... m) {
    f(Columns{"utime[us]"}, m.utime...);
    f(Columns{"seq[-]"}, m.seq...);
    f(Columns{"sim_time[s]"}, m.sim_time...);
    f(Columns{"base_x[m]", "base_y[m]", "base_z[m]"}, m.base_position...);
    f(Columns{"base_qw[-]", "base_qx[-]", "base_qy[-]", "base_qz[-]"}, m.base_quaternion...);
    f(Columns{"base_wx[rad/s]", "base_wy[rad/s]", "base_wz[rad/s]"}, m.base_rate...);
    f(Columns{"base_vx[m/s]", "base_vy[m/s]", "base_vz[m/s]"}, m.base_velocity...);
    f(Columns{"theta1[rad]", "theta2[rad]"}, m.joint_angle...);
    f(Columns{"dtheta1[rad/s]", "dtheta2[rad/s]"}, m.joint_rate...);
    f(Columns{"tau1[N m]", "tau2[N m]"}, m.applied_torque...);
    f(Columns{"ecc1_x[m]", "ecc1_y[m]", "ecc2_x[m]", "ecc2_y[m]"}, m.eccentricity...);
    f(Columns{"delta1[m]", "delta2[m]"}, m.penetration...);
    f(Columns{"fn1[N]", "fn2[N]"}, m.contact_normal_force...);
    f(Columns{"ft1[N]", "ft2[N]"}, m.contact_tangential_force...);
    f(Columns{"joint2_force[N]"}, m.joint2_force...);
    f(Columns{"tilt1[rad]", "tilt2[rad]"}, m.tilt...);
    f(Columns{"delta1_minus[m]", "delta1_plus[m]", "delta2_minus[m]", "delta2_plus[m]"}, m.end_penetration...);
    f(Columns{"fn1_minus[N]", "fn1_plus[N]", "fn2_minus[N]", "fn2_plus[N]"}, m.end_normal_force...);
    f(Columns{"bore_x[-]", "bore_y[-]", "bore_z[-]"}, m.boresight...);
    f(Columns{"target_x[-]", "target_y[-]", "target_z[-]"}, m.target_boresight...);
    f(Columns{"pointing_error[rad]"}, m.pointing_error...);
    f(Columns{"mom_px[N s]", "mom_py[N s]", "mom_pz[N s]"}, m.momentum_linear...);
    f(Columns{"mom_lx[N m s]", "mom_ly[N m s]", "mom_lz[N m s]"}, m.momentum_angular...);
    f(Columns{"energy[J]"}, m.energy...);
    f(Columns{"faults[-]"}, m.faults...);
    f(Columns{"injected_faults[-]"}, m.injected_faults...);
  }
};

/// gimbal_attitude_t / Attitude.
struct AttitudeFields {
  template <class F, class... M>
  static void visit(F&& f, M&... m) {
    f(Columns{"utime[us]"}, m.utime...);
    f(Columns{"seq[-]"}, m.seq...);
    f(Columns{"gyro_time[s]"}, m.gyro_time...);
    f(Columns{"gyro_wx[rad/s]", "gyro_wy[rad/s]", "gyro_wz[rad/s]"}, m.gyro_rate...);
    f(Columns{"star_valid[-]"}, m.star_valid...);
    f(Columns{"star_time[s]"}, m.star_time...);
    f(Columns{"star_qw[-]", "star_qx[-]", "star_qy[-]", "star_qz[-]"}, m.star_quaternion...);
    f(Columns{"star_outage[-]"}, m.star_outage...);
  }
};

/// gimbal_status_t / Status.
struct StatusFields {
  template <class F, class... M>
  static void visit(F&& f, M&... m) {
    f(Columns{"utime[us]"}, m.utime...);
    f(Columns{"seq[-]"}, m.seq...);
    f(Columns{"angle1[rad]", "angle2[rad]"}, m.angle...);
    f(Columns{"rate1[rad/s]", "rate2[rad/s]"}, m.rate...);
    f(Columns{"tau1[N m]", "tau2[N m]"}, m.applied_torque...);
    f(Columns{"faults[-]"}, m.faults...);
    f(Columns{"last_command_seq[-]"}, m.last_command_seq...);
    f(Columns{"commands_received[-]"}, m.commands_received...);
    f(Columns{"commands_rejected[-]"}, m.commands_rejected...);
    f(Columns{"commands_missed[-]"}, m.commands_missed...);
    f(Columns{"injected_faults[-]"}, m.injected_faults...);
  }
};

/// gimbal_command_t / Command.
struct CommandFields {
  template <class F, class... M>
  static void visit(F&& f, M&... m) {
    f(Columns{"utime[us]"}, m.utime...);
    f(Columns{"seq[-]"}, m.seq...);
    f(Columns{"status_seq[-]"}, m.status_seq...);
    f(Columns{"mode[-]"}, m.mode...);
    f(Columns{"tau1[N m]", "tau2[N m]"}, m.torque...);
  }
};

/// gimbal_loop_stats_t (no LCM-free twin: firmware_sim fills it from its
/// statistics, lcm_bridge.cpp).
struct LoopStatsFields {
  template <class F, class... M>
  static void visit(F&& f, M&... m) {
    f(Columns{"utime[us]"}, m.utime...);
    f(Columns{"ticks[-]"}, m.ticks...);
    f(Columns{"period_p50[us]"}, m.period_p50...);
    f(Columns{"period_p99[us]"}, m.period_p99...);
    f(Columns{"period_p999[us]"}, m.period_p999...);
    f(Columns{"period_max[us]"}, m.period_max...);
    f(Columns{"lateness_p50[us]"}, m.lateness_p50...);
    f(Columns{"lateness_p99[us]"}, m.lateness_p99...);
    f(Columns{"lateness_p999[us]"}, m.lateness_p999...);
    f(Columns{"lateness_max[us]"}, m.lateness_max...);
    f(Columns{"compute_p50[us]"}, m.compute_p50...);
    f(Columns{"compute_p99[us]"}, m.compute_p99...);
    f(Columns{"compute_max[us]"}, m.compute_max...);
    f(Columns{"overruns[-]"}, m.overruns...);
    f(Columns{"roundtrip_p50[us]"}, m.roundtrip_p50...);
    f(Columns{"roundtrip_p99[us]"}, m.roundtrip_p99...);
    f(Columns{"roundtrip_p999[us]"}, m.roundtrip_p999...);
    f(Columns{"roundtrip_max[us]"}, m.roundtrip_max...);
    f(Columns{"substeps_mean[-]"}, m.substeps_mean...);
    f(Columns{"substeps_max[-]"}, m.substeps_max...);
    f(Columns{"commands_received[-]"}, m.commands_received...);
    f(Columns{"commands_rejected[-]"}, m.commands_rejected...);
    f(Columns{"commands_missed[-]"}, m.commands_missed...);
    f(Columns{"realtime[-]"}, m.realtime...);
    f(Columns{"lockstep[-]"}, m.lockstep...);
    f(Columns{"late_ticks[-]"}, m.late_ticks...);
  }
};

namespace detail {
template <class T>
void assignField(T& dst, const T& src) noexcept {
  dst = src;
}
template <class T, std::size_t N>
void assignField(T (&dst)[N], const T (&src)[N]) noexcept {
  for (std::size_t i = 0; i < N; ++i) dst[i] = src[i];
}
}  // namespace detail

/// dst.x = src.x for every field x of the list D (e.g. Truth -> gimbal_truth_t).
template <class D, class Dst, class Src>
void copyFields(Dst& dst, const Src& src) noexcept {
  D::visit([](Columns, auto& d, const auto& s) { detail::assignField(d, s); }, dst, src);
}

/// gimbal_antenna_t / Antenna.
struct AntennaFields {
  template <class F, class... M>
  static void visit(F&& f, M&... m) {
    f(Columns{"utime[us]"}, m.utime...);
    f(Columns{"seq[-]"}, m.seq...);
    f(Columns{"tracker_valid[-]"}, m.tracker_valid...);
    f(Columns{"tracker_time[s]"}, m.tracker_time...);
    f(Columns{"tracker_u[rad]", "tracker_v[rad]"}, m.tracker_error...);
    f(Columns{"tracker_outage[-]"}, m.tracker_outage...);
    f(Columns{"antenna_gyro_time[s]"}, m.gyro_time...);
    f(Columns{"antenna_gyro_wx[rad/s]", "antenna_gyro_wy[rad/s]", "antenna_gyro_wz[rad/s]"}, m.gyro_rate...);
  }
};

}  // namespace gimbalsim::contract
