#!/usr/bin/env python3
"""Checkpoint and replay: save the state in the middle of an impact, run on,
then restore the pickled checkpoint in a new process-independent Simulator
and replay: the same bits.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/checkpoint_replay.py
"""
import pathlib
import pickle

import numpy as np

import gimbalsim

ROOT = pathlib.Path(__file__).resolve().parents[2]
scene = gimbalsim.load_scene(ROOT / "tools" / "scenes" / "paper_clearance.yaml")
sim = gimbalsim.Simulator(scene)
while not sim.state.in_contact:  # step until the journal hits the bearing
    sim.step(5.0, 10.0)
blob = pickle.dumps((scene, sim.state))
print(f"checkpoint at t = {sim.t:.3f} s, in contact, {len(blob)} bytes pickled")

tau = np.tile([5.0, 10.0], (500, 1))
first = sim.run(tau)

scene2, state = pickle.loads(blob)
replay = gimbalsim.Simulator(scene2)
replay.state = state
second = replay.run(tau)
print("replay identical bit for bit:", first.tobytes() == second.tobytes())
