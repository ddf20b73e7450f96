"""One open-loop sample (runs on a worker): the scene's constant torques, and
the pointing error against the ideal-joint twin with the same parameters."""
import math

import numpy as np

import gimbalsim
from ._closed_sample import load_sample


def _bore_angles(a, b):
    """Angle [rad] between the boresight rows of two runs, row by row."""
    i = [gimbalsim.COLUMNS.index(c) for c in ("bore_x", "bore_y", "bore_z")]
    n = min(len(a), len(b))
    u, v = a[:n][:, i], b[:n][:, i]
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), np.einsum("ij,ij->i", u, v))


def run_sample(base, overrides, ideal_cache, series=False):
    """Sample's metrics: status and METRICS (dict), and `applied`: the
    dispersed keys as the loaded scene holds them (_provenance.applied). The ideal-joint run with
    the same parameters is the pointing reference (cached: it does not depend
    on the joint's parameters). With series, the run too, under "run"."""
    scene, _, loaded = load_sample(base, None, overrides)
    if scene is None:
        return {"status": loaded["status"]}  # an open loop's row has no reason column
    applied = loaded["applied"]  # as loaded, not as drawn
    run = gimbalsim.simulate(scene)
    ideal = scene.replace({"structure.joint1": "ideal", "structure.joint2": "ideal"})
    key = tuple(sorted(ideal.values().items()))
    if key not in ideal_cache:
        ideal_cache[key] = gimbalsim.simulate(ideal).rows
    err = _bore_angles(run.rows, ideal_cache[key])
    s = run.summary
    status = "ok" if run.ok else (s["stop"]["key"] or s["stop"]["step_status"].replace(" ", "_"))
    return {"status": status, "applied": applied, **({"run": run} if series else {}),
            "pointing_error_max": float(err.max()) if len(err) else math.nan,
            "pointing_error_final": float(err[-1]) if len(err) else math.nan,
            "peak_contact_force": s["peak_contact_force_N"],
            "peak_joint2_force": s["peak_joint2_force_N"],
            "impacts": s["impacts"],
            "continuous_contact_from": s["continuous_contact_from_s"],
            **joint_metrics(s)}


def joint_metrics(summary):
    """impacts_joint1/2 and max_tilt1/2 from a run summary's clearance_joints."""
    out = {}
    for j in (1, 2):
        o = summary.get("clearance_joints", {}).get(f"joint{j}", {})
        out[f"impacts_joint{j}"] = o.get("impacts", 0)
        out[f"max_tilt{j}"] = o.get("max_tilt_rad", 0.0)
    return out
