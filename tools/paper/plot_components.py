"""Figs 8-16 of the main job (tools/paper/plot_paper.py): one row per component,
ideal | clearance | clearance - ideal, with SI prefixes chosen per panel."""
import sys
import math

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from paper_data import wrap_pi  # noqa: E402

C_IDEAL = "tab:blue"
C_CLEAR = "tab:red"
C_DIFF = "tab:purple"


_PREFIX = [(1.0, ""), (1e-3, "m"), (1e-6, "\u00b5"), (1e-9, "n"), (1e-12, "p")]


def auto_scale(values, base_unit, base_factor=1.0):
    """Pick an SI prefix so that max|values| (in base_unit) reads between 1 and
    1000. base_factor converts the raw SI data to base_unit first. Returns
    (factor to multiply raw data by, unit label)."""
    m = float(np.max(np.abs(values))) * base_factor if len(values) else 0.0
    if m == 0.0 or not math.isfinite(m):
        return base_factor, base_unit
    for scale, prefix in _PREFIX:
        if m >= scale:
            return base_factor / scale, prefix + base_unit
    return base_factor / _PREFIX[-1][0], _PREFIX[-1][1] + base_unit


def fig_components(save, fname, title, ideal, clear, ideal_g, clear_g,
                   comps, unit, factor, is_angle=False, spiky=False):
    """comps: list of (column, label). spiky: accelerations, whose clearance
    curve has impact spikes; then the ideal and clearance panels get their own
    y scales and the clearance panel shows the ideal curve as a reference."""
    n = len(comps)
    fig, axes = plt.subplots(n, 3, figsize=(15, 2.5 * n + 1.0), sharex=True,
                             squeeze=False, constrained_layout=True)
    fig.suptitle(title, fontsize=13)
    for r, (col, label) in enumerate(comps):
        ax_i, ax_c, ax_d = axes[r]
        ax_i.plot(ideal["t_s"], ideal[col] * factor, color=C_IDEAL, lw=1.0)
        if spiky:
            ax_c.plot(ideal["t_s"], ideal[col] * factor, color="0.55", lw=1.6,
                      label="ideal (reference)", zorder=1)
        ax_c.plot(clear["t_s"], clear[col] * factor, color=C_CLEAR, lw=0.8,
                  label="clearance", zorder=2)
        if spiky:
            ax_c.legend(loc="best", fontsize=8)
        else:
            # Same y range on both runs so the panels compare at a glance.
            lo = min(ax_i.get_ylim()[0], ax_c.get_ylim()[0])
            hi = max(ax_i.get_ylim()[1], ax_c.get_ylim()[1])
            ax_i.set_ylim(lo, hi)
            ax_c.set_ylim(lo, hi)
        d = clear_g[col] - ideal_g[col]
        if is_angle:
            d = wrap_pi(d)
        dfac, dunit = auto_scale(d, unit_base(unit), base_factor=1.0)
        ax_d.plot(ideal_g["t_s"], d * dfac, color=C_DIFF, lw=0.8)
        ax_d.axhline(0.0, color="0.6", lw=0.6)
        ax_i.set_ylabel(f"{label} [{unit}]")
        ax_c.set_ylabel(f"{label} [{unit}]")
        ax_d.set_ylabel(f"\u0394{label} [{dunit}]")
        for ax in axes[r]:
            ax.grid(True, alpha=0.3)
    axes[0][0].set_title("ideal joint 2")
    axes[0][1].set_title("clearance joint 2")
    axes[0][2].set_title("difference: clearance \u2212 ideal")
    for ax in axes[-1]:
        ax.set_xlabel("t [s]")
    save(fig, fname)


def unit_base(unit):
    """The SI unit behind a display unit, for auto-scaling differences."""
    return {"mm": "m", "mm/s": "m/s", "mm/s\u00b2": "m/s\u00b2"}.get(unit, unit)


# Figs 8-16: (file, title, [(column, label)], display unit, factor, is_angle, spiky).
_XYZ = ("x", "y", "z")
COMPONENT_FIGURES = [
    ("fig08_base_position.png", "Fig. 8  Base centre-of-mass position (inertial frame)",
     [(f"base_{k}_m", k) for k in _XYZ], "mm", 1e3, False, False),
    ("fig09_base_velocity.png", "Fig. 9  Base centre-of-mass velocity",
     [(f"base_v{k}_m_per_s", f"v_{k}") for k in _XYZ], "mm/s", 1e3, False, False),
    ("fig10_base_acceleration.png", "Fig. 10  Base centre-of-mass acceleration",
     [(f"base_a{k}_m_per_s2", f"a_{k}") for k in _XYZ], "mm/s\u00b2", 1e3, False, True),
    ("fig11_base_euler.png", "Fig. 11  Base attitude, Z-Y-X Euler angles",
     [("base_roll_rad", "roll"), ("base_pitch_rad", "pitch"), ("base_yaw_rad", "yaw")],
     "rad", 1.0, True, False),
    ("fig12_base_rates.png", "Fig. 12  Base angular velocity (base frame)",
     [(f"base_w{k}_rad_per_s", f"\u03c9_{k}") for k in _XYZ], "rad/s", 1.0, False, False),
    ("fig13_base_angular_acceleration.png", "Fig. 13  Base angular acceleration (base frame)",
     [(f"base_dw{k}_rad_per_s2", f"d\u03c9_{k}/dt") for k in _XYZ], "rad/s\u00b2", 1.0, False, True),
    ("fig14_joint_angles.png", "Fig. 14  Joint angles (shaft 1 azimuth, shaft 2 elevation)",
     [("theta1_rad", "\u03b8\u2081"), ("theta2_rad", "\u03b8\u2082")], "rad", 1.0, False, False),
    ("fig15_joint_rates.png", "Fig. 15  Joint angular velocities",
     [("dtheta1_rad_per_s", "d\u03b8\u2081/dt"), ("dtheta2_rad_per_s", "d\u03b8\u2082/dt")], "rad/s", 1.0,
     False, False),
    ("fig16_joint_accelerations.png", "Fig. 16  Joint angular accelerations",
     [("ddtheta1_rad_per_s2", "d\u00b2\u03b8\u2081/dt\u00b2"), ("ddtheta2_rad_per_s2", "d\u00b2\u03b8\u2082/dt\u00b2")],
     "rad/s\u00b2", 1.0, False, True),
]


if __name__ == "__main__":  # (pass 79) run alone it took any arguments, did nothing and exited 0
    print("plot_components.py: error: a module of tools/paper/plot_paper.py, not a program: "
          "run plot_paper.py, which draws these figures", file=sys.stderr)
    sys.exit(2)
