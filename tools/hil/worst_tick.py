#!/usr/bin/python3
"""Worst-case tick: firmware_sim's stepping CPU time per tick against the
bound it states at start (prints tables; not a test). firmware_sim +
pointing_controller over LCM udpm (ttl=0) in a private network namespace, the
runs, namespace and parsing helpers imported from tools/hil/hil_speed.py.

firmware_sim's bound: worst-case tick = steps per tick x work-unit cap x the
time of one work unit (an RK4 sub-step, scaled when a unit may take more than
4 derivatives), measured at start, + the truth's derivative, the cost of cold
caches (once per tick) and a clock read.
The count part is proven by tests (tests/dynamics/work_bound_test.cpp); the time per
unit is measured. The figure compared with it is the loop thread's
CPU time (CLOCK_THREAD_CPUTIME_ID) of each tick's stepping span, which
preemption does not inflate.

 (A) lockstep: every scene in tools/scenes at 1 kHz with --lockstep and the
     controller, --seconds simulated seconds each (default 100: 1e5 ticks).
     A scene firmware_sim cannot run at 1 kHz gets a row saying why.
 (B) real time: --realtime-seconds at 1 kHz (0 skips) for --realtime-scenes,
     firmware_sim's loop thread SCHED_FIFO 80 pinned to --cpu, both processes
     under chrt -f 60 when allowed; the same columns plus overruns, and the
     replay: the run's truth CSV fed back by torque_replay (tools/bench) to 3
     lockstep runs, whose dynamics then follow the real-time run bit for bit
     (same derivatives per tick, checked).

Verdict per row, for the two parts of the bound: the count (the most
derivative evaluations of one tick's stepping, counted by the dynamics,
against steps x cap x derivatives per unit: exact, no clock involved) and the
time (the stepping's CPU time max against the bound in microseconds, max /
bound <= 100 % as firmware_sim computes it from the unrounded bound). In
lockstep each scene runs RUNS (3) times with --tick-log: the runs do the same work tick by tick, so per
tick the best of their CPU times is the tick's own cost with what the
machine added to some of the runs taken out ("repeat"). The last line sums up.

Usage:
  /usr/bin/python3 tools/hil/worst_tick.py [--seconds 100] [--realtime-seconds 100]
      [--realtime-scenes paper_clearance,paper_both_spatial] [--cpu 1] [--build build] [--results]

--results also writes the tables into docs/results/worst_tick.md (header by
tools/pages/results_page.py: machine, commit, date, load at start and end).
"""
import argparse
import csv
import glob
import os
import shlex
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hil_speed  # noqa: E402  (run_pair reads hil_speed.BIN and hil_speed.CHRT when called)
import output_file  # noqa: E402  (on the path hil_speed set: the one reading of a flag's number)
from hil_speed import grab, load, run_pair  # noqa: E402

ROOT = hil_speed.ROOT
PAGE = "docs/results/worst_tick.md"
TITLE = "Worst-case tick: stepping CPU time against firmware_sim's bound"
START = (r"worst-case tick (\S+) us = (\d+) steps x (\d+) work units \(cap\) x (\S+) us per unit "
         r"\((\d+) derivatives at most")
STEPPING = (r"stepping per tick, thread CPU \[us\]: p50 (\S+)  p99 (\S+)  max (\S+); worst-case bound (\S+) "
            r"\(max (\S+) % of it\); the max at tick (-?\d+) \((\d+) sub-steps\)")
WHOLE = r"compute per tick, thread CPU \[us\]: p50 (\S+)  p99 (\S+)  max (\S+)"
COUNT = r"stepping per tick, derivative evaluations: max (\d+) of the bound's (\d+)"
COLUMNS = ["scene", "ticks", "x real time", "unit [us]", "steps per tick", "cap (work units)",
           "derivatives per unit", "bound [us]", "stepping CPU p50 / p99 / max [us]", "max / bound",
           "max sub-steps at the max tick", "whole tick CPU p50 / p99 / max [us]", "derivatives per tick: max / bound"]

