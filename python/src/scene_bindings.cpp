// Scenes (load, keys, pickle) and whole runs (simulate, the CSV bytes).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cerrno>
#include <cstdio>
#include <stdexcept>

#include "bindings.hpp"
#include "errors.hpp"
#include "key_dicts.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/run_output/run_output.hpp"

namespace gimbalsim::py {

namespace pyb = pybind11;

namespace {

PyScene load(const std::string& path, const std::vector<std::string>& overrides) {
  try {
    return PyScene{firmware::loadPlantScene(path, overrides), path};
  } catch (const InputError& e) {
    raiseSceneError(e);
  }
}

/// The scene's every key as --set reads it back, then `overrides`: a new scene.
PyScene replaced(const PyScene& s, const std::vector<std::string>& overrides) {
  std::vector<std::string> all = firmware::plantTable().values(s.plant);
  all.insert(all.end(), overrides.begin(), overrides.end());
  return loadPyScene("", s.path, all);
}

/// Writes the CSV text of rows (n x kNumColumns) to path; raises OSError naming the file.
void writeCsv(const std::string& path, pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast> rows) {
  if (rows.ndim() != 2 || rows.shape(1) != kNumColumns) {
    throw std::invalid_argument("rows must be an (N, " + std::to_string(kNumColumns) + ") array");
  }
  std::string text = io::csvHeader();
  const double* p = rows.data();
  for (pyb::ssize_t i = 0; i < rows.shape(0); ++i) {
    io::appendCsvRow(text, std::span<const double, kNumColumns>(p + i * kNumColumns, kNumColumns));
  }
  // io::writeFileAtomically: a temporary beside it, renamed when whole; a
  // symlink or non-regular file under the name is refused.
  try {
    io::writeFileAtomically(path, text);
  } catch (const io::OutputError& e) {
    PyErr_SetString(PyExc_OSError, e.what());
    throw pyb::error_already_set();
  }
}

}  // namespace

PyScene loadPyScene(const std::string& yaml, const std::string& origin, const std::vector<std::string>& overrides) {
  try {
    return PyScene{firmware::loadPlantSceneText(yaml, origin, overrides), origin};
  } catch (const InputError& e) {
    raiseSceneError(e);
  }
}

void bindScene(pyb::module_& m) {
  pyb::class_<PyScene>(m, "Scene", "A validated scene: the physics (Model) and how to run it (RunSpec)")
      .def_property_readonly("path", [](const PyScene& s) { return s.path; }, "the file it was loaded from")
      .def_property_readonly("name", [](const PyScene& s) { return s.scene().model.name; })
      .def_property_readonly("variant", [](const PyScene& s) { return variantName(s.scene().model); },
                             "the compiled variant it runs as, e.g. floating_clearance_friction")
      .def_property_readonly("warnings", [](const PyScene& s) { return s.scene().warnings; })
      .def_property_readonly("step", [](const PyScene& s) { return s.scene().model.integrator.step; }, "sim.step [s]")
      .def_property_readonly("duration", [](const PyScene& s) { return s.scene().run.duration; }, "sim.duration [s]")
      .def_property_readonly("output_interval", [](const PyScene& s) { return s.scene().run.output_interval; },
                             "sim.output_interval [s]")
      .def("values", [](const PyScene& s) { return keyValueDict(firmware::plantTable().values(s.plant)); },
           "every key with its value, as text that load_scene's overrides read back exactly")
      .def("_replaced", &replaced, pyb::arg("overrides"))
      .def(pyb::pickle(
          [](const PyScene& s) { return pyb::make_tuple(s.path, firmware::plantTable().values(s.plant)); },
          [](const pyb::tuple& t) {
            if (t.size() != 2) throw std::runtime_error("Scene pickle: expected (path, values)");
            return loadPyScene("", t[0].cast<std::string>(), t[1].cast<std::vector<std::string>>());
          }));

  m.def("_load_scene", &load, pyb::arg("path"), pyb::arg("overrides"));
  m.def("_load_scene_text", &loadPyScene, pyb::arg("yaml"), pyb::arg("origin"), pyb::arg("overrides"));
  m.def("_keys", [] { return keyInfoList(firmware::plantTable().info()); });
  m.attr("COLUMNS") = [] {
    pyb::tuple t(kNumColumns);
    for (int i = 0; i < kNumColumns; ++i) t[i] = pyb::str(kColumns[i]);
    return t;
  }();

  m.def(
      "_simulate",
      [](const PyScene& s, const std::string& integrator) {
        if (integrator != "rk4" && integrator != "reference") {
          throw pyb::value_error("integrator must be 'rk4' or 'reference', got '" + integrator + "'");
        }
        std::vector<double> rows;
        RunResult r;
        {
          pyb::gil_scoped_release nogil;
          r = simulate(
              s.scene(),
              [&](const Row& row) { rows.insert(rows.end(), rowData(row), rowData(row) + kNumColumns); },
              integrator == "reference" ? IntegratorKind::Reference : IntegratorKind::Rk4);
        }
        const pyb::ssize_t n = static_cast<pyb::ssize_t>(rows.size() / kNumColumns);
        pyb::array_t<double> a({n, static_cast<pyb::ssize_t>(kNumColumns)});
        std::copy(rows.begin(), rows.end(), a.mutable_data());
        return pyb::make_tuple(a, io::runSummary(s.scene().model, r, s.path, integrator).dump());
      },
      pyb::arg("scene"), pyb::arg("integrator"));

  m.def("_write_csv", &writeCsv, pyb::arg("path"), pyb::arg("rows"));
}

}  // namespace gimbalsim::py
