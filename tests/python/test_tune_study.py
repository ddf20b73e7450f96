"""gimbalsim.tune keeps its evidence: each trial's per-plant results in
trials.csv, trial 0 the configuration's own gains, the study stored in
OUT/study.db so that --resume continues it after a SIGKILL (the killed trial
failed and run again, the numbering continued, the requested count reached),
and a study folder never overwritten without --resume."""
import contextlib
import csv
import json
import os
import resource
import signal
import sqlite3
import subprocess
import sys
import time

import pytest

import gimbalsim
from conftest import CONTROLLER_CONFIG, SCENES

CLEARANCE = 3.0e-4
DURATION = 3.7
# Plants that differ a little (a batch of one plant is refused): the test computes each plant's runs itself.
SPEC = f"""
scene: {SCENES}/paper_clearance.yaml
controller: {CONTROLLER_CONFIG}
duration: {DURATION}
trials: TRIALS
parallel_trials: 1
seed: 3
batch: 2
objective: {{metric: max_track, percentile: 90}}
gains:
  azimuth.kp: {{loguniform: [5000, 80000]}}
  elevation.kd: {{uniform: [300, 3000]}}
plants:
  contact.clearance: {{uniform: [{CLEARANCE * 0.9}, {CLEARANCE}]}}
"""
GAINS = ("azimuth.kp", "elevation.kd")
COLUMN = {"azimuth.kp": "azimuth_kp_Nm_per_rad", "elevation.kd": "elevation_kd_Nms_per_rad"}  # trials.csv
FIGURES = ("max_truth_error_track_rad", "rms_truth_error_track_rad", "controller_limited_ticks", "ticks")


def tune_cmd(spec, out, *args):
    return [sys.executable, "-m", "gimbalsim.tune", str(spec), "--out", str(out), "--no-progress", "--workers", "1",
            *args]


def write_spec(tmp_path, trials):
    (tmp_path / "t.yaml").write_text(SPEC.replace("TRIALS", str(trials)))
    return tmp_path / "t.yaml"


def trials(out):
    from test_csv_convention import check_convention
    check_convention(out / "trials.csv")  # the project's CSV convention: numpy and csv read the same names
    with open(out / "trials.csv") as f:
        return list(csv.DictReader(f))


def direct(gains, stepping, clearance):
    """The plant's closed loop through the Python API, with these gains over the configuration, stepped as the
    tuner steps it (stepping: its sampling overrides, _sampling.py), at this clearance [m]."""
    scene = gimbalsim.load_scene(SCENES / "paper_clearance.yaml", {"contact.clearance": clearance, **stepping})
    return gimbalsim.closed_loop(scene, gimbalsim.Controller(CONTROLLER_CONFIG, gains), DURATION).summary


