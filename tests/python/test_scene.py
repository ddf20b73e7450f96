"""load_scene, keys() and Scene: overrides as --set reads them, every refusal
the command line makes is a SceneError naming the same key and place (an
override named as the dict entry it was), and a pickled Scene is the same scene."""
import pickle
import re
import warnings

import numpy as np
import pytest

import gimbalsim
from conftest import run_cli, scene_path

KEYS = gimbalsim.keys()
CLEARANCE = scene_path("paper_clearance")
VECTOR_SIZE = {"vec2": 2, "vec3": 3, "inertia": 3}


def violating(k):
    """A value the key's own check (or type) refuses."""
    size = VECTOR_SIZE.get(k["type"])
    bad = {"> 0": 0.0, ">= 0": -1.0, ">= 1": 0.0, "in [0, 0.5)": 0.5, "in [1, 3]": 4.0, "in (0, 1]": 1.5,
           "in (0, 1)": 1.0, "non-zero": 0.0}.get(k["check"])
    if k["check"] == "symmetric positive definite":
        return [1.0, -1.0, 1.0]
    if bad is not None:
        return [bad] * size if size else bad
    if "|" in k["type"]:
        return "bogus"
    if k["type"] == "int":
        return 1.5
    if k["type"] == "string":
        return [1, 2]
    return [1.0] * (size + 1) if size else "abc"


CASES = [{k["key"]: violating(k)} for k in KEYS]
CASES += [
    {"contact.stifness_scale": 2.0},                 # unknown key
    {"sim.substep": 2.0e-3, "sim.step": 1.0e-3},    # across keys
    {"sim.output_interval": 1.5e-3},                # not a multiple of sim.step
    ["sim.step"],                                     # no '='
    ["sim.step=[1, 2"],                               # not YAML
    {"contact.clearance": 1.0e-4, "contact.journal_radius": 9.5e-3},  # one field twice (pass 71: the later won)
]


def cli_problems(overrides, path=CLEARANCE):
    sets = [a for kv in gimbalsim.as_overrides(overrides) for a in ("--set", kv)]
    p = run_cli("simulate", path, *sets, "--out", "/dev/null", check=False)
    lines = [l[len("error: "):] for l in p.stderr.splitlines() if l.startswith("error: ")]
    return p.returncode, lines


def as_python(line, overrides):
    """A command-line refusal as Python words it: the override's place "--set
    #k 'key=value'" becomes the dict entry or list item, "overrides['key']
    (key=value)" or "overrides[i] (key=value)"."""
    texts = gimbalsim.as_overrides(overrides)
    m = re.match(r"--set #(\d+) '", line)
    if not m:
        return line
    k = int(m.group(1))
    label = f"overrides[{list(overrides)[k - 1]!r}]" if isinstance(overrides, dict) else f"overrides[{k - 1}]"
    return line.replace(f"--set #{k} '{texts[k - 1]}'", f"{label} ({texts[k - 1]})", 1)


def named_key(text):
    m = re.search(r"(?:unknown )?key '([^']+)'", text)
    return m.group(1) if m else None


@pytest.mark.parametrize("overrides", CASES, ids=[str(c)[:60] for c in CASES])
def test_every_refusal_is_a_scene_error_with_the_same_key(overrides):
    code, cli = cli_problems(overrides)
    assert code == 2, f"the command line accepted {overrides}"
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.load_scene(CLEARANCE, overrides)
    assert isinstance(e.value, ValueError)
    assert [p["text"] for p in e.value.problems] == [as_python(t, overrides) for t in cli]
    assert [p["key"] for p in e.value.problems] == [named_key(t) for t in cli]
    assert not any("--set" in p["text"] for p in e.value.problems)
    if isinstance(overrides, dict):
        assert set(e.value.keys) <= set(overrides) | {None}
        assert e.value.key in overrides


def test_file_refusals_name_line_and_column(tmp):
    bad = tmp / "bad.yaml"
    bad.write_text("sim:\n  step: 1.0e-3\n  duration: -2\ncontact:\n  restitution: 1.5\n  nonsense: 1\n")
    code, cli = cli_problems({}, bad)
    assert code == 2
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.load_scene(bad)
    assert [p["text"] for p in e.value.problems] == cli
    where = {p["key"]: (p["file"], p["line"], p["column"]) for p in e.value.problems}
    assert where["contact.nonsense"] == (str(bad), 6, 3)
    assert where["sim.duration"] == (str(bad), 3, 3)
    assert where["contact.restitution"] == (str(bad), 5, 3)
    for p in e.value.problems:
        assert p["text"].startswith(f"{bad}:{p['line']}:{p['column']}: ")


def test_yaml_syntax_and_unreadable_files(tmp):
    broken = tmp / "broken.yaml"
    broken.write_text("sim: {step: [1\n")
    code, cli = cli_problems({}, broken)
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.load_scene(broken)
    assert code == 2 and [p["text"] for p in e.value.problems] == cli
    assert e.value.key is None and e.value.line is not None
    missing = tmp / "missing.yaml"
    code, cli = cli_problems({}, missing)
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.load_scene(missing)
    assert code == 2 and [p["text"] for p in e.value.problems] == cli


