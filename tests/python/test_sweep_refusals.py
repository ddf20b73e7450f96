"""gimbalsim.sweep's spec refusals: each bad spec is refused with exit 2
before anything runs, naming the spec's line and key and why (a key the
runs would never read, a value that crashed a worker before)."""
import subprocess
import sys

import pytest

from conftest import SCENES
from test_sweep import run_sweep

HEAD = f"scene: {SCENES}/paper_clearance.yaml\nsamples: 3\nseed: 1\n"

BAD = [
    ("parameters:\n  contact.clearance: {triangular: [1, 2]}\n", "parameters.contact.clearance", 7,
     "unknown distribution"),
    ("parameters:\n  contact.clearence: {uniform: [1.0e-4, 2.0e-4]}\n", "parameters.contact.clearence", 7,
     "not a key of the scene"),
    ("parameters:\n  contact.restitution: {uniform: [0.5, 1.5]}\n", "parameters.contact.restitution", 7,
     "the scene refuses"),
    ("parameters:\n  friction.mu: {disk: {radius: 1}}\n", "parameters.friction.mu", 7, "disk needs a vec2 key"),
    # a fraction beside a radius scales nothing: it was read and never acted
    ("parameters:\n  initial.ecc: {disk: {radius: 1.0e-4, fraction: 0.5}}\n", "parameters.initial.ecc", 7,
     "disk expects {radius: r} or {within: key, fraction: f}"),
    ("parameters:\n  friction.mu: {normal: {mean: 0.2, sd: -1}}\n", "parameters.friction.mu", 7, "sd > 0"),
    ("grid:\n  friction.law: [coulomb, sticky]\n", "grid.friction.law", 7, "the scene refuses"),
    ("set: {sim.durration: 2}\nparameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n", "set.sim.durration", 6,
     "not a key of the scene"),
    # a key the open-loop runs never read: recorded as applied, acting on nothing
    ("parameters:\n  sensors.star_tracker_noise: {uniform: [0.0, 1.0e-5]}\n",
     "parameters.sensors.star_tracker_noise", 7, "an open-loop run has no sensors"),
    # keys this scene's structure never reads (they gave equal figures in every row, recorded as applied)
    ("parameters:\n  contact.bearing_length: {uniform: [0.02, 0.05]}\n", "parameters.contact.bearing_length", 7,
     "no joint's bearing is spatial"),
    ("parameters:\n  initial.ecc1: {disk: {radius: 1.0e-5}}\n", "parameters.initial.ecc1", 7, "joint 1 is ideal"),
    ("set: {structure.joint2: ideal}\nparameters:\n  contact.restitution: {uniform: [0.5, 0.9]}\n",
     "parameters.contact.restitution", 8, "both joints are ideal"),
    ("parameters:\n  sim.substep_tol: {choice: [1.0e-8, 1.0e-10]}\n", "parameters.sim.substep_tol", 7,
     "sim.substep_policy is fixed"),
    # the contact's sub-stepping with no contact: every row the same, recorded as applied
    ("set: {structure.joint2: ideal}\nparameters:\n  sim.substep: {uniform: [1.0e-5, 5.0e-5]}\n",
     "parameters.sim.substep", 8, "both joints are ideal: no contact to sub-step"),
    ("set: {structure.joint2: ideal}\nparameters:\n  sim.event_tol: {choice: [1.0e-9, 1.0e-6]}\n",
     "parameters.sim.event_tol", 8, "both joints are ideal: no contact to sub-step"),
    ("set: {structure.base: fixed}\nparameters:\n  base.mass: {uniform: [500, 1500]}\n", "parameters.base.mass", 8,
     "structure.base is fixed"),
    # ... and every other contact-only key: its stops and its work cap
    ("set: {structure.joint2: ideal}\nparameters:\n  sim.penetration_limit: {choice: [0.0, 1.0e-3]}\n",
     "parameters.sim.penetration_limit", 8, "both joints are ideal: no contact, nothing penetrates"),
    ("set: {structure.joint2: ideal}\nparameters:\n  sim.max_event_iters: {choice: [10, 60]}\n",
     "parameters.sim.max_event_iters", 8, "both joints are ideal: no contact to sub-step"),
    ("set: {structure.joint2: ideal}\nparameters:\n  sim.max_substeps: {choice: [0, 100]}\n",
     "parameters.sim.max_substeps", 8, "both joints are ideal: no contact to sub-step"),
    # the invariants an open loop does not check (dynamics/src/invariants.cpp): momentum on a fixed base,
    # the energy balance with a spatial bearing
    ("set: {structure.base: fixed}\nparameters:\n  sim.momentum_tol: {choice: [0.0, 1.0e-300]}\n",
     "parameters.sim.momentum_tol", 8, "structure.base is fixed: no momentum drift is checked"),
    ("set: {structure.joint2: spatial}\nparameters:\n  sim.energy_tol: {choice: [0.0, 1.0e-300]}\n",
     "parameters.sim.energy_tol", 8, "a joint's bearing is spatial: the energy balance is no invariant there"),
    # the scene's label
    ("parameters:\n  name: {choice: [a, b]}\n", "parameters.name", 7, "the scene's label: no run reads it"),
    ("parameters:\n  torque.limit: {choice: [[0.001, 0.001], [1000, 1000]]}\n", "parameters.torque.limit", 7,
     "the firmware's motor limit"),
    # a shared bearing key that every joint with a bearing overrides with its own: recorded, acting on nothing
    ("set: {joint2.contact.clearance: 2.0e-4}\nparameters:\n  contact.clearance: {uniform: [1.0e-4, 3.0e-4]}\n",
     "parameters.contact.clearance", 8, "on every joint with a bearing: overridden by joint2.contact.journal_radius"),
    # initial.ecc where every joint with a bearing has its own initial.eccJ (set, or dispersed too): every row
    # ran the same journal start while recording its draw as applied
    ("set: {initial.ecc2: [1.0e-4, 0]}\nparameters:\n  initial.ecc: {disk: {radius: 3.0e-4}}\n",
     "parameters.initial.ecc", 8, "on every joint with a bearing: overridden by initial.ecc2"),
    ("parameters:\n  initial.ecc: {disk: {radius: 3.0e-4}}\n  initial.ecc2: {disk: {radius: 2.0e-4}}\n",
     "parameters.initial.ecc", 7, "on every joint with a bearing: overridden by initial.ecc2"),
    # ... also when the set one equals initial.ecc (the scene's values leave it out; it was silently dropped)
    ("set: {initial.ecc2: [0.0, 0.0]}\nparameters:\n  initial.ecc: {disk: {radius: 1.0e-4}}\n",
     "parameters.initial.ecc", 8, "on every joint with a bearing: overridden by initial.ecc2"),
    ("set: {joint2.friction.mu: 0.25}\nparameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n",
     "parameters.friction.mu", 8, "on every joint with a bearing: overridden by joint2.friction.mu"),
    ("set: {structure.joint1: planar, initial.ecc1: [0, 1.0e-4]}\nparameters:\n"
     "  initial.ecc: {disk: {radius: 3.0e-4}}\n  initial.ecc2: {disk: {radius: 2.0e-4}}\n",
     "parameters.initial.ecc", 8, "overridden by initial.ecc1; overridden by initial.ecc2"),
    # a key the joint's law does not read (friction.mu under no friction, restitution without damping)
    ("set: {friction.law: none}\nparameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n", "parameters.friction.mu", 8,
     "joint 2's friction.law is none"),
    ("set: {contact.damping: none}\nparameters:\n  contact.restitution: {uniform: [0.5, 0.9]}\n",
     "parameters.contact.restitution", 8, "joint 2's contact.damping is none"),
    ("parameters:\n  friction.v_a: {uniform: [1.0e-5, 1.0e-4]}\n", "parameters.friction.v_a", 7,
     "joint 2's friction.law is coulomb"),
    # every damping law's factor is 0 at restitution 1: the law and its v0 floor act on nothing (pass 56)
    ("set: {contact.restitution: 1}\nparameters:\n  contact.v0_min: {loguniform: [1.0e-6, 1.0e-3]}\n",
     "parameters.contact.v0_min", 8, "joint 2's contact.restitution is 1 (every damping law's factor is 0"),
    ("set: {contact.restitution: 1}\ngrid:\n  contact.damping: [hunt_crossley, flores]\n",
     "grid.contact.damping", 8, "joint 2's contact.restitution is 1"),
    ("parameters:\n  contact.v0_min: {loguniform: [1.0e-6, 1.0e-3]}\n  contact.restitution: {choice: [1, 1.0]}\n",
     "parameters.contact.v0_min", 7, "for every value of contact.restitution the study gives"),
    # a key given under set: that the runs never read, refused as the same key dispersed (the base is fixed)
    ("set: {structure.base: fixed, sim.momentum_tol: 1.0e-6}\n"
     "parameters:\n  contact.clearance: {uniform: [1.0e-4, 3.0e-4]}\n",
     "set.sim.momentum_tol", 6, "not read by this sweep's runs (structure.base is fixed: no momentum drift is "
     "checked): the value given would be recorded but never act"),
    ("set: {sensors.gyro_noise: 1.0e-5}\nparameters:\n  contact.clearance: {uniform: [1.0e-4, 3.0e-4]}\n",
     "set.sensors.gyro_noise", 6, "an open-loop run has no sensors"),
    ("set: {friction.law: none, friction.mu: 0.3}\n"
     "parameters:\n  contact.clearance: {uniform: [1.0e-4, 3.0e-4]}\n",
     "set.friction.mu", 6, "joint 2's friction.law is none"),
    # (pass 72) the law's velocities at friction.mu 0: no friction force, every row alike
    ("set: {friction.law: ambrosio, friction.mu: 0.0}\nparameters:\n  friction.v_a: {uniform: [1.0e-5, 5.0e-5]}\n",
     "parameters.friction.v_a", 8, "joint 2's friction.mu is 0"),
    # (pass 84) ... and the law itself: at friction.mu 0 every law gives no force, coulomb and ambrosio rows alike
    ("set: {friction.mu: 0.0}\ngrid:\n  friction.law: [coulomb, ambrosio]\n",
     "grid.friction.law", 8, "joint 2's friction.mu is 0"),
    # (pass 73) ... and at friction.mu dispersed over zeros only (a grid, a choice): judged for each value
    ("set: {friction.law: ambrosio}\ngrid:\n  friction.mu: [0.0]\nparameters:\n"
     "  friction.v_a: {uniform: [1.0e-5, 5.0e-5]}\n",
     "parameters.friction.v_a", 10, "joint 2's friction.mu is 0.0, for every value of friction.mu the study gives"),
    # (pass 76) ... a range of width 0 is a choice of its one value
    ("set: {friction.law: ambrosio}\nparameters:\n  friction.mu: {uniform: [0.0, 0.0]}\n"
     "  friction.v_a: {uniform: [1.0e-5, 5.0e-5]}\n",
     "parameters.friction.v_a", 9, "joint 2's friction.mu is 0.0, for every value of friction.mu the study gives"),
    ("set: {friction.v_b: 1.0e-3}\nparameters:\n  friction.mu: {choice: [0.0, 0]}\n"
     "  contact.restitution: {uniform: [0.5, 0.9]}\n",
     "set.friction.v_b", 6, "for every value of friction.mu the study gives"),
    # the law itself is read by no run at those values either (pass 84)
    ("set: {friction.law: ambrosio}\nparameters:\n  friction.mu: {choice: [0.0, 0]}\n"
     "  contact.restitution: {uniform: [0.5, 0.9]}\n",
     "set.friction.law", 6, "for every value of friction.mu the study gives"),
    # (pass 74) a shared journal radius under set where joint 2's own clearance is dispersed: recorded, acting
    # on nothing (a clearance and a journal radius give one value)
    ("set: {contact.journal_radius: 0.0095}\nparameters:\n  joint2.contact.clearance: {uniform: [1.0e-4, 3.0e-4]}\n",
     "set.contact.journal_radius", 6, "overridden by joint2.contact.clearance"),
    # a vector on the grid: one text cell for it, two number cells for its applied_ value
    ("grid:\n  torque.limit: [[1, 1], [2, 2]]\n", "grid.torque.limit", 7, "a vec2 key is dispersed under parameters"),
    # the law dispersed too, but over values none of which reads the key
    ("parameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n  friction.law: {choice: [none]}\n",
     "parameters.friction.mu", 7, "joint 2's friction.law is none, for every value of friction.law the study gives"),
    ("parameters:\n  friction.mu: {uniform: [0.1, 0.2]}\ngrid:\n  friction.law: [none]\n",
     "parameters.friction.mu", 7, "for every value of friction.law the study gives"),
    # one key in two spellings inside set: the last one acted, silently
    ("set: {structure.joint1: planar, friction1.mu: 0.1, joint1.friction.mu: 0.3}\n"
     "parameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n",
     "set.joint1.friction.mu", 6, "the same key as set.friction1.mu"),
    # one key in two spellings: both would be recorded while one value acts
    ("parameters:\n  friction1.mu: {uniform: [0.1, 0.2]}\ngrid:\n  joint1.friction.mu: [0.3, 0.4]\n",
     "grid.joint1.friction.mu", 9, "the same key as parameters.friction1.mu"),
    # (pass 100) and one spelling under set, the other dispersed: the loader's order picked one
    ("set: {structure.joint1: planar, joint1.friction.mu: 0.3}\nparameters:\n  friction1.mu: {uniform: [0.15, 0.35]}\n",
     "parameters.friction1.mu", 8, "the same key as set.joint1.friction.mu: give it in one place"),
    # (pass 70) a clearance under set beside a dispersed journal radius: the later spelling won silently; a
    # clearance and a journal radius both inside set
    ("set: {contact.clearance: 2.0e-4}\nparameters:\n  contact.journal_radius: {uniform: [9.7e-3, 9.9e-3]}\n",
     "parameters.contact.journal_radius", 8, "the same quantity as set.contact.clearance"),
    ("set: {joint2.contact.journal_radius: 9.8e-3, joint2.contact.clearance: 2.0e-4}\n"
     "parameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n",
     "set.joint2.contact.clearance", 6, "the same quantity as set.joint2.contact.journal_radius"),
    # a controller key in an open-loop sweep: what it is and where it goes, not "not a key of the scene"
    ("grid:\n  controller.azimuth.kp: [2000.0, 4000.0]\n", "grid.controller.azimuth.kp", 7,
     "a controller key, dispersed only by a closed-loop sweep: name its controller (controller: default or a "
     "configuration file), then give it as controller.<key> under parameters or grid"),
    ("parameters:\n  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}\n", "parameters.controller.azimuth.kp", 7,
     "a controller key, dispersed only by a closed-loop sweep"),
    # (pass 34) draws that cannot differ: three identical units, counted by a budget as three independent ones
    ("parameters:\n  friction.mu: {uniform: [0.2, 0.2]}\n  initial.ecc: {disk: {radius: 0.0}}\n", "samples", 2,
     "a radius of 0, a choice of one): the 3 draws are one unit"),
    ("parameters:\n  friction.mu: {choice: [0.2, 0.2]}\n  contact.restitution: {loguniform: [0.5, 0.5]}\n", "samples",
     2, "each parameter takes one value"),
    # (pass 36) a range one double's step wide: its draws rounded to one value
    ("parameters:\n  friction.mu: {uniform: [2.0e-4, 2.0000000000000003e-4]}\n", "samples", 2,
     "a range of width 0 or narrower than 1e-12 of its ends"),
    ("parameters:\n  friction.mu: {choice: [2.0e-4, 2.0000000000000003e-4]}\n", "samples", 2,  # (pass 37)
     "each parameter takes one value"),
    # (pass 39) a key the scene derives: "the scene gives it no number >= 0 (got None)"
    ("parameters:\n  initial.ecc: {disk: {within: contact.clearance, fraction: 0.5}}\n", "parameters.initial.ecc", 7,
     "is not one of the scene's own values (it derives it from other keys)"),
    # (pass 38) 0.0 and -0.0 are one value; a normal spreads by the ends it draws between, as a range does
    ("parameters:\n  friction.mu: {choice: [0.0, -0.0]}\n", "samples", 2, "each parameter takes one value"),
    ("parameters:\n  contact.clearance: {normal: {mean: 2.0e-4, sd: 1.0e-18}}\n", "samples", 2,
     "a range of width 0 or narrower than 1e-12 of its ends"),
    ("parameters:\n  contact.clearance: {uniform: [1.0e-4, 1.0e-4]}\n"
     "  initial.ecc: {disk: {within: contact.clearance, fraction: 0.0}}\n", "samples", 2,
     "each parameter takes one value"),
    ("grid:\n  friction.mu: [0.1, 0.2]\n", "samples", 2,
     "no parameter is dispersed: the 3 draws at each grid point are one unit"),
    # (pass 41) a bound that is no finite number was said "expects [lo, hi] with lo <= hi"
    ("parameters:\n  friction.mu: {uniform: [0.1, 0x10]}\n", "parameters.friction.mu", 7,
     "uniform expects [lo, hi], two finite numbers: hi got '0x10' (not a number)"),
    ("parameters:\n  friction.mu: {uniform: [0.1, .inf]}\n", "parameters.friction.mu", 7,
     "uniform expects [lo, hi], two finite numbers: hi got inf (not finite)"),
    ("parameters:\n  friction.mu: {loguniform: [-.inf, 0.2]}\n", "parameters.friction.mu", 7,
     "loguniform expects [lo, hi], two finite numbers: lo got -inf (not finite)"),
    ("parameters:\n  friction.mu: {uniform: [0.1, '']}\n", "parameters.friction.mu", 7,
     "hi got '' (not a number)"),
    ("parameters:\n  friction.mu: {uniform: [0.3, 0.2]}\n", "parameters.friction.mu", 7,
     "uniform expects [lo, hi] with lo <= hi, got [0.3, 0.2]"),
    ("parameters:\n  friction.mu: {normal: {mean: .inf, sd: 0.1}}\n", "parameters.friction.mu", 7,
     "normal: mean, sd, min and max must be finite numbers: mean got inf (not finite)"),
]