def test_trials_hold_each_plant_and_trial_0_is_the_configuration(tmp_path):
    spec = write_spec(tmp_path, 3)
    p = subprocess.run(tune_cmd(spec, tmp_path / "o"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    rows = trials(tmp_path / "o")
    assert [int(r["trial"]) for r in rows] == [0, 1, 2]
    own = gimbalsim.Controller(CONTROLLER_CONFIG).values()
    assert rows[0]["origin"] == "baseline"
    assert [float(rows[0][COLUMN[g]]) for g in GAINS] == [float(own[g]) for g in GAINS]
    from gimbalsim._tune_spec import TuneSpec
    tuned = TuneSpec(spec)
    stepping = tuned.sampling["overrides"]
    clearances = [tuned.plants.draw(j)["contact.clearance"] for j in range(2)]  # each plant's, from the seed
    assert clearances[0] != clearances[1] and all(CLEARANCE * 0.9 <= c <= CLEARANCE for c in clearances)
    r = rows[2]
    assert [float(r[COLUMN[g]]) for g in GAINS] != [float(own[g]) for g in GAINS]
    for j, clearance in enumerate(clearances):
        baseline = direct({}, stepping, clearance)  # the configuration as it is: no gain laid over it
        assert rows[0][f"plant{j}_status"] == "ok"
        assert [float(rows[0][f"plant{j}_{c}"]) for c in FIGURES] == [float(baseline[c]) for c in FIGURES]
        tuned_run = direct({g: float(r[COLUMN[g]]) for g in GAINS}, stepping, clearance)
        assert [float(r[f"plant{j}_{c}"]) for c in FIGURES] == [float(tuned_run[c]) for c in FIGURES]
    # the plants differ in what they measure, not only in their label
    assert rows[0]["plant0_max_truth_error_track_rad"] != rows[0]["plant1_max_truth_error_track_rad"]


def test_a_study_folder_is_not_overwritten_without_resume(tmp_path):
    spec = write_spec(tmp_path, 1)
    out = tmp_path / "o"
    p = subprocess.run(tune_cmd(spec, out), capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    before = {f: (out / f).read_bytes() for f in ("study.db", "trials.csv", "best.yaml")}
    p = subprocess.run(tune_cmd(spec, out), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and str(out) in p.stderr and "--resume" in p.stderr, p.stderr
    assert {f: (out / f).read_bytes() for f in before} == before


def test_a_spec_or_controller_among_the_outputs_is_refused_before_any_trial(tmp_path):
    """A tuner whose spec is its own best.yaml-to-be, or whose controller is:
    refused at once (it used to run every trial, then exit 4)."""
    out = tmp_path / "tf"
    out.mkdir()
    (out / "best.yaml").write_text(SPEC.replace("TRIALS", "3"))
    p = subprocess.run(tune_cmd(out / "best.yaml", out), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "an input of this run" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert sorted(x.name for x in out.iterdir()) == ["best.yaml"], "nothing written"
    (out / "best.yaml").write_bytes(CONTROLLER_CONFIG.read_bytes())
    (tmp_path / "t.yaml").write_text(SPEC.replace("TRIALS", "3").replace(str(CONTROLLER_CONFIG), str(out / "best.yaml")))
    p = subprocess.run(tune_cmd(tmp_path / "t.yaml", out), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "an input of this run" in p.stderr, p.stderr


def test_a_gain_range_without_the_configurations_value_is_refused_at_its_line(tmp_path):
    (tmp_path / "t.yaml").write_text(SPEC.replace("TRIALS", "2").replace("[5000, 80000]", "[30000, 80000]"))
    p = subprocess.run(tune_cmd(tmp_path / "t.yaml", tmp_path / "o"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "key 'gains.azimuth.kp'" in p.stderr and "t.yaml:11:" in p.stderr and "21120" in p.stderr, p.stderr
    assert not (tmp_path / "o").exists()


def running_trial(db, gains=len(GAINS)):
    """The number of a RUNNING trial with its gains drawn, after a finished one, read from the study, or None."""
    try:
        with sqlite3.connect(f"file:{db}?mode=ro", uri=True, timeout=1) as c:
            states = dict(c.execute("SELECT number, state FROM trials").fetchall())
            drawn = dict(c.execute("SELECT t.number, count(*) FROM trials t JOIN trial_params p "
                                   "ON p.trial_id = t.trial_id GROUP BY t.number").fetchall())
    except sqlite3.Error:
        return None
    running = [n for n, s in states.items() if s == "RUNNING" and drawn.get(n) == gains]
    return running[0] if running and "COMPLETE" in states.values() else None


def test_a_resume_after_sigkill_retries_the_killed_trial_and_finishes_the_count(tmp_path):
    spec = write_spec(tmp_path, 4)
    out = tmp_path / "o"
    proc = subprocess.Popen(tune_cmd(spec, out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    t0 = time.time()
    while (killed := running_trial(out / "study.db")) is None:
        assert proc.poll() is None and time.time() - t0 < 300, "no trial running after a finished one"
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)  # the tuner and its workers, mid-trial
    proc.communicate(timeout=60)
    p = subprocess.run(tune_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    rows = trials(out)
    numbers = [int(r["trial"]) for r in rows]
    assert numbers == list(range(5))  # no duplicates, numbering continued: 4 finished + the killed one
    dead = rows[killed]
    assert dead["state"] == "FAIL" and dead["reason"] == "killed"
    retry = [r for r in rows if r["origin"] == f"retry of {killed}"]
    assert len(retry) == 1 and retry[0]["state"] == "COMPLETE"
    assert [retry[0][COLUMN[g]] for g in GAINS] == [dead[COLUMN[g]] for g in GAINS]
    assert sum(r["state"] == "COMPLETE" for r in rows) == 4
    assert rows[0]["origin"] == "baseline"


def test_a_resume_proposes_no_finished_gains_again(tmp_path):
    # (pass 80) the resumed sampler, seeded with the spec's seed alone, replayed the first run's random draws: a
    # new trial ran the gains of a finished one, bit for bit (12 trials: 4 drawn at random before TPE; one gain,
    # as found: the first TPE proposal after the retry drew the killed trial's gains again)
    spec = write_spec(tmp_path, 12)
    spec.write_text(spec.read_text().replace("seed: 3", "seed: 1").replace("  elevation.kd: {uniform: [300, 3000]}\n",
                                                                           ""))
    out = tmp_path / "o"
    proc = subprocess.Popen(tune_cmd(spec, out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    t0 = time.time()
    while (killed := running_trial(out / "study.db", gains=1)) is None or killed < 4:
        assert proc.poll() is None and time.time() - t0 < 300, "no trial 4 running"
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=60)
    spec.write_text(spec.read_text().replace("trials: 12", "trials: 7"))  # the count may differ on a resume
    p = subprocess.run(tune_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    rows = trials(out)
    runs = [r[COLUMN["azimuth.kp"]] for r in rows if r["origin"] != f"retry of {killed}"]
    assert len(rows) > killed + 2 and len(set(runs)) == len(runs), \
        [(r["trial"], r["origin"], r[COLUMN["azimuth.kp"]]) for r in rows][killed:]


def test_a_trial_killed_before_its_gains_were_drawn_gets_no_retry(tmp_path):
    # (pass 80) its retry was queued with no gains: a fresh proposal called "retry of N"
    import optuna
    spec = write_spec(tmp_path, 2)
    out = tmp_path / "o"
    assert subprocess.run(tune_cmd(spec, out), capture_output=True, timeout=600).returncode == 0
    study = optuna.load_study(study_name="gimbalsim.tune", storage=f"sqlite:///{out / 'study.db'}")
    left = study.ask().number  # a tuner killed right after it asked: RUNNING, no gains drawn
    spec.write_text(spec.read_text().replace("trials: 2", "trials: 3"))
    p = subprocess.run(tune_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    rows = trials(out)
    assert rows[left]["state"] == "FAIL" and rows[left]["reason"] == "killed", rows[left]
    assert [r["origin"] for r in rows] == ["baseline", "", "", ""] and rows[-1]["state"] == "COMPLETE", rows


@pytest.mark.parametrize("batch", [2, 4])  # (pass 43) 4 plants on 2 workers: a task of two, both "crashed"
def test_a_plant_that_kills_its_worker_fails_its_trials_not_the_study(tmp_path, batch):
    spec = write_spec(tmp_path, 2)
    spec.write_text(spec.read_text().replace("batch: 2", f"batch: {batch}"))
    p = subprocess.run(tune_cmd(spec, tmp_path / "o")[:-1] + ["2"], capture_output=True, text=True, timeout=600,
                       env={**os.environ, "GIMBALSIM_TEST_KILL_WORKER_AT": "1"})
    assert p.returncode == 3 and "no trial completed" in p.stderr, p.stderr  # every trial meets plant 1
    rows = trials(tmp_path / "o")
    assert [int(r["trial"]) for r in rows] == [0, 1]
    for r in rows:
        assert r["state"] == "FAIL" and r["reason"] == "plant stopped: crashed", r
        assert [r[f"plant{j}_status"] for j in range(batch)] == ["ok", "crashed"] + ["ok"] * (batch - 2), r
        assert r["plants_ok"] == str(batch - 1), r
    # (pass 44) no trial completed: no summary.json was written; it says so, with the reason, and no best
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["best_trial"] is None and summary["best_score"] is None and summary["best_gains"] is None
    assert summary["trials"] == 2 and summary["complete"] == 0
    assert summary["note"] == "no trial completed (2 failed): plant stopped: crashed", summary
    assert not (tmp_path / "o" / "best.yaml").exists()


def test_a_resume_after_a_kill_mid_write_rolls_the_study_back_and_goes_on(tmp_path):
    # (pass 43) a tuner killed while writing study.db left SQLite's hot journal beside it; the resume's read-only
    # check then refused the study ("attempt to write a readonly database") every time
    spec = write_spec(tmp_path, 1)
    out = tmp_path / "o"
    assert subprocess.run(tune_cmd(spec, out), capture_output=True, text=True, timeout=600).returncode == 0
    killed = ("import os, sqlite3\n"
              f"c = sqlite3.connect({str(out / 'study.db')!r}, isolation_level=None)\n"
              "c.execute('PRAGMA cache_size=2'); c.execute('BEGIN IMMEDIATE')\n"
              "c.execute('CREATE TABLE pad(x)'); c.executemany('INSERT INTO pad VALUES (?)', [(b'x' * 1000,)] * 200)\n"
              "os._exit(0)  # killed mid-transaction: pages already in the file, the journal hot\n")
    subprocess.run([sys.executable, "-c", killed], check=True, timeout=60)
    assert (out / "study.db-journal").stat().st_size > 0
    p = subprocess.run(tune_cmd(write_spec(tmp_path, 2), out, "--resume"), capture_output=True, text=True,
                       timeout=600)
    assert p.returncode == 0, p.stderr
    assert [int(r["trial"]) for r in trials(out)] == [0, 1] and not (out / "study.db-journal").exists()
    with sqlite3.connect(out / "study.db") as c:
        assert "pad" not in [r[0] for r in c.execute("SELECT name FROM sqlite_master")]  # the kill's write undone


def test_a_resume_of_another_spec_or_of_no_study_is_refused(tmp_path):
    spec = write_spec(tmp_path, 1)
    out = tmp_path / "o"
    assert subprocess.run(tune_cmd(spec, out), capture_output=True, timeout=600).returncode == 0
    before = (out / "study.db").read_bytes()
    (tmp_path / "t2.yaml").write_text(spec.read_text().replace("seed: 3", "seed: 4"))
    p = subprocess.run(tune_cmd(tmp_path / "t2.yaml", out, "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "study.db holds a study of another spec" in p.stderr, p.stderr
    assert (out / "study.db").read_bytes() == before
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / "study.db").write_bytes(b"not a database, " * 100)
    p = subprocess.run(tune_cmd(spec, tmp_path / "bad", "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "study.db: cannot open it as a study" in p.stderr, p.stderr
    assert "Traceback" not in p.stderr
    # An empty file would open as a new study and overwrite trials.csv; a dropped table was a traceback.
    (tmp_path / "empty").mkdir()
    (tmp_path / "empty" / "study.db").write_bytes(b"")
    (tmp_path / "empty" / "trials.csv").write_text("kept\n")
    p = subprocess.run(tune_cmd(spec, tmp_path / "empty", "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "study.db: empty" in p.stderr, p.stderr
    assert (tmp_path / "empty" / "trials.csv").read_text() == "kept\n"
    # A missing study beside trials.csv, another program's database, a link to another study: refused, unwritten.
    (tmp_path / "empty" / "study.db").unlink()
    p = subprocess.run(tune_cmd(spec, tmp_path / "empty", "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "study.db: missing" in p.stderr, p.stderr
    with sqlite3.connect(tmp_path / "empty" / "study.db") as db:
        db.execute("CREATE TABLE foo(x)")
    before = (tmp_path / "empty" / "study.db").read_bytes()
    p = subprocess.run(tune_cmd(spec, tmp_path / "empty", "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "cannot open it as a study" in p.stderr, p.stderr
    assert (tmp_path / "empty" / "study.db").read_bytes() == before
    (tmp_path / "linked").mkdir()
    (tmp_path / "linked" / "study.db").symlink_to(out / "study.db")
    study_before = (out / "study.db").read_bytes()
    p = subprocess.run(tune_cmd(spec, tmp_path / "linked", "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "a symbolic link" in p.stderr, p.stderr  # refused before the study is opened
    assert (out / "study.db").read_bytes() == study_before
    with sqlite3.connect(out / "study.db") as db:
        db.execute("DROP TABLE trial_values")
    p = subprocess.run(tune_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "Traceback" not in p.stderr, p.stderr
    assert "study.db: cannot read it as a study" in p.stderr or "damaged" in p.stderr, p.stderr


def test_a_study_refused_space_exits_4_and_resumes(tmp_path):
    spec = write_spec(tmp_path, 1)
    out = tmp_path / "o"
    assert subprocess.run(tune_cmd(spec, out), capture_output=True, timeout=600).returncode == 0
    more = write_spec(tmp_path, 40)
    limit = (out / "study.db").stat().st_size + 8192  # room for a trial or two, not for 40
    p = subprocess.run(tune_cmd(more, out, "--resume"), capture_output=True, text=True, timeout=600,
                       preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit)))
    assert p.returncode == 4 and "cannot write the study" in p.stderr and "Traceback" not in p.stderr, p.stderr
    kept = [int(r["trial"]) for r in trials(out)]
    p = subprocess.run(tune_cmd(write_spec(tmp_path, 3), out, "--resume"), capture_output=True, text=True,
                       timeout=600)
    assert p.returncode == 0, p.stderr
    rows = trials(out)
    assert [int(r["trial"]) for r in rows][:len(kept)] == kept and len(rows) >= 3
    assert sum(r["state"] == "COMPLETE" for r in rows) >= 3


def test_a_second_tuner_on_a_running_study_is_refused(tmp_path):
    spec = write_spec(tmp_path, 4)
    out = tmp_path / "o"
    first = subprocess.Popen(tune_cmd(spec, out), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        while not (out / "study.db").exists() and time.monotonic() < deadline and first.poll() is None:
            time.sleep(0.05)
        assert first.poll() is None, "the first tuner ended before the second could try"
        p = subprocess.run(tune_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=120)
        assert p.returncode == 2, p.stderr
        assert "another sweep, tuner or allocation is running in this folder" in p.stderr and "Traceback" not in p.stderr
    finally:
        _, err = first.communicate(timeout=600)
    assert first.returncode == 0, err
    assert len(trials(out)) == 4  # the first tuner's study whole


def test_a_study_file_of_another_optuna_version_is_refused(tmp_path):
    spec = write_spec(tmp_path, 1)
    out = tmp_path / "o"
    assert subprocess.run(tune_cmd(spec, out), capture_output=True, timeout=600).returncode == 0
    with sqlite3.connect(out / "study.db") as db:  # a schema this Optuna does not know (a later one's)
        db.execute("UPDATE alembic_version SET version_num = 'v9.9.9.z'")
    p = subprocess.run(tune_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 2, p.stderr
    assert "study.db: cannot open it as a study" in p.stderr and "Traceback" not in p.stderr


def test_gains_the_run_cannot_take_fail_their_trial_and_the_study_goes_on(tmp_path):
    # A control period drawn between 1 and 2 ms rarely divides the 3.7 s run: such a trial is FAIL with the
    # reason, the others (the configuration's 1 ms first) run, and the tuner ends normally.
    text = SPEC.replace("TRIALS", "4").replace("  elevation.kd: {uniform: [300, 3000]}\n",
                                               "  control.period: {uniform: [0.001, 0.002]}\n")
    (tmp_path / "t.yaml").write_text(text)
    p = subprocess.run(tune_cmd(tmp_path / "t.yaml", tmp_path / "o"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    assert "Traceback" not in p.stderr
    rows = trials(tmp_path / "o")
    assert len(rows) == 4 and rows[0]["state"] == "COMPLETE"
    failed = [r for r in rows if r["state"] == "FAIL"]
    assert failed and all("control period" in r["reason"] or "control.period" in r["reason"] for r in failed), rows


def test_a_trial_that_cannot_run_names_the_key_and_has_no_constraint(tmp_path):
    # A period that does not divide the run (0.7 ms in 0.3 s) or sim.step (1.5 ms): no plant ran a tick, so
    # the trial is FAIL "not run" (not "plant stopped"), each plant refused:control.period, and no constraint
    # value (no saturation was measured), as a trial killed with the tuner has none.
    spec = tmp_path / "t.yaml"
    spec.write_text(f"""
scene: {SCENES}/paper_clearance.yaml
controller: {CONTROLLER_CONFIG}
duration: 0.3
trials: 6
parallel_trials: 1
seed: 1
batch: 2
max_saturation: 0.9
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.1, profile.hold_time: 0.1}}
objective: {{metric: max_track, percentile: 90}}
gains:
  control.period: {{choice: [0.001, 0.0015, 0.0007]}}
plants:
  contact.clearance: {{uniform: [{CLEARANCE * 0.9}, {CLEARANCE}]}}
""")
    p = subprocess.run(tune_cmd(spec, tmp_path / "o"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 0 and "Traceback" not in p.stderr, p.stderr
    rows = trials(tmp_path / "o")
    assert rows[0]["state"] == "COMPLETE" and rows[0]["constraint"] != "", rows[0]  # a ran trial has its value
    failed = {r["control_period_s"]: r for r in rows if r["state"] == "FAIL"}
    assert set(failed) == {"0.0015", "0.0007"}, rows
    for r in failed.values():
        assert r["constraint"] == "" and r["score"] == "" and r["plants_ok"] == "0", r
        assert [r["plant0_status"], r["plant1_status"]] == ["refused:control.period"] * 2, r
        assert r["reason"].startswith("not run: refused:control.period (") and "plant stopped" not in r["reason"], r
    assert "duration 0.3 s must be a whole multiple of control.period (" in failed["0.0007"]["reason"]
    assert "not a whole multiple of sim.step" in failed["0.0015"]["reason"]


def test_a_trial_some_of_whose_plants_were_refused_says_how_many_and_why(tmp_path):
    # An eccentricity drawn beyond its plant's clearance: that plant is refused, the others run. The reason
    # said "not run: refused:initial.ecc" (no plant could start) with plants_ok 3 of 6, and no why.
    spec = tmp_path / "t.yaml"
    spec.write_text(f"""
scene: {SCENES}/paper_clearance.yaml
controller: {CONTROLLER_CONFIG}
duration: 0.3
trials: 1
parallel_trials: 1
seed: 1
batch: 6
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.1, profile.hold_time: 0.1}}
gains:
  azimuth.kp: {{loguniform: [5000, 80000]}}
plants:
  initial.ecc: {{disk: {{radius: 4.9e-4}}}}
  contact.clearance: {{uniform: [1.0e-4, 6.0e-4]}}
""")
    p = subprocess.run(tune_cmd(spec, tmp_path / "o"), capture_output=True, text=True, timeout=600)
    assert p.returncode == 3 and "no trial completed" in p.stderr and "Traceback" not in p.stderr, p.stderr
    r = trials(tmp_path / "o")[0]
    refused = [j for j in range(6) if r[f"plant{j}_status"] == "refused:initial.ecc"]
    assert 0 < len(refused) < 6 and int(r["plants_ok"]) + len(refused) == 6, r
    assert r["state"] == "FAIL", r
    assert r["reason"].startswith(f"{len(refused)} of 6 plants refused: refused:initial.ecc ("), r
    assert "initial eccentricity exceeds the radial clearance" in r["reason"] and "not run" not in r["reason"], r


def test_a_resume_into_a_missing_folder_makes_none(tmp_path):
    # (pass 48) refused (exit 2), but the folder was made first and left behind, empty
    p = subprocess.run(tune_cmd(write_spec(tmp_path, 1), tmp_path / "new", "--resume"), capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 2 and "new: no such folder: no study to resume" in p.stderr, p.stderr
    assert not (tmp_path / "new").exists()


def test_a_resume_whose_study_lost_its_trials_keeps_trials_csv(tmp_path):
    # (pass 51) study.db's trial rows gone: the resume rewrote trials.csv to its header (the only record of the
    # finished trials lost), then ended 4 with "free the space"
    spec = write_spec(tmp_path, 2)
    assert subprocess.run(tune_cmd(spec, tmp_path / "o"), capture_output=True, timeout=300).returncode == 0
    before = (tmp_path / "o" / "trials.csv").read_bytes()
    with contextlib.closing(sqlite3.connect(tmp_path / "o" / "study.db")) as db:
        db.execute("DELETE FROM trials")
        db.commit()
    p = subprocess.run(tune_cmd(spec, tmp_path / "o", "--resume"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 2 and "trials.csv records 2 trial(s) the study in" in p.stderr, p.stderr
    assert (tmp_path / "o" / "trials.csv").read_bytes() == before


def _file_size_limit(size_bytes):
    """A child's file-size limit, its signal ignored: a write past it fails with EFBIG (a full disk's stand-in)."""
    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (size_bytes, size_bytes))
    return limit


def test_a_new_study_that_could_not_be_written_leaves_nothing_to_refuse(tmp_path):
    # (pass 55) study.db failed before the study was recorded: the tuner said to run again with --resume, which
    # was refused ("holds no study"), as was a plain run ("already holds a study"), over a partial study.db
    spec = write_spec(tmp_path, 1)
    p = subprocess.run(tune_cmd(spec, tmp_path / "o"), capture_output=True, text=True, timeout=300,
                       preexec_fn=_file_size_limit(16 * 1024))
    assert p.returncode == 4 and "cannot write the study" in p.stderr, p.stderr
    assert "free the space and run again (nothing was kept)" in p.stderr and "--resume" not in p.stderr, p.stderr
    assert not (tmp_path / "o").exists()  # the folder it made goes too (pass 66: left empty)
    again = subprocess.run(tune_cmd(spec, tmp_path / "o"), capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr
