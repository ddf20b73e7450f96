// firmware_sim's exit summary (stdout) and plant-fault report (stderr, exit 3).
#pragma once

#include <cstdint>
#include <string>

#include "app.hpp"

namespace gimbalsim::firmware {

/// What the firmware core says at the end of a run.
struct Outcome {
  std::int64_t ticks = 0;
  Counters counters;
  bool plant_fault = false;
  StepResult plant;  ///< the plant's failed step (status, time, coordinate, figures) when plant_fault
  double last_good_s = 0.0;  ///< [s] when plant_fault: the time of its frozen state (the truth CSV's frozen rows)
};

template <class V>
Outcome outcomeOf(const Firmware<V>& fw) {
  return {fw.ticks(), fw.counters(), fw.plantFault(), fw.plantResult(), fw.state().t};
}

/// The summary on stdout (docs/bench.md "The exit summary").
void printExitSummary(const Run& r, const Outcome& out);

/// kExitOk, or the PLANT FAULT line on stderr and kExitPlantFault.
int reportPlantFault(const Model& m, const Outcome& out);

/// Both, in that order: the end of every run.
inline int finish(const Run& r, const Outcome& out) {
  printExitSummary(r, out);
  return reportPlantFault(r.setup.plant.scene.model, out);
}

}  // namespace gimbalsim::firmware
