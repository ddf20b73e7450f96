#!/usr/bin/python3
"""Work-precision plot from gimbalsim_workprec's CSV: max boresight error
against CPU time per simulated second, log-log, one panel per scene, one
curve per policy (the MuJoCo peer is one more curve). Failed points are left
out (the CSV keeps them with the reason).

    /usr/bin/python3 tools/workprec/plot_workprec.py [CSV] [--out PNG]

CSV defaults to the repository's out/workprec/workprec.csv (where
run_workprec.sh writes it), from any folder; PNG to beside the CSV.
"""
import argparse
import os
import pathlib
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
sys.path.insert(0, str(ROOT / "tools" / "workprec"))
import output_file  # noqa: E402  (standard_flags)
from output_file import Refused, check_before_writing, check_figure_format, run_script, savefig  # noqa: E402
import workprec_page  # noqa: E402  (the CSV's one reader: its writer's rules, as the results page reads it)

TARGETS = workprec_page.TARGETS  # [rad], the targets the tool reports


def read(path):
    """{scene: {policy: [(cpu, error, on the front)]}} of the points that ran ok, read by the results page's
    rules (workprec_page.load; pass 69: the plot took CRLF, h_s 0, a negative error on a failed point and a point
    twice, which the page refuses); Refused naming the file, line and column."""
    if os.path.exists(path) and not os.path.isfile(path):
        raise Refused(f"{path}: not a regular file")
    if not os.path.lexists(path):
        raise Refused(f"{path}: no such file")
    scenes = OrderedDict()
    for r in workprec_page.load(pathlib.Path(path)):
        if r["ok"]:
            curves = scenes.setdefault(r["scene"], OrderedDict())
            # an error of exactly 0 (a point equal to the reference) has no place on a log axis: drawn at 1e-16
            curves.setdefault(r["policy"], []).append((r["cpu_s_per_sim_s"], max(r["bore_err_max_rad"], 1e-16),
                                                       r["pareto"]))
    return scenes


def main():
    ap = argparse.ArgumentParser(allow_abbrev=False, description=__doc__.splitlines()[0])
    output_file.standard_flags(ap)
    # the repository's, not the working folder's (pass 69: run from elsewhere it named a missing out/ folder)
    ap.add_argument("csv", nargs="?", default=str(ROOT / "out" / "workprec" / "workprec.csv"))
    ap.add_argument("--out", default=None, help="PNG path (default: beside the CSV)")
    a = ap.parse_args()
    out = os.path.splitext(a.csv)[0] + ".png" if a.out is None else a.out  # --out '' is refused, not defaulted
    scenes = read(a.csv)  # the input first: a missing CSV is named as such, not by its PNG's folder
    check_before_writing([out], [a.csv], names=["--out"])
    check_figure_format(out)
    if not scenes:
        raise Refused(f"{a.csv}: no successful points to plot")
    n = len(scenes)
    cols = min(n, 2)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(6.5 * cols, 4.8 * rows), squeeze=False)
    for ax, (scene, curves) in zip(axes.flat, scenes.items()):
        for policy, pts in curves.items():  # in sweep order (h or tolerance decreasing)
            style = "s--" if policy.startswith("MuJoCo") else "o-"
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], style, ms=4, label=policy)
        front = sorted(p for pts in curves.values() for p in pts if p[2])
        if front:
            ax.loglog([p[0] for p in front], [p[1] for p in front], "k:", lw=1, label="Pareto front")
        for t in TARGETS:
            ax.axhline(t, color="grey", lw=0.6, ls="--")
        ax.set_title(scene)
        ax.set_xlabel("CPU time per simulated second [s/s] (median)")
        ax.set_ylabel("max boresight error [rad]")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.suptitle("gimbalsim work-precision: RK4 + contact sub-stepping vs Dormand-Prince reference")
    fig.tight_layout()
    savefig(fig, out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    sys.exit(run_script("plot_workprec", main, whole_set=True))