@pytest.mark.parametrize("tail,key,line,why", BAD, ids=[b[1] + ":" + b[3] for b in BAD])
def test_spec_refusals_name_the_key_and_line(tail, key, line, why, tmp_path):
    head = f"scene: {SCENES}/paper_clearance.yaml\nsamples: 3\nseed: 1\n\n\n"
    (tmp_path / "bad.yaml").write_text(head + tail)
    p = run_sweep(tmp_path / "bad.yaml", tmp_path / "o", check=False)
    assert p.returncode == 2, p.stderr
    assert f"bad.yaml:{line}:" in p.stderr and f"key '{key}'" in p.stderr and why in p.stderr, p.stderr
    assert not (tmp_path / "o" / "results.csv").exists()


CRASHED = [
    ("set: {sim.duration: null}\nparameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n", 4, "set.sim.duration", "null"),
    ("set: {sim.duration: {a: 1}}\nparameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n", 4, "set.sim.duration",
     "a mapping"),
    ("grid:\n  friction.mu: [0.1, null]\n", 5, "grid.friction.mu", "null"),
    ("grid:\n  friction.mu: [0.1, 2024-01-01]\n", 5, "grid.friction.mu", "the scene refuses"),
    ("grid:\n  friction.mu: [0.1, !!binary aGVsbG8=]\n", 5, "grid.friction.mu", "unsupported tag"),
    ("grid:\n  friction.mu: [0.1, !!timestamp 2024-01-01]\n", 5, "grid.friction.mu", "unsupported tag"),
    ("grid:\n  friction.mu: [0.1, {a: 1}]\n", 5, "grid.friction.mu", "a mapping"),
    ("parameters:\n  friction.law: {choice: [coulomb, !custom x]}\n", 5, "parameters.friction.law.choice",
     "unsupported tag"),
    ("parameters:\n  friction.mu: {choice: [0.1, null]}\n", 5, "parameters.friction.mu", "null"),
    ("parameters:\n  friction.mu: {choice: [0.1, {a: 1}]}\n", 5, "parameters.friction.mu", "a mapping"),
    ("parameters:\n  friction.mu: !!python/object:os.system {uniform: [0.1, 0.2]}\n", 5, "parameters.friction.mu",
     "unsupported tag"),
    ("set: {sim.duration: !!int x}\nparameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n", 4, "set.sim.duration",
     "does not read"),
    # the scene gives no contact.clearance (journal_radius instead): a disk within it has no radius
    ("set: {contact.journal_radius: 9.0e-3}\nparameters:\n  initial.ecc: {disk: {within: contact.clearance}}\n", 6,
     "parameters.initial.ecc", "not dispersed"),
]