PREAMBLE = """`tools/hil/worst_tick.py`: firmware_sim + pointing_controller over LCM udpm (ttl=0) in a private network
namespace, each scene of tools/scenes at 1 kHz with `--profile controllers/config/default.yaml`; figures parsed from
firmware_sim's start line and exit summary (helpers of `tools/hil/hil_speed.py`).

The bound is firmware_sim's worst-case tick: steps per tick x work-unit cap x the time of one work unit, + the truth's
derivative, the extra cost of a first unit on cold caches and a clock read. The count of units and of derivatives per
unit is a proven bound (tests/dynamics/work_bound_test.cpp); the time of a unit is measured by firmware_sim at start, in wall
time (median of 7 batches of 200: the slower of a whole free step and an RK4 sub-step pressed into the bearing and
sliding, scaled by derivatives per unit / 4 where a unit may take more than an RK4 sub-step's 4).

Measured against it: the loop thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`) of the stepping span of each tick (the
plant's steps), which preemption does not inflate. "Whole tick" is the same clock over the tick's whole compute span
(commands, sensors, truth, messages and the stepping), which the bound does not cover. p50 and p99 are upper edges
of 1 us bins, the max is exact; max / bound is firmware_sim's, from the unrounded bound; "within" = max / bound
<= 100 %. The sub-steps are the RK4 sub-steps of the tick with the longest stepping. "Derivatives per tick" is the
bound's count part checked exactly: the most forward-dynamics evaluations one tick's stepping took, counted by the
dynamics, against steps x cap x derivatives per unit. Part A runs lockstep (each
tick waits for the controller's command); part B runs in real time, firmware_sim's loop thread SCHED_FIFO 80 pinned
to one CPU.

What the thread's CPU clock charges to a tick is not only the tick's own work: this kernel has no
`CONFIG_IRQ_TIME_ACCOUNTING`, so interrupt and softirq work serviced during a tick is charged to the thread, and so
is any stall of the VM's virtual CPU that the host does not report as steal time. Either shows as a single outlier
tick: a max far above p99, at a tick that did no more work than usual (its sub-steps in the table; 50 = 1 ms /
`sim.substep` is the common count). Lockstep tells the two apart: each scene runs 3 times (`--tick-log`), the runs
do the same work at every tick (same sub-steps and derivatives, checked), and "repeat" is the largest over the ticks
of the smallest of the runs' stepping CPU times: what is left when a one-off of some runs is taken out. A real-time
run cannot be run again (timing decides its commands), but its work can: `torque_replay` answers a lockstep
firmware_sim with the torques the real-time run applied (its truth CSV), so the replay's dynamics are the run's bit
for bit, and "replay" is the largest over the ticks of the smallest of the real-time run's and 3 replays' stepping
CPU times (the derivatives per tick are checked equal). The summary
line also counts the rows whose p99 is within the bound. A scene
without clearance has a bound of about 1.5 us here, so one interrupt in a tick is enough to exceed it. The tables give
the max as measured; nothing is filtered out. firmware_sim holds idle CPUs awake in both modes (`--cpu-dma-latency-us`
0) and steps a scratch copy of the plant before the first tick: without either, a tick after a halted CPU or the
first tick of a run cost up to 2.5 times its usual CPU time here.
"""


def reason(message):
    """One line from run_pair's or grab's exit message: firmware_sim's exit code and the telling stderr line."""
    lines = [x.strip() for x in str(message).splitlines() if x.strip()]
    if not lines:
        return "no output"
    head = lines[0]
    if head.startswith("hil_speed: firmware_sim exited"):
        code = head.split("exited", 1)[1].split(":", 1)[0].strip()
        err = lines[1:]
        telling = [x for x in err if any(w in x.lower() for w in ("error", "refus", "fault", "fail"))]
        first = telling[0] if telling else (err[0] if err else "(no stderr)")
        return f"exit {code}: {first}"
    return head.removeprefix("hil_speed: ")[:300]


