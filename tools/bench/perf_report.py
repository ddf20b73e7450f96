#!/usr/bin/python3
"""docs/results/performance.md: the performance report of the dynamics and the bench, every figure
measured in this one run of the tool on this machine.

 1. The derivative and the RK4 step of every compiled variant (Google
    Benchmark medians, build/bin/gimbalsim_bench). With --baseline-bench BIN
    (the same benchmark built from an older commit) both binaries run
    alternately, --rounds passes each, and the page gives ours / baseline.
    Build the baseline in a worktree of its own, for example:
        git worktree add /tmp/base COMMIT
        cmake -S /tmp/base -B /tmp/base/build -DCMAKE_BUILD_TYPE=Release
        cmake --build /tmp/base/build -j2 --target gimbalsim_bench
    then pass --baseline-bench /tmp/base/build/bin/gimbalsim_bench
    --baseline-name COMMIT (and git worktree remove /tmp/base afterwards).
 2. MuJoCo's RK4 against ours (gimbalsim_workprec on paper_ideal_valid_inertia,
    when the build has the MuJoCo peer: Debian's libmujoco-dev).
 3. firmware_sim's stated worst-case tick, per scene and control rate
    (its start-up line; above 1 kHz sim.step = 1/rate, as tools/hil/hil_speed.py
    runs them), against the period.
 4. The bench: lockstep speed and the process boundary (three ways), and the
    real-time wake-up lateness against cyclictest (tools/hil/hil_speed.py; needs
    a network namespace and root: --skip-hil leaves it out, and says so).

    /usr/bin/python3 tools/bench/perf_report.py [--baseline-bench BIN --baseline-name NAME]
        [--rounds 5] [--min-time 0.2] [--rates 1000,2000,4000] [--hil-long 20] [--skip-hil] [--build build]
"""
import argparse
import os
import pathlib
import re
import shlex
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
import output_file  # noqa: E402  (the one reading of a flag's number)
import results_page  # noqa: E402

sys.path.insert(0, str(ROOT / "tools" / "bench"))
import compare_bench  # noqa: E402

SCENES = sorted(p.stem for p in (ROOT / "tools/scenes").glob("*.yaml"))
BOUND = re.compile(r"worst-case tick ([\d.]+) us = (\d+) steps x (\d+) work units \(cap\) x ([\d.]+) us per unit")


def dynamics_section(a, bench):
    flt = "^BM_(ForwardDynamics|Rk4)<"
    sides = {"ours": bench, **({"baseline": a.baseline_bench} if a.baseline_bench else {})}
    times = {side: {} for side in sides}
    for _ in range(a.rounds):  # alternated (compare_bench.py): a drift in the load hits both alike
        for side, binary in sides.items():
            for name, t in compare_bench.one_pass(binary, flt, a.min_time).items():
                times[side].setdefault(name.removesuffix(" [ns]"), []).append(t)
    med = {side: {n: statistics.median(ts) for n, ts in by.items()} for side, by in times.items()}
    names = sorted(med["ours"], key=lambda n: (not n.startswith("BM_Rk4"), n))
    md = ["## 1. The derivative and the RK4 step", "",
          f"Google Benchmark (`{os.path.relpath(bench, ROOT)}`, tools/bench/bench_dynamics.cpp): CPU time per call, "
          f"the median of {a.rounds} passes of {a.min_time:g} s per benchmark"
          + (f", alternating with the baseline `{a.baseline_name}` (tools/bench/compare_bench.py's passes)"
             if a.baseline_bench else "") + ". "
          "BM_ForwardDynamics: one derivative; BM_Rk4: one RK4 step (four derivatives and the stage "
          "arithmetic). States mid-run of the paper scene.", ""]
    if a.baseline_bench:
        md += [f"| benchmark | ours [ns] | {a.baseline_name} [ns] | ours / baseline |", "|---|---|---|---|"]
        for n in names:
            b = med["baseline"].get(n)
            ratio = "not in the baseline" if b is None else f"{med['ours'][n] / b:.2f}"
            md.append(f"| {n} | {med['ours'][n]:.0f} | {'' if b is None else f'{b:.0f}'} | {ratio} |")
    else:
        md += ["| benchmark | ours [ns] |", "|---|---|"] + [f"| {n} | {med['ours'][n]:.0f} |" for n in names]
        md += ["", "No baseline given (--baseline-bench): no before/after ratio in this run."]
    rk4 = {n: med["ours"][n] for n in names if n.startswith("BM_Rk4<Floating")}
    summary = ", ".join(f"{n[7:-1]} {v / 1000:.2f} us" for n, v in rk4.items())
    return md + [""], f"RK4 step: {summary}"


