"""The two runs plot_paper.py compares: the CSV columns it needs (read by
name), the summaries, their common time grid, and the derived signals
(boresight angle, contact starts). No plotting here.
"""
import io
import json
import math
import os
import re
import sys
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pages"))
from output_file import Refused, check_as_written, check_header, plain_number  # noqa: E402  (the shared readers)

# Columns this script reads (the simulator writes more; extra ones are ignored).
REQUIRED = [
    "t_s",
    "base_x_m", "base_y_m", "base_z_m",
    "base_vx_m_per_s", "base_vy_m_per_s", "base_vz_m_per_s",
    "base_ax_m_per_s2", "base_ay_m_per_s2", "base_az_m_per_s2",
    "base_roll_rad", "base_pitch_rad", "base_yaw_rad",
    "base_wx_rad_per_s", "base_wy_rad_per_s", "base_wz_rad_per_s",
    "base_dwx_rad_per_s2", "base_dwy_rad_per_s2", "base_dwz_rad_per_s2",
    "theta1_rad", "theta2_rad", "dtheta1_rad_per_s", "dtheta2_rad_per_s", "ddtheta1_rad_per_s2", "ddtheta2_rad_per_s2",
    "ecc2_x_m", "ecc2_y_m", "ecc2_m", "delta2_m", "fn2_N", "joint2_force_N",
    "bore_x", "bore_y", "bore_z",
]

class InputError(Exception):
    pass


# ----------------------------------------------------------------------------
# Input
# ----------------------------------------------------------------------------
# A cell as the simulator writes a number, matched a whole line at a time (one regex a line, not Python a cell: a
# 100k-row file stays fast); at most a two-digit exponent, so every cell it takes is finite. A line it does not
# take is read cell by cell (plain_number) to name the first bad cell.
_CELL = rb"[+-]?(?:[0-9]{1,200}\.?[0-9]{0,200}|\.[0-9]{1,200})(?:[eE][+-]?[0-9]{1,2})?"
NOT_AS_WRITTEN = "not as gimbalsim simulate writes a CSV"


def first_bad_cell(raw, start, header, path):
    """Refused naming file:line, the column and the cell of the first data cell that is not a plain finite
    decimal, or the line with a wrong count of fields (numpy only says that something failed, not where)."""
    row = re.compile(rb"%s(?:,%s){%d}(?:\n|\Z)" % (_CELL, _CELL, len(header) - 1))
    at, line = start, 2  # the first byte of a line and its number
    while at < len(raw):
        taken = row.match(raw, at)
        eol = taken.end() if taken else (raw.find(b"\n", at) + 1 or len(raw) + 1)
        if not taken:
            cells = raw[at:eol - 1].split(b",")
            if len(cells) != len(header):
                raise Refused(f"{path}:{line}: not a table of numbers: {len(cells)} fields, the header has {len(header)}")
            for name, cell in zip(header, cells):
                plain_number(cell.decode("utf-8", "replace"), f"{path}:{line}: column {name}")
        at, line = eol, line + 1


def load_csv(path):
    """Return {column name: float array}, checked for the REQUIRED columns; every cell a plain finite decimal.
    InputError names the file and, for a cell, its line, column and text (as plot_bench's refusals do)."""
    try:
        return _load_csv(path)
    except Refused as e:  # the shared readers' refusals, as this module's callers expect them
        raise InputError(str(e)) from None


def _load_csv(path):
    if not os.path.isfile(path):
        raise InputError(f"{path}: " + ("not a regular file" if os.path.exists(path) else "no such file"))
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as e:
        raise InputError(f"cannot read {path}: {e.strerror}")
    if not raw.strip():
        raise InputError(f"{path}: empty file (no CSV header)")
    check_as_written(raw, path, NOT_AS_WRITTEN)
    start = raw.find(b"\n") + 1 or len(raw)  # the first byte of line 2
    try:
        header = [h.strip() for h in raw[:start].rstrip(b"\n").decode("utf-8").split(",")]
    except UnicodeDecodeError as e:
        raise InputError(f"{path}:1: not a CSV file ({e})")
    check_header(header, path)
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise InputError(f"{path}: missing column(s) {', '.join(repr(m) for m in missing)} "
                         f"(header has: {','.join(header)})")
    # numpy reads the table; only when it fails or takes a non-finite value ('nan', '1e999') is the text
    # scanned for the first bad cell, so a good file costs one parse.
    data = None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an empty table is said below, not warned about
            data = np.loadtxt(io.BytesIO(raw), delimiter=",", comments=None, skiprows=1, dtype=float, ndmin=2)
    except (ValueError, UnicodeDecodeError):
        pass
    if data is None or (data.size and (data.shape[1] != len(header) or not np.isfinite(data).all())):
        first_bad_cell(raw, start, header, path)
        raise InputError(f"{path}: not a table of numbers")  # numpy refused what the scan took
    if data.size == 0 or data.shape[0] < 2:
        raise InputError(f"{path}: fewer than 2 data rows")
    cols = {name: data[:, k] for k, name in enumerate(header)}
    if np.any(np.diff(cols["t_s"]) <= 0):
        raise InputError(f"{path}: column 't_s' is not strictly increasing")
    return cols


