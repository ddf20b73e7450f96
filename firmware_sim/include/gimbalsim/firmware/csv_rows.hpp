// CSV rows of the bench messages, one format for everyone who writes them:
// firmware_sim --truth-csv (from its Truth struct) and gimbalsim_log2csv
// (from the decoded LCM types of a log). The writers are templates over the
// field names, which the LCM types and the firmware structs share, so the two
// programs write the same bytes for the same message. Header cells are
// `name[unit]`; numbers are %.17g (a row round-trips exactly), integers %lld.
#pragma once

#include <cstdint>
#include <cstdio>

namespace gimbalsim::firmware::csv {

namespace detail {
inline void put(std::FILE* f, const double* x, int n) {
  for (int i = 0; i < n; ++i) std::fprintf(f, ",%.17g", x[i]);
}
inline void put(std::FILE* f, double x) { std::fprintf(f, ",%.17g", x); }
inline void putInt(std::FILE* f, long long x) { std::fprintf(f, ",%lld", x); }
}  // namespace detail

/// gimbal_truth_t (firmware::Truth): header line, with newline.
inline constexpr const char* kTruthHeader =
    "utime[us],seq[-],sim_time[s],base_x[m],base_y[m],base_z[m],base_qw[-],base_qx[-],base_qy[-],"
    "base_qz[-],base_wx[rad/s],base_wy[rad/s],base_wz[rad/s],base_vx[m/s],base_vy[m/s],base_vz[m/s],"
    "theta1[rad],theta2[rad],dtheta1[rad/s],dtheta2[rad/s],tau1[N m],tau2[N m],ecc_x[m],ecc_y[m],"
    "delta[m],fn[N],ft[N],joint2_force[N],bore_x[-],bore_y[-],bore_z[-],target_x[-],target_y[-],"
    "target_z[-],pointing_error[rad],mom_px[N s],mom_py[N s],mom_pz[N s],mom_lx[N m s],mom_ly[N m s],"
    "mom_lz[N m s],energy[J],faults[-]\n";

template <class T>
void writeTruthRow(std::FILE* f, const T& t) {
  using detail::put;
  std::fprintf(f, "%lld,%lld", static_cast<long long>(t.utime), static_cast<long long>(t.seq));
  put(f, t.sim_time);
  put(f, t.base_position, 3);
  put(f, t.base_quaternion, 4);
  put(f, t.base_rate, 3);
  put(f, t.base_velocity, 3);
  put(f, t.joint_angle, 2);
  put(f, t.joint_rate, 2);
  put(f, t.applied_torque, 2);
  put(f, t.eccentricity, 2);
  put(f, t.penetration);
  put(f, t.contact_normal_force);
  put(f, t.contact_tangential_force);
  put(f, t.joint2_force);
  put(f, t.boresight, 3);
  put(f, t.target_boresight, 3);
  put(f, t.pointing_error);
  put(f, t.momentum_linear, 3);
  put(f, t.momentum_angular, 3);
  put(f, t.energy);
  std::fprintf(f, ",%d\n", static_cast<int>(t.faults));
}

/// gimbal_status_t (firmware::Status).
inline constexpr const char* kStatusHeader =
    "utime[us],seq[-],angle1[rad],angle2[rad],rate1[rad/s],rate2[rad/s],tau1[N m],tau2[N m],faults[-],"
    "last_command_seq[-],commands_received[-],commands_rejected[-],commands_missed[-]\n";

template <class T>
void writeStatusRow(std::FILE* f, const T& s) {
  using detail::put;
  using detail::putInt;
  std::fprintf(f, "%lld,%lld", static_cast<long long>(s.utime), static_cast<long long>(s.seq));
  put(f, s.angle, 2);
  put(f, s.rate, 2);
  put(f, s.applied_torque, 2);
  putInt(f, s.faults);
  putInt(f, s.last_command_seq);
  putInt(f, s.commands_received);
  putInt(f, s.commands_rejected);
  putInt(f, s.commands_missed);
  std::fputc('\n', f);
}

/// gimbal_command_t.
inline constexpr const char* kCommandHeader = "utime[us],seq[-],status_seq[-],mode[-],tau1[N m],tau2[N m]\n";

template <class T>
void writeCommandRow(std::FILE* f, const T& c) {
  std::fprintf(f, "%lld,%lld,%lld,%d", static_cast<long long>(c.utime), static_cast<long long>(c.seq),
               static_cast<long long>(c.status_seq), static_cast<int>(c.mode));
  detail::put(f, c.torque, 2);
  std::fputc('\n', f);
}

/// gimbal_loop_stats_t.
inline constexpr const char* kLoopStatsHeader =
    "utime[us],ticks[-],period_p50[us],period_p99[us],period_p999[us],period_max[us],lateness_p50[us],"
    "lateness_p99[us],lateness_p999[us],lateness_max[us],compute_p50[us],compute_p99[us],compute_max[us],"
    "overruns[-],roundtrip_p50[us],roundtrip_p99[us],roundtrip_p999[us],roundtrip_max[us],substeps_mean[-],"
    "substeps_max[-],commands_received[-],commands_rejected[-],commands_missed[-],realtime[-],lockstep[-]\n";

template <class T>
void writeLoopStatsRow(std::FILE* f, const T& s) {
  using detail::put;
  using detail::putInt;
  std::fprintf(f, "%lld,%lld", static_cast<long long>(s.utime), static_cast<long long>(s.ticks));
  put(f, s.period_p50);
  put(f, s.period_p99);
  put(f, s.period_p999);
  put(f, s.period_max);
  put(f, s.lateness_p50);
  put(f, s.lateness_p99);
  put(f, s.lateness_p999);
  put(f, s.lateness_max);
  put(f, s.compute_p50);
  put(f, s.compute_p99);
  put(f, s.compute_max);
  putInt(f, s.overruns);
  put(f, s.roundtrip_p50);
  put(f, s.roundtrip_p99);
  put(f, s.roundtrip_p999);
  put(f, s.roundtrip_max);
  put(f, s.substeps_mean);
  putInt(f, s.substeps_max);
  putInt(f, s.commands_received);
  putInt(f, s.commands_rejected);
  putInt(f, s.commands_missed);
  putInt(f, s.realtime);
  putInt(f, s.lockstep);
  std::fputc('\n', f);
}

}  // namespace gimbalsim::firmware::csv
