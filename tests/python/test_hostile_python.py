"""Careless and hostile calls of the Python package: no call kills the
interpreter (pickles of every protocol, instances made by __new__ without
__init__); one Simulator stepped from two threads runs the calls one after
the other; a State from outside is checked as a scene is; output methods
follow the command line's output rules and no path may hold a NUL; a closed
loop gone NaN is a stop with its reason; values are typed and objects print
usefully; an override's problem names the override, not "--set #k"."""
import math
import os
import pathlib
import pickle
import re
import shutil
import subprocess
import sys
import textwrap
import threading

import numpy as np
import pytest

import gimbalsim
from conftest import CONTROLLER_CONFIG, SCENES, scene_path


def scene(name="paper_clearance", overrides=None):
    return gimbalsim.load_scene(scene_path(name), overrides)


def run_python(code):
    """Runs code in a fresh interpreter (a crash there is not ours); returns the CompletedProcess."""
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
                          timeout=300, env=os.environ)


# ---- no call kills the interpreter ----

PICKLABLE = f"""
import pickle, gimbalsim
scene = gimbalsim.load_scene({str(scene_path("paper_clearance"))!r}, {{"sim.duration": 0.01}})
objects = {{"Scene": scene, "State": gimbalsim.Simulator(scene).state,
            "Controller": gimbalsim.Controller({str(CONTROLLER_CONFIG)!r})}}
"""


def test_every_pickle_protocol_round_trips_every_picklable_class():
    p = run_python(PICKLABLE + textwrap.dedent("""
        for name, obj in objects.items():
            for protocol in range(pickle.HIGHEST_PROTOCOL + 1):
                back = pickle.loads(pickle.dumps(obj, protocol=protocol))
                assert type(back) is type(obj), (name, protocol)
                if name == "State":
                    assert back.q.tobytes() == obj.q.tobytes() and back.t == obj.t, protocol
                else:
                    assert back.values() == obj.values() and back.path == obj.path, (name, protocol)
        print("round-tripped", pickle.HIGHEST_PROTOCOL + 1)
        """))
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "round-tripped 6"


# Every public method or property of every class, called on an instance made
# by __new__ alone: each must raise TypeError, none may crash.
CALLS = {
    "Scene": ["s.path", "s.name", "s.variant", "s.warnings", "s.step", "s.duration", "s.output_interval",
              "s.values()", "s._non_default()", "s._replaced([])", "s.__reduce__()", "repr(s)",
              "gimbalsim.simulate(s)", "gimbalsim.Simulator(s)",
              "gimbalsim.closed_loop(s, gimbalsim.Controller(), 0.1)", "pickle.dumps(s)"],
    "State": ["s.variant", "s.t", "s.q", "s.v", "s.in_contact", "s.v0", "s.friction_mode", "s.vt_floor",
              "s.h_next", "s.__reduce__()", "pickle.dumps(s)", "setattr(good_sim, 'state', s)"],
    "Simulator": ["s.t", "s.variant", "s.step_size", "s.step(1.0, 2.0)", "s.step(1.0, 2.0, n=10)",
                  "s.run(np.zeros((3, 2)))", "s.output()", "s._output_array()", "s.state",
                  "setattr(s, 'state', good_sim.state)"],
    "Controller": ["s.path", "s.period", "s._values_text()", "s.values()", "s.reset()", "s.update(0.0, 0.1, 0.2)",
                   "s.__reduce__()", "pickle.dumps(s)",
                   "gimbalsim.closed_loop(gimbalsim.load_scene_text(''), s, 0.1)"],
}


@pytest.mark.parametrize("cls", list(CALLS))
def test_an_instance_made_by_new_alone_raises_and_never_crashes(cls):
    calls = "\n".join(f"""
try:
    {c}
    print("NO ERROR", {c!r})
except TypeError as e:
    assert "not initialised" in str(e) or "incompatible" in str(e), ({c!r}, str(e))
    print("refused", {c!r})
""" for c in CALLS[cls])
    p = run_python(f"""
import pickle, numpy as np, gimbalsim
from gimbalsim import _gimbalsim
good_sim = gimbalsim.Simulator(gimbalsim.load_scene_text(""))
s = _gimbalsim.{cls}.__new__(_gimbalsim.{cls})
{calls}
""")
    assert p.returncode == 0, f"died with {p.returncode}: {p.stderr[-2000:]}"
    assert "NO ERROR" not in p.stdout, p.stdout
    assert p.stdout.count("refused") == len(CALLS[cls]), p.stdout


