"""What the sweep and the tuner refuse before any sample or trial runs, and
before anything is written to --out: a malformed --scheduler (exit 2), a
scheduler that does not answer (exit 6, no traceback, nothing left that would
ask for --resume), and a link or an input under the name of any output
(every plot, summary.json, ...), which was found only at the end (exit 4)."""
import os
import socket
import subprocess
import sys

import pytest

from conftest import CONTROLLER_CONFIG, SCENES

SWEEP = """scene: {scene}
set: {{sim.duration: 0.05}}
samples: 2
seed: 1
parameters:
  friction.mu: {{uniform: [0.1, 0.2]}}
"""
CLOSED = """scene: {scene}
set: {{sim.duration: 0.5}}
controller: {controller}
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.2, profile.hold_time: 0.1}}
samples: 2
seed: 11
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
"""
TUNE = """scene: {scene}
controller: {controller}
duration: 3.7
trials: 1
seed: 3
batch: 1
objective: {{metric: max_track, percentile: 90}}
max_saturation: 0.0
gains:
  azimuth.kp: {{loguniform: [5000, 80000]}}
plants:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
"""
SCENE = SCENES / "paper_clearance.yaml"


def run(module, spec, out, *args, env=None):
    return subprocess.run([sys.executable, "-m", f"gimbalsim.{module}", str(spec), "--out", str(out), "--no-progress",
                           *args], capture_output=True, text=True, timeout=300, env=env)


def run_patched(script, spec, out):
    """The sweep's own main under a stand-in (script: Python that patches gimbalsim.sweep, then runs its main)."""
    return subprocess.run([sys.executable, "-c", script, str(spec), "--out", str(out), "--no-progress", "--workers",
                           "1"], capture_output=True, text=True, timeout=300)


def spec_file(path, text, scene=SCENE, controller=CONTROLLER_CONFIG):
    path.write_text(text.format(scene=scene, controller=controller))
    return path


