// pointing_controller's status handler: decodes each status into a stack
// message (fixed-size arrays: no allocation), runs the controller's answer
// and sends it through lcm_wire's sender (encoded in its preallocated slot). Statuses are taken from one plant
// (plant_binding.hpp), so a spoofed status cannot reset or steer the controller. One program's header: it
// lives beside pointing_controller_main.cpp.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <string_view>

#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/controllers/answer.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/gimbal_antenna_t.hpp"
#include "gimbalsim/gimbal_attitude_t.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/io/csv_format.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/lcm_wire/udpm_receiver.hpp"
#include "gimbalsim/lcm_wire/udpm_sender.hpp"
#include "plant_binding.hpp"

namespace gimbalsim::controllers {

/// Answers statuses; everything it needs is allocated before the first one.
class StatusHandler {
 public:
  /// log: the --log-csv file (null: none), written row by row through its checked write (which keeps
  /// the system's reason of a failure: pass 66 said "write failed" alone on a full disk).
  StatusHandler(const ControllerConfig& c, lcm_wire::UdpmSender& tx, const contract::Channels& ch, io::OutputFile* log)
      : c_(c), tx_(tx), ch_(ch), log_(log), binding_(c.period) {}

  /// One received message; the channel says which handler. now_ns: CLOCK_MONOTONIC.
  void onMessage(const lcm_wire::Message& m, std::int64_t now_ns) {
    const int size = static_cast<int>(m.size);  // bounded by the receiver's limit
    if (m.channel == ch_.status) {
      gimbal_status_t st{};
      const bool decoded = st.decode(m.data, 0, size) == size;  // the seq is the binding's evidence
      if (!binding_.accept(m.source, decoded, st.seq, now_ns)) return;
      if (binding_.rebound()) startAfresh();
      if (decoded) answer(st);
      else ++undecodable_;
      return;
    }
    if (!binding_.accept(m.source, false, 0, now_ns)) return;
    if (binding_.rebound()) startAfresh();
    if (m.channel == ch_.attitude) onAttitude(m.data, size);
    else if (m.channel == ch_.antenna) onAntenna(m.data, size);
  }

  /// The antenna's sensors (a scene with sensors.antenna): used by the law
  /// only with antenna.tracker: use (tracker_fusion.hpp).
  void onAntenna(const std::uint8_t* data, int size) {
    gimbal_antenna_t m{};
    if (m.decode(data, 0, size) != size) {
      ++undecodable_;
      return;
    }
    contract::Antenna a;
    contract::copyFields<contract::AntennaFields>(a, m);
    noteAntennaReading(state_.fusion, a);
  }

  void onAttitude(const std::uint8_t* data, int size) {
    gimbal_attitude_t m{};
    if (m.decode(data, 0, size) != size) {
      ++undecodable_;
      return;
    }
    contract::copyFields<contract::AttitudeFields>(attitude_, m);
    noteAttitude(state_, attitude_);  // a late status finds the attitude of its tick (fault_monitor.hpp)
  }

  void onStatus(const std::uint8_t* data, int size) {
    gimbal_status_t st{};
    if (st.decode(data, 0, size) != size) {
      ++undecodable_;  // garbage, another type or trailing bytes on the status channel
      return;
    }
    answer(st);
  }

