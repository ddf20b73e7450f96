// The stepping simulator and its checkpoints (State).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <memory>
#include <mutex>

#include "bindings.hpp"
#include "errors.hpp"
#include "guarded_caster.hpp"
#include "gimbalsim/dynamics/saved_state.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/dynamics/simulator.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/run_output/run_output.hpp"

namespace gimbalsim::py {

/// A Simulator and the lock that serialises calls on it: stepping releases
/// the GIL, so two threads may call one object; the second waits (without
/// the GIL) until the first is done, and each call sees a whole state.
struct PySimulator {
  explicit PySimulator(const Scene& scene) : sim(scene) {}
  Simulator sim;
  std::mutex busy;
};

}  // namespace gimbalsim::py

GIMBALSIM_GUARDED_CASTER(gimbalsim::SavedState)
GIMBALSIM_GUARDED_CASTER(gimbalsim::py::PySimulator)

namespace gimbalsim::py {

namespace pyb = pybind11;

namespace {

/// The columns of r the simulator's scene writes (io::outputColumns), by name.
pyb::dict rowDict(const Row& r, const ColumnSet& cols) {
  pyb::dict d;
  const double* p = rowData(r);
  for (int k = 0; k < cols.count; ++k) d[kColumns[cols.index[k]]] = p[cols.index[k]];
  return d;
}

pyb::array_t<double> vec(const std::vector<double>& x) {
  pyb::array_t<double> a(static_cast<pyb::ssize_t>(x.size()));
  std::copy(x.begin(), x.end(), a.mutable_data());
  return a;
}

std::string stopMessage(const Model& m, const StepResult& r) {
  std::string msg = describeStop(m, r);  // the one message of a stopped step, as the command line's
  if (*r.key()) msg += std::string(" (limit: ") + r.key() + ")";
  return msg;
}

constexpr long long kMaxSteps = 1LL << 40;  ///< per call: far past any run, far from overflow of k

/// f(sim) with the GIL released and the object's lock held (lock after
/// release, unlock before reacquiring: no thread ever waits holding both).
template <class F>
auto locked(PySimulator& p, F&& f) {
  pyb::gil_scoped_release nogil;
  std::lock_guard<std::mutex> lock(p.busy);
  return f(p.sim);
}

/// A State from its fields (a pickle, a user's arrays): checked as any state
/// from outside is (saved_state.hpp), ValueError naming each bad field.
SavedState makeState(const std::string& variant, double t, const std::vector<double>& q,
                     const std::vector<double>& v, const std::vector<bool>& in_contact,
                     const std::vector<double>& v0, int friction_mode, double vt_floor,
                     double h_next) {
  SavedState s;
  s.variant = variant;
  s.t = t;
  s.q = q;
  s.v = v;
  s.in_contact = in_contact;
  s.v0 = v0;
  s.friction_mode = friction_mode;
  s.vt_floor = vt_floor;
  s.h_next = h_next;
  try {
    checkSavedState(s);
  } catch (const std::invalid_argument& e) {
    throw pyb::value_error(e.what());
  }
  return s;
}

/// [N m] the range of a joint torque: torque.tau1 and tau2's (dynamics/scene/src/scene.cpp, kTorque),
/// within which the plant's arithmetic stays finite (1e300 N m overflowed the state to NaN).
constexpr double kMaxAbsTorque = 1e6;

void checkTorque(double tau1, double tau2) {
  if (!(std::abs(tau1) <= kMaxAbsTorque) || !(std::abs(tau2) <= kMaxAbsTorque)) {
    throw pyb::value_error("torques must be finite and within [-1e6, 1e6] N m (as torque.tau1, tau2), got tau1 = " +
                           formatNumber(tau1) + ", tau2 = " + formatNumber(tau2) + " [N m]");
  }
}

}  // namespace

void bindSimulator(pyb::module_& m) {
  pyb::class_<SavedState> state(m, "State",
                                "A full checkpoint of a Simulator: restore it and step on, the same bits as never "
                                "having stopped. Picklable. Made from fields, it is checked as a scene is.");
  state
      .def(pyb::init(&makeState), pyb::arg("variant"), pyb::arg("t"), pyb::arg("q"), pyb::arg("v"),
           pyb::arg("in_contact") = std::vector<bool>{}, pyb::arg("v0") = std::vector<double>{},
           pyb::arg("friction_mode") = 0,
           pyb::arg("vt_floor") = 0.0, pyb::arg("h_next") = 0.0)
      .def_readonly("variant", &SavedState::variant)
      .def_readonly("t", &SavedState::t, "[s]")
      .def_property_readonly("q", [](const SavedState& s) { return vec(s.q); }, "generalised coordinates")
      .def_property_readonly("v", [](const SavedState& s) { return vec(s.v); }, "generalised velocities")
      .def_property_readonly("in_contact", [](const SavedState& s) { return s.in_contact; },
                             "each contact end's side (joint 1's ends first; a spatial joint has two)")
      .def_property_readonly("v0", [](const SavedState& s) { return s.v0; },
                             "each contact end's normal velocity at the onset of its impact [m/s]")
      .def_readonly("friction_mode", &SavedState::friction_mode)
      .def_readonly("vt_floor", &SavedState::vt_floor, "[m/s]")
      .def_readonly("h_next", &SavedState::h_next, "adaptive: next contact sub-step to try [s]")
      // Pickled as a call of the class with its fields (any protocol, 0 to 5),
      // so an unpickled State is checked as a constructed one.
      .def("__reduce__", [state](const SavedState& s) {
        return pyb::make_tuple(state, pyb::make_tuple(s.variant, s.t, s.q, s.v, s.in_contact, s.v0, s.friction_mode,
                                                      s.vt_floor, s.h_next));
      });

  pyb::class_<PySimulator>(m, "Simulator",
                           "The scene's plant stepped call by call (sim.step per step, sub-stepping inside). "
                           "Stepping releases the GIL; calls on one Simulator from several threads run one "
                           "after the other.")
      .def(pyb::init([](const PyScene& s) { return std::make_unique<PySimulator>(s.scene()); }), pyb::arg("scene"))
      .def_property_readonly("t", [](PySimulator& p) { return locked(p, [](Simulator& s) { return s.time(); }); },
                             "simulated time [s]")
      .def_property_readonly("variant", [](const PySimulator& p) { return variantName(p.sim.model()); })
      .def_property_readonly("step_size", [](const PySimulator& p) { return p.sim.model().integrator.step; },
                             "sim.step [s]")
      .def(
          "step",
          [](PySimulator& p, double tau1, double tau2, pyb::handle steps) {
            // bool is an int to Python: step(n=True) would run one step for a flag given by mistake
            if (PyBool_Check(steps.ptr()) || !PyIndex_Check(steps.ptr())) {
              throw pyb::type_error("n must be an int (a number of steps), got " +
                                    std::string(pyb::str(pyb::type::handle_of(steps).attr("__name__"))));
            }
            int overflow = 0;  // an int beyond long long (2**70) is out of range too, not a cast error
            const long long n = PyLong_AsLongLongAndOverflow(steps.ptr(), &overflow);
            if (n == -1 && PyErr_Occurred()) throw pyb::error_already_set();
            if (overflow != 0 || n < 0 || n > kMaxSteps) {
              throw pyb::value_error("n must be in [0, 2^40], got " + std::string(pyb::str(steps)));
            }
            checkTorque(tau1, tau2);
            const StepResult r = locked(p, [&](Simulator& s) { return s.step(Vec2(tau1, tau2), n); });
            if (!r.ok()) raiseStopped(r, stopMessage(p.sim.model(), r));
          },
          pyb::arg("tau1"), pyb::arg("tau2"), pyb::arg("n") = 1,
          "advance n steps with joint torques tau1, tau2 [N m] held; raises SimulationStopped on numerical "
          "trouble (the state is then the last good one)")
      .def(
          "run",
          [](PySimulator& p, pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast> tau) {
            if (tau.ndim() != 2 || tau.shape(1) != 2) throw pyb::value_error("torques must be an (N, 2) array [N m]");
            const long long n = tau.shape(0);
            for (long long i = 0; i < n; ++i) {
              const double* row = tau.data(i, 0);
              if (!(std::abs(row[0]) <= kMaxAbsTorque) || !(std::abs(row[1]) <= kMaxAbsTorque)) {
                throw pyb::value_error("torques row " + std::to_string(i) +
                                       " is not finite and within [-1e6, 1e6] N m (" + formatNumber(row[0]) + ", " +
                                       formatNumber(row[1]) + ") [N m]");
              }
            }
            pyb::array_t<double> rows({static_cast<pyb::ssize_t>(n), static_cast<pyb::ssize_t>(kNumColumns)});
            long long done = 0;
            const double* in = tau.data();
            double* out = rows.mutable_data();
            const StepResult r = locked(p, [&](Simulator& s) { return s.run(in, n, out, done); });
            if (!r.ok()) {
              pyb::dict extra;
              extra["steps_done"] = done;
              extra["outputs"] = rows[pyb::slice(0, done, 1)];
              raiseStopped(r, stopMessage(p.sim.model(), r), extra);
            }
            return rows;
          },
          pyb::arg("torques"),
          "one step per row of torques (N, 2) [N m]; returns the (N, len(COLUMNS)) output rows after each step")
      .def("output",
           [](PySimulator& p) {
             return rowDict(locked(p, [](Simulator& s) { return s.output(); }), io::outputColumns(p.sim.model()));
           },
           "the current output row as a dict: the scene's CSV columns without their unit suffix (Scene.columns)")
      .def("_output_array",
           [](PySimulator& p) {
             const Row r = locked(p, [](Simulator& s) { return s.output(); });
             pyb::array_t<double> a(kNumColumns);
             std::copy(rowData(r), rowData(r) + kNumColumns, a.mutable_data());
             return a;
           })
      .def_property(
          "state", [](PySimulator& p) { return locked(p, [](Simulator& s) { return s.save(); }); },
          [](PySimulator& p, const SavedState& saved) {
            const std::string refused = locked(p, [&](Simulator& s) {
              try {
                s.restore(saved);  // checked against this simulator's scene (saved_state.hpp)
              } catch (const std::invalid_argument& e) {
                return std::string(e.what());
              }
              return std::string();
            });
            if (!refused.empty()) throw pyb::value_error(refused);
          },
          "the full checkpoint (get: a copy; set: restore, checked against this simulator's scene)");
}

}  // namespace gimbalsim::py
