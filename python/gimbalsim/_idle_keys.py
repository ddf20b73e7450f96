"""Keys a run never reads: a dispersed value of one would be recorded as
applied while it acts on nothing, so sweeps and tuning studies refuse it at
its line. A key is judged under every value the study gives the settings
that decide it (a choice, a grid); a decider drawn from a range is not
judged, and neither is the key, except the sensors' sample instants, judged
over every value drawn (_idle_sensors._every_sample_lost)."""
import functools
import itertools
import math
import re

import yaml

from . import _gimbalsim
from ._closed_spec import CONTROLLER_PREFIX
from ._idle_antenna import ANTENNA_TRACKER, idle_at_antenna, open_at_antenna
from ._idle_estimate import idle_estimate
from ._idle_sensors import ANTENNA_NOISE_KEYS, NOISE_KEYS, TRUTH_ONLY, Span, _Given, idle_in_sensors, idle_on_fixed_base
from ._idle_outage import OUTAGE_DECIDERS, idle_outage
from .indices import seconds

# What a closed loop never reads, and what an open-loop run never reads.
# The scene keys and controller keys the C++ closed loop never reads are its own lists (firmware_sim
# closedLoopIdleSceneKeys, closedLoopIdleControllerKeys), which the study programs refuse too; a study adds the
# length it sets itself.
CLOSED_LOOP_IDLE = {"sim.duration": "every closed loop of a study runs one length: a sweep's set: sim.duration, "
                                    "a tuner's duration:",
                    **dict(_gimbalsim._closed_loop_idle_scene_keys()),
                    **{CONTROLLER_PREFIX + k: why for k, why in _gimbalsim._closed_loop_idle_controller_keys()}}
OPEN_LOOP_IDLE = {"torque.limit": "the firmware's motor limit: an open-loop run applies the scene's torques as "
                  "they are"}
# Read by no run of either kind.
ALWAYS_IDLE = {"name": "the scene's label: no run reads it"}

# Controller keys read only under settings of others: the controller library's one table
# (controllers/src/key_use.cpp), key (or prefix ending in ".") -> conditions that must all hold; a condition is a
# list of (that key, the values that read it), any one of which will do.
CONTROLLER_READ_UNDER = _gimbalsim._controller_read_rules()
FEEDFORWARD_KEY = CONTROLLER_PREFIX + "pointing.accel_feedforward"


def idle_in_controller(key, values, dispersed):
    """Why a controller key cannot act with these settings (None if it can):
    one of its conditions holds for no value the configuration has (a decider
    in `dispersed` is not judged)."""
    rules = CONTROLLER_READ_UNDER.get(key) or CONTROLLER_READ_UNDER.get(key[:key.find(".") + 1], [])
    for alternatives in rules:
        if any(d in dispersed or str(values.get(d)) in reading for d, reading in alternatives):
            continue
        return "the controller reads it only with " + " or with ".join(
            f"{d} {' or '.join(reading)}" for d, reading in alternatives) + "; it has " + \
            ", ".join(f"{d} {values.get(d)}" for d, _ in alternatives)
    return None


# The settings that switch other keys off.
_DECIDERS = re.compile(r"structure\..*|sim\.substep_policy|(joint[12]\.)?(friction\.law|contact\.damping)|"
                       r"sensors\.(star_)?tracker_(outage|latency)|sensors\.antenna")
_CONTROLLER_DECIDERS = {CONTROLLER_PREFIX + d for rules in CONTROLLER_READ_UNDER.values() for c in rules
                        for d, _ in c} | {ANTENNA_TRACKER}
_MAX_COMBINATIONS = 256  # of the deciders' values: beyond it nothing is judged
# Numbers that decide a few keys only (_READ_UNDER): the keys (by their ends), the number's key.
_NUMBER_DECIDERS = ((("contact.v0_min", "contact.damping"), "contact.restitution"),
                    (("friction.v_a", "friction.v_b", "friction.law"), "friction.mu"))


