"""The outputs of allocate, sweep and tune, checked before any run (exit 2):
no output written through a link or onto something of another kind, no
folder holding another tool's outputs, an allocation's resume of a value as
the sweep's own resume (a damaged value's rows checked, its missing samples
run), a range whose values the sweep would refuse, and keys that do not act.

The runs are cheap: the antenna holds still for 0.3 s (test_allocate.py's scene)."""
import csv
import json
import shutil
import subprocess
import sys

import pytest

from conftest import SCENES
from test_allocate import BASE as ALLOCATION_BASE

# test_allocate's spec, four units a value
BASE = ALLOCATION_BASE.replace("samples: 8", "samples: 4")
assert "samples: 4" in BASE
ALLOCATE = """allocate:
  key: sensors.star_tracker_noise
  range: [1.0e-5, 3.0e-4]
  direction: largest
  index: ape
  phase: late
  requirement: 6.0e-5
  level: 0.5
  confidence: 0.5
  values: 3
"""


SWEEP = BASE.replace("{sim.duration: 0.3}", "{sim.duration: 0.3, sensors.star_tracker_noise: 1.0e-4}")


def write_spec(folder, text, name="spec.yaml"):
    path = folder / name
    path.write_text(text)
    return path


def tool(name, spec, out, *args):
    return subprocess.run([sys.executable, "-m", f"gimbalsim.{name}", str(spec), "--out", str(out), "--workers", "1",
                           "--no-progress", *args], capture_output=True, text=True, timeout=300)


def line_of(text, start):
    return next(k for k, line in enumerate(text.split("\n"), 1) if line.lstrip().startswith(start))


def nothing_ran(out):
    return not any(out.rglob("results.partial.csv")) and not any(out.rglob("results.csv"))


# ---- F1, F2: every output name of allocate refused up front when a link or not its kind ----

LINKS = ["values/1", "values/2/report.md", "values/2/plots", "values/1/plots/ape_late_cdf.png"]


@pytest.mark.parametrize("name", LINKS)
def test_a_link_under_any_name_allocate_writes_is_refused_before_running(tmp_path, name):
    spec = write_spec(tmp_path, BASE + ALLOCATE)
    out, victim = tmp_path / "out", tmp_path / "victim"
    victim.mkdir()
    (out / name).parent.mkdir(parents=True)
    (out / name).symlink_to(victim)
    p = tool("allocate", spec, out, "--resume")
    assert p.returncode == 2 and f"{out / name}: a symbolic link" in p.stderr, p.stderr
    assert not any(victim.iterdir()) and nothing_ran(out)


FOLDERS = ["allocation.png", "allocation.json", "allocation.md", "allocation.csv", "allocation_spec.json",
           "values/0/summary.json"]


@pytest.mark.parametrize("name", FOLDERS)
def test_a_folder_under_a_file_name_allocate_writes_is_refused_before_running(tmp_path, name):
    spec = write_spec(tmp_path, BASE + ALLOCATE)
    out = tmp_path / "out"
    (out / name).mkdir(parents=True)
    p = tool("allocate", spec, out, *(["--resume"] if name.startswith("values") else []))
    assert p.returncode == 2, p.stderr
    assert f"{out / name}: not a regular file (a folder) where this run writes a file" in p.stderr, p.stderr
    assert nothing_ran(out)


def test_a_file_under_the_values_folder_is_refused_before_running(tmp_path):
    spec = write_spec(tmp_path, BASE + ALLOCATE)
    out = tmp_path / "out"
    (out / "values").mkdir(parents=True)
    (out / "values" / "1").write_text("")
    p = tool("allocate", spec, out, "--resume")
    assert p.returncode == 2, p.stderr
    assert f"{out / 'values' / '1'}: not a folder (a file) where this run writes a folder" in p.stderr, p.stderr
    assert nothing_ran(out)


@pytest.mark.parametrize("name", ["summary.json", "report.md", "plots/ape_late_cdf.png"])
def test_a_folder_under_a_file_name_the_sweep_writes_is_refused_before_running(tmp_path, name):
    spec = write_spec(tmp_path, SWEEP)
    out = tmp_path / "out"
    (out / name).mkdir(parents=True)
    p = tool("sweep", spec, out)
    assert p.returncode == 2, p.stderr
    assert f"{out / name}: not a regular file (a folder) where this run writes a file" in p.stderr, p.stderr
    assert nothing_ran(out)


# ---- F3: a resume of a finished value goes through the sweep's own checks ----

@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    d = tmp_path_factory.mktemp("finished")
    spec = write_spec(d, BASE + ALLOCATE)
    p = tool("allocate", spec, d / "out")
    assert p.returncode in (0, 3), p.stderr
    return spec, d / "out", p.returncode, json.loads((d / "out" / "allocation.json").read_text())


