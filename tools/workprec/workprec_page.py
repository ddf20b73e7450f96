#!/usr/bin/python3
"""docs/results/workprec.md from a gimbalsim_workprec run (called by
tools/workprec/run_workprec.sh --results): what ran, the cheapest setting per
target boresight error, each scene's Pareto front, and the MuJoCo peer
against our RK4 at the same steps, from out/workprec/workprec.csv and its log.

    /usr/bin/python3 tools/workprec/workprec_page.py --dir out/workprec --command CMD [--t0 T0 --load0 L]
"""
import math
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
import results_page  # noqa: E402
import study_csv  # noqa: E402

TARGETS = (1e-3, 1e-6, 1e-9)
MUJOCO = "MuJoCo"


FIGURE = study_csv.Column(0.0, math.inf, nan=True)  # a figure >= 0; nan: one the point has not (it failed)
COUNT = study_csv.Column(0, 10**15, whole=True)
# the keys tools/workprec/policies.yaml sweeps, each by its gimbalsim range
SWEPT = {"sim.substep_tol": study_csv.Column(0.0, 1.0, open_lo=True, open_hi=True)}
# every number column (points.cpp kCsvColumns; sweep_value is the policy table's text), as gimbalsim_workprec writes it
COLUMNS = {"ok": study_csv.Column(flag=True), "pareto": study_csv.Column(flag=True), "h_s": FIGURE,
           "substep_s": FIGURE, "event_tol_s": FIGURE, "cpu_s_per_sim_s": FIGURE, "repeats": COUNT,
           "bore_err_max_rad": FIGURE, "bore_err_end_rad": FIGURE, "theta1_err_max_rad": FIGURE,
           "theta2_err_max_rad": FIGURE, "peak_force_err_rel": FIGURE, "momentum_drift_rel": FIGURE,
           "substeps": COUNT, "impacts": COUNT}


SETTING = ("scene", "policy", "h_s", "substep_s", "event_tol_s", "sweep_key", "sweep_value")  # one point's identity
ERRORS = ("bore_err_max_rad", "bore_err_end_rad", "theta1_err_max_rad", "theta2_err_max_rad")  # of every ok point
NO_CONTACT = "peak_force_err_rel: no contact in the reference"  # points.cpp's note for its nan


def load(path):
    """workprec.csv's points by its writer's column rules (study_csv), and a point that ran ok has the figures the
    page shows: a finite step, CPU time above 0, a finite error and, where its setting names one, a sub-step
    above 0 (pass 48: read as nan and printed; pass 49: an error of -1 named cheapest, 1e-400 shown as 0)."""
    rows = study_csv.read_rows(path.parent, path.name, COLUMNS)
    seen = {}
    for line, r in enumerate(rows, start=2):
        # (pass 69) one setting twice: which of two measurements would the page and the plot show?
        point = tuple(repr(r[k]) for k in SETTING)
        if point in seen:
            raise results_page.output_file.Refused(f"{path}:{line}: the point of line {seen[point]} again (scene, "
                                                   "policy, steps and swept value): its writer measures each once")
        seen[point] = line
        # a swept key's value is the policy table's number (pass 51: 'banana' was shown as the setting)
        if r["sweep_key"]:
            where = f"{path}:{line}: column sweep_"
            rule = SWEPT.get(r["sweep_key"])
            if rule is None:  # (pass 52) any text was taken as the key, and shown
                raise results_page.output_file.Refused(f"{where}key: {r['sweep_key']!r} is no key the policy table "
                                                       f"sweeps ({', '.join(SWEPT)})")
            rule.read(r["sweep_value"], f"{where}value of {r['sweep_key']}")  # (pass 52) 999999 and 0 were shown as the tolerance
        elif r["sweep_value"]:
            raise results_page.output_file.Refused(f"{path}:{line}: column sweep_value: {r['sweep_value']!r} with "
                                                   "no sweep_key (its writer writes it empty)")
        if not r["ok"]:
            continue
        for k in ("h_s", "cpu_s_per_sim_s", *ERRORS) + (("substep_s",) if _shows_substep(r) else ()):
            if not math.isfinite(r[k]) or (r[k] == 0 and k not in ERRORS):
                raise results_page.output_file.Refused(f"{path}:{line}: column {k}: {r[k]!r} is no figure of a "
                                                       "point that ran ok")
        # its writer leaves the force's error nan only where the reference has no contact, and says so (pass 69)
        if math.isnan(r["peak_force_err_rel"]) and NO_CONTACT not in r["note"]:
            raise results_page.output_file.Refused(f"{path}:{line}: column peak_force_err_rel: nan on a point that "
                                                   f"ran ok without the note '{NO_CONTACT}'")
    return rows


def _shows_substep(r):
    return not r["sweep_key"] and r["policy"] != "plain" and not r["policy"].startswith(MUJOCO)


def setting(r):
    s = f"{r['policy']}, h = {r['h_s']:g} s"
    if r["sweep_key"]:
        s += f", {r['sweep_key'].removeprefix('sim.')} {r['sweep_value']}"
    elif _shows_substep(r):
        s += f", sub-step {r['substep_s']:g} s"
    return s


def cheapest(rows, scene, target):
    ok = [r for r in rows if r["scene"] == scene and r["ok"] and r["bore_err_max_rad"] <= target]
    return min(ok, key=lambda r: r["cpu_s_per_sim_s"]) if ok else None


