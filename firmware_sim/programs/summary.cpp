#include "summary.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gimbalsim/lcm_wire/peak_memory.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/firmware_sim/plant_stop.hpp"
#include "gimbalsim/pointing/profile_windows.hpp"
#include "lcm_bridge.hpp"

namespace gimbalsim::firmware {

namespace {
/// "p50 A  p99 B  [p99.9 C  ]max D" of a histogram [us]: the summary's one
/// format for a spread (the tools read these lines).
std::string spread(const Histogram& h, bool with_p999) {
  if (h.count() == 0) return "n/a (no tick measured)";  // a run stopped before its first tick: no 0 for nothing
  char buf[160];
  if (with_p999) {
    std::snprintf(buf, sizeof buf, "p50 %.0f  p99 %.0f  p99.9 %.0f  max %.1f", h.quantile(0.5), h.quantile(0.99),
                  h.quantile(0.999), h.max());
  } else {
    std::snprintf(buf, sizeof buf, "p50 %.0f  p99 %.0f  max %.1f", h.quantile(0.5), h.quantile(0.99), h.max());
  }
  return buf;
}

/// "%.2f" of a speed, or n/a (with no tick, a speed over nothing).
std::string speed(double simulated_s, double seconds) {
  if (!(simulated_s > 0.0 && seconds > 0.0)) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", simulated_s / seconds);
  return buf;
}
}  // namespace

void printExitSummary(const Run& r, const Outcome& out) {
  const LoopStats& st = r.report.stats;
  const Counters& n = out.counters;
  const double sim_s = static_cast<double>(out.ticks) * r.setup.c.control_period;
  // Two speeds: the whole loop (in lockstep it waits for the controller) and the plant's own work.
  std::printf("firmware_sim: %lld ticks, %.3f s simulated in %.3f s wall (%s x real time), %s\n",
              static_cast<long long>(out.ticks), sim_s, r.report.wall_seconds, speed(sim_s, r.report.wall_seconds).c_str(),
              r.setup.o.lockstep ? "lockstep" : (r.report.fifo ? "real time, SCHED_FIFO" : "real time, SCHED_OTHER"));
  std::printf("  speed: whole loop %s x real time%s; the plant's own compute %.3f s, %s x real time\n",
              speed(sim_s, r.report.wall_seconds).c_str(), r.setup.o.lockstep ? " (with the waits for the controller)" : "",
              r.report.compute_seconds, speed(sim_s, r.report.compute_seconds).c_str());
  if (out.plant_fault) {  // the ticks ran on; the plant did not (reportPlantFault says why)
    std::printf("  the plant stopped after t = %s: the ticks after it held that state and are in no figure below\n",
                describeStopWhen(out.last_good_s, out.plant).c_str());
  }
  const PointingErrorStats& pe = r.report.pointing;
  if (pe.n > 0 && out.plant_fault && !(out.last_good_s > 0.0)) {
    // Whole-run figures need a step the plant completed (usage.md): over t = 0 alone they printed 0 (pass 83).
    std::printf("  truth pointing error [rad] against %s: n/a (the plant's first step failed: no step completed)\n",
                r.setup.profile ? "the profile" : "the boresight at t = 0 (no --profile)");
  } else if (pe.n == 0) {  // stopped before its first tick: said, not left out (pass 86)
    std::printf("  truth pointing error [rad] against %s: n/a (no tick ran)\n",
                r.setup.profile ? "the profile" : "the boresight at t = 0 (no --profile)");
  } else {
    std::printf("  truth pointing error [rad] against %s: max %.3e, RMS %.3e, final %.3e",
                r.setup.profile ? "the profile" : "the boresight at t = 0 (no --profile)", pe.max_rad,
                std::sqrt(pe.sum_sq / static_cast<double>(pe.n)), pe.last_rad);
    if (r.setup.profile) {
      // A run that ended before the track has no tracking figure: n/a with the reason, never 0.
      const double t_last = out.plant_fault ? out.last_good_s  // the plant's last good state
                                            : static_cast<double>(out.ticks - 1) * r.setup.c.control_period;
      const std::string why = pointing::windowNotReached(
          pointing::profileWindow(*r.setup.profile, pointing::Segment::Track), pointing::WindowNeed::Part, t_last);
      if (!why.empty() || pe.n_track == 0) {
        std::printf("; while tracking: n/a (%s)", why.empty() ? "no tracking tick" : why.c_str());
      } else {
        std::printf("; while tracking: max %.3e, RMS %.3e", pe.max_track_rad,
                    std::sqrt(pe.sum_sq_track / static_cast<double>(pe.n_track)));
      }
    }
    std::printf("\n");
  }
  if (!r.setup.o.lockstep) {
    std::printf("  wake-up lateness [us]: %s\n", spread(st.lateness, true).c_str());
    std::printf("  tick period [us]:      %s\n", spread(st.period, true).c_str());
  }
  if (st.compute.count() == 0) {
    std::printf("  compute per tick [us]: %s\n", spread(st.compute, false).c_str());
  } else {
    std::printf("  compute per tick [us]: %s   (1 us bins); worst-case bound %.0f (max %.1f %% of it)\n",
                spread(st.compute, false).c_str(), r.setup.worst_tick_us,
                r.setup.worst_tick_us > 0 ? 100.0 * st.compute.max() / r.setup.worst_tick_us : 0.0);
  }
  std::printf("  compute per tick, thread CPU [us]: %s   (preemption not counted; the "
              "stepping and the tick's fixed work: commands, sensors, truth, messages)\n",
              spread(st.compute_cpu, false).c_str());
  if (st.stepping_cpu.count() == 0) {
    std::printf("  stepping per tick, thread CPU [us]: %s\n", spread(st.stepping_cpu, false).c_str());
  } else {
    std::printf("  stepping per tick, thread CPU [us]: %s; worst-case bound %.0f (max %.1f %% of "
                "it); the max at tick %lld (%d sub-steps)\n",
                spread(st.stepping_cpu, false).c_str(), r.setup.worst_tick_us,
                r.setup.worst_tick_us > 0 ? 100.0 * st.stepping_cpu.max() / r.setup.worst_tick_us : 0.0,
                static_cast<long long>(st.stepping_cpu_max_tick.load()), st.stepping_cpu_max_substeps.load());
  }
  if (r.setup.worst_tick_derivatives > 0 && out.ticks == 0) {  // a max over no tick is none (pass 86: it said 0)
    std::printf("  stepping per tick, derivative evaluations: n/a (no tick ran)\n");
  } else if (r.setup.worst_tick_derivatives > 0) {
    std::printf("  stepping per tick, derivative evaluations: max %lld of the bound's %lld (%.1f %%)\n",
                out.counters.max_derivatives_in_tick, r.setup.worst_tick_derivatives,
                100.0 * static_cast<double>(out.counters.max_derivatives_in_tick) /
                    static_cast<double>(r.setup.worst_tick_derivatives));
  }
  if (!r.setup.o.lockstep) {
    std::printf("  late ticks %lld (run at once after an overrun, holding the last command, to keep wall-clock time)",
                static_cast<long long>(st.late_ticks.load()));
    if (st.late.count() > 0) {
      std::printf(": late by p50 %.0f  p99 %.0f  max %.0f us (10 us bins)", 10.0 * st.late.quantile(0.5),
                  10.0 * st.late.quantile(0.99), 10.0 * st.late.max());
    }
    std::printf("\n");
  }
  const Histogram& rt = r.ports.bridge.roundtrip;
  if (rt.count() > 0) {
    std::printf("  status -> command round trip [us]: %s  (%llu answers)\n", spread(rt, true).c_str(),
                static_cast<unsigned long long>(rt.count()));
  }
  char substeps[64] = "n/a (no tick ran)";
  if (out.ticks > 0) std::snprintf(substeps, sizeof substeps, "mean %.2f, max %d", st.substepsMean(), st.substeps_max.load());
  std::printf("  overruns %lld (ticks whose work ended after the next deadline); RK4 sub-steps per tick: %s\n",
              static_cast<long long>(st.overruns.load()), substeps);
  std::printf("  commands: received %lld, rejected %lld, missed %lld; watchdog trips %lld; ticks at the motor limit (torque.limit) %lld\n",
              static_cast<long long>(n.received), static_cast<long long>(n.rejected), static_cast<long long>(n.missed),
              static_cast<long long>(n.watchdog_trips), static_cast<long long>(n.motor_limited_ticks));
  for (int i = 1; i < kNumRejections; ++i) {
    if (n.by_reason[i] > 0) {
      std::printf("    rejected %lld: %s\n", static_cast<long long>(n.by_reason[i]), describe(static_cast<Rejection>(i)));
    }
  }
  if (r.setup.o.lockstep) {
    std::printf("  lockstep timeouts %lld; bindings released %lld (the bound controller silent for "
                "--lockstep-timeout-ms while another answered)\n",
                r.report.lockstep_timeouts, r.report.lockstep_rebinds);
  }
  if (r.setup.faults != nullptr) {
    std::printf("  scheduled faults: active in %lld ticks; commands dropped %lld, delayed %lld; statuses dropped %lld, delayed %lld\n",
                static_cast<long long>(n.fault_ticks), static_cast<long long>(n.bus.commands_dropped),
                static_cast<long long>(n.bus.commands_delayed), static_cast<long long>(n.bus.status_dropped),
                static_cast<long long>(n.bus.status_delayed));
  }
  if (st.dropped_out.load() > 0 || r.ports.bridge.dropped_in > 0 || r.ports.bridge.publishErrors() > 0) {
    std::printf("  lost: %lld outbound (ring full), %lld inbound (ring full), %lld publish errors\n",
                static_cast<long long>(st.dropped_out.load()), r.ports.bridge.dropped_in, r.ports.bridge.publishErrors());
  }
  std::printf("  receive: %s\n", r.ports.bridge.receiver().summary().c_str());
  std::printf("  peak memory (VmHWM) %ld kB\n", lcm_wire::peakRssKb());
  std::fflush(stdout);
}

int reportPlantFault(const Model& m, const Outcome& out) {
  if (!out.plant_fault) return kExitOk;
  // The one message of a stopped step, its time said as every reader of the run says it (the last good
  // state, pass 35: "stopped at t = 0.16 s" beside the summary's 0.159 s).
  std::fprintf(stderr,
               "firmware_sim: PLANT FAULT, %s; the state was frozen there and every later status carried "
               "FAULT_PLANT_FAULT\n",
               describePlantStop(m, out.last_good_s, out.plant).c_str());
  return kExitPlantFault;
}

}  // namespace gimbalsim::firmware
