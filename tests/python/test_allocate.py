"""Tolerance allocation (python3 -m gimbalsim.allocate): the bracket against
a brute-force sweep over the same key and units, each careless input
refused at its line (exit 2), a requirement no value meets (exit 3, the
best value), one every value meets, a non-monotone index located, and a
resume that does not rerun finished values.

The scene is cheap: the antenna holds still (no slew, no track) for 0.3 s,
so the pointing error is the star tracker's noise fed through the loop
(about 0.8 x its 1-sigma in the last 0.1 s); each unit has its own noise
stream (sensors.seed)."""
import csv
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from scipy import stats

from conftest import SCENES
from gimbalsim import _cluster, allocate

BASE = f"""scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.3}}
controller: default
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.1, profile.hold_time: 0.1, profile.start: [0.0, 0.0],
                 profile.slew_target: [0.0, 0.0], profile.track_rate: [0.0, 0.0], profile.track_amplitude: [0.0, 0.0]}}
samples: 8
seed: 5
parameters:
  sensors.seed: {{choice: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]}}
phases: [{{late: [0.2, 0.3]}}]
indices:
  ape: {{}}
"""
ALLOCATE = """allocate:
  key: sensors.star_tracker_noise
  range: [1.0e-5, 3.0e-4]
  direction: largest
  index: ape
  phase: late
  requirement: {requirement}
  level: 0.8
  confidence: 0.5
  values: {values}
"""
LEVEL, CONFIDENCE, REQUIREMENT = 0.8, 0.5, 1.0e-4


def write_spec(folder, text, name="spec.yaml"):
    path = folder / name
    path.write_text(text)
    return path


def run(spec, out, *args, **kw):
    return subprocess.run([sys.executable, "-m", "gimbalsim.allocate", str(spec), "--out", str(out), "--workers", "1",
                           "--no-progress", *args], capture_output=True, text=True, timeout=300, **kw)


def figures(results_csv, column="ape_late_rad"):
    """A sweep's per-unit figures by (grid value, sample), nan for a unit that did not end ok."""
    with open(results_csv) as f:
        rows = list(csv.DictReader(f))
    return [(r, float(r[column]) if r["status"] == "ok" else math.nan) for r in rows]


def passes(x, requirement=REQUIREMENT):
    """Clopper-Pearson here, from the figures: at least LEVEL of the units meet it at CONFIDENCE."""
    x = np.asarray(x)
    k, n = int(np.sum(np.isfinite(x) & (x <= requirement))), len(x)
    return k > 0 and stats.beta.ppf(1 - CONFIDENCE, k, n - k + 1) >= LEVEL


@pytest.fixture(scope="module")
def bracketed(tmp_path_factory):
    d = tmp_path_factory.mktemp("alloc")
    spec = write_spec(d, BASE + ALLOCATE.format(requirement=REQUIREMENT, values=6))
    p = run(spec, d / "out")
    assert p.returncode == 0, p.stderr
    return d, json.loads((d / "out" / "allocation.json").read_text()), p.stderr


def test_the_bracket_is_the_brute_force_sweeps(bracketed, tmp_path):
    d, answer, _ = bracketed
    assert answer["outcome"] == "bracket" and answer["monotone"]
    meet, fail = answer["bracket"]
    dense = list(np.linspace(1.0e-5, 3.0e-4, 13))
    grid = sorted(set(dense + [meet, fail]))
    # The same spec as a plain sweep over the key: same seed, so the same units at every value.
    sweep = BASE + f"grid: {{sensors.star_tracker_noise: [{', '.join(repr(float(v)) for v in grid)}]}}\n"
    out = tmp_path / "brute"
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(write_spec(tmp_path, sweep)), "--out", str(out),
                        "--workers", "1", "--no-progress"], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    by_value = {}
    for row, x in figures(out / "results.csv"):
        by_value.setdefault(float(row["sensors_star_tracker_noise_rad"]), []).append(x)
    verdict = {v: passes(x) for v, x in by_value.items()}
    assert verdict[meet] and not verdict[fail]
    # the brute force's own limit lies inside the allocation's bracket
    assert all(verdict[v] for v in dense if v <= meet) and not any(verdict[v] for v in dense if v >= fail)
    # 3 scanned values, then 3 halvings of the bracket between the scan's neighbours
    assert fail - meet == pytest.approx((3.0e-4 - 1.0e-5) / 2 / 8, rel=1e-9)
    # each value tried: the same units as the brute force's (the counts meeting agree)
    with open(d / "out" / "allocation.csv") as f:
        table = list(csv.DictReader(f))
    assert len(table) == 6 and answer["runs_used"] == 48
    for r in table:
        v = float(r["sensors_star_tracker_noise_rad"])
        if v in by_value:
            x = np.asarray(by_value[v])
            assert int(r["n_meeting"]) == int(np.sum(x <= REQUIREMENT))
            assert float(r["estimate_rad"]) == np.sort(x)[math.ceil(len(x) * LEVEL) - 1]
            assert (r["verdict"] == "PASS") == passes(x)


