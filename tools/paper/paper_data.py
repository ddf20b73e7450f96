"""The two runs plot_paper.py compares: the CSV columns it needs (read by
name), the summaries, their common time grid, and the derived signals
(boresight angle, contact starts). No plotting here.
"""
import csv
import json
import math
import os

import numpy as np

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
def load_csv(path):
    """Return {column name: float array}, checked for the REQUIRED columns."""
    if not os.path.isfile(path):
        raise InputError(f"{path}: " + ("not a regular file" if os.path.exists(path) else "no such file"))
    try:
        with open(path, newline="") as f:
            header = next(csv.reader(f), None)
    except OSError as e:
        raise InputError(f"cannot read {path}: {e.strerror}")
    except (csv.Error, UnicodeDecodeError) as e:
        raise InputError(f"{path}: not a CSV file ({e})")
    if not header:
        raise InputError(f"{path}: empty file (no CSV header)")
    header = [h.strip() for h in header]
    repeated = sorted({h for h in header if header.count(h) > 1})
    if repeated:
        raise InputError(f"{path}:1: column {repeated[0]} appears twice")
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise InputError(f"{path}: missing column(s) {', '.join(repr(m) for m in missing)} "
                         f"(header has: {','.join(header)})")
    try:
        data = np.genfromtxt(path, delimiter=",", skip_header=1, dtype=float, ndmin=2)
    except (ValueError, UnicodeDecodeError) as e:  # rows of unequal length, bytes that are not text
        raise InputError(f"{path}: not a table of numbers ({str(e).strip().splitlines()[-1]})")
    if data.size == 0 or data.shape[0] < 2:
        raise InputError(f"{path}: fewer than 2 data rows")
    if data.shape[1] != len(header):
        raise InputError(f"{path}: {data.shape[1]} values per row but {len(header)} header names")
    cols = {name: data[:, k] for k, name in enumerate(header)}
    for name in REQUIRED:
        if not np.all(np.isfinite(cols[name])):
            bad = int(np.argmax(~np.isfinite(cols[name])))
            raise InputError(f"{path}: column {name!r} has a non-finite value at data row {bad + 1}")
    if np.any(np.diff(cols["t_s"]) <= 0):
        raise InputError(f"{path}: column 't_s' is not strictly increasing")
    return cols


def load_summary(path):
    if path is None:
        return {}
    if not os.path.isfile(path):
        raise InputError(f"{path}: " + ("not a regular file" if os.path.exists(path) else "no such file"))
    try:
        with open(path) as f:
            summary = json.load(f)
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
