#!/usr/bin/python3
"""The budget at the default sampling against a fine fixed setting, side by
side (prints figures; not a test). The same closed-loop budget spec (the
shipped tools/sweeps/pointing_budget.yaml unless --spec) runs twice on the
same units: as shipped (`sampling: auto`, the default) and at a fine fixed
setting (`sampling: scene`: the scene's own friction law under the fixed
sub-step policy, sim.substep --fine-substep; a spec that sets or disperses
sim.substep or sim.substep_policy has no fine run and is refused). It compares

 - the speed: wall time, samples per second and CPU per sample (the
   sweep's own engine figures) of each run, and their ratio;
 - each index in each phase: the default's quantile estimate against the
   fine run's equal-tailed order-statistics interval at the spec's level and
   confidence (an end below the best or beyond the worst unit is open);
 - each unit: its figure's distance from the fine run's, against 1 % of the
   index's requirement (an index without one: 1 % of the spec's largest, or
   gimbalsim's stated sampling tolerance when the spec gives none); each
   unit beyond it is nudged (unit_conditioning.py) to tell a figure the
   loop does not define to the tolerance from one the sampling moved, and
   each one the nudges hold is run again at the fine sub-step / 2, / 4 and / 16
   to tell a figure the fine run has not settled from one the sampling moved.

Usage:
  /usr/bin/python3 tools/sweeps/budget_speed.py [--build build] [--workers 2] [--spec SPEC]
      [--samples N] [--fine-substep 5e-6] [--nudge N] [--out DIR] [--results]

--samples N runs only the spec's first N of its samples (a quick look; the page is
for the whole spec). --nudge N nudges at most N units (default 200).
--results also writes the shipped budget's page (tools/pages/results_page.py),
docs/results/budget_speed*.md: --help names each (PAGES); the runs stay in
--out (default: the repository's out/budget_speed, or out/budget_speed_<spec
name> for another spec; each run's folder and the spec it ran).
"""
import argparse
import contextlib
import csv
import io
import json
import math
import os
import pathlib
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
import output_file  # noqa: E402  (how a script ends; the writer's rules)
import results_page  # noqa: E402  (the page's writer)
from output_file import Refused  # noqa: E402
import unit_conditioning  # noqa: E402  (how well each unit's figure is defined)
from budget_speed_specs import check_derived, derived_specs  # noqa: E402  (the default and fine runs' specs)

SHIPPED = ROOT / "tools" / "sweeps" / "pointing_budget.yaml"
# The shipped budgets this tool writes a page for, each with its wall-time target on 2 workers (issue 40):
# {spec name: (page, target [s], target [samples/s])}
PAGES = {"pointing_budget.yaml": (ROOT / "docs" / "results" / "budget_speed.md", 60.0, 18.0),
         "pointing_budget_spatial.yaml": (ROOT / "docs" / "results" / "budget_speed_spatial.md", 300.0, 3.7),
         "pointing_budget_spatial_tracker.yaml": (ROOT / "docs" / "results" / "budget_speed_spatial_tracker.md",
                                                  300.0, 3.7)}
SHARE = 0.01  # of the requirement: how far a unit's figure may move
MAX_PROBED = 200  # units beyond the tolerance nudged (four fine runs each) to see whether their figure is defined
RUNS = ("default", "fine")  # what --out holds: each run's folder and the spec it ran


class SweepFailed(Exception):
    """A run's sweep ended with an error: its exit code, and what it said."""


def run_sweep(build, spec, out, workers):
    """The sweep's summary.json and its rows {sample: row}; SweepFailed
    naming the failure."""
    env = {**os.environ, "PYTHONPATH": str(build / "python")}
    cmd = [sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", str(out), "--workers", str(workers),
           "--no-progress"]
    r = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if r.returncode != 0:
        raise SweepFailed(r.returncode, f"{shlex.join(cmd)} failed (exit {r.returncode}):\n{r.stderr[-3000:]}")
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "results.csv", newline="") as f:
        rows = {int(row["sample"]): row for row in csv.DictReader(f)}
    return summary, rows


