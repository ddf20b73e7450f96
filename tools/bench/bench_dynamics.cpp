// Microbenchmarks of the dynamics hot path, named BM_<piece><Variant>: one
// derivative (BM_ForwardDynamics) and its parts, one RK4 step (BM_Rk4), one
// integrator step (BM_Step: one RK4 step away from contact, up to
// step/substep sub-steps in contact) for every compiled Variant; for the four
// clearance variants the contact law alone (BM_ContactLaw), the whole contact
// evaluation (BM_ClearanceContact) and step() through a located impact
// (BM_StepImpact).
//
// States are taken mid-run (after simulating 0.5 s of the paper scene; for
// the clearance variants the first step boundary after that with the journal
// in contact), so the numbers are those of a real run, not of the rest state.
//
//   build/bin/gimbalsim_bench                                  # quick look
//   build/bin/gimbalsim_bench --benchmark_repetitions=9        # medians (shown
//       with mean, stddev, cv and min; per-repetition rows are hidden on the
//       console but kept in --benchmark_out files)
//   tools/bench/run_bench.sh [extra args]                      # median table
//
// Scene files are read from GIMBALSIM_SCENE_DIR (environment), else from the
// source tree this binary was built from.
#include <benchmark/benchmark.h>

#include "bench_main.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "gimbalsim/dynamics/contact_law.hpp"
#include "gimbalsim/dynamics/forward_dynamics.hpp"
#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/scene/scene.hpp"
#include "gimbalsim/dynamics/simulate.hpp"

#ifndef GIMBALSIM_SCENE_DIR
#define GIMBALSIM_SCENE_DIR "tools/scenes"
#endif

namespace {

using namespace gimbalsim;

std::string sceneDir() {
  const char* env = std::getenv("GIMBALSIM_SCENE_DIR");
  return env && *env ? env : GIMBALSIM_SCENE_DIR;
}

/// Scene file and --set overrides that make a model of variant V.
template <class V>
Scene sceneFor() {
  std::vector<std::string> sets;
  if (!V::kFloating) sets.push_back("structure.base=fixed");
  if (V::kContact && !V::kFriction) sets.push_back("friction.law=none");
  const std::string file = sceneDir() + (V::kContact ? "/paper_clearance.yaml" : "/paper_ideal.yaml");
  Scene sc = loadScene(file, sets);
  bool match = false;
  dispatchVariant(sc.model, [&](auto tag) { match = std::is_same_v<decltype(tag), V>; });
  if (!match) throw std::runtime_error("scene " + file + " does not load as the benchmarked variant");
  return sc;
}

/// A model, a workspace and a mid-run state of variant V, plus the state at
/// the start of a step that contains a located impact (clearance only).
template <class V>
struct Fixture {
  Scene sc;
  Model m;
  std::unique_ptr<Data<V>> d;
  State<V> s;           ///< mid-run; in contact for the clearance variants
  State<V> pre_impact;  ///< start of a step during which an impact is located
  Input u;

