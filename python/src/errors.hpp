// Raising the package's Python exceptions (gimbalsim._errors) from C++ with
// their fields set, so a program reads the key and place, not the text.
#pragma once

#include <pybind11/pybind11.h>

#include "gimbalsim/scene/scene.hpp"
#include "gimbalsim/dynamics/step_result.hpp"

namespace gimbalsim::py {

/// Raises gimbalsim.SceneError (a ValueError) for a refused scene or configuration.
[[noreturn]] void raiseSceneError(const InputError& e);

/// Raises gimbalsim.SimulationStopped naming the step's status, limit key and time.
/// `message` is the text; `extra` entries become attributes (e.g. outputs, steps_done).
[[noreturn]] void raiseStopped(const StepResult& r, const std::string& message, pybind11::dict extra = {});

/// Raises MemoryError, "<subject> need X GB (<detail>), more than the Y GB of memory free now<tail>", unless
/// need_bytes fit in the memory free now (the one check of the Python API's whole-run calls and Simulator.run).
void fitsInMemory(double need_bytes, const std::string& subject, const std::string& detail, const std::string& tail);

/// The number of rows a run will hold in memory (`rows` of `columns` doubles, kept twice: the records, then the
/// numpy array made from them), after checking that they fit in the memory free now; raises MemoryError naming the
/// gigabytes and `what` (the call and its size) otherwise. Pages are committed as they are written, so a run that
/// would not fit never failed to allocate: it grew the process until the kernel killed it.
std::size_t rowsFitInMemory(double rows, int columns, const std::string& what);

}  // namespace gimbalsim::py
