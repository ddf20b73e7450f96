"""One default controller: controllers/config/default.yaml, `pointing_controller`
run without a file and Python `Controller(None)` are the same configuration,
key for key, and no program reads a data file by a source path baked into it."""
import re
import subprocess

import numpy as np
import yaml

import gimbalsim
from conftest import BIN, CONTROLLER_CONFIG, SOURCE, scene_path


def _flatten(node, prefix=""):
    out = {}
    for k, v in node.items():
        if isinstance(v, dict):
            out.update(_flatten(v, f"{prefix}{k}."))
        else:
            out[f"{prefix}{k}"] = v
    return out


def _value(v):
    """A key's value as a float, a list of floats or a word, however it was written."""
    if isinstance(v, (list, tuple)):
        return [_value(x) for x in v]
    if isinstance(v, bool):
        return v
    if isinstance(v, (int, float)):
        return float(v)
    s = str(v).strip()
    if s.startswith("[") and s.endswith("]"):
        return [_value(x) for x in s[1:-1].split(",")]
    try:
        return float(s)
    except ValueError:
        return s


def _normalised(d):
    return {k: _value(v) for k, v in d.items()}


def test_default_yaml_no_file_and_controller_none_are_one_controller():
    with open(CONTROLLER_CONFIG) as f:
        from_file = _normalised(_flatten(yaml.safe_load(f)))
    p = subprocess.run([str(BIN / "pointing_controller"), "--print-config"], capture_output=True, text=True,
                       timeout=60, cwd="/")
    assert p.returncode == 0, p.stderr
    no_file = _normalised(dict(line.split("=", 1) for line in p.stdout.splitlines()))
    from_python = _normalised(gimbalsim.Controller(None)._values_text())
    keys = {k["key"] for k in gimbalsim._gimbalsim._controller_keys()}
    # The file states every key (none left to a default it does not show).
    assert set(from_file) == keys
    assert set(no_file) == keys
    assert set(from_python) == keys
    for k in sorted(keys):
        assert no_file[k] == from_file[k], k
        assert from_python[k] == from_file[k], k
    assert from_file["azimuth.kp"] > 0  # not vacuous: the default controller has gains


def test_closed_loop_with_the_default_controller_points():
    # Before: Controller(None) had zero gains, applied no torque and drifted 0.6 rad.
    scene = gimbalsim.load_scene(scene_path("paper_ideal"))
    run = gimbalsim.closed_loop(scene, None, 4.0)
    assert run.ok
    t, err = run.columns["t"], run.columns["truth_error"]
    slew_end = gimbalsim.Controller(None).values()["profile.slew_start"] + 2.0
    after = err[t > slew_end + 0.5]
    assert after.size > 0
    assert np.max(after) < 1e-4  # [rad]; the paper's controller settles to microradians


def test_closed_loop_sees_the_tilt_no_encoder_sees():
    # The plant's truth carries each journal's tilt: a spatial elevation journal
    # tilts under the controller, a planar one never does.
    def loop(name):
        run = gimbalsim.closed_loop(gimbalsim.load_scene(scene_path(name)), None, 4.0)
        assert run.ok, run.summary["error"]
        return run
    spatial, planar = loop("paper_spatial2"), loop("paper_clearance")
    t1, t2 = spatial.summary["max_tilt_rad"]
    assert t1 == 0.0 and t2 > 1e-3
    assert t2 == np.max(spatial.columns["tilt2"])
    assert planar.summary["max_tilt_rad"] == (0.0, 0.0)
    assert not np.any(planar.columns["tilt2"])


def _source_strings(binary):
    """Every NUL-terminated string in the binary that starts with the source folder."""
    data = binary.read_bytes()
    root = str(SOURCE.resolve()).encode()
    return {m.group().decode(errors="replace") for m in re.finditer(re.escape(root) + rb"[^\x00]*", data)}


def test_no_program_bakes_in_a_source_data_path():
    # __FILE__ of an assert names a source file (.cpp/.hpp); a data path
    # (a scene or configuration folder or file) must not be in a program.
    programs = ["pointing_controller", "gimbalsim_pointing_study", "gimbalsim_controller_floor", "gimbalsim_workprec",
                "gimbalsim_stress", "gimbalsim_bench", "gimbalsim", "firmware_sim", "controller_sweep"]
    built = [name for name in programs if (BIN / name).exists()]
    assert "pointing_controller" in built
    for name in built:
        found = [s for s in _source_strings(BIN / name) if not re.search(r"\.(cpp|hpp|h)$", s)]
        assert found == [], f"{name} holds source paths {found}"
