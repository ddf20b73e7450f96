// The project's pointing controller (configuration, update law) and the
// in-process closed loop (firmware::runClosedLoop: the plant with this
// controller wired to its port).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "bindings.hpp"
#include "errors.hpp"
#include "key_dicts.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/controllers/key_use.hpp"
#include "gimbalsim/controllers/pointing_controller.hpp"
#include "gimbalsim/firmware_sim/closed_loop.hpp"
#include "gimbalsim/firmware_sim/study_idle.hpp"
#include "gimbalsim/firmware_sim/fault_schedule_io.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/pointing/profile_windows.hpp"

namespace gimbalsim::py {

/// A controller configuration, the file it came from, and the law's memory.
struct PyController {
  controllers::ControllerConfig config;
  controllers::ControllerState state;
  std::string path;  ///< "" = the built-in defaults (= controllers/config/default.yaml)
  std::string file;  ///< path made absolute when loaded: a run's to_csv input wherever one stands (PyScene::file)
  double last_t = -1.0;  ///< [s] the last update's time since the last reset (-1: none)
  std::vector<std::string> labels;  ///< each override as the caller named it ("overrides['key']"; none: --set #k)
};

}  // namespace gimbalsim::py

GIMBALSIM_GUARDED_CASTER(gimbalsim::py::PyController)

