#!/usr/bin/python3
"""Plot the paper's figures 6-16 (You, Pan, Zhao 2010, section 4) from two
gimbalsim runs, ideal joint 2 and clearance joint 2, plus the antenna pointing
error between them (fig 17) and the joint-2 force comparison (fig 18); given
a third run with a spatial joint 2 (paper_spatial2), the joint kinds compared
(fig 19: pointing error against the ideal joint, mid-plane eccentricity,
largest tilt).

Usage:
  /usr/bin/python3 tools/plot_paper.py --ideal ideal.csv --clearance clearance.csv \
      --out DIR [--ideal-summary ideal.json] [--clearance-summary clearance.json] \
      [--spatial spatial.csv [--spatial-summary spatial.json]]

Writes DIR/fig06_eccentricity.png ... DIR/fig18_joint2_force.png (and
fig19_joint_kinds.png) and DIR/pointing_error.csv (t_s, pointing_error_rad,
and pointing_error_spatial_rad with a spatial run), and prints a short summary.

Columns are read by NAME from the CSV header (SI units, angles in rad); see
docs/MODEL.md section 8.8. Only numpy and matplotlib (Agg) are needed.
"""
import argparse
import math
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from output_file import open_output, savefig  # noqa: E402  (the package's one writer, tools/output_file.py)
from plot_joint_kinds import fig_joint_kinds, spatial_tilt  # noqa: E402  (fig 19)
from paper_data import (InputError, angle_between, boresight, common_grid, contact_starts,  # noqa: E402
                        continuous_contact_from, load_csv, load_summary, summary_number, wrap_pi)

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


def save(fig, out_dir, name, written):
    path = os.path.join(out_dir, name)
    savefig(fig, path, dpi=110)
    plt.close(fig)
    written.append(path)