def _for_every_value(judge, key, values, dispersed, takes, own_deciders=()):
    """judge(key, values, dispersed) under each combination of the values the
    dispersed deciding settings take (a choice, a grid): why the key acts
    under none of them, or None as soon as one reads it. A decider drawn from
    no list cannot be judged, and neither can the key (judge exempts it).
    own_deciders: settings that decide this key only (sensors.seed's noises:
    as deciders of every key, one drawn from a range would stop all judging)."""
    deciders = sorted(k for k in dispersed if _DECIDERS.fullmatch(k) or k in _CONTROLLER_DECIDERS or
                      k in own_deciders)
    lists = [takes.get(k) for k in deciders]
    if not deciders or any(not isinstance(v, list) for v in lists) or math.prod(map(len, lists)) > _MAX_COMBINATIONS:
        return judge(key, values, dispersed)
    rest, why = dispersed - set(deciders), None
    for combination in itertools.product(*lists):
        why = judge(key, {**values, **dict(zip(deciders, combination))}, rest)
        if why is None:
            return None
    return f"{why}, for every value of {', '.join(deciders)} the study gives"


def _idle_play_guard(key, values, dispersed, takes):
    """Why a dispersed <axis>.play_inertia cannot act: off the antenna's
    loop the guard only lowers the axis's rate gain to min(kd, g play_inertia
    / Ts) (g: play_guard.hpp's kPlayRateGainEncoders, read from the module), kd
    itself for every value given that is 0 (no guard) or at least kd Ts / g: those
    values all run alike. Judged with kd and the period fixed and two values or more (a fixed value is a
    setting: 5 runs as 0 does, not as the default 0.1); whether a smaller value acts is the run's motion
    (the guard's evidence), not the configuration's: not judged."""
    axis = next((a for a in ("azimuth", "elevation") if key == f"{CONTROLLER_PREFIX}{a}.play_inertia"), None)
    kd_key, period_key = f"{CONTROLLER_PREFIX}{axis}.kd", CONTROLLER_PREFIX + "control.period"
    if axis is None or open_at_antenna(values, dispersed) is None or {kd_key, period_key} & dispersed:
        return None
    # Values compared with each other: a fixed value (or an allocation's one-point grid) is a setting the
    # run reads (0 turns the guard off), whatever it equals
    t = takes.get(key) if key in dispersed else None
    try:
        given = [(t.lo, t.hi)] if isinstance(t, Span) else [(float(v), float(v)) for v in t]
        kd, period = float(values[kd_key]), float(values[period_key])
    except (KeyError, TypeError, ValueError):
        return None
    if not isinstance(t, Span) and len(set(given)) < 2:
        return None
    gain = _gimbalsim._PLAY_RATE_GAIN_ENCODERS
    floor = kd * period / gain
    if all(lo == hi == 0.0 or lo >= floor * (1.0 + 1e-9) for lo, hi in given):  # (not at the floor: rounding)
        return (f"the loop does not close at the antenna, where the guard only caps the rate gain at {gain:g} "
                f"play_inertia / control.period; at {kd_key} {kd!r} N m s/rad and {period_key} {period!r} s that "
                f"cap is kd itself from play_inertia {floor!r} kg m^2 up, and 0 turns the guard off: every value "
                "given steps with kd")
    return None


def _feedforwards_alike(key, values, dispersed, takes):
    """Why pointing.accel_feedforward's value inertial cannot act as given: in pointing.mode joint the inertial
    feed-forward takes the profile's acceleration, as profile does (controllers/src/inertial_reference.cpp):
    recorded as inertial, run as profile (pass 59 dispersed, pass 99 set; pointing_controller refuses it as
    key_use.cpp's controllerValueRunsAsAnother). Judged for every mode the study gives."""
    mode_key = CONTROLLER_PREFIX + "pointing.mode"
    if key != FEEDFORWARD_KEY:
        return None
    modes = takes.get(mode_key) if mode_key in dispersed else [values.get(mode_key)]
    given = takes.get(key) if key in dispersed else [values.get(key)]
    if not isinstance(given, list) or not isinstance(modes, list) or any(str(m) != "joint" for m in modes) or \
            "inertial" not in given:
        return None
    if set(given) == {"inertial", "profile"}:
        return ("with pointing.mode joint the inertial feed-forward takes the profile's joint acceleration, as "
                "profile does: every value given runs alike")
    return ("with pointing.mode joint the inertial feed-forward takes the profile's joint acceleration: "
            "inertial runs as profile")


