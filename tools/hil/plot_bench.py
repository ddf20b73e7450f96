#!/usr/bin/python3
"""Plot a hardware-in-the-loop bench run from its truth CSV.

The truth CSV is what `firmware_sim --truth-csv FILE` writes, or what
`gimbalsim_log2csv LOG` makes of the <PREFIX>GIMBAL_TRUTH channel of an
lcm-logger log (same columns, `name_unit` header). One figure against
simulated time: truth pointing error (log scale), joint angles, applied
torques, firmware fault flags (one row per FAULT_* bit) and, when the run had
a fault schedule (firmware_sim --faults), the scheduled faults active at each
tick (column injected_faults: one row per fault seen).

Usage:
  /usr/bin/python3 tools/hil/plot_bench.py truth.csv --out bench.png [--title TEXT]

Prints a short summary (rows, time span, pointing error at the end and its
maximum after --after seconds, ticks per fault flag). Needs numpy and
matplotlib (Debian: python3-numpy python3-matplotlib, for /usr/bin/python3).
"""
import argparse
import io
import os
import re
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pages"))
import output_file  # noqa: E402  (standard_flags)
from output_file import (Refused, arg_decimal, check_as_written, check_before_writing, check_figure_format,  # noqa: E402
                         check_header, plain_number, run_script, savefig, underflowed)  # the package's one writer

FAULTS = [(1, "watchdog"), (2, "motor limit"), (4, "cmd rejected"), (8, "plant fault"), (16, "lockstep timeout")]
# Scheduled fault kinds in the order of FaultKind (firmware_sim/include/gimbalsim/firmware_sim/fault_schedule.hpp):
# kind k, axis a sets bit 2 k + a of injected_faults (kinds without an axis: bit 2 k).
FAULT_KINDS = ["encoder_dropout", "encoder_stuck", "encoder_bias", "encoder_noise", "status_delay", "status_drop",
               "command_delay", "command_drop", "torque_limit", "motor_failure", "star_tracker_outage",
               "gyro_bias_jump", "bearing_wear", "friction_rise", "tracker_outage", "tracker_bias", "tracker_dropout"]
AXIS_KINDS = {"encoder_dropout", "encoder_stuck", "encoder_bias", "encoder_noise", "torque_limit", "motor_failure"}


