#!/usr/bin/python3
"""Plot the paper's figures 6-16 (You, Pan, Zhao 2010, section 4) from two
gimbalsim runs, ideal joint 2 and clearance joint 2, plus the antenna pointing
error between them (fig 17) and the joint-2 force comparison (fig 18); given
a third run with a spatial joint 2 (paper_spatial2), the joint kinds compared
(fig 19: pointing error against the ideal joint, mid-plane eccentricity,
largest tilt).

Usage:
  /usr/bin/python3 tools/paper/plot_paper.py --ideal ideal.csv --clearance clearance.csv \
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
from types import SimpleNamespace

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pages"))
import output_file  # noqa: E402  (standard_flags)
from output_file import Refused, check_before_writing, csv_number, open_output, run_script, savefig  # noqa: E402  (the package's one writer, tools/pages/output_file.py)
from plot_components import C_CLEAR, C_DIFF, C_IDEAL, COMPONENT_FIGURES, fig_components  # noqa: E402  (figs 8-16)
from plot_joint_kinds import fig_joint_kinds, spatial_tilt  # noqa: E402  (fig 19)
from paper_data import (InputError, angle_between, boresight, check_joint2, check_summary_figures,  # noqa: E402
                        check_summary_is_the_runs, common_grid, contact_starts, continuous_contact_from, load_csv,
                        load_summary, summary_number)



def save(fig, out_dir, name, written):
    path = os.path.join(out_dir, name)
    savefig(fig, path, dpi=110)
    plt.close(fig)
    written.append(path)


def parse_args(argv):
    p = argparse.ArgumentParser(allow_abbrev=False, description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
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
    return a


def load_runs(a):
    """The runs, their summaries, their common grid and the clearance run's
    impact phase; raises InputError naming the file at fault."""
    r = SimpleNamespace(ideal=load_csv(a.ideal), clear=load_csv(a.clearance), s_ideal=load_summary(a.ideal_summary),
                        s_clear=load_summary(a.clearance_summary), spatial=None, s_spatial=None, spatial_g=None)
    # Each run must be the one its flag names (the ideal and clearance runs swapped drew a wrong page).
    check_joint2("--ideal", a.ideal, r.ideal, "--ideal-summary", a.ideal_summary, r.s_ideal, ["ideal"])
    check_joint2("--clearance", a.clearance, r.clear, "--clearance-summary", a.clearance_summary, r.s_clear,
                 ["planar", "spatial"])
    for flag, path, summary, cols in (("--ideal-summary", a.ideal_summary, r.s_ideal, r.ideal),
                                      ("--clearance-summary", a.clearance_summary, r.s_clear, r.clear)):
        check_summary_is_the_runs(flag, path, summary, cols)
        check_summary_figures(flag, path, summary, cols)
    r.ideal_g, r.clear_g, r.grid_note = common_grid(r.ideal, r.clear)
    if a.spatial:
        r.spatial, r.s_spatial = load_csv(a.spatial), load_summary(a.spatial_summary)
        check_joint2("--spatial", a.spatial, r.spatial, "--spatial-summary", a.spatial_summary, r.s_spatial,
                     ["spatial"])
        check_summary_is_the_runs("--spatial-summary", a.spatial_summary, r.s_spatial, r.spatial)
        check_summary_figures("--spatial-summary", a.spatial_summary, r.s_spatial, r.spatial)
        ideal_s, r.spatial_g, _ = common_grid(r.ideal, r.spatial)
        if ideal_s["t_s"].shape != r.ideal_g["t_s"].shape:
            raise InputError(f"{a.spatial}: the spatial run covers {r.spatial['t_s'][0]:g}..{r.spatial['t_s'][-1]:g} s, "
                             f"the clearance run {r.clear['t_s'][0]:g}..{r.clear['t_s'][-1]:g} s: "
                             "run both over the same time")
    r.t_i, r.t_c = r.ideal["t_s"], r.clear["t_s"]
    # Radial clearance c: from the summary if it carries it, else ecc - delta.
    r.c = summary_number(r.s_clear, "clearance_m", "clearance", "contact.clearance_m", "contact.clearance")
    r.c_src = "summary"
    if r.c is None:
        r.c = float(np.max(r.clear["ecc2_m"] - r.clear["delta2_m"]))
        r.c_src = "max(ecc - delta)"
    if not r.c > 0.0:  # an ideal joint's run: no bearing, so no figure of this page would mean anything
        raise InputError(f"{a.clearance}: joint 2 has no clearance (ecc - delta is {r.c:g} m throughout): "
                         "is it the ideal run? --clearance takes the run of a clearance joint 2")
    r.t_cont = summary_number(r.s_clear, "continuous_contact_from_s")
    if r.t_cont is None and not a.clearance_summary:
        r.t_cont = continuous_contact_from(r.clear)
    r.dt_out = float(np.median(np.diff(r.t_c)))
    # Window for the "impact phase" zooms.
    r.t_zoom = min(r.t_c[-1], max(0.3, 1.2 * r.t_cont) if r.t_cont else 0.25 * r.t_c[-1] + 0.3)
    return r


def fig_eccentricity(r, out_dir, written):
    """Fig 6: joint 2's eccentricity, whole run and impact phase, and the journal centre's path."""
    ideal, clear, t_i, t_c, c = r.ideal, r.clear, r.t_i, r.t_c, r.c
    fig = plt.figure(figsize=(15, 4.6), constrained_layout=True)
    gs = fig.add_gridspec(1, 3, width_ratios=[1.4, 1.4, 1.0])
    ax1, ax2, ax3 = fig.add_subplot(gs[0]), fig.add_subplot(gs[1]), fig.add_subplot(gs[2])
    fig.suptitle("Fig. 6  Eccentricity of joint 2 (clearance run; the ideal joint has e \u2261 0)",
                 fontsize=13)
    for ax, tmax in ((ax1, t_c[-1]), (ax2, r.t_zoom)):
        m = t_c <= tmax
        ax.plot(t_c[m], clear["ecc2_m"][m] * 1e3, color=C_CLEAR, lw=0.8, label="e (clearance run)")
        ax.axhline(c * 1e3, color="k", ls="--", lw=1.0, label=f"clearance c = {c*1e3:.3g} mm")
        ax.plot(t_i[t_i <= tmax], ideal["ecc2_m"][t_i <= tmax] * 1e3, color=C_IDEAL, lw=1.0,
                label="e (ideal run)")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("eccentricity e [mm]")
        ax.grid(True, alpha=0.3)
    if r.t_cont:
        ax2.axvline(r.t_cont, color="0.4", ls=":", lw=1.0, label=f"continuous contact from {r.t_cont:.3g} s")
    ax1.set_title("whole run")
    ax2.set_title(f"impact phase, 0\u2013{r.t_zoom:.3g} s")
    ax1.legend(loc="lower right", fontsize=8)
    ax2.legend(loc="lower right", fontsize=8)
    th = np.linspace(0, 2 * np.pi, 361)
    ax3.plot(c * 1e3 * np.cos(th), c * 1e3 * np.sin(th), "k--", lw=1.0, label="e = c")
    ax3.plot(clear["ecc2_x_m"] * 1e3, clear["ecc2_y_m"] * 1e3, color=C_CLEAR, lw=0.6,
             label="journal centre")
    ax3.plot(clear["ecc2_x_m"][0] * 1e3, clear["ecc2_y_m"][0] * 1e3, "o", color="k", ms=4, label="start")
    ax3.set_aspect("equal")
    ax3.set_xlabel("ecc2_x, along joint-2 plane axis u1 [mm]")
    ax3.set_ylabel("ecc2_y, along u2 = k2 \u00d7 u1 [mm]")
    ax3.set_title("journal centre in the bearing")
    ax3.legend(loc="upper left", fontsize=7)
    ax3.grid(True, alpha=0.3)
    save(fig, out_dir, "fig06_eccentricity.png", written)


def fig_contact_force(r, out_dir, written):
    """Fig 7: the ideal joint's reaction against the clearance joint's normal
    force; returns the summary's true peak (force [N], time [s]), None where absent."""
    ideal, clear, t_i, t_c = r.ideal, r.clear, r.t_i, r.t_c
    pk_fn = summary_number(r.s_clear, "peak_contact_force_N")
    t_pk_fn = summary_number(r.s_clear, "t_peak_contact_force_s")
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    fig.suptitle("Fig. 7  Joint-2 force: ideal joint reaction vs clearance contact normal force F_n",
                 fontsize=13)
    ymax = 1.05 * max(np.max(clear["fn2_N"]), np.max(ideal["joint2_force_N"]), pk_fn or 0.0)
    axes[0].plot(t_i, ideal["joint2_force_N"], color=C_IDEAL, lw=1.0)
    axes[0].set_title("ideal joint 2: |joint force|")
    axes[0].set_ylabel("|joint 2 force| [N]")
    for ax, tmax in ((axes[1], t_c[-1]), (axes[2], r.t_zoom)):
        m = t_c <= tmax
        ax.plot(t_c[m], clear["fn2_N"][m], color=C_CLEAR, lw=0.7,
                label=f"F_n (CSV, sampled every {r.dt_out*1e3:.3g} ms)")
        if pk_fn is not None and t_pk_fn is not None and t_pk_fn <= tmax:
            ax.plot([t_pk_fn], [pk_fn], "kv", ms=7,
                    label=f"true peak {pk_fn:.0f} N at {t_pk_fn:.4g} s (summary)")
        ax.set_ylabel("contact normal force F_n [N]")
    if r.t_cont:
        axes[2].axvline(r.t_cont, color="0.4", ls=":", lw=1.0,
                        label=f"continuous contact from {r.t_cont:.3g} s")
    axes[1].set_title("clearance joint 2: F_n, whole run")
    axes[2].set_title(f"clearance joint 2: F_n, impact phase 0\u2013{r.t_zoom:.3g} s")
    for ax in axes:
        ax.set_ylim(0, ymax)
        ax.set_xlabel("t [s]")
        ax.grid(True, alpha=0.3)
    axes[1].legend(loc="upper right", fontsize=8)
    axes[2].legend(loc="upper right", fontsize=8)
    save(fig, out_dir, "fig07_contact_force.png", written)
    return pk_fn, t_pk_fn