def figure(row, column):
    """A unit's figure [rad]; NaN for a unit without one (never 0)."""
    try:
        return float(row[column]) if row["status"] == "ok" else math.nan
    except (KeyError, ValueError):
        return math.nan


def interval(values, level, confidence):
    """(low, high) of the level-quantile at confidence over values, from the
    order statistics (gimbalsim.indices' ranks): an end beyond the units is
    -inf / +inf. A unit without a figure counts as +inf, as in the budget."""
    from gimbalsim import indices
    xs = sorted(v if math.isfinite(v) else math.inf for v in values)
    _, r, s2 = indices._ranks(len(xs), level, confidence)
    return (xs[r - 1] if r >= 1 else -math.inf), (xs[s2 - 1] if s2 <= len(xs) else math.inf)


def _distance_text(worst, unit):
    if unit is None:
        return "n/a (no unit has a figure in either run)"
    return f"{'a figure in one run only' if worst == math.inf else f'{worst:.2e}'} (unit {unit})"


def compare(spec, budget_default, budget_fine, rows_default, rows_fine, tolerance_default):
    """Per index-phase of the budget: a dict of its estimates, the fine run's
    interval, the tolerance, the largest unit distance and the units beyond."""
    reqs = {name: float(opts["requirement"]) for name, opts in (spec.get("indices") or {}).items()
            if isinstance(opts, dict) and "requirement" in opts}
    fallback = SHARE * max(reqs.values()) if reqs else tolerance_default
    fine_of = {(b["index"], b["phase"]): b for b in budget_fine}
    units = sorted(set(rows_default) & set(rows_fine))
    found = []
    for b in budget_default:
        f, key = fine_of[(b["index"], b["phase"])], f"{b['index']}_{b['phase']}"
        a_vals = [figure(rows_default[u], key + "_rad") for u in units]
        f_vals = [figure(rows_fine[u], key + "_rad") for u in units]
        low, high = interval(f_vals, b["level"], b["confidence"])
        # an estimate beyond every figure (it falls on units without one, counted as worst) is +inf, not "none"
        # (pass 42: read as NaN, it was never inside an interval open at its top, and the verdict said "no")
        est_a, est_f = (_estimate(x) for x in (b, f))
        tol = SHARE * reqs[b["index"]] if b["index"] in reqs else fallback
        # over the units with a figure in either run: one in one run only is beyond any tolerance
        diffs = [(abs(x - y) if math.isfinite(x) and math.isfinite(y) else math.inf, u)
                 for x, y, u in zip(a_vals, f_vals, units) if math.isfinite(x) or math.isfinite(y)]
        worst, worst_unit = max(diffs) if diffs else (math.nan, None)
        found.append({"key": key, "est_a": est_a, "est_f": est_f, "low": low, "high": high, "tol": tol,
                      # no estimate (no unit has a figure): not inside; an interval open at both ends (too few
                      # units for the level and confidence) bounds nothing: no verdict
                      "judged": math.isfinite(low) or math.isfinite(high),
                      "fine_none": not any(math.isfinite(y) for y in f_vals),  # no interval to hold it to
                      "inside": not math.isnan(est_a) and low <= est_a <= high, "worst": worst,
                      "worst_unit": worst_unit, "compared": bool(diffs),  # no unit with a figure: no verdict
                      "beyond": [u for d, u in diffs if d > tol]})
    return found


def _estimate(entry):
    """A budget entry's estimate [rad]: +inf beyond every figure, NaN with no unit with a figure."""
    x, none = entry["estimate_rad"], entry["n_missing"] == entry["n"]  # no unit with a figure: nothing beyond
    return x if x is not None else math.inf if "estimate_note" in entry and not none else math.nan


def _estimate_text(x):
    return "n/a (no unit has a figure)" if math.isnan(x) else "beyond every figure" if math.isinf(x) else f"{x:.3e}"


def _category(c):
    """Where an index stands against the fine run: "none" (no unit has a figure in either run), "fine_none" (no
    unit of the fine run has one), "unjudged" (its interval is open at both ends), "inside" or "outside"."""
    if not c["compared"]:
        return "none"
    if c["fine_none"]:
        return "fine_none"
    return "unjudged" if not c["judged"] else "inside" if c["inside"] else "outside"


