#!/usr/bin/python3
"""docs/results/speed.md (called by tools/bench/run_bench.sh --results): the
Google Benchmark medians of gimbalsim_bench, and the MuJoCo peer's ratio to
our RK4 from a gimbalsim_workprec run of the ideal scene (both measured in the
same script run; the load average at start and end is in the header).

    /usr/bin/python3 tools/bench/speed_page.py --bench-json B.json [--mujoco-dir DIR | --no-mujoco REASON]
        --command CMD [--t0 T0 --load0 L]
"""
import argparse
import json
import math
import pathlib
import statistics
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
sys.path.insert(0, str(ROOT / "tools" / "workprec"))
import results_page  # noqa: E402
import workprec_page  # noqa: E402


NS_PER = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}  # Google Benchmark's time units
MAX_NS = 1e15        # a call of 11 days: no benchmark of gimbalsim_bench's comes near
MAX_REPS = 10**6     # run_bench.sh takes REPS in [2, 1000]


def _ns(r):
    """An aggregate's figure: a CPU time per call > 0 in ns (a spread, stddev, >= 0; cv a ratio >= 0, kept as is),
    finite and in one of Google Benchmark's units (pass 49: a time <= 0 was printed, and a benchmark timed in us
    dropped without a word; pass 48: a nan was printed as a measurement)."""
    t, unit, what = r["cpu_time"], r.get("time_unit", "ns"), r["aggregate_name"]
    spread = what in ("stddev", "cv")
    ns = t * NS_PER[unit] if type(t) in (int, float) and unit in NS_PER and what != "cv" else t
    if type(t) not in (int, float) or not math.isfinite(t) or t < 0 or (t == 0 and not spread) or unit not in NS_PER \
            or not ns <= MAX_NS:
        raise ValueError(f"{r['run_name']} {what}: cpu_time {t!r} {unit!r} (a time > 0 in ns, us, ms or s, at most "
                         f"{MAX_NS:g} ns)")
    return ns


def bench_table(path):
    """The medians table of a Google Benchmark JSON (Refused, exit 2, for one that is not: pass 47)."""
    data = json.loads(results_page.output_file.read_input(path, "--bench-json"))
    if not isinstance(data, dict) or not isinstance(data.get("benchmarks"), list):
        raise results_page.output_file.Refused(f"--bench-json {path}: not Google Benchmark's JSON (no list "
                                               "'benchmarks')")
    rows = {}
    for r in data["benchmarks"]:
        if r.get("run_type") != "aggregate":
            continue
        row = rows.setdefault(r["run_name"], {})
        if r["aggregate_name"] in row:  # (pass 50) the last of two medians was shown
            raise ValueError(f"{r['run_name']}: a second {r['aggregate_name']!r} aggregate")
        row[r["aggregate_name"]] = _ns(r)
        row["reps"] = r["repetitions"]
        if type(row["reps"]) is not int or not 1 <= row["reps"] <= MAX_REPS:  # (pass 49) null, 0 or -1 was shown
            raise ValueError(f"{r['run_name']}: repetitions {row['reps']!r} (a whole number in [1, {MAX_REPS}])")
    ctx = data.get("context", {})
    if not isinstance(ctx, dict):
        raise ValueError("'context' is no object (Google Benchmark writes one)")
    md = ["| benchmark | median CPU per call [ns] | min [ns] | cv |", "|---|---|---|---|"]
    for name, row in rows.items():
        cv = row.get("cv")  # (pass 48) a median or min the JSON lacks is no figure: KeyError, refused
        if row["median"] < row["min"]:  # (pass 50) shown as measured
            raise ValueError(f"{name}: min {row['min']} ns above its median {row['median']} ns")
        name = name.replace("|", "\\|")  # a '|' in a name would split the table's row
        md.append(f"| {name} | {row['median']:.1f} | {row['min']:.1f} | {'' if cv is None else f'{cv:.1%}'} |")
    if len(md) == 2:
        raise results_page.no_rows(f"--bench-json {path}", "docs/results/speed.md")
    counts = sorted({r["reps"] for r in rows.values()})
    reps = f"{counts[0]}" if len(counts) == 1 else f"{counts[0]} to {counts[-1]}"
    return "\n".join(md) + "\n", reps, ctx