def _idle_in_controller_keys(key, values, dispersed):
    """idle_in_controller on the study's controller.* names."""
    if not key.startswith(CONTROLLER_PREFIX):
        return None
    strip = lambda k: k[len(CONTROLLER_PREFIX):]  # noqa: E731
    return idle_in_controller(strip(key), {strip(k): v for k, v in values.items() if k.startswith(CONTROLLER_PREFIX)},
                              {strip(k) for k in dispersed if k.startswith(CONTROLLER_PREFIX)})


def takes_of(parameters, grid, aliases, prefix=""):
    """The values each dispersed key takes, by canonical name (prefix + key):
    a list (a choice, a grid), a Span for a number drawn from a range (its
    ends), None otherwise (a ball, a disk)."""
    def taken(p):
        if p.kind == "choice":
            return [str(v) for v in p.args]
        if p.kind in ("uniform", "loguniform", "normal"):
            ends = [float(v) for v in p.extremes()]
            # a range of width 0 draws its one value: judged as a choice of it (pass 76: friction.mu [0, 0])
            return Span(min(ends), max(ends)) if p.spreads() else [str(ends[0])]
        return None
    takes = {prefix + aliases.get(p.key, p.key): taken(p) for p in parameters}
    takes.update({prefix + aliases.get(k, k): [str(v) for v in values] for k, values in grid})
    return takes


def idle_reason(key, values, dispersed, takes, closed, unread_ticks=TRUTH_ONLY):
    """Why the dispersed `key` (canonical; controller keys as controller.*)
    cannot act in this study, or None. values: the scene's and (closed loop)
    the controller's (as controller.*), as text; unread_ticks: how many of
    the run's last ticks' measurements no figure reads (_idle_sensors)."""
    # the restitution decides only the damping's keys, friction.mu only Ambrosio's speeds (a grid of zeros
    # recorded them as applied, pass 73): as deciders of every key, one drawn from a range would stop all judging
    decider = next((d for ends, d in _NUMBER_DECIDERS if key.endswith(ends)), None)
    own = tuple(p + decider for p in ("", "joint1.", "joint2.")) if decider else ()
    why = ALWAYS_IDLE.get(key) or (CLOSED_LOOP_IDLE if closed else OPEN_LOOP_IDLE).get(key) or \
        _for_every_value(_idle_in_scene, key, values, dispersed, takes, own)
    if why is None and closed:
        why = _for_every_value(_idle_in_controller_keys, key, values, dispersed, takes) or \
            _for_every_value(functools.partial(idle_in_sensors, takes=takes, unread_ticks=unread_ticks), key, values,
                             dispersed, takes,
                             NOISE_KEYS + ANTENNA_NOISE_KEYS if key == "sensors.seed" else ()) or \
            _for_every_value(idle_on_fixed_base, key, values, dispersed, takes) or \
            _for_every_value(functools.partial(idle_estimate, truth_only=unread_ticks == TRUTH_ONLY), key, values,
                             dispersed, takes) or \
            _for_every_value(functools.partial(idle_outage, unread=unread_ticks, takes=takes), key, values, dispersed,
                             takes, OUTAGE_DECIDERS.get(key, ()))
    if why is None and closed:
        why = _idle_after_the_run(key, values, dispersed, takes) or _idle_motor_limit(key, values, dispersed, takes)
    if why is None and closed:
        why = _for_every_value(idle_at_antenna, key, values, dispersed, takes) or \
            _for_every_value(functools.partial(_idle_play_guard, takes=takes), key, values, dispersed, takes) or \
            _feedforwards_alike(key, values, dispersed, takes)
    if why is None and not closed and key.startswith("sensors."):
        why = "an open-loop run has no sensors (they act in a closed-loop sweep: name its controller)"
    return why


