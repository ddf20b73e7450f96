// The stepping simulator and its checkpoints (State).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <limits>
#include <memory>

#include "bindings.hpp"
#include "errors.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/dynamics/simulator.hpp"

namespace gimbalsim::py {

namespace pyb = pybind11;

namespace {

pyb::dict rowDict(const Row& r) {
  pyb::dict d;
  const double* p = rowData(r);
  for (int i = 0; i < kNumColumns; ++i) d[kColumns[i]] = p[i];
  return d;
}

pyb::array_t<double> vec(const std::vector<double>& x) {
  pyb::array_t<double> a(static_cast<pyb::ssize_t>(x.size()));
  std::copy(x.begin(), x.end(), a.mutable_data());
  return a;
}

std::string stopMessage(const Simulator& sim, const StepResult& r) {
  std::string msg = std::string("simulation stopped at t = ") + std::to_string(r.time) + " s: " + describe(r.status);
  if (*r.key()) msg += std::string(" (limit: ") + r.key() + ")";
  (void)sim;
  return msg;
}

constexpr long long kMaxSteps = 1LL << 40;  ///< per call: far past any run, far from overflow of k

}  // namespace

void bindSimulator(pyb::module_& m) {
  pyb::class_<SavedState>(m, "State",
                          "A full checkpoint of a Simulator: restore it and step on, the same bits as never "
                          "having stopped. Picklable.")
      .def_readonly("variant", &SavedState::variant)
      .def_readonly("t", &SavedState::t, "[s]")
      .def_property_readonly("q", [](const SavedState& s) { return vec(s.q); }, "generalised coordinates")
      .def_property_readonly("v", [](const SavedState& s) { return vec(s.v); }, "generalised velocities")
      .def_readonly("in_contact", &SavedState::in_contact)
      .def_readonly("v0", &SavedState::v0, "normal velocity at the onset of this impact [m/s]")
      .def_readonly("friction_mode", &SavedState::friction_mode)
      .def_readonly("vt_floor", &SavedState::vt_floor, "[m/s]")
      .def_readonly("h_next", &SavedState::h_next, "adaptive: next contact sub-step to try [s]")
      .def(pyb::pickle(
          [](const SavedState& s) {
            return pyb::make_tuple(s.variant, s.t, s.q, s.v, s.in_contact, s.v0, s.friction_mode, s.vt_floor,
                                   s.h_next);
          },
          [](const pyb::tuple& t) {
            if (t.size() != 9) throw std::runtime_error("State pickle: expected 9 fields");
            SavedState s;
            s.variant = t[0].cast<std::string>();
            s.t = t[1].cast<double>();
            s.q = t[2].cast<std::vector<double>>();
            s.v = t[3].cast<std::vector<double>>();
            s.in_contact = t[4].cast<bool>();
            s.v0 = t[5].cast<double>();
            s.friction_mode = t[6].cast<int>();
            s.vt_floor = t[7].cast<double>();
            s.h_next = t[8].cast<double>();
            return s;
          }));

  pyb::class_<Simulator>(m, "Simulator",
                         "The scene's plant stepped call by call (sim.step per step, sub-stepping inside). "
                         "Stepping releases the GIL.")
      .def(pyb::init([](const PyScene& s) { return std::make_unique<Simulator>(s.scene()); }), pyb::arg("scene"))
      .def_property_readonly("t", &Simulator::time, "simulated time [s]")
      .def_property_readonly("variant", [](const Simulator& s) { return variantName(s.model()); })
      .def_property_readonly("step_size", [](const Simulator& s) { return s.model().integrator.step; },
                             "sim.step [s]")
      .def(
          "step",
          [](Simulator& sim, double tau1, double tau2, long long n) {
            if (n < 0 || n > kMaxSteps) throw pyb::value_error("n must be in [0, 2^40], got " + std::to_string(n));
            StepResult r;
            {
              pyb::gil_scoped_release nogil;
              r = sim.step(Vec2(tau1, tau2), n);
            }
            if (!r.ok()) raiseStopped(r, stopMessage(sim, r));
          },
          pyb::arg("tau1"), pyb::arg("tau2"), pyb::arg("n") = 1,
          "advance n steps with joint torques tau1, tau2 [N m] held; raises SimulationStopped on numerical "
          "trouble (the state is then the last good one)")
      .def(
          "run",
          [](Simulator& sim, pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast> tau) {
            if (tau.ndim() != 2 || tau.shape(1) != 2) throw pyb::value_error("torques must be an (N, 2) array [N m]");
            const long long n = tau.shape(0);
            pyb::array_t<double> rows({static_cast<pyb::ssize_t>(n), static_cast<pyb::ssize_t>(kNumColumns)});
            long long done = 0;
            StepResult r;
            {
              pyb::gil_scoped_release nogil;
              r = sim.run(tau.data(), n, rows.mutable_data(), done);
            }
            if (!r.ok()) {
              pyb::dict extra;
              extra["steps_done"] = done;
              extra["outputs"] = rows[pyb::slice(0, done, 1)];
              raiseStopped(r, stopMessage(sim, r), extra);
            }
            return rows;
          },
          pyb::arg("torques"),
          "one step per row of torques (N, 2) [N m]; returns the (N, len(COLUMNS)) output rows after each step")
      .def("output", [](Simulator& sim) { return rowDict(sim.output()); },
           "the current output row (the CSV columns) as a dict")
      .def("_output_array",
           [](Simulator& sim) {
             const Row r = sim.output();
             pyb::array_t<double> a(kNumColumns);
             std::copy(rowData(r), rowData(r) + kNumColumns, a.mutable_data());
             return a;
           })
      .def_property(
          "state", [](const Simulator& sim) { return sim.save(); },
          [](Simulator& sim, const SavedState& s) {
            try {
              sim.restore(s);
            } catch (const std::invalid_argument& e) {
              throw pyb::value_error(e.what());
            }
          },
          "the full checkpoint (get: a copy; set: restore)");
}

}  // namespace gimbalsim::py
