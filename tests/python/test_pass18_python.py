"""Issue 41, "Hostile and careless input" (pass 18): a tracker key dispersed
under an outage over the whole run, sweep --check doing every refusal of the
run, a replay's outputs inside another tool's folder, an RPE window of one
control period, and a closed stderr (`2>&1 | head -1`).

The runs are cheap: test_allocate.py's scene (the antenna holds still for 0.3 s)."""
import math
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import SCENES
from test_pass16_outputs import ALLOCATE, BASE, SWEEP, TUNE, tool, write_spec
import gimbalsim._errors as errors
from gimbalsim import indices


def check(spec, out, *args):
    return subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", str(out), "--check", *args],
                          capture_output=True, text=True, timeout=120)


# ---- D4 (class 3): a tracker key under an outage over the whole run does not act, whichever key is dispersed ----

OUTAGE = BASE.replace("{sim.duration: 0.3}", "{sim.duration: 0.3, sensors.star_tracker_outage: [0, 5]}") \
    .replace("  sensors.seed: {choice: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]}\n", "")
assert "sensors.seed" not in OUTAGE
TRACKER = f"""scene: {SCENES}/paper_spatial2_tracker.yaml
set: {{sim.duration: 0.3, sensors.tracker_outage: [0, 5]}}
controller: default
samples: 2
seed: 1
phases: [{{late: [0.2, 0.3]}}]
indices:
  ape: {{}}
parameters:
"""
DISPERSED = [
    (OUTAGE, "sensors.star_tracker_latency", {"sensors.star_tracker_latency": "{uniform: [0.0, 0.005]}"}),
    # the noise judged while the latency is drawn from a range too: the outage still takes every sample
    (OUTAGE, "sensors.star_tracker_noise", {"sensors.star_tracker_noise": "{uniform: [0.0, 1.0e-4]}",
                                            "sensors.star_tracker_latency": "{uniform: [0.0, 0.005]}"}),
    (TRACKER, "sensors.tracker_latency", {"sensors.tracker_latency": "{uniform: [0.0, 0.005]}"}),
    (TRACKER, "sensors.tracker_noise", {"sensors.tracker_noise": "{uniform: [0.0, 1.0e-4]}",
                                        "sensors.tracker_latency": "{uniform: [0.0, 0.005]}"}),
]


@pytest.mark.parametrize("text,key,dispersed", DISPERSED, ids=[f"{k}-{len(d)}" for _, k, d in DISPERSED])
def test_a_tracker_key_under_an_outage_over_the_whole_run_is_refused(tmp_path, text, key, dispersed):
    text = text.replace("parameters:\n", "parameters:\n" + "".join(f"  {k}: {v}\n" for k, v in dispersed.items()))
    spec = write_spec(tmp_path, text)
    p = check(spec, tmp_path / "out")
    assert p.returncode == 2, p.stderr
    assert f"key 'parameters.{key}'" in p.stderr and "covers the whole run" in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()


def test_a_tuners_plant_latency_under_an_outage_over_the_whole_run_is_refused(tmp_path):
    text = TUNE.replace("controller: default", "set: {sensors.star_tracker_outage: [0, 10]}\ncontroller: default") + \
        "  sensors.star_tracker_latency: {uniform: [0.0, 0.005]}\n"
    spec = write_spec(tmp_path, text)
    p = tool("tune", spec, tmp_path / "out")
    assert p.returncode == 2, p.stderr
    assert "key 'plants.sensors.star_tracker_latency'" in p.stderr and "covers the whole run" in p.stderr, p.stderr


# ---- D5 (class 7): sweep --check refuses what the run refuses, and writes nothing ----

CASES = ["finished", "link", "allocation-resume", "until-phase", "grown-past-the-cap"]