def injected_name(bit):
    kind = FAULT_KINDS[bit // 2] if bit // 2 < len(FAULT_KINDS) else f"bit {bit}"
    if kind in AXIS_KINDS:
        return f"{kind} {'el' if bit % 2 else 'az'}"
    return kind
NEEDED = ["sim_time_s", "theta1_rad", "theta2_rad", "tau1_Nm", "tau2_Nm", "pointing_error_rad", "faults"]


# A cell as the project's writer writes a number (shortest round-trip decimal), matched a whole line at a time
# (one regex a line, not Python a cell: a 2M-row file stays fast). At most 200 digits a run and a two-digit
# exponent, so that every cell it takes is finite and kept by the parse (|x| >= 1e-299). A line it does not take
# is read cell by cell by check_line (plain_number and the underflow rule of base/input underflow.hpp, as
# torque_replay reads it): refused, or taken (1e-150).
_CELL = rb"[+-]?(?:[0-9]{1,200}\.?[0-9]{0,200}|\.[0-9]{1,200})(?:[eE][+-]?[0-9]{1,2})?"
NOT_AS_WRITTEN = "not as firmware_sim writes a truth CSV"


def check_line(cells, header, where):
    """Refused naming `where` (file:line) and the column of the first cell of a data line that is not a plain
    finite decimal the parse kept (1e-400 reads as 0: it underflows a double), or of a wrong count of fields."""
    if len(cells) != len(header):
        raise Refused(f"{where}: {len(cells)} fields, the header has {len(header)}")
    for name, cell in zip(header, cells):
        text = cell.decode("utf-8", "replace")
        x = plain_number(text, f"{where}: column {name}")
        if underflowed(text, x):
            raise Refused(f"{where}: column {name}: {text!r} underflows a double")


def read(path):
    """The columns NEEDED (and injected_faults) of a truth CSV as arrays;
    Refused naming the file, line and column of what is wrong. Every cell of
    every column, plotted or not, is a plain finite decimal, and the file is
    as firmware_sim writes it (LF line ends, no byte-order mark): a cell that
    is not is no tick of the run (torque_replay refuses the same file)."""
    if os.path.exists(path) and not os.path.isfile(path):
        raise Refused(f"{path}: not a regular file")
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as e:
        raise Refused(f"cannot read {path}: {e.strerror}")
    if not raw:
        raise Refused(f"{path} is empty")
    check_as_written(raw, path, NOT_AS_WRITTEN)
    start = raw.find(b"\n") + 1 or len(raw)  # the first byte of line 2 (the text is scanned in place: 2M rows)
    try:
        header = raw[:start].rstrip(b"\n").decode("utf-8").split(",")
    except UnicodeDecodeError as e:
        raise Refused(f"{path}:1: not a CSV file ({e})")
    check_header(header, path)
    missing = [c for c in NEEDED if c not in header]
    if missing:
        raise Refused(f"{path}: not a bench truth CSV, missing column(s) {', '.join(missing)}")
    if start == len(raw):
        raise Refused(f"{path}: no rows")
    row = re.compile(rb"%s(?:,%s){%d}(?:\n|\Z)" % (_CELL, _CELL, len(header) - 1))
    at, line = start, 2  # the first byte of a line and its number
    while at < len(raw):
        taken = row.match(raw, at)
        if taken:
            at = taken.end()
        else:
            eol = raw.find(b"\n", at)
            eol = len(raw) if eol < 0 else eol
            check_line(raw[at:eol].split(b","), header, f"{path}:{line}")  # refused, or a line the pass left to it
            at = eol + 1
        line += 1
    wanted = NEEDED + [c for c in ("injected_faults", "seq") if c in header]
    table = np.loadtxt(io.BytesIO(raw), delimiter=",", comments=None, skiprows=1, dtype=float, ndmin=2,
                       usecols=[header.index(c) for c in wanted])
    cols = {c: table[:, j] for j, c in enumerate(wanted)}
    # every row's bit sets first (whole numbers, the frozen rows' too: the plant's stop is read from them)
    for c, bits in (("faults", 31), ("injected_faults", 2 * len(FAULT_KINDS))):
        if c in cols:
            bad = np.flatnonzero(~((cols[c] >= 0) & (cols[c] < 2**bits) & (cols[c] == np.floor(cols[c]))))
            if bad.size:
                raise Refused(f"{path}:{bad[0] + 2}: column {c}: {cols[c][bad[0]]:g} is not a set of fault bits")
    _check_every_tick_kept(cols, path)
    cols = _until_the_plant_stopped(cols)
    if (np.diff(cols["sim_time_s"]) <= 0).any():
        raise Refused(f"{path}:{int(np.argmax(np.diff(cols['sim_time_s']) <= 0)) + 3}: sim_time_s does not increase")
    neg = np.flatnonzero(cols["pointing_error_rad"] < 0)  # an angle's size: a log axis would hide it
    if neg.size:
        value = cols["pointing_error_rad"][neg[0]]
        raise Refused(f"{path}:{neg[0] + 2}: column pointing_error_rad: {value:g} is negative")
    return cols


def _check_every_tick_kept(cols, path):
    """A truth CSV holds every N-th tick (--truth-every N, N from its first two rows; a log from a recorder
    started late begins anywhere): seq steps by N on every row. A jump is a row cut out, and a plot over it
    would draw a line across ticks nobody saw (pass 70); Refused naming the line."""
    if "seq" not in cols:
        return
    seq = cols.pop("seq")
    not_ticks = np.flatnonzero((seq < 0) | (seq != np.floor(seq)))
    if not_ticks.size:
        raise Refused(f"{path}:{not_ticks[0] + 2}: column seq: {seq[not_ticks[0]]:g} is not a tick number")
    if len(seq) < 2:
        return
    step = np.diff(seq)
    bad = np.flatnonzero(step != step[0])
    if step[0] <= 0 or bad.size:
        k = int(bad[0]) + 1 if step[0] > 0 else 1
        raise Refused(f"{path}:{k + 2}: seq {seq[k]:.0f} after {seq[k - 1]:.0f}, where the rows before step by "
                      f"{step[0]:.0f}: ticks cut out or out of order ({NOT_AS_WRITTEN}, every N-th tick)")


PLANT_FAULT = 8  # gimbal_status_t.FAULT_PLANT_FAULT: the integration failed, the state frozen (latched)


def _until_the_plant_stopped(cols):
    """The rows up to a plant's stop: after it the firmware repeats the
    frozen state, its time included, with FAULT_PLANT_FAULT on every row
    (a stopped run, firmware_sim exit 3). Those repeats are no motion: left
    out, and cols["stopped_at"] says where. Anything else is left as read."""
    t = cols["sim_time_s"]
    flat = np.flatnonzero(np.diff(t) <= 0)
    if not flat.size:
        return cols
    k = flat[0] + 1  # the first repeat
    if (t[k:] == t[k - 1]).all() and ((cols["faults"][k:].astype(np.int64) & PLANT_FAULT) != 0).all():
        return {**{c: v[:k] for c, v in cols.items()}, "stopped_at": float(t[k - 1]), "frozen_rows": len(t) - k}
    return cols


def log_series(err):
    """The pointing error as drawn on the log axis and a note on what was left out ('' if nothing): an exact 0
    has no place on a log scale, so it is a gap and said to be one, never a point at an invented floor."""
    zeros = int((err == 0).sum())
    note = ""
    if zeros == err.size:
        note = "0 throughout: nothing drawn on the log axis"
    elif zeros:
        note = f"exactly 0 in {zeros} of {err.size} rows: gaps on the log axis"
    return np.where(err > 0, err, np.nan), note


def main():
    p = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    p.add_argument("truth", help="truth CSV (firmware_sim --truth-csv or gimbalsim_log2csv)")
    p.add_argument("--out", required=True, help="output image (.png, .pdf, .svg)")
    p.add_argument("--title", default="", help="figure title (default: the CSV path)")
    p.add_argument("--after", type=arg_decimal(0.0, 1e9), default=2.5,
                   help="report the max pointing error after this time [s], in [0, 1e9]")
    a = p.parse_args()
    check_before_writing([a.out], [a.truth], names=["--out"])
    check_figure_format(a.out)
    c = read(a.truth)
    t = c["sim_time_s"]
    err = c["pointing_error_rad"]
    faults = c["faults"].astype(np.int64)
    injected = c["injected_faults"].astype(np.int64) if "injected_faults" in c else np.zeros_like(faults)
    seen = [b for b in range(2 * len(FAULT_KINDS)) if ((injected >> b) & 1).any()]

    panels = 5 if seen else 4
    ratios = [3, 2, 2, 1.2] + ([0.3 * len(seen) + 0.6] if seen else [])
    fig, ax = plt.subplots(panels, 1, figsize=(9, 10 + (0.25 * len(seen) if seen else 0)), sharex=True,
                           gridspec_kw={"height_ratios": ratios})
    drawn, note = log_series(err)
    ax[0].set_yscale("log")
    if note:
        ax[0].text(0.5, 0.5, f"pointing error {note}", transform=ax[0].transAxes, ha="center", va="center")
    if np.isfinite(drawn).any():
        ax[0].plot(t, drawn, lw=0.8)
    else:  # an empty log axis's decades would be a scale of nothing
        ax[0].tick_params(axis="y", which="both", left=False, labelleft=False)
    ax[0].set_ylabel("pointing error [rad]")
    ax[0].grid(True, which="both", alpha=0.3)
    ax[1].plot(t, c["theta1_rad"], label="theta1 (azimuth)", lw=0.9)
    ax[1].plot(t, c["theta2_rad"], label="theta2 (elevation)", lw=0.9)
    ax[1].set_ylabel("joint angle [rad]")
    ax[1].legend(loc="best", fontsize=8)
    ax[1].grid(True, alpha=0.3)
    ax[2].plot(t, c["tau1_Nm"], label="tau1", lw=0.7)
    ax[2].plot(t, c["tau2_Nm"], label="tau2", lw=0.7)
    ax[2].set_ylabel("applied torque [N m]")
    ax[2].legend(loc="best", fontsize=8)
    ax[2].grid(True, alpha=0.3)
    for row, (bit, name) in enumerate(FAULTS):
        on = (faults & bit) != 0
        ax[3].fill_between(t, row - 0.4, row + 0.4, where=on, step="post", alpha=0.8)
    ax[3].set_yticks(range(len(FAULTS)))
    ax[3].set_yticklabels([n for _, n in FAULTS], fontsize=7)
    ax[3].set_ylim(-0.6, len(FAULTS) - 0.4)
    ax[3].set_ylabel("firmware")
    ax[3].grid(True, axis="x", alpha=0.3)
    if seen:
        for row, bit in enumerate(seen):
            on = ((injected >> bit) & 1) != 0
            ax[4].fill_between(t, row - 0.4, row + 0.4, where=on, step="post", alpha=0.8, color="tab:red")
        ax[4].set_yticks(range(len(seen)))
        ax[4].set_yticklabels([injected_name(b) for b in seen], fontsize=7)
        ax[4].set_ylim(-0.6, len(seen) - 0.4)
        ax[4].set_ylabel("scheduled")
        ax[4].grid(True, axis="x", alpha=0.3)
    if "stopped_at" in c:  # the frozen rows are left out: the stop is drawn, on the plant-fault row too
        for a_ in ax:
            a_.axvline(c["stopped_at"], color="C3", ls=":", lw=1)
        ax[3].plot([c["stopped_at"]], [[n for _, n in FAULTS].index("plant fault")], "x", color="C3", ms=8)
    ax[-1].set_xlabel("simulated time [s]")
    stop = f" (the plant stopped after {c['stopped_at']:g} s)" if "stopped_at" in c else ""
    fig.suptitle((a.title or a.truth) + stop, fontsize=10)
    fig.tight_layout()
    savefig(fig, a.out, inputs=[a.truth], dpi=120)

    # the last row the plant moved to; its stop itself falls in the step after (firmware_sim says when)
    stopped = "" if "stopped_at" not in c else \
        f"; the plant stopped after t = {c['stopped_at']:g} s, its last good state (the frozen rows after it left out)"
    print(f"plot_bench: {len(t)} rows, t = {t[0]:.3f} .. {t[-1]:.3f} s{stopped} -> {a.out}")
    # A figure over [after, inf) only if the last row lies past its start (docs/usage.md "Figures over a window").
    # sim_time_s sums the period tick by tick (0.6000000000000004 for tick 600): a row within a millionth of a
    # tick of the start is at it, so a run ending there has not passed it (pass 61: a figure over that row alone)
    tol = 1e-6 * (float(np.median(np.diff(t))) if len(t) > 1 else 0.0)
    if "stopped_at" in c and not c["stopped_at"] > 0.0:  # t = 0 alone is no run's figure (firmware_sim: n/a)
        print("  pointing error: n/a (the plant's first step failed: no step completed)")
        note = ""
    else:
        if t[-1] > a.after + tol:
            tail = f"max after {a.after:g} s {err[t >= a.after - tol].max():.3e} rad"
        else:
            tail = f"max after {a.after:g} s n/a (window [{a.after:g}, inf) s not reached: run ended at {t[-1]:g} s)"
        print(f"  pointing error: end {err[-1]:.3e} rad, {tail}")
    if note:
        print(f"  pointing error {note}")
    frozen = c.get("frozen_rows", 0)  # each carries FAULT_PLANT_FAULT: counted, though not drawn

    def ticks(bit):
        n = int(((faults & bit) != 0).sum())
        return f"{n + frozen} ({frozen} of them the frozen rows after the stop)" if bit == PLANT_FAULT and frozen \
            else str(n)
    print("  fault ticks: " + ", ".join(f"{name} {ticks(bit)}" for bit, name in FAULTS))
    if seen:
        print("  scheduled fault ticks: " + ", ".join(f"{injected_name(b)} {int(((injected >> b) & 1).sum())}" for b in seen))


if __name__ == "__main__":
    sys.exit(run_script("plot_bench", main, whole_set=True))
