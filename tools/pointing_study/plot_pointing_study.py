#!/usr/bin/python3
"""Figures of gimbalsim_pointing_study's output directory.

  pointing_error_vs_time.png       truth pointing error against time (log scale),
                                   the ideal joint and each clearance
  pointing_error_vs_clearance.png  peak and RMS truth pointing error while tracking
                                   against the clearance; the ideal joint as
                                   horizontal lines

Usage: /usr/bin/python3 tools/pointing_study/plot_pointing_study.py [DIR]  (default out/pointing_study)
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from output_file import savefig  # noqa: E402  (temporary + rename, tools/output_file.py)
import numpy as np  # noqa: E402


def read_series(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        sys.exit(f"plot_pointing_study: {path}: no data rows")
    head = rows[0]
    cols = {h: [] for h in head}
    for r in rows[1:]:
        for h, v in zip(head, r):
            cols[h].append(float(v) if v else np.nan)
    return head, {h: np.array(v) for h, v in cols.items()}


def read_summary(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def plot_time(head, cols, summary, out):
    fig, ax = plt.subplots(figsize=(9, 5))
    t = cols[head[0]]
    for name in head[1:]:
        y = np.where(cols[name] > 0, cols[name], np.nan)
        label = name.removeprefix("error_").removesuffix("_rad")  # error_c0p25mm_rad -> c0p25mm
        ideal = label == "ideal"
        ax.semilogy(t, y, lw=1.6 if ideal else 0.9, color="k" if ideal else None, label=label)
    ideal = [r for r in summary if r["run"] == "ideal"]
    if ideal and int(ideal[0]["track_ticks"]) > 0:
        n = len(t) - int(ideal[0]["track_ticks"])
        if 0 <= n < len(t):
            ax.axvline(t[n], color="0.5", ls=":", lw=1)
            ax.text(t[n], ax.get_ylim()[1], " tracking", va="top", fontsize=8, color="0.4")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("truth pointing error [rad]")
    ax.set_title("Closed-loop truth pointing error: ideal joint and elevation-joint clearances")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    savefig(fig, out, dpi=120)
    plt.close(fig)


def plot_clearance(summary, out):
    ideal = [r for r in summary if r["run"] == "ideal"]
    runs = sorted((r for r in summary if r["run"] != "ideal" and r["status"] == "ok"),
                  key=lambda r: float(r["clearance_m"]))
    fig, ax = plt.subplots(figsize=(7, 5))
    c_mm = [1e3 * float(r["clearance_m"]) for r in runs]
    for key, label, color in (("peak_track_rad", "peak while tracking", "C0"), ("rms_track_rad", "RMS while tracking", "C1")):
        ax.plot(c_mm, [float(r[key]) for r in runs], "o-", color=color, label=label)
        if ideal:
            ax.axhline(float(ideal[0][key]), color=color, ls="--", lw=1, label=label + ", ideal joint")
    stopped = [r for r in summary if r["status"] != "ok"]
    if stopped:
        ax.set_title("stopped (not plotted): " + ", ".join(f"{r['run']} ({r['status']})" for r in stopped), fontsize=8)
    ax.set_xlabel("radial clearance [mm]")
    ax.set_ylabel("truth pointing error [rad]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    savefig(fig, out, dpi=120)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dir", nargs="?", default="out/pointing_study", help="the tool's --out directory")
    a = p.parse_args()
    series, summary = os.path.join(a.dir, "pointing_error.csv"), os.path.join(a.dir, "summary.csv")
    for path in (series, summary):
        if not os.path.isfile(path):
            sys.exit(f"plot_pointing_study: {path}: not found (run gimbalsim_pointing_study --out {a.dir})")
    head, cols = read_series(series)
    rows = read_summary(summary)
    outs = [os.path.join(a.dir, "pointing_error_vs_time.png"), os.path.join(a.dir, "pointing_error_vs_clearance.png")]
    plot_time(head, cols, rows, outs[0])
    plot_clearance(rows, outs[1])
    print("wrote " + ", ".join(outs))


if __name__ == "__main__":
    main()