def measure(name, seconds, lockstep, fw_extra=(), controller=None):
    """firmware_sim's figures for one run as a dict, or a string saying why there are none."""
    try:
        out = run_pair(os.path.join(hil_speed.SCENES, name + ".yaml"), seconds, lockstep=lockstep, fw_extra=fw_extra,
                       controller=controller)
        r = dict(zip(("bound0", "steps", "cap", "deriv", "per_unit"), grab(out, START, 5)))
        r.update(zip(("s50", "s99", "smax", "bound", "pct", "tick", "subs"), grab(out, STEPPING, 7)))
        r.update(zip(("c50", "c99", "cmax"), grab(out, WHOLE, 3)))
        r.update(zip(("dmax", "dbound"), grab(out, COUNT, 2)))
        r["ticks"] = grab(out, r"firmware_sim: (\d+) ticks")
        r["speed"] = grab(out, r"\(([\d.]+) x real time\)")
        r["overruns"] = 0.0 if lockstep else grab(out, r"overruns (\d+)")
        r["within"] = r["pct"] <= 100.0
        return r
    except SystemExit as e:  # run_pair (firmware_sim refused or failed) or grab (no such line)
        return reason(e.code)
    except subprocess.TimeoutExpired as e:
        return f"timed out after {e.timeout:g} s wall"


def tick_log(path):
    """(derivatives, stepping CPU time [us]) of each tick of a firmware_sim --tick-log."""
    with open(path, newline="") as f:
        return [(int(x["derivatives"]), float(x["stepping_cpu_us"])) for x in csv.DictReader(f)]


RUNS = 3  # lockstep runs of the same work per scene: the row's and 2 more; in real time, 3 lockstep replays


def repeat(r, logs, again):
    """Per tick the smallest stepping CPU time over the runs of `logs` (the first has run; again(log) runs another
    that does the same work and returns None, or why it could not), its max against the row's bound."""
    for log in logs[1:]:
        why = again(log)
        if why:
            return f"repeat could not run: {why}"
    runs = [tick_log(log) for log in logs]
    if any(len(x) != len(runs[0]) or any(a[0] != b[0] for a, b in zip(x, runs[0])) for x in runs[1:]):
        return "the repeat did other work (derivatives per tick differ)"
    best = [min(t[1] for t in ticks) for ticks in zip(*runs)]
    k = max(range(len(best)), key=best.__getitem__)
    bound = r["smax"] * 100.0 / r["pct"] if r["pct"] > 0 else float("nan")  # firmware_sim's unrounded bound
    pct = 100.0 * best[k] / bound
    return {"max": best[k], "tick": k, "pct": pct, "within": pct <= 100.0}


def row(name, r, realtime):
    n = len(COLUMNS) + (3 if realtime else 2)  # + overruns (real time), repeat or replay, verdict
    if isinstance(r, str):
        return f"| {name} | could not run: {r.replace('|', '/')} |" + " |" * (n - 2)
    cells = [name, f"{r['ticks']:.0f}", f"{r['speed']:.2f}", f"{r['deriv']:.2f}", f"{r['steps']:.0f}",
             f"{r['cap']:.0f}", f"{r['per_unit']:.0f}", f"{r['bound']:.0f}",
             f"{r['s50']:.0f} / {r['s99']:.0f} / {r['smax']:.1f}", f"{r['pct']:.1f} %",
             f"{r['subs']:.0f} (tick {r['tick']:.0f})", f"{r['c50']:.0f} / {r['c99']:.0f} / {r['cmax']:.1f}",
             f"{r['dmax']:.0f} / {r['dbound']:.0f}"]
    rep = r.get("repeat")
    if realtime:
        cells.append(f"{r['overruns']:.0f}")
    if isinstance(rep, dict):
        cells.append(f"{rep['max']:.1f} ({rep['pct']:.1f} %, tick {rep['tick']})")
    else:
        cells.append(str(rep).replace("|", "/"))
    cells.append(("count within" if r["dmax"] <= r["dbound"] else "count EXCEEDS") + ", " +
                 ("time within" if r["within"] else "time EXCEEDS") + (", replay " if realtime else ", repeat ") +
                 ("not shown" if not isinstance(rep, dict) else "within" if rep["within"] else "EXCEEDS"))
    return "| " + " | ".join(cells) + " |"


