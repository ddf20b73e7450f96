#!/usr/bin/python3
"""The lockstep bench tick's fixed work, part by part (prints figures; not a
test). Two measurements side by side on this machine, in a private network
namespace (as tools/hil/hil_speed.py):

 1. gimbalsim_bench_tick (Google Benchmark, medians of --reps repetitions):
    each part of firmware_sim's lockstep tick alone: clock reads, encodes,
    LCM publishes with the two receiving sockets a bench has on its port,
    a command's receive, and the tick in process (firmware, sensors, step,
    truth).
 2. lockstep paper_ideal with pointing_controller over LCM (--runs runs of
    --seconds simulated s, medians): speed, firmware_sim's thread CPU per
    tick, its stepping, and the round trip; once as shipped and once with
    --truth-every 1000 (the truth message one tick in 1000).

The table puts the parts, times how often a tick does each, against the
thread CPU per tick firmware_sim measures; the rest of the wall time per
tick is the controller's turn and the wake-ups between the processes.

Usage:
  /usr/bin/python3 tools/bench/tick_parts.py [--build build] [--reps 9] [--runs 7] [--seconds 10] [--results]

--results also writes docs/results/bench_tick.md (tools/pages/results_page.py).
"""
import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools", "hil"))
import hil_speed  # noqa: E402  (its namespace, pair runner and summary parser)
import output_file  # noqa: E402  (on the path hil_speed set: the one reading of a flag's number)

# What firmware_sim's lockstep loop does per tick (firmware_sim/programs/lockstep_loop.cpp, lcm_bridge.cpp):
# (part, benchmark whose median is one occurrence, occurrences per tick, minus this benchmark's median).
PARTS = [
    ("clock read, thread CPU (before and after the step)", "BM_ClockRead/1", 2, None),
    ("clock reads, monotonic (tick, round trip, wait loop; about)", "BM_ClockRead/0", 8, None),
    ("publish attitude, status and truth (encode + sendmmsg; 2 sockets on the port)", "BM_PublishTick/2", 1, None),
    ("receive the command (blocking recvmmsg + reassemble + decode)", "BM_ReceiveCommand",
     1, "BM_Publish<gimbal_status_t>/1"),
    ("tick in process: firmware, sensors, truth, RK4 step (paper_ideal)", "BM_Tick/scene:0/truth:1", 1, None),
]


def benchmarks(reps):
    """Median CPU time of each benchmark [us]."""
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        env = {**os.environ, "GIMBALSIM_SCENE_DIR": hil_speed.SCENES, "GIMBALSIM_BENCH_LCM_URL": hil_speed.URL}
        r = subprocess.run([os.path.join(hil_speed.BIN, "gimbalsim_bench_tick"), f"--benchmark_repetitions={reps}",
                            "--benchmark_report_aggregates_only=true", f"--benchmark_out={out.name}",
                            "--benchmark_out_format=json"], env=env, capture_output=True, text=True)
        if r.returncode != 0 or "error_occurred" in open(out.name).read():
            sys.exit(f"tick_parts: gimbalsim_bench_tick failed (exit {r.returncode}):\n"
                     f"{r.stdout[-3000:]}{r.stderr[-3000:]}")
        runs = json.load(open(out.name))["benchmarks"]
    return {r["run_name"]: r["cpu_time"] * {"ns": 1e-3, "us": 1.0, "ms": 1e3}[r["time_unit"]]
            for r in runs if r.get("aggregate_name") == "median"}


def lockstep(seconds, runs, ways):
    """Per way (firmware_sim's extra flags), medians over runs: x real time, thread CPU per tick p50,
    stepping p50, round trip p50 [us], and the speeds. The ways alternate run by run, so a drift of a
    shared machine falls on each alike (side by side, not one block after the other)."""
    scene = os.path.join(hil_speed.SCENES, "paper_ideal.yaml")
    rows = [[] for _ in ways]
    for _ in range(runs):
        for way, flags in zip(rows, ways):
            out = hil_speed.run_pair(scene, seconds, lockstep=True, fw_extra=flags)
            way.append([hil_speed.grab(out, r"\(([\d.]+) x real time\)"),
                        hil_speed.grab(out, r"compute per tick, thread CPU \[us\]: p50 ([\d.]+)"),
                        hil_speed.grab(out, r"stepping per tick, thread CPU \[us\]: p50 ([\d.]+)"),
                        hil_speed.grab(out, r"round trip \[us\]: p50 ([\d.]+)")])
    return [([statistics.median(col) for col in zip(*way)], [r[0] for r in way]) for way in rows]