@pytest.mark.parametrize("tail,line,key,why", CRASHED, ids=[c[2] + ":" + c[3] for c in CRASHED])
def test_spec_values_that_crashed_are_refused_before_anything_runs(tail, line, key, why, tmp_path):
    (tmp_path / "bad.yaml").write_text(HEAD + tail)
    p = run_sweep(tmp_path / "bad.yaml", tmp_path / "o", check=False)
    assert p.returncode == 2, p.stderr
    assert f"bad.yaml:{line}:" in p.stderr and f"key '{key}'" in p.stderr and why in p.stderr, p.stderr
    assert "Traceback" not in p.stderr and not (tmp_path / "o").exists()


def test_a_spec_that_is_not_utf8_is_refused_at_its_line(tmp_path):
    (tmp_path / "bad.yaml").write_bytes(HEAD.encode() + b"parameters:\n  friction.mu: {uniform: [0.1, 0.\xe92]}\n")
    p = run_sweep(tmp_path / "bad.yaml", tmp_path / "o", check=False)
    assert p.returncode == 2 and "bad.yaml:5:" in p.stderr and "not UTF-8" in p.stderr, p.stderr
    assert not (tmp_path / "o").exists()


# initial.ecc still acts: on joint 1 when it has a bearing of its own without initial.ecc1, and on joint 2
# when it has no initial.ecc2 of its own.
# (joint 1 is given a bearing for its own initial.ecc1: on an ideal joint the set key would act on nothing)
ECC_ACTS = ["{structure.joint1: planar, initial.ecc2: [1.0e-4, 0]}",
            "{structure.joint1: planar, initial.ecc1: [1.0e-4, 0]}"]