  void answer(const gimbal_status_t& st) {
    if (st.seq < last_status_seq_) {  // the plant restarted: start the controller afresh
      state_ = ControllerState{};
      ++restarts_;
    }
    last_status_seq_ = st.seq;
    // The same answer as the in-process loop's (PointingController): seq from
    // this process's own counter, strictly increasing.
    contract::Status status;
    contract::copyFields<contract::StatusFields>(status, st);
    if (attitude_.seq != status.seq) ++unpaired_;
    const Answer a = answerStatus(c_, state_, status, attitude_, next_seq_);
    const Measurement& meas = a.meas;
    const ControlOutput& out = a.out;
    if (std::isfinite(a.cmd.torque[0]) && std::isfinite(a.cmd.torque[1])) {
      gimbal_command_t cmd{};
      contract::copyFields<contract::CommandFields>(cmd, a.cmd);
      if (!tx_.send(ch_.command, cmd)) ++publish_errors_;
      if (first_sent_seq_ < 0) first_sent_seq_ = a.cmd.seq;
    } else {
      ++not_finite_;  // never sent: NaN or Inf is no command (the plant would refuse it)
    }
    // Accepted: the plant's last accepted seq is one this process sent (a second controller numbering from
    // the same base would read the first's acceptances as its own: pass 33).
    if (first_sent_seq_ >= 0 && st.last_command_seq >= first_sent_seq_ && st.last_command_seq < next_seq_) {
      accepted_any_ = true;
      if (st.last_command_seq != last_accepted_seq_) ++accepted_, last_accepted_seq_ = st.last_command_seq;
    }
    // Bookkeeping after the answer is on its way.
    ++answered_;
    last_t_ = meas.t;
    faults_seen_ |= st.faults;
    // The plant rejected our last answer (the flag, its last accepted seq unchanged): counted in a row, for a
    // lockstep plant that ends the run after contract::kRejectedInARow of them (pass 71).
    const bool refused = (st.faults & gimbal_status_t::FAULT_COMMAND_REJECTED) != 0 && answered_ > 0 &&
                         st.last_command_seq == prev_last_command_seq_;
    rejected_in_a_row_ = refused ? rejected_in_a_row_ + 1 : 0;
    prev_last_command_seq_ = st.last_command_seq;
    // A stopped plant's frozen state against a profile that moves on is no pointing it did: the figures stop.
    if ((st.faults & gimbal_status_t::FAULT_PLANT_FAULT) != 0 && std::isnan(plant_stopped_t_)) plant_stopped_t_ = meas.t;
    const bool moving = std::isnan(plant_stopped_t_);
    if (moving) last_good_t_ = meas.t;  // the plant's last good state is the last status before its fault
    if (out.star_outage) ++outage_statuses_;
    if (moving && (out.saturated[0] || out.saturated[1])) ++controller_limited_;
    if (moving && out.ref.segment == Segment::Track) {
      ++track_statuses_;
      // A rejected reading (NaN or Inf) measured nothing: its error is no figure (a lone one printed 0).
      if (!out.rejected) {
        const double e = out.error.cwiseAbs().maxCoeff();
        max_track_error_ = std::isnan(max_track_error_) ? e : std::max(max_track_error_, e);
      }
    }
    if (log_) log(st, meas, out, a.flags);
  }

  /// The log's header line, newline included.
  static std::string header() {
    // The cells as name[unit], written in the project's CSV names (io::csvNameOf: t_s, tau_az_Nm).
    static constexpr const char* kCells =
        "t[s],seq[-],segment[-],ref_az[rad],ref_el[rad],ref_daz[rad/s],ref_del[rad/s],ref_ddaz[rad/s^2],"
        "ref_ddel[rad/s^2],meas_az[rad],meas_el[rad],rate_az[rad/s],rate_el[rad/s],err_az[rad],"
        "err_el[rad],tau_az[N m],tau_el[N m],tau_unsat_az[N m],tau_unsat_el[N m],faults[-],prof_az[rad],"
        "prof_el[rad],est_qw[-],est_qx[-],est_qy[-],est_qz[-],est_wx[rad/s],est_wy[rad/s],est_wz[rad/s],"
        "star_outage[-],attitude_paired[-],stale[-],safe[-],suspect_az[-],suspect_el[-],reason";
    std::string h, cell;
    for (const char* c = kCells;; ++c) {
      if (*c == ',' || *c == '\0') {
        (h.empty() ? h : h += ',') += io::csvNameOf(cell);
        cell.clear();
        if (*c == '\0') break;
      } else {
        cell += *c;
      }
    }
    return h + "\n";
  }

  long long answered() const { return answered_; }
  /// The run of a controller whose last status is last_seq has ended: that status (or a later one, the one
  /// before it lost) answered, from a plant whose stream has shown (or exactly last_seq: a one-status run).
  bool runEnded(std::int64_t last_seq) const {
    return last_seq >= 0 && answered_ > 0 && last_status_seq_ >= last_seq &&
           (last_status_seq_ == last_seq || binding_.streamShown());
  }
  /// Statuses answered with the command held at this controller's own limit (azimuth/elevation.torque_limit), either axis.
  long long controllerLimited() const { return controller_limited_; }
  std::int64_t lastSeq() const { return last_status_seq_; }
  long long foreign() const { return binding_.foreign(); }
  /// Times another source took the binding from the one bound (plant_binding.hpp).
  long long rebinds() const { return binding_.rebinds(); }
  long long plantRestarts() const { return restarts_; }
  long long undecodable() const { return undecodable_; }
  long long publishErrors() const { return publish_errors_; }
  long long notFinite() const { return not_finite_; }
  /// Whether the plant has reported accepting one of this controller's commands.
  bool acceptedAny() const { return accepted_any_; }
  /// Our commands the plant's statuses show it took (the last answer's shows in a status that may never come).
  long long accepted() const { return accepted_; }
  /// The last statuses in a row saying the plant rejected our answer to the one before.
  long long rejectedInARow() const { return rejected_in_a_row_; }
  double lastTime() const { return last_t_; }
  int faultsSeen() const { return faults_seen_; }
  /// [rad] the largest |joint error| of an accepted reading while tracking; NaN before one.
  double maxTrackError() const { return max_track_error_; }
  /// Statuses answered while tracking, accepted or rejected.
  long long trackStatuses() const { return track_statuses_; }
  /// [s] the first status carrying FAULT_PLANT_FAULT (the plant's stop), NaN while it moves.
  double plantStoppedTime() const { return plant_stopped_t_; }
  /// [s] the time of the last status before FAULT_PLANT_FAULT (the plant's last good state); NaN before any.
  double lastGoodTime() const { return last_good_t_; }
  long long unpaired() const { return unpaired_; }
  long long outageStatuses() const { return outage_statuses_; }
  const MonitorState& monitor() const { return state_.monitor; }
  long long rejectedReadings() const { return state_.rejected_readings; }