# The profile's segments (dynamics/pointing/src/target_profile.cpp): a key shapes the reference only from the
# start of its segment on, slew_start for the slew's keys, slew_start + slew_time + hold_time for the hold's
# length and the track's keys; before it every value gives the same reference (profile.start always acts).
_PROFILE = CONTROLLER_PREFIX + "profile."
_SLEW_BEGINS = ("slew_start",)
_TRACK_BEGINS = ("slew_start", "slew_time", "hold_time")
_SEGMENT_BEGINS = {"slew_start": _SLEW_BEGINS, "slew_time": _SLEW_BEGINS, "slew_target": _SLEW_BEGINS,
                   "hold_time": _TRACK_BEGINS, "track_rate": _TRACK_BEGINS, "track_ramp_time": _TRACK_BEGINS,
                   "track_amplitude": _TRACK_BEGINS, "track_period": _TRACK_BEGINS}


def _idle_after_the_run(key, values, dispersed, takes):
    """Why a dispersed profile key cannot act: the segment it shapes begins,
    for every value the study gives the keys that place it, at or after the
    run's end (the controller, the truth's target and every figure read the
    profile at the ticks alone). Dispersed only: a fixed value is a setting
    compared with none (slew_start 10 runs as 0.5 does not)."""
    begins_keys = _SEGMENT_BEGINS.get(key[len(_PROFILE):]) if key.startswith(_PROFILE) else None
    if begins_keys is None or key not in dispersed:
        return None
    given = _Given(takes, values, dispersed)
    try:
        earliest = sum(given.span(_PROFILE + k)[0] for k in begins_keys)
        duration = float(values["sim.duration"])
    except (KeyError, TypeError, ValueError):
        return None
    # at the segment's start the reference's angle is the one before it (continuous), and a command of the
    # last tick acts after the run: a segment beginning at the run's end acts on nothing either (pass 53)
    if not earliest >= duration * (1.0 - 1e-9):
        return None
    segment = "slew" if begins_keys == _SLEW_BEGINS else "track"
    return (f"the {segment} it shapes begins at {seconds(earliest)} s at the earliest "
            f"({' + '.join('profile.' + k for k in begins_keys)}, lowest values given), at or after the run's "
            f"end at {seconds(duration)} s: every value runs the same reference")


def _pair(text):
    """[a, b] (text or list) as two floats, or None."""
    try:
        v = yaml.safe_load(text) if isinstance(text, str) else text
        return [float(v[0]), float(v[1])] if isinstance(v, list) and len(v) == 2 else None
    except (yaml.YAMLError, TypeError, ValueError):
        return None


def _idle_motor_limit(key, values, dispersed, takes):
    """Why torque.limit cannot act in a closed loop: the controller holds each axis's command at its own
    azimuth/elevation.torque_limit (pid.cpp), and a study's loop has no fault schedule to add torque, so a
    motor limit at or above those on both axes, for every value given, clips nothing (pass 55: every row
    recorded its drawn limit, all else identical)."""
    own_keys = [CONTROLLER_PREFIX + axis + ".torque_limit" for axis in ("azimuth", "elevation")]
    if key != "torque.limit" or key not in dispersed or any(k in dispersed for k in own_keys):
        return None
    try:
        own = [float(values[k]) for k in own_keys]
    except (KeyError, TypeError, ValueError):
        return None
    given = takes.get(key)
    limits = [_pair(v) for v in given] if isinstance(given, list) else [None]
    if any(lim is None for lim in limits) or not all(lim[0] >= own[0] and lim[1] >= own[1] for lim in limits):
        return None
    return (f"every value given is at or above the controller's own command limits (azimuth/elevation.torque_limit "
            f"{own[0]:g} / {own[1]:g} N m), which hold every command it sends: the motor limit clips nothing")


def refuse_idle_set(spec, entries, values, dispersed, takes, closed, runs, unread_ticks=TRUTH_ONLY, controller=None):
    """A key given under set: or controller_set: [(where, canonical key, node)]
    that the runs never read: refused at its line as the dispersed key is
    (whatever its value: it would be recorded in the fingerprint and act on
    nothing). Judged with the loaded values; a key also dispersed is judged
    as dispersed. controller: (where, node) of the controller file, refused
    when its own values run as others (_feedforwards_alike)."""
    for where, key, node in entries:
        why = None if key in dispersed else idle_reason(key, values, dispersed, takes, closed, unread_ticks)
        if why is not None:
            spec.refuse(where, f"not read by {runs} ({why}): the value given would be recorded but never act", node)
    # the feed-forward from the controller file: refused at the set mode's line, else at the file's
    if controller is not None and FEEDFORWARD_KEY not in dispersed | {key for _, key, _ in entries}:
        if (why := _feedforwards_alike(FEEDFORWARD_KEY, values, dispersed, takes)) is not None:
            where, _, node = next((e for e in entries if e[1] == CONTROLLER_PREFIX + "pointing.mode"),
                                  (controller[0], None, controller[1]))
            spec.refuse(where, f"the configuration's values would be recorded as given and act as others in {runs} "
                        f"({why})", node)


