// The in-process closed-loop tick against the plant's stepping (Google
// Benchmark): one iteration is one run of the pointing study's length
// (8.5 s: slew, hold, track) of a scene with the default controller, as
// runClosedLoop runs it for the sweeps and studies. Counters per tick, from
// the run's own cost meter (ClosedLoopOptions::cost, steady clock):
//   step_us        the plant's stepping (RK4 and its contact sub-steps)
//   controller_us  the controller's turn (estimator, reference, PID, model feed-forward)
//   tick_work_us   everything else the tick does besides stepping: the
//                  controller, firmware and sensors, truth observer, record, figures
//   work_per_step  tick_work_us / step_us (issue target on paper_clearance: at most 0.3)
//
//   build/bin/gimbalsim_bench_loop --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// Scene files: GIMBALSIM_SCENE_DIR (environment), else tools/scenes from the working directory.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <exception>
#include <iterator>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "scene_once.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/controllers/pointing_controller.hpp"
#include "gimbalsim/firmware_sim/closed_loop.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"

#ifndef GIMBALSIM_SCENE_DIR
#define GIMBALSIM_SCENE_DIR "tools/scenes"
#endif

namespace {

using namespace gimbalsim;

struct Case {
  const char* scene;
  std::vector<std::string> overrides;
  const char* label;
};
// paper_clearance twice: the scene's fixed sub-steps, and the adaptive policy
// (which plain Coulomb friction cannot use: coulomb_stick, its regularised twin).
const Case kCases[] = {
    {"paper_ideal", {}, "paper_ideal"},
    {"paper_clearance", {}, "paper_clearance"},
    {"paper_clearance", {"friction.law=coulomb_stick", "sim.substep_policy=adaptive"}, "paper_clearance adaptive"},
    {"paper_spatial2", {}, "paper_spatial2"},
};

const firmware::PlantScene& plantOf(const Case& k) {
  const char* dir = std::getenv("GIMBALSIM_SCENE_DIR");
  return bench::plantSceneOnce(std::string(dir && *dir ? dir : GIMBALSIM_SCENE_DIR) + "/" + k.scene + ".yaml",
                               k.overrides);
}

void BM_ClosedLoop(benchmark::State& bs) {
  const Case& k = kCases[bs.range(0)];
  bs.SetLabel(k.label);
  const firmware::PlantScene& ps = plantOf(k);  // loaded before any case ran (main): the same object
  const controllers::ControllerConfig c =
      controllers::loadControllerConfigText("", "the built-in default configuration", {});
  try {
    firmware::ClosedLoopCost cost;
    firmware::ClosedLoopOptions opt;
    opt.duration = 8.5;
    opt.cost = &cost;
    for (auto _ : bs) {
      controllers::PointingController controller(c);
      const firmware::ClosedLoopResult r = firmware::runClosedLoop(ps, controller, c.profile, opt);
      if (!r.ok) {
        bench::fail(bs, r.error, program::kStopped);
        return;
      }
    }
    const double ticks = static_cast<double>(cost.ticks);
    bs.counters["step_us"] = 1e6 * cost.step_s / ticks;
    bs.counters["controller_us"] = 1e6 * cost.controller_s / ticks;
    bs.counters["tick_work_us"] = 1e6 * (cost.total_s - cost.step_s) / ticks;
    bs.counters["work_per_step"] = (cost.total_s - cost.step_s) / cost.step_s;
  } catch (const std::exception& e) {
    bench::fail(bs, e.what(), program::kInternal);
  }
}
BENCHMARK(BM_ClosedLoop)->DenseRange(0, 3)->ArgName("scene")->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  // every selected case's scene loads before any case runs: one that does not refuses the run (exit 2)
  return gimbalsim::bench::benchmarkMain("gimbalsim_bench_loop", argc, argv, [](int n, char** v) {
    for (std::size_t i = 0; i < std::size(kCases); ++i) {
      if (gimbalsim::bench::filterSelects(n, v, "BM_ClosedLoop/scene:" + std::to_string(i) + "/iterations:1")) {
        (void)plantOf(kCases[i]);
      }
    }
  });
}
