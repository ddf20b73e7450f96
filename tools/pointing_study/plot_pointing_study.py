#!/usr/bin/python3
"""Figures of gimbalsim_pointing_study's output directory.

  pointing_error_vs_time.png       truth pointing error against time (log scale),
                                   the ideal joint and each clearance (with several
                                   clearance scenes or sensor sets: the ideal joint
                                   and each scene's largest clearance, perfect sensors)
  pointing_error_vs_clearance.png  RMS (solid) and peak (dotted) truth pointing error
                                   while tracking against the clearance, one line per
                                   scene and sensor set; the ideal joint as
                                   horizontal lines

Usage: /usr/bin/python3 tools/pointing_study/plot_pointing_study.py [DIR]  (default out/pointing_study)
"""
import argparse
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pages"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import output_file  # noqa: E402  (standard_flags)
from output_file import Refused, check_as_written, check_before_writing, check_header, run_script, savefig  # noqa: E402  (the package's one writer, tools/pages/output_file.py)
import numpy as np  # noqa: E402
import pointing_page  # noqa: E402  (the summary's one reader: its writer's rules)
import results_page  # noqa: E402


def read_series(folder):
    """pointing_error.csv of the study in folder: t_s and each run's error [rad], as the study writes them (LF
    lines, no byte-order mark, t_s >= 0 increasing, an error in [0, pi], never nan nor -0, or empty from where
    that run had ended to the last line); Refused naming file, line and column."""
    path = os.path.join(folder, "pointing_error.csv")
    raw = results_page.run_file(folder, "pointing_error.csv").encode()
    check_as_written(raw, path, "not as gimbalsim_pointing_study writes it")
    rows = [line.split(",") for line in raw.decode().split("\n")[:-1]]
    if len(rows) < 2:
        raise Refused(f"{path}: no data rows")
    head = rows[0]
    check_header(head, path)
    # (pass 81) every error a tick gave, no nan: an ended run's cells are empty, from its end to the last line
    error = pointing_page.study_csv.Column(0.0, math.pi)
    rules = {h: (pointing_page.study_csv.Column(0.0) if j == 0 else error) for j, h in enumerate(head)}
    cols, ended = {h: [] for h in head}, {}
    for line, r in enumerate(rows[1:], start=2):
        if len(r) != len(head):
            raise Refused(f"{path}:{line}: {len(r)} fields, the header has {len(head)}")
        for j, (h, v) in enumerate(zip(head, r)):
            if v == "" and j > 0:
                ended.setdefault(h, line)
                cols[h].append(np.nan)
                continue
            if h in ended:
                raise Refused(f"{path}:{line}: column {h}: a value after the run's end (its empty cell on line "
                              f"{ended[h]}): not as gimbalsim_pointing_study writes it")
            cols[h].append(rules[h].read(v, f"{path}:{line}: column {h}"))
    t = np.array(cols[head[0]])
    if (np.diff(t) <= 0).any():
        line = int(np.argmax(np.diff(t) <= 0)) + 3
        raise Refused(f"{path}:{line}: column {head[0]}: does not increase")
    return head, {h: np.array(v) for h, v in cols.items()}


def read_summary(folder):
    """summary.csv of the study in folder, by pointing_page's rules (the page's reader); Refused when empty."""
    summary = pointing_page.read_summary(folder)
    if not summary:
        raise Refused(f"{os.path.join(folder, 'summary.csv')}: no runs")
    return summary


def error_column(run):
    """The time series' column of a run (gimbalsim_pointing_study): c=0.25mm -> error_c0p25mm_rad."""
    return "error_" + run.replace(".", "p").replace("=", "") + "_rad"


def shown_in_time_plot(summary):
    """Runs drawn against time: all of one scene and sensor set; else the ideal
    joint and each scene's largest clearance, with the first sensor set the
    study ran (perfect, or perfect except a --scene-set sensor key)."""
    groups = {(r["scene"], r.get("sensors", "perfect")) for r in summary if r["clearance_m"] > 0}
    if len(groups) <= 1 and len({r.get("sensors", "perfect") for r in summary}) <= 1:
        return [r["run"] for r in summary]
    first = summary[0].get("sensors", "perfect") if summary else "perfect"
    perfect = [r for r in summary if r.get("sensors", "perfect") == first]
    shown = [r["run"] for r in perfect if r["clearance_m"] == 0]
    for scene in dict.fromkeys(r["scene"] for r in perfect if r["clearance_m"] > 0):
        runs = [r for r in perfect if r["scene"] == scene]
        shown.append(max(runs, key=lambda r: r["clearance_m"])["run"])
    return shown


