#!/usr/bin/python3
"""Plot a hardware-in-the-loop bench run from its truth CSV.

The truth CSV is what `firmware_sim --truth-csv FILE` writes, or what
`gimbalsim_log2csv LOG` makes of the <PREFIX>GIMBAL_TRUTH channel of an
lcm-logger log (same columns, `name[unit]` header). One figure, four panels
against simulated time: truth pointing error (log scale), joint angles,
applied torques, fault flags (one row per FAULT_* bit).

Usage:
  /usr/bin/python3 tools/plot_bench.py truth.csv --out bench.png [--title TEXT]

Prints a short summary (rows, time span, pointing error at the end and its
maximum after --after seconds, ticks per fault flag). Needs numpy and
matplotlib (Debian: python3-numpy python3-matplotlib, for /usr/bin/python3).
"""
import argparse
import csv
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from output_file import savefig  # noqa: E402  (temporary + rename, tools/output_file.py)

FAULTS = [(1, "watchdog"), (2, "saturated"), (4, "cmd rejected"), (8, "plant fault"), (16, "lockstep timeout")]
NEEDED = ["sim_time[s]", "theta1[rad]", "theta2[rad]", "tau1[N m]", "tau2[N m]", "pointing_error[rad]", "faults[-]"]


def read(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        sys.exit(f"plot_bench: cannot read {path}: {e.strerror}")
    if not rows:
        sys.exit(f"plot_bench: {path} is empty")
    header, data = rows[0], rows[1:]
    missing = [c for c in NEEDED if c not in header]
    if missing:
        sys.exit(f"plot_bench: {path}: not a bench truth CSV, missing column(s) {', '.join(missing)}")
    if not data:
        sys.exit(f"plot_bench: {path}: no rows")
    cols = {}
    for c in NEEDED:
        i = header.index(c)
        try:
            cols[c] = np.array([float(r[i]) for r in data])
        except (ValueError, IndexError) as e:
            sys.exit(f"plot_bench: {path}: bad value in column {c}: {e}")
    return cols


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("truth", help="truth CSV (firmware_sim --truth-csv or gimbalsim_log2csv)")
    p.add_argument("--out", required=True, help="output image (.png, .pdf, .svg)")
    p.add_argument("--title", default="", help="figure title (default: the CSV path)")
    p.add_argument("--after", type=float, default=2.5, help="report the max pointing error after this time [s]")
    a = p.parse_args()
    c = read(a.truth)
    t = c["sim_time[s]"]
    err = c["pointing_error[rad]"]
    faults = c["faults[-]"].astype(np.int64)

    fig, ax = plt.subplots(4, 1, figsize=(9, 10), sharex=True,
                           gridspec_kw={"height_ratios": [3, 2, 2, 1.2]})
    ax[0].semilogy(t, np.maximum(err, 1e-12), lw=0.8)
    ax[0].set_ylabel("pointing error [rad]")
    ax[0].grid(True, which="both", alpha=0.3)
    ax[1].plot(t, c["theta1[rad]"], label="theta1 (azimuth)", lw=0.9)
    ax[1].plot(t, c["theta2[rad]"], label="theta2 (elevation)", lw=0.9)
    ax[1].set_ylabel("joint angle [rad]")
    ax[1].legend(loc="best", fontsize=8)
    ax[1].grid(True, alpha=0.3)
    ax[2].plot(t, c["tau1[N m]"], label="tau1", lw=0.7)
    ax[2].plot(t, c["tau2[N m]"], label="tau2", lw=0.7)
    ax[2].set_ylabel("applied torque [N m]")
    ax[2].legend(loc="best", fontsize=8)
    ax[2].grid(True, alpha=0.3)
    for row, (bit, name) in enumerate(FAULTS):
        on = (faults & bit) != 0
        ax[3].fill_between(t, row - 0.4, row + 0.4, where=on, step="post", alpha=0.8)
    ax[3].set_yticks(range(len(FAULTS)))
    ax[3].set_yticklabels([n for _, n in FAULTS], fontsize=7)
    ax[3].set_ylim(-0.6, len(FAULTS) - 0.4)
    ax[3].set_xlabel("simulated time [s]")
    ax[3].grid(True, axis="x", alpha=0.3)
    fig.suptitle(a.title or a.truth, fontsize=10)
    fig.tight_layout()
    savefig(fig, a.out, dpi=120)

    after = err[t >= a.after]
    print(f"plot_bench: {len(t)} rows, t = {t[0]:.3f} .. {t[-1]:.3f} s -> {a.out}")
    tail = f"max after {a.after:g} s {after.max():.3e} rad" if after.size else f"(run ends before {a.after:g} s)"
    print(f"  pointing error: end {err[-1]:.3e} rad, {tail}")
    print("  fault ticks: " + ", ".join(f"{name} {int(((faults & bit) != 0).sum())}" for bit, name in FAULTS))


if __name__ == "__main__":
    main()