@pytest.mark.parametrize("set_", ECC_ACTS)
def test_a_shared_eccentricity_a_joint_reads_is_accepted(set_, tmp_path):
    from gimbalsim.sweep import SweepSpec
    (tmp_path / "s.yaml").write_text(HEAD + f"set: {set_}\nparameters:\n  initial.ecc: {{disk: {{radius: 5.0e-5}}}}\n")
    spec = SweepSpec(tmp_path / "s.yaml")
    j = 2 if "initial.ecc1" in set_ else 1
    draw = spec.design.draw(0)["initial.ecc"]
    values = spec.base.replace({"initial.ecc": draw}).values()  # a sample's scene, as a worker loads it
    # joint j's eccentricity is listed only where the scene or set gave it: here it is the draw
    assert f"initial.ecc{j}" not in values
    assert [float(x) for x in values["initial.ecc"].strip("[]").split(",")] == list(draw)


def test_a_sample_keeps_the_joints_own_key_set_equal_to_the_shared_one(tmp_path):
    # set's initial.ecc2 equals initial.ecc, so the scene's values leave it out: a sample's scene, loaded from
    # them with the drawn initial.ecc, gave joint 2 the draw. Joint 1 reads the draw, joint 2 keeps [0, 0].
    from gimbalsim._closed_sample import load_sample
    from gimbalsim.sweep import SweepSpec
    (tmp_path / "s.yaml").write_text(HEAD + "set: {structure.joint1: planar, initial.ecc2: [0.0, 0.0]}\n"
                                     "parameters:\n  initial.ecc: {disk: {radius: 5.0e-5}}\n")
    spec = SweepSpec(tmp_path / "s.yaml")
    draw = spec.design.draw(0)
    scene, _, loaded = load_sample(spec.base, None, draw)  # as a worker loads it
    values = scene.values()
    assert values["initial.ecc2"] == "[0, 0]", values
    assert [float(x) for x in values["initial.ecc"].strip("[]").split(",")] == list(draw["initial.ecc"])
    assert loaded["applied"][-1] == ""  # the draw applied as drawn