def load_summary(path):
    if path is None:
        return {}
    if not os.path.isfile(path):
        raise InputError(f"{path}: " + ("not a regular file" if os.path.exists(path) else "no such file"))
    def not_json(constant):  # Python's json takes NaN and Infinity; gimbalsim writes a non-finite figure as null
        raise InputError(f"{path}: holds {constant}, which is not JSON: not a run's summary as gimbalsim writes it "
                         "(a figure it has not is null)")
    try:
        with open(path) as f:
            summary = json.load(f, parse_constant=not_json)
    except OSError as e:
        raise InputError(f"cannot read {path}: {e.strerror}")
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise InputError(f"{path}: not valid JSON ({e})")
    except RecursionError:
        raise InputError(f"{path}: nested too deeply")
    if not isinstance(summary, dict):
        raise InputError(f"{path}: not a run's summary (a JSON object)")
    return summary


def joint2_in_csv(cols):
    """Joint 2's kind as a run's CSV shows it: 'ideal' when ecc - delta (the clearance) is 0 throughout,
    'spatial' with a tilt2_rad column, else 'planar'."""
    if not np.max(cols["ecc2_m"] - cols["delta2_m"]) > 0.0:
        return "ideal"
    return "spatial" if "tilt2_rad" in cols else "planar"


def joint2_in_summary(summary):
    """Joint 2's kind as a run's summary records it (clearance_joints lists a joint with clearance, never an
    ideal one), or None for a summary that is not gimbalsim's (no variant)."""
    if "variant" not in summary:
        return None
    joints = summary.get("clearance_joints")
    j2 = joints.get("joint2") if isinstance(joints, dict) else None
    return "ideal" if j2 is None else str(j2.get("kind") if isinstance(j2, dict) else j2)


def check_joint2(flag, path, cols, summary_flag, summary_path, summary, wanted):
    """Refuses (InputError naming the flag) a run given where another belongs: its CSV's joint 2 must be one
    of wanted, and its summary, when given, must record the same joint 2 (not the other run's summary)."""
    kind, gap = joint2_in_csv(cols), float(np.max(cols["ecc2_m"] - cols["delta2_m"]))
    if kind not in wanted:
        takes = {("ideal",): "an ideal joint 2", ("spatial",): "a spatial joint 2"}.get(tuple(wanted),
                                                                                      "a clearance joint 2")
        if kind == "ideal":
            why = "joint 2 has no clearance (ecc - delta is 0 m throughout): is it the ideal run?"
        elif wanted == ["spatial"]:
            why = "joint 2 has planar clearance (no tilt2_rad column): is it the clearance run?"
        else:
            why = f"joint 2 has {kind} clearance (ecc - delta up to {gap:g} m): is it the clearance run?"
        raise InputError(f"{flag} {path}: {why} {flag} takes the run of {takes}")
    recorded = joint2_in_summary(summary) if summary_path else None
    if recorded is not None and recorded != kind:
        raise InputError(f"{summary_flag} {summary_path}: its run ({summary.get('name')!r}) has joint 2 {recorded}, "
                         f"the run of {flag} {path} has joint 2 {kind}: is it another run's summary?")


# The summary's figures the page reads, each with what it must be (a summary not as gimbalsim writes it is refused
# at its key: pass 68 printed a peak contact force of -5 N, and one at t = 1e308 s of a 0.5 s run).
SUMMARY_FIGURES = {"clearance_m": "length", "continuous_contact_from_s": "time", "impacts": "count",
                   "peak_contact_force_N": "force", "t_peak_contact_force_s": "time",
                   "peak_joint2_force_N": "force", "t_peak_joint2_force_s": "time"}


def check_summary_is_the_runs(flag, path, summary, cols):
    """Refuses (InputError naming the flag and file) a summary of another run than its CSV (cols): its row
    count, or its final joint angles and base position where the CSV's last row is at its final time (pass 69)."""
    if not path:
        return
    rows = summary.get("rows")
    if isinstance(rows, int) and not isinstance(rows, bool) and rows != len(cols["t_s"]):
        raise InputError(f"{flag} {path}: rows = {rows}, its CSV has {len(cols['t_s'])}: another run's summary")
    final = summary.get("final_state")
    q = final.get("q") if isinstance(final, dict) else None
    if isinstance(q, dict) and final.get("t") == float(cols["t_s"][-1]):
        for key, column in (("theta1", "theta1_rad"), ("theta2", "theta2_rad"), ("base_x", "base_x_m")):
            if isinstance(q.get(key), float) and q[key] != float(cols[column][-1]):
                raise InputError(f"{flag} {path}: final_state.q.{key} = {q[key]!r}, its CSV's last {column} "
                                 f"{float(cols[column][-1])!r}: another run's summary")


