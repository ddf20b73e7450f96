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
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pages"))
import output_file  # noqa: E402  (add_version)
from output_file import Refused, check_before_writing, check_header, plain_number, run_script, savefig  # noqa: E402  (the package's one writer, tools/pages/output_file.py)
import numpy as np  # noqa: E402


SUMMARY_COLUMNS = ["run", "scene", "clearance_m", "status", "rms_track_rad", "peak_track_rad", "track_ticks"]
SUMMARY_NUMBERS = ["clearance_m", "rms_track_rad", "peak_track_rad", "track_ticks"]


def read_rows(path):
    """The CSV's rows (header first); Refused naming the file when it cannot be read."""
    if not os.path.isfile(path):
        raise Refused(f"{path}: " + ("not a regular file" if os.path.exists(path) else
                                     "not found (run gimbalsim_pointing_study --out DIR)"))
    try:
        with open(path, newline="") as f:
            return list(csv.reader(f))
    except OSError as e:
        raise Refused(f"cannot read {path}: {e.strerror}")
    except (csv.Error, UnicodeDecodeError) as e:
        raise Refused(f"{path}: not a CSV file ({e})")


def number(path, line, column, text):
    if text in ("", "nan"):  # no value (the CSV convention: a figure over a window not reached, a stopped run)
        return np.nan
    return plain_number(text, f"{path}:{line}: column {column}")


def read_series(path):
    rows = read_rows(path)
    if len(rows) < 2:
        raise Refused(f"{path}: no data rows")
    head = rows[0]
    check_header(head, path)
    cols = {h: [] for h in head}
    for line, r in enumerate(rows[1:], start=2):
        if len(r) != len(head):
            raise Refused(f"{path}:{line}: {len(r)} fields, the header has {len(head)}")
        for h, v in zip(head, r):
            cols[h].append(number(path, line, h, v))
    return head, {h: np.array(v) for h, v in cols.items()}


def read_summary(path):
    rows = read_rows(path)
    if not rows or any(c not in rows[0] for c in SUMMARY_COLUMNS):
        raise Refused(f"{path}: not the study's summary: needs columns {', '.join(SUMMARY_COLUMNS)}")
    check_header(rows[0], path)
    summary = [dict(zip(rows[0], r)) for r in rows[1:]]
    for line, (r, raw) in enumerate(zip(summary, rows[1:]), start=2):
        if len(raw) != len(rows[0]):
            raise Refused(f"{path}:{line}: {len(raw)} fields, the header has {len(rows[0])}")
        for c in SUMMARY_NUMBERS:
            r[c] = number(path, line, c, r[c])
    if not summary:
        raise Refused(f"{path}: no runs")
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
    output_file.add_version(p)
    p.add_argument("dir", nargs="?", default="out/pointing_study", help="the tool's --out directory")
    a = p.parse_args()
    if not os.path.isdir(a.dir):  # the study's folder is the input: said as such, not as an output's missing folder
        raise Refused(f"{a.dir}: " + ("not a folder" if os.path.exists(a.dir) else "no such folder") +
                      " (give gimbalsim_pointing_study's --out folder)")
    series, summary = os.path.join(a.dir, "pointing_error.csv"), os.path.join(a.dir, "summary.csv")
    outs = [os.path.join(a.dir, "pointing_error_vs_time.png"), os.path.join(a.dir, "pointing_error_vs_clearance.png")]
    check_before_writing(outs, [series, summary])
    head, cols = read_series(series)
    rows = read_summary(summary)
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