def test_a_resume_runs_the_missing_samples_and_drops_rows_the_sweep_did_not_write(tmp_path, finished):
    spec, first, code, answer = finished
    out = tmp_path / "out"
    shutil.copytree(first, out)
    rows = {k: (out / "values" / str(k) / "results.csv").read_text().splitlines(keepends=True) for k in range(3)}
    (out / "values" / "0" / "results.csv").write_text("".join(rows[0][:-1]))  # the last sample missing
    renumbered = rows[1][2].split(",", 1)
    (out / "values" / "1" / "results.csv").write_text("".join(rows[1][:2] + [f"7,{renumbered[1]}"] + rows[1][3:]))
    (out / "values" / "2" / "results.csv").write_text("".join(rows[2] + rows[2][-1:]))  # a row twice
    p = tool("allocate", spec, out, "--resume")
    assert p.returncode == code, p.stderr
    again = json.loads((out / "allocation.json").read_text())
    assert [v["n"] for v in again["values"]] == [4, 4, 4]
    assert again["values"] == answer["values"] and again["runs_used"] == 12
    assert "(read back)" not in p.stderr and "sample index outside the design" in p.stderr, p.stderr
    for k in range(3):  # each value's results whole again, as the sweep wrote them (all but the run's wall time)
        assert without_wall_time(out / "values" / str(k) / "results.csv") == \
            without_wall_time(first / "values" / str(k) / "results.csv")


def without_wall_time(path):
    with open(path, newline="") as f:
        return [{k: v for k, v in r.items() if k != "wall_time_s"} for r in csv.DictReader(f)]


# ---- F6: no tool writes into a folder holding another's outputs ----

TUNE = f"""scene: {SCENES}/paper_clearance.yaml
controller: default
duration: 3.6
trials: 2
parallel_trials: 1
seed: 1
batch: 2
objective: {{metric: max_track, percentile: 90}}
max_saturation: 1.0
gains:
  azimuth.kp: {{loguniform: [5000, 80000]}}
plants:
  friction.mu: {{uniform: [0.15, 0.35]}}
"""
HELD = [("allocate", "results.csv", "a sweep"), ("allocate", "results.partial.csv", "a sweep"),
        ("allocate", "study.db", "a tuning study"), ("allocate", "trials.csv", "a tuning study"),
        ("sweep", "allocation.json", "an allocation"), ("sweep", "allocation_spec.json", "an allocation"),
        ("sweep", "values/", "an allocation"), ("tune", "allocation_spec.json", "an allocation"),
        ("tune", "values/", "an allocation")]


@pytest.mark.parametrize("resume", [False, True], ids=["new", "resume"])
@pytest.mark.parametrize("program,held,what", HELD, ids=[f"{p}-{h}" for p, h, _ in HELD])
def test_a_folder_holding_another_tools_outputs_is_refused(tmp_path, program, held, what, resume):
    text = {"allocate": BASE + ALLOCATE, "sweep": SWEEP, "tune": TUNE}[program]
    spec = write_spec(tmp_path, text)
    out = tmp_path / "out"
    out.mkdir()
    (out / held.rstrip("/")).mkdir() if held.endswith("/") else (out / held).write_text("")
    p = tool(program, spec, out, *(["--resume"] if resume else []))
    assert p.returncode == 2 and f"{out} holds {what} ({held.rstrip('/')}" in p.stderr, p.stderr
    assert sorted(f.name for f in out.iterdir()) == [held.rstrip("/")]  # nothing written


# ---- F8: a range where a value's runs never reach the phase ----

# slew 0.1 s and hold 0.1 s from slew_start (the controller's 0.5 s): the track from 0.7 s of a 0.8 s run
REACH = SWEEP.replace("profile.slew_start: 0.0, ", "").replace("[{late: [0.2, 0.3]}]", "[track]") \
    .replace("sim.duration: 0.3", "sim.duration: 0.8")


def test_a_range_whose_runs_end_before_the_phase_is_refused_at_its_line(tmp_path):
    text = REACH + ALLOCATE.replace("sensors.star_tracker_noise", "controller.profile.slew_start") \
        .replace("[1.0e-5, 3.0e-4]", "[0.0, 0.6]").replace("phase: late", "phase: track")
    p = tool("allocate", write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2, p.stderr
    assert f"spec.yaml:{line_of(text, 'range:')}:" in p.stderr and "key 'allocate.range'" in p.stderr, p.stderr
    assert "controller.profile.slew_start = 0.6: " in p.stderr and "before phase 'track'" in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()


def test_a_grid_point_whose_runs_end_before_the_phase_is_refused_at_its_line(tmp_path):
    text = REACH.replace("parameters:", "grid: {controller.profile.slew_start: [0.0, 0.65]}\nparameters:")
    p = tool("sweep", write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2, p.stderr
    assert f"spec.yaml:{line_of(text, 'grid:')}:" in p.stderr and "before phase 'track'" in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()


# ---- F4: controller keys at the antenna, on a scene without the antenna's sensors ----

def test_an_antenna_controller_key_is_refused_as_the_allocation_key(tmp_path):
    text = SWEEP + ALLOCATE.replace("sensors.star_tracker_noise", "controller.antenna.bandwidth") \
        .replace("[1.0e-5, 3.0e-4]", "[5.0, 20.0]")
    p = tool("allocate", write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2 and f"spec.yaml:{line_of(text, 'key:')}:" in p.stderr, p.stderr
    assert "key 'allocate.key'" in p.stderr and "sensors.antenna is none" in p.stderr, p.stderr


def test_an_antenna_controller_key_is_refused_as_a_gain(tmp_path):
    text = TUNE.replace("azimuth.kp: {loguniform: [5000, 80000]}", "antenna.bandwidth: {uniform: [5, 20]}")
    p = tool("tune", write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2 and "key 'gains.antenna.bandwidth'" in p.stderr, p.stderr
    assert "sensors.antenna is none" in p.stderr and not (tmp_path / "out").exists(), p.stderr
