"""A sweep's provenance and replay: results.csv records each dispersed key as
the loaded scene holds it (checked here through the scene API, not the
sweep's code) and the base scene's fingerprint; `--replay I` reproduces
sample I's row bit for bit, writes its time series and plot, and refuses
what it cannot replay (exit 2), naming it."""
import csv
import hashlib
import json
import os
import shutil
import subprocess
import sys

import pytest

import gimbalsim
from conftest import SCENES

SET = {"sim.duration": 0.15}
SPEC = """
scene: scene.yaml
set: {sim.duration: 0.15}
samples: 6
seed: 3
parameters:
  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}
  friction.mu: {uniform: [0.15, 0.35]}
  initial.ecc: {disk: {within: contact.clearance, fraction: 0.9}}
"""
N = 6


def sweep(*args, env=None):
    return subprocess.run([sys.executable, "-m", "gimbalsim.sweep", *map(str, args)], capture_output=True,
                          text=True, timeout=600, env=env)


def make_sweep(folder, env=None):
    """A sweep of SPEC over a copy of paper_clearance.yaml in folder; returns its output folder."""
    folder.mkdir(exist_ok=True)
    shutil.copy(SCENES / "paper_clearance.yaml", folder / "scene.yaml")
    (folder / "spec.yaml").write_text(SPEC)
    p = sweep(folder / "spec.yaml", "--out", folder / "out", "--workers", "1", "--no-progress", env=env)
    assert p.returncode == 0, p.stderr
    return folder / "out"