def check_summary_figures(flag, path, summary, cols):
    """Refuses (InputError naming the flag, file and key) a figure of
    SUMMARY_FIGURES that is not a finite number or null, a negative force,
    length or count, or a time outside the run's [0, end] (cols: its CSV)."""
    if not path:
        return
    end = max(float(cols["t_s"][-1]), 0.0)
    final = summary.get("final_state")
    final_t = final.get("t") if isinstance(final, dict) else None
    if isinstance(final_t, (int, float)) and not isinstance(final_t, bool):
        end = max(end, float(final_t))  # a last output row before the end: the peak may lie after it
    for key, kind in SUMMARY_FIGURES.items():
        x = summary.get(key)
        if x is None:
            continue
        where = f"{flag} {path}: {key} = {x!r}"
        if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
            raise InputError(f"{where}: not a finite number (gimbalsim writes a number, or null when it has none)")
        if kind == "count" and x != int(x):
            raise InputError(f"{where}: not a whole number")
        if x < 0.0:
            raise InputError(f"{where}: a {kind} below 0")
        if kind == "time" and x > end * (1.0 + 1e-9):
            raise InputError(f"{where}: after the run's end at {end:g} s (is it another run's summary?)")


def summary_number(summary, *keys):
    """First finite number found under any of the (possibly dotted) keys."""
    for key in keys:
        node = summary
        for part in key.split("."):
            node = node.get(part) if isinstance(node, dict) else None
        if isinstance(node, (int, float)) and not isinstance(node, bool) and math.isfinite(node):
            return float(node)
    return None


def common_grid(ideal, clear):
    """Return (t, clearance columns on that grid, note). The ideal grid is the
    reference; the clearance run is linearly interpolated onto it if needed."""
    ti, tc = ideal["t_s"], clear["t_s"]
    tol = 1e-9 * max(1.0, abs(ti[-1]))
    if ti.shape == tc.shape and np.allclose(ti, tc, rtol=0.0, atol=tol):
        return ideal, clear, None
    lo, hi = max(ti[0], tc[0]), min(ti[-1], tc[-1])
    keep = (ti >= lo - tol) & (ti <= hi + tol)
    if keep.sum() < 2:
        raise InputError("the two runs do not overlap in time "
                         f"(ideal {ti[0]:g}..{ti[-1]:g} s, clearance {tc[0]:g}..{tc[-1]:g} s)")
    ideal_c = {k: v[keep] for k, v in ideal.items()}
    t = ideal_c["t_s"]
    clear_i = {k: np.interp(t, tc, v) for k, v in clear.items()}
    clear_i["t_s"] = t.copy()
    # Interpolated unit vectors are a little short: renormalise the boresight.
    b = np.stack([clear_i["bore_x"], clear_i["bore_y"], clear_i["bore_z"]], axis=1)
    b /= np.linalg.norm(b, axis=1, keepdims=True)
    clear_i["bore_x"], clear_i["bore_y"], clear_i["bore_z"] = b.T
    note = (f"NOTE: the t grids differ (ideal {len(ti)} rows, clearance {len(tc)} rows); "
            f"the clearance run was linearly interpolated onto the ideal grid over "
            f"{t[0]:g}..{t[-1]:g} s for differences and pointing error "
            f"(single-run panels use each run's own samples).")
    return ideal_c, clear_i, note


# ----------------------------------------------------------------------------
# Helpers
# ----------------------------------------------------------------------------
def wrap_pi(a):
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def boresight(cols):
    return np.stack([cols["bore_x"], cols["bore_y"], cols["bore_z"]], axis=1)


def angle_between(a, b):
    """Angle between unit-vector rows, robust near 0 and pi: atan2(|a x b|, a.b)."""
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.sum(a * b, axis=1))


def contact_starts(cols):
    """Times (CSV samples) at which delta goes from <= 0 to > 0."""
    inside = cols["delta2_m"] > 0.0
    k = np.flatnonzero(~inside[:-1] & inside[1:]) + 1
    return cols["t_s"][k]


def continuous_contact_from(cols):
    """CSV estimate of the start of the final, unbroken contact (None if the run
    does not end in contact or never separated after a first impact)."""
    inside = cols["delta2_m"] > 0.0
    if not inside[-1] or inside.all():
        return None
    last_out = int(np.flatnonzero(~inside)[-1])
    return float(cols["t_s"][last_out + 1])


if __name__ == "__main__":  # (pass 79) run alone it took any arguments, did nothing and exited 0
    print("paper_data.py: error: a module of tools/paper/plot_paper.py, not a program: "
          "run plot_paper.py, which reads the runs through it", file=sys.stderr)
    sys.exit(2)