def test_outputs_are_written_and_name_the_bracket(bracketed):
    d, answer, stderr = bracketed
    out = d / "out"
    assert (out / "allocation.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert f"{answer['bracket'][0]!r} rad meets" in stderr
    for v in answer["values"]:  # every bound a number (never NaN) in a fully supported table
        assert v["estimate_rad"] is not None and v["upper_bound_rad"] >= v["estimate_rad"]
        assert (out / v["folder"] / "results.csv").exists()


def test_a_value_sweep_replays_without_calling_its_spec_edited(bracketed, tmp_path):
    # (pass 56) a value's sweep runs a text made from the allocation spec: compared with the file, the replay
    # said "one of them was edited" over an unedited spec
    d, answer, _ = bracketed
    folder = d / "out" / answer["values"][0]["folder"]
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(folder), "--replay", "0", "--out",
                        str(tmp_path / "run.csv")], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "edited" not in p.stderr, p.stderr
    spec = d / "spec.yaml"
    text = spec.read_text()
    try:  # the allocation spec edited since: said as it is
        spec.write_text(text + "# a comment added\n")
        p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(folder), "--replay", "0", "--out",
                            str(tmp_path / "run2.csv")], capture_output=True, text=True, timeout=300)
    finally:
        spec.write_text(text)
    assert p.returncode == 0, p.stderr
    assert f"replay: {spec} was edited since the sweep; replaying from the sweep's copy" in p.stderr, p.stderr


# ---- careless input: refused at its line, exit 2 ----

def line_of(text, start):
    return next(k for k, line in enumerate(text.split("\n"), 1) if line.lstrip().startswith(start))


CASES = [  # (replace in ALLOCATE, with, the key refused, the line that starts with)
    ("  values: {values}", "  values: 6\n  bogus: 1", "allocate.bogus", "bogus:"),
    ("key: sensors.star_tracker_noise", "key: sensors.no_such_key", "allocate.key", "key:"),
    ("range: [1.0e-5, 3.0e-4]", "range: [1.0e-4, 1.0e-4]", "allocate.range", "range:"),
    ("range: [1.0e-5, 3.0e-4]", "range: [3.0e-4, 1.0e-5]", "allocate.range", "range:"),
    ("range: [1.0e-5, 3.0e-4]", "range: [1.0e-5, .inf]", "allocate.range", "range:"),
    ("range: [1.0e-5, 3.0e-4]", "range: [1.0e-5, 2.0]", "allocate.range", "range:"),  # the key's own: [0, 1]
    ("level: 0.8", "level: 1.5", "allocate.level", "level:"),
    ("confidence: 0.5", "confidence: 0.0", "allocate.confidence", "confidence:"),
    ("level: 0.8", "level: 0.9973", "samples", "samples:"),  # 8 units cannot show 99.73 % at 50 %
    ("direction: largest", "direction: biggest", "allocate.direction", "direction:"),
    ("  values: {values}", "  values: 2", "allocate.values", "values:"),
    ("phase: late", "phase: track", "allocate.phase", "phase:"),
    # above pi rad every unit meets it: a verdict from no question (pass 70 drew a blank CDF for 1e308)
    ("requirement: {requirement}", "requirement: 1.0e+308", "allocate.requirement", "requirement:"),
]


