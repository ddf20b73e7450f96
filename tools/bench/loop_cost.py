#!/usr/bin/python3
"""The in-process closed-loop tick's own work against the plant's stepping
(prints figures; not a test). gimbalsim_bench_loop (Google Benchmark,
tools/bench/bench_closed_loop.cpp) runs the pointing study's 8.5 s with the
default controller, --reps times per case, and its cost meter splits each
run's time per tick: the plant's stepping (RK4 and its contact sub-steps),
the controller's turn, and the rest of the tick (firmware, sensors, truth
observer, record, figures). The table gives the medians over the
repetitions; work/step is the tick's work besides stepping over the
stepping, which should be at most 0.3 on paper_clearance.

Usage:
  /usr/bin/python3 tools/bench/loop_cost.py [--build build] [--reps 9] [--results]

--results also writes docs/results/closed_loop_cost.md (tools/pages/results_page.py).
"""
import argparse
import contextlib
import io
import json
import os
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pages"))
import output_file  # noqa: E402,F401  (its import keeps the console: a reader gone stops nothing)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TARGET = 0.3  # work / step on paper_clearance
COUNTERS = ("step_us", "controller_us", "tick_work_us", "work_per_step")


def run_benchmark(binary, reps):
    """{case label: {counter: median over the repetitions}}; exits naming the failure."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "loop.json")
        env = {**os.environ, "GIMBALSIM_SCENE_DIR": os.path.join(ROOT, "tools", "scenes")}
        r = subprocess.run([binary, f"--benchmark_repetitions={reps}", f"--benchmark_out={out}",
                            "--benchmark_out_format=json"], env=env, capture_output=True, text=True)
        text = open(out).read() if os.path.exists(out) else ""
        if r.returncode != 0 or not text or "error_occurred\": true" in text:
            sys.exit(f"loop_cost: {binary} failed (exit {r.returncode}):\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    runs = {}
    for b in json.loads(text)["benchmarks"]:
        if b.get("run_type") == "iteration":  # each repetition's own figures; the medians are taken here
            runs.setdefault(b["label"], []).append(b)
    return {label: {c: statistics.median(x[c] for x in rs) for c in COUNTERS} for label, rs in runs.items()}


def report(med, reps):
    print(f"Medians of {reps} repetitions, each one 8.5 s run (8501 ticks of 1 ms), per tick:\n")
    print("| case | stepping [us] | controller [us] | tick work besides stepping [us] | work / step |")
    print("|---|---|---|---|---|")
    for label, m in med.items():
        print(f"| {label} | {m['step_us']:.2f} | {m['controller_us']:.2f} | {m['tick_work_us']:.2f} | "
              f"{m['work_per_step']:.3f} |")
    clearance = med.get("paper_clearance")
    if clearance is None:
        sys.exit("loop_cost: the benchmark reported no paper_clearance case")
    verdict = "met" if clearance["work_per_step"] <= TARGET else "missed"
    print(f"\nTarget: work / step at most {TARGET} on paper_clearance (the scene's fixed sub-steps): "
          f"{clearance['work_per_step']:.3f}, {verdict}.")
    adaptive = med.get("paper_clearance adaptive")
    if adaptive is not None:
        print(f"With adaptive sub-steps (friction.law coulomb_stick) the stepping is "
              f"{clearance['step_us'] / adaptive['step_us']:.1f} times cheaper and work / step "
              f"{adaptive['work_per_step']:.3f}.")


def main():
    p = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    output_file.add_build(p)
    p.add_argument("--reps", type=output_file.arg_whole(1, 10**6), default=9, help="benchmark repetitions (medians)")
    p.add_argument("--results", action="store_true", help="also write docs/results/closed_loop_cost.md")
    a = p.parse_args()
    if not 1 <= a.reps <= 1000:
        p.error("--reps must be in [1, 1000]")
    sys.path.insert(0, os.path.join(ROOT, "tools", "pages"))
    import results_page
    if a.results:  # refused now, not after the measurements
        results_page.check_page(os.path.join(ROOT, "docs/results/closed_loop_cost.md"))
    binary = os.path.join(ROOT, a.build, "bin", "gimbalsim_bench_loop")
    if not os.access(binary, os.X_OK):
        raise output_file.Refused(f"{binary} missing (it needs Google Benchmark): "
                                  f"cmake --build {a.build} -j2 --target gimbalsim_bench_loop")
    t0, load0 = str(time.time()), open("/proc/loadavg").read()
    med = run_benchmark(binary, a.reps)
    body = io.StringIO()
    with contextlib.redirect_stdout(body):
        report(med, a.reps)
    print(body.getvalue(), end="")
    if not a.results:
        return
    c = med["paper_clearance"]
    results_page.write_page(os.path.join(ROOT, "docs/results/closed_loop_cost.md"),
                            "The in-process closed-loop tick against its stepping",
                            "/usr/bin/python3 tools/bench/loop_cost.py " + shlex.join(sys.argv[1:]),
                            __doc__.split("\n\n")[0] + "\n\n" + body.getvalue(),
                            summary=f"paper_clearance: tick work / stepping {c['work_per_step']:.3f} "
                                    f"(target {TARGET})", t0=t0, load0=load0)
    print("loop_cost: wrote docs/results/closed_loop_cost.md")


if __name__ == "__main__":
    sys.exit(output_file.run_script("loop_cost", main))