def report(med, shipped, no_truth, runs):
    print("| part of firmware_sim's lockstep tick | benchmark (median) | per tick | us each | us per tick |")
    print("|---|---|---|---|---|")
    total = 0.0
    for name, bench, n, minus in PARTS:
        each = med[bench] - (med[minus] if minus else 0.0)
        total += n * each
        label = f"{bench} - {minus}" if minus else bench
        print(f"| {name} | `{label}` | {n} | {each:.3f} | {n * each:.2f} |")
    (x, cpu, stepping, rtt), xs = shipped
    print(f"| **sum of the parts** | | | | **{total:.1f}** |")
    print(f"| firmware_sim's own thread CPU per tick, p50 (lockstep run) | | | | {cpu:g} |")
    print(f"| of which its stepping, p50 | | | | {stepping:g} |")
    print(f"| wall time per tick (1000 / {x:.2f} x real time) | | | | {1000.0 / x:.1f} |")
    print(f"| status -> command round trip, p50 (the controller's turn and both wake-ups) | | | | {rtt:g} |")
    (x2, cpu2, _, rtt2), xs2 = no_truth
    print(f"\nlockstep paper_ideal, {runs} runs each: as shipped {', '.join(f'{v:.2f}' for v in xs)} x real time "
          f"(median {x:.2f}, thread CPU p50 {cpu:g} us); with --truth-every 1000 "
          f"{', '.join(f'{v:.2f}' for v in xs2)} (median {x2:.2f}, thread CPU p50 {cpu2:g} us, "
          f"round trip p50 {rtt2:g} us): wall per tick {1000.0 / x:.1f} us as shipped, {1000.0 / x2:.1f} us with "
          "the truth one tick in 1000.")
    saved_cpu, saved_wall = cpu - cpu2, 1000.0 / x - 1000.0 / x2
    # The truth goes out after the status, while the controller computes: whether that is on the critical path.
    # It can also shorten the tick: without it firmware_sim blocks for the command sooner and is woken from
    # sleep (the round trip grows), where with it the command is often there when it asks.
    said = f"Without the truth firmware_sim's thread saves {saved_cpu:g} us per tick, and the tick's wall time "
    if saved_wall < -0.25 * max(saved_cpu, 1.0):
        print(said + f"grows by {-saved_wall:.1f} us (the round trip from {rtt:g} to {rtt2:g} us): without the "
              "truth's send to do, firmware_sim blocks for the command at once and is woken from sleep, which "
              "costs this machine more than the send, which overlaps the controller's turn.")
    elif abs(saved_wall) < 0.25 * max(saved_cpu, 1.0):
        print(said + f"moves {saved_wall:.1f} us: the truth's send is off the critical path (it overlaps the "
              "controller's turn); the status and attitude sends, the receive and the two wake-ups are on it.")
    else:
        print(said + f"shrinks by {saved_wall:.1f} us: the truth's send is on the critical path.")
    print(f"40 x real time needs {1000.0 / 40:.0f} us of wall per tick.")


def main():
    p = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    output_file.add_build(p)
    p.add_argument("--reps", type=output_file.arg_whole(1, 10**6), default=9, help="benchmark repetitions (medians)")
    p.add_argument("--runs", type=output_file.arg_whole(1, 10**6), default=7,
                   help="lockstep runs per way, alternating (medians)")
    p.add_argument("--seconds", type=output_file.arg_decimal(1e-3, 1e6), default=10.0,
                   help="simulated seconds per lockstep run")
    p.add_argument("--results", action="store_true", help="also write docs/results/bench_tick.md")
    a = p.parse_args()
    if a.reps < 1 or a.runs < 1 or not 0.0 < a.seconds <= 3600.0:
        p.error("--reps and --runs must be >= 1, --seconds in (0, 3600]")
    sys.path.insert(0, os.path.join(ROOT, "tools", "pages"))
    import results_page
    t0, load0 = results_page.measured_start(os.path.join(ROOT, "docs/results/bench_tick.md"), a.results)
    hil_speed.BIN = os.path.join(ROOT, a.build, "bin")
    for t in ("firmware_sim", "pointing_controller", "gimbalsim_bench_tick"):
        if not os.access(os.path.join(hil_speed.BIN, t), os.X_OK):
            raise output_file.Refused(f"{hil_speed.BIN}/{t} missing (gimbalsim_bench_tick needs Google Benchmark): "
                                      f"cmake --build {a.build} -j2 --target firmware_sim pointing_controller "
                                      "gimbalsim_bench_tick")
    hil_speed.enter_namespace()
    if a.results:
        sys.stdout = hil_speed.Tee(sys.stdout)
    print(f"tick_parts: {os.cpu_count()} CPUs, kernel {os.uname().release}, load {' '.join(hil_speed.load())}\n")
    med = benchmarks(a.reps)
    shipped, no_truth = lockstep(a.seconds, a.runs, [[], ["--truth-every", "1000"]])
    report(med, shipped, no_truth, a.runs)
    if a.results:
        text = sys.stdout.copy.getvalue()
        sys.stdout = sys.stdout.out
        body = "\n".join(line for line in text.splitlines() if not line.startswith("tick_parts:")) + "\n"
        x = shipped[0][0]
        results_page.write_page(os.path.join(ROOT, "docs/results/bench_tick.md"),
                                "The lockstep bench tick, part by part",
                                "/usr/bin/python3 tools/bench/tick_parts.py " + shlex.join(sys.argv[1:]),
                                "\n\n".join(__doc__.split("\n\n")[:3]) + "\n\n" + body,
                                summary=f"lockstep paper_ideal {x:.1f} x real time; firmware_sim thread CPU per tick "
                                        f"p50 {shipped[0][1]:g} us",
                                t0=t0, load0=load0)
        print("tick_parts: wrote docs/results/bench_tick.md")


if __name__ == "__main__":
    sys.exit(output_file.run_script("tick_parts", main))