@pytest.mark.parametrize("case", CASES)
def test_check_refuses_what_the_run_refuses(tmp_path, case):
    spec = write_spec(tmp_path, SWEEP)
    out, args = tmp_path / "out", []
    if case == "finished":
        out.mkdir()
        (out / "results.csv").write_text("sample\n")
    elif case == "link":
        out.mkdir()
        (tmp_path / "victim.txt").write_text("victim\n")
        (out / "results.csv").symlink_to(tmp_path / "victim.txt")
    elif case == "allocation-resume":
        out.mkdir()
        (out / "allocation_spec.json").write_text("{}")
        args = ["--resume"]
    elif case == "until-phase":
        args = ["--until", "ape:early:0.2"]  # the spec's phase is late
    else:  # an earlier --until grew it to 8 samples: a cap of 4 would say it stopped there
        out.mkdir()
        (out / "design.json").write_text('{"samples": 8}')
        args = ["--resume", "--until", "ape:late:0.2", "--max-samples", "4"]
    before = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*"))
    p = check(spec, out, *args)
    assert p.returncode == 2, p.stderr
    assert sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*")) == before  # nothing written
    run = tool("sweep", spec, out, *args)
    assert run.returncode == 2, run.stderr
    assert p.stderr.splitlines()[-1] == run.stderr.splitlines()[-1]  # the one refusal, said the same


# ---- D7 (class 6): a replay never writes inside another tool's folder ----

@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    d = tmp_path_factory.mktemp("swept")
    spec = write_spec(d, SWEEP.replace("samples: 4", "samples: 1"))
    p = tool("sweep", spec, d / "out")
    assert p.returncode == 0, p.stderr
    return d / "out"


HELD = [("allocation_spec.json", "allocation.csv", "an allocation"),
        ("allocation_spec.json", "values/0/run.csv", "an allocation"),
        ("study.db", "trials.csv", "a tuning study"),
        ("spec.json inputs.json", "results.csv", "a sweep"),
        ("spec.json inputs.json", "plots/x.csv", "a sweep")]


@pytest.mark.parametrize("flag", ["--out", "--plot"])
@pytest.mark.parametrize("marks,name,what", HELD, ids=[f"{w.split()[-1]}-{n}" for _, n, w in HELD])
def test_a_replay_output_inside_another_tools_folder_is_refused(tmp_path, swept, flag, marks, name, what):
    held = tmp_path / "held"
    (held / name).parent.mkdir(parents=True)
    for m in marks.split():
        (held / m).write_text("{}")
    target = held / name
    target.write_text("theirs\n")
    given = {"--out": target, "--plot": target.with_suffix(".png")}
    if flag == "--out":
        args = ["--out", str(target)]
    else:
        given["--plot"].write_bytes(b"theirs")
        args = ["--out", str(tmp_path / "mine.csv"), "--plot", str(given["--plot"])]
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(swept), "--replay", "0", *args],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2, p.stderr
    assert f"{flag} {given[flag]}: lies inside {what} ({held})" in p.stderr, p.stderr
    assert target.read_text() == "theirs\n" and not (tmp_path / "mine.csv").exists()
    if flag == "--plot":
        assert given["--plot"].read_bytes() == b"theirs"


# ---- a relative --out is where it really goes: '../x' from inside a study's folder is outside it ----

STANDING = [("sweep", "a sweep"), ("replay", "a sweep"), ("allocate", "an allocation"), ("tune", "a tuning study")]


@pytest.mark.parametrize("program,what", STANDING, ids=[p for p, _ in STANDING])
def test_a_relative_out_is_read_from_where_it_leads_not_from_the_folder_one_stands_in(tmp_path, swept, program, what):
    # DIR/../x was walked upward as named: DIR, a study, refused it as lying inside (the absolute path was taken)
    study = tmp_path / "study"
    shutil.copytree(swept, study)  # a real sweep: replay reads it; the marks are all the other tools look for
    for mark in {"allocate": ["allocation_spec.json"], "tune": ["study.db"]}.get(program, []):
        (study / mark).write_text("{}")
    # tune has no --check: a spec it refuses stops it after --out was checked, before anything runs
    spec = write_spec(tmp_path, {"sweep": SWEEP, "allocate": BASE + ALLOCATE, "tune": "trials: 2\n"}.get(program, ""))
    before = sorted(p.name for p in study.rglob("*"))

    def run(out):
        args = ([str(study), "--replay", "0"] if program == "replay" else [str(spec), "--workers", "1"]) + \
            ["--out", out] + (["--check"] if program in ("sweep", "allocate") else [])
        module = "sweep" if program == "replay" else program
        return subprocess.run([sys.executable, "-m", f"gimbalsim.{module}", *args], capture_output=True, text=True,
                              timeout=120, cwd=study)

    outside = run("../x.csv" if program == "replay" else "../x")
    assert "lies inside" not in outside.stderr, outside.stderr
    assert outside.returncode == (2 if program == "tune" else 0), outside.stderr
    if program == "replay":
        assert (tmp_path / "x.csv").is_file()
    inside = run("./x.csv" if program == "replay" else "./x")  # truly inside: still refused, nothing written
    assert inside.returncode == 2, inside.stderr
    assert ("inside the sweep's folder" if program == "replay" else f"lies inside {what} ({study})") in inside.stderr, \
        inside.stderr
    assert sorted(p.name for p in study.rglob("*")) == before


