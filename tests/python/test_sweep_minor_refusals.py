"""A replay names the file it read: a sweep's copy of its spec (DIR/spec.yaml)
edited since the sweep is named in the notice and the refusals, never the
original spec, which did not change."""
import os
import shutil

import pytest

from conftest import CONTROLLER_CONFIG, SCENES
from test_sweep_replay import make_sweep, sweep


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    return make_sweep(tmp_path_factory.mktemp("sweep"))


def edited_copy(swept, tmp_path, old, new):
    """A copy of the sweep's output folder whose spec.yaml has old replaced by new."""
    out = tmp_path / "out"
    shutil.copytree(swept, out)
    text = (out / "spec.yaml").read_text()
    assert old in text
    (out / "spec.yaml").write_text(text.replace(old, new))
    return out


def test_an_edited_copy_is_named_not_the_original(swept, tmp_path):
    # the old notice said "<original spec> changed since the sweep": that file was never touched
    out = edited_copy(swept, tmp_path, "seed: 3", "seed: 4")
    p = sweep(out, "--replay", 0, "--out", tmp_path / "run.csv")
    assert p.returncode == 8, p.stderr  # another draw: the row differs, said column by column
    assert f"replay: {out / 'spec.yaml'} differs from the spec the sweep ran (its fingerprint " \
        f"{out / 'spec.json'}): edited since the sweep" in p.stderr, p.stderr
    assert str(swept.parent / "spec.yaml") not in p.stderr, p.stderr


def test_a_set_edited_in_the_copy_is_refused_naming_the_copy(swept, tmp_path):
    out = edited_copy(swept, tmp_path, "set: {sim.duration: 0.15}", "set: {sim.duration: 0.2}")
    p = sweep(out, "--replay", 0, "--out", tmp_path / "run.csv")
    assert p.returncode == 2, p.stderr
    assert f"(with the set of {out / 'spec.yaml'}) is not the scene the sweep ran; changed: sim.duration 0.15 -> " \
        "0.2" in p.stderr, p.stderr
    assert not (tmp_path / "run.csv").exists()


def test_a_scene_missing_from_the_copy_says_where_it_looked(swept, tmp_path):
    # the copy's paths are read against the original's folder, not "beside the spec" (beside the copy)
    out = edited_copy(swept, tmp_path, "scene: scene.yaml", "scene: nope.yaml")
    p = sweep(out, "--replay", 0, "--out", tmp_path / "run.csv")
    assert p.returncode == 2, p.stderr
    # ... then where the sweep ran (inputs.json workdir), then here
    assert f"{out / 'spec.yaml'}:2:1: key 'scene': no such file: nope.yaml (looked in {swept.parent}, the sweep's " \
        f"spec's folder, then in {os.getcwd()}, the sweep's working directory, then in the current directory)" \
        in p.stderr, p.stderr


CLOSED_SPEC = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.1}}
controller: {CONTROLLER_CONFIG}
controller_set: {{azimuth.kd: 1000}}
samples: 1
seed: 3
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
phases: [{{first: [0.0, 0.1]}}]
indices:
  ape: {{}}
"""


def test_a_controller_set_edited_in_the_copy_is_refused_naming_the_copy(tmp_path):
    (tmp_path / "spec.yaml").write_text(CLOSED_SPEC)
    p = sweep(tmp_path / "spec.yaml", "--out", tmp_path / "out", "--workers", "1", "--no-progress")
    assert p.returncode == 0, p.stderr
    out = tmp_path / "out"
    (out / "spec.yaml").write_text(CLOSED_SPEC.replace("azimuth.kd: 1000", "azimuth.kd: 1001"))
    p = sweep(out, "--replay", 0, "--out", tmp_path / "run.csv")
    assert p.returncode == 2, p.stderr
    assert f"controller_config_sha256 differs from the sweep's: the controller configuration {CONTROLLER_CONFIG} " \
        f"(with the controller_set of {out / 'spec.yaml'}) is not the one the sweep ran" in p.stderr, p.stderr