def mujoco_section(a):
    md = ["## 2. Against MuJoCo", ""]
    cache = (ROOT / a.build / "CMakeCache.txt")
    if not cache.is_file() or not re.search(r"^mujoco_DIR:PATH=/", cache.read_text(), re.M):
        return md + ["Not measured: this build has no MuJoCo peer (apt-get install libmujoco-dev libqhull-dev, "
                     "then reconfigure the build).", ""], ""
    sys.path.insert(0, str(ROOT / "tools" / "workprec"))
    import workprec_page  # noqa: E402
    with tempfile.TemporaryDirectory() as out:
        subprocess.run([str(ROOT / a.build / "bin/gimbalsim_workprec"), "--scenes", "paper_ideal_valid_inertia",
                        "--policy", "plain", "--steps", "1e-2,5e-3,2e-3,1e-3", "--repeats", str(a.rounds), "--out", out],
                       check=True, capture_output=True)
        rows = workprec_page.load(pathlib.Path(out) / "workprec.csv")
    ratios = workprec_page.mujoco_ratios(rows)
    if not ratios:
        return md + ["The MuJoCo run gave no comparable points.", ""], ""
    med = statistics.median(ratios)
    md += ["MuJoCo 2.2's RK4 (Debian's libmujoco-dev, the same gimbal as an MJCF model, tools/mujoco/) against "
           "our plain RK4 on `paper_ideal_valid_inertia` (MuJoCo refuses the paper's base inertia), steps 10, 5, 2 "
           f"and 1 ms, thread CPU time of the stepping per simulated second (ms), {a.rounds} repeats per point "
           "(`gimbalsim_workprec`). The error columns are each integrator's largest boresight error [rad] against "
           "a tight Dormand-Prince reference of the same scene (docs/results/workprec.md):", "",
           workprec_page.mujoco_table(rows),
           f"**MuJoCo / ours: median {med:.2f}** (range {min(ratios):.2f} to {max(ratios):.2f}; above 1: ours faster).",
           ""]
    return md, f"MuJoCo / ours {med:.2f}"


def bound_section(a, rates):
    md = ["## 3. firmware_sim's bound on a tick's stepping", "",
          "The worst-case figure firmware_sim states at start (\"worst-case tick\", docs/bench.md): steps per "
          "tick x the step's work cap x the cost of one work unit, timed at start, plus the truth's derivative, "
          "the extra cost of a first unit on cold caches, and a clock read. A work unit is an RK4 sub-step, a "
          "switch-locating trial or a mode entry after a located switch (docs/MODEL.md 7.8); the cap is the most "
          "units any step may take before it stops. It "
          "bounds the stepping, not the tick's fixed work (commands, sensors, messages: a few us, measured by "
          "firmware_sim's exit summary), nor time the CPU spends elsewhere. Above 1 kHz the scene runs with "
          "sim.step = 1/rate (one RK4 step per tick). Share = bound / period; above 100 % firmware_sim warns "
          "that it cannot guarantee the rate.", "",
          "| scene | " + " | ".join(f"{r} Hz: bound [us] (share; work units per step)" for r in rates) + " |",
          "|---|" + "---|" * len(rates)]
    for scene in SCENES:
        cells = []
        for rate in rates:
            cmd = [str(ROOT / a.build / "bin/firmware_sim"), str(ROOT / "tools/scenes" / f"{scene}.yaml"),
                   "--lockstep", "--lcm-url", "memq://", "--rate", str(rate), "--duration", repr(1.0 / rate)]
            if rate > 1000:
                cmd += ["--set", f"sim.step={1.0 / rate!r}"]
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
            m = BOUND.search(r.stderr)
            if not m:
                cells.append(f"not stated (exit {r.returncode})")
                continue
            bound, period = float(m.group(1)), 1e6 / rate
            cells.append(f"{bound:.0f} ({100 * bound / period:.1f} %; {m.group(3)})")
        md.append(f"| {scene} | " + " | ".join(cells) + " |")
    return md + [""]