def table(title, names, seconds, lockstep, fw_extra=()):
    """Runs each scene, prints its row as soon as it is measured; returns {name: figures or why not}."""
    print(f"\n{title}  [load before: {' '.join(load())}]")
    cols = COLUMNS + ([f"repeat: max over ticks of the best of {RUNS} runs [us] (of bound)"] if lockstep
                      else ["overruns", f"replay: max over ticks of the best of the run and {RUNS} lockstep replays "
                            "[us] (of bound)"]) + ["verdict"]
    print("| " + " | ".join(cols) + " |")
    print("|" + "---|" * len(cols))
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            logs = [os.path.join(tmp, f"{name}_{i}.csv") for i in range(RUNS if lockstep else RUNS + 1)]
            truth = os.path.join(tmp, f"{name}_truth.csv")
            extra = tuple(fw_extra) + ("--tick-log", logs[0]) + (() if lockstep else ("--truth-csv", truth))
            results[name] = measure(name, seconds, lockstep, extra)
            if not isinstance(results[name], str):
                def again(log, name=name, truth=truth):
                    """Lockstep: the scene once more; real time: a lockstep run answered by torque_replay with the
                    run's torques (its truth CSV), so every tick does the run's work."""
                    ctl = None if lockstep else [os.path.join(hil_speed.BIN, "torque_replay"), truth, "--lcm-url",
                                                 hil_speed.URL]
                    x = measure(name, seconds, True, ("--tick-log", log), ctl)
                    return x if isinstance(x, str) else None
                results[name]["repeat"] = repeat(results[name], logs, again)
            print(row(name, results[name], not lockstep), flush=True)
    print(f"[load after: {' '.join(load())}]")
    return results


def summary(parts):
    """parts: [(label, {name: figures or why not})] -> one line."""
    bits, best = [], None
    for label, res in parts:
        ran = {k: v for k, v in res.items() if not isinstance(v, str)}
        within = sum(1 for v in ran.values() if v["within"])
        p99 = sum(1 for v in ran.values() if v["s99"] <= v["bound"])
        counted = sum(1 for v in ran.values() if v["dmax"] <= v["dbound"])
        bit = (f"{label}: {len(res)} scenes, {len(ran)} ran; derivative count within the bound in {counted}; "
               f"stepping CPU time max within it in {within} (p99 in {p99})")
        reps = [v["repeat"] for v in ran.values() if "repeat" in v]
        if reps:
            ok = sum(1 for x in reps if isinstance(x, dict) and x["within"])
            how = f"repeat (best of {RUNS} runs per tick)" if label == "lockstep" else \
                f"replay (best of the run and {RUNS} lockstep replays per tick)"
            bit += f"; {how} within it in {ok} of {len(reps)}"
        if len(ran) < len(res):
            bit += f", {len(res) - len(ran)} could not run ({', '.join(k for k in res if k not in ran)})"
        bits.append(bit)
        for k, v in ran.items():
            if best is None or v["pct"] > best[0]:
                best = (v["pct"], k, label, v["tick"], v["subs"])
    if best:
        bits.append(f"highest max / bound {best[0]:.1f} % ({best[1]}, {best[2]}, tick {best[3]:.0f}, "
                    f"{best[4]:.0f} sub-steps)")
    return "; ".join(bits)


def page_body(text):
    """The printed report as Markdown: the preamble, a heading per part, tables and lines kept."""
    out, table_before = [PREAMBLE.rstrip("\n")], False
    for line in text.splitlines():
        if not line.strip():
            continue
        is_table = line.startswith("|")
        if line.startswith("("):
            out += ["", "### " + line]
        elif is_table:
            out += ([] if table_before else [""]) + [line]
        else:
            out += ["", line]
        table_before = is_table
    return "\n".join(out) + "\n"


def shipped_scene(name):
    """An argparse type: the name of a scene in tools/scenes (NAME for tools/scenes/NAME.yaml; pass 91: a name
    given with its .yaml was looked up as NAME.yaml.yaml)."""
    if name.endswith(".yaml"):
        raise argparse.ArgumentTypeError(f"{name!r}: give the scene's name without .yaml (tools/scenes/NAME.yaml)")
    if "/" in name or name.startswith("."):  # (pass 93) ./NAME ran NAME twice, ../x a file outside tools/scenes
        raise argparse.ArgumentTypeError(f"{name!r}: a scene's name in tools/scenes (NAME for NAME.yaml), not a path")
    if not os.path.isfile(os.path.join(hil_speed.SCENES, name + ".yaml")):
        raise argparse.ArgumentTypeError(f"no tools/scenes/{name}.yaml")
    return name


