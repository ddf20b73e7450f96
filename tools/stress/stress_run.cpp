// Running the stress grid: see stress_run.hpp.
#include "stress_run.hpp"

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <thread>

#include "gimbalsim/scene/scene.hpp"
#include "gimbalsim/program/stop_signal.hpp"

namespace gimbalsim::stress {

void parallel(std::size_t n, int threads, const std::function<void(std::size_t)>& job) {
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i; (i = next++) < n;) job(i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
}

namespace {
std::mutex g_print;
}

void printCase(const Case& c) {
  std::lock_guard<std::mutex> lock(g_print);
  const Outcome& o = c.out;
  if (o.verdict == Verdict::Refused) {  // nothing ran: no figures to print
    std::printf("%-15s %-24s %-16s %s\n    %s\n", verdictName(o.verdict), c.group.c_str(), c.scene.c_str(),
                joined(c.sets).c_str(), o.reason.c_str());
    std::fflush(stdout);
    return;
  }
  std::printf("%-15s %-24s %-16s %-62s subst/s %8.3g  P %8.2g L %8.2g  Erise %8.2g  pen %8.2g m  %6.2f s\n",
              verdictName(o.verdict), c.group.c_str(), c.scene.c_str(), joined(c.sets).c_str(),
              o.substeps_per_second, o.momentum_rel_linear, o.momentum_rel_angular, o.energy_rise_rel,
              o.max_penetration, o.run.wall_seconds);
  if (!o.reason.empty()) std::printf("    %s\n", o.reason.c_str());
  std::fflush(stdout);
}

bool isSceneStem(const std::string& scene) {
  // a name with a file's extension is a path (pass 45: NAME.yaml was read as <scenes>/NAME.yaml.yaml)
  return scene.find('/') == std::string::npos && std::filesystem::path(scene).extension() != ".yaml";
}

std::string scenePath(const std::string& scenes, const std::string& scene) {
  return isSceneStem(scene) ? scenes + "/" + scene + ".yaml" : scene;
}

void runCase(Case& c, const std::string& scenes, const Bounds& b) {
  c.out = stress::runCase(scenePath(scenes, c.scene), c.sets, b);
  c.ran = true;
  printCase(c);
}

void runSweeps(std::vector<Case>& cases, const std::string& scenes, int threads, const Bounds& b) {
  parallel(cases.size(), threads, [&](std::size_t i) {
    if (io::stopRequested()) return;
    runCase(cases[i], scenes, b);
  });
}

namespace {

void walkCell(Cell& cell, const std::string& scenes, const std::string& dur, const Bounds& b) {
  for (double h : walkValues(cell.mode)) {
    if (io::stopRequested()) return;  // the walk keeps its whole cases
    Case c = walkCase(cell, h, dur);
    runCase(c, scenes, b);
    cell.walk.push_back(c);
    if (c.out.verdict == Verdict::Trustworthy) {
      cell.stable = static_cast<int>(cell.walk.size()) - 1;
      return;
    }
  }
}

}  // namespace

void runGrid(std::vector<Cell>& cells, const std::string& scenes, const std::string& dur, int threads,
             const Bounds& b) {
  parallel(cells.size(), threads, [&](std::size_t i) { walkCell(cells[i], scenes, dur, b); });
}

std::vector<RestitutionRow> restitutionTable(const std::string& scenes, double v_in) {
  std::vector<RestitutionRow> rows;
  for (double ce : kRestitutions) {
    RestitutionRow r;
    r.ce = ce;
    for (const auto& law : kDamping) {
      const Model m = loadScene(scenes + "/paper_clearance.yaml", restitutionSets(law, ce)).model;
      r.eff[law] = effectiveRestitution(m, v_in);
    }
    rows.push_back(r);
  }
  return rows;
}

}  // namespace gimbalsim::stress
