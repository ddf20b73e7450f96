"""Fig 19 of the main job (tools/paper/plot_paper.py --spatial): the paper's scene
with joint 2 ideal, planar and spatial clearance (the journal may tilt):
pointing error against the ideal joint, mid-plane eccentricity, largest tilt."""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def spatial_tilt(summary):
    """Largest tilt of joint 2 [rad] from a summary's clearance_joints, or None."""
    try:
        return float(summary["clearance_joints"]["joint2"]["max_tilt_rad"])
    except (TypeError, KeyError, ValueError):
        return None


def fig_joint_kinds(save, t, err_planar, err_spatial, clear, spatial, s_spatial, c, color_planar):
    """Fig 19 through save(fig, name): t [s] and the pointing errors against the
    ideal joint [rad] on one grid, the planar and spatial runs' columns, the
    spatial run's summary (or None), the clearance c [m]."""
    C_CLEAR, C_SPATIAL = color_planar, "tab:green"
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(15, 4.8), constrained_layout=True)
    tilt = spatial_tilt(s_spatial)
    tilt_txt = f"; largest tilt of the spatial journal {tilt:.3g} rad" if tilt is not None else ""
    fig.suptitle("Fig. 19  Joint 2 ideal, planar clearance, spatial clearance (the journal may tilt)"
                 + tilt_txt, fontsize=13)
    ax1.set_yscale("log")
    for e, color, name in ((err_planar, C_CLEAR, "planar clearance"), (err_spatial, C_SPATIAL, "spatial clearance")):
        pos = e > 0.0  # a log axis cannot show exact zeros (e.g. t = 0)
        ax1.plot(t[pos], e[pos], color=color, lw=1.0, label=f"{name}: {float(e[-1]):.3g} rad at {t[-1]:.3g} s")
    ax1.set_xlabel("t [s]")
    ax1.set_ylabel("pointing error against the ideal joint [rad]")
    ax1.set_title("antenna boresight against the ideal joint's")
    ax1.grid(True, which="both", alpha=0.3)
    ax1.legend(loc="lower right", fontsize=9)
    ax2.plot(clear["t_s"], clear["ecc2_m"] * 1e3, color=C_CLEAR, lw=0.7, label="planar clearance")
    ax2.plot(spatial["t_s"], spatial["ecc2_m"] * 1e3, color=C_SPATIAL, lw=0.7, label="spatial: at the mid-plane")
    ax2.axhline(c * 1e3, color="k", ls="--", lw=1.0, label=f"clearance c = {c*1e3:.3g} mm")
    ax2.set_xlabel("t [s]")
    ax2.set_ylabel("journal eccentricity [mm]")
    ax2.set_title("journal centre (a tilted journal touches at the bearing's ends)")
    ax2.grid(True, alpha=0.3)
    ax2.legend(loc="lower right", fontsize=8)
    save(fig, "fig19_joint_kinds.png")


if __name__ == "__main__":  # (pass 79) run alone it took any arguments, did nothing and exited 0
    print("plot_joint_kinds.py: error: a module of tools/paper/plot_paper.py, not a program: "
          "run plot_paper.py --spatial, which draws this figure", file=sys.stderr)
    sys.exit(2)