def test_init_called_again_on_a_live_object_does_not_crash():
    p = run_python(f"""
import gimbalsim
from gimbalsim import _gimbalsim
scene = gimbalsim.load_scene({str(scene_path("paper_clearance"))!r})
sim = gimbalsim.Simulator(scene)
sim.step(1.0, 2.0, n=10)
sim.__init__(scene)
sim.step(1.0, 2.0, n=10)
c = gimbalsim.Controller()
c.__init__("", [])
print(sim.t > 0.0, c.period > 0)
""")
    assert p.returncode == 0, p.stderr
    assert p.stdout.split() == ["True", "True"]


# ---- one Simulator, two threads ----

def test_one_simulator_stepped_from_two_threads_runs_the_calls_one_after_the_other():
    s = scene(overrides={"sim.duration": 10.0})
    sim = gimbalsim.Simulator(s)
    n, calls = 200, 10
    errors = []

    def work():
        try:
            for _ in range(calls):
                sim.step(5.0, 10.0, n=n)
                sim.run(np.tile([5.0, 10.0], (n, 1)))
                sim.output()
                sim.state
        except Exception as e:  # noqa: BLE001 - any error is the finding
            errors.append(e)

    threads = [threading.Thread(target=work) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    # One thread doing all the calls in turn reaches the same time and state.
    alone = gimbalsim.Simulator(s)
    for _ in range(2 * calls):
        alone.step(5.0, 10.0, n=n)
        alone.run(np.tile([5.0, 10.0], (n, 1)))
    assert sim.t == alone.t == pytest.approx(2 * calls * 2 * n * s.step)
    assert sim._output_array().tobytes() == alone._output_array().tobytes()


def test_one_simulator_restored_while_another_thread_steps_stays_whole():
    s = scene()
    sim = gimbalsim.Simulator(s)
    start = sim.state
    errors = []

    def stepper():
        try:
            for _ in range(50):
                sim.step(5.0, 10.0, n=20)
        except Exception as e:  # noqa: BLE001
            errors.append(e)

    def restorer():
        try:
            for _ in range(50):
                sim.state = start
                st = sim.state
                assert st.t == pytest.approx(round(st.t / s.step) * s.step, abs=1e-12)
        except Exception as e:  # noqa: BLE001
            errors.append(e)

    threads = [threading.Thread(target=stepper), threading.Thread(target=restorer)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    assert 0.0 <= sim.t <= 50 * 20 * s.step + 1e-12


# ---- a State from outside is checked ----

def good_fields():
    st = gimbalsim.Simulator(scene()).state
    return dict(variant=st.variant, t=st.t, q=list(st.q), v=list(st.v), in_contact=st.in_contact, v0=st.v0,
                friction_mode=st.friction_mode, vt_floor=st.vt_floor, h_next=st.h_next)


def _set(field, i, x):
    def change(f):
        f[field] = list(f[field])
        f[field][i] = x
    return change


# (change of the fields of a good State of paper_clearance (floating_ideal_planar_friction: q holds
# p (3), the base quaternion (4), theta1, ecc (2), theta2), the field named, refused already
# without a scene (else only when restored into this scene))
BAD_STATES = [
    ({"t": 1e300}, "State.t", False),  # beyond what the step counter reaches
    ({"t": -1.0}, "State.t", True),
    ({"t": math.inf}, "State.t", True),
    ({"v0": [math.nan]}, "State.v0", True),
    ({"v0": [], "in_contact": []}, "State.in_contact", True),  # paper_clearance has one contact end
    ({"vt_floor": math.nan}, "State.vt_floor", True),
    ({"vt_floor": 1.0}, "State.vt_floor", True),
    ({"h_next": -1e-6}, "State.h_next", True),
    ({"h_next": 1.0}, "State.h_next", False),  # beyond sim.step
    ({"friction_mode": 7}, "State.friction_mode", True),
    ({"variant": "warp_drive"}, "State.variant", True),
    ({"variant": "fixed_ideal_planar_friction"}, "State.q", True),  # sizes of another variant
    ({"variant": "floating_ideal_ideal"}, "State.variant", False),  # sizes of another variant
    (_set("q", 0, math.nan), "State.q[0]", True),
    (_set("v", 1, math.inf), "State.v[1]", True),
    (_set("q", 3, 2.0), "State.q[3:7]", True),  # not a unit quaternion
    (_set("q", 8, 1.0), "State.q", False),  # |ecc| 1 m: outside the bearing
]


@pytest.mark.parametrize("change,field,at_construction", BAD_STATES,
                         ids=[f"{b[1]}-{i}" for i, b in enumerate(BAD_STATES)])
def test_a_state_from_outside_is_refused_naming_the_field(change, field, at_construction):
    fields = good_fields()
    if callable(change):
        change(fields)
    else:
        fields.update(change)
    if fields["variant"] == "floating_ideal_ideal":  # its sizes: no contact end
        fields["q"], fields["v"] = fields["q"][:9], fields["v"][:8]
        fields["in_contact"], fields["v0"] = [], []
    sim = gimbalsim.Simulator(scene())
    before = sim._output_array().tobytes()
    named = re.escape(field)
    if at_construction:
        with pytest.raises(ValueError, match=named):
            gimbalsim.State(**fields)
        # the same fields in a pickle (what a foreign file can hold) are refused too
        with pytest.raises(ValueError, match=named):
            pickle.loads(pickle.dumps(_Crafted(fields)))
    else:
        state = gimbalsim.State(**fields)  # nothing wrong without a scene ...
        with pytest.raises(ValueError, match=named):
            sim.state = state  # ... but this scene cannot run it
    assert sim._output_array().tobytes() == before  # a refused state changes nothing


class _Crafted:
    """Pickles as gimbalsim.State called with any fields: what a foreign pickle can hold."""

    def __init__(self, fields):
        self.fields = fields

    def __reduce__(self):
        f = self.fields
        return gimbalsim.State, (f["variant"], f["t"], f["q"], f["v"], f["in_contact"], f["v0"],
                                 f["friction_mode"], f["vt_floor"], f["h_next"])


# (field change, the field named): values numpy or pybind11 took silently (a complex q's imaginary part dropped,
# friction_mode True as 1, a contact flag 1 or 2.5 as True) or refused naming no field (friction_mode 1.0)
MISTYPED_STATES = [
    ({"q": np.array(good_fields()["q"]) + 50j}, "State.q"),
    ({"v": np.array(good_fields()["v"]) + 1e3j}, "State.v"),
    ({"v0": [0.0 + 1j]}, "State.v0"),
    ({"t": 0.0 + 1e-3j}, "State.t"),
    ({"h_next": True}, "State.h_next"),
    ({"friction_mode": True}, "State.friction_mode"),
    ({"friction_mode": 1.0}, "State.friction_mode"),
    ({"in_contact": [1]}, "State.in_contact[0]"),
    ({"in_contact": [2.5]}, "State.in_contact[0]"),
    ({"in_contact": False}, "State.in_contact"),
    ({"variant": None}, "State.variant"),
]


@pytest.mark.parametrize("change,field", MISTYPED_STATES, ids=[f"{m[1]}-{i}" for i, m in enumerate(MISTYPED_STATES)])
def test_a_state_field_of_the_wrong_type_is_refused_naming_it(change, field):
    fields = {**good_fields(), **change}
    with pytest.raises(TypeError, match=rf"^{re.escape(field)}: expected"):
        gimbalsim.State(**fields)
    with pytest.raises(TypeError, match=rf"^{re.escape(field)}: expected"):  # a foreign pickle alike
        pickle.loads(pickle.dumps(_Crafted(fields)))


def test_a_state_of_numpy_values_still_round_trips():
    sim = gimbalsim.Simulator(scene())
    sim.step(1.0, 2.0, n=3)
    st = sim.state
    fields = dict(variant=st.variant, t=np.float64(st.t), q=np.array(st.q), v=np.array(st.v),
                  in_contact=np.array(st.in_contact, dtype=bool), v0=np.array(st.v0),
                  friction_mode=np.int64(st.friction_mode), vt_floor=np.array(st.vt_floor), h_next=st.h_next)
    made = gimbalsim.State(**fields)
    for copy in [made] + [pickle.loads(pickle.dumps(st, protocol)) for protocol in range(pickle.HIGHEST_PROTOCOL + 1)]:
        assert (copy.t, list(copy.q), list(copy.v), copy.in_contact, copy.v0, copy.friction_mode) == \
            (st.t, list(st.q), list(st.v), st.in_contact, st.v0, st.friction_mode)
    sim.state = made
    assert sim.t == st.t


def test_a_restored_time_near_the_limit_steps_on():
    s = scene()
    sim = gimbalsim.Simulator(s)
    far = {**good_fields(), "t": 2.0**40 * s.step}
    sim.state = gimbalsim.State(**far)
    sim.step(0.0, 0.0, n=3)
    assert sim.t == (2.0**40 + 3) * s.step


def test_non_finite_torques_are_refused_before_stepping():
    sim = gimbalsim.Simulator(scene())
    with pytest.raises(ValueError, match="finite"):
        sim.step(math.nan, 0.0)
    tau = np.zeros((5, 2))
    tau[3, 1] = math.inf
    with pytest.raises(ValueError, match="row 3"):
        sim.run(tau)
    assert sim.t == 0.0


# ---- outputs and paths ----

def test_run_to_csv_refuses_its_scene_file_and_a_missing_folder(tmp_path):
    path = tmp_path / "scene.yaml"
    path.write_text(scene_path("paper_clearance").read_text())
    original = path.read_bytes()
    run = gimbalsim.simulate(gimbalsim.load_scene(path, {"sim.duration": 0.01}))
    with pytest.raises(OSError, match="the same file as the input"):
        run.to_csv(path)
    with pytest.raises(OSError, match="the same file as the input"):
        run.to_csv(tmp_path / "." / "scene.yaml")  # another spelling of it
    assert path.read_bytes() == original
    with pytest.raises(OSError, match="does not exist"):
        run.to_csv(tmp_path / "missing" / "run.csv")
    assert not (tmp_path / "missing").exists()
    os.symlink(tmp_path / "target.csv", tmp_path / "link.csv")
    with pytest.raises(OSError, match="symbolic link"):
        run.to_csv(tmp_path / "link.csv")
    run.to_csv(tmp_path / "run.csv")
    assert (tmp_path / "run.csv").read_text().count("\n") == len(run.rows) + 1


def test_a_path_with_a_nul_is_refused_everywhere(tmp_path):
    good = str(scene_path("paper_clearance"))
    s = gimbalsim.load_scene(good, {"sim.duration": 0.01})
    run = gimbalsim.simulate(s)
    (tmp_path / "out.csv").write_text("keep")
    calls = {
        "load_scene": lambda: gimbalsim.load_scene(good + "\0.txt"),
        "Controller": lambda: gimbalsim.Controller(str(CONTROLLER_CONFIG) + "\0x"),
        "closed_loop faults": lambda: gimbalsim.closed_loop(s, gimbalsim.Controller(), 0.1,
                                                            faults=str(SCENES) + "\0x"),
        "Run.to_csv": lambda: run.to_csv(str(tmp_path / "out.csv") + "\0.bak"),
        "_load_scene": lambda: gimbalsim._gimbalsim._load_scene(good + "\0x", []),
        "_write_csv": lambda: gimbalsim._gimbalsim._write_csv(str(tmp_path / "out.csv") + "\0x", run.rows, [], list(run.columns)),
        "_Controller": lambda: gimbalsim._gimbalsim.Controller(str(CONTROLLER_CONFIG) + "\0x", []),
        # (pass 84) a pickle is anyone's bytes: its file name labels the scene and is an input of its outputs
        "unpickled scene name": lambda: gimbalsim._unpickle_scene("/x\0y.yaml", s.__reduce__()[1][1]),
        "unpickled scene value": lambda: gimbalsim._unpickle_scene(good, ["name=a\0b"]),
        "unpickled controller": lambda: gimbalsim._unpickle_controller("c\0.yaml", []),
    }
    for name, call in calls.items():
        with pytest.raises(ValueError, match="NUL"):
            call()
    assert (tmp_path / "out.csv").read_text() == "keep"


# ---- NaN is a stop, not a figure ----

@pytest.mark.parametrize("how", ["subnormal encoder resolution", "huge gyro bias"])
def test_inputs_that_turned_a_closed_loop_nan_are_refused_naming_the_key(how, tmp_path):
    # A subnormal encoder resolution turned the measured angles (and then the
    # commands) into NaN, a gyro bias of 1e300 rad/s the attitude estimate; the
    # loop reported ok. Both are refused at load now, naming the key and the
    # place; a loop that meets a non-finite value anyway stops there
    # (ClosedLoop.ANonFiniteCommandStopsTheRunNamingItAndTheFiguresStayFinite).
    if how == "huge gyro bias":
        faults = tmp_path / "faults.yaml"
        faults.write_text("seed: 1\nfaults:\n  - {type: gyro_bias_jump, start: 0.2, bias: [0, 0, 1.0e300]}\n")
        with pytest.raises(gimbalsim.SceneError, match=r"faults.yaml:3:\d+: .*key 'bias': must be in"):
            gimbalsim.closed_loop(scene(), gimbalsim.Controller(CONTROLLER_CONFIG), duration=1.5, faults=faults)
    else:
        with pytest.raises(gimbalsim.SceneError, match=r"key 'sensors.encoder_resolution': must be"):
            scene(overrides={"sensors.encoder_resolution": 1e-300})
        with pytest.raises(gimbalsim.SceneError, match=r"key 'sensors.encoder_resolution': '1e-310' underflows"):
            scene(overrides={"sensors.encoder_resolution": 1e-310})


# ---- typed values and useful reprs ----

def test_controller_values_are_typed_as_their_keys():
    c = gimbalsim.Controller(CONTROLLER_CONFIG)
    values = c.values()
    types = {k["key"]: k["type"] for k in gimbalsim.controller_keys()}
    assert set(values) == set(types)
    for key, v in values.items():
        t = types[key]
        if t == "number":
            assert type(v) is float, (key, v)
        elif t == "int":
            assert type(v) is int, (key, v)
        elif t.startswith("vec"):
            assert isinstance(v, list) and len(v) == int(t[3:]) and all(type(x) is float for x in v), (key, v)
        elif t == "inertia":  # the principal moments of a diagonal inertia (plant.*)
            assert isinstance(v, list) and len(v) == 3 and all(type(x) is float for x in v), (key, v)
        else:
            assert type(v) is str, (key, v)
    assert values["control.period"] == c.period
    # the typed values read back exactly
    assert gimbalsim.Controller(None, values).values() == values


def test_scene_and_run_print_what_they_are():
    s = scene(overrides={"friction.mu": 0.2, "sim.duration": 0.01})
    text = repr(s)
    assert str(scene_path("paper_clearance")) in text and "friction.mu=0.2" in text and "sim.duration=0.01" in text
    default = gimbalsim.load_scene_text("")
    assert "friction.mu" not in repr(default) and "the defaults" in repr(default)
    run = gimbalsim.simulate(s)
    text = repr(run)
    assert str(scene_path("paper_clearance")) in text and "0.01 s" in text
    assert f"{len(run.rows)} rows" in text and "ok" in text


# ---- an override's problem names the override ----

def test_a_dict_override_is_named_as_the_dict_entry():
    with pytest.raises(gimbalsim.SceneError) as e:
        scene(overrides={"sim.duration": 0.1, "contact.restitution": 1.5})
    msg = str(e.value)
    assert "overrides['contact.restitution'] (contact.restitution=1.5)" in msg and "--set" not in msg, msg
    assert e.value.problems[0]["source"] == "overrides['contact.restitution']"
    with pytest.raises(gimbalsim.SceneError) as e:
        scene().replace({"friction.mu": -1})
    assert "overrides['friction.mu'] (friction.mu=-1)" in str(e.value) and "--set" not in str(e.value), str(e.value)
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.Controller(CONTROLLER_CONFIG, {"azimuth.kp": -5.0})
    assert "overrides['azimuth.kp'] (azimuth.kp=-5.0)" in str(e.value) and "--set" not in str(e.value), str(e.value)
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.load_scene_text("", overrides=["sim.step=0.001", "sim.step=-1"])
    assert "overrides[1] (sim.step=-1)" in str(e.value) and "--set" not in str(e.value), str(e.value)


def test_a_0d_array_override_is_its_number_and_a_bad_source_is_named_by_its_key():
    # np.array(0.01) got numpy's "iteration over a 0-d array", naming no key; np.float64(0.01) ran
    given = scene(overrides={"sim.duration": np.array(0.01)})
    assert given.values() == scene(overrides={"sim.duration": 0.01}).values()
    assert gimbalsim.Controller(None, {"azimuth.kp": np.array(900.0)}).values()["azimuth.kp"] == 900.0
    with pytest.raises(TypeError, match=r"^override 'sim.duration': cannot use a complex"):
        scene(overrides={"sim.duration": np.array(0.01 + 1j)})
    # a (file, line) whose line is no whole number got int()'s bare "invalid literal" once the override was refused
    path = scene_path("paper_clearance")
    for source in (("x.yaml", "notint"), ("x.yaml",), 12, ("x.yaml", True)):
        with pytest.raises(TypeError, match=r"^sources\['sim.duration'\]: a source is a label \(a str\) or a "
                                            r"\(file, line\) pair"):
            gimbalsim.load_scene(path, {"sim.duration": -1}, sources={"sim.duration": source})
    with pytest.raises(gimbalsim.SceneError, match=r"x.yaml:12 \(sim.duration=-1\)"):
        gimbalsim.load_scene(path, {"sim.duration": -1}, sources={"sim.duration": ("x.yaml", 12)})


@pytest.mark.parametrize("gyro,error,why", [(np.array(0.0), TypeError, "got ndarray"), (0.0, TypeError, "got float"),
                                            ([0, 0], ValueError, "got 2"), (np.zeros(4), ValueError, "got 4")])
def test_controller_update_refuses_a_gyro_that_is_not_three_numbers_naming_it(gyro, error, why):
    # a 0-d array got numpy's "iteration over a 0-d array", a short list pybind11's signatures: neither named gyro
    c = gimbalsim.Controller(None, {})
    with pytest.raises(error, match=rf"^gyro \[rad/s\]: expected 3 real numbers \(x, y, z\), {why}"):
        c.update(0.0, 0.1, 0.2, gyro=gyro)
    assert all(math.isfinite(x) for x in c.update(0.0, 0.1, 0.2, gyro=np.zeros(3))["tau"])


SWEEP_HEAD = f"scene: {SCENES}/paper_clearance.yaml\nsamples: 3\nseed: 1\n"


def test_a_sweep_spec_override_is_named_by_its_line(tmp_path):
    from gimbalsim.sweep import SweepSpec, SpecError
    bad = tmp_path / "spec.yaml"
    bad.write_text(SWEEP_HEAD + "set:\n  sim.duration: 0.1\n  contact.restitution: 1.5\n"
                   "parameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n")
    with pytest.raises(SpecError) as e:
        SweepSpec(bad)
    assert f"{bad}:6 (contact.restitution=1.5)" in str(e.value) and "--set" not in str(e.value), str(e.value)
    bad.write_text(SWEEP_HEAD + "parameters:\n  friction.mu: {uniform: [0.1, 0.2]}\n"
                   "grid:\n  contact.restitution: [0.5, 1.5]\n")
    with pytest.raises(SpecError) as e:
        SweepSpec(bad)
    assert f"{bad}:7 (contact.restitution=1.5)" in str(e.value) and "--set" not in str(e.value), str(e.value)


def test_a_tune_spec_override_is_named_by_its_line(tmp_path):
    from gimbalsim.tune import TuneSpec, SpecError
    spec = (f"scene: {SCENES}/paper_clearance.yaml\ncontroller: {CONTROLLER_CONFIG}\nduration: 3.7\n"
            "trials: 2\nseed: 3\nbatch: 2\n"
            "controller_set:\n  azimuth.kp: -5\n"
            "gains:\n  elevation.kd: {uniform: [300, 3000]}\n")
    bad = tmp_path / "t.yaml"
    bad.write_text(spec)
    with pytest.raises(SpecError) as e:
        TuneSpec(bad)
    assert f"{bad}:8 (azimuth.kp=-5)" in str(e.value) and "--set" not in str(e.value), str(e.value)
    bad.write_text(spec.replace("controller_set:\n  azimuth.kp: -5\n", "set:\n  contact.restitution: 1.5\n"))
    with pytest.raises(SpecError) as e:
        TuneSpec(bad)
    assert f"{bad}:8 (contact.restitution=1.5)" in str(e.value) and "--set" not in str(e.value), str(e.value)


def test_a_closed_loop_duration_between_control_periods_is_refused():
    # every duration of the project is whole steps or refused, never rounded (usage.md "Durations")
    with pytest.raises(ValueError, match=r"duration 0.0025 s must be a whole multiple of the control period"):
        gimbalsim.closed_loop(scene(), gimbalsim.Controller(CONTROLLER_CONFIG), duration=0.0025)


@pytest.mark.parametrize("kwargs,error,message", [
    ({"settle_tol": float("nan")}, ValueError, "settle_tol [rad] must be in (0, 10], got nan"),  # settled at 0 s
    ({"settle_tol": 0.0}, ValueError, "settle_tol [rad] must be in (0, 10]"),  # never settled: inf
    ({"settle_tol": float("inf")}, ValueError, "settle_tol [rad] must be in (0, 10]"),
    ({"duration": "3"}, TypeError, "duration [s]: expected a number, got str '3'"),
    ({"duration": True}, TypeError, "duration [s]: expected a number, got bool True"),  # ran for 1 s
])
def test_closed_loop_arguments_out_of_range_or_of_another_type_are_refused(kwargs, error, message):
    args = {"duration": 0.01, **kwargs}
    with pytest.raises(error) as e:
        gimbalsim.closed_loop(scene(), gimbalsim.Controller(CONTROLLER_CONFIG), **args)
    assert message in str(e.value), str(e.value)


@pytest.mark.parametrize("call,message", [
    (lambda: gimbalsim.simulate(None), "simulate: scene must be a gimbalsim.Scene (gimbalsim.load_scene(path)), "
                                       "got NoneType None"),
    (lambda: gimbalsim.simulate(str(scene_path("paper_ideal"))), "simulate: scene must be a gimbalsim.Scene"),
    (lambda: gimbalsim.Simulator("paper_ideal.yaml"), "Simulator: scene must be a gimbalsim.Scene"),
    (lambda: gimbalsim.closed_loop({}, gimbalsim.Controller(), 0.01), "closed_loop: scene must be a gimbalsim.Scene"),
    (lambda: gimbalsim.simulate(scene(), integrator=None), "simulate: integrator must be 'rk4' or 'reference', "
                                                           "got NoneType None"),
    (lambda: gimbalsim.simulate(scene(), b"rk4"), "integrator must be 'rk4' or 'reference', got bytes b'rk4'"),
])
def test_a_whole_run_call_names_the_argument_of_the_wrong_type(call, message):
    # (pass 84) pybind11's own TypeError listed the binding's signatures ("incompatible function arguments")
    with pytest.raises(TypeError) as e:
        call()
    assert message in str(e.value) and "incompatible" not in str(e.value), str(e.value)


def test_closed_loop_takes_the_range_it_states_and_refuses_what_memory_cannot_hold():
    # (pass 82) 1e9 s, inside the stated (0, 1e+09], was refused as outside "(0, 1e9)"; 1e8 s at 1 ms then ran on,
    # growing the process towards 30 TB of ticks
    with pytest.raises(MemoryError, match=r"^closed_loop \(duration 1e\+09 s at control.period 0.001 s.*\): "
                                          r"1000000000001 rows need [0-9.e+]+ GB .* more than the [0-9.e+]+ GB of "
                                          r"memory free now"):
        gimbalsim.closed_loop(scene(), gimbalsim.Controller(CONTROLLER_CONFIG), 1e9)
    # the same for simulate: 1e5 s at 1 ms is 1e8 rows of 58 columns, 93 GB (the CSV bound allows it)
    if os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") > 93e9:
        pytest.skip("this machine has 93 GB free: the run would fit")
    with pytest.raises(MemoryError, match=r"^simulate \(sim.duration 1e\+05 s .*\): 100000001 rows need [0-9.]+ GB"):
        gimbalsim.simulate(scene(overrides={"sim.duration": 1e5}))
    with pytest.raises(ValueError, match=r"duration \[s\] must be in \(0, 1e\+09\], got 1000000001"):
        gimbalsim.closed_loop(scene(), gimbalsim.Controller(CONTROLLER_CONFIG), 1e9 + 1)


def test_a_runs_record_cannot_be_edited_in_place(tmp_path):
    # (pass 84) Run.columns share Run.rows' memory: an in-place edit (an unwrapped angle, a mistyped index) changed
    # what to_csv wrote as the run, inf and a bare nan included
    run = gimbalsim.simulate(scene(overrides={"sim.duration": 0.01}))
    loop = gimbalsim.closed_loop(scene(), gimbalsim.Controller(CONTROLLER_CONFIG), 0.01)
    for array in (run.rows, run.columns["theta1"], loop.rows, loop.columns["ref1"]):
        with pytest.raises(ValueError, match="read-only"):
            array[..., 1] = math.inf
    edited = run.columns["theta1"].copy()  # a copy is the user's own to edit
    edited[1] = 0.5
    assert run.columns["theta1"][1] != 0.5
    # (pass 86) numpy let the flag be set back on an array owning its data, a column be replaced by a new array
    # and the attributes be assigned: each was written by to_csv as the run
    for array in (run.rows, run.columns["theta1"], loop.rows, loop.columns["ref1"]):
        with pytest.raises(ValueError, match="cannot set WRITEABLE flag"):
            array.flags.writeable = True
    for columns in (run.columns, loop.columns):
        for edit in (lambda c: c.__setitem__("theta1", np.zeros(3)), lambda c: c.update(x=1), lambda c: c.pop("t"),
                     lambda c: c.clear(), lambda c: c.setdefault("x", 1), lambda c: c.__delitem__("t")):
            with pytest.raises(TypeError, match="read-only: edit a copy"):
                edit(columns)
    # (pass 90) the files to_csv never writes over: another scene, or no inputs, under the name let it
    for obj, name in ((run, "rows"), (run, "columns"), (loop, "columns"), (loop, "rows"), (run, "scene"),
                      (loop, "inputs")):  # loop's rows: pass 87
        with pytest.raises(AttributeError):
            setattr(obj, name, None)
    for a, b in ((run, pickle.loads(pickle.dumps(run))), (loop, pickle.loads(pickle.dumps(loop)))):
        assert not b.rows.flags.writeable and not next(iter(b.columns.values())).flags.writeable  # unpickled too
        assert list(b.columns) == list(a.columns) and np.array_equal(a.rows, b.rows, equal_nan=True)
        for name in ("scene", "inputs"):
            if hasattr(a, name):
                assert getattr(b, name) is not None
                with pytest.raises(AttributeError):
                    setattr(b, name, None)
    # written over copies: a regression must not write over the repository's files
    shutil.copy(scene_path("paper_clearance"), tmp_path / "s.yaml")
    shutil.copy(CONTROLLER_CONFIG, tmp_path / "c.yaml")
    mine = gimbalsim.load_scene(tmp_path / "s.yaml", {"sim.duration": 0.01})
    loop_copy = gimbalsim.closed_loop(mine, gimbalsim.Controller(tmp_path / "c.yaml"), 0.01)
    for r, path in ((pickle.loads(pickle.dumps(gimbalsim.simulate(mine))), tmp_path / "s.yaml"),
                    (loop_copy, tmp_path / "c.yaml")):
        with pytest.raises(OSError, match="input"):
            r.to_csv(path)
    assert (tmp_path / "c.yaml").read_bytes() == pathlib.Path(CONTROLLER_CONFIG).read_bytes()


def test_controller_update_gives_no_command_from_a_non_finite_or_overflowing_input():
    # gyro 1e308 overflowed the law into tau (nan, nan), returned as a command
    c = gimbalsim.Controller(None, {})
    for kwargs, what in (({"theta1": float("nan")}, "theta1 is not finite"),
                         ({"dtheta2": float("inf")}, "dtheta2 is not finite"),
                         ({"gyro": [0.0, float("nan"), 0.0]}, "gyro is not finite"),
                         ({"gyro": [1e308, 1e308, 1e308]}, "the law gave a non-finite torque"),
                         # the command saturates to a finite one, but what the law asked for overflowed
                         ({"dtheta2": 1e308}, "the law gave a non-finite torque")):
        args = {"t": 0.0, "theta1": 0.1, "theta2": 0.2, **kwargs}
        with pytest.raises(ValueError, match=what):
            c.update(**args)
        c.reset()
    out = c.update(0.0, 0.1, 0.2, gyro=[0.0, 0.0, 0.0])
    assert all(math.isfinite(x) for x in out["tau"])


@pytest.mark.parametrize("kwargs,name", [({"t": True}, "t [s]"), ({"theta1": True}, "theta1 [rad]"),
                                         ({"dtheta2": "0.1"}, "dtheta2 [rad/s]"), ({"theta2": 1 + 2j}, "theta2 [rad]"),
                                         ({"gyro": [0.0, False, 0.0]}, "gyro[1] [rad/s]")])
def test_controller_update_refuses_a_bool_or_a_text_as_a_measurement(kwargs, name):
    # (pass 82) update(True, 0, 0) ran as t = 1 s and commanded 50 N m; Simulator.step refuses True as a torque
    c = gimbalsim.Controller(None, {})
    with pytest.raises(TypeError, match=rf"^{re.escape(name)}: expected a real number"):
        c.update(**{"t": 0.0, "theta1": 0.1, "theta2": 0.2, **kwargs})
    out = c.update(np.float64(0.0), 0.1, 0, gyro=(0, 0.0, np.float32(0.0)))  # numbers of any real type still run
    assert all(math.isfinite(x) for x in out["tau"])


@pytest.mark.parametrize("module", ["gimbalsim.dispersion", "gimbalsim.indices", "gimbalsim.replay", "gimbalsim"])
def test_a_library_module_run_as_a_program_is_refused(module):
    # (pass 39) `python3 -m gimbalsim.indices --bogus` took any argument, did nothing and exited 0 (usage.md: an
    # unknown flag is exit 2 in every program, the Python modules included); (pass 40) `python3 -m gimbalsim`
    # exited 1 ("cannot be directly executed"), which the table calls a bug
    p = subprocess.run([sys.executable, "-m", module, "--bogus"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 2 and f"{module}: error: a library " in p.stderr and "not a program" in p.stderr, p.stderr


def test_a_model_no_double_solves_is_refused_naming_a_key():
    # (pass 39) run and "stopped" at t = 0 with no good row; (pass 40) then refused with no key: a sweep's status
    # read "refused:" and the tuner's "refused:None"
    with pytest.raises(gimbalsim.SceneError, match="the model's first row is not finite") as e:
        gimbalsim.load_scene(scene_path("paper_spatial2"), {"shaft2.mass": "1e9", "shaft2.com": "[1000, 0, 0]"})
    assert e.value.key == "shaft2.mass"


def test_to_csv_never_writes_over_the_runs_inputs_after_a_change_of_folder(tmp_path, monkeypatch):
    # (pass 92) the scene's, controller's and fault schedule's paths were kept as typed ('s.yaml'): after a chdir
    # the input check read them in the new folder, and to_csv wrote over all three
    a, b = tmp_path / "A", tmp_path / "B"
    a.mkdir(), b.mkdir()
    shutil.copy(scene_path("paper_clearance"), a / "s.yaml")
    shutil.copy(CONTROLLER_CONFIG, a / "c.yaml")
    (a / "f.yaml").write_text("faults:\n  - {type: encoder_bias, axis: azimuth, start: 0.1, bias: 1.0e-3}\n")
    before = {n: (a / n).read_bytes() for n in ("s.yaml", "c.yaml", "f.yaml")}
    monkeypatch.chdir(a)
    run = gimbalsim.simulate(gimbalsim.load_scene("s.yaml", {"sim.duration": 0.01}))
    loop = gimbalsim.closed_loop(gimbalsim.load_scene("s.yaml"), gimbalsim.Controller("c.yaml"), 0.3, faults="f.yaml")
    monkeypatch.chdir(b)
    for r, name in ((run, "s.yaml"), (pickle.loads(pickle.dumps(run)), "s.yaml"), (loop, "s.yaml"),
                    (loop, "c.yaml"), (loop, "f.yaml"), (pickle.loads(pickle.dumps(loop)), "c.yaml")):
        for path in (a / name, f"../A/{name}"):
            with pytest.raises(OSError, match="the same file as the input"):
                r.to_csv(path)
    assert {n: (a / n).read_bytes() for n in before} == before
    assert run.scene.path == "s.yaml"  # the path as given stays what it says