def test_a_joints_own_key_in_the_scene_file_equal_to_the_shared_one_keeps_its_joint(tmp_path):
    # The scene file itself gives initial.ecc2 equal to initial.ecc: the scene's values dropped it, so a
    # drawn initial.ecc reached joint 2 too. Dispersing initial.ecc now acts on joint 1 only.
    from gimbalsim._closed_sample import load_sample
    from gimbalsim.sweep import SweepSpec
    text = (SCENES / "paper_both_planar.yaml").read_text()
    assert "\ninitial:\n" in text
    (tmp_path / "own.yaml").write_text(text.replace("\ninitial:\n", "\ninitial:\n  ecc2: [0, 0]\n", 1))
    (tmp_path / "s.yaml").write_text("scene: own.yaml\nsamples: 3\nseed: 1\n"
                                     "parameters:\n  initial.ecc: {disk: {radius: 5.0e-5}}\n")
    spec = SweepSpec(tmp_path / "s.yaml")
    draw = spec.design.draw(0)
    scene, _, loaded = load_sample(spec.base, None, draw)
    values = scene.values()
    assert values["initial.ecc2"] == "[0, 0]", values
    assert [float(x) for x in values["initial.ecc"].strip("[]").split(",")] == list(draw["initial.ecc"])
    assert loaded["applied"][-1] == ""
    # and with joint 1 ideal, initial.ecc acts on no journal: refused at its line
    (tmp_path / "own1.yaml").write_text(text.replace("\ninitial:\n", "\ninitial:\n  ecc2: [0, 0]\n", 1)
                                        .replace("joint1: planar", "joint1: ideal", 1))
    (tmp_path / "s1.yaml").write_text("scene: own1.yaml\nsamples: 3\nseed: 1\n"
                                      "parameters:\n  initial.ecc: {disk: {radius: 5.0e-5}}\n")
    p = run_sweep(tmp_path / "s1.yaml", tmp_path / "o1", check=False)
    assert p.returncode == 2 and "s1.yaml:5:" in p.stderr and "initial.ecc" in p.stderr, p.stderr


