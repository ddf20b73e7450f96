// The gimbal firmware and the plant it drives, one tick per control period,
// without LCM, threads or clocks: the tick's order (commands, watchdog,
// saturation, sensors, physics) in docs/bench.md "One tick", where scheduled
// faults enter in docs/ARCHITECTURE.md "Where faults enter". sample(),
// advance(), receive() and receiveUndecodable() are noexcept and allocation-free.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/observables.hpp"
#include "gimbalsim/dynamics/run_spec.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/firmware_sim/attitude_sensors.hpp"
#include "gimbalsim/firmware_sim/command_gate.hpp"
#include "gimbalsim/firmware_sim/fault_bus.hpp"
#include "gimbalsim/firmware_sim/fault_schedule.hpp"
#include "gimbalsim/firmware_sim/firmware_types.hpp"
#include "gimbalsim/firmware_sim/joint_sensors.hpp"
#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/firmware_sim/sensor_noise.hpp"
#include "gimbalsim/firmware_sim/truth_from_row.hpp"

namespace gimbalsim::firmware {
// The bench messages are the contract's (lcmtypes/contract), shared with the controller.
using namespace gimbalsim::contract;  // NOLINT(google-build-using-namespace)

template <class V>
class Firmware {
 public:
  /// ps and faults must outlive the Firmware; faults may be null (none). c
  /// must pass checkConfig(); faults checkFaultsAgainstScene().
  Firmware(const PlantScene& ps, const Config& c, const FaultSchedule* faults = nullptr)
      : m_(ps.scene.model), run_(ps.scene.run), sensors_(ps.sensors), c_(c), d_(m_), obs_(m_),
        s_(initialState<V>(ps.scene.run.initial)), noise_(static_cast<std::uint64_t>(ps.sensors.seed)),
        attitude_sensors_(ps.sensors, c.control_period),
        clock_(faults, c.control_period, {m_.bearing[0].clearance, m_.bearing[1].clearance},
               {m_.bearing[0].mu, m_.bearing[1].mu},
               {m_.joint1_kind != ClearanceKind::Ideal, m_.joint2_kind != ClearanceKind::Ideal}),
        bus_(clock_.any()) {
    // The caller checked; a bad config leaves steps_per_tick_ at 1.
    steps_per_tick_ = std::max(1, checkConfig(ps.scene, c).steps_per_tick);
    watchdog_ticks_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(c.watchdog_timeout / c.control_period - 1e-9)));
    gate_ = CommandGate(watchdog_ticks_);  // the binding lasts as long as the watchdog
    kinematics(m_, obs_, s_.q, s_.v);
    initial_boresight_ = boresight(m_, obs_, s_);
    truthFromRow();  // built here, so no tick pays for it
  }

  /// Validates a decoded command from `src` on arrival. A valid one becomes
  /// the pending command (the newest wins) and acts from the next tick; a
  /// rejected one changes nothing but the counters and the rejection flag.
  /// Under a command fault it may first be lost or held on the bus, and is
  /// then validated, with its source, when the bus releases it.
  Rejection receive(const Command& cmd, SourceId src = kInProcessSource) noexcept {
    if (bus_.take(cmd, src, tick_, clock_.current(), n_.bus)) return Rejection::None;  // lost or held on the bus
    ++n_.received;
    const Rejection r = validate(cmd, src);
    if (r != Rejection::None) {
      reject(r);
      return r;
    }
    pending_ = cmd;
    has_pending_ = true;
    last_accepted_seq_ = cmd.seq;
    gate_.accept(src, cmd.seq, tick_);
    return r;
  }

  /// Bytes on the command channel that are not a gimbal_command_t.
  void receiveUndecodable() noexcept {
    ++n_.received;
    reject(Rejection::Undecodable);
  }

  /// One control period: sample() then advance(). utime stamps status and
  /// truth [us]; truth is computed only when want_truth (it costs a
  /// forward-dynamics evaluation); extra_faults are or-ed into the report.
  void tick(std::int64_t utime, bool want_truth = true, std::int32_t extra_faults = 0) noexcept {
    sample(utime, want_truth, extra_faults);
    advance();
  }

  /// First half of a tick (steps 1-3): command intake, watchdog, saturation,
  /// status, attitude sensors and truth at t_k. The loop publishes attitude
  /// and status right after it, before the physics, so the controller's
  /// clock starts early.
  void sample(std::int64_t utime, bool want_truth = true, std::int32_t extra_faults = 0) noexcept {
    const std::int64_t k = tick_;
    const ActiveFaults& af = clock_.at(k);
    if (clock_.any()) enterFaults(k, af);
    std::int32_t faults = pending_faults_ | extra_faults;
    pending_faults_ = 0;

    // 1. command intake: the newest valid command received since the last tick.
    if (has_pending_) {
      active_ = pending_;
      has_active_ = true;
      has_pending_ = false;
      last_valid_tick_ = k;
    } else if (k > 0) {
      ++n_.missed;
    }

    // 2. watchdog, mode, saturation.
    const bool tripped = k - last_valid_tick_ >= watchdog_ticks_;
    if (tripped && !tripped_) ++n_.watchdog_trips;
    tripped_ = tripped;
    Vec2 tau = Vec2::Zero();
    if (tripped) {
      tau = c_.safe_torque;
      faults |= kWatchdogTripped;
    } else if (has_active_ && active_.mode == kModeTorque) {
      tau = Vec2(active_.torque[0], active_.torque[1]);
    }
    const Vec2 limit = run_.torque_limit.cwiseMin(Vec2(af.torque_limit[0], af.torque_limit[1]));
    const Vec2 clipped = tau.cwiseMax(-limit).cwiseMin(limit);
    if (clipped != tau) {
      faults |= kTorqueSaturated;
      ++n_.motor_limited_ticks;
    }
    driver_tau_ = clipped;  // what the firmware commands; a failed motor gives none of it
    u_.tau = clipped;
    for (int j = 0; j < 2; ++j) {
      if (af.motor_failed[j]) u_.tau(j) = 0.0;
    }
    if (plant_fault_) faults |= kPlantFault;

    // 3. status, attitude and truth at t_k.
    sampleStatus(k, utime, faults, af);
    const Status* delivered = bus_.deliverStatus(k, sampled_, af, n_.bus);
    status_delivered_ = delivered != nullptr;
    if (delivered) status_ = *delivered;
    sampleAttitude(k, utime, af);
    if (want_truth) sampleTruth(k, utime, faults);
    truth_.injected_faults = af.bits;
  }

  /// Second half of a tick (step 4): the plant over [t_k, t_k+1]; then the
  /// next tick begins. Call once after each sample().
  void advance() noexcept {
    const long long substeps0 = d_.stats.substeps, derivatives0 = d_.stats.derivatives;
    for (int i = 0; i < steps_per_tick_ && !plant_fault_; ++i) {  // a faulted plant is never stepped again
      const StepResult st = step(m_, d_, s_, u_);
      if (!st.ok()) {
        plant_fault_ = true;
        plant_result_ = st;
      }
    }
    last_substeps_ = static_cast<int>(d_.stats.substeps - substeps0);
    last_derivatives_ = d_.stats.derivatives - derivatives0;
    n_.substeps += last_substeps_;
    n_.max_substeps_in_tick = std::max(n_.max_substeps_in_tick, last_substeps_);
    n_.max_derivatives_in_tick = std::max(n_.max_derivatives_in_tick, last_derivatives_);
    ++tick_;
  }

  /// The status delivered this tick (without faults: the one sampled).
  const Status& status() const noexcept { return status_; }
  /// False when a scheduled status drop or delay left nothing to deliver this tick.
  bool statusDelivered() const noexcept { return status_delivered_; }
  /// The scheduled faults active in the last sample().
  const ActiveFaults& activeFaults() const noexcept { return clock_.current(); }
  /// The Model the plant steps (the scene's, with bearing wear and friction rise applied).
  const Model& model() const noexcept { return m_; }
  const Truth& truth() const noexcept { return truth_; }
  /// Where the antenna pointed at t = 0 (unit, inertial): the truth
  /// observer's target when there is no profile.
  const Vec3& initialBoresight() const noexcept { return initial_boresight_; }
  const Attitude& attitude() const noexcept { return attitude_; }
  /// The antenna's (last body's) attitude R_WA (antenna -> inertial) and its
  /// angular velocity in its own frame [rad/s], at the last sampled tick: what
  /// the antenna sensors measure (antenna_sensors.hpp). Runs the kinematics
  /// in the observation workspace (the stepping one is never touched).
  void antennaMotion(Mat3& R_WA, Vec3& w_A) noexcept {
    kinematics(m_, obs_, s_.q, s_.v);
    R_WA = worldPoses(obs_, s_).R[V::NJ - 1];
    w_A = obs_.v[V::NJ - 1].template head<3>();
  }
  const Counters& counters() const noexcept { return n_; }
  /// The command binding ends (CommandGate::release): the next valid command binds afresh.
  void releaseBinding() noexcept { gate_.release(); }
  const State<V>& state() const noexcept { return s_; }
  const Input& appliedInput() const noexcept { return u_; }
  std::int64_t ticks() const noexcept { return tick_; }
  int stepsPerTick() const noexcept { return steps_per_tick_; }
  int lastSubsteps() const noexcept { return last_substeps_; }
  /// Forward-dynamics evaluations of the last advance().
  long long lastDerivatives() const noexcept { return last_derivatives_; }
  std::int64_t watchdogTicks() const noexcept { return watchdog_ticks_; }
  bool watchdogTripped() const noexcept { return tripped_; }
  std::int64_t lastAcceptedSeq() const noexcept { return last_accepted_seq_; }

  bool plantFault() const noexcept { return plant_fault_; }
  StepStatus plantStatus() const noexcept { return plant_result_.status; }
  /// Why the plant stopped: status, time [s], coordinate, limit key.
  const StepResult& plantResult() const noexcept { return plant_result_; }

 private:
  Rejection validate(const Command& cmd, SourceId src) const noexcept {
    if (!std::isfinite(cmd.torque[0]) || !std::isfinite(cmd.torque[1])) return Rejection::NonFinite;
    if (cmd.mode != kModeOff && cmd.mode != kModeTorque) return Rejection::UnknownMode;
    for (int i = 0; i < 2; ++i) {
      if (std::fabs(cmd.torque[i]) > c_.torque_sanity_factor * run_.torque_limit(i)) return Rejection::OutOfRange;
    }
    switch (gate_.check(src, cmd.seq, tick_)) {
      case CommandGate::Verdict::WrongSource: return Rejection::WrongSource;
      case CommandGate::Verdict::StaleSeq: return Rejection::StaleSeq;
      case CommandGate::Verdict::Accept: break;
    }
    // Status tick_ - 1 is the newest one published (status k is sampled in tick k).
    if (cmd.status_seq > tick_ - 1) return Rejection::FutureStatus;
    return Rejection::None;
  }

  void reject(Rejection r) noexcept {
    ++n_.rejected;
    ++n_.by_reason[static_cast<int>(r)];
    pending_faults_ |= kCommandRejected;
  }

  void sampleStatus(std::int64_t k, std::int64_t utime, std::int32_t faults, const ActiveFaults& af) noexcept {
    Status& o = sampled_;
    o.utime = utime;
    o.seq = k;
    joint_sensors_.sample(k, s_, sensors_, af, noise_, o);
    for (int j = 0; j < 2; ++j) o.applied_torque[j] = driver_tau_(j);
    o.injected_faults = af.bits;
    o.faults = faults;
    o.last_command_seq = last_accepted_seq_;
    o.commands_received = n_.received;
    o.commands_rejected = n_.rejected;
    o.commands_missed = n_.missed;
  }

  /// The attitude sensors measure the base attitude and rate of s_ (fixed base: identity, zero).
  void sampleAttitude(std::int64_t k, std::int64_t utime, const ActiveFaults& af) noexcept {
    Quat q = Quat::Identity();
    Vec3 w = Vec3::Zero();
    if constexpr (V::kFloating) {
      q = Quat(s_.q(3), s_.q(4), s_.q(5), s_.q(6)).normalized();  // as sampleTruth
      w = s_.v.template head<3>();
    }
    attitude_sensors_.sample(k, utime, q, w, attitude_, af.star_outage);
    for (int i = 0; i < 3; ++i) attitude_.gyro_rate[i] += af.gyro_bias(i);
  }

  /// Scheduled faults at tick k's start: ramps of the contact parameters,
  /// then the commands held on the bus that are due.
  void enterFaults(std::int64_t k, const ActiveFaults& af) noexcept {
    if (af.bits != 0) ++n_.fault_ticks;
    if constexpr (V::kContact) {
      // Wear and friction rise act on the bearings FaultClock names.
      bool wear = false, rise = false;
      for (int j = 0; j < 2; ++j) {
        if (V::kind(j) == ClearanceKind::Ideal) continue;
        ContactParams& cp = m_.bearing[j];
        const bool wear_j = af.clearance[j] >= 0.0 && af.clearance[j] != cp.clearance;
        const bool rise_j = af.mu[j] >= 0.0 && af.mu[j] != cp.mu;
        if (wear_j) setClearance(cp, af.clearance[j]);  // the journal is what wears
        if (rise_j) cp.mu = af.mu[j];
        wear = wear || wear_j;
        rise = rise || rise_j;
      }
      if (wear || rise) {
        d_.k_last_valid = false;  // the cached f(s) belongs to the old parameters
        // A journal in contact whose bearing receded past it is free now.
        for (int e = 0; e < V::NC; ++e) {
          if (s_.in_contact[e] && !(endGap<V>(m_, e, s_.q, s_.v).delta > 0.0)) enterContactSide(m_, d_, s_, u_, e);
        }
      }
    }
    bus_.releaseDue(k, [this](const Command& cmd, SourceId src) { receive(cmd, src); });
  }

  /// The one mapping from the plant to Truth: the observables at s_ (one
  /// forward-dynamics evaluation). The target and the pointing error are an
  /// observer's (pointing/truth_observer.hpp): the plant knows no target.
  void sampleTruth(std::int64_t k, std::int64_t utime, std::int32_t faults) noexcept {
    Truth& o = truth_;
    const Row r = observe(m_, obs_, s_, u_);  // runs kinematics at s_ in obs_
    o.utime = utime;
    o.seq = k;
    o.sim_time = s_.t;
    copyRowToTruth(r, o);  // every truth column that is an output column, by name
    if constexpr (V::kFloating) {
      const Quat qn = Quat(s_.q(3), s_.q(4), s_.q(5), s_.q(6)).normalized();
      o.base_quaternion[0] = qn.w(), o.base_quaternion[1] = qn.x();
      o.base_quaternion[2] = qn.y(), o.base_quaternion[3] = qn.z();
    }
    o.applied_torque[0] = u_.tau(0), o.applied_torque[1] = u_.tau(1);
    o.faults = faults;
  }


  Model m_;  ///< the firmware's own copy: faults change its contact parameters between ticks
  const RunSpec& run_;
  const SensorParams& sensors_;
  Config c_;
  Data<V> d_;    ///< stepping workspace
  Data<V> obs_;  ///< observation workspace (truth), never disturbs the stepping one
  State<V> s_;
  Input u_;
  GaussianNoise noise_;
  AttitudeSensors attitude_sensors_;
  Vec3 initial_boresight_ = Vec3::UnitX();

  int steps_per_tick_ = 1;
  std::int64_t watchdog_ticks_ = 50;
  std::int64_t tick_ = 0;              ///< index of the next tick
  std::int64_t last_valid_tick_ = 0;   ///< tick that took the last valid command (0 at start)
  std::int64_t last_accepted_seq_ = -1;
  CommandGate gate_{1};
  Command pending_, active_;
  bool has_pending_ = false, has_active_ = false, tripped_ = false;
  std::int32_t pending_faults_ = 0;
  int last_substeps_ = 0;
  long long last_derivatives_ = 0;
  bool plant_fault_ = false;
  StepResult plant_result_;

  FaultClock clock_;
  Vec2 driver_tau_ = Vec2::Zero();  ///< [N m] torque the firmware commands (status); u_.tau is what acts
  FaultBus bus_;
  bool status_delivered_ = true;
  JointSensors joint_sensors_;
  Status sampled_;  ///< the status sampled this tick
  Status status_;   ///< the status delivered this tick
  Truth truth_;
  Attitude attitude_;
  Counters n_;
};

}  // namespace gimbalsim::firmware