  Fixture() : sc(sceneFor<V>()), m(sc.model), d(std::make_unique<Data<V>>(m)) {
    u.tau = sc.run.torque;
    s = initialState<V>(sc.run.initial);
    bool have_impact = false;
    const long long n_max = std::llround(sc.run.duration / m.integrator.step);
    for (long long k = 0; k < n_max; ++k) {
      const bool past = s.t >= 0.5 - 1e-12;
      bool in_contact = true;
      if constexpr (V::kContact) in_contact = s.in_contact[0] && clearanceGap<V>(m, s.q, s.v).delta > 0.0;
      if (past && in_contact && (!V::kContact || have_impact)) return;
      const State<V> before = s;
      const long long impacts = d->stats.impacts;
      if (!step(m, *d, s, u).ok()) throw std::runtime_error("set-up run failed");
      if (V::kContact && past && !have_impact && d->stats.impacts > impacts) {
        pre_impact = before;
        have_impact = true;
      }
    }
    throw std::runtime_error("no suitable mid-run state found");
  }
};

template <class V>
Fixture<V>& fixture() {
  static Fixture<V> f;  // built once per variant, on first use
  return f;
}

template <class V>
void BM_ForwardDynamics(benchmark::State& bs) {
  Fixture<V>& f = fixture<V>();
  for (auto _ : bs) {
    forwardDynamics(f.m, *f.d, f.s, f.u);
    benchmark::DoNotOptimize(f.d->vdot.data());
    benchmark::DoNotOptimize(f.d->qdot.data());
    benchmark::ClobberMemory();
  }
}

/// One RK4 step of the size step() would take here (h away from contact, the
/// sub-step in contact): four derivatives plus the stage arithmetic.
template <class V>
void BM_Rk4(benchmark::State& bs) {
  Fixture<V>& f = fixture<V>();
  const double h = V::kContact ? f.m.integrator.substep : f.m.integrator.step;
  State<V> out;
  for (auto _ : bs) {
    rk4(f.m, *f.d, f.s, f.u, h, out);
    benchmark::DoNotOptimize(out.q.data());
    benchmark::DoNotOptimize(out.v.data());
    benchmark::ClobberMemory();
  }
}

/// One integrator step of h from `start` (the state is reset each
/// iteration; a State copy costs a few ns), with the sub-steps (and, with
/// count_impacts, the impacts) per step as counters.
template <class V>
void timeStepFrom(benchmark::State& bs, const State<V>& start, bool count_impacts) {
  Fixture<V>& f = fixture<V>();
  State<V> s;
  const RunStats before = f.d->stats;
  for (auto _ : bs) {
    s = start;
    benchmark::DoNotOptimize(step(f.m, *f.d, s, f.u));
    benchmark::DoNotOptimize(s.q.data());
    benchmark::ClobberMemory();
  }
  auto perStep = [](long long n) {
    return benchmark::Counter(static_cast<double>(n), benchmark::Counter::kAvgIterations);
  };
  bs.counters["substeps"] = perStep(f.d->stats.substeps - before.substeps);
  if (count_impacts) bs.counters["impacts"] = perStep(f.d->stats.impacts - before.impacts);
}

/// One integrator step from the mid-run state.
template <class V>
void BM_Step(benchmark::State& bs) {
  timeStepFrom(bs, fixture<V>().s, /*count_impacts=*/false);
}

/// step() across a contact onset: sub-steps plus switch location.
template <class V>
void BM_StepImpact(benchmark::State& bs) {
  timeStepFrom(bs, fixture<V>().pre_impact, /*count_impacts=*/true);
}

/// The contact law alone: normalForce + frictionForce at the mid-run contact.
template <class V>
void BM_ContactLaw(benchmark::State& bs) {
  Fixture<V>& f = fixture<V>();
  forwardDynamics(f.m, *f.d, f.s, f.u);
  const ContactParams& cp = f.m.bearing[1];
  double delta = f.d->contact[0].delta, vn = f.d->contact[0].vn, vt = f.d->contact[0].vt, v0 = f.s.v0[0];
  for (auto _ : bs) {
    benchmark::DoNotOptimize(delta);  // keep the inputs opaque
    benchmark::DoNotOptimize(vn);
    benchmark::DoNotOptimize(vt);
    benchmark::DoNotOptimize(v0);
    const double fn = normalForce(cp, delta, vn, v0);
    const double ft = frictionForce(cp, fn, vt);
    benchmark::DoNotOptimize(fn);
    benchmark::DoNotOptimize(ft);
  }
}

/// The whole contact evaluation of the clearance joint at the mid-run state:
/// geometry (eccentricity, normal, relative velocities; needs shaft 1's twist
/// from the kinematics, done once outside the loop), the law, and the
/// generalised forces it adds.
template <class V>
void BM_ClearanceContact(benchmark::State& bs) {
  Fixture<V>& f = fixture<V>();
  kinematics(f.m, *f.d, f.s.q, f.s.v);
  for (auto _ : bs) {
    f.d->tau.setZero();
    clearanceContact<V>(f.m, *f.d, f.s.q, f.s.v, f.s.v0[0]);
    addContactForces(f.m, *f.d);
    benchmark::DoNotOptimize(f.d->tau.data());
    benchmark::ClobberMemory();
  }
}

/// The parts of one derivative, to see where its time goes: kinematics, the
/// bias forces (RNEA at zero acceleration), the mass matrix (CRBA) and the
/// solve of M vdot = tau - C (BM_MassSolve, as forwardDynamics() does it;
/// BM_CholeskySolve, the dense cross-check). Each part runs on
/// the workspace as forwardDynamics() leaves it at the mid-run state.
template <class V, class Part>
void timePart(benchmark::State& bs, Part&& part) {
  Fixture<V>& f = fixture<V>();
  forwardDynamics(f.m, *f.d, f.s, f.u);
  for (auto _ : bs) {
    part(f.m, *f.d, f.s);
    benchmark::ClobberMemory();
  }
}

template <class V>
void BM_Kinematics(benchmark::State& bs) {
  timePart<V>(bs, [](const Model& m, Data<V>& d, const State<V>& s) { kinematics(m, d, s.q, s.v); });
}

template <class V>
void BM_BiasForces(benchmark::State& bs) {
  timePart<V>(bs, [](const Model& m, Data<V>& d, const State<V>& s) {
    rnea(m, d, s.v, Data<V>::VecV::Zero(), d.bias);
  });
}

template <class V>
void BM_MassMatrix(benchmark::State& bs) {
  timePart<V>(bs, [](const Model& m, Data<V>& d, const State<V>&) { crba(m, d); });
}

/// As forwardDynamics() calls it: factor d.M (closed-form base block, Schur
/// complement over the chain: mass_factor.hpp) and solve for tau - bias.
template <class V>
void BM_MassSolve(benchmark::State& bs) {
  MassFactor<V> F;
  typename Data<V>::VecV x;
  timePart<V>(bs, [&](const Model&, Data<V>& d, const State<V>&) {
    benchmark::DoNotOptimize(factorMass(d.M, F));
    solveMass(F, (d.tau - d.bias).eval(), x);
    benchmark::DoNotOptimize(x.data());
  });
}

/// The cross-check's dense solve: Cholesky of the whole d.M, for tau - bias.
template <class V>
void BM_CholeskySolve(benchmark::State& bs) {
  typename Data<V>::MatV L;
  typename Data<V>::VecV x;
  timePart<V>(bs, [&](const Model&, Data<V>& d, const State<V>&) {
    benchmark::DoNotOptimize(choleskySolve(d.M, L, [&](int j) { return d.tau(j) - d.bias(j); }, x));
    benchmark::DoNotOptimize(x.data());
  });
}

/// Median, mean, stddev and cv are Google Benchmark's defaults; the minimum
/// is the least noisy figure on a shared machine.
double minimum(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

void configure(benchmark::internal::Benchmark* b) {
  b->Unit(benchmark::kNanosecond)->DisplayAggregatesOnly(true)->ComputeStatistics("min", minimum);
}

#define GIMBALSIM_BENCH_ALL_VARIANTS(fn)                               \
  BENCHMARK_TEMPLATE(fn, FixedIdeal)->Apply(configure);                \
  BENCHMARK_TEMPLATE(fn, FixedClearance)->Apply(configure);            \
  BENCHMARK_TEMPLATE(fn, FixedClearanceFriction)->Apply(configure);    \
  BENCHMARK_TEMPLATE(fn, FloatingIdeal)->Apply(configure);             \
  BENCHMARK_TEMPLATE(fn, FloatingClearance)->Apply(configure);         \
  BENCHMARK_TEMPLATE(fn, FloatingClearanceFriction)->Apply(configure)

#define GIMBALSIM_BENCH_CLEARANCE_VARIANTS(fn)                         \
  BENCHMARK_TEMPLATE(fn, FixedClearance)->Apply(configure);            \
  BENCHMARK_TEMPLATE(fn, FixedClearanceFriction)->Apply(configure);    \
  BENCHMARK_TEMPLATE(fn, FloatingClearance)->Apply(configure);         \
  BENCHMARK_TEMPLATE(fn, FloatingClearanceFriction)->Apply(configure)

#define GIMBALSIM_BENCH_NO_FRICTION_VARIANTS(fn)                       \
  BENCHMARK_TEMPLATE(fn, FixedIdeal)->Apply(configure);                \
  BENCHMARK_TEMPLATE(fn, FixedClearance)->Apply(configure);            \
  BENCHMARK_TEMPLATE(fn, FloatingIdeal)->Apply(configure);             \
  BENCHMARK_TEMPLATE(fn, FloatingClearance)->Apply(configure)

GIMBALSIM_BENCH_ALL_VARIANTS(BM_ForwardDynamics);
GIMBALSIM_BENCH_ALL_VARIANTS(BM_Rk4);
GIMBALSIM_BENCH_ALL_VARIANTS(BM_Step);
GIMBALSIM_BENCH_NO_FRICTION_VARIANTS(BM_Kinematics);
GIMBALSIM_BENCH_NO_FRICTION_VARIANTS(BM_BiasForces);
GIMBALSIM_BENCH_NO_FRICTION_VARIANTS(BM_MassMatrix);
GIMBALSIM_BENCH_NO_FRICTION_VARIANTS(BM_MassSolve);
GIMBALSIM_BENCH_NO_FRICTION_VARIANTS(BM_CholeskySolve);
GIMBALSIM_BENCH_CLEARANCE_VARIANTS(BM_ContactLaw);
GIMBALSIM_BENCH_CLEARANCE_VARIANTS(BM_ClearanceContact);
GIMBALSIM_BENCH_CLEARANCE_VARIANTS(BM_StepImpact);

}  // namespace

// Google Benchmark's own arguments, under the project's program entry: its
// --version, exit codes (an argument it does not know is refused with 2; it
// returned 1) and outermost guard.
int main(int argc, char** argv) { return gimbalsim::bench::benchmarkMain("gimbalsim_bench", argc, argv); }