def fig_pointing_error(r, a, written):
    """Fig 17 and pointing_error.csv: the angle between the two boresights
    (and the spatial run's); returns its figures."""
    t = r.ideal_g["t_s"]
    err = angle_between(boresight(r.ideal_g), boresight(r.clear_g))
    k_max = int(np.argmax(err))
    pe = SimpleNamespace(t=t, err=err, err_max=float(err[k_max]), t_err_max=float(t[k_max]), err_final=float(err[-1]),
                         err_sp=angle_between(boresight(r.ideal_g), boresight(r.spatial_g))
                         if r.spatial is not None else None,
                         path=os.path.join(a.out, "pointing_error.csv"))
    # The CSV convention (docs/usage.md "CSV files"): unit-suffixed names, its numbers (csv_number).
    with open_output(pe.path, inputs=[a.ideal, a.clearance, a.spatial]) as f:
        cols = {"pointing_error_rad": err}
        if pe.err_sp is not None:
            cols["pointing_error_spatial_rad"] = pe.err_sp
        f.write(",".join(["t_s", *cols]) + "\n")
        f.writelines(",".join([csv_number(ti)] + [csv_number(e[k]) for e in cols.values()]) + "\n"
                     for k, ti in enumerate(t))
    fig, ax = plt.subplots(figsize=(11, 4.8), constrained_layout=True)
    pos = err > 0.0  # a log axis cannot show exact zeros (e.g. t = 0)
    ax.set_yscale("log")
    if pos.any():
        ax.plot(t[pos], err[pos], color=C_DIFF, lw=1.0)
        ax.plot([pe.t_err_max], [pe.err_max], "kv", ms=7,
                label=f"max {pe.err_max:.3g} rad ({math.degrees(pe.err_max):.3g}\u00b0) at {pe.t_err_max:.3g} s")
        if pe.err_final > 0.0:
            ax.plot([t[-1]], [pe.err_final], "ko", ms=5,
                    label=f"final {pe.err_final:.3g} rad ({math.degrees(pe.err_final):.3g}\u00b0) "
                          f"at {t[-1]:.3g} s")
    else:
        ax.text(0.5, 0.5, "the two boresights coincide at every sample (error = 0)",
                transform=ax.transAxes, ha="center")
    if r.t_cont:
        ax.axvline(r.t_cont, color="0.4", ls=":", lw=1.0, label=f"continuous contact from {r.t_cont:.3g} s")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("pointing error [rad]")
    sec = ax.secondary_yaxis("right", functions=(np.degrees, np.radians))
    sec.set_ylabel("pointing error [deg]")
    ax.set_title("Fig. 17  Antenna pointing error: angle between the clearance and ideal "
                 "boresight vectors, atan2(|a\u00d7b|, a\u00b7b)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="lower right", fontsize=9)
    save(fig, a.out, "fig17_pointing_error.png", written)
    return pe


def fig_joint_force(r, out_dir, written):
    """Fig 18: the force joint 2 transmits, clearance against ideal; returns the peaks and their ratios."""
    ideal, clear, t_i, t_c = r.ideal, r.clear, r.t_i, r.t_c
    jf = SimpleNamespace(pk_c=summary_number(r.s_clear, "peak_joint2_force_N"),
                         t_pk_c=summary_number(r.s_clear, "t_peak_joint2_force_s"),
                         pk_i=summary_number(r.s_ideal, "peak_joint2_force_N"),
                         t_pk_i=summary_number(r.s_ideal, "t_peak_joint2_force_s"), src="summary (all sub-steps)")
    pk_c_csv, pk_i_csv = float(np.max(clear["joint2_force_N"])), float(np.max(ideal["joint2_force_N"]))
    if jf.pk_c is None or jf.pk_i is None:
        jf.pk_c, jf.pk_i, jf.src = pk_c_csv, pk_i_csv, "CSV samples"
        jf.t_pk_c = float(t_c[np.argmax(clear["joint2_force_N"])])
        jf.t_pk_i = float(t_i[np.argmax(ideal["joint2_force_N"])])
    jf.ratio = jf.pk_c / jf.pk_i if jf.pk_i > 0 else float("inf")
    if abs(t_i[-1] - t_c[-1]) > 1e-9 * max(1.0, t_i[-1]):
        print(f"WARNING: the runs end at different times (ideal {t_i[-1]:g} s, clearance "
              f"{t_c[-1]:g} s): the joint-force peaks below cover different durations.")
    # The ideal joint force grows with the spin-up; compare also with the ideal
    # force at the moment of the clearance peak.
    # Only inside the ideal run: np.interp held its last value past its end (pass 56: a time it never reached).
    jf.same_t_why = None
    if jf.t_pk_c is not None and not t_i[0] <= jf.t_pk_c <= t_i[-1]:
        jf.same_t_why = f"the ideal run ended at {t_i[-1]:.4g} s, before the clearance peak at {jf.t_pk_c:.4g} s"
    jf.f_i_at_pk = float(np.interp(jf.t_pk_c, t_i, ideal["joint2_force_N"])) \
        if jf.t_pk_c is not None and jf.same_t_why is None else None
    jf.ratio_same_t = jf.pk_c / jf.f_i_at_pk if jf.f_i_at_pk else None

    fig, axes = plt.subplots(1, 2, figsize=(15, 4.8), constrained_layout=True,
                             gridspec_kw={"width_ratios": [1.6, 1.0]})
    same_t_txt = (f"; vs ideal at the same instant {jf.ratio_same_t:.0f}\u00d7"
                  if jf.ratio_same_t is not None else "")
    fig.suptitle(f"Fig. 18  Force transmitted by joint 2: peak clearance / peak ideal = "
                 f"{jf.ratio:.2f}\u00d7 (peaks from {jf.src}){same_t_txt}", fontsize=13)
    for ax, tmax in ((axes[0], t_c[-1]), (axes[1], r.t_zoom)):
        mc, mi = t_c <= tmax, t_i <= tmax
        # Ideal drawn broad and underneath, so the clearance run's thin curve stays
        # visible where the two coincide (continuous contact).
        ax.plot(t_i[mi], ideal["joint2_force_N"][mi], color=C_IDEAL, lw=3.0, alpha=0.6,
                label="ideal joint", zorder=1)
        ax.plot(t_c[mc], clear["joint2_force_N"][mc], color=C_CLEAR, lw=0.7,
                label="clearance joint (CSV samples)", zorder=2)
        if jf.t_pk_c is not None and jf.t_pk_c <= tmax:
            ax.plot([jf.t_pk_c], [jf.pk_c], "v", color="darkred", ms=7,
                    label=f"clearance peak {jf.pk_c:.0f} N at {jf.t_pk_c:.4g} s")
        if jf.t_pk_i is not None and jf.t_pk_i <= tmax:
            ax.plot([jf.t_pk_i], [jf.pk_i], "^", color="navy", ms=7,
                    label=f"ideal peak {jf.pk_i:.0f} N at {jf.t_pk_i:.4g} s")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("|joint 2 force| [N]")
        ax.set_ylim(0, 1.08 * max(jf.pk_c, pk_c_csv))
        ax.grid(True, alpha=0.3)
    axes[0].set_title("whole run")
    axes[1].set_title(f"impact phase 0\u2013{r.t_zoom:.3g} s")
    axes[0].legend(loc="upper right", fontsize=8)
    if jf.f_i_at_pk:
        axes[1].plot([], [], " ", label=f"ideal at clearance-peak time: {jf.f_i_at_pk:.1f} N "
                                         f"(ratio {jf.ratio_same_t:.0f})")
    axes[1].legend(loc="upper right", fontsize=8)
    save(fig, out_dir, "fig18_joint2_force.png", written)
    return jf


def print_summary(r, pk_fn, t_pk_fn, pe, jf, written, out_dir):
    """The text summary on stdout (run_paper.sh keeps it as plot_summary.txt)."""
    clear, t_c, t = r.clear, r.t_c, pe.t
    impacts = summary_number(r.s_clear, "impacts")
    if impacts is None:
        impacts_txt = f"{len(contact_starts(clear))} (counted from CSV samples; short impacts may be missed)"
    else:
        impacts_txt = f"{int(impacts)} (summary)"
    if pk_fn is not None and t_pk_fn is None:  # the summary's peak of a run without contact
        pk_fn_txt = "none: no contact (summary)"
    elif pk_fn is None and not np.max(clear["fn2_N"]) > 0.0:
        pk_fn_txt = "none: no contact in the CSV samples"
    elif pk_fn is None:
        pk_fn_txt = (f"{np.max(clear['fn2_N']):.1f} N at t = {t_c[np.argmax(clear['fn2_N'])]:.4g} s "
                     f"(CSV samples)")
    else:
        pk_fn_txt = f"{pk_fn:.1f} N at t = {t_pk_fn:.4g} s (summary); CSV samples max {np.max(clear['fn2_N']):.1f} N"
    print("gimbalsim paper figures")
    print(f"  clearance c                 : {r.c*1e3:.4g} mm (from {r.c_src})")
    print(f"  peak contact force          : {pk_fn_txt}")
    print(f"  impacts                     : {impacts_txt}")
    if r.t_cont is not None:
        print(f"  continuous contact from     : {r.t_cont:.4g} s")
    print(f"  max pointing error          : {pe.err_max:.4g} rad ({math.degrees(pe.err_max):.4g} deg) "
          f"at t = {pe.t_err_max:.4g} s")
    print(f"  final pointing error        : {pe.err_final:.4g} rad ({math.degrees(pe.err_final):.4g} deg) "
          f"at t = {t[-1]:.4g} s")
    print(f"  joint-2 force peaks         : clearance {jf.pk_c:.1f} N / ideal {jf.pk_i:.1f} N "
          f"= {jf.ratio:.2f} ({jf.src})")
    if jf.ratio_same_t is not None:
        print(f"    vs ideal at the same time : ideal {jf.f_i_at_pk:.1f} N at t = {jf.t_pk_c:.4g} s "
              f"-> ratio {jf.ratio_same_t:.1f}")
    elif jf.same_t_why is not None:
        print(f"    vs ideal at the same time : n/a ({jf.same_t_why})")
    if pe.err_sp is not None:
        tilt = spatial_tilt(r.s_spatial)
        print(f"  spatial joint 2             : pointing error {float(pe.err_sp[-1]):.4g} rad at t = {t[-1]:.4g} s "
              f"(planar {pe.err_final:.4g} rad), max {float(np.max(pe.err_sp)):.4g} rad; largest tilt "
              + (f"{tilt:.4g} rad" if tilt is not None else "not in a summary"))
    print(f"  wrote {len(written)} figures and {pe.path} into {out_dir}")


def output_paths(a):
    """Every file the run writes into --out, checked before anything is read."""
    names = (["fig06_eccentricity.png", "fig07_contact_force.png"] + [f[0] for f in COMPONENT_FIGURES]
             + ["fig17_pointing_error.png", "pointing_error.csv", "fig18_joint2_force.png"]
             + (["fig19_joint_kinds.png"] if a.spatial else []))
    return [os.path.join(a.out, n) for n in names]


def main(argv=None):
    a = parse_args(argv)
    if not os.path.isdir(a.out):  # no program makes a folder it is given (docs/usage.md "Output files")
        raise Refused(f"--out {a.out}: " + ("not a folder" if os.path.exists(a.out) else "no such folder (create it first)"))
    if os.path.islink(a.out.rstrip("/") or "/"):  # (pass 71) its figures went through the link, elsewhere
        raise Refused(f"--out {a.out}: a symbolic link; not written through: name the folder itself")
    inputs = [a.ideal, a.clearance, a.ideal_summary, a.clearance_summary, a.spatial, a.spatial_summary]
    check_before_writing(output_paths(a), inputs)
    try:
        r = load_runs(a)
    except InputError as e:
        raise Refused(str(e)) from None
    if r.grid_note:
        print(r.grid_note)
    written = []
    fig_eccentricity(r, a.out, written)
    pk_fn, t_pk_fn = fig_contact_force(r, a.out, written)
    for fname, title, comps, unit, factor, is_angle, spiky in COMPONENT_FIGURES:
        fig_components(lambda fig, name: save(fig, a.out, name, written), fname, title, r.ideal, r.clear,
                       r.ideal_g, r.clear_g, comps, unit, factor, is_angle=is_angle, spiky=spiky)
    pe = fig_pointing_error(r, a, written)
    jf = fig_joint_force(r, a.out, written)
    if r.spatial is not None:
        fig_joint_kinds(lambda fig, name: save(fig, a.out, name, written), pe.t, pe.err, pe.err_sp, r.clear,
                        r.spatial, r.s_spatial, r.c, C_CLEAR)
    print_summary(r, pk_fn, t_pk_fn, pe, jf, written, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(run_script("plot_paper.py", main, whole_set=True))