@pytest.mark.parametrize("module", ["gimbalsim.sweep", "gimbalsim.tune"])
def test_a_spec_path_that_is_no_file_says_what_it_is(module, tmp_path):
    # "not a readable file" said neither that the file was missing nor that the path was a folder or a device
    cases = [(tmp_path / "none.yaml", "none.yaml: cannot open spec file: No such file or directory"),
             (tmp_path, f"{tmp_path}: a folder; expected a spec file"),
             ("/dev/null", "/dev/null: not a regular file (a pipe or a device); expected a spec file")]
    for path, message in cases:
        p = subprocess.run([sys.executable, "-m", module, str(path), "--out", str(tmp_path / "o")],
                           capture_output=True, text=True, timeout=120)
        assert p.returncode == 2 and message in p.stderr, (path, p.stderr)
        assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("batch", ["99999999999", "10000001", "0"])
def test_a_batch_outside_its_range_is_refused_and_help_gives_the_range(batch, tmp_path):
    # --batch 99999999999 was taken (only >= 1 was checked), and --help gave no range
    from gimbalsim.sweep import MAX_SAMPLES
    (tmp_path / "s.yaml").write_text(HEAD + "parameters:\n  contact.clearance: {uniform: [1.0e-4, 3.0e-4]}\n")
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(tmp_path / "s.yaml"), "--out",
                        str(tmp_path / "o"), "--batch", batch, "--no-progress"], capture_output=True, text=True,
                       timeout=120)
    assert p.returncode == 2 and f"--batch must be in [1, {MAX_SAMPLES}]" in p.stderr, p.stderr
    assert not (tmp_path / "o").exists()
    h = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", "--help"], capture_output=True, text=True,
                       timeout=60)
    assert f"samples per task, in [1, {MAX_SAMPLES}]" in " ".join(h.stdout.split()), h.stdout