namespace gimbalsim::py {

namespace pyb = pybind11;
using namespace gimbalsim::controllers;
using firmware::ClosedLoopOptions;
using firmware::ClosedLoopResult;
using firmware::TickRecord;

namespace {

/// (pass 94) An outage the scene sets that acts on nothing (a fixed base with perfect sensors, between two samples,
/// a tracker the run lacks) ran silently, where firmware_sim refuses the same --set: refused as sensorKeyIdle says.
void refuseIdleOutages(const PyScene& s, const ControllerConfig& c, double duration,
                       const firmware::FaultSchedule* faults) {
  const firmware::SensorParams& sp = s.plant.sensors;
  const firmware::SensorRun run{duration, c.period, c.antenna.use_tracker, s.scene().model.floating_base, faults,
                                true};  // its last row records the estimate
  for (const auto& [key, window] : {std::pair{"sensors.star_tracker_outage", sp.star_tracker_outage},
                                    std::pair{"sensors.tracker_outage", sp.tracker_outage}}) {
    if (!(window(1) > window(0))) continue;  // none set
    if (const std::string why = firmware::sensorKeyIdle(key, sp, run); !why.empty()) {
      const std::string text = s.path + ": key '" + key + "': " + why + " (firmware_sim refuses it as a --set)";
      raiseSceneError(InputError({Problem{text, key, s.path, 0, 0, 0}}));
    }
  }
}

/// (pass 99) A value recorded as given that runs as another (pointing.mode joint with accel_feedforward inertial
/// ran as profile), where pointing_controller refuses it: refused naming the feed-forward key.
void refuseValueRunningAsAnother(const PyController& c) {
  if (Problem p = c.config.runs_as_another; !p.text.empty()) {  // (pass 106) named where given, as a load's problem
    p.text = relabelledProblems(InputError({p}), c.labels).front() + " (pointing_controller refuses it)";
    raiseSceneError(InputError({p}));
  }
}

PyController loadController(const std::string& path, const std::vector<std::string>& overrides,
                            const std::vector<std::string>& labels) {
  checkPath(path, "controller configuration path");
  try {
    if (path.empty()) {
      return {loadControllerConfigText("", "the built-in default configuration", overrides), {}, "", "", -1.0, labels};
    }
    return {loadControllerConfig(path, overrides), {}, path, absoluteFile(path), -1.0, labels};
  } catch (const InputError& e) {
    raiseSceneError(e);
  }
}

/// Per-tick columns of a closed-loop run, filled without the GIL.
struct Ticks {
  static constexpr const char* kNames[] = {
      "t",          "ref1",         "ref2",         "profile1",       "profile2",       "theta1_true",
      "theta2_true", "theta1_meas", "theta2_meas",  "tau1_cmd",       "tau2_cmd",       "tau1_applied",
      "tau2_applied", "truth_error", "attitude_error", "star_outage", "segment",     "injected_faults",
      "los_error_x", "los_error_y", "los_error_z", "los_error_est_x", "los_error_est_y", "los_error_est_z",
      "tilt1",       "tilt2",       "tracker_u",   "tracker_v"};
  static constexpr int kN = sizeof(kNames) / sizeof(kNames[0]);
  std::vector<double> data;
  void add(const TickRecord& r) {
    const double row[kN] = {r.t,
                            r.ref.q(0),
                            r.ref.q(1),
                            r.profile.q(0),
                            r.profile.q(1),
                            r.theta_true(0),
                            r.theta_true(1),
                            r.theta_meas(0),
                            r.theta_meas(1),
                            r.tau_cmd(0),
                            r.tau_cmd(1),
                            r.tau_applied(0),
                            r.tau_applied(1),
                            r.truth_error,
                            r.attitude_error,
                            r.star_outage ? 1.0 : 0.0,
                            static_cast<double>(r.profile.segment),
                            static_cast<double>(r.injected_faults),
                            r.los_error_true(0),
                            r.los_error_true(1),
                            r.los_error_true(2),
                            r.los_error_est(0),
                            r.los_error_est(1),
                            r.los_error_est(2),
                            r.tilt(0),
                            r.tilt(1),
                            r.tracker(0),
                            r.tracker(1)};
    data.insert(data.end(), row, row + kN);
  }
};

pyb::dict resultDict(const ClosedLoopResult& r) {
  pyb::dict d;
  d["ok"] = r.ok;
  d["error"] = r.error;
  // Why it stopped, never "" when not ok: the limit's key, non_finite (no
  // setting causes it), or refused (nothing ran: runClosedLoop refuses only a
  // control.period that is no whole multiple of sim.step, closed_loop.hpp).
  // rejected_stop: the plant refused every command (the error says the commonest reason).
  const char* stop = r.rejected_stop                           ? "commands_rejected"
                     : r.stop_status == StepStatus::Ok         ? "refused:controller.control.period"
                     : r.stop_status == StepStatus::NonFinite ? "non_finite"
                                                              : limitKey(r.stop_status);
  d["stop_key"] = r.ok ? "" : stop;
  d["t_end_s"] = r.t_end;
  d["settle_time_s"] = r.settle_time;
  d["max_joint_error_slew_rad"] = r.max_joint_error_slew;
  d["max_joint_error_hold_rad"] = r.max_joint_error_hold;
  d["max_joint_error_track_rad"] = r.max_joint_error_track;
  d["max_truth_error_track_rad"] = r.max_truth_error_track;
  d["rms_truth_error_track_rad"] = r.rms_truth_error_track;
  d["max_truth_error_hold_end_rad"] = r.max_truth_error_hold_end;
  d["max_abs_tau_Nm"] = pyb::make_tuple(r.max_abs_tau(0), r.max_abs_tau(1));
  d["controller_limited_ticks"] = r.controller_limited_ticks;
  // a count over the track window: NaN with the track's reason when the run never reached it (pass 42: a bare 0)
  d["controller_limited_track_ticks"] = r.track_reason.empty()
                                            ? pyb::object(pyb::int_(r.controller_limited_ticks_track))
                                            : pyb::object(pyb::float_(std::numeric_limits<double>::quiet_NaN()));
  d["motor_limited_ticks"] = r.motor_limited_ticks;
  d["max_attitude_error_rad"] = r.max_attitude_error;
  d["max_tilt_rad"] = pyb::make_tuple(r.max_tilt(0), r.max_tilt(1));
  d["star_outage_ticks"] = r.star_outage_ticks;
  // When each axis went onto its backlash guard's gains; None: it never did (no play seen).
  const auto onset = [&](int j) -> pyb::object {
    return std::isnan(r.play_onset(j)) ? pyb::object(pyb::none()) : pyb::object(pyb::float_(r.play_onset(j)));
  };
  d["play_onset_s"] = pyb::make_tuple(onset(0), onset(1));
  d["ticks"] = r.ticks;
  // A figure over a window the run did not reach is NaN; "reasons" says why,
  // one entry per such figure (IndexValue's convention, docs/python.md).
  pyb::dict reasons;
  const std::pair<const char*, const std::string*> why[] = {
      {"settle_time_s", &r.settle_reason},         {"max_joint_error_slew_rad", &r.slew_reason},
      {"max_joint_error_hold_rad", &r.hold_reason},  {"max_joint_error_track_rad", &r.track_reason},
      {"max_truth_error_track_rad", &r.track_reason}, {"rms_truth_error_track_rad", &r.track_reason},
      {"controller_limited_track_ticks", &r.track_reason},
      {"max_truth_error_hold_end_rad", &r.hold_end_reason}, {"max_abs_tau_Nm", &r.run_reason},
      {"max_attitude_error_rad", &r.run_reason},       {"max_tilt_rad", &r.run_reason}};
  for (const auto& [field, reason] : why) {
    if (!reason->empty()) reasons[field] = *reason;
  }
  d["reasons"] = reasons;
  return d;
}

/// The figures of the summary computed over the ticks (every one but ok,
/// error, stop_key, t_end_s and ticks).
constexpr const char* kTickFigures[] = {
    "settle_time_s",           "max_joint_error_slew_rad",    "max_joint_error_hold_rad", "max_joint_error_track_rad",
    "max_truth_error_track_rad", "rms_truth_error_track_rad", "max_truth_error_hold_end_rad", "max_abs_tau_Nm",
    "controller_limited_ticks", "controller_limited_track_ticks", "motor_limited_ticks", "max_attitude_error_rad",
    "max_tilt_rad"};

/// A non-finite value in any tick is a stop with its reason, and no figure
/// is reported over it (a max over NaN reads as 0.0): the figures become NaN
/// with that reason.
void guardNonFinite(const Ticks& ticks, pyb::dict& summary) {
  for (std::size_t i = 0; i < ticks.data.size(); ++i) {
    if (std::isfinite(ticks.data[i])) continue;
    if (std::strncmp(Ticks::kNames[i % Ticks::kN], "tracker_", 8) == 0) continue;  // NaN: the scene has no tracker
    const std::size_t row = i / Ticks::kN;
    const std::string what = std::string("non-finite ") + Ticks::kNames[i % Ticks::kN] + " at t = " +
                             std::to_string(ticks.data[row * Ticks::kN]) + " s (tick " + std::to_string(row) + ")";
    if (summary["ok"].cast<bool>()) {
      summary["ok"] = false;
      summary["stop_key"] = "non_finite";
      summary["error"] = what;
    } else {
      summary["error"] = summary["error"].cast<std::string>() + "; " + what;
    }
    // The summary's one convention for a figure without a value: NaN and its reason.
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    pyb::dict reasons = summary["reasons"];
    for (const char* figure : kTickFigures) {
      const bool pair = std::string(figure) == "max_abs_tau_Nm" || std::string(figure) == "max_tilt_rad";
      summary[figure] = pair ? pyb::object(pyb::make_tuple(kNaN, kNaN)) : pyb::object(pyb::float_(kNaN));
      reasons[figure] = what;
    }
    return;
  }
}

}  // namespace

std::size_t closedLoopRowsFit(double duration, double control_period, const std::string& note) {
  return rowsFitInMemory(std::floor(duration / control_period + 0.5) + 1.0, Ticks::kN,
                         "closed_loop (duration " + formatNumber(duration) + " s at control.period " +
                             formatNumber(control_period) + " s" + note + ")");
}

void bindController(pyb::module_& m) {
  pyb::class_<PyController>(m, "Controller",
                            "The project's pointing controller: its configuration (the keys of "
                            "`pointing_controller --keys`) and its update law with its memory")
      .def(pyb::init(&loadController), pyb::arg("path"), pyb::arg("overrides"),
           pyb::arg("labels") = std::vector<std::string>{})
      .def_property_readonly("path", [](const PyController& c) { return c.path; })
      .def_property_readonly("_file", [](const PyController& c) { return c.file; }, "that file's absolute path")
      .def_property_readonly("period", [](const PyController& c) { return c.config.period; },
                             "control.period [s]")
      .def_property_readonly(
          "windows",
          [](const PyController& c) {
            // The profile's windows as every tool computes them (pointing/profile_windows.hpp).
            pyb::dict d;
            for (auto seg : {pointing::Segment::Slew, pointing::Segment::Hold, pointing::Segment::Track}) {
              const pointing::ProfileWindow w = pointing::profileWindow(c.config.profile, seg);
              d[pointing::describe(seg)] = pyb::make_tuple(w.start_s, w.end_s);
            }
            return d;
          },
          "the profile's windows {'slew': (start, end), 'hold': ..., 'track': (start, inf)} [s]")
      .def("_values_text", [](const PyController& c) { return keyValueDict(configValues(c.config)); },
           "every key with its value, as text the overrides read back exactly")
      .def("reset", [](PyController& c) { c.state = ControllerState{}, c.last_t = -1.0; }, "forget the law's memory")
      .def(
          "update",
          [](PyController& c, double t, double theta1, double theta2, double dtheta1, double dtheta2,
             std::optional<std::array<double, 3>> gyro) {
            // A measurement that is no number, or a law that overflows on one, gives no command
            // (the bench's controller never sends a non-finite one either).
            const std::pair<const char*, double> given[] = {{"t", t}, {"theta1", theta1}, {"theta2", theta2},
                                                            {"dtheta1", dtheta1}, {"dtheta2", dtheta2}};
            for (const auto& [name, v] : given) {
              if (!std::isfinite(v)) throw pyb::value_error(std::string("update: ") + name + " is not finite");
            }
            if (gyro && !(std::isfinite((*gyro)[0]) && std::isfinite((*gyro)[1]) && std::isfinite((*gyro)[2]))) {
              throw pyb::value_error("update: gyro is not finite");
            }
            // The profile's times are within 1e9 s (the configuration's ranges), and the law's memory
            // (estimator, filters) only runs forward: t = 1e300 left a reference of 2e298 rad for ever after.
            if (!(t >= 0.0 && t <= 1e9)) {
              throw pyb::value_error("update: t must be in [0, 1e9] s, got " + formatNumber(t));
            }
            if (t < c.last_t) {
              throw pyb::value_error("update: t = " + formatNumber(t) + " s is before the last update's " +
                                     formatNumber(c.last_t) + " s: time runs forward; reset() to start again");
            }
            Measurement meas;
            meas.t = t;
            meas.theta = {theta1, theta2};
            meas.dtheta = {dtheta1, dtheta2};
            if (gyro) {
              meas.att.gyro = {(*gyro)[0], (*gyro)[1], (*gyro)[2]};
            } else {
              meas.att.gyro_valid = false;
            }
            const ControlOutput out = update(c.config, c.state, meas);
            c.last_t = t;
            if (!(out.tau.allFinite() && out.tau_unsat.allFinite() && out.error.allFinite() && out.ref.q.allFinite())) {
              throw pyb::value_error("update: the law gave a non-finite torque from these measurements (an "
                                     "overflow): no command; reset() before the next update");
            }
            pyb::dict d;
            d["tau"] = pyb::make_tuple(out.tau(0), out.tau(1));
            d["tau_unsat"] = pyb::make_tuple(out.tau_unsat(0), out.tau_unsat(1));
            d["error"] = pyb::make_tuple(out.error(0), out.error(1));
            d["ref"] = pyb::make_tuple(out.ref.q(0), out.ref.q(1));
            d["saturated"] = pyb::make_tuple(out.saturated[0], out.saturated[1]);
            d["in_play"] = pyb::make_tuple(out.in_play[0], out.in_play[1]);  // the backlash guard has seen a play
            return d;
          },
          pyb::arg("t"), pyb::arg("theta1"), pyb::arg("theta2"), pyb::arg("dtheta1") = 0.0,
          pyb::arg("dtheta2") = 0.0, pyb::arg("gyro") = pyb::none(),
          "one control period: time [s], encoder angles [rad], rates [rad/s], base rate gyro [rad/s] "
          "(base frame; None = no sample); returns the command tau [N m] and what it saw")
      // Pickled as a call of gimbalsim._unpickle_controller (any protocol, 0
      // to 5): the values are loaded again, so an unpickled controller is checked.
      .def("__reduce__", [](const PyController& c) {
        return pyb::make_tuple(pyb::module_::import("gimbalsim").attr("_unpickle_controller"),
                               pyb::make_tuple(c.path, configValues(c.config), c.file));
      });

  m.def("_unpickle_controller", [](const std::string& path, const std::vector<std::string>& values,
                                    const std::string& file) {
    PyController c = loadController("", values, {});
    c.path = path;
    c.file = file;
    return c;
  });

  m.def(
      "_closed_loop",
      [](const PyScene& s, const PyController& c, double duration, double settle_tol, const std::string& faults,
         bool refuse_idle) {
        // (0, 1e9] as closed_loop and controller_sweep --duration say (1e9 itself was refused, pass 82)
        if (!(duration > 0.0 && duration <= 1e9)) throw pyb::value_error("duration [s] must be in (0, 1e+09]");
        const std::size_t rows =
            closedLoopRowsFit(duration, c.config.period, "; controller_sweep streams its ticks");
        ClosedLoopOptions opt;
        opt.duration = duration;
        opt.settle_tol = settle_tol;
        firmware::FaultSchedule schedule;
        checkPath(faults, "fault schedule path");
        if (!faults.empty()) {
          try {
            schedule = firmware::loadFaultSchedule(faults);
            std::vector<std::string> bad = firmware::checkFaultsAgainstScene(schedule, s.plant, faults);
            const double period = c.config.period;
            for (std::string& late : firmware::checkFaultsAgainstDuration(schedule, duration, period, faults)) {
              bad.push_back(std::move(late));
            }
            if (bad.empty()) {
              bad = firmware::checkFaultsAgainstSamples(schedule, s.plant, duration, period, faults, true);
            }
            // (pass 104) a limit at or above the controller's own holds no command the controller sends
            const Vec2 own(c.config.axis[0].torque_limit, c.config.axis[1].torque_limit);
            for (std::size_t i = 0; i < schedule.faults.size() && bad.empty(); ++i) {
              const firmware::FaultSpec& f = schedule.faults[i];
              if (const int j = firmware::torqueLimitClipsNothingOn(f, own); j >= 0) {  // (pass 108) its column too
                const bool at_limit = f.param_line > 0;
                bad.push_back(faults + ":" + std::to_string(at_limit ? f.param_line : f.line) + ":" +
                              std::to_string(at_limit ? f.param_column : f.column) + ": fault #" +
                              std::to_string(i + 1) + " (torque_limit): key 'limit': " + formatNumber(f.value) +
                              " N m is not below the controller's own " + (j == 0 ? "azimuth" : "elevation") +
                              ".torque_limit (" + formatNumber(own(j)) + " N m), which holds every command: the "
                              "limit would clip nothing");
              }
            }
            if (!bad.empty()) {
              std::vector<Problem> problems;
              for (const std::string& b : bad) problems.push_back(Problem{b, "", faults, 0, 0, 0});
              throw SceneError(problems);
            }
          } catch (const InputError& e) {
            raiseSceneError(e);
          }
          opt.faults = &schedule;
        }
        if (refuse_idle) {
          refuseIdleOutages(s, c.config, duration, faults.empty() ? nullptr : &schedule);
          refuseValueRunningAsAnother(c);
        }
        Ticks ticks;
        ticks.data.reserve(rows * Ticks::kN);  // no doubling on the way: the bound above holds
        ClosedLoopResult r;
        {
          pyb::gil_scoped_release nogil;
          PointingController controller(c.config);
          r = firmware::runClosedLoop(s.plant, controller, c.config.profile, opt,
                                      [&](const firmware::TickRecord& rec) { ticks.add(rec); });
        }
        pyb::dict summary = resultDict(r);
        guardNonFinite(ticks, summary);
        pyb::dict cols;
        const pyb::ssize_t n = static_cast<pyb::ssize_t>(ticks.data.size() / Ticks::kN);
        for (int j = 0; j < Ticks::kN; ++j) {
          pyb::array_t<double> a(n);
          double* p = a.mutable_data();
          for (pyb::ssize_t i = 0; i < n; ++i) p[i] = ticks.data[static_cast<std::size_t>(i * Ticks::kN + j)];
          cols[Ticks::kNames[j]] = a;
        }
        return pyb::make_tuple(summary, cols);
      },
      pyb::arg("scene"), pyb::arg("controller"), pyb::arg("duration"), pyb::arg("settle_tol"), pyb::arg("faults"),
      pyb::arg("refuse_idle"));
}

}  // namespace gimbalsim::py
