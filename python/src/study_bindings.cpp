// The rules the Python studies judge their keys by (gimbalsim/_idle_keys.py, _idle_sensors.py, the specs): which
// controller keys a configuration reads, which keys a closed loop never reads, what the controller's sample
// histories hold, and whether a closed loop's ticks fit in memory. The C++ tables themselves, never copies.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>

#include "bindings.hpp"
#include "errors.hpp"
#include "key_dicts.hpp"
#include "gimbalsim/controllers/attitude_estimator.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/controllers/key_use.hpp"
#include "gimbalsim/controllers/play_guard.hpp"
#include "gimbalsim/controllers/tracker_fusion.hpp"
#include "gimbalsim/firmware_sim/study_idle.hpp"
#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim::py {

namespace pyb = pybind11;
using namespace gimbalsim::controllers;

void bindStudyRules(pyb::module_& m) {
  m.def("_controller_keys", [] { return keyInfoList(controllerKeys()); });
  m.def("_closed_loop_idle_scene_keys", [] { return firmware::closedLoopIdleSceneKeys(); });
  m.def("_closed_loop_idle_controller_keys", [] { return firmware::closedLoopIdleControllerKeys(); });
  // key -> [[(deciding key, (values that read it)), ...] per condition] (gimbalsim/_idle_keys.py)
  m.def("_controller_read_rules", [] {
    pyb::dict rules;
    for (const KeyReadRule& r : controllerReadRules()) {
      pyb::list conditions;
      for (const auto& condition : r.conditions) {
        pyb::list settings;
        for (const ReadingSetting& s : condition) {
          settings.append(pyb::make_tuple(s.key, pyb::tuple(pyb::cast(s.values))));
        }
        conditions.append(settings);
      }
      rules[pyb::str(r.key)] = conditions;
    }
    return rules;
  });
  // What the controller's histories hold at a control period [s]: the star-tracker latency [s] at or beyond
  // which the attitude estimator drops every sample, and the boresight tracker's history in ticks
  // (gimbalsim/_idle_sensors.py: sensor keys that act on nothing).
  m.def("_sample_histories", [](double control_period) {
    if (!(control_period > 0.0 && std::isfinite(control_period))) throw pyb::value_error("control period must be > 0 s");
    return pyb::make_tuple(historySpan(AttitudeEstimatorParams{}, control_period), TrackerFusionState::kSize);
  });
  // (pass 104) the closed loop's memory check at a spec's line: a sweep's sim.duration of 1e5 s passed --check and
  // every sample ended in closed_loop's MemoryError (a traceback, exit 1)
  m.def("_closed_loop_fits_in_memory", [](double duration, double control_period) {
    if (!(duration > 0.0 && control_period > 0.0)) throw pyb::value_error("duration and period must be > 0 s");
    closedLoopRowsFit(duration, control_period, "");
  });
  // The backlash guard's rate gain inside the play on the encoders alone [-] (x play_inertia / Ts): the idle rule of
  // a dispersed play_inertia (gimbalsim/_idle_keys.py) reads the controller's own constant, never a copy
  m.attr("_PLAY_RATE_GAIN_ENCODERS") = kPlayRateGainEncoders;
}

}  // namespace gimbalsim::py