def names(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def free_port():
    """A loopback port with nothing listening on it (bound, then let go)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.mark.parametrize("module,address", [("sweep", "bogus"), ("sweep", "tcp://127.0.0.1"),
                                            ("sweep", "tcp://127.0.0.1:0"), ("sweep", "http://127.0.0.1:8786"),
                                            ("tune", "bogus")])
def test_a_malformed_scheduler_is_refused_before_anything_is_written(module, address, tmp_path):
    spec = spec_file(tmp_path / "s.yaml", SWEEP if module == "sweep" else TUNE)
    p = run(module, spec, tmp_path / "o", "--scheduler", address)
    assert p.returncode == 2, p.stderr
    assert "--scheduler" in p.stderr and repr(address) in p.stderr and "tcp://HOST:PORT" in p.stderr, p.stderr
    assert "Traceback" not in p.stderr and not (tmp_path / "o").exists(), p.stderr


@pytest.mark.parametrize("module", ["sweep", "tune"])
def test_a_scheduler_that_does_not_answer_is_exit_6_and_leaves_nothing_to_resume(module, tmp_path):
    spec = spec_file(tmp_path / "s.yaml", SWEEP if module == "sweep" else TUNE)
    address = f"tcp://127.0.0.1:{free_port()}"
    # Dask's own connect timeout (30 s unless the environment says): refused connections are retried until it ends
    env = {**os.environ, "DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "2s"}
    p = run(module, spec, tmp_path / "o", "--scheduler", address, env=env)
    assert p.returncode == 6, p.stderr
    assert f"{module}: error: --scheduler {address}: no Dask scheduler answered within 2 s" in p.stderr, p.stderr
    assert "Traceback" not in p.stderr and not (tmp_path / "o").exists(), p.stderr
    # the next run on the same --out starts afresh: no journal or study asks for --resume
    p = run(module, spec, tmp_path / "o", "--workers", "1")
    assert p.returncode == 0, p.stderr


def out_with(tmp_path, make):
    """--out holding what make(out) puts there; returns (out, its names before the run)."""
    out = tmp_path / "o"
    (out / "plots").mkdir(parents=True)
    make(out)
    return out, names(out)


SWEEP_CASES = {
    # links inside plots/, at the names the open loop's plots take
    "link at a distribution plot": lambda t, o: (o / "plots/pointing_error_distribution.png").symlink_to(t / "victim"),
    "link at a plot against a key": lambda t, o: (o / "plots/pointing_error_vs_friction.mu.png").symlink_to(t / "v"),
    # an input under an output's name, by a hard link: the same file under another name
    "hard link of the scene at summary.json": lambda t, o: os.link(t / "sc.yaml", o / "summary.json"),
    "hard link of the spec at a plot": lambda t, o: os.link(t / "s.yaml", o / "plots/peak_force_distribution.png"),
    "a file where plots/ goes": lambda t, o: ((o / "plots").rmdir(), (o / "plots").write_text("x\n")),
}


@pytest.mark.parametrize("case", SWEEP_CASES)
def test_a_sweep_refuses_a_link_or_an_input_under_any_outputs_name_before_running(case, tmp_path):
    (tmp_path / "sc.yaml").write_bytes(SCENE.read_bytes())
    spec = spec_file(tmp_path / "s.yaml", SWEEP, scene=tmp_path / "sc.yaml")
    out, before = out_with(tmp_path, lambda o: SWEEP_CASES[case](tmp_path, o))
    p = run("sweep", spec, out, "--workers", "1")
    assert p.returncode == 2 and "sweep: error:" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert "to run" not in p.stderr, p.stderr  # no sample ran
    assert names(out) == before, "nothing written: no journal, no spec copy, no results"
    assert not (tmp_path / "victim").exists() and not (tmp_path / "v").exists()


def test_a_closed_loop_sweep_refuses_a_link_at_a_budget_plot_before_running(tmp_path):
    spec = spec_file(tmp_path / "c.yaml", CLOSED, controller="default")
    out, before = out_with(tmp_path, lambda o: (o / "plots/ape_track_cdf.png").symlink_to(tmp_path / "victim"))
    p = run("sweep", spec, out, "--workers", "1")
    assert p.returncode == 2 and "ape_track_cdf.png: a symbolic link" in p.stderr, p.stderr
    assert "to run" not in p.stderr and names(out) == before and not (tmp_path / "victim").exists(), p.stderr


@pytest.mark.parametrize("name", ["summary.json", "best.yaml", "progress.png"])
def test_a_tuner_refuses_a_hard_link_of_its_controller_file_at_an_output_before_running(name, tmp_path):
    (tmp_path / "ctrl.yaml").write_bytes(CONTROLLER_CONFIG.read_bytes())
    spec = spec_file(tmp_path / "t.yaml", TUNE, controller=tmp_path / "ctrl.yaml")
    out = tmp_path / "o"
    out.mkdir()
    os.link(tmp_path / "ctrl.yaml", out / name)
    p = run("tune", spec, out, "--workers", "1")
    assert p.returncode == 2 and f"{name}: the same file as the input" in p.stderr, p.stderr
    assert "Traceback" not in p.stderr and names(out) == [name], names(out)


# The sweep's own main, with a link made under summary.json while the plots are drawn:
# the one refusal the up-front check cannot see. The note must not say to free space.
LINK_DURING_THE_RUN = """
import os, sys
import gimbalsim.sweep as sw
real = sw.plot
def plot_then_link(spec, rows, folder, inputs=()):
    written = real(spec, rows, folder, inputs)
    os.symlink(os.devnull, folder.parent / "summary.json")
    return written
sw.plot = plot_then_link
sys.exit(sw.main(sys.argv[1:]))
"""


def test_a_name_refused_at_the_end_does_not_say_free_the_space(tmp_path):
    spec = spec_file(tmp_path / "s.yaml", SWEEP)
    out = tmp_path / "o"
    p = run_patched(LINK_DURING_THE_RUN, spec, out)
    assert p.returncode == 4 and "summary.json: is a symbolic link" in p.stderr, p.stderr
    assert "free the space" not in p.stderr and "move it out of --out and run again with --resume" in p.stderr


# The sweep's own main, whose first write (the fingerprint) finds the disk full: no journal was written.
FULL_AT_THE_FIRST_WRITE = """
import errno, sys
import gimbalsim.sweep as sw
from gimbalsim._output import output_failed
def full(path, text, inputs=()):  # as the writer fails on a full disk: its errno kept
    cause = OSError(errno.ENOSPC, __import__('os').strerror(errno.ENOSPC))
    raise output_failed(f"{path}: could not be written: {cause.strerror}", cause)
sw.write_text = full
sys.exit(sw.main(sys.argv[1:]))
"""


def test_a_sweep_stopped_before_its_journal_says_nothing_was_kept(tmp_path):
    # (pass 53) it said "0 samples kept in o/results.partial.csv", a file that did not exist, and to --resume,
    # which had nothing to resume
    spec = spec_file(tmp_path / "s.yaml", SWEEP)
    out = tmp_path / "o"
    p = run_patched(FULL_AT_THE_FIRST_WRITE, spec, out)
    assert p.returncode == 4 and "No space left on device" in p.stderr, p.stderr
    assert f"nothing kept ({out / 'results.partial.csv'} was not written); free the space and run again" \
        in p.stderr and "--resume" not in p.stderr and "samples kept" not in p.stderr, p.stderr



FULL_AT_THE_INPUTS = FULL_AT_THE_FIRST_WRITE.replace("sw.write_text = full", """real = sw.write_text
sw.write_text = lambda path, text, inputs=(): (full if path.name == "inputs.json" else real)(path, text, inputs)""")


def test_a_sweep_whose_start_fails_takes_back_what_it_wrote(tmp_path):
    # (pass 66) "nothing kept", yet spec.json and spec.yaml stayed in the folder the run had made
    spec = spec_file(tmp_path / "s.yaml", SWEEP)
    out = tmp_path / "o"
    p = run_patched(FULL_AT_THE_INPUTS, spec, out)
    assert p.returncode == 4 and "inputs.json: could not be written" in p.stderr, p.stderr
    assert "nothing kept" in p.stderr and not out.exists(), sorted(os.listdir(out))
    # a folder the user made stays, emptied of what the run wrote
    out.mkdir()
    p = run_patched(FULL_AT_THE_INPUTS, spec, out)
    assert p.returncode == 4 and os.listdir(out) == [], sorted(os.listdir(out))


def test_an_out_folder_that_cannot_be_made_is_not_told_to_free_space(tmp_path):
    # (pass 58) /proc/sw cannot be made (no such file or directory): exit 4, and the advice was "free the space"
    spec = spec_file(tmp_path / "s.yaml", SWEEP)
    p = run("sweep", spec, "/proc/gimbalsim_sweep", "--workers", "1")
    assert p.returncode == 4 and "cannot make the folder /proc/gimbalsim_sweep: No such file or directory" \
        in p.stderr, p.stderr
    assert "free the space" not in p.stderr and "fix the cause and run again" in p.stderr, p.stderr

@pytest.mark.parametrize("args, said", [
    (["--replay", "0", "--resume"], "--replay runs one sample in this process: not with --resume "),
    (["--replay", "0", "--workers", "2", "--batch", "3"], "not with --batch, --workers (flags of a sweep)"),
    (["--plot", "x.png"], "--plot goes with --replay"),
    (["--until", "ape:track:0.2", "--max-samples", "99999999999999999999"], "must be in [1, 10000000]"),
])
def test_a_flag_that_would_be_ignored_is_refused(tmp_path, args, said):
    spec = spec_file(tmp_path / "s.yaml", SWEEP)
    p = run("sweep", spec, tmp_path / "out", *args)
    assert p.returncode == 2 and said in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert names(tmp_path) == ["s.yaml"]


@pytest.mark.parametrize("module,change,key", [
    ("sweep", ("set: {{sim.duration: 0.5}}",
               "set: {{sim.duration: 1.0e5, sim.step: 1.0e-4, sim.output_interval: 0.01}}"), "set.sim.duration"),
    ("tune", ("duration: 3.7", "duration: 1.0e5\nset: {{sim.step: 1.0e-4}}"), "duration")])
def test_a_closed_loop_too_long_for_memory_is_refused_at_its_line(module, change, key, tmp_path):
    # (pass 104) 1e5 s passed --check; every sample then ended in closed_loop's MemoryError (a traceback, exit 1),
    # leaving the study's first files (here 1e9 ticks of 0.1 ms: 450 GB, more than any machine of ours holds)
    text = (CLOSED if module == "sweep" else TUNE).replace(*change)
    spec = spec_file(tmp_path / "s.yaml", text + "controller_set: {{control.period: 1.0e-4}}\n"
                     if module == "tune" else text.replace("controller_set: {{", "controller_set: {{control.period: "
                                                                                  "1.0e-4, "))
    p = run(module, spec, tmp_path / "o", "--workers", "1")
    assert p.returncode == 2 and f"key '{key}'" in p.stderr and "every sample would be refused" in p.stderr, p.stderr
    assert "Traceback" not in p.stderr and not (tmp_path / "o").exists()