@pytest.mark.parametrize("old,new,key,starts", CASES, ids=[c[2] + ":" + c[1].split(":")[-1].strip() for c in CASES])
def test_careless_allocate_keys_are_refused_at_their_line(tmp_path, capsys, monkeypatch, old, new, key, starts):
    monkeypatch.setattr(_cluster, "raise_on_signals", lambda: None)  # no signal handlers in pytest's process
    assert old in ALLOCATE
    text = BASE + ALLOCATE.replace(old, new).format(requirement=REQUIREMENT, values=4)
    spec = write_spec(tmp_path, text)
    assert allocate.main([str(spec), "--out", str(tmp_path / "out"), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert f"spec.yaml:{line_of(text, starts)}:" in err and f"key '{key}'" in err, err
    assert not (tmp_path / "out").exists()  # nothing run, nothing written


def test_a_key_also_dispersed_is_refused_not_taken_out(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(_cluster, "raise_on_signals", lambda: None)
    text = BASE.replace("parameters:\n", "parameters:\n  sensors.star_tracker_noise: {uniform: [0.0, 1.0e-5]}\n") + \
        ALLOCATE.format(requirement=REQUIREMENT, values=4)
    spec = write_spec(tmp_path, text)
    assert allocate.main([str(spec), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"spec.yaml:{line_of(text, 'key:')}:" in err and "key 'allocate.key'" in err
    assert f"under parameters: (line {line_of(text, 'sensors.star_tracker_noise:')})" in err, err


# ---- what the data say ----

def test_no_value_meets_says_so_with_the_best_value(tmp_path):
    spec = write_spec(tmp_path, BASE + ALLOCATE.format(requirement=1.0e-6, values=3))
    p = run(spec, tmp_path / "out")
    assert p.returncode == 3, p.stderr  # docs/usage.md: no value of the range meets the requirement
    answer = json.loads((tmp_path / "out" / "allocation.json").read_text())
    assert answer["outcome"] == "no_value_meets" and answer["bracket"] is None and "no value of" in p.stderr
    # the best: the lowest noise (its figures are the smallest), with its interval
    best = min(answer["values"], key=lambda v: v["upper_bound_rad"])
    assert answer["best"] == best["value"] == 1.0e-5
    x = np.sort([x for _, x in figures(tmp_path / "out" / best["folder"] / "results.csv")])
    assert best["estimate_rad"] == x[math.ceil(len(x) * LEVEL) - 1] and all(best["interval_rad"])


def test_the_page_says_why_a_bound_is_missing_never_a_bare_nan(tmp_path):
    # 12 units give no two-sided interval at 90 % with 60 %: the CSV holds nan, its page held "| nan |" alone.
    text = (BASE + ALLOCATE.format(requirement=REQUIREMENT, values=3)).replace("level: 0.8", "level: 0.9") \
        .replace("confidence: 0.5", "confidence: 0.6").replace("samples: 8", "samples: 12")
    p = run(write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode in (0, 3), p.stderr
    assert ",nan," in (tmp_path / "out" / "allocation.csv").read_text()  # the CSV convention
    page = (tmp_path / "out" / "allocation.md").read_text()
    table = [line for line in page.splitlines() if line.startswith("| ")]
    assert len(table) == 4 and not any("| nan |" in line for line in table), page
    assert "| n/a |" in table[1] and "\nn/a: 12 units give only a one-sided bound at 60% confidence.\n" in page, page


def test_every_value_meets_says_the_limit_is_beyond_the_range(tmp_path):
    spec = write_spec(tmp_path, BASE + ALLOCATE.format(requirement=1.0e-2, values=3))
    p = run(spec, tmp_path / "out")
    assert p.returncode == 0, p.stderr
    answer = json.loads((tmp_path / "out" / "allocation.json").read_text())
    assert answer["outcome"] == "every_value_meets" and answer["answer"] == 3.0e-4 and "beyond the range" in p.stderr
    assert answer["runs_used"] == 3 * 8  # no bisection without a failing value


def test_a_verdict_over_figures_all_exactly_0_says_the_index_does_not_see_the_key(tmp_path):
    # (pass 70) no noise and no motion: every unit's APE is 0 at every value tried, and the allocation said PASS
    # for each, "the limit lies beyond the range", as if the key had been judged
    text = (BASE.replace("set: {sim.duration: 0.3}", "set: {sim.duration: 0.3, sensors.star_tracker_noise: 0.0}")
            .replace("sensors.seed: {choice: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]}",
                     "friction.mu: {uniform: [0.1, 0.3]}") +
            ALLOCATE.format(requirement=REQUIREMENT, values=3).replace("sensors.star_tracker_noise",
                                                                      "contact.restitution")
            .replace("[1.0e-5, 3.0e-4]", "[0.3, 0.9]"))
    p = run(write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 0, p.stderr
    said = ("every figure of ape late is exactly 0 rad at contact.restitution = 0.3, 0.6, 0.9 -: the index does not "
            "see the key there")
    assert said in p.stderr, p.stderr
    answer = json.loads((tmp_path / "out" / "allocation.json").read_text())
    assert all("every unit's figure is exactly 0 rad" in v["note"] for v in answer["values"]), answer["values"]
    assert said in (tmp_path / "out" / "allocation.md").read_text()


def slew_start_spec(tmp_path, duration):
    """slew_start allocated over [0, 0.3] s: a 0.01 rad slew of 0.05 s, the run `duration` s long."""
    text = (BASE.replace("sim.duration: 0.3", f"sim.duration: {duration}")
            .replace("profile.slew_target: [0.0, 0.0]", "profile.slew_target: [0.01, 0.0]")
            .replace("profile.slew_start: 0.0, profile.slew_time: 0.1", "profile.slew_time: 0.05")
            .replace("parameters:\n", "parameters:\n  sensors.star_tracker_noise: {uniform: [0.0, 1.0e-5]}\n")
            .replace("samples: 8", "samples: 4"))
    text += ALLOCATE.format(requirement=2.0e-3, values=4).replace("sensors.star_tracker_noise",
                                                                  "controller.profile.slew_start") \
        .replace("[1.0e-5, 3.0e-4]", "[0.0, 0.3]").replace("level: 0.8", "level: 0.5")
    return text, write_spec(tmp_path, text)


def test_a_range_reaching_past_the_run_is_refused_at_its_line(tmp_path):
    # slew_start 0.3 in a 0.3 s run: the slew begins at the run's end, so that value runs what every later one
    # would: the range reaches past where the key acts (it was refused at the key's line, as a key never read).
    text, spec = slew_start_spec(tmp_path, 0.3)
    p = run(spec, tmp_path / "out")
    assert p.returncode == 2 and f"spec.yaml:{line_of(text, 'range:')}:" in p.stderr, p.stderr
    assert "key 'allocate.range'" in p.stderr and "controller.profile.slew_start = 0.3: not read" in p.stderr
    assert not (tmp_path / "out").exists()


def test_another_key_idle_at_one_value_of_the_range_is_refused_at_the_range(tmp_path):
    # (pass 78) friction.v_a (ambrosio) is read wherever friction.mu > 0: a range from mu = 0 was refused at v_a's
    # line as if v_a acted at no value tried; it acts at the scan's others, so the range's value 0 is what refuses
    text = (f"scene: {SCENES}/paper_clearance.yaml\nset: {{sim.duration: 5.0, friction.law: ambrosio}}\n"
            "controller: default\nsamples: 59\nseed: 39\nparameters:\n  friction.v_a: {uniform: [0.0001, 0.0009]}\n"
            "phases: [track]\nindices: {ape: {}}\n"
            "allocate: {key: friction.mu, range: [0.0, 0.3], direction: largest, index: ape, phase: track, "
            "requirement: 1.0e-4, level: 0.95, confidence: 0.95, values: 3}\n")
    spec = write_spec(tmp_path, text)
    p = run(spec, tmp_path / "out", "--check")
    assert p.returncode == 2 and f"spec.yaml:{line_of(text, 'allocate:')}:" in p.stderr, p.stderr
    assert "key 'allocate.range': friction.mu = 0.0: key 'parameters.friction.v_a'" in p.stderr, p.stderr
    assert "for every value of" not in p.stderr, "mu is one value there, not the study's several: " + p.stderr
    p = run(write_spec(tmp_path, text.replace("[0.0, 0.3]", "[0.1, 0.3]"), "ok.yaml"), tmp_path / "out", "--check")
    assert p.returncode == 0, p.stderr


def test_a_problem_of_every_value_is_told_not_one_values_own(tmp_path):
    # (pass 79) with friction.v_a drawn at or above the scene's v_b (1 mm/s), every value of the scan is refused by
    # the scene; the refusal told mu = 0's own (v_a idle there, "for every value of friction.mu the study gives")
    text = (f"scene: {SCENES}/paper_clearance.yaml\nset: {{sim.duration: 5.0, friction.law: ambrosio}}\n"
            "controller: default\nsamples: 59\nseed: 39\nparameters:\n  friction.v_a: {uniform: [1.0e-3, 2.0e-3]}\n"
            "phases: [track]\nindices: {ape: {}}\n"
            "allocate: {key: friction.mu, range: [0.0, 0.3], direction: largest, index: ape, phase: track, "
            "requirement: 1.0e-4, level: 0.95, confidence: 0.95, values: 3}\n")
    p = run(write_spec(tmp_path, text), tmp_path / "out", "--check")
    assert p.returncode == 2 and f"spec.yaml:{line_of(text, 'friction.v_a')}:" in p.stderr, p.stderr
    assert "must be > friction.v_a" in p.stderr and "for every value of" not in p.stderr, p.stderr


def test_a_non_monotone_index_says_where(tmp_path):
    # Inside the window [0.2, 0.3) s of a 0.35 s run the error is large while the slew settles, small before
    # the slew and after it settled: the index rises then falls with slew_start.
    text, spec = slew_start_spec(tmp_path, 0.35)
    p = run(spec, tmp_path / "out")
    answer = json.loads((tmp_path / "out" / "allocation.json").read_text())
    assert p.returncode == 0 and not answer["monotone"] and "not monotone" in p.stderr, p.stderr
    # where: recomputed here from each value's own figures (the empirical median, level 0.5)
    med = {v["value"]: np.sort([x for _, x in figures(tmp_path / "out" / v["folder"] / "results.csv")])[1]
           for v in answer["values"]}
    xs = sorted(med)
    want = {(a, b) for a, b in zip(xs, xs[1:]) if med[a] > med[b] * (1 + 1e-9)}
    got = {(b["from"], b["to"]) for b in answer["breaks"] if b["statistic"] == "estimate"}
    assert got == want and (xs[-2], xs[-1]) in got
    assert any(b["statistic"] == "verdict" and b["to"] == 0.3 for b in answer["breaks"])


def test_resume_does_not_rerun_finished_values(tmp_path, bracketed):
    spec = write_spec(tmp_path, BASE + ALLOCATE.format(requirement=REQUIREMENT, values=6))
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "gimbalsim.allocate", str(spec), "--out", str(out), "--workers",
                             "1", "--no-progress"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not (out / "values" / "2").exists() and time.monotonic() < deadline:  # values 0 and 1 done
        time.sleep(0.02)
    proc.send_signal(signal.SIGINT)
    err = proc.communicate(timeout=120)[1]
    assert proc.returncode == 130, err
    finished = sorted(int(f.name) for f in (out / "values").iterdir()
                      if (f / "results.csv").exists() and not (f / "results.partial.csv").exists())
    assert 2 <= len(finished) < 6
    # the rows as they ran, each with its own wall time: a value run again would have others
    rows = {k: (out / "values" / str(k) / "results.csv").read_text() for k in finished}
    assert run(spec, out).returncode == 2  # without --resume: refused, not overwritten
    p = run(spec, out, "--resume")
    assert p.returncode == 0, p.stderr
    assert {k: (out / "values" / str(k) / "results.csv").read_text() for k in finished} == rows
    assert p.stderr.count("(read back)") == len(finished)
    answer = json.loads((out / "allocation.json").read_text())
    assert answer["bracket"] == bracketed[1]["bracket"] and answer["runs_used"] == 48
    assert answer["ran_this_invocation"] <= 48 - 8 * len(finished)
    # the page's wall time is this invocation's: it says how many runs it made
    assert f"48 runs (8 units each, common random numbers); {answer['ran_this_invocation']} of them run by this " \
        "invocation, the others read back" in (out / "allocation.md").read_text()


def test_units_without_a_figure_are_worst_and_never_a_nan_bound(tmp_path):
    # A 2e-6 m clearance is below what the slew's load presses into the contact: every unit stops
    # (sim.penetration_limit) and has no figure; 4e-4 m and 8e-4 m run.
    text = f"""scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.5}}
controller: default
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.2, profile.hold_time: 0.1}}
samples: 4
seed: 11
parameters:
  friction.mu: {{uniform: [0.15, 0.35]}}
phases: [track]
indices:
  ape: {{level: 0.5, confidence: 0.5, requirement: 1.0}}
allocate: {{key: contact.clearance, range: [2.0e-6, 8.0e-4], direction: largest, index: ape, phase: track,
           values: 3}}
"""
    p = run(write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 3, p.stderr  # no bracket: the favourable end fails
    out = tmp_path / "out"
    answer = json.loads((out / "allocation.json").read_text())
    assert answer["outcome"] == "favourable_end_fails" and answer["bracket"] is None and not answer["monotone"]
    first = answer["values"][0]
    assert first["value"] == 2.0e-6 and first["verdict"] == "FAIL"
    assert all(not math.isfinite(x) for _, x in figures(out / first["folder"] / "results.csv"))  # no unit has one
    assert first["n_missing"] == 4 and first["upper_bound_rad"] is None and first["estimate_rad"] is None
    # (pass 81) each null said why beside it (the note was empty), in the JSON and in the table
    assert first["note"].startswith("estimate, interval end, upper bound beyond every figure: 4 of 4 units have "
                                    "no figure"), first
    with open(out / "allocation.csv") as f:
        table = list(csv.DictReader(f))
    assert [r[k] for r in table[:1] for k in ("estimate_rad", "interval_low_rad", "interval_high_rad",
                                                "upper_bound_rad")] == ["inf"] * 4
    assert table[0]["note"] == first["note"].replace(",", ";"), table[0]
    assert "nan" not in (out / "allocation.csv").read_text() and "nan" not in p.stderr
    assert answer["best"] == min((v for v in answer["values"][1:]), key=lambda v: v["upper_bound_rad"])["value"]


def test_the_shipped_example_asks_the_issues_question():
    from conftest import SOURCE
    from gimbalsim import indices
    from gimbalsim._allocate_spec import AllocationSpec
    a = AllocationSpec(SOURCE / "tools" / "sweeps" / "allocation_clearance.yaml")  # refused: SpecError
    assert (a.key, a.direction, a.index, a.phase, a.requirement) == ("contact.clearance", "largest", "ape", "track",
                                                                      1.0e-4)
    assert (a.level, a.confidence) == (0.9973, 0.95)
    sweep = a.sweep_at(a.lo)
    assert sweep.scene_path.name == "paper_spatial2_tracker.yaml" and sweep.base.values()["structure.joint2"] == "spatial"
    assert sweep.samples >= indices.min_units(a.level, a.confidence)


def test_an_out_that_cannot_be_made_keeps_nothing_and_says_so(tmp_path):
    # (pass 59) it named out/values, said "finished values kept" and to --resume, which was then refused
    spec = write_spec(tmp_path, BASE + ALLOCATE.format(requirement=REQUIREMENT, values=3))
    p = run(spec, "/proc/gimbalsim_al")
    assert p.returncode == 4, p.stderr
    assert p.stderr == ("allocate: error: cannot make the folder /proc/gimbalsim_al: No such file or directory; "
                        "nothing kept (/proc/gimbalsim_al/allocation_spec.json was not written); fix the cause and "
                        "run again\n"), p.stderr


def test_a_fingerprint_not_written_leaves_no_folder_to_refuse_the_next_run(tmp_path, capsys, monkeypatch):
    import errno
    from gimbalsim._output import output_failed

    def full(path, text, inputs=()):  # as the writer fails on a full disk
        raise output_failed(f"{path}: write failed: No space left on device", OSError(errno.ENOSPC, "full"))
    monkeypatch.setattr(allocate, "write_text", full)
    spec = write_spec(tmp_path, BASE + ALLOCATE.format(requirement=REQUIREMENT, values=3))
    assert allocate.main([str(spec), "--out", str(tmp_path / "o"), "--workers", "1", "--no-progress"]) == 4
    err = capsys.readouterr().err
    assert "nothing kept" in err and "free the space and run again\n" in err and "--resume" not in err, err
    assert not (tmp_path / "o").exists()  # the folders it made went: a plain run is not refused over them


def test_a_resume_removes_what_a_killed_writer_left_in_the_allocations_own_folder(tmp_path, bracketed):
    # (pass 76) only the value sweeps' folders were cleaned: a SIGKILLed allocation's own temporaries stayed
    out = tmp_path / "out"
    shutil.copytree(bracketed[0] / "out", out)
    spec = write_spec(tmp_path, BASE + ALLOCATE.format(requirement=REQUIREMENT, values=6))
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    left = [out / f".allocation.csv.{p.pid}.1.tmp", out / "values" / f".x.{p.pid}.2.tmp"]
    for f in left:
        f.write_text("half a file")
    live = out / f".allocation.json.{os.getpid()}.1.tmp"
    live.write_text("a live writer's")
    q = run(spec, out, "--resume")
    assert q.returncode == 0, q.stderr
    assert not any(f.exists() for f in left) and live.exists(), sorted(os.listdir(out))
    assert f"removed 2 temporary file(s) a killed writer left: .allocation.csv.{p.pid}.1.tmp, " \
        f"values/.x.{p.pid}.2.tmp" in q.stderr, q.stderr
