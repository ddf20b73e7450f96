"""How a closed-loop sweep's samples step the plant (the spec's `sampling:`,
docs/python.md "Sampling"): `auto` (the default) or `scene` (the scene's own
stepping, as it is written).

`auto` steps each sample with the cheapest setting the work-precision
measurements found to keep the figures the sweep reads (each index in each
phase) within TOLERANCE_RAD of a fine run's (a 5 us fixed sub-step of the
scene's own law; tests/python/test_sampling.py), and never changes a scene
whose fastest accurate setting is its own. Over the whole shipped budget
(tools/sweeps/budget_speed.py, docs/results/budget_speed.md) every index
lies within the fine run's order-statistics interval and 52 of 13308 unit
figures lie beyond TOLERANCE_RAD, at most 2.8e-6 rad; 33 of those 52 are
not defined to it (the fine run itself moves them beyond it when the
journal starts 1e-12 m away: tools/sweeps/unit_conditioning.py), 9 more
are not settled by the fine run (its own figure moves beyond it at 2.5,
1.25 or 0.3125 us), and 10 the sampling moved. No sampling holds every
unit: at ADAPTIVE_TOL 1e-10, 49 figures lie beyond it (22 of them ones
1e-9 held), and the default's own law at the fine 5 us fixed sub-step differs
from the fine run in 43 figures (at most 2.5e-6 rad): near a branch point
two accurate steppings of the loop part by that much.

- a planar bearing in joint 2 alone (joint 1 ideal) with plain Coulomb
  friction under the fixed sub-step policy: its set-valued Coulomb law with
  located stick and slip (`coulomb_stick`, the law plain Coulomb's chatter
  converges to as the sub-step shrinks; docs/MODEL.md 6.2, 6.4) under the
  adaptive policy at ADAPTIVE_TOL;
- a spatial bearing in joint 2 alone (the bearing that tilts) with plain
  Coulomb friction under the fixed sub-step policy, the loop on the
  encoders or at the antenna (sensors.antenna none or tracker_gyro): fixed
  sub-steps of SPATIAL_SUBSTEP_S, when the scene's are finer. There the
  tolerance is the budget's: every index of each shipped spatial budget
  within a 5 us fixed sub-step's order-statistics interval
  (tools/sweeps/budget_speed.py, docs/results/budget_speed_spatial.md and
  budget_speed_spatial_tracker.md), not TOLERANCE_RAD per unit. On the
  encoders the hold and track figures are not defined to it (the loop is
  chaotic there: a 1e-12 m nudge of the journal moves them by up to
  1.7e-4 rad); the slew's are, though 5 us does not settle all of them.
  At the antenna the figures are defined (the nudges hold them) but the
  scene's own 2e-5 s does not hold them either: over the tracker budget's
  1109 units APE while tracking lies from the 5 us run's a median 1.1e-6
  rad away (max 1.2e-4) at 2e-5 s and 4.1e-6 (max 1.3e-4) at 8e-5 s,
  whose 99.73 % quantiles read up to 4 % high (APE tracking 2.71e-4
  against 2.65e-4 rad).
  There the median figure is held as well: more than half the figures
  within TOLERANCE_RAD of the fine run's (56 % of the tracker budget's
  13308; test_sampling.py holds it on 8 units, where 1.6e-4 s fails it);
- every other scene (ideal joints, both joints with clearance, a bearing in
  joint 1, a smooth law) keeps its own stepping: no cheaper setting has
  been judged there (the Ambrosio law changes the physics).

Nothing is chosen when the spec itself sets or disperses a key the choice
would change (the user asked for that stepping), on a spatial bearing when
it disperses sim.step (set, its value decides), or in
open loop (its figures include contact forces the tolerance does not speak
for). Each "why" says what decided.
"""
import gimbalsim

# The keys auto may set, and those whose presence in set:/parameters:/grid: leaves the scene's stepping alone.
_DECIDING = ("friction.law", "joint1.friction.law", "joint2.friction.law", "structure.joint1", "structure.joint2",
             "sim.substep_policy", "sim.substep", "sim.substep_tol", "sim.substep_min", "sim.substep_max",
             "sim.min_substeps_per_impact")  # the fixed policy's: a spec giving it asks for that policy
MODES = ("auto", "scene")
TOLERANCE_RAD = 1.0e-6   # a figure's distance from a 5 us fixed sub-step's (1 % of a 1e-4 rad requirement)
ADAPTIVE_TOL = "1e-9"    # sim.substep_tol of the adaptive policy (tests/python/test_sampling.py measures it)
SPATIAL_SUBSTEP_S = "8e-05"  # [s] a spatial joint 2's fixed sub-step (4x the shipped scene's 2e-5: 3x cheaper)


