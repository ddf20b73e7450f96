// Scenes (load, keys, pickle) and whole runs (simulate, the CSV bytes).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "bindings.hpp"
#include "errors.hpp"
#include "key_dicts.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/run_output/run_output.hpp"

namespace gimbalsim::py {

namespace pyb = pybind11;

namespace {

PyScene load(const std::string& path, const std::vector<std::string>& overrides) {
  checkPath(path, "scene path");
  try {
    return PyScene{firmware::loadPlantScene(path, overrides), path, absoluteFile(path)};
  } catch (const InputError& e) {
    raiseSceneError(e);
  }
}

/// The scene's every key as --set reads it back, then `overrides`: a new scene.
PyScene replaced(const PyScene& s, const std::vector<std::string>& overrides) {
  std::vector<std::string> all = firmware::plantTable().values(s.plant);
  const std::size_t printed = all.size();
  all.insert(all.end(), overrides.begin(), overrides.end());
  PyScene out = loadPyScene("", s.path, all, printed);
  out.file = s.file;
  return out;
}

/// The column set of `names`, which must be the columns of some scene's
/// joint kinds (Scene.columns), so that a CSV is always one a run writes.
ColumnSet columnSet(const std::vector<std::string>& names) {
  using K = ClearanceKind;
  for (K k1 : {K::Ideal, K::Planar, K::Spatial}) {
    for (K k2 : {K::Ideal, K::Planar, K::Spatial}) {
      const ColumnSet cols = outputColumns(k1, k2);
      bool same = static_cast<int>(names.size()) == cols.count;
      for (int k = 0; same && k < cols.count; ++k) same = names[k] == kColumns[cols.index[k]];
      if (same) return cols;
    }
  }
  throw std::invalid_argument("columns must be a scene's output columns (Scene.columns), got " +
                              std::to_string(names.size()) + " names");
}

/// Writes the CSV text of the columns `names` of rows (n x kNumColumns) to
/// path, by the rules of every output (io/output_file.hpp: its folder must
/// exist, no link, never one of `inputs`); raises OSError naming the file.
void writeCsv(const std::string& path, pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast> rows,
              const std::vector<std::string>& inputs, const std::vector<std::string>& names) {
  checkPath(path, "output path");
  for (const std::string& in : inputs) checkPath(in, "input path");
  if (rows.ndim() != 2 || rows.shape(1) != kNumColumns) {
    throw std::invalid_argument("rows must be an (N, " + std::to_string(kNumColumns) + ") array");
  }
  const ColumnSet cols = columnSet(names);
  std::string text = io::csvHeader(cols);
  const double* p = rows.data();
  for (pyb::ssize_t i = 0; i < rows.shape(0); ++i) {
    io::appendCsvRow(text, std::span<const double, kNumColumns>(p + i * kNumColumns, kNumColumns), cols);
  }
  try {
    io::OutputFile out(path, inputs);
    if (!out.write(text) || !out.commit()) {
      throw io::OutputError(out.error().empty() ? path + ": write failed" : out.error());
    }
  } catch (const io::OutputError& e) {
    PyErr_SetString(PyExc_OSError, e.what());
    throw pyb::error_already_set();
  }
}

/// "key=value" for every key whose value differs from the built-in default.
std::vector<std::string> nonDefault(const PyScene& s) {
  static const std::vector<std::string> defaults =
      firmware::plantTable().values(firmware::loadPlantSceneText("", "<defaults>", {}));
  std::vector<std::string> out;
  for (const std::string& kv : firmware::plantTable().values(s.plant)) {
    if (std::find(defaults.begin(), defaults.end(), kv) == defaults.end()) out.push_back(kv);
  }
  return out;
}

}  // namespace

std::string absoluteFile(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::absolute(path, ec);
  return ec ? path : p.lexically_normal().string();
}

void checkPath(const std::string& path, const char* what) {
  if (path.find('\0') != std::string::npos) {
    throw pyb::value_error(std::string(what) + " holds a NUL byte at position " + std::to_string(path.find('\0')) +
                           ": refused (the file before it would be used)");
  }
}

PyScene loadPyScene(const std::string& yaml, const std::string& origin, const std::vector<std::string>& overrides,
                    std::size_t printed) {
  try {
    return PyScene{firmware::loadPlantSceneText(yaml, origin, overrides, printed), origin, ""};
  } catch (const InputError& e) {
    raiseSceneError(e);
  }
}

void bindScene(pyb::module_& m) {
  pyb::class_<PyScene>(m, "Scene", "A validated scene: the physics (Model) and how to run it (RunSpec)")
      .def_property_readonly("path", [](const PyScene& s) { return s.path; }, "the file it was loaded from")
      .def_property_readonly("_file", [](const PyScene& s) { return s.file; }, "that file's absolute path")
      .def_property_readonly("name", [](const PyScene& s) { return s.scene().model.name; })
      .def_property_readonly("variant", [](const PyScene& s) { return variantName(s.scene().model); },
                             "the compiled variant it runs as, e.g. floating_ideal_planar_friction")
      .def_property_readonly("warnings", [](const PyScene& s) { return s.scene().warnings; })
      .def_property_readonly(
          "columns",
          [](const PyScene& s) {
            const ColumnSet cols = io::outputColumns(s.scene().model);
            pyb::tuple t(cols.count);
            for (int k = 0; k < cols.count; ++k) t[k] = pyb::str(kColumns[cols.index[k]]);
            return t;
          },
          "the output columns this scene writes, a subset of COLUMNS in its order (the CSV's, without units): "
          "joint 1's when it has clearance, tilt and per-end ones for a spatial joint")
      .def_property_readonly("step", [](const PyScene& s) { return s.scene().model.integrator.step; }, "sim.step [s]")
      .def_property_readonly("duration", [](const PyScene& s) { return s.scene().run.duration; }, "sim.duration [s]")
      .def_property_readonly("output_interval", [](const PyScene& s) { return s.scene().run.output_interval; },
                             "sim.output_interval [s]")
      .def("values", [](const PyScene& s) { return keyValueDict(firmware::plantTable().values(s.plant)); },
           "every key with its value, as text that load_scene's overrides read back exactly (a joint's own "
           "bearing or eccentricity key only where it differs from the one for both joints)")
      .def("_replaced", &replaced, pyb::arg("overrides"))
      .def("_non_default", &nonDefault, "'key=value' for every key that differs from the built-in default")
      // Pickled as a call of gimbalsim._unpickle_scene (any protocol, 0 to 5;
      // a Python function, as pickle cannot name a pybind11 one): the values
      // are loaded again, so an unpickled scene is checked as a loaded one.
      .def("__reduce__", [](const PyScene& s) {
        return pyb::make_tuple(pyb::module_::import("gimbalsim").attr("_unpickle_scene"),
                               pyb::make_tuple(s.path, firmware::plantTable().values(s.plant), s.file));
      });

  m.def("_unpickle_scene", [](const std::string& path, const std::vector<std::string>& values,
                               const std::string& file) {
    PyScene s = loadPyScene("", path, values, values.size());
    s.file = file;
    return s;
  });
  m.def("_load_scene", &load, pyb::arg("path"), pyb::arg("overrides"));
  m.def("_load_scene_text", [](const std::string& yaml, const std::string& origin,
                               const std::vector<std::string>& overrides) { return loadPyScene(yaml, origin, overrides); },
        pyb::arg("yaml"), pyb::arg("origin"), pyb::arg("overrides"));
  m.def("_keys", [] { return keyInfoList(firmware::plantTable().info()); });
  m.def("_key_aliases", [] { return firmware::plantTable().aliases; });
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
        if (integrator == "reference") {
          if (const std::string why = referenceRefusal(s.scene().model); !why.empty()) {
            throw pyb::value_error("integrator 'reference': " + why);
          }
        }
        // the rows of sim.duration at sim.output_interval, and the initial one
        const RunSpec& run = s.scene().run;
        const std::size_t n_rows = rowsFitInMemory(
            std::ceil(run.duration / run.output_interval) + 1.0, kNumColumns,
            "simulate (sim.duration " + formatNumber(run.duration) + " s at sim.output_interval " +
                formatNumber(run.output_interval) + " s; gimbalsim simulate --out streams its rows)");
        std::vector<double> rows;
        rows.reserve(n_rows * kNumColumns);  // no doubling on the way: the bound above holds
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

  m.def("_write_csv", &writeCsv, pyb::arg("path"), pyb::arg("rows"), pyb::arg("inputs"), pyb::arg("columns"));
}

}  // namespace gimbalsim::py
