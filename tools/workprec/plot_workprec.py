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
import csv
import os
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pages"))
import output_file  # noqa: E402  (add_version)
from output_file import (Refused, check_before_writing, check_figure_format, check_header, plain_number,  # noqa: E402
                         run_script, savefig)  # the package's one writer

TARGETS = (1e-3, 1e-6, 1e-9)  # [rad], the targets the tool reports


COLUMNS = ("ok", "bore_err_max_rad", "cpu_s_per_sim_s", "scene", "policy", "pareto")


def read(path):
    """{scene: {policy: [(cpu, error, on the front)]}} of the successful points;
    Refused naming the file and line of a row that is not the tool's."""
    if not os.path.isfile(path):
        raise Refused(f"{path}: " + ("not a regular file" if os.path.exists(path) else "no such file"))
    scenes = OrderedDict()
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            if reader.fieldnames is None or any(c not in reader.fieldnames for c in COLUMNS):
                raise Refused(f"{path}: not gimbalsim_workprec's CSV: needs columns {', '.join(COLUMNS)}")
            check_header(reader.fieldnames, path)
            for r in reader:
                where = f"{path}:{reader.line_num}"
                if None in r or None in r.values():
                    raise Refused(f"{where}: the row has not the header's {len(reader.fieldnames)} fields")
                if r["ok"] not in ("0", "1"):
                    raise Refused(f"{where}: column ok: expected 0 or 1, got {r['ok']!r}")
                if r["ok"] != "1":
                    continue
                err = plain_number(r["bore_err_max_rad"], f"{where}: column bore_err_max_rad")
                cpu = plain_number(r["cpu_s_per_sim_s"], f"{where}: column cpu_s_per_sim_s")
                # below 0 is no time or error gimbalsim_workprec writes (pass 68's follow-up: a -1 was skipped)
                for name, x in (("cpu_s_per_sim_s", cpu), ("bore_err_max_rad", err)):
                    if x < 0:
                        raise Refused(f"{where}: column {name}: {x!r} is below 0")
                if cpu == 0:  # a point too fast for the clock has no place on a log axis
                    continue
                curves = scenes.setdefault(r["scene"], OrderedDict())
                curves.setdefault(r["policy"], []).append((cpu, max(err, 1e-16), r["pareto"] == "1"))
    except OSError as e:
        raise Refused(f"cannot read {path}: {e.strerror}")
    except (csv.Error, UnicodeDecodeError) as e:
        raise Refused(f"{path}: not a CSV file ({e})")
    return scenes


def main():
    ap = argparse.ArgumentParser(allow_abbrev=False, description=__doc__.splitlines()[0])
    output_file.add_version(ap)
    # the repository's, not the working folder's (pass 69: run from elsewhere it named a missing out/ folder)
    default_csv = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "out", "workprec", "workprec.csv")
    ap.add_argument("csv", nargs="?", default=os.path.normpath(default_csv))
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