def hil_section(a):
    md = ["## 4. The bench: lockstep and real-time wake-ups", ""]
    if a.skip_hil:
        return md + ["Not measured in this run (--skip-hil).", ""], ""
    cmd = ["/usr/bin/python3", "tools/hil/hil_speed.py", "--skip-sweep", "--long", f"{a.hil_long:g}", "--build", a.build]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=3600, cwd=ROOT)
    if r.returncode != 0:
        return md + [f"Not measured: tools/hil/hil_speed.py exited {r.returncode}: {r.stdout[-500:]}{r.stderr[-500:]}", ""], ""
    body = [line for line in r.stdout.splitlines() if not line.startswith("hil_speed: private")]
    ratio = next((line.split("=", 1)[1].strip() for line in body if "firmware_sim / cyclictest" in line), "")
    md += [f"`{' '.join(shlex.quote(x) for x in cmd[1:])}` (paper_ideal and paper_clearance with the pointing "
           "controller over udpm in a private network namespace; its tables as printed):", "", *body, ""]
    return md, f"wake-up lateness / cyclictest (p50 / p99 / p99.9 / max) {ratio}"


def main():
    p = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    output_file.add_build(p)
    p.add_argument("--baseline-bench", help="gimbalsim_bench built from an older commit (the 'before')")
    p.add_argument("--baseline-name", default="baseline", help="what the baseline is, e.g. its commit")
    p.add_argument("--rounds", type=output_file.arg_whole(1, 10**6), default=5,
                   help="alternated passes of the benchmarks; MuJoCo repeats")
    p.add_argument("--min-time", type=output_file.arg_decimal(1e-3, 1e4), default=0.2,
                   help="seconds per benchmark per pass")
    p.add_argument("--rates", type=output_file.arg_whole_list(1, 10**6), default="1000,2000,4000",
                   help="control rates of the worst-case table [Hz]")
    p.add_argument("--hil-long", type=output_file.arg_decimal(1e-3, 1e6), default=20.0,
                   help="seconds of the real-time wake-up run")
    p.add_argument("--skip-hil", action="store_true", help="leave out section 4 (needs root for the namespace)")
    a = p.parse_args()
    if a.rounds < 1:
        p.error(f"--rounds {a.rounds}: at least 1")
    if not a.min_time > 0:
        p.error(f"--min-time {a.min_time}: must be above 0 s")
    results_page.check_page(ROOT / "docs/results/performance.md")  # refused now, not after the measurements
    bench = str(ROOT / a.build / "bin/gimbalsim_bench")
    for f in (bench, str(ROOT / a.build / "bin/firmware_sim")):
        if not os.access(f, os.X_OK):
            p.error(f"{f} is missing: cmake --build {a.build} -j2 --target gimbalsim_bench firmware_sim")
    if a.baseline_bench:
        if not (os.path.isfile(a.baseline_bench) and os.access(a.baseline_bench, os.X_OK)):
            p.error(f"--baseline-bench {a.baseline_bench}: not an executable file")
        listed = subprocess.run([a.baseline_bench, "--benchmark_list_tests"], capture_output=True, text=True).stdout
        if "BM_Rk4<" not in listed:
            p.error(f"--baseline-bench {a.baseline_bench}: lists no BM_Rk4 benchmark; not a gimbalsim_bench")
    elif a.baseline_name != "baseline":
        p.error("--baseline-name names the --baseline-bench, which was not given")
    rates = a.rates
    if not a.hil_long > 0:
        p.error(f"--hil-long {a.hil_long}: must be above 0 s")
    t0, load0 = time.time(), open("/proc/loadavg").read()
    dyn, s_dyn = dynamics_section(a, bench)
    mj, s_mj = mujoco_section(a)
    bound = bound_section(a, rates)
    hil, s_hil = hil_section(a)
    body = ["Every figure below comes from the one run of the command above, on the machine in the header. The "
            "2 cores are shared: absolute times move with the load (see the load average), so compare figures "
            "within this page, not across pages.", "", *dyn, *mj, *bound, *hil]
    command = "/usr/bin/python3 tools/bench/perf_report.py " + " ".join(shlex.quote(x) for x in sys.argv[1:])
    results_page.write_page(ROOT / "docs/results/performance.md", "Performance: derivative, MuJoCo, worst-case tick, bench",
                            command.strip(), "\n".join(body), summary="; ".join(x for x in (s_dyn, s_mj, s_hil) if x),
                            t0=t0, load0=load0)
    print("perf_report: wrote docs/results/performance.md")
    return 0


if __name__ == "__main__":
    sys.exit(output_file.run_script("perf_report", main))