# the table's "within" cell per category: no verdict over no figure or an interval that bounds nothing
WITHIN_TEXT = {"none": "n/a (no unit has a figure)", "fine_none": "n/a (no unit of the fine run has a figure)",
               "unjudged": "n/a (open at both ends: too few units)", "inside": "yes", "outside": "**no**"}


def report(spec_name, spec, runs, fine_substep, workers, tolerance_default, fine_spec, most_probed):
    (s_d, r_d), (s_f, r_f) = runs
    n = len(r_d)
    print(f"{spec_name}: {n} units, {workers} worker{'s' if workers != 1 else ''}; the default sampling: "
          f"{s_d['sampling']['why']}; the fine setting: the scene's own law, fixed sub-steps of {fine_substep:g} s.\n")
    print("| run | wall [s] | samples/s | CPU per sample [ms] | engine overhead per sample [ms] |")
    print("|---|---|---|---|---|")
    for label, s in ((f"default (sampling: {s_d['sampling']['mode']})", s_d),
                     (f"fine (sim.substep {fine_substep:g} s)", s_f)):
        e = s["engine"]
        print(f"| {label} | {e['elapsed_s']:.1f} | {_number(e['samples_per_s'], '.1f')} | "
              f"{_number(e['mean_run_s'], '.1f', 1e3)} | {_number(e['engine_overhead_per_sample_s'], '.2f', 1e3)} |")
    ratio = s_f["engine"]["elapsed_s"] / s_d["engine"]["elapsed_s"]
    cpu_f, cpu_d = s_f["engine"]["mean_run_s"], s_d["engine"]["mean_run_s"]
    cpu = "n/a: a run whose every sample crashed has no CPU per sample" if not (cpu_f and cpu_d) else \
        f"{_times(cpu_f / cpu_d, 'less', 'more')} CPU per sample"
    print(f"\nThe default runs the budget {_times(ratio, 'faster', 'slower')} than the fine setting ({cpu}).")
    if spec_name in PAGES and n == 1109 and workers == 2:
        e, (_, target_s, target_rate) = s_d["engine"], PAGES[spec_name]
        met = e["elapsed_s"] <= target_s and e["samples_per_s"] >= target_rate
        print(f"Target (the shipped budget on 2 workers in at most {target_s:.0f} s, at least {target_rate:g} "
              f"samples/s): {e['elapsed_s']:.1f} s, {e['samples_per_s']:.1f} samples/s, "
              f"{'met' if met else 'missed'}.")
    found = compare(spec, s_d["budget"], s_f["budget"], r_d, r_f, tolerance_default)
    probed = sorted({u for c in found for u in c["beyond"]})
    spread = unit_conditioning.spreads(fine_spec, probed[:most_probed], [c["key"] for c in found], r_f, workers) \
        if probed and most_probed else {}
    judged = unit_conditioning.classify(found, spread)  # {key: (ill-defined, held, not judged)}
    ill = {k: v[0] for k, v in judged.items()}
    # the units the nudges held, at finer fine sub-steps: a figure the fine run has not settled is no reference
    held_units = sorted({u for v in judged.values() for u in v[1]})
    settle = unit_conditioning.spreads(fine_spec, held_units[:most_probed], [c["key"] for c in found], r_f, workers,
                                       refined=fine_substep) if held_units and most_probed else {}
    settled = unit_conditioning.classify([{**c, "beyond": judged[c["key"]][1]} for c in found], settle)
    unsettled = {k: v[0] for k, v in settled.items()}  # {key: units}; v[1]: settled, v[2]: not refined
    print("\nEach index (the budget's level and confidence) at the default against the fine run: its quantile "
          "estimate, the fine run's order-statistics interval, and the largest distance of a unit's figure "
          "from its fine figure, against the tolerance (1 % of the requirement). Ill-defined: of the units "
          "beyond it, those whose fine figure itself moves beyond the tolerance when the fine run starts its "
          f"journal {unit_conditioning.NUDGE_M:g} m away (tools/sweeps/unit_conditioning.py). Unsettled: of "
          "the others, those whose fine figure moves beyond the tolerance when the fine sub-step is divided by "
          f"{' or '.join(map(str, unit_conditioning.REFINE))} (the fine run is no reference for them).\n")
    print("| index | default [rad] | fine [rad] | fine interval [rad] | within | largest unit distance [rad] "
          "| tolerance [rad] | units beyond | of them ill-defined | of the rest, unsettled |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    show = lambda x, end="open": end if not math.isfinite(x) else f"{x:.3e}"  # noqa: E731
    for c in found:
        print(f"| {c['key']} | {_estimate_text(c['est_a'])} | {_estimate_text(c['est_f'])} | "
              f"{'n/a (no figure)' if c['fine_none'] else '[' + show(c['low']) + ', ' + show(c['high']) + ']'} | "
              f"{WITHIN_TEXT[_category(c)]}"
              f" | {_distance_text(c['worst'], c['worst_unit'])} | {c['tol']:.0e} | {len(c['beyond'])} | "
              f"{len(ill[c['key']])} | {len(unsettled[c['key']])} |")
    keys_in = {k: [c["key"] for c in found if _category(c) == k] for k in WITHIN_TEXT}
    outside, unjudged, fine_none, nothing, inside = (keys_in[k] for k in
                                                     ("outside", "unjudged", "fine_none", "none", "inside"))
    beyond = [f"{c['key']} ({len(c['beyond'])} units)" for c in found if c["beyond"]]
    held_to = [f"{k} ({len(v[1])} of {len(v[0]) + len(v[1]) + len(v[2])})" for k, v in judged.items() if v[1]]
    not_judged = [f"{k} ({len(v[2])})" for k, v in judged.items() if v[2]]
    few = "some" if any(v[0] for v in judged.values()) else "any"  # of the units beyond, when none held
    # no verdict over no figure (passes 37, 39): each index without one named apart, never a bare "yes" or "no"
    none = f"n/a for {', '.join(nothing)} (no unit has a figure in either run)" if nothing else ""
    within = "; ".join(x for x in (
        "no (" + ", ".join(outside) + ")" if outside else "yes" if inside else "",
        f"n/a for {', '.join(unjudged)} (intervals open at both ends: too few units for the level and confidence)"
        if unjudged else "",
        f"n/a for {', '.join(fine_none)} (no unit of the fine run has a figure)" if fine_none else "", none) if x)
    unit = "; ".join(x for x in ("no (" + ", ".join(beyond) + ")" if beyond else "yes" if len(nothing) < len(found)
                                 else "", none) if x)
    print(f"\nEvery index within the fine run's interval: {within}."
          f"\nEvery unit within the tolerance of its fine figure: {unit}.")
    if beyond:
        cut = f" (the first {most_probed} of {len(probed)} units nudged)" if len(probed) > most_probed else ""
        reasons = sorted({v for v in spread.values() if isinstance(v, str)})
        print(unit_conditioning.verdict(
            f"Every unit beyond it ill-defined (its own fine figure moves beyond the tolerance when nudged){cut}",
            'no' if held_to else 'yes' if not not_judged else 'n/a (no nudge could judge ' + few + ')',
            [("units whose fine figure held under every nudge", held_to),
             ("units no nudge could judge (no figure in any run, or none made)", not_judged)], "not nudged", reasons))
    settled_to = [f"{k} ({len(v[1])} of {len(judged[k][1])})" for k, v in settled.items() if v[1]]
    unrefined = [f"{k} ({len(v[2])})" for k, v in settled.items() if v[2]]
    if held_to:
        cut = f" (the first {most_probed} of {len(held_units)} units)" if len(held_units) > most_probed else ""
        reasons = sorted({v for v in settle.values() if isinstance(v, str)})
        print(unit_conditioning.verdict(
            "Every unit the nudges held unsettled by the fine run (its fine figure moves beyond the tolerance at the "
            f"fine sub-step / {' or / '.join(map(str, unit_conditioning.REFINE))}){cut}",
            'no' if settled_to else 'yes' if not unrefined else 'n/a (no refinement could judge them)',
            [("units whose fine figure settled (the sampling moved them)", settled_to),
             ("units no refinement could judge", unrefined)], "not refined", reasons))
    if len(nothing) == len(found):
        return ratio, "not judged (no unit has a figure)"
    return ratio, ("held" if not (outside or unjudged or fine_none or beyond) else "moved" if
                   outside or unjudged or not_judged or settled_to or unrefined else "moved only where ill-defined"
                   + (" or unsettled by the fine run" if held_to else ""))


def _times(r, more, less):
    """A ratio of two costs in words: "2.0 times faster", or "3.3 times slower" below 1."""
    return f"{r:.1f} times {more}" if r >= 1.0 else f"{1.0 / r:.1f} times {less}"


def _number(x, form, scale=1.0):
    """An engine figure for the table; n/a where the sweep has none (every sample crashed)."""
    return "n/a" if x is None else format(scale * x, form)


def check_out(out):
    """--out is this tool's folder or nothing: never a link, a file, or a
    folder holding anything else (it is replaced when both runs finish)."""
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise Refused(f"--out {out}: a symbolic link or not a folder; the runs replace it: give another")
    if out.is_dir():
        links = sorted(x.name for x in out.iterdir() if x.is_symlink())
        if links:
            raise Refused(f"--out {out}: holds the link {links[0]}; the runs replace the folder whole: give another")
        strangers = sorted(x.name for x in out.iterdir() if x.name not in RUNS + tuple(f"{r}.yaml" for r in RUNS))
        if strangers:
            raise Refused(f"--out {out}: holds {', '.join(strangers[:3])}, not this tool's runs; the runs replace "
                          "it: give another folder")


def main():
    p = argparse.ArgumentParser(allow_abbrev=False, description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    output_file.add_build(p, holding="python/")
    p.add_argument("--spec", default=str(SHIPPED), help="closed-loop sweep spec (default: the shipped budget)")
    p.add_argument("--workers", type=output_file.arg_whole(1, 4 * (os.cpu_count() or 1)), default=2,
                   help="local Dask workers of each run (as the sweep: 4 per core of this machine at most)")
    p.add_argument("--samples", type=output_file.arg_whole(1, 10**6), default=None,
                   help="run only the spec's first N units")
    p.add_argument("--fine-substep", type=output_file.arg_decimal(1e-8, 1e-3), default=5e-6,
                   help="the fine run's fixed sub-step [s], in [1e-8, 1e-3]")
    p.add_argument("--out", default=None, help="folder for both runs, replaced when both finish "
                   "(default: the repository's out/budget_speed)")
    p.add_argument("--nudge", type=output_file.arg_whole(0, 10**6), default=MAX_PROBED,
                   help=f"units beyond the tolerance nudged, four fine runs each (default {MAX_PROBED}; 0: none)")
    p.add_argument("--results", action="store_true", help="also write the spec's page in docs/results/ "
                   f"({', '.join(f'{k}: {v[0].name}' for k, v in PAGES.items())})")
    a = p.parse_args()
    if a.results and a.samples is not None:
        p.error("--results writes the page for the whole spec: leave out --samples")
    if a.results and pathlib.Path(a.spec).name not in PAGES:
        p.error(f"--results writes the page of a shipped budget ({', '.join(PAGES)}): leave it out for {a.spec}")
    build = pathlib.Path(a.build)
    spec_path = pathlib.Path(a.spec).resolve()
    if not spec_path.is_file():
        p.error(f"--spec {a.spec}: {'not a regular file' if spec_path.exists() else 'no such file'}")
    # (pass 48) a copy named as a shipped budget (2 units, another profile) replaced the shipped budget's page
    if a.results and spec_path != (ROOT / "tools" / "sweeps" / spec_path.name).resolve():
        p.error(f"--results writes the page of the shipped {spec_path.name} in tools/sweeps/: --spec {a.spec} is "
                "another file; leave out --results")
    out = pathlib.Path(os.path.abspath(a.out)) if a.out is not None else \
        ROOT / "out" / ("budget_speed" if spec_path == SHIPPED else f"budget_speed_{spec_path.stem}")
    if out == ROOT or out in spec_path.parents or ROOT / "docs" in [out, *out.parents]:
        p.error(f"--out {a.out}: would replace the source tree, the spec's folder or the docs")
    return output_file.run_script("budget_speed.py", lambda: _run(a, build, spec_path, out))


def _run(a, build, spec_path, out):
    """Everything checked (the specs by the sweep's --check, --out, the page's
    names), then both runs into a fresh folder beside --out, which replaces
    it; a refusal or a failed run leaves --out as it was."""
    output_file.import_package(build)  # the package of --build, or a refusal naming the command that builds it
    from gimbalsim import _sampling, _scene_warnings
    _scene_warnings.quiet()  # as the sweeps it runs: they judge their keys; the scene's own warnings are simulate's

    t0, load0 = str(time.time()), open("/proc/loadavg").read()
    plain, texts, user_paths = derived_specs(spec_path, a.samples, a.fine_substep)
    for given in [spec_path, user_paths["scene"]] + ([user_paths["controller"]] if "controller" in user_paths else []):
        # the runs replace --out whole: an input in it, or a link in it to one, would go with it
        for path in (pathlib.Path(os.path.abspath(given)), pathlib.Path(given).resolve()):
            if out.resolve() in path.parents or pathlib.Path(os.path.abspath(out)) in path.parents:
                raise Refused(f"--out {out}: holds {path}, an input of this run; the runs replace it: give another "
                              "folder")
    check_out(out)
    page = PAGES[spec_path.name][0] if a.results else None
    if a.results:
        results_page.check_page(page)
    if a.out is None:
        out.parent.mkdir(exist_ok=True)  # the repository's out/, as the scripts of tools/ make it
    elif not out.parent.is_dir():
        raise Refused(f"--out {out}: its folder {out.parent} does not exist")
    # one run per --out at a time (as one sweep per folder): the second would replace the first's folder
    with output_file.one_at_a_time(out.parent / f".{out.name}.budget_speed.lock", f"--out {out}"):
        work = pathlib.Path(tempfile.mkdtemp(prefix=out.name + ".new-", dir=out.parent))
        try:
            return _run_in(a, build, spec_path, out, work, plain, texts, _sampling.TOLERANCE_RAD, t0, load0, page)
        finally:
            shutil.rmtree(work, ignore_errors=True)  # gone once renamed to --out; else nothing is left behind


def _run_in(a, build, spec_path, out, work, plain, texts, tolerance, t0, load0, page):
    """_run's work in the fresh folder work, renamed to out at the end."""
    paths = {name: work / f"{name}.yaml" for name in RUNS}
    for name in RUNS:  # every spec written and checked before the first run
        output_file.write_text(paths[name], texts[name])
        check_derived(paths[name], name)
    try:
        runs = []
        for name in RUNS:
            print(f"budget_speed.py: running {name} ({paths[name]}) ...", file=sys.stderr)
            runs.append(run_sweep(build, paths[name], work / name, a.workers))
    except SweepFailed as e:
        print(f"budget_speed.py: {e.args[1]}", file=sys.stderr)
        return e.args[0]
    body = io.StringIO()
    with contextlib.redirect_stdout(body):
        ratio, held = report(spec_path.name, plain, runs, a.fine_substep, a.workers, tolerance, paths["fine"],
                             a.nudge)
    print(body.getvalue(), end="")
    check_out(out)  # as before the runs: nothing planted there since
    if out.exists():
        shutil.rmtree(out)
    work.rename(out)
    if not a.results:
        return 0
    e = runs[0][0]["engine"]
    results_page.write_page(page, f"{spec_path.name} at its default sampling against a fine fixed setting",
                            "/usr/bin/python3 tools/sweeps/budget_speed.py " + shlex.join(sys.argv[1:]),
                            __doc__.split("\n\n")[0] + "\n\n" + body.getvalue(),
                            summary=f"{spec_path.name}: {e['elapsed_s']:.0f} s on {a.workers} workers "
                                    f"({e['samples_per_s']:.1f} samples/s), {_times(ratio, 'faster', 'slower')} "
                                    f"than fine; figures {held}", t0=t0, load0=load0)
    print(f"budget_speed.py: wrote {page.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
