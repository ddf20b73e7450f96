"""Closed-loop sweeps: per-sample pointing indices (ECSS-E-ST-60-10C) equal
indices.py applied here to the run's own ticks, phases from the profile,
NaN with a reason past the run's end (and a spec whose run ends before a
phase refused at its line), the budget table with its intervals
and "not supported" marks, requirement verdicts, --until, refusals at the
spec's line, and the same results with 1 and 2 workers and a real scheduler."""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np
import pytest
from scipy import stats

import gimbalsim
from gimbalsim import indices
from conftest import CONTROLLER_CONFIG, SCENES

DURATION = 0.5
SPEC = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: {DURATION}}}
controller: {CONTROLLER_CONFIG}
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.2, profile.hold_time: 0.1}}
samples: 6
seed: 11
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
  sensors.star_tracker_noise: {{uniform: [0.0, 2.0e-5]}}
  controller.azimuth.kp: {{uniform: [2000.0, 4000.0]}}
phases: [slew, hold, track, {{late: [0.4, 0.5]}}]
indices:
  ape: {{level: 0.5, confidence: 0.5, requirement: 1.0}}
  rpe: {{window: 0.05}}
  pde: {{window: 0.02, separation: 0.05}}
  knowledge: {{requirement: 1.0e-12}}
"""
PHASES = ["slew", "hold", "track", "late"]
INDICES = ["ape", "rpe", "pde", "knowledge"]


def sweep_cmd(spec, out, *args):
    return [sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", str(out), "--no-progress", *args]


def run_sweep(spec, out, *args):
    p = subprocess.run(sweep_cmd(spec, out, *args), capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    return p


def read(out):
    """results.csv without wall_time: (header, rows)."""
    with open(out / "results.csv") as f:
        rows = list(csv.reader(f))
    w = rows[0].index("wall_time_s")
    rows = [r[:w] + r[w + 1:] for r in rows]
    return rows[0], rows[1:]


@pytest.fixture(scope="module")
def spec(tmp_path_factory):
    d = tmp_path_factory.mktemp("spec")
    (d / "spec.yaml").write_text(SPEC)
    return d / "spec.yaml"


@pytest.fixture(scope="module")
def reference(spec, tmp_path_factory):
    out = tmp_path_factory.mktemp("ref")
    p = run_sweep(spec, out, "--workers", "1")
    from test_csv_convention import check_convention
    check_convention(out / "results.csv")
    return out, p.stderr


def test_columns_follow_the_csv_convention(reference):
    header, rows = read(reference[0])
    assert header[:3] == ["sample", "contact_clearance_m", "sensors_star_tracker_noise_rad"]
    assert header[3].startswith("controller_azimuth_kp") and header[4] == "status"
    assert header[header.index("status") + 1] == "reason"
    for p in PHASES:
        for i in INDICES:
            assert f"{i}_{p}_rad" in header
    assert [int(r[0]) for r in rows] == list(range(6))
    # Each journal's largest tilt, from the truth: a planar bearing never tilts.
    t1, t2 = header.index("max_tilt1_rad"), header.index("max_tilt2_rad")
    assert header[t2 + 1] == "t_end_s"
    assert all(float(r[t1]) == 0.0 and float(r[t2]) == 0.0 for r in rows if r[4] == "ok")


def independent_indices(run, dt):
    """indices.py on the run's ticks, the phases found from the ticks' own
    segment column (the profile the firmware ran: 1 slew, 2 hold, 3 track)."""
    c = run.columns
    t = np.asarray(c["t"])
    seg = np.asarray(c["segment"])
    e = np.column_stack([c["los_error_x"], c["los_error_y"], c["los_error_z"]])
    k = np.column_stack([c["los_error_est_x"], c["los_error_est_y"], c["los_error_est_z"]])
    windows = {}
    for name, code in (("slew", 1), ("hold", 2), ("track", 3)):
        ts = t[seg == code]
        windows[name] = (ts.min(), ts.max() + dt)
    windows["late"] = (0.4, 0.5)
    out = {}
    for p, (t0, t1) in windows.items():
        out[f"ape_{p}_rad"] = indices.ape(t, e, t0, t1)
        out[f"rpe_{p}_rad"] = indices.rpe(t, e, t0, t1, 0.05)
        out[f"pde_{p}_rad"] = indices.pde(t, e, t0, t1, 0.02, 0.05)
        out[f"knowledge_{p}_rad"] = indices.knowledge(t, k, e, t0, t1)
    return out


def test_per_sample_indices_equal_indices_py_on_the_runs_own_ticks(reference, spec):
    from gimbalsim.sweep import SweepSpec
    header, rows = read(reference[0])
    for row in rows[:2]:
        v = dict(zip(header, row))
        kp = float(row[3])  # controller.azimuth.kp, with its unit suffix
        # the scene as the sweep steps it (sampling: auto's overrides, _sampling.py)
        scene = gimbalsim.load_scene(SCENES / "paper_clearance.yaml",
                                     {"sim.duration": DURATION, "contact.clearance": float(v["contact_clearance_m"]),
                                      "sensors.star_tracker_noise": float(v["sensors_star_tracker_noise_rad"]),
                                      **SweepSpec(spec).sampling["overrides"]})
        ctrl = gimbalsim.Controller(CONTROLLER_CONFIG, {"profile.slew_start": 0.0, "profile.slew_time": 0.2,
                                                        "profile.hold_time": 0.1, "azimuth.kp": kp})
        run = gimbalsim.closed_loop(scene, ctrl, DURATION)
        assert run.ok and v["status"] == "ok"
        # the error vector's length is the scalar truth error
        e = np.column_stack([run.columns[f"los_error_{a}"] for a in "xyz"])
        np.testing.assert_allclose(np.linalg.norm(e, axis=1), run.columns["truth_error"], rtol=1e-9, atol=1e-15)
        assert np.abs(e).max() > 0
        expected = independent_indices(run, ctrl.period)
        for col, value in expected.items():
            if value.ok:
                assert float(v[col]) == value.value, col
            else:
                assert v[col] == "nan", col
        # every index of every phase is a number (the spec's phases all lie within the run)
        assert all(math.isfinite(float(v[f"{i}_{p}_rad"])) for i in INDICES for p in PHASES)
        assert v["reason"] == ""
        # a phase a sample's run never reached (one that stopped early) is NaN with its reason
        from gimbalsim._closed_sample import sample_indices
        past = sample_indices(SweepSpec(spec).closed, run.columns, {p: (5.0, 6.0) for p in PHASES})
        assert all(not past[f"{i}_{p}"].ok and math.isnan(past[f"{i}_{p}"].value) for i in INDICES for p in PHASES)
        assert "never reached the phase [5, 6) s" in past["ape_late"].reason


def test_the_budget_table_marks_what_n_cannot_support_and_gives_verdicts(reference):
    out, stderr = reference
    header, rows = read(out)
    s = json.loads((out / "summary.json").read_text())
    table = {(e["index"], e["phase"]): e for e in s["budget"]}
    assert set(table) == {(i, p) for i in INDICES for p in PHASES}
    # the default level 99.73 % at 95 %: 6 units cannot support it, and say so
    rpe = table[("rpe", "track")]
    assert rpe["level"] == 0.9973 and not rpe["supported"]
    assert rpe["note"] == "not supported: n=6 < 1109 needed for 99.73 % at 95 %"
    assert rpe["interpretation"] == "ensemble of units, worst time in the phase"
    assert "rpe track at 99.73 %: not supported: n=6 < 1109 needed" in stderr
    # the median at 50 %: the interval from order statistics, computed here from the binomial
    ape = table[("ape", "track")]
    x = np.sort([float(r[header.index("ape_track_rad")]) for r in rows])
    cdf = stats.binom.cdf(np.arange(7), 6, 0.5)
    r = max(k for k in range(7) if k == 0 or cdf[k - 1] <= 0.25)
    s2 = min(k for k in range(1, 8) if cdf[k - 1] >= 0.75)
    assert ape["supported"] and ape["n"] == 6
    assert ape["estimate_rad"] == x[2] and ape["interval_rad"] == [x[r - 1], x[s2 - 1]]
    # requirements: 1 rad met by all (PASS at 50 %), 1e-12 rad by none (FAIL)
    assert ape["requirement"]["verdict"] == "PASS" and ape["requirement"]["n_meeting"] == 6
    assert ape["requirement"]["fraction_lower_bound"] == pytest.approx(0.5 ** (1 / 6))
    know = table[("knowledge", "track")]
    assert know["requirement"]["verdict"] == "FAIL" and know["requirement"]["n_meeting"] == 0
    late = table[("ape", "late")]
    assert late["n_missing"] == 0 and late["n"] == 6
    report = (out / "report.md").read_text()
    assert "not supported: n=6 < 1109 needed for 99.73 % at 95 %" in report
    assert (out / "plots" / "ape_track_cdf.png").stat().st_size > 5000
    assert "Spearman" in report


def test_one_and_two_workers_and_a_real_scheduler_give_the_same_results(reference, spec, tmp_path):
    ref = read(reference[0])
    run_sweep(spec, tmp_path / "two", "--workers", "2", "--batch", "1")
    assert read(tmp_path / "two") == ref
    from test_sweep import free_port
    port = free_port()
    addr = f"tcp://127.0.0.1:{port}"
    procs = [subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        time.sleep(1.0)
        for _ in range(2):
            procs.append(subprocess.Popen(["dask-worker", addr, "--nthreads", "1", "--no-dashboard",
                                           "--host", "127.0.0.1"], stdout=subprocess.DEVNULL,
                                          stderr=subprocess.DEVNULL, env=dict(os.environ)))
        from distributed import Client
        with Client(addr, timeout="30s") as c:
            c.wait_for_workers(2, timeout=60)
        run_sweep(spec, tmp_path / "s", "--scheduler", addr)
        assert read(tmp_path / "s") == ref
        assert json.loads((tmp_path / "s" / "summary.json").read_text())["engine"]["workers"] == 2
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            p.wait(timeout=30)


def small_spec(tmp_path, samples):
    text = SPEC.replace("samples: 6", f"samples: {samples}")
    path = tmp_path / f"spec{samples}.yaml"
    path.write_text(text)
    return path


def test_until_stops_by_the_cap_and_by_width_and_does_not_depend_on_batches(tmp_path):
    run_sweep(small_spec(tmp_path, 9), tmp_path / "nine", "--workers", "1")
    nine = read(tmp_path / "nine")
    # a width no interval reaches: batches of 3 up to the cap of 9, the same rows as 9 at once
    p = run_sweep(small_spec(tmp_path, 3), tmp_path / "cap", "--workers", "1", "--until", "ape:track:1e-9",
                  "--max-samples", "9")
    assert read(tmp_path / "cap") == nine
    u = json.loads((tmp_path / "cap" / "summary.json").read_text())["until"]
    assert u["stopped_by"] == "cap" and u["samples"] == 9
    assert "stopped by the cap at 9 samples" in p.stderr
    # a width the first interval meets (the median of 4 units has a two-sided interval): no batch added
    run_sweep(small_spec(tmp_path, 4), tmp_path / "width", "--workers", "1", "--until", "ape:track:1e9",
              "--max-samples", "9")
    u = json.loads((tmp_path / "width" / "summary.json").read_text())["until"]
    assert u["stopped_by"] == "width" and u["samples"] == 4
    assert read(tmp_path / "width")[1] == nine[1][:4]


def test_resume_and_replay_keep_the_rows_until_added(tmp_path):
    # --until grew a 3-sample spec to 8 rows: the cap fell inside the third batch, and design.json says 8.
    grown = tmp_path / "grown"
    run_sweep(small_spec(tmp_path, 3), grown, "--workers", "1", "--until", "ape:track:1e-9", "--max-samples", "8")
    assert json.loads((grown / "design.json").read_text()) == {"samples": 8}
    finished = read(grown)
    assert len(finished[1]) == 8
    # An interrupted copy keeps rows 3..6 (not "outside the design") and runs sample 7 only.
    out = tmp_path / "resumed"
    out.mkdir()
    for name in ("spec.json", "design.json"):
        (out / name).write_text((grown / name).read_text())
    lines = (grown / "results.csv").read_text().splitlines(keepends=True)
    (out / "results.partial.csv").write_text("".join(lines[:8]))  # the header and samples 0 to 6
    p = run_sweep(small_spec(tmp_path, 3), out, "--workers", "1", "--resume")
    assert "8 samples, 7 already done, 1 to run" in p.stderr, p.stderr
    assert "dropped" not in p.stderr
    assert read(out) == finished
    # The finished sweep resumed runs nothing: its capped batch is not made whole (it ran 9 before).
    p = run_sweep(small_spec(tmp_path, 3), grown, "--workers", "1", "--resume")
    assert "8 samples, 8 already done, 0 to run" in p.stderr, p.stderr
    assert read(grown) == finished
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(grown), "--replay", "7", "--out",
                        str(tmp_path / "run7.csv")], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0 and "reproduces its row" in p.stderr, p.stderr
    # results.csv of the sweep before --until grew it, the journal with the rows added since: both are read
    stale = tmp_path / "stale"
    shutil.copytree(grown, stale)
    (stale / "results.partial.csv").write_text("".join(lines))
    (stale / "results.csv").write_text("".join(lines[:4]))
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(stale), "--replay", "6", "--out",
                        str(tmp_path / "run6.csv")], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0 and "reproduces its row" in p.stderr, p.stderr
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(grown), "--replay", "8", "--out",
                        str(tmp_path / "run8.csv")], capture_output=True, text=True, timeout=300)
    assert p.returncode == 2 and "outside the sweep's samples 0..7" in p.stderr, p.stderr
    # a cap below what the sweep already holds cannot shrink it (it said "stopped by the cap at 8")
    p = subprocess.run(sweep_cmd(small_spec(tmp_path, 3), grown, "--workers", "1", "--resume", "--until",
                                 "ape:track:1e-9", "--max-samples", "5"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 2 and "--max-samples 5 is below the 8 samples" in p.stderr, p.stderr
    # Without its record the rows beyond the spec are refused, never dropped (they were 5 rows lost).
    (grown / "design.json").unlink()
    p = subprocess.run(sweep_cmd(small_spec(tmp_path, 3), grown, "--workers", "1", "--resume"),
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 2 and "beyond the sweep's 3 samples" in p.stderr and "design.json" in p.stderr, p.stderr
    assert read(grown) == finished
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(grown), "--replay", "1", "--out",
                        str(tmp_path / "run1.csv")], capture_output=True, text=True, timeout=300)  # as the resume
    assert p.returncode == 2 and "beyond the sweep's 3 samples" in p.stderr, p.stderr


def test_a_design_record_that_is_not_the_sweeps_is_refused(tmp_path):
    out = tmp_path / "d"
    out.mkdir()
    (out / "design.json").write_text('{"samples": 2}')  # fewer than the spec's 3
    p = subprocess.run(sweep_cmd(small_spec(tmp_path, 3), out, "--workers", "1", "--resume"),
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 2 and "design.json" in p.stderr and "3 to" in p.stderr, p.stderr
    p = subprocess.run(sweep_cmd(small_spec(tmp_path, 3), out, "--workers", "1"),
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 2 and "already holds a sweep" in p.stderr, p.stderr


def test_workers_beyond_the_machine_or_below_one_are_refused(tmp_path):
    for n in ("0", "-1", str(4 * (os.cpu_count() or 1) + 1), "2.5"):
        p = subprocess.run(sweep_cmd(small_spec(tmp_path, 3), tmp_path / "w", "--workers", n),
                           capture_output=True, text=True, timeout=300)
        assert p.returncode == 2 and "--workers" in p.stderr and "Traceback" not in p.stderr, (n, p.stderr)
        assert not (tmp_path / "w").exists()


def test_until_keeps_one_cluster_for_all_its_rounds(tmp_path, monkeypatch):
    import contextlib
    from gimbalsim import _cluster, sweep
    from gimbalsim._until import Until
    starts = []
    real = _cluster.dask_client

    @contextlib.contextmanager
    def counted(*args, **kwargs):
        starts.append(args)
        with real(*args, **kwargs) as cluster:
            yield cluster
    monkeypatch.setattr(_cluster, "dask_client", counted)
    spec = sweep.SweepSpec(small_spec(tmp_path, 2))
    s = sweep.sweep(spec, tmp_path / "o", workers=1, progress=False, until=Until("ape:track:1e-9", spec, 6))
    assert s["until"]["samples"] == 6 and s["until"]["stopped_by"] == "cap"
    assert len(starts) == 1  # three rounds of two samples, one cluster

def test_a_dispersed_profile_that_empties_a_phase_gives_nan_with_the_reason(tmp_path):
    # controller.profile.hold_time drawn 0 for some units: their hold has no tick, so its indices are NaN
    # with the reason in the row; the sweep finishes (it was a traceback, exit 1).
    text = SPEC.replace("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}",
                        "  controller.profile.hold_time: {choice: [0.1, 0.0]}").replace("samples: 6", "samples: 4")
    text = text.replace("  pde: {window: 0.02, separation: 0.05}\n", "").replace("  rpe: {window: 0.05}\n", "")
    (tmp_path / "h.yaml").write_text(text)
    run_sweep(tmp_path / "h.yaml", tmp_path / "o", "--workers", "1")
    with open(tmp_path / "o" / "results.csv") as f:
        rows = list(csv.DictReader(f))
    empty = [r for r in rows if float(r["controller_profile_hold_time_s"]) == 0.0]
    assert empty and all(r["ape_hold_rad"] == "nan" and "is empty" in r["reason"] for r in empty), rows
    assert all(r["ape_hold_rad"] != "nan" for r in rows if r not in empty)


def test_until_refused_for_an_index_the_spec_does_not_name(spec, tmp_path):
    p = subprocess.run(sweep_cmd(spec, tmp_path / "u", "--until", "ape:cruise:0.1"), capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 2 and "phase 'cruise' is not one of the spec's" in p.stderr
    assert not (tmp_path / "u").exists()
    # inf stopped at once, "converged" with no interval at all; (pass 33) ' 0.1' and '1_0' were float()'s
    for width in ("inf", "nan", "0", "-0.1", " 0.1", "0.1 ", "1_0", "0x1", "5e-324"):
        p = subprocess.run(sweep_cmd(spec, tmp_path / "u", "--until", f"ape:track:{width}"), capture_output=True,
                           text=True, timeout=120)
        assert p.returncode == 2 and "RELWIDTH must be a plain decimal number > 0" in p.stderr, (width, p.stderr)
        assert not (tmp_path / "u").exists()
        if width == "5e-324":  # (pass 35) and why, as every number flag says it
            assert "'5e-324' is too small for a double" in p.stderr, p.stderr


def test_the_shipped_budget_spec_is_accepted():
    from conftest import SOURCE
    from gimbalsim.sweep import SweepSpec
    spec = SweepSpec(SOURCE / "tools" / "sweeps" / "pointing_budget.yaml")
    assert spec.closed is not None and spec.closed.controller_path is None  # the default controller
    dispersed = {p.key for p in spec.parameters}
    assert {"contact.clearance", "friction.mu", "contact.restitution", "initial.ecc", "sensors.star_tracker_noise",
            "sensors.gyro_bias"} <= dispersed
    bias = spec.design.draw(0)["sensors.gyro_bias"]
    assert len(bias) == 3 and 0 < np.linalg.norm(bias) <= 1.0e-5


def test_sample_alone_reproduces_its_row_and_returns_its_run(reference, spec):
    from gimbalsim.sweep import SweepSpec, sample_alone
    header, rows = read(reference[0])
    row, run = sample_alone(SweepSpec(spec), 3)
    w = SweepSpec(spec).header().index("wall_time")
    assert row[:w] + row[w + 1:] == rows[3]
    assert run.ok and len(run.columns["los_error_x"]) == round(DURATION / 1e-3) + 1


def test_resume_reads_the_closed_loops_journal_back(reference, spec, tmp_path):
    ref_out = reference[0]
    out = tmp_path / "resumed"
    out.mkdir()
    (out / "spec.json").write_text((ref_out / "spec.json").read_text())
    lines = (ref_out / "results.csv").read_text().splitlines(keepends=True)
    (out / "results.partial.csv").write_text("".join(lines[:4]))  # the header and samples 0 to 2, reasons included
    p = run_sweep(spec, out, "--workers", "1", "--resume")
    assert "6 samples, 3 already done, 3 to run" in p.stderr
    assert "dropped" not in p.stderr
    assert read(out) == read(ref_out)


def test_a_unit_that_did_not_end_ok_counts_as_worst_whatever_its_row_holds(tmp_path):
    # A stopped run's figures over the part it ran were counted as a good unit's (a budget could PASS on them).
    from gimbalsim import _budget
    from gimbalsim.sweep import SweepSpec
    path = tmp_path / "s.yaml"
    path.write_text(SPEC.replace(f"set: {{sim.duration: {DURATION}}}", "set: {sim.duration: 0.5}"))
    spec = SweepSpec(path)
    header = spec.header()
    ok = ["1e-3"] * len(header)
    ok[header.index("status")] = "ok"
    stopped = list(ok)
    stopped[header.index("status")] = "non_finite"
    values = _budget.column_values(spec, [ok, stopped], "ape_track")
    assert values[0] == 1e-3 and math.isnan(values[1])
