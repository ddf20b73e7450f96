// One bench tick, written once: the firmware's tick k up to its messages
// (status, attitude, and the truth with the observer's pointing error), then
// the plant's step. firmware_sim's lockstep and real-time loops and the
// in-process closed loop all tick through it; they differ only in how the
// messages travel (LCM, a ring to the communication thread, a controller
// port) and in the clock. docs/ARCHITECTURE.md "The data path".
#pragma once

#include <cstdint>

#include <optional>

#include "gimbalsim/firmware_sim/antenna_sensors.hpp"
#include "gimbalsim/firmware_sim/firmware.hpp"
#include "gimbalsim/pointing/target_profile.hpp"
#include "gimbalsim/pointing/truth_observer.hpp"

namespace gimbalsim::firmware {

/// The truth message as published: the plant's truth with the observer's
/// target line of sight and pointing error at t [s]. noexcept, no allocation.
inline contract::Truth observedTruth(contract::Truth truth, const pointing::TruthObserver& o, double t) noexcept {
  truth.pointing_error = o.observe(t, truth.boresight, truth.target_boresight);
  return truth;
}

/// The truth pointing error over a run's truths, and over the profile's
/// Track segment; no allocation.
struct PointingErrorStats {
  double max_rad = 0.0, sum_sq = 0.0, last_rad = 0.0;  ///< [rad], [rad^2]
  long long n = 0;
  double max_track_rad = 0.0, sum_sq_track = 0.0;
  long long n_track = 0;
  void add(double e_rad, bool tracking) noexcept {
    max_rad = e_rad > max_rad ? e_rad : max_rad;
    sum_sq += e_rad * e_rad;
    last_rad = e_rad;
    ++n;
    if (tracking) {
      max_track_rad = e_rad > max_track_rad ? e_rad : max_track_rad;
      sum_sq_track += e_rad * e_rad;
      ++n_track;
    }
  }
};

/// What tick k hands to its transport. Pointers into the BenchTick, valid
/// until its next sample().
struct TickMessages {
  const Attitude* attitude = nullptr;
  const Status* status = nullptr;  ///< null: the fault schedule dropped or still holds this tick's status
  const Truth* truth = nullptr;    ///< null: no truth this tick (firmware_sim --truth-every)
  const Antenna* antenna = nullptr;  ///< null: the scene has no antenna sensors (sensors.antenna none)
};

template <class V>
class BenchTick {
 public:
  /// ps, faults and profile must outlive the tick; profile null: the target
  /// is the boresight at t = 0. c must pass checkConfig().
  BenchTick(const PlantScene& ps, const Config& c, const FaultSchedule* faults, const pointing::TargetProfile* profile)
      : fw_(ps, c, faults), observer_(ps.scene.model, profile, fw_.initialBoresight()), profile_(profile),
        period_(c.control_period) {
    if (ps.sensors.antenna_sensors) antenna_sensors_.emplace(ps.scene.model, ps.sensors, c.control_period);
  }

  /// Tick k at t_k = k T up to its messages: the commands received so far
  /// take effect (Firmware::sample), status and attitude are sampled, and
  /// (want_truth) the truth with its pointing error. utime stamps them.
  TickMessages sample(std::int64_t k, std::int64_t utime, bool want_truth, std::int32_t extra_faults = 0) noexcept {
    fw_.sample(utime, want_truth, extra_faults);
    TickMessages m{&fw_.attitude(), fw_.statusDelivered() ? &fw_.status() : nullptr, nullptr};
    if (want_truth) {
      const double t = static_cast<double>(k) * period_;
      truth_ = observedTruth(fw_.truth(), observer_, t);
      // A stopped plant's frozen state against a profile that moves on is no pointing the plant did.
      if (!fw_.plantFault()) {
        pointing_.add(truth_.pointing_error,
                      profile_ != nullptr && observer_.sample(t).segment == pointing::Segment::Track);
      }
      m.truth = &truth_;
    }
    if (antenna_sensors_) {  // the target is the observer's: the tracker sees the target, the plant knows none
      Mat3 R_WA;
      Vec3 w_A;
      fw_.antennaMotion(R_WA, w_A);
      const ActiveFaults& af = fw_.activeFaults();  // the tracker's scheduled faults (fault_schedule.hpp)
      antenna_sensors_->sample(k, utime, R_WA, w_A, observer_.lineOfSight(static_cast<double>(k) * period_), antenna_,
                               af.tracker_outage, af.tracker_bias, af.tracker_dropout);
      m.antenna = &antenna_;
    }
    return m;
  }

  /// The plant's step over [t_k, t_k+1] with the applied torque.
  void advance() noexcept { fw_.advance(); }

  Firmware<V>& firmware() noexcept { return fw_; }
  const Firmware<V>& firmware() const noexcept { return fw_; }
  const pointing::TruthObserver& observer() const noexcept { return observer_; }
  const PointingErrorStats& pointing() const noexcept { return pointing_; }

 private:
  Firmware<V> fw_;
  pointing::TruthObserver observer_;
  const pointing::TargetProfile* profile_;
  double period_;  ///< [s] the control period T
  Truth truth_;
  PointingErrorStats pointing_;
  std::optional<AntennaSensors> antenna_sensors_;  ///< only a scene that names them has them (sensors.antenna)
  Antenna antenna_;
};

}  // namespace gimbalsim::firmware
