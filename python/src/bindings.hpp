// The extension module gimbalsim._gimbalsim: one function per part, each in
// its own file. The Python-facing API (names, dict overrides, Run) is in
// python/gimbalsim/__init__.py; these are its building blocks.
#pragma once

#include <pybind11/pybind11.h>

#include "gimbalsim/scene/scene.hpp"

namespace gimbalsim::py {

/// A loaded scene and the path it was loaded from (the summary's "scene").
struct PyScene {
  Scene scene;
  std::string path;
};

void bindScene(pybind11::module_& m);       ///< Scene, load_scene, keys, simulate, write_csv
void bindSimulator(pybind11::module_& m);   ///< State, Simulator
void bindController(pybind11::module_& m);  ///< Controller, closed_loop

}  // namespace gimbalsim::py