def rows_of(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    return make_sweep(tmp_path_factory.mktemp("sweep"))


def loaded(folder, row):
    """Sample `row`'s scene loaded from its drawn columns by the scene API."""
    return gimbalsim.load_scene(folder / "scene.yaml", {
        **SET, "contact.clearance": float(row["contact_clearance_m"]), "friction.mu": float(row["friction_mu"]),
        "initial.ecc": [float(row["initial_ecc_0_m"]), float(row["initial_ecc_1_m"])]})


def test_applied_values_are_the_loaded_scenes(swept):
    rows = rows_of(swept / "results.csv")
    assert len(rows) == N
    clearance_rounded = 0
    for row in rows:
        v = loaded(swept.parent, row).values()
        # contact.clearance has no value of its own: the model runs with bearing_radius - journal_radius
        clearance = float(v["contact.bearing_radius"]) - float(v["contact.journal_radius"])
        assert float(row["applied_contact_clearance_m"]) == clearance
        assert row["applied_friction_mu"] == repr(float(v["friction.mu"]))
        ecc = [float(x) for x in v["initial.ecc"].strip("[]").split(",")]
        assert [float(row["applied_initial_ecc_0_m"]), float(row["applied_initial_ecc_1_m"])] == ecc
        assert row["applied_differs"] == ""  # journal_radius is bearing_radius - the drawn clearance, exactly
        clearance_rounded += row["applied_contact_clearance_m"] != row["contact_clearance_m"]
    # the subtraction loses the last bit for most draws: the column is what the scene applied, not the draw
    assert clearance_rounded > 0


def test_a_value_the_scene_does_not_apply_as_drawn_is_flagged(swept, monkeypatch):
    from gimbalsim import sweep as sweep_module

    spec = sweep_module.SweepSpec(swept / "spec.yaml", folder=swept.parent)
    i = next(i for i in range(N) if spec.design.draw(i)["friction.mu"] > 0.2)
    replace = gimbalsim.Scene.replace

    def clamping(self, overrides, sources=None):  # a scene that clamps friction.mu to 0.2
        overrides = dict(overrides)
        if "friction.mu" in overrides:
            overrides["friction.mu"] = min(overrides["friction.mu"], 0.2)
        return replace(self, overrides, sources)

    monkeypatch.setattr(gimbalsim.Scene, "replace", clamping)
    row, run = sweep_module.sample_alone(spec, i)
    row = dict(zip(spec.csv_header(), row))
    assert float(row["friction_mu"]) == spec.design.draw(i)["friction.mu"] > 0.2
    assert row["applied_friction_mu"] == "0.2"
    assert row["applied_differs"] == "friction.mu"
    assert run.scene.values()["friction.mu"] == "0.2"


def fingerprint(scene):
    """The documented fingerprint: SHA-256 of `key=value\\n` for every key, sorted by key."""
    v = scene.values()
    return hashlib.sha256("".join(f"{k}={v[k]}\n" for k in sorted(v)).encode()).hexdigest()


def test_fingerprint_in_results_and_summary(swept):
    expected = fingerprint(gimbalsim.load_scene(swept.parent / "scene.yaml", SET))
    assert {r["base_scene_sha256"] for r in rows_of(swept / "results.csv")} == {expected}
    summary = json.loads((swept / "summary.json").read_text())
    assert summary["fingerprints"] == {"base_scene_sha256": expected}
    assert summary["applied_differs"] == 0


def test_replay_reproduces_its_row_and_writes_the_time_series(swept, tmp_path):
    from test_csv_convention import check_convention

    out = tmp_path / "run.csv"
    p = sweep(swept, "--replay", 4, "--out", out)
    assert p.returncode == 0, p.stderr
    assert "reproduces its row" in p.stderr and "bit for bit" in p.stderr
    check_convention(out)
    row = rows_of(swept / "results.csv")[4]
    run = gimbalsim.simulate(loaded(swept.parent, row))  # the sample's run, made here by the scene API
    with open(out, newline="") as f:
        lines = list(csv.reader(f))
    assert len(lines) - 1 == len(run.rows) == round(SET["sim.duration"] / run.scene.output_interval) + 1
    run.to_csv(tmp_path / "expected.csv")
    assert out.read_bytes() == (tmp_path / "expected.csv").read_bytes()
    assert (tmp_path / "run.png").stat().st_size > 0


def test_a_row_that_does_not_reproduce_is_an_error_naming_its_columns(swept, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(swept, copy)
    lines = (copy / "results.csv").read_text().split("\n")
    header = lines[0].split(",")
    cells = lines[3].split(",")  # sample 2
    k = header.index("peak_joint2_force_N")
    cells[k] = repr(float(cells[k]) * (1 + 1e-15))
    lines[3] = ",".join(cells)
    (copy / "results.csv").write_text("\n".join(lines))
    p = sweep(copy, "--replay", 2, "--out", tmp_path / "run.csv", "--plot", tmp_path / "p.png")
    # its own code of the project's table (docs/usage.md "Exit codes"), not 1, an internal error
    assert p.returncode == 8, p.stderr
    lines = p.stderr.splitlines()
    assert lines[-1].startswith("replay: error: sample 2 does not reproduce its row") and \
        "1 column differ: peak_joint2_force_N" in lines[-1], p.stderr
    assert "Traceback" not in p.stderr
    assert (tmp_path / "run.csv").exists() and (tmp_path / "p.png").exists()  # what was computed is kept


def test_two_different_rows_of_one_sample_are_refused_not_one_of_them_compared(swept, tmp_path):
    # (pass 34) the replay compared with the first of two rows of sample 2 (the real one first: "reproduces",
    # exit 0; the edited one first: 8) and never said the study holds two
    copy = tmp_path / "copy"
    shutil.copytree(swept, copy)
    lines = (copy / "results.csv").read_text().rstrip("\n").split("\n")
    header = lines[0].split(",")
    cells = lines[3].split(",")  # sample 2
    cells[header.index("peak_joint2_force_N")] = "1"
    (copy / "results.csv").write_text("\n".join(lines + [",".join(cells)]) + "\n")
    p = sweep(copy, "--replay", 2, "--out", tmp_path / "run.csv")
    assert p.returncode == 2 and "two different rows of sample 2" in p.stderr and "results.csv:4 and " in p.stderr, \
        p.stderr
    assert not (tmp_path / "run.csv").exists()


def test_a_replay_runs_without_the_sweep_module(swept, tmp_path):
    """The replay takes what it shares with the sweep (the journal's name,
    the spec, one sample's run) from modules both import: with gimbalsim.sweep
    blocked it replays all the same."""
    code = ("import sys; sys.modules['gimbalsim.sweep'] = None\n"
            "from gimbalsim import replay\n"
            "sys.exit(replay.main(sys.argv[1], 3, sys.argv[2], None))")
    p = subprocess.run([sys.executable, "-c", code, str(swept), str(tmp_path / "run.csv")], capture_output=True,
                       text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    assert "reproduces its row" in p.stderr and (tmp_path / "run.csv").exists()


def test_replay_from_the_journal_alone(swept, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(swept, copy)
    lines = (copy / "results.csv").read_text().split("\n")
    (copy / "results.csv").unlink()
    (copy / "results.partial.csv").write_text("\n".join(lines[:3]) + "\n")  # samples 0 and 1 journaled
    p = sweep(copy, "--replay", 1, "--out", tmp_path / "run.csv")
    assert p.returncode == 0, p.stderr
    assert "results.partial.csv" in p.stderr
    p = sweep(copy, "--replay", 3, "--out", tmp_path / "run.csv")
    assert p.returncode == 2 and "sample 3 has no row" in p.stderr and "--resume" in p.stderr, p.stderr
    (copy / "results.partial.csv").unlink()
    p = sweep(copy, "--replay", 1, "--out", tmp_path / "run.csv")
    assert p.returncode == 2 and "holds neither results.csv nor the journal" in p.stderr, p.stderr


def test_a_last_row_cut_by_an_interruption_is_refused_as_not_whole_as_a_resume_drops_it(swept, tmp_path):
    # (bug) the replay read the cut row (its fingerprint cut short, every column there), ran the sample and blamed
    # the simulation (exit 8, outputs written); the resume's rule (_journal.whole_lines) drops the line
    copy = tmp_path / "copy"
    shutil.copytree(swept, copy)
    text = (copy / "results.csv").read_text()
    (copy / "results.csv").unlink()
    (copy / "results.partial.csv").write_text(text[:text.index("\n", text.index("\n2,") + 1) - 40])  # sample 2 cut
    p = sweep(copy, "--replay", 2, "--out", tmp_path / "run.csv")
    assert p.returncode == 2, p.stderr
    assert "results.partial.csv:4: sample 2's row is not whole (its last line, cut by an interruption)" in p.stderr \
        and "--resume" in p.stderr, p.stderr
    assert not (tmp_path / "run.csv").exists() and not (tmp_path / "run.png").exists()
    p = sweep(copy, "--replay", 1, "--out", tmp_path / "run.csv")  # the whole rows before it are the sweep's
    assert p.returncode == 0 and "reproduces its row of" in p.stderr, p.stderr


@pytest.mark.parametrize("case", ["out_of_range", "negative", "out_is_results", "out_is_journal_name",
                                  "out_is_folder", "out_folder_missing", "no_sweep_folder", "not_a_sweep",
                                  "plot_is_out"])
def test_refusals(swept, tmp_path, case):
    run_csv = tmp_path / "run.csv"
    args, message = {
        "out_of_range": ([swept, "--replay", N, "--out", run_csv], f"--replay {N}: outside the sweep's samples 0..5"),
        "negative": ([swept, "--replay", -1, "--out", run_csv], "--replay -1: outside the sweep's samples 0..5"),
        "out_is_results": ([swept, "--replay", 0, "--out", swept / "results.csv"], "inside the sweep's folder"),
        "out_is_journal_name": ([swept, "--replay", 0, "--out", swept / "run.csv"], "inside the sweep's folder"),
        "out_is_folder": ([swept, "--replay", 0, "--out", tmp_path], "is a folder"),
        "out_folder_missing": ([swept, "--replay", 0, "--out", tmp_path / "no" / "run.csv"], "does not exist"),
        "no_sweep_folder": ([tmp_path / "nowhere", "--replay", 0, "--out", run_csv], "no such sweep folder"),
        "not_a_sweep": ([tmp_path, "--replay", 0, "--out", run_csv], "not a sweep folder"),
        "plot_is_out": ([swept, "--replay", 0, "--out", run_csv, "--plot", run_csv], "the same file as --out"),
    }[case]
    before = sorted(os.listdir(swept))
    p = sweep(*args)
    assert p.returncode == 2, p.stderr
    assert message in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert not run_csv.exists() and sorted(os.listdir(swept)) == before


def test_changed_base_scene_is_refused_and_a_changed_spec_is_replayed_from_the_copy(tmp_path):
    out = make_sweep(tmp_path / "s")
    scene = tmp_path / "s" / "scene.yaml"
    text = scene.read_text()
    assert "restitution: 0.95" in text
    # the spec file edited after the sweep: the replay runs the sweep's own copy
    (tmp_path / "s" / "spec.yaml").write_text(SPEC.replace("seed: 3", "seed: 4"))
    p = sweep(out, "--replay", 0, "--out", tmp_path / "run.csv")
    assert p.returncode == 0, p.stderr
    assert f"{tmp_path / 's' / 'spec.yaml'} was edited since the sweep; replaying from the sweep's copy" \
        in p.stderr, p.stderr
    scene.write_text(text.replace("restitution: 0.95", "restitution: 0.9"))
    assert fingerprint(gimbalsim.load_scene(scene, SET)) != rows_of(out / "results.csv")[0]["base_scene_sha256"]
    p = sweep(out, "--replay", 0, "--out", tmp_path / "run2.csv")
    assert p.returncode == 2, p.stderr
    assert "base_scene_sha256 differs from the sweep's" in p.stderr
    assert "contact.restitution 0.95 -> 0.9" in p.stderr
    assert not (tmp_path / "run2.csv").exists()
    scene.unlink()  # gone: refused at the copy's `scene:` line
    p = sweep(out, "--replay", 0, "--out", tmp_path / "run2.csv")
    assert p.returncode == 2, p.stderr
    assert f"{out / 'spec.yaml'}:2:1: key 'scene': no such file: scene.yaml" in p.stderr, p.stderr


def test_a_crashed_sample_is_replayed_alone_and_reported(tmp_path):
    env = dict(os.environ, GIMBALSIM_TEST_KILL_WORKER_AT="2")
    out = make_sweep(tmp_path / "s", env=env)
    row = rows_of(out / "results.csv")[2]
    assert row["status"] == "crashed" and row["applied_friction_mu"] == ""
    p = sweep(out, "--replay", 2, "--out", tmp_path / "run.csv")
    assert p.returncode == 0, p.stderr
    assert "recorded crashed" in p.stderr and "ran alone to status ok" in p.stderr
    assert (tmp_path / "run.csv").exists()


def test_closed_loop_provenance_reads_the_loaded_controller(tmp_path):
    """What a closed-loop sweep (a spec with a `controller`) gets from the
    provenance module: the controller's fingerprint (its file with the
    spec's overrides) and its keys as loaded."""
    from conftest import CONTROLLER_CONFIG
    from gimbalsim import _provenance
    from gimbalsim.sweep import SweepSpec

    shutil.copy(SCENES / "paper_clearance.yaml", tmp_path / "scene.yaml")
    shutil.copy(CONTROLLER_CONFIG, tmp_path / "ctrl.yaml")
    (tmp_path / "spec.yaml").write_text(CLOSED_SPEC.replace("controller: ctrl.yaml",
                                                            "controller: ctrl.yaml\ncontroller_set: {azimuth.kp: 900.0}"))
    spec = SweepSpec(tmp_path / "spec.yaml")
    ctrl = gimbalsim.Controller(CONTROLLER_CONFIG, {"azimuth.kp": 900.0})
    scene = gimbalsim.load_scene(tmp_path / "scene.yaml", {"sim.duration": 1.0, **spec.sampling["overrides"]})
    v = ctrl._values_text()  # the --set text of each key, as scene.values() gives a scene's
    expected = hashlib.sha256("".join(f"{k}={v[k]}\n" for k in sorted(v)).encode())
    assert _provenance.fingerprints(spec) == {"base_scene_sha256": fingerprint(scene),
                                              "controller_config_sha256": expected.hexdigest()}
    v0 = gimbalsim.Controller(CONTROLLER_CONFIG)._values_text()  # without the spec's override
    assert expected.hexdigest() != hashlib.sha256("".join(f"{k}={v0[k]}\n" for k in sorted(v0)).encode()).hexdigest()
    loaded = {**scene.values(), **ctrl._values_text()}
    assert _provenance.applied(loaded, {"azimuth.kp": 900.0, "friction.mu": 0.25}) == [900.0, 0.25, ""]
    assert _provenance.applied(loaded, {"azimuth.kp": 901.0}) == [900.0, "azimuth.kp"]
    # a closed-loop design names controller keys controller.<key>
    prefixed = {**scene.values(), **{"controller." + k: t for k, t in ctrl._values_text().items()}}
    assert _provenance.applied(prefixed, {"controller.azimuth.kp": 900.0}) == [900.0, ""]


def test_a_sample_whose_run_stopped_reproduces_and_exits_3(tmp_path):
    folder = tmp_path / "s"
    folder.mkdir()
    shutil.copy(SCENES / "paper_clearance.yaml", folder / "scene.yaml")
    stopping = SPEC.replace("{sim.duration: 0.15}", "{sim.duration: 0.15, sim.velocity_limit: 0.01}")
    (folder / "spec.yaml").write_text(stopping)
    p = sweep(folder / "spec.yaml", "--out", folder / "out", "--workers", "1", "--no-progress")
    assert p.returncode == 0, p.stderr
    row = rows_of(folder / "out" / "results.csv")[1]
    assert row["status"] == "sim.velocity_limit"
    p = sweep(folder / "out", "--replay", 1, "--out", tmp_path / "run.csv")
    assert p.returncode == 3, p.stderr
    assert "reproduces its row" in p.stderr and "sim.velocity_limit" in p.stderr
    # the stop's own time and words (it printed the last row's time and "()" for a closed loop)
    assert "status sim.velocity_limit: the run stopped at t = " in p.stderr and "()" not in p.stderr, p.stderr
    assert "a velocity exceeded sim.velocity_limit" in p.stderr
    with open(tmp_path / "run.csv") as f:
        n = sum(1 for _ in f) - 1
    assert 0 < n < round(0.15 / 0.001) + 1  # the rows up to the stop


CLOSED_SPEC = """
scene: scene.yaml
set: {sim.duration: 1.0}
controller: ctrl.yaml
samples: 3
seed: 5
parameters:
  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}
  controller.azimuth.kp: {uniform: [800.0, 1200.0]}
phases: [{first: [0.0, 1.0]}]   # the run is shorter than the profile's slew
indices:
  ape: {}
"""


def test_a_closed_loop_sample_is_replayed_bit_for_bit_and_its_controller_fingerprinted(tmp_path):
    """A closed-loop sweep: the controller's fingerprint and applied keys in
    results.csv (checked through the Controller API), a replay that
    reproduces its row and writes the ticks by the CSV convention (the same
    truth error as a closed loop run here), and a controller file changed
    since the sweep refused by its fingerprint."""
    from conftest import CONTROLLER_CONFIG
    from test_csv_convention import check_convention

    shutil.copy(SCENES / "paper_clearance.yaml", tmp_path / "scene.yaml")
    shutil.copy(CONTROLLER_CONFIG, tmp_path / "ctrl.yaml")
    (tmp_path / "spec.yaml").write_text(CLOSED_SPEC)
    p = sweep(tmp_path / "spec.yaml", "--out", tmp_path / "out", "--workers", "1", "--no-progress")
    assert p.returncode == 0, p.stderr
    rows = rows_of(tmp_path / "out" / "results.csv")
    v = gimbalsim.Controller(tmp_path / "ctrl.yaml")._values_text()
    expected = hashlib.sha256("".join(f"{k}={v[k]}\n" for k in sorted(v)).encode()).hexdigest()
    assert {r["controller_config_sha256"] for r in rows} == {expected}
    kp_drawn = next(c for c in rows[0] if c.startswith("controller_azimuth_kp"))
    kp_applied = next(c for c in rows[0] if c.startswith("applied_controller_azimuth_kp"))
    assert all(float(r[kp_applied]) == float(r[kp_drawn]) and not r["applied_differs"] for r in rows)

    out = tmp_path / "run.csv"
    p = sweep(tmp_path / "out", "--replay", 1, "--out", out)
    assert p.returncode == 0, p.stderr
    assert "bit for bit" in p.stderr
    check_convention(out)
    r = rows[1]
    from gimbalsim.sweep import SweepSpec
    stepping = SweepSpec(tmp_path / "spec.yaml").sampling["overrides"]  # as the sweep steps it (_sampling.py)
    scene = gimbalsim.load_scene(tmp_path / "scene.yaml", {"sim.duration": 1.0,
                                                            "contact.clearance": float(r["contact_clearance_m"]),
                                                            **stepping})
    run = gimbalsim.closed_loop(scene, gimbalsim.Controller(tmp_path / "ctrl.yaml",
                                                            {"azimuth.kp": float(r[kp_drawn])}), 1.0)
    with open(out, newline="") as f:
        ticks = list(csv.DictReader(f))
    assert len(ticks) == len(run.columns["t"])
    assert [float(t["truth_error_rad"]) for t in ticks] == [float(x) for x in run.columns["truth_error"]]
    assert (tmp_path / "run.png").stat().st_size > 0
    # the closed loop's plot shows its own columns: true joint angles, applied torques, truth error
    from types import SimpleNamespace
    from gimbalsim import replay
    drawn = [label for label, _ in replay._panels(run)]
    assert drawn == ["joint angle [rad]", "applied torque [N m]", "truth pointing error [rad]"]
    png = replay._plot(run, SimpleNamespace(spec_path=tmp_path / "out" / "spec.yaml"), 1, "ok", "png")
    assert png.startswith(b"\x89PNG")

    text = (tmp_path / "ctrl.yaml").read_text()
    assert text.count("kd: 1050") == 1  # the elevation's derivative gain, changed since the sweep
    (tmp_path / "ctrl.yaml").write_text(text.replace("kd: 1050", "kd: 1049"))
    p = sweep(tmp_path / "out", "--replay", 1, "--out", tmp_path / "again.csv")
    assert p.returncode == 2, p.stderr
    assert "controller_config_sha256" in p.stderr and "ctrl.yaml" in p.stderr
    assert not (tmp_path / "again.csv").exists()


def test_a_figure_format_matplotlib_cannot_write_is_refused_before_anything_runs(swept, tmp_path):
    (tmp_path / "notes.yaml").write_text("mine: 1\n")
    p = sweep(swept, "--replay", 2, "--out", tmp_path / "run.csv", "--plot", tmp_path / "notes.yaml")
    assert p.returncode == 2, p.stderr
    assert "--plot" in p.stderr and "not 'yaml'" in p.stderr and "Traceback" not in p.stderr
    assert not (tmp_path / "run.csv").exists() and (tmp_path / "notes.yaml").read_text() == "mine: 1\n"
    # pgf needs a LaTeX the project does not install: not offered (it was a traceback)
    p = sweep(swept, "--replay", 2, "--out", tmp_path / "run.csv", "--plot", tmp_path / "run.pgf")
    assert p.returncode == 2 and "not 'pgf'" in p.stderr and "Traceback" not in p.stderr, p.stderr


def test_a_plot_that_cannot_be_written_takes_its_csv_with_it(swept, tmp_path, monkeypatch):
    from gimbalsim import replay
    from gimbalsim._output import OutputError

    def full_disk(path, data, inputs=()):
        raise OutputError(f"{path}: write failed: No space left on device")
    monkeypatch.setattr(replay, "write_bytes", full_disk)
    with pytest.raises(OutputError, match="No space left"):
        replay.replay(swept, 2, tmp_path / "run.csv", tmp_path / "run.png")
    assert sorted(os.listdir(tmp_path)) == []  # neither output, no temporary


def test_the_spec_the_sweep_ran_from_is_never_an_output(swept):
    # The original spec (beside the sweep folder) is an input of the replay too: refused, left whole.
    original = swept.parent / "spec.yaml"
    before = original.read_bytes()
    p = sweep(swept, "--replay", 1, "--out", original, "--plot", swept.parent / "never.png")
    assert p.returncode == 2, p.stderr
    assert original.read_bytes() == before and not (swept.parent / "never.png").exists()


@pytest.mark.parametrize("name", ["results.csv", "summary.json"])
def test_a_hard_link_of_a_file_of_the_sweep_is_never_an_output(swept, tmp_path, name):
    # (pass 69) --out inside the folder was refused, but a hard link of its results.csv or summary.json
    # elsewhere was written over (a new file under the link's name, the study's own left as it was)
    link = tmp_path / "link.csv"
    os.link(swept / name, link)
    before = (swept / name).read_bytes()
    p = sweep(swept, "--replay", 1, "--out", link, "--plot", tmp_path / "never.png")
    assert p.returncode == 2, p.stderr
    assert "the same file as the input" in p.stderr and name in p.stderr, p.stderr
    assert link.read_bytes() == before and os.path.samefile(link, swept / name)
    assert not (tmp_path / "never.png").exists()


def test_a_replayed_stop_is_said_in_the_runs_own_words():
    from gimbalsim.replay import _stop_text
    scene = gimbalsim.load_scene(SCENES / "paper_clearance.yaml", {"sim.velocity_limit": 0.05})
    ctrl = gimbalsim.Controller(None, {"profile.slew_start": 0.0, "profile.slew_time": 0.1, "profile.hold_time": 0.1})
    closed = gimbalsim.closed_loop(scene, ctrl, 0.4).summary
    text = _stop_text(closed, "sim.velocity_limit")
    assert text.startswith("status sim.velocity_limit: simulation stopped at t = 0.007 s") and "()" not in text, text
    # an open-loop sample whose ideal-joint twin stopped: the run did not
    open_ok = {"stop": None}  # as an open loop that ended ok gives it
    text = _stop_text(open_ok, "ideal:sim.energy_tol")
    assert text == ("status ideal:sim.energy_tol: the ideal-joint twin (the pointing error's reference) stopped on "
                    "sim.energy_tol, so the sample has no pointing error"), text