def _idle_in_scene(key, scene, dispersed):
    """Why `key` cannot act in this scene (None if it can): a bearing key on
    an ideal joint, a tilt key on a planar bearing, a contact sub-stepping or
    penetration key with both joints ideal, an adaptive-step key under the
    fixed policy, a base key, geometry.joint1_position or sim.momentum_tol on
    a fixed base, sim.energy_tol with a spatial bearing. Nothing is judged when the
    deciding key (structure.*, sim.substep_policy) is itself dispersed."""
    joints = {j: scene.get(f"structure.joint{j}") for j in (1, 2)}
    rules = []
    for j in (1, 2):  # a joint's own bearing keys
        rules.append(((f"joint{j}.contact.", f"joint{j}.friction.", f"initial.ecc{j}"), f"structure.joint{j}",
                      joints[j] != "ideal", f"joint {j} is ideal: it has no bearing"))
        rules.append(((f"joint{j}.contact.bearing_length", f"initial.tilt{j}"), f"structure.joint{j}",
                      joints[j] == "spatial",
                      f"joint {j}'s bearing is {'ideal' if joints[j] == 'ideal' else 'planar'}: it cannot tilt"))
    any_clearance = any(k != "ideal" for k in joints.values())
    rules += [(("contact.bearing_length",), "structure.joint", any(k == "spatial" for k in joints.values()),
               "no joint's bearing is spatial: none can tilt"),
              (("contact.", "friction.", "initial.ecc"), "structure.joint", any_clearance,
               "both joints are ideal: no bearing"),
              # the contact's sub-stepping (sim.substep*, its policy and tolerances, the event location, the
              # work cap) and its penetration stop: dynamics/include/gimbalsim/dynamics/integrator.hpp
              (("sim.substep", "sim.event_tol", "sim.min_substeps_per_impact", "sim.max_substeps",
                "sim.max_event_iters"), "structure.joint", any_clearance,
               "both joints are ideal: no contact to sub-step, every step is one RK4 step of sim.step"),
              (("sim.penetration_limit",), "structure.joint", any_clearance,
               "both joints are ideal: no contact, nothing penetrates"),
              # the invariants (dynamics/src/invariants.cpp): momentum only on a floating base, and no energy
              # balance with a spatial bearing (its contact force works on the tilt)
              (("sim.momentum_tol",), "structure.base", scene.get("structure.base") != "fixed",
               "structure.base is fixed: no momentum drift is checked"),
              (("sim.energy_tol",), "structure.joint", all(k != "spatial" for k in joints.values()),
               "a joint's bearing is spatial: the energy balance is no invariant there and is not checked"),
              (("sim.substep_tol", "sim.substep_min", "sim.substep_max"), "sim.substep_policy",
               scene.get("sim.substep_policy") == "adaptive", "sim.substep_policy is fixed: only the adaptive "
               "policy reads it"),
              # the fixed policy's resolution check (substep_policy.hpp FixedSubsteps); sim.substep itself still
              # counts under the adaptive policy (its sub-step cap, integrator.hpp substepCap)
              (("sim.min_substeps_per_impact",), "sim.substep_policy", scene.get("sim.substep_policy") != "adaptive",
               "sim.substep_policy is adaptive: only the fixed policy checks an impact's sub-steps"),
              (("base.",), "structure.base", scene.get("structure.base") != "fixed",
               "structure.base is fixed: the base never moves"),
              # where joint 1 sits on a fixed base only moves the whole gimbal (no gravity): every figure is the
              # same, only the momentum about the base CoM (no row figure, unchecked on a fixed base) differs
              (("geometry.joint1_position",), "structure.base", scene.get("structure.base") != "fixed",
               "structure.base is fixed: joint 1's place on it only shifts the whole gimbal, no figure changes")]
    for prefixes, decider, acts, why in rules:
        if key.startswith(prefixes) and not acts and not any(d.startswith(decider) for d in dispersed):
            return why
    return _bearing_key_idle(key, joints, scene, dispersed)