def choose(mode, scene_values, given, closed, varied=()):
    """(overrides, why): the scene overrides every sample steps with, and the
    sentence the report prints. scene_values: the base scene's values (as
    text, the spec's set: in them); given: the canonical keys the spec sets
    or disperses; varied: those it disperses (each sample's own value)."""
    if mode == "scene":
        return {}, "the scene's own stepping (sampling: scene)"
    if not closed:
        return {}, "the scene's own stepping (an open-loop sweep: sampling: auto chooses for closed loops only)"
    asked = sorted(k for k in given if k in _DECIDING)
    if asked:
        return {}, f"the scene's own stepping: the spec gives {', '.join(asked)}"
    j1, j2 = scene_values.get("structure.joint1"), scene_values.get("structure.joint2")
    law_key = "joint2.friction.law" if "joint2.friction.law" in scene_values else "friction.law"
    law, policy = scene_values.get(law_key), scene_values.get("sim.substep_policy")
    if j1 == "ideal" and j2 in ("planar", "clearance") and law == "coulomb" and policy == "fixed":
        overrides = {law_key: "coulomb_stick", "sim.substep_policy": "adaptive", "sim.substep_tol": ADAPTIVE_TOL}
        return overrides, ("a planar joint 2 with Coulomb friction steps with its set-valued law (" +
                           ", ".join(f"{k} {v}" for k, v in overrides.items()) + "): the shipped budget's "
                           "indices within a 5 us fixed sub-step's intervals, its units' figures within "
                           f"{TOLERANCE_RAD:g} rad but 52 of 13308 (at most 2.8e-6, 42 of them ill-defined or "
                           "unsettled; docs/results/budget_speed.md); "
                           "sampling: scene keeps the scene's")
    if j1 == "ideal" and j2 == "spatial" and law == "coulomb" and policy == "fixed":
        # the base's values are the samples' unless dispersed (pass 38: a sim.step set to the scene's own kept it)
        own = "the scene's own stepping (a spatial joint 2 with Coulomb friction: "
        if "sim.step" in varied:
            return {}, own + f"the spec disperses sim.step; the {SPATIAL_SUBSTEP_S} s sub-step is judged at one)"
        if float(scene_values.get("sim.substep", "0")) >= float(SPATIAL_SUBSTEP_S):
            return {}, own + f"its sim.substep is no finer than {SPATIAL_SUBSTEP_S} s)"
        if float(scene_values.get("sim.step", "0")) < float(SPATIAL_SUBSTEP_S):  # a sub-step fits in a step
            return {}, own + f"its sim.step is finer than the {SPATIAL_SUBSTEP_S} s sub-step)"
        overrides = {"sim.substep": SPATIAL_SUBSTEP_S}
        return overrides, (f"a spatial joint 2 with Coulomb friction steps with fixed sub-steps of "
                           f"{SPATIAL_SUBSTEP_S} s: the shipped spatial budgets' indices (on the encoders, at the "
                           "antenna) within a 5 us fixed sub-step's intervals, not each unit's figure within "
                           "1e-6 rad (at the antenna more than half of them; docs/results/budget_speed_spatial.md, "
                           "budget_speed_spatial_tracker.md); "
                           "sampling: scene keeps the scene's")
    return {}, (f"the scene's own stepping (joints {j1}/{j2}, {law_key} {law}, sim.substep_policy {policy}: "
                "no cheaper setting has been judged there)")


def apply(spec, root, base, given, closed, varied=()):
    """(base, sampling): the spec's `sampling:` read (refused at its line
    unless a mode), its choice made, and the base scene with its overrides;
    sampling = {"mode", "overrides", "why"} for the summary and the report.
    given: the keys the spec sets or disperses; varied: those it disperses."""
    mode = spec.text("sampling", root["sampling"]) if "sampling" in root else "auto"
    if mode not in MODES:
        spec.refuse("sampling", f"expected {' or '.join(MODES)}, got {mode!r}", root["sampling"])
    aliases = gimbalsim.key_aliases()
    overrides, why = choose(mode, base.values(), {aliases.get(k, k) for k in given}, closed,
                            {aliases.get(k, k) for k in varied})
    if overrides:
        try:
            return base.replace(overrides), {"mode": mode, "overrides": overrides, "why": why}
        except gimbalsim.SceneError as e:  # a choice this scene cannot take is no refusal of the user's spec
            why = f"the scene's own stepping: it refuses sampling: auto's {overrides} ({e})"
    return base, {"mode": mode, "overrides": {}, "why": why}
