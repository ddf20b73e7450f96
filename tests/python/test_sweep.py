"""gimbalsim.sweep on Dask: the same results.csv (all but wall_time) with 1
or 2 local workers, on a real dask-scheduler with two dask-worker processes,
with a worker killed mid-sweep, and after an interrupted sweep resumed; spec
refusals name the spec's key and line."""
import csv
import json
import os
import pathlib
import re
import signal
import socket
import subprocess
import sys
import time

import psutil
import pytest

from conftest import SCENES, SOURCE
from gimbalsim._errors import SpecError
from gimbalsim._sweep_spec import SweepSpec

SPEC = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.3}}
samples: 30
seed: 7
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
  friction.mu: {{normal: {{mean: 0.25, sd: 0.05, min: 0.05, max: 0.5}}}}
  contact.restitution: {{uniform: [0.8, 0.98]}}
  initial.ecc: {{disk: {{within: contact.clearance, fraction: 0.9}}}}
grid:
  torque.tau2: [5.0, 20.0]
"""
N = 60


def sweep_cmd(spec, out, *args):
    return [sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", str(out), "--no-progress", *args]


def run_sweep(spec, out, *args, check=True):
    p = subprocess.run(sweep_cmd(spec, out, *args), capture_output=True, text=True, timeout=600)
    if check:
        assert p.returncode == 0, p.stderr
    return p


def results(out):
    """results.csv without wall_time."""
    with open(out / "results.csv") as f:
        rows = list(csv.reader(f))
    w = rows[0].index("wall_time_s")
    return [r[:w] + r[w + 1:] for r in rows]


@pytest.fixture(scope="module")
def spec(tmp_path_factory):
    d = tmp_path_factory.mktemp("spec")
    (d / "spec.yaml").write_text(SPEC)
    return d / "spec.yaml"


@pytest.fixture(scope="module")
def reference(spec, tmp_path_factory):
    out = tmp_path_factory.mktemp("ref")
    run_sweep(spec, out, "--workers", "1")
    from test_csv_convention import check_convention
    check_convention(out / "results.csv")  # the project's CSV convention: numpy and csv read the same names
    return results(out)


def test_a_spatial_bearings_sweep_reports_each_joints_impacts_and_tilt(tmp_path):
    # The elevation journal tilts, up to about its bearing's 2c/L; the
    # azimuth joint is ideal: no impacts, no tilt.
    (tmp_path / "s.yaml").write_text(f"""
scene: {SCENES}/paper_spatial2.yaml
set: {{sim.duration: 0.3}}
samples: 3
seed: 1
parameters:
  contact.bearing_length: {{uniform: [0.04, 0.06]}}
""")
    run_sweep(tmp_path / "s.yaml", tmp_path / "o", "--workers", "1")
    with open(tmp_path / "o" / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 3
    for r in rows:
        assert r["status"] == "ok", r
        limit = 2 * 0.5e-3 / float(r["contact_bearing_length_m"])  # c = R_i - R_j of the scene
        assert 0.1 * limit < float(r["max_tilt2_rad"]) < 1.2 * limit, r
        assert float(r["max_tilt1_rad"]) == 0.0 and int(r["impacts_joint1"]) == 0
        assert int(r["impacts_joint2"]) == int(r["impacts"]) > 0


def test_a_sweep_disperses_one_bearing_by_either_spelling(tmp_path):
    # Both bearings planar; the azimuth's own clearance and friction are
    # dispersed, by today's key and by its old spelling (contact1.*, friction1.*).
    import gimbalsim
    for clearance_key, mu_key in (("joint1.contact.clearance", "joint1.friction.mu"),
                                  ("contact1.clearance", "friction1.mu")):
        out = tmp_path / clearance_key
        (tmp_path / "s.yaml").write_text(f"""
scene: {SCENES}/paper_both_planar.yaml
set: {{sim.duration: 0.05}}
samples: 2
seed: 3
parameters:
  {clearance_key}: {{uniform: [1.0e-4, 3.0e-4]}}
  {mu_key}: {{uniform: [0.1, 0.2]}}
