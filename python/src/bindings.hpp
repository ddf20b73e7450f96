// The extension module gimbalsim._gimbalsim: one function per part, each in
// its own file. The Python-facing API (names, dict overrides, Run) is in
// python/gimbalsim/__init__.py; these are its building blocks.
#pragma once

#include <pybind11/pybind11.h>

#include <cstddef>
#include <string>

#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "guarded_caster.hpp"

namespace gimbalsim::py {

/// A loaded scene (the plant's: the Scene and its sensors) and the path it
/// was loaded from (the summary's "scene").
struct PyScene {
  firmware::PlantScene plant;
  std::string path;
  /// The file's absolute path, taken when it was loaded ("" for a text's scene): the input a run's to_csv never
  /// writes over, wherever the caller stands by then (pass 92: a relative path read after a chdir let it).
  std::string file;
  const Scene& scene() const { return plant.scene; }
};

/// Loads a plant scene from YAML text (empty: the defaults, then the
/// overrides); a refusal becomes the Python SceneError.
PyScene loadPyScene(const std::string& yaml, const std::string& origin, const std::vector<std::string>& overrides,
                    std::size_t printed = 0);

/// path made absolute against the current folder (as given when that fails).
std::string absoluteFile(const std::string& path);

/// Refuses (ValueError) a path holding a NUL byte: the C library would read
/// only the part before it, a file the caller did not name. `what` names the argument.
void checkPath(const std::string& path, const char* what);

void bindScene(pybind11::module_& m);       ///< Scene, load_scene, keys, simulate, write_csv
void bindSimulator(pybind11::module_& m);   ///< State, Simulator
void bindController(pybind11::module_& m);  ///< Controller, closed_loop
void bindStudyRules(pybind11::module_& m);  ///< the studies' key rules (_controller_read_rules, ...)

/// The rows of a closed loop's ticks over duration [s] at control_period [s], refused (MemoryError) when they would
/// not fit in memory (pass 82: 1e8 s at 1 ms grew towards 30 TB); note: said after the run's length.
std::size_t closedLoopRowsFit(double duration, double control_period, const std::string& note);

}  // namespace gimbalsim::py

GIMBALSIM_GUARDED_CASTER(gimbalsim::py::PyScene)
