#!/usr/bin/env python3
"""A closed loop with a controller written in Python: a PD law on the joint
angles, stepping the clearance scene's plant one control period at a time,
then the same slew with the project's own controller (closed_loop) for scale.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/python_controller.py
"""
import pathlib

import numpy as np

import gimbalsim

ROOT = pathlib.Path(__file__).resolve().parents[2]
scene = gimbalsim.load_scene(ROOT / "tools" / "scenes" / "paper_clearance.yaml")
sim = gimbalsim.Simulator(scene)

target = np.array([0.3, -0.2])          # joint angles [rad]
kp, kd = np.array([400.0, 400.0]), np.array([80.0, 80.0])  # [N m/rad], [N m s/rad]
period = 1.0e-3                          # control period [s], a multiple of sim.step
steps = round(period / sim.step_size)
errors = []
for _ in range(round(2.0 / period)):
    y = sim.output()
    theta = np.array([y["theta1"], y["theta2"]])
    rate = np.array([y["dtheta1"], y["dtheta2"]])
    tau = np.clip(kp * (target - theta) - kd * rate, -50.0, 50.0)
    sim.step(tau[0], tau[1], n=steps)
    errors.append(np.abs(target - theta).max())
print(f"Python PD: joint error {errors[0]:.3f} rad at start, {errors[-1]:.2e} rad after {sim.t:.1f} s; "
      f"eccentricity now {sim.output()['ecc2']*1e3:.3f} mm")

run = gimbalsim.closed_loop(scene, gimbalsim.Controller(ROOT / "controllers" / "config" / "default.yaml"), 2.0)
err = run.columns["truth_error"]
print(f"project controller (inertial pointing, its own profile): truth pointing error {err.max():.2e} rad at "
      f"most, {err[-1]:.2e} rad at the end of {run.summary['ticks']} ticks")