# ---- D8 (class 4): an RPE window of one control period holds one tick: 0 by construction ----

def test_an_rpe_window_of_one_control_period_is_refused_at_its_line(tmp_path):
    text = SWEEP.replace("  ape: {}\n", "  ape: {}\n  rpe: {window: 0.001, requirement: 1.0e-12}\n")
    spec = write_spec(tmp_path, text)
    p = check(spec, tmp_path / "out")
    line = next(k for k, s in enumerate(text.split("\n"), 1) if s.lstrip().startswith("rpe:"))
    assert p.returncode == 2 and f"spec.yaml:{line}:" in p.stderr and "indices.rpe.window" in p.stderr, p.stderr
    assert "two control periods" in p.stderr, p.stderr
    # two periods hold a deviation from their mean: taken
    p = check(write_spec(tmp_path, text.replace("window: 0.001", "window: 0.002")), tmp_path / "out")
    assert p.returncode == 0, p.stderr


def test_an_rpe_window_of_one_control_period_at_a_grid_point_is_refused_at_the_grid(tmp_path):
    text = SWEEP.replace("  ape: {}\n", "  rpe: {window: 0.002}\n") + \
        "grid:\n  controller.control.period: [0.001, 0.002]\n"
    p = check(write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2 and "grid.controller.control.period" in p.stderr, p.stderr
    assert "holds one control tick" in p.stderr, p.stderr


def test_indices_rpe_of_a_one_sample_window_is_nan_with_a_reason():
    t = np.arange(0, 1.0, 0.001)
    v = indices.rpe(t, 1e-5 * np.sin(7 * t), 0.2, 0.8, 0.001)
    assert math.isnan(v.value) and not v.ok and "one sample" in v.reason, v.reason
    assert indices.rpe(t, 1e-5 * np.sin(7 * t), 0.2, 0.8, 0.002).value > 0


# ---- D10 (class 10): a closed stderr stops no program and makes no exit 1 ----

class _Closed:
    """A stderr whose reader is gone."""

    def write(self, text):
        raise BrokenPipeError(32, "Broken pipe")

    def flush(self):
        raise BrokenPipeError(32, "Broken pipe")


@pytest.mark.parametrize("raised,code", [(None, 0), (errors.SpecError("refused"), 2)])
def test_guarded_main_goes_on_with_a_closed_stderr(monkeypatch, raised, code):
    monkeypatch.setattr(sys, "stderr", _Closed())
    seen = []

    def body():
        for k in range(3):
            print(f"line {k}", file=sys.stderr)
            seen.append(k)
        sys.stderr.flush()
        if raised is not None:
            raise raised
        return 0
    assert errors.guarded_main("sweep", body) == code
    assert seen == [0, 1, 2]


@pytest.mark.parametrize("program", ["sweep", "allocate"])
def test_a_study_into_a_closed_pipe_finishes_with_its_exit_code(tmp_path, program):
    spec = write_spec(tmp_path, SWEEP if program == "sweep" else BASE + ALLOCATE)
    out = tmp_path / "out"
    p = subprocess.run(["bash", "-c", f'"{sys.executable}" -m gimbalsim.{program} "{spec}" --out "{out}" '
                        '--workers 1 --no-progress 2>&1 | head -1 >/dev/null; echo "rc=${PIPESTATUS[0]}"'],
                       capture_output=True, text=True, timeout=300)
    assert p.stdout.strip() in ("rc=0", "rc=3"), p.stdout + p.stderr
    assert (out / ("results.csv" if program == "sweep" else "allocation.json")).is_file()