def plot_time(head, cols, summary, out):
    fig, ax = plt.subplots(figsize=(9, 5))
    t = cols[head[0]]
    for run in shown_in_time_plot(summary):
        name = error_column(run)
        if name not in cols:
            continue
        y = np.where(cols[name] > 0, cols[name], np.nan)
        ideal = run.startswith("ideal")
        ax.semilogy(t, y, lw=1.6 if ideal else 0.9, color="k" if ideal else None, label=run)
    ideal = [r for r in summary if r["clearance_m"] == 0]
    if ideal and ideal[0]["track_ticks"] > 0:  # NaN (not recorded) is no line
        n = len(t) - int(ideal[0]["track_ticks"])
        if 0 <= n < len(t):
            ax.axvline(t[n], color="0.5", ls=":", lw=1)
            ax.text(t[n], ax.get_ylim()[1], " tracking", va="top", fontsize=8, color="0.4")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("truth pointing error [rad]")
    ax.set_title("Closed-loop truth pointing error: ideal joint and bearing clearance")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    savefig(fig, out, dpi=120)
    plt.close(fig)


def plot_clearance(summary, out):
    fig, ax = plt.subplots(figsize=(11, 5.5))
    ok = [r for r in summary if r["status"] == "ok"]
    groups = dict.fromkeys((r["scene"], r.get("sensors", "perfect")) for r in ok
                           if r["clearance_m"] > 0 and np.isfinite(r["rms_track_rad"]))
    scenes = list(dict.fromkeys(scene for scene, _ in groups))
    for scene, sensors in groups:  # a colour per scene, a marker per sensor set
        runs = sorted((r for r in ok if r["scene"] == scene and r.get("sensors", "perfect") == sensors
                       and r["clearance_m"] > 0), key=lambda r: r["clearance_m"])
        c_mm = [1e3 * r["clearance_m"] for r in runs]
        color, marker = f"C{scenes.index(scene) % 10}", "o" if sensors == "perfect" else "s"
        ax.semilogy(c_mm, [r["rms_track_rad"] for r in runs], marker + "-", color=color,
                    label=f"{scene}, {sensors} sensors: RMS (peak dotted)")
        ax.semilogy(c_mm, [r["peak_track_rad"] for r in runs], marker + ":", color=color, lw=0.8)
    for r in (r for r in ok if r["clearance_m"] == 0):
        ax.axhline(r["rms_track_rad"], color="k", ls="--" if r.get("sensors", "perfect") == "perfect" else "-.",
                   lw=1, label=f"ideal joint, {r.get('sensors', 'perfect')} sensors: RMS")
    if not groups:  # only the ideal joint's lines: said on the axes, not left as a plot that looks whole (pass 53)
        ax.text(0.5, 0.5, "no clearance run has a figure while tracking", transform=ax.transAxes, ha="center",
                va="center", fontsize=11, color="C3")
    stopped = [r for r in summary if r["status"] != "ok"]
    if stopped:
        ax.set_title("stopped (not plotted): " + ", ".join(f"{r['run']} ({r['status']})" for r in stopped), fontsize=8)
    ax.set_xlabel("radial clearance [mm]")
    ax.set_ylabel("truth pointing error while tracking [rad]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    savefig(fig, out, dpi=120)
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    p.add_argument("dir", nargs="?", default="out/pointing_study", help="the tool's --out directory")
    p.add_argument("--check", action="store_true",
                   help="check the figures' names alone (before the study runs) and write nothing")
    a = p.parse_args()
    if not os.path.isdir(a.dir):  # the study's folder is the input: said as such, not as an output's missing folder
        raise Refused(f"{a.dir}: " + ("not a folder" if os.path.exists(a.dir) else "no such folder") +
                      " (give gimbalsim_pointing_study's --out folder)")
    series, summary = os.path.join(a.dir, "pointing_error.csv"), os.path.join(a.dir, "summary.csv")
    outs = [os.path.join(a.dir, "pointing_error_vs_time.png"), os.path.join(a.dir, "pointing_error_vs_clearance.png")]
    check_before_writing(outs, [series, summary])
    if a.check:
        return 0
    head, cols = read_series(a.dir)
    rows = read_summary(a.dir)
    # Both figures are the tracking's: a study none of whose runs has a figure there draws two empty axes.
    if not any(r["status"] == "ok" and np.isfinite(r["rms_track_rad"]) for r in rows):
        why = next((r["track_reason"] for r in rows if r.get("track_reason")), "no run ended ok")
        raise Refused(f"{summary}: no run has a figure while tracking ({why}): nothing to plot")
    if not any(np.any(cols.get(error_column(run), np.array([])) > 0) for run in shown_in_time_plot(rows)):
        raise Refused(f"{series}: no run drawn against time has a pointing error above 0: nothing to plot")
    plot_time(head, cols, rows, outs[0])
    plot_clearance(rows, outs[1])
    print("wrote " + ", ".join(outs))


if __name__ == "__main__":
    sys.exit(run_script("plot_pointing_study", main, whole_set=True))
