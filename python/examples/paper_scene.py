#!/usr/bin/env python3
"""The paper's scene from Python: ideal vs clearance joint, the journal's
eccentricity and the force joint 2 transmits, plotted.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/paper_scene.py [--duration 1] [--out out/py_paper.png]
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import gimbalsim

ROOT = pathlib.Path(__file__).resolve().parents[2]

ap = argparse.ArgumentParser()
ap.add_argument("--duration", type=float, default=1.0, help="simulated time [s]")
ap.add_argument("--out", default="out/py_paper.png")
a = ap.parse_args()

runs = {}
for name in ("paper_ideal", "paper_clearance"):
    scene = gimbalsim.load_scene(ROOT / "tools" / "scenes" / f"{name}.yaml", {"sim.duration": a.duration})
    runs[name] = gimbalsim.simulate(scene)
    s = runs[name].summary
    print(f"{name}: {s['variant']}, {s['rows']} rows, {s['impacts']} impacts, peak joint-2 force "
          f"{s['peak_joint2_force_N']:.1f} N, wall {s['wall_time_s']*1e3:.1f} ms")

fig, ax = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
c = runs["paper_clearance"].columns
ax[0].plot(c["t"], c["ecc2"] * 1e3)
ax[0].set_ylabel("eccentricity [mm]")
for name, run in runs.items():
    ax[1].plot(run.columns["t"], run.columns["joint2_force"], label=name)
ax[1].set_ylabel("joint 2 force [N]")
ax[1].set_xlabel("t [s]")
ax[1].legend()
out = pathlib.Path(a.out)
out.parent.mkdir(parents=True, exist_ok=True)
fig.savefig(out, dpi=120)
print(f"wrote {out}")