 private:
  /// Another source took the binding: what the one before it said is no state of this plant.
  void startAfresh() {
    state_ = ControllerState{};
    attitude_ = contract::Attitude{.seq = -1};
    last_status_seq_ = -1;
    prev_last_command_seq_ = -1;
    rejected_in_a_row_ = 0;
  }

  void log(const gimbal_status_t& st, const Measurement& m, const ControlOutput& o, const MonitorFlags& f) {
    const ProfileSample& r = o.ref;
    // One line in a fixed buffer (no allocation on the answer path); doubles as io::formatCsvNumber.
    char line[2048];
    int n = io::formatCsvNumber(line, m.t);
    n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), ",%lld,%s", static_cast<long long>(st.seq),
                       describe(r.segment));
    bool finite = true;  // a NaN or Inf is written nan, with its reason in the last column (the CSV convention)
    auto num = [&](double x) {
      line[n++] = ',';
      finite = finite && std::isfinite(x);
      n += io::formatCsvNumber(line + n, std::isfinite(x) ? x : std::nan(""));
    };
    auto flag = [&](int v) { n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), ",%d", v); };
    for (double x : {r.q(0), r.q(1), r.dq(0), r.dq(1), r.ddq(0), r.ddq(1), m.theta(0), m.theta(1), m.dtheta(0),
                     m.dtheta(1), o.error(0), o.error(1), o.tau(0), o.tau(1), o.tau_unsat(0), o.tau_unsat(1)}) {
      num(x);
    }
    flag(st.faults);
    for (double x : {o.profile.q(0), o.profile.q(1), o.q_WB_est.w(), o.q_WB_est.x(), o.q_WB_est.y(),
                     o.q_WB_est.z(), o.omega_B_est(0), o.omega_B_est(1), o.omega_B_est(2)}) {
      num(x);
    }
    for (bool b : {o.star_outage, attitude_.seq == st.seq, f.stale, f.safe, f.encoder_suspect[0],
                   f.encoder_suspect[1]}) {
      flag(b ? 1 : 0);
    }
    const char* reason = o.rejected ? "reading rejected (a NaN or Inf in it): the last command held"
                         : finite   ? ""
                                    : "a value computed from the reading is not finite (an overflow)";
    n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), ",%s\n", reason);
    log_->write(std::string_view(line, static_cast<std::size_t>(n)));  // a failure is kept, with its reason
  }

  const ControllerConfig& c_;
  lcm_wire::UdpmSender& tx_;
  const contract::Channels& ch_;
  io::OutputFile* log_;
  ControllerState state_;
  contract::Attitude attitude_{.seq = -1};  ///< the newest attitude message (seq -1: none yet)
  long long unpaired_ = 0;        ///< statuses without the attitude of their tick (gyro rate held)
  long long outage_statuses_ = 0; ///< statuses answered during a star tracker outage
  PlantBinding binding_;
  /// Commands are numbered from a random base per process (below 2^60, room for 2^60 commands): two
  /// controllers on one plant never share seqs, so each tells its own acceptances from the other's.
  std::int64_t next_seq_ = static_cast<std::int64_t>(std::random_device{}() & 0xFFFFFu) << 40;
  std::int64_t last_status_seq_ = -1;
  long long restarts_ = 0;  ///< statuses whose seq went backwards
  long long answered_ = 0, undecodable_ = 0, publish_errors_ = 0, controller_limited_ = 0;
  long long not_finite_ = 0;            ///< answers not sent: a torque NaN or Inf
  std::int64_t first_sent_seq_ = -1;    ///< seq of the first command sent (-1: none yet)
  bool accepted_any_ = false;
  long long accepted_ = 0;
  std::int64_t last_accepted_seq_ = -1;
  long long rejected_in_a_row_ = 0;
  std::int64_t prev_last_command_seq_ = -1;
  long long track_statuses_ = 0;
  double last_t_ = 0.0, max_track_error_ = std::nan(""), plant_stopped_t_ = std::nan(""), last_good_t_ = std::nan("");
  int faults_seen_ = 0;
};

}  // namespace gimbalsim::controllers
