// The tests' wiring of the project's controller to the plant's in-process
// closed loop, as a tool or the Python package wires them.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/controllers/pointing_controller.hpp"
#include "gimbalsim/firmware_sim/closed_loop.hpp"

namespace gimbalsim::controllers {
using firmware::ClosedLoopOptions;
using firmware::ClosedLoopResult;
using firmware::TickRecord;

/// The configured PointingController on the plant scene ps.
inline ClosedLoopResult runClosedLoop(const firmware::PlantScene& ps, const ControllerConfig& c,
                                      const ClosedLoopOptions& opt,
                                      const std::function<void(const TickRecord&)>& sink = {}) {
  PointingController controller(c);
  return firmware::runClosedLoop(ps, controller, c.profile, opt, sink);
}

/// The same on a Scene with the default (perfect) sensors.
inline ClosedLoopResult runClosedLoop(const Scene& sc, const ControllerConfig& c, const ClosedLoopOptions& opt,
                                      const std::function<void(const TickRecord&)>& sink = {}) {
  return runClosedLoop(firmware::PlantScene{sc, {}}, c, opt, sink);
}

}  // namespace gimbalsim::controllers
