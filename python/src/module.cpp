#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "errors.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/io/csv_format.hpp"
#include "gimbalsim/program/version.hpp"

PYBIND11_MODULE(_gimbalsim, m) {
  m.doc() = "gimbalsim's C++ core: scenes, runs, the stepping simulator, the pointing controller";
  gimbalsim::py::bindScene(m);
  gimbalsim::py::bindSimulator(m);
  gimbalsim::py::bindController(m);
  gimbalsim::py::bindStudyRules(m);
  m.attr("__version__") = gimbalsim::program::kVersion;  // the programs' --version string
  // The CSV convention's column names, the C++ writers' own rule (sweep and tune use it).
  m.def("csv_name", [](const std::string& name, const std::string& unit) { return gimbalsim::io::csvName(name, unit); },
        pybind11::arg("name"), pybind11::arg("unit") = "");
  // The whole-multiple rule of the scene and controller keys, so the specs check a duration alike.
  m.def("_whole_multiple_problem", &gimbalsim::wholeMultipleProblem, pybind11::arg("value"), pybind11::arg("unit"),
        pybind11::arg("unit_name"));
  // The memory check of the whole-run calls, for Simulator.run's Python argument check (_checked_methods.py).
  m.def("_fits_in_memory", &gimbalsim::py::fitsInMemory, pybind11::arg("need_bytes"), pybind11::arg("subject"),
        pybind11::arg("detail"), pybind11::arg("tail"));
}