# ----------------------------------------------------------------------------
# Figures 8-16: one row per component; ideal | clearance | clearance - ideal
# ----------------------------------------------------------------------------
def fig_components(out_dir, written, fname, title, ideal, clear, ideal_g, clear_g,
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
    save(fig, out_dir, fname, written)


def unit_base(unit):
    """The SI unit behind a display unit, for auto-scaling differences."""
    return {"mm": "m", "mm/s": "m/s", "mm/s\u00b2": "m/s\u00b2"}.get(unit, unit)


# ----------------------------------------------------------------------------
# Main
# ----------------------------------------------------------------------------
def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--ideal", required=True, help="CSV of the ideal-joint run")
    p.add_argument("--clearance", required=True, help="CSV of the clearance-joint run")
    p.add_argument("--out", required=True, help="output directory for the PNGs")
    p.add_argument("--ideal-summary", help="summary JSON of the ideal run (optional)")
    p.add_argument("--clearance-summary", help="summary JSON of the clearance run (optional)")
    p.add_argument("--spatial", help="CSV of the same scene with a spatial joint 2 (optional): fig 19")
    p.add_argument("--spatial-summary", help="summary JSON of the spatial run (optional)")
    a = p.parse_args(argv)
    if a.spatial_summary and not a.spatial:
        p.error("--spatial-summary needs --spatial")

    try:
        ideal = load_csv(a.ideal)
        clear = load_csv(a.clearance)
        s_ideal = load_summary(a.ideal_summary)
        s_clear = load_summary(a.clearance_summary)
        ideal_g, clear_g, grid_note = common_grid(ideal, clear)
        spatial = s_spatial = spatial_g = None
        if a.spatial:
            spatial, s_spatial = load_csv(a.spatial), load_summary(a.spatial_summary)
            ideal_s, spatial_g, _ = common_grid(ideal, spatial)
            if ideal_s["t_s"].shape != ideal_g["t_s"].shape:
                raise InputError(f"{a.spatial}: the spatial run covers {spatial['t_s'][0]:g}..{spatial['t_s'][-1]:g} s, "
                                 f"the clearance run {clear['t_s'][0]:g}..{clear['t_s'][-1]:g} s: "
                                 "run both over the same time")
    except InputError as e:
        print(f"plot_paper.py: error: {e}", file=sys.stderr)
        return 2
    os.makedirs(a.out, exist_ok=True)
    if grid_note:
        print(grid_note)
    written = []
    t_i, t_c = ideal["t_s"], clear["t_s"]

    # Radial clearance c: from the summary if it carries it, else ecc - delta.
    c = summary_number(s_clear, "clearance_m", "clearance", "contact.clearance_m",
                       "contact.clearance")
    c_src = "summary"
    if c is None:
        c = float(np.max(clear["ecc2_m"] - clear["delta2_m"]))
        c_src = "max(ecc - delta)"
    t_cont = summary_number(s_clear, "continuous_contact_from_s")
    if t_cont is None and not a.clearance_summary:
        t_cont = continuous_contact_from(clear)
    dt_out = float(np.median(np.diff(t_c)))
    # Window for the "impact phase" zooms.
    t_zoom = min(t_c[-1], max(0.3, 1.2 * t_cont) if t_cont else 0.25 * t_c[-1] + 0.3)

    # -- Fig 6: eccentricity ------------------------------------------------------
    fig = plt.figure(figsize=(15, 4.6), constrained_layout=True)
    gs = fig.add_gridspec(1, 3, width_ratios=[1.4, 1.4, 1.0])
    ax1, ax2, ax3 = fig.add_subplot(gs[0]), fig.add_subplot(gs[1]), fig.add_subplot(gs[2])
    fig.suptitle("Fig. 6  Eccentricity of joint 2 (clearance run; the ideal joint has e \u2261 0)",
                 fontsize=13)
    for ax, tmax in ((ax1, t_c[-1]), (ax2, t_zoom)):
        m = t_c <= tmax
        ax.plot(t_c[m], clear["ecc2_m"][m] * 1e3, color=C_CLEAR, lw=0.8, label="e (clearance run)")
        ax.axhline(c * 1e3, color="k", ls="--", lw=1.0, label=f"clearance c = {c*1e3:.3g} mm")
        ax.plot(t_i[t_i <= tmax], ideal["ecc2_m"][t_i <= tmax] * 1e3, color=C_IDEAL, lw=1.0,
                label="e (ideal run)")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("eccentricity e [mm]")
        ax.grid(True, alpha=0.3)
    if t_cont:
        ax2.axvline(t_cont, color="0.4", ls=":", lw=1.0, label=f"continuous contact from {t_cont:.3g} s")
    ax1.set_title("whole run")
    ax2.set_title(f"impact phase, 0\u2013{t_zoom:.3g} s")
    ax1.legend(loc="lower right", fontsize=8)
    ax2.legend(loc="lower right", fontsize=8)
    th = np.linspace(0, 2 * np.pi, 361)
    ax3.plot(c * 1e3 * np.cos(th), c * 1e3 * np.sin(th), "k--", lw=1.0, label="e = c")
    ax3.plot(clear["ecc2_x_m"] * 1e3, clear["ecc2_y_m"] * 1e3, color=C_CLEAR, lw=0.6,
             label="journal centre")
    ax3.plot(clear["ecc2_x_m"][0] * 1e3, clear["ecc2_y_m"][0] * 1e3, "o", color="k", ms=4, label="start")
    ax3.set_aspect("equal")
    ax3.set_xlabel("ecc_x, along joint-plane axis u1 [mm]")
    ax3.set_ylabel("ecc_y, along u2 = k2 \u00d7 u1 [mm]")
    ax3.set_title("journal centre in the bearing")
    ax3.legend(loc="upper left", fontsize=7)
    ax3.grid(True, alpha=0.3)
    save(fig, a.out, "fig06_eccentricity.png", written)

    # -- Fig 7: contact force --------------------------------------------------
    pk_fn = summary_number(s_clear, "peak_contact_force_N")
    t_pk_fn = summary_number(s_clear, "t_peak_contact_force_s")
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    fig.suptitle("Fig. 7  Joint-2 force: ideal joint reaction vs clearance contact normal force F_n",
                 fontsize=13)
    ymax = 1.05 * max(np.max(clear["fn2_N"]), np.max(ideal["joint2_force_N"]), pk_fn or 0.0)
    axes[0].plot(t_i, ideal["joint2_force_N"], color=C_IDEAL, lw=1.0)
    axes[0].set_title("ideal joint 2: |joint force|")
    axes[0].set_ylabel("|joint 2 force| [N]")
    for ax, tmax in ((axes[1], t_c[-1]), (axes[2], t_zoom)):
        m = t_c <= tmax
        ax.plot(t_c[m], clear["fn2_N"][m], color=C_CLEAR, lw=0.7,
                label=f"F_n (CSV, sampled every {dt_out*1e3:.3g} ms)")
        if pk_fn is not None and t_pk_fn is not None and t_pk_fn <= tmax:
            ax.plot([t_pk_fn], [pk_fn], "kv", ms=7,
                    label=f"true peak {pk_fn:.0f} N at {t_pk_fn:.4g} s (summary)")
        ax.set_ylabel("contact normal force F_n [N]")
    if t_cont:
        axes[2].axvline(t_cont, color="0.4", ls=":", lw=1.0,
                        label=f"continuous contact from {t_cont:.3g} s")
    axes[1].set_title("clearance joint 2: F_n, whole run")
    axes[2].set_title(f"clearance joint 2: F_n, impact phase 0\u2013{t_zoom:.3g} s")
    for ax in axes:
        ax.set_ylim(0, ymax)
        ax.set_xlabel("t [s]")
        ax.grid(True, alpha=0.3)
    axes[1].legend(loc="upper right", fontsize=8)
    axes[2].legend(loc="upper right", fontsize=8)
    save(fig, a.out, "fig07_contact_force.png", written)

    # -- Figs 8-16 ---------------------------------------------------------------
    xyz = ("x", "y", "z")
    specs = [
        ("fig08_base_position.png", "Fig. 8  Base centre-of-mass position (inertial frame)",
         [(f"base_{k}_m", k) for k in xyz], "mm", 1e3, False, False),
        ("fig09_base_velocity.png", "Fig. 9  Base centre-of-mass velocity",
         [(f"base_v{k}_m_per_s", f"v_{k}") for k in xyz], "mm/s", 1e3, False, False),
        ("fig10_base_acceleration.png", "Fig. 10  Base centre-of-mass acceleration",
         [(f"base_a{k}_m_per_s2", f"a_{k}") for k in xyz], "mm/s\u00b2", 1e3, False, True),
        ("fig11_base_euler.png", "Fig. 11  Base attitude, Z-Y-X Euler angles",
         [("base_roll_rad", "roll"), ("base_pitch_rad", "pitch"), ("base_yaw_rad", "yaw")],
         "rad", 1.0, True, False),
        ("fig12_base_rates.png", "Fig. 12  Base angular velocity (base frame)",
         [(f"base_w{k}_rad_per_s", f"\u03c9_{k}") for k in xyz], "rad/s", 1.0, False, False),
        ("fig13_base_angular_acceleration.png", "Fig. 13  Base angular acceleration (base frame)",
         [(f"base_dw{k}_rad_per_s2", f"d\u03c9_{k}/dt") for k in xyz], "rad/s\u00b2", 1.0, False, True),
        ("fig14_joint_angles.png", "Fig. 14  Joint angles (shaft 1 azimuth, shaft 2 elevation)",
         [("theta1_rad", "\u03b8\u2081"), ("theta2_rad", "\u03b8\u2082")], "rad", 1.0, False, False),
        ("fig15_joint_rates.png", "Fig. 15  Joint angular velocities",
         [("dtheta1_rad_per_s", "d\u03b8\u2081/dt"), ("dtheta2_rad_per_s", "d\u03b8\u2082/dt")], "rad/s", 1.0,
         False, False),
        ("fig16_joint_accelerations.png", "Fig. 16  Joint angular accelerations",
         [("ddtheta1_rad_per_s2", "d\u00b2\u03b8\u2081/dt\u00b2"), ("ddtheta2_rad_per_s2", "d\u00b2\u03b8\u2082/dt\u00b2")],
         "rad/s\u00b2", 1.0, False, True),
    ]
    for fname, title, comps, unit, factor, is_angle, spiky in specs:
        fig_components(a.out, written, fname, title, ideal, clear, ideal_g, clear_g,
                       comps, unit, factor, is_angle=is_angle, spiky=spiky)

    # -- Fig 17: pointing error ------------------------------------------------
    t = ideal_g["t_s"]
    err = angle_between(boresight(ideal_g), boresight(clear_g))
    k_max = int(np.argmax(err))
    err_max, t_err_max, err_final = float(err[k_max]), float(t[k_max]), float(err[-1])
    err_sp = angle_between(boresight(ideal_g), boresight(spatial_g)) if spatial is not None else None
    pe_path = os.path.join(a.out, "pointing_error.csv")
    # The CSV convention (docs/usage.md "CSV files"): unit-suffixed names, round-trip numbers (repr).
    with open_output(pe_path, inputs=[a.ideal, a.clearance, a.spatial]) as f:
        cols = {"pointing_error_rad": err}
        if err_sp is not None:
            cols["pointing_error_spatial_rad"] = err_sp
        f.write(",".join(["t_s", *cols]) + "\n")
        f.writelines(",".join([repr(float(ti))] + [repr(float(e[k]) + 0.0) for e in cols.values()]) + "\n"
                     for k, ti in enumerate(t))
    fig, ax = plt.subplots(figsize=(11, 4.8), constrained_layout=True)
    pos = err > 0.0  # a log axis cannot show exact zeros (e.g. t = 0)
    ax.set_yscale("log")
    if pos.any():
        ax.plot(t[pos], err[pos], color=C_DIFF, lw=1.0)
        ax.plot([t_err_max], [err_max], "kv", ms=7,
                label=f"max {err_max:.3g} rad ({math.degrees(err_max):.3g}\u00b0) at {t_err_max:.3g} s")
        if err_final > 0.0:
            ax.plot([t[-1]], [err_final], "ko", ms=5,
                    label=f"final {err_final:.3g} rad ({math.degrees(err_final):.3g}\u00b0) "
                          f"at {t[-1]:.3g} s")
    else:
        ax.text(0.5, 0.5, "the two boresights coincide at every sample (error = 0)",
                transform=ax.transAxes, ha="center")
    if t_cont:
        ax.axvline(t_cont, color="0.4", ls=":", lw=1.0, label=f"continuous contact from {t_cont:.3g} s")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("pointing error [rad]")
    sec = ax.secondary_yaxis("right", functions=(np.degrees, np.radians))
    sec.set_ylabel("pointing error [deg]")
    ax.set_title("Fig. 17  Antenna pointing error: angle between the clearance and ideal "
                 "boresight vectors, atan2(|a\u00d7b|, a\u00b7b)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="lower right", fontsize=9)
    save(fig, a.out, "fig17_pointing_error.png", written)

    # -- Fig 18: joint-2 force ---------------------------------------------------
    pk_c_csv, pk_i_csv = float(np.max(clear["joint2_force_N"])), float(np.max(ideal["joint2_force_N"]))
    pk_c = summary_number(s_clear, "peak_joint2_force_N")
    t_pk_c = summary_number(s_clear, "t_peak_joint2_force_s")
    pk_i = summary_number(s_ideal, "peak_joint2_force_N")
    t_pk_i = summary_number(s_ideal, "t_peak_joint2_force_s")
    src = "summary (all sub-steps)"
    if pk_c is None or pk_i is None:
        pk_c, pk_i, src = pk_c_csv, pk_i_csv, "CSV samples"
        t_pk_c = float(t_c[np.argmax(clear["joint2_force_N"])])
        t_pk_i = float(t_i[np.argmax(ideal["joint2_force_N"])])
    ratio = pk_c / pk_i if pk_i > 0 else float("inf")
    if abs(t_i[-1] - t_c[-1]) > 1e-9 * max(1.0, t_i[-1]):
        print(f"WARNING: the runs end at different times (ideal {t_i[-1]:g} s, clearance "
              f"{t_c[-1]:g} s): the joint-force peaks below cover different durations.")
    # The ideal joint force grows with the spin-up; compare also with the ideal
    # force at the moment of the clearance peak.
    f_i_at_pk = float(np.interp(t_pk_c, t_i, ideal["joint2_force_N"])) if t_pk_c is not None else None
    ratio_same_t = pk_c / f_i_at_pk if f_i_at_pk else None

    fig, axes = plt.subplots(1, 2, figsize=(15, 4.8), constrained_layout=True,
                             gridspec_kw={"width_ratios": [1.6, 1.0]})
    same_t_txt = (f"; vs ideal at the same instant {ratio_same_t:.0f}\u00d7"
                  if ratio_same_t is not None else "")
    fig.suptitle(f"Fig. 18  Force transmitted by joint 2: peak clearance / peak ideal = "
                 f"{ratio:.2f}\u00d7 (peaks from {src}){same_t_txt}", fontsize=13)
    for ax, tmax in ((axes[0], t_c[-1]), (axes[1], t_zoom)):
        mc, mi = t_c <= tmax, t_i <= tmax
        # Ideal drawn broad and underneath, so the clearance run's thin curve stays
        # visible where the two coincide (continuous contact).
        ax.plot(t_i[mi], ideal["joint2_force_N"][mi], color=C_IDEAL, lw=3.0, alpha=0.6,
                label="ideal joint", zorder=1)
        ax.plot(t_c[mc], clear["joint2_force_N"][mc], color=C_CLEAR, lw=0.7,
                label="clearance joint (CSV samples)", zorder=2)
        if t_pk_c is not None and t_pk_c <= tmax:
            ax.plot([t_pk_c], [pk_c], "v", color="darkred", ms=7,
                    label=f"clearance peak {pk_c:.0f} N at {t_pk_c:.4g} s")
        if t_pk_i is not None and t_pk_i <= tmax:
            ax.plot([t_pk_i], [pk_i], "^", color="navy", ms=7,
                    label=f"ideal peak {pk_i:.0f} N at {t_pk_i:.4g} s")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("|joint 2 force| [N]")
        ax.set_ylim(0, 1.08 * max(pk_c, pk_c_csv))
        ax.grid(True, alpha=0.3)
    axes[0].set_title("whole run")
    axes[1].set_title(f"impact phase 0\u2013{t_zoom:.3g} s")
    axes[0].legend(loc="upper right", fontsize=8)
    if f_i_at_pk:
        axes[1].plot([], [], " ", label=f"ideal at clearance-peak time: {f_i_at_pk:.1f} N "
                                         f"(ratio {ratio_same_t:.0f})")
    axes[1].legend(loc="upper right", fontsize=8)
    save(fig, a.out, "fig18_joint2_force.png", written)

    if spatial is not None:
        fig_joint_kinds(lambda fig, name: save(fig, a.out, name, written), t, err, err_sp, clear, spatial,
                        s_spatial, c, C_CLEAR)

    # -- Text summary ----------------------------------------------------------
    impacts = summary_number(s_clear, "impacts")
    if impacts is None:
        impacts_txt = f"{len(contact_starts(clear))} (counted from CSV samples; short impacts may be missed)"
    else:
        impacts_txt = f"{int(impacts)} (summary)"
    if pk_fn is None:
        pk_fn_txt = (f"{np.max(clear['fn2_N']):.1f} N at t = {t_c[np.argmax(clear['fn2_N'])]:.4g} s "
                     f"(CSV samples)")
    else:
        pk_fn_txt = f"{pk_fn:.1f} N at t = {t_pk_fn:.4g} s (summary); CSV samples max {np.max(clear['fn2_N']):.1f} N"
    print("gimbalsim paper figures")
    print(f"  clearance c                 : {c*1e3:.4g} mm (from {c_src})")
    print(f"  peak contact force          : {pk_fn_txt}")
    print(f"  impacts                     : {impacts_txt}")
    if t_cont is not None:
        print(f"  continuous contact from     : {t_cont:.4g} s")
    print(f"  max pointing error          : {err_max:.4g} rad ({math.degrees(err_max):.4g} deg) "
          f"at t = {t_err_max:.4g} s")
    print(f"  final pointing error        : {err_final:.4g} rad ({math.degrees(err_final):.4g} deg) "
          f"at t = {t[-1]:.4g} s")
    print(f"  joint-2 force peaks         : clearance {pk_c:.1f} N / ideal {pk_i:.1f} N "
          f"= {ratio:.2f} ({src})")
    if ratio_same_t is not None:
        print(f"    vs ideal at the same time : ideal {f_i_at_pk:.1f} N at t = {t_pk_c:.4g} s "
              f"-> ratio {ratio_same_t:.1f}")
    if err_sp is not None:
        tilt = spatial_tilt(s_spatial)
        print(f"  spatial joint 2             : pointing error {float(err_sp[-1]):.4g} rad at t = {t[-1]:.4g} s "
              f"(planar {err_final:.4g} rad), max {float(np.max(err_sp)):.4g} rad; largest tilt "
              + (f"{tilt:.4g} rad" if tilt is not None else "not in a summary"))
    print(f"  wrote {len(written)} figures and {pe_path} into {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