def test_override_values_are_read_as_the_command_line_reads_them():
    s = gimbalsim.load_scene(CLEARANCE, {"contact.clearance": 2.5e-4, "initial.ecc": np.array([1e-4, 0.0]),
                                         "sim.max_substeps": 5000, "friction.law": "ambrosio",
                                         "sim.step": 0.1 + 0.2 - 0.3 + 1e-3})
    v = s.values()
    assert float(v["contact.journal_radius"]) == float(gimbalsim.load_scene(CLEARANCE).values()["contact.bearing_radius"]) - 2.5e-4
    assert [float(x) for x in v["initial.ecc"].strip("[]").split(",")] == [1e-4, 0.0]
    assert v["sim.max_substeps"] == "5000" and v["friction.law"] == "ambrosio"
    assert float(v["sim.step"]) == 0.1 + 0.2 - 0.3 + 1e-3     # every bit of the float survives
    with pytest.raises(TypeError, match="sim.step"):
        gimbalsim.load_scene(CLEARANCE, {"sim.step": object()})


def test_keys_lists_every_key_with_type_unit_and_meaning():
    names = [k["key"] for k in KEYS]
    assert len(names) == len(set(names)) > 50
    assert {"contact.clearance", "friction.mu", "sim.step", "initial.ecc"} <= set(names)
    for k in KEYS:
        assert k["type"] and k["meaning"], k
    assert next(k for k in KEYS if k["key"] == "sim.step")["unit"] == "s"
    cli = run_cli("keys").stdout
    for name in names:
        assert name in cli


def test_pickled_scene_is_the_same_scene():
    s = gimbalsim.load_scene(CLEARANCE, {"sim.duration": 0.3, "friction.mu": 0.17, "name": "mine"})
    t = pickle.loads(pickle.dumps(s))
    assert t.values() == s.values() and t.name == "mine" and t.path == s.path and t.variant == s.variant
    assert np.array_equal(gimbalsim.simulate(t).rows, gimbalsim.simulate(s).rows)
    r = s.replace({"friction.mu": 0.3})
    assert r.values()["friction.mu"] == "0.3" and s.values()["friction.mu"] == "0.17"


@pytest.mark.parametrize("key", ["friction.mu", "joint1.friction.mu", "joint2.friction.mu"])
def test_a_friction_coefficient_is_bounded_as_a_faults_rise_is(key):
    # (pass 37) 1e308 was accepted and overflowed the friction force to Inf at the first contact (exit 3)
    with pytest.raises(gimbalsim.SceneError, match=r"must be in \[0, 10\], got 1e\+308"):
        gimbalsim.load_scene(scene_path("paper_clearance"), {key: "1e308"})
    assert gimbalsim.load_scene(scene_path("paper_clearance"), {key: "10"}).values()[key] == "10"



def test_replace_of_one_alternative_still_replaces_the_printed_other():
    # a scene's printed values hold its journal radius; a clearance given to replace() replaces it (the sweep's
    # samples are built so), where both given by the user are refused above
    scene = gimbalsim.load_scene(CLEARANCE)
    again = scene.replace({"contact.clearance": 2.0e-4})
    radius = float(scene.values()["contact.bearing_radius"]) - 2.0e-4
    assert float(again.values()["contact.journal_radius"]) == pytest.approx(radius, rel=1e-12)


def test_a_scenes_own_values_left_idle_are_not_warned_about_again_on_replace_or_unpickle():
    # the ideal twin's bearing keys are its own (printed) values: a replace or an unpickle said 17 times that
    # they do not act; a user's override that does not act is said once
    ideal = gimbalsim.load_scene(scene_path("paper_ideal"))
    assert len(ideal.warnings) == 1  # the base inertia's
    for again in (ideal.replace(["sim.duration=0.5"]), pickle.loads(pickle.dumps(ideal))):
        assert len(again.warnings) == 1 and "triangle inequality" in again.warnings[0], again.warnings
    set_idle = ideal.replace(["contact.restitution=0.5"]).warnings
    assert len(set_idle) == 2 and "key 'contact.restitution': no joint has clearance" in set_idle[1], set_idle


def test_a_printed_default_or_a_value_said_at_load_is_not_warned_about_on_replace():
    # a planar scene prints the bearing length it never gave: every replace said it does not act (pass 76);
    # an idle key the user gave at load was said then, not again at each replace
    planar = gimbalsim.load_scene(scene_path("paper_clearance"), {"joint1.friction.mu": 0.2})
    said = [w for w in planar.warnings if "joint1.friction.mu" in w]
    assert len(said) == 1, planar.warnings
    again = planar.replace(["friction.mu=0.2"])
    assert not [w for w in again.warnings if "bearing_length" in w or "joint1.friction.mu" in w], again.warnings
    assert [w for w in planar.replace(["contact.bearing_length=0.1"]).warnings if "bearing_length" in w]


def test_a_value_that_does_not_act_is_a_python_warning_naming_the_callers_entry():
    # (pass 76) the loader's warnings stayed in scene.warnings: Scene.replace and load_scene said nothing where the
    # command line says "this value does not act" (docs/scene_keys.md: accepted with a warning)
    both = {"contact.clearance": 2.0e-4, "joint2.contact.clearance": 3.0e-4}
    base = gimbalsim.load_scene(CLEARANCE)
    for call in (lambda: base.replace(both), lambda: gimbalsim.load_scene(CLEARANCE, both)):
        with pytest.warns(gimbalsim.SceneWarning) as said:
            call()
        ours = [str(w.message) for w in said if "contact.clearance=" in str(w.message)]
        assert ours == ["overrides['contact.clearance'] (contact.clearance=0.0002): key 'contact.clearance': every "
                        "joint it would act on gives its own (joint2.contact.clearance): this value does not act"], \
            [str(w.message) for w in said]
    # what the scene itself gave was said at its load, not at each replace
    with warnings.catch_warnings():
        warnings.simplefilter("error", gimbalsim.SceneWarning)
        base.replace({"friction.mu": 0.2})
    with pytest.warns(gimbalsim.SceneWarning, match="triangle inequality"):
        gimbalsim.load_scene(CLEARANCE)