""")
        run_sweep(tmp_path / "s.yaml", out, "--workers", "1")
        with open(out / "results.csv") as f:
            rows = list(csv.DictReader(f))
        col = clearance_key.replace(".", "_") + "_m"
        for r in rows:
            assert r["status"] == "ok", r
            assert r["applied_differs"] == "", r  # each draw was applied as drawn
            scene = gimbalsim.load_scene(f"{SCENES}/paper_both_planar.yaml",
                                         {clearance_key: float(r[col]), mu_key: float(r[mu_key.replace(".", "_")])})
            v = scene.values()  # a joint's own key only where it differs from contact.*
            c1 = float(v["contact.bearing_radius"]) - float(v["joint1.contact.journal_radius"])
            c2 = float(v["contact.bearing_radius"]) - float(v["contact.journal_radius"])
            assert "joint2.contact.journal_radius" not in v
            assert c1 == pytest.approx(float(r[col]), rel=1e-9) and c2 == pytest.approx(5e-4, rel=1e-9)


def test_one_worker_results_are_whole_and_sorted(reference, spec):
    header, rows = reference[0], reference[1:]
    # the project's CSV convention: identifiers, the key's unit as a suffix
    assert header[:8] == ["sample", "torque_tau2_Nm", "contact_clearance_m", "friction_mu", "contact_restitution",
                          "initial_ecc_0_m", "initial_ecc_1_m", "status"]
    assert [int(r[0]) for r in rows] == list(range(N))
    ok = [r for r in rows if r[7] == "ok"]
    assert len(ok) == N  # the disk is inside the clearance: every sample runs
    col = header.index("pointing_error_max_rad")
    assert all(0.0 < float(r[col]) < 0.01 for r in ok)
    # common random numbers: grid point 1 sees the draws of grid point 0
    assert [r[2:7] for r in rows[:30]] == [r[2:7] for r in rows[30:]]
    assert {r[1] for r in rows[:30]} == {"5"} and {r[1] for r in rows[30:]} == {"20"}


def test_two_workers_and_other_batches_give_the_same_results(reference, spec, tmp_path):
    run_sweep(spec, tmp_path / "a", "--workers", "2", "--batch", "3")
    assert results(tmp_path / "a") == reference
    summary = json.loads((tmp_path / "a" / "summary.json").read_text())
    assert summary["status"] == {"ok": N}
    assert summary["engine"]["workers"] == 2 and summary["engine"]["ran_this_invocation"] == N
    # the workers' wait after their last task is apart from the engine's overhead, and within the run's time
    e = summary["engine"]
    assert 0.0 <= e["drain_idle_per_sample_s"] <= e["elapsed_s"] * 2 / N, e
    assert e["engine_overhead_per_sample_s"] + e["drain_idle_per_sample_s"] <= e["elapsed_s"] * 2 / N, e
    assert 0.0 < e["warm_up_s"] < e["elapsed_s"], e  # every worker answered before the first task
    p = summary["percentiles_of_ok_samples"]["pointing_error_max"]
    assert p["p50"] <= p["p90"] <= p["p99"] <= p["max"]
    assert (tmp_path / "a" / "plots" / "pointing_error_distribution.png").stat().st_size > 5000


@pytest.mark.parametrize("n,workers,size", [(60, 2, 4), (1109, 2, 10), (7, 2, 1), (200, 4, 7)])
def test_default_tasks_shrink_to_single_samples_at_the_end(n, workers, size):
    # (issue 40) tasks of 4 closed-loop units left one of two workers idle ~2 s at the end of a 60-unit sweep
    from gimbalsim._cluster import task_chunks
    guided, fixed = (task_chunks(list(range(n)), size, workers, g) for g in (True, False))
    for chunks in (guided, fixed):
        assert [i for c in chunks for i in c] == list(range(n))  # every sample once, in order
    assert max(map(len, guided)) == size and [len(c) for c in fixed[:-1]] == [size] * (len(fixed) - 1)
    sizes = [len(c) for c in guided]
    assert sizes == sorted(sizes, reverse=True)  # never a bigger task after a smaller one
    assert sizes[-2 * workers:] == [1] * 2 * workers  # the last round, one sample per task
    assert len(guided) <= len(fixed) + 4 * workers + size  # the tail costs a few tasks, not one per sample


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_real_scheduler_with_two_workers_gives_the_same_results(reference, spec, tmp_path):
    port = free_port()
    addr = f"tcp://127.0.0.1:{port}"
    env = dict(os.environ)
    procs = [subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                              env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        time.sleep(1.0)
        for _ in range(2):
            procs.append(subprocess.Popen(["dask-worker", addr, "--nthreads", "1", "--no-dashboard",
                                           "--host", "127.0.0.1"], env=env, stdout=subprocess.DEVNULL,
                                          stderr=subprocess.DEVNULL))
        from distributed import Client
        with Client(addr, timeout="30s") as c:
            c.wait_for_workers(2, timeout=60)
        run_sweep(spec, tmp_path / "s", "--scheduler", addr)
        assert results(tmp_path / "s") == reference
        assert json.loads((tmp_path / "s" / "summary.json").read_text())["engine"]["workers"] == 2
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            p.wait(timeout=30)


def journal_rows(out):
    try:
        return max(0, (out / "results.partial.csv").read_text().count("\n") - 1)
    except FileNotFoundError:
        return 0


def wait_for_rows(out, proc, n, timeout=120):
    t0 = time.time()
    while journal_rows(out) < n:
        assert proc.poll() is None, "the sweep ended before the test could interrupt it"
        assert time.time() - t0 < timeout
        time.sleep(0.02)


def test_a_worker_killed_mid_sweep_loses_no_sample(reference, spec, tmp_path):
    out = tmp_path / "k"
    proc = subprocess.Popen(sweep_cmd(spec, out, "--workers", "2", "--batch", "1"), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    wait_for_rows(out, proc, 5)
    workers = [c for c in psutil.Process(proc.pid).children() if "spawn_main" in " ".join(c.cmdline())]
    assert len(workers) == 2
    workers[0].kill()
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err
    assert journal_rows(out) == 0 and results(out) == reference  # every sample exactly once, the same values


def test_resume_runs_only_what_is_missing(reference, spec, tmp_path):
    out = tmp_path / "r"
    proc = subprocess.Popen(sweep_cmd(spec, out, "--workers", "1", "--batch", "1"), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, start_new_session=True)
    wait_for_rows(out, proc, 10)
    os.killpg(proc.pid, signal.SIGKILL)  # as a crash or a power cut: no clean-up at all
    proc.wait()
    done = journal_rows(out)
    assert 10 <= done < N and not (out / "results.csv").exists()
    refused = run_sweep(spec, out, "--workers", "1", check=False)
    assert refused.returncode == 2 and "--resume" in refused.stderr
    p = run_sweep(spec, out, "--workers", "2", "--resume")
    assert f"{done} already done, {N - done} to run" in p.stderr
    assert json.loads((out / "summary.json").read_text())["engine"]["ran_this_invocation"] == N - done
    assert results(out) == reference
    again = run_sweep(spec, out, "--resume")  # nothing left: runs nothing, same results
    assert f"{N} already done, 0 to run" in again.stderr and results(out) == reference


def test_a_link_under_an_outputs_name_is_refused_before_any_sample(spec, tmp_path):
    for name in ("summary.json", "design.json", "results.partial.csv"):
        out = tmp_path / name.replace(".", "_")
        out.mkdir()
        (out / name).symlink_to(tmp_path / "victim")  # every sample ran, then exit 4 ("free the space")
        p = run_sweep(spec, out, check=False)
        assert p.returncode == 2 and "a symbolic link" in p.stderr and name in p.stderr, p.stderr
        assert sorted(x.name for x in out.iterdir()) == [name] and not (tmp_path / "victim").exists()


def test_an_out_through_a_link_and_unreadable_study_files_are_refused(spec, tmp_path):
    (tmp_path / "real").mkdir()
    (tmp_path / "L").symlink_to(tmp_path / "real")
    p = run_sweep(spec, tmp_path / "L", check=False)
    assert p.returncode == 2 and "is a link" in p.stderr and not any((tmp_path / "real").iterdir()), p.stderr
    (tmp_path / "deep.yaml").write_text("samples: " + "[" * 1000 + "]" * 1000 + "\n")
    p = run_sweep(tmp_path / "deep.yaml", tmp_path / "o", check=False)
    assert p.returncode == 2 and "nested too deeply" in p.stderr and "Traceback" not in p.stderr, p.stderr
    # a journal holding a line no sweep wrote (over the csv module's field limit) or a pipe in its place
    out = tmp_path / "j"
    run_sweep(spec, out, "--workers", "1")
    header = (out / "results.csv").read_text().splitlines()[0]
    (out / "results.csv").unlink()
    (out / "results.partial.csv").write_text(header + "\n1," + "x" * 500000 + "\n")
    p = run_sweep(spec, out, "--workers", "1", "--resume", check=False)
    assert p.returncode == 0 and "dropped 1 journal row (unreadable line) at " \
        f"{out / 'results.partial.csv'} line 2;" in p.stderr, p.stderr
    with open(out / "results.csv", "a") as f:
        f.write("2," + "y" * 500000 + "\n")
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(out), "--replay", "1", "--out",
                        str(tmp_path / "r.csv")], capture_output=True,
                       text=True, timeout=300)
    assert p.returncode == 2 and "cannot read it" in p.stderr and "Traceback" not in p.stderr, p.stderr
    fifo = tmp_path / "f"
    fifo.mkdir()
    (fifo / "spec.json").write_text((out / "spec.json").read_text())
    os.mkfifo(fifo / "results.partial.csv")
    p = subprocess.run(sweep_cmd(spec, fifo, "--resume"), capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "not a regular file" in p.stderr, p.stderr


def test_missing_or_malformed_specs_are_refused(tmp_path):
    (tmp_path / "a.yaml").write_text(f"scene: {SCENES}/paper_clearance.yaml\nseed: 1\n")
    p = run_sweep(tmp_path / "a.yaml", tmp_path / "o", check=False)
    assert p.returncode == 2 and "key 'samples': missing" in p.stderr
    (tmp_path / "b.yaml").write_text("samples: [1,\n")
    p = run_sweep(tmp_path / "b.yaml", tmp_path / "o", check=False)
    assert p.returncode == 2 and "not valid YAML" in p.stderr
    (tmp_path / "c.yaml").write_text("a: &x [1, 2]\nb: &y [*x, *x, *x, *x, *x, *x, *x, *x, *x, *x]\n"
                                     "c: &z [*y, *y, *y, *y, *y, *y, *y, *y, *y, *y]\n"
                                     "d: &w [*z, *z, *z, *z, *z, *z, *z, *z, *z, *z]\n"
                                     "e: &v [*w, *w, *w, *w, *w, *w, *w, *w, *w, *w]\n"
                                     "f: [*v, *v, *v, *v, *v, *v, *v, *v, *v, *v]\n")
    p = run_sweep(tmp_path / "c.yaml", tmp_path / "o", check=False)
    assert p.returncode == 2 and "c.yaml:1:4: anchors (&name) are not accepted: write the value out" in p.stderr, \
        p.stderr
    # (pass 81) an alias copied one key's distribution to another and the sweep ran: refused as the scene
    # loader refuses it, at the alias
    spec = (f"scene: {SCENES}/paper_clearance.yaml\nsamples: 2\nseed: 1\nparameters:\n"
            "  friction.mu: {uniform: [0.2, 0.3]}\n  contact.restitution: *u\n")
    (tmp_path / "d.yaml").write_text(spec)
    p = run_sweep(tmp_path / "d.yaml", tmp_path / "o", check=False)
    assert p.returncode == 2 and "d.yaml:6:24: aliases (*name) are not accepted" in p.stderr, p.stderr


def test_the_keys_the_docs_call_required_are_the_ones_the_spec_needs(tmp_path):
    # docs/python.md: "(`a`, `b` and at least one of `c` and `d` are required; ...)". A spec of
    # the required keys and either one of the others loads; one without any of them is refused naming it.
    doc = (SOURCE / "docs" / "python.md").read_text()
    sentence = re.search(r"\(([^()]*) are\s+required; every other key is optional\)", doc).group(1)
    always, either = sentence.split("at least one of")
    required, one_of = re.findall(r"`([a-z_]+)`", always), re.findall(r"`([a-z_]+)`", either)
    assert required and one_of, sentence
    # samples: 1, as a grid alone draws nothing to tell its samples apart (refused above 1)
    values = {"scene": f"{SCENES}/paper_clearance.yaml", "samples": "1", "seed": "1",
              "parameters": "{friction.mu: {uniform: [0.1, 0.2]}}", "grid": "{friction.mu: [0.1, 0.2]}"}
    spec = lambda keys: "".join(f"{k}: {values[k]}\n" for k in keys)  # noqa: E731
    for extra in one_of:
        (tmp_path / "min.yaml").write_text(spec(required + [extra]))
        assert SweepSpec(tmp_path / "min.yaml").samples == 1
    for left_out in required:
        (tmp_path / "less.yaml").write_text(spec([k for k in required if k != left_out] + one_of[:1]))
        with pytest.raises(SpecError, match=f"key '{left_out}': missing"):
            SweepSpec(tmp_path / "less.yaml")
    (tmp_path / "none.yaml").write_text(spec(required))
    with pytest.raises(SpecError, match="nothing is dispersed"):
        SweepSpec(tmp_path / "none.yaml")


def test_a_joints_own_eccentricity_is_dispersed_and_recorded(tmp_path):
    # initial.ecc2 is listed by a scene only where it differs from initial.ecc: its provenance
    # column read it from there (a KeyError, exit 1, when a draw equalled the shared value).
    (tmp_path / "e.yaml").write_text(f"scene: {SCENES}/paper_clearance.yaml\nset: {{sim.duration: 0.1}}\n"
                                     "samples: 2\nseed: 1\nparameters:\n"
                                     "  initial.ecc2: {choice: [[0.0, 0.0], [1.0e-4, 0.0]]}\n")
    run_sweep(tmp_path / "e.yaml", tmp_path / "o", "--workers", "1")
    with open(tmp_path / "o" / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 2 and all(r["status"] == "ok" and r["applied_differs"] == "" for r in rows), rows
    assert all(r["applied_initial_ecc2_0_m"] == r["initial_ecc2_0_m"] for r in rows), rows


def test_an_out_that_is_a_file_is_refused_and_left_alone(spec, tmp_path):
    before = spec.read_bytes()
    p = run_sweep(spec, spec, check=False)  # --out is the spec itself
    assert p.returncode == 2 and "is the spec file itself" in p.stderr, p.stderr
    assert spec.read_bytes() == before
    (tmp_path / "f").write_text("x")
    p = run_sweep(spec, tmp_path / "f", check=False)
    assert p.returncode == 2 and "exists and is not a folder" in p.stderr, p.stderr
    p = run_sweep(spec, "", check=False)  # it wrote the whole sweep into the current folder
    assert p.returncode == 2 and "argument --out: an empty path" in p.stderr, p.stderr
    p = run_sweep(spec, "  ", check=False)  # it made a folder named two spaces
    assert p.returncode == 2 and "argument --out: a blank path '  '" in p.stderr, p.stderr
    (tmp_path / "study").mkdir()
    (tmp_path / "study" / "trials.csv").write_text("trial\n")  # a tuning study's: its summary.json was replaced
    (tmp_path / "study" / "summary.json").write_text("{}")
    p = run_sweep(spec, tmp_path / "study", check=False)
    assert p.returncode == 2 and "holds a tuning study" in p.stderr, p.stderr
    assert (tmp_path / "study" / "summary.json").read_text() == "{}"


def test_an_input_among_the_outputs_is_refused_before_anything_runs(spec, tmp_path):
    """A spec saved as the summary it would be overwritten by, or one inside
    a plots folder: refused at once (it used to run every sample, then exit 4)."""
    for rel in ("summary.json", "spec.yaml", "plots/s.yaml"):
        out = tmp_path / rel.replace("/", "_")
        (out / rel).parent.mkdir(parents=True)
        (out / rel).write_bytes(spec.read_bytes())
        p = run_sweep(out / rel, out, check=False)
        assert p.returncode == 2 and "an input of this run" in p.stderr and "Traceback" not in p.stderr, p.stderr
        assert "samples" not in p.stderr.split("an input")[0], "refused before any sample ran"
        assert sorted(x.name for x in out.rglob("*")) == sorted(pathlib.PurePath(rel).parts), "nothing written"


# ---- every class of spec value that once crashed the reader: exit 2, the spec's file and line, no files ----

HEAD = f"scene: {SCENES}/paper_clearance.yaml\nsamples: 3\nseed: 1\n"
def test_numbers_read_as_the_scene_reads_them(tmp_path):
    # YAML 1.1 reads 1e-4 as a string and 010 as eight: the scene loader reads 0.0001 and ten
    from gimbalsim.sweep import SweepSpec
    (tmp_path / "s.yaml").write_text(HEAD + "set: {sim.duration: 1e-1}\nparameters:\n"
                                     "  contact.clearance: {uniform: [1e-4, 8E-4]}\ngrid:\n  torque.tau2: [010]\n")
    s = SweepSpec(tmp_path / "s.yaml")
    assert s.set == {"sim.duration": 0.1} and s.parameters[0].args == [1e-4, 8e-4] and s.grid == [("torque.tau2", [10])]


def test_an_out_under_a_file_is_refused_before_anything_runs(spec, tmp_path):
    (tmp_path / "f").write_text("x")
    p = run_sweep(spec, tmp_path / "f" / "sub", check=False)
    assert p.returncode == 2 and "is a file, not a folder" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert (tmp_path / "f").read_text() == "x"


def test_an_out_whose_folder_is_missing_is_refused_not_made(spec, tmp_path):
    # a sweep makes its own folder, never the ones above it (the rule of every output)
    p = run_sweep(spec, tmp_path / "missing" / "o", check=False)
    assert p.returncode == 2 and "does not exist (create it first)" in p.stderr, p.stderr
    assert "Traceback" not in p.stderr
    assert not (tmp_path / "missing").exists()


def test_a_grid_too_large_is_counted_not_built(tmp_path):
    # 10^12 points: building the product first would take all memory; counting takes none
    tau = "[" + ", ".join(f"{1 + k * 1e-3:.3f}" for k in range(10_000)) + "]"
    restitution = "[" + ", ".join(f"{0.5 + k * 1e-4:.4f}" for k in range(1000)) + "]"
    (tmp_path / "g.yaml").write_text(HEAD.replace("samples: 3", "samples: 10000") +
                                     f"grid:\n  torque.tau2: {tau}\n  friction.mu: [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, "
                                     f"0.7, 0.8, 0.9, 0.95]\n  contact.restitution: {restitution}\n")
    import resource
    limit = lambda: resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))  # far below 10^12 tuples
    p = subprocess.run(sweep_cmd(tmp_path / "g.yaml", tmp_path / "o"), capture_output=True, text=True,
                       timeout=120, preexec_fn=limit)
    assert p.returncode == 2, p.stderr
    assert "g.yaml:4:" in p.stderr and "key 'grid'" in p.stderr, p.stderr
    assert "1000000000000 samples" in p.stderr and "more than the limit 10000000" in p.stderr, p.stderr
    assert not (tmp_path / "o").exists()