# The damping's keys act where some restitution given is below 1: a choice with one, a range, the scene's 0.95.
@pytest.mark.parametrize("tail", ["  contact.restitution: {choice: [1, 0.9]}\n",
                                  "  contact.restitution: {uniform: [0.9, 1.0]}\n", ""])
def test_the_damping_floor_is_accepted_where_a_restitution_below_one_reads_it(tail, tmp_path):
    from gimbalsim.sweep import SweepSpec
    (tmp_path / "s.yaml").write_text(HEAD + "parameters:\n  contact.v0_min: {loguniform: [1.0e-6, 1.0e-3]}\n" + tail)
    assert "contact.v0_min" in [p.key for p in SweepSpec(tmp_path / "s.yaml").parameters]


@pytest.mark.parametrize("module", ["sweep", "tune", "allocate"])
def test_an_empty_spec_or_path_is_refused_not_read_as_the_folder_one_stands_in(module, tmp_path):
    # (pass 87) "" read the current folder: a replay of the sweep one stood in, "a folder" for a spec or a scene
    p = subprocess.run([sys.executable, "-m", f"gimbalsim.{module}", "", "--out", "x"], capture_output=True,
                       text=True, timeout=60, cwd=tmp_path)
    assert p.returncode == 2 and "argument spec: an empty path" in p.stderr, p.stderr
    spec = tmp_path / "s.yaml"
    spec.write_text('scene: ""\nsamples: 2\nseed: 1\nparameters:\n  contact.clearance: {uniform: [1.0e-4, 2.0e-4]}\n')
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", "o", "--check"],
                       capture_output=True, text=True, timeout=60, cwd=tmp_path)
    assert p.returncode == 2 and "key 'scene': an empty path '': name a file" in p.stderr, p.stderr
    assert sorted(x.name for x in tmp_path.iterdir()) == ["s.yaml"]