def main():
    p = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    p.add_argument("--seconds", type=output_file.arg_decimal(1e-3, 1e6), default=100.0,
                   help="simulated seconds per scene in lockstep (part A)")
    p.add_argument("--realtime-seconds", type=output_file.arg_decimal(0, 1e6), default=100.0,
                   help="seconds per real-time run (part B); 0 skips")
    p.add_argument("--realtime-scenes", type=output_file.arg_list(shipped_scene),
                   default="paper_clearance,paper_both_spatial",
                   help="comma-separated scene names (tools/scenes/NAME.yaml) for part B")
    p.add_argument("--cpu", type=output_file.arg_cpu, default=1,
                   help="part B: CPU of firmware_sim's loop thread (-1: no pinning)")
    output_file.add_build(p)
    p.add_argument("--results", action="store_true", help="also write " + PAGE)
    a = p.parse_args()
    if 0 < a.realtime_seconds < 1e-3:  # (pass 88: 1e-300 passed) no firmware_sim --duration is shorter than a tick
        p.error(f"--realtime-seconds: 0 (skip) or at least 0.001 (one 1 kHz tick), got {a.realtime_seconds:g}")
    import results_page  # (on the path hil_speed set)
    t0, load0 = results_page.measured_start(os.path.join(ROOT, PAGE), a.results)
    hil_speed.BIN = os.path.join(ROOT, a.build, "bin")
    hil_speed.CPU[0] = a.cpu
    for t in ("firmware_sim", "pointing_controller", "torque_replay"):
        if not os.access(os.path.join(hil_speed.BIN, t), os.X_OK):
            raise output_file.Refused(f"{hil_speed.BIN}/{t} missing: cmake --build {a.build} -j2 "
                                      "--target firmware_sim pointing_controller torque_replay")
    names = sorted(os.path.basename(f)[:-len(".yaml")] for f in glob.glob(os.path.join(hil_speed.SCENES, "*.yaml")))
    rt_names = a.realtime_scenes if a.realtime_seconds > 0 else []
    hil_speed.enter_namespace()  # re-runs sys.argv[0], this script, inside the namespace
    if a.results:
        sys.stdout = hil_speed.Tee(sys.stdout)
    if subprocess.run(["chrt", "-f", "60", "true"], capture_output=True).returncode == 0:
        hil_speed.CHRT.extend(["chrt", "-f", "60"])
    print(f"worst_tick: {os.cpu_count()} CPUs, kernel {os.uname().release}, load {' '.join(load())}; "
          f"real-time runs: controller and firmware_sim {'under ' + ' '.join(hil_speed.CHRT) if hil_speed.CHRT else 'SCHED_OTHER (chrt -f 60 refused here)'}"
          f" (firmware loop thread SCHED_FIFO 80{f', CPU {a.cpu}' if a.cpu >= 0 else ''})")
    parts = [("lockstep", table(f"(A) lockstep, 1 kHz, {a.seconds:g} simulated s per scene, with pointing_controller",
                                names, a.seconds, True))]
    if rt_names:
        fw = ["--cpu", str(a.cpu)] if a.cpu >= 0 else []
        parts.append(("real time", table(f"(B) real time, 1 kHz, {a.realtime_seconds:g} s per scene, with "
                                         "pointing_controller", rt_names, a.realtime_seconds, False, fw)))
    line = summary(parts)
    print(f"\nworst_tick: {line}")
    if a.results:
        command = "/usr/bin/python3 tools/hil/worst_tick.py " + " ".join(shlex.quote(x) for x in sys.argv[1:])
        results_page.write_page(os.path.join(ROOT, PAGE), TITLE, command.rstrip(), page_body(sys.stdout.copy.getvalue()),
                                summary=line, t0=t0, load0=load0)
        sys.stdout = sys.stdout.out
        print(f"worst_tick: wrote {PAGE}")


if __name__ == "__main__":
    sys.exit(output_file.run_script("worst_tick", main))