def main():
    ap = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    results_page.output_file.standard_flags(ap)
    ap.add_argument("--bench-json", required=True)
    ap.add_argument("--mujoco-dir")
    ap.add_argument("--no-mujoco", help="why there is no MuJoCo figure")
    ap.add_argument("--command", required=True)
    results_page.add_start_arguments(ap)
    a = ap.parse_args()
    with results_page.study_files(a.bench_json, "gimbalsim_bench"):
        table, reps, ctx = bench_table(a.bench_json)
    md = ["Both parts below ran in one run of the command above on the machine in the header; medians and ratios "
          "are from this run only. The 2 cores are shared (see the load average above): absolute times move "
          "by tens of percent with the load, and on this VM even the ratios of one run move by up to a quarter "
          "between runs minutes apart; re-run on a quiet machine before quoting a figure.", "",
          "## Dynamics micro-benchmarks (Google Benchmark)", "",
          f"`build/bin/gimbalsim_bench` (tools/bench/bench_dynamics.cpp, Release build), {reps} repetitions, median "
          f"and minimum CPU time per call and the coefficient of variation over the repetitions (Google Benchmark "
          f"from Debian's libbenchmark-dev, which reports itself as a {ctx.get('library_build_type', '?')} build: "
          "that is its own timing loop, not the code measured). "
          "Variants: Fixed/Floating base, Ideal/Clearance joint, with or without friction; states taken mid-run "
          "of the paper scene. BM_ForwardDynamics: one derivative; BM_Rk4: one RK4 step; BM_Step: one integrator "
          "step (sub-steps in contact); BM_ContactLaw, BM_ClearanceContact, BM_StepImpact: the contact pieces.", "",
          table, "## MuJoCo peer", ""]
    summary = ""
    if a.mujoco_dir:
        with results_page.study_files(a.mujoco_dir, "gimbalsim_workprec"):
            rows = workprec_page.load(pathlib.Path(a.mujoco_dir) / "workprec.csv")
            mj = workprec_page.mujoco_table(rows)
            ratios = workprec_page.mujoco_ratios(rows)
        if mj and ratios:
            med = statistics.median(ratios)
            summary = f"MuJoCo 2.2 RK4 step / ours: median {med:.2f} over {len(ratios)} step sizes"
            md += ["MuJoCo 2.2's RK4 (Debian's libmujoco-dev; tools/mujoco/mujoco_peer.cpp builds the same gimbal "
                   "as an MJCF model) against our plain RK4 on `paper_ideal_valid_inertia` (the paper's scene with "
                   "base inertia diag(1000, 600, 600): MuJoCo refuses the paper's, which violates the triangle "
                   "inequality), same steps, same Dormand-Prince reference, thread CPU time of the stepping, "
                   "measured by `gimbalsim_workprec` in this run:", "", mj,
                   f"**MuJoCo / ours, CPU time per simulated second: median {med:.2f}** "
                   f"(range {min(ratios):.2f} to {max(ratios):.2f}).", ""]
        else:
            md += ["The MuJoCo run produced no comparable points (see out/speed/mujoco/workprec.log).", ""]
    else:
        md += [f"Not measured: {a.no_mujoco or 'no MuJoCo'}.", ""]
    results_page.write_page(ROOT / "docs/results/speed.md", "Speed: dynamics micro-benchmarks and the MuJoCo ratio",
                            a.command, "\n".join(md), summary=summary, t0=a.t0, load0=a.load0)
    print("speed_page: wrote docs/results/speed.md")
    return 0


if __name__ == "__main__":
    sys.exit(results_page.output_file.run_script("speed_page", main))