def _number_reads(test):
    """A scene value (text) read as a number by test; a value that is no number reads (its own check refuses it)."""
    def reads(text):
        try:
            return test(float(text))
        except (TypeError, ValueError):
            return True
    return reads


# Bearing keys read only under some settings: each (setting, which of its values read the key) must hold.
# Every damping law's factor chi is 0 at c_e = 1 (dynamics/include/gimbalsim/dynamics/contact_law.hpp,
# dampingFactor): the law and its v0 floor act only below it. At friction.mu 0 no law's velocities act (pass 72).
_DAMPED = ("contact.damping", lambda law: law != "none")
_INELASTIC = ("contact.restitution", _number_reads(lambda restitution: restitution != 1.0))
_FRICTION = ("friction.mu", _number_reads(lambda mu: mu > 0.0))
_READ_UNDER = {"friction.mu": [("friction.law", lambda law: law != "none")],
               "friction.law": [_FRICTION],  # at friction.mu 0 every law gives no force (pass 84: a grid of laws)
               "friction.v_a": [("friction.law", lambda law: law == "ambrosio"), _FRICTION],
               "friction.v_b": [("friction.law", lambda law: law == "ambrosio"), _FRICTION],
               "contact.restitution": [_DAMPED],
               "contact.v0_min": [_DAMPED, _INELASTIC],
               "contact.damping": [_INELASTIC]}


def _own_key(j, shared):
    """Joint j's own key for a key shared by both: jointJ.contact.*,
    jointJ.friction.*, or initial.eccJ for initial.ecc."""
    return f"initial.ecc{j}" if shared == "initial.ecc" else f"joint{j}.{shared}"


def _bearing_key_idle(key, joints, scene, dispersed):
    """Why a bearing key (contact.*, friction.*, initial.ecc, or a joint's own
    jointJ.*) is read on no joint (None if it is read on one): on each joint
    with a bearing, a shared key is overridden by the joint's own value (in
    the scene's values, which list every own key the scene or set gave, or
    dispersed; a clearance and a journal radius give one value: either own
    overrides either shared), or the joint's law does not read it (friction.mu
    under friction.law none). initial.ecc is joint j's unless initial.eccJ is
    given (dynamics/scene/src/bearing_keys.cpp, deriveBearings)."""
    m = re.fullmatch(r"(?:joint([12])\.)?((?:contact|friction)\..+|initial\.ecc)", key)
    if m is None or any(d.startswith("structure.joint") for d in dispersed):
        return None
    own, shared = (int(m.group(1)) if m.group(1) else None), m.group(2)
    bearings = [j for j in ((own,) if own else (1, 2)) if joints[j] != "ideal"]
    if not bearings:
        return None  # the structure's rules say so
    radius = ("contact.clearance", "contact.journal_radius")
    names = set(radius) if shared in radius else {shared}
    why = []
    for j in bearings:
        overriding = sorted(_own_key(j, n) for n in names if _own_key(j, n) in scene or _own_key(j, n) in dispersed)
        if own is None and overriding:
            sets = f" (joint{j}.contact.clearance sets it)" if overriding[0].endswith("journal_radius") else ""
            why.append(f"overridden by {overriding[0]}{sets}")
            continue
        # a setting dispersed from a range is not judged: it may read the key
        unread = [(law_key, scene.get(f"joint{j}.{law_key}", scene.get(law_key)))
                  for law_key, reads in _READ_UNDER.get(shared, ())
                  if not any(d in (law_key, f"joint{j}.{law_key}") for d in dispersed)
                  and not reads(scene.get(f"joint{j}.{law_key}", scene.get(law_key)))]
        if not unread:
            return None
        law_key, law = unread[0]
        why.append(f"joint {j}'s {law_key} is {law}" + (
            " (every damping law's factor is 0 at c_e = 1: no law acts)" if law_key == _INELASTIC[0] else ""))
    return "on every joint with a bearing: " + "; ".join(why)