def mujoco_pairs(rows):
    """(MuJoCo row, our plain-RK4 row) for every (scene, h) both measured."""
    pairs = []
    for m in rows:
        if m["ok"] and m["policy"].startswith(MUJOCO):
            o = next((r for r in rows if r["ok"] and r["policy"] == "plain" and r["scene"] == m["scene"]
                      and abs(r["h_s"] - m["h_s"]) < 1e-12), None)
            if o is not None:
                pairs.append((m, o))
    return pairs


def mujoco_ratios(rows):
    """MuJoCo's CPU time per simulated second over ours, per (scene, h) pair."""
    return [m["cpu_s_per_sim_s"] / o["cpu_s_per_sim_s"] for m, o in mujoco_pairs(rows)]


def mujoco_table(rows):
    """(scene, h) pairs measured by both the MuJoCo peer and our plain RK4."""
    out = [f"| {m['scene']} | {m['h_s']:g} | {o['cpu_s_per_sim_s'] * 1e3:.3g} | "
           f"{m['cpu_s_per_sim_s'] * 1e3:.3g} | {m['cpu_s_per_sim_s'] / o['cpu_s_per_sim_s']:.2f} | "
           f"{o['bore_err_max_rad']:.2e} | {m['bore_err_max_rad']:.2e} |" for m, o in mujoco_pairs(rows)]
    if not out:
        return ""
    return ("| scene | h [s] | ours: CPU ms per simulated s | MuJoCo RK4 | MuJoCo / ours | ours: max boresight error "
            "[rad] | MuJoCo |\n|---|---|---|---|---|---|---|\n" + "\n".join(out) + "\n")


def body(rows, log, command):
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    failed = sum(not r["ok"] for r in rows)
    md = [f"`build/bin/gimbalsim_workprec` (tools/workprec/): per scene, every contact sub-stepping policy of "
          f"tools/workprec/policies.yaml over the outer steps; for each point the median thread CPU time of the "
          f"stepping per simulated second and the errors against the Dormand-Prince reference (1e-12) at every "
          f"output row. The run-time checks are off (every setting's error is measured instead). "
          f"{len(rows)} points on {', '.join(scenes)}; {failed} failed (kept in the CSV with the reason). "
          f"CSV: out/workprec/workprec.csv; plot: out/workprec/workprec.png.", ""]
    ref = [line.rstrip() for line in log.splitlines()
           if line.startswith(("work-precision", "[")) or line.startswith(("  reference", "  stick-slip"))]
    if ref:
        md += ["## What ran", "", "```", *ref, "```", ""]
    md += ["## Cheapest setting per target max boresight error", "",
           "Median CPU time per simulated second, and per simulated 5 s (the paper's run) in brackets.", "",
           "| scene | " + " | ".join(f"{t:.0e} rad" for t in TARGETS) + " |",
           "|---|" + "---|" * len(TARGETS)]
    for s in scenes:
        cells = []
        for t in TARGETS:
            b = cheapest(rows, s, t)
            cells.append("not reached" if b is None else
                         f"{setting(b)}: {b['cpu_s_per_sim_s'] * 1e3:.3g} ms/s ({b['cpu_s_per_sim_s'] * 5e3:.3g} ms), "
                         f"error {b['bore_err_max_rad']:.2g}")
        md.append(f"| {s} | " + " | ".join(cells) + " |")
    md.append("")
    md += ["## Pareto front per scene", "",
           "Points no other point beats in both CPU time and max boresight error, cheapest first.", "",
           "| scene | setting | CPU ms per simulated s | max boresight error [rad] | RK4 sub-steps |",
           "|---|---|---|---|---|"]
    for s in scenes:
        front = sorted((r for r in rows if r["scene"] == s and r["ok"] and r["pareto"]),
                       key=lambda r: r["cpu_s_per_sim_s"])
        for r in front:
            md.append(f"| {s} | {setting(r)} | {r['cpu_s_per_sim_s'] * 1e3:.3g} | {r['bore_err_max_rad']:.2e} | "
                      f"{r['substeps']:.0f} |")
    md.append("")
    mj = mujoco_table(rows)
    md += ["## MuJoCo peer", ""]
    if mj:
        md += ["MuJoCo 2.2's RK4 (Debian's libmujoco-dev, tools/mujoco/) on the same scene and reference, against "
               "our plain RK4 at the same step, measured in the same run:", "", mj]
    else:
        md += ["No MuJoCo points in this run: the build has no MuJoCo (install libmujoco-dev and libqhull-dev, "
               "reconfigure), or no scene without clearance was swept.", ""]
    return "\n".join(md)


def main():
    ap = results_page.page_arguments(__doc__, "out/workprec")
    a = ap.parse_args()
    d = ROOT / a.dir
    with results_page.study_files(d, "gimbalsim_workprec"):
        rows = load(d / "workprec.csv")
        if not rows:
            raise results_page.no_rows(d / "workprec.csv", "docs/results/workprec.md")
        log = results_page.run_file(d, "workprec.log", optional=True)
        b = cheapest(rows, "paper_clearance", 1e-6)
        summary = (f"paper_clearance to 1e-6 rad cheapest: {setting(b)}, {b['cpu_s_per_sim_s'] * 1e3:.3g} ms CPU "
                   f"per simulated s") if b else f"{len(rows)} points"
        text = body(rows, log, a.command)
    results_page.write_page(ROOT / "docs/results/workprec.md", "Run time against error (work-precision)",
                            a.command, text, summary=summary, t0=a.t0, load0=a.load0)
    print("workprec_page: wrote docs/results/workprec.md")
    return 0


if __name__ == "__main__":
    sys.exit(results_page.output_file.run_script("workprec_page", main))
