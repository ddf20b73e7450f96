"""The sweep's journal (results.partial.csv): a resume killed at the worst
moment or refused space loses no row; it and the sweep's other files are
written by the one writer (no link planted beside them written through);
rows the design did not draw are dropped, counted and run again; Ctrl-C and
SIGTERM keep the journal, shut the cluster down quietly and say how to resume
(sweep and tune)."""
import csv
import json
import os
import resource
import signal
import subprocess
import sys
import time

import psutil
import pytest

from conftest import CONTROLLER_CONFIG, SCENES

N = 24
SPEC = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.1}}
samples: {N}
seed: 11
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
  friction.mu: {{uniform: [0.15, 0.35]}}
  initial.ecc: {{disk: {{within: contact.clearance, fraction: 0.9}}}}
"""


def sweep_cmd(spec, out, *args, workers=1):
    return [sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", str(out), "--no-progress",
            "--workers", str(workers), *args]


@pytest.fixture
def spec(tmp_path):
    (tmp_path / "spec.yaml").write_text(SPEC)
    return tmp_path / "spec.yaml"


def forged_journal(spec, out, rows, tail=b""):
    """A journal of `rows` samples whose parameters are the design's draws,
    whose provenance is what the draw applies (a resume checks it) and whose
    figures are marked (pointing_error_max = 100 + sample): a row that
    survives a resume is recognised in results.csv."""
    from gimbalsim._closed_sample import load_sample
    from gimbalsim._sample import row_values
    from gimbalsim.sweep import SweepSpec, csv_line

    s = SweepSpec(spec)
    out.mkdir()
    (out / "spec.json").write_text(s.fingerprint)
    header = s.header()
    lines = [csv_line(s.csv_header())]
    for i in rows:
        values = s.design.draw(i)
        r = dict(sample=i, status="ok", pointing_error_max=100.0 + i, pointing_error_final=1.0,
                 peak_contact_force=2.0, peak_joint2_force=3.0, impacts=4, continuous_contact_from=None,
                 impacts_joint1=0, impacts_joint2=4, max_tilt1=0.0, max_tilt2=0.0, wall_time=0.5,
                 **load_sample(s.base, None, values)[2])
        lines.append(csv_line(row_values(s, values, r)))
    (out / "results.partial.csv").write_bytes("".join(lines).encode() + tail)
    return s, header


def trusted_rows(path):
    """The journal's whole rows after its header, as text lines."""
    text = path.read_text()
    return [line for line in text.split("\n")[1:-1]]


def marked_samples(out):
    with open(out / "results.csv") as f:
        rows = list(csv.DictReader(f))
    assert [int(r["sample"]) for r in rows] == list(range(N))
    return {int(r["sample"]) for r in rows if float(r["pointing_error_max_rad"]) >= 100.0}


def killer(when):
    """A python -c prefix that SIGKILLs the sweep at a moment of its journal's life."""
    code = f"""
import builtins, os, signal, sys
WHEN = {when!r}
real_open, real_replace = builtins.open, os.replace
def die():
    os.kill(os.getpid(), signal.SIGKILL)
def open_(file, mode="r", *a, **k):
    f = real_open(file, mode, *a, **k)
    if "w" in mode and "results.partial.csv" in str(file) and WHEN == "journal opened for writing":
        die()
    return f
def replace_(a, b, **k):
    if "results.partial.csv" in str(b):
        if WHEN == "before the rename":
            die()
        real_replace(a, b, **k)
        if WHEN == "after the rename":
            die()
        return
    real_replace(a, b, **k)
builtins.open, os.replace = open_, replace_
import runpy
sys.argv[0] = "gimbalsim.sweep"
runpy.run_module("gimbalsim.sweep", run_name="__main__")
"""
    return ("-c", code)


@pytest.mark.parametrize("when", ["journal opened for writing", "before the rename", "after the rename"])
def test_a_resume_killed_while_it_rewrites_the_journal_loses_no_row(spec, tmp_path, when):
    out = tmp_path / "o"
    # a cut last line makes the resume rewrite the journal: the worst moment to die
    forged_journal(spec, out, range(18), tail=b"18,0.000")
    before = trusted_rows(out / "results.partial.csv")
    cmd = sweep_cmd(spec, out, "--resume")
    p = subprocess.run([sys.executable, *killer(when), *cmd[3:]], capture_output=True, text=True, timeout=300)
    assert p.returncode == -signal.SIGKILL, p.stderr
    assert trusted_rows(out / "results.partial.csv")[:18] == before  # every row still there, header too
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert marked_samples(out) == set(range(18))


def test_a_resume_refused_space_loses_no_row(spec, tmp_path):
    out = tmp_path / "o"
    forged_journal(spec, out, range(20), tail=b"20,0.0")
    before = (out / "results.partial.csv").read_bytes()
    limit = len(before) - 200  # the rewrite cannot fit: every write beyond it fails (EFBIG)
    p = subprocess.run(sweep_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=300,
                       preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit)))
    assert p.returncode == 4, p.stderr
    assert "Traceback" not in p.stderr and "--resume" in p.stderr.splitlines()[-1], p.stderr
    assert (out / "results.partial.csv").read_bytes() == before
    # a whole journal is appended to: refused space there keeps every row as well
    (out / "results.partial.csv").write_bytes(before[:before.rindex(b"\n") + 1])
    whole = (out / "results.partial.csv").read_bytes()
    limit = len(whole) + 10
    p = subprocess.run(sweep_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=300,
                       preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit)))
    assert p.returncode == 4, p.stderr
    assert (out / "results.partial.csv").read_bytes()[:len(whole)] == whole
    p = subprocess.run(sweep_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert marked_samples(out) == set(range(20))


def test_links_planted_at_temporary_names_are_not_written_through(spec, tmp_path):
    """Every file of the sweep goes through the one writer (_output.py): the
    old one opened "<name>.tmp" for writing, so a link planted there had the
    sweep write through it, then rename the link onto the name."""
    out = tmp_path / "o"
    out.mkdir()
    victim = tmp_path / "victim"
    victim.write_text("keep\n")
    names = ["spec.json", "spec.yaml", "inputs.json", "results.partial.csv", "results.csv", "summary.json"]
    for name in names:
        (out / f"{name}.tmp").symlink_to(victim)
    p = subprocess.run(sweep_cmd(spec, out), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert victim.read_text() == "keep\n"
    for name in ("spec.json", "spec.yaml", "inputs.json", "results.csv", "summary.json"):
        assert (out / name).is_file() and not (out / name).is_symlink(), name
    assert not any(n.startswith(".") for n in os.listdir(out)), "no temporary left"


def test_rows_the_design_did_not_draw_are_dropped_counted_and_run_again(spec, tmp_path):
    out = tmp_path / "o"
    s, header = forged_journal(spec, out, range(10))
    lines = (out / "results.partial.csv").read_text().split("\n")
    rows = list(csv.reader(lines[1:-1]))
    mu = header.index("friction.mu")
    outside = [str(N + 5)] + rows[0][1:]                  # a sample beyond the design
    rows[3][mu] = repr(float(rows[3][mu]) * 1.01)         # parameters that are not sample 3's draw
    rows[4][header.index("impacts")] = "lots"             # a figure that is no number
    text = lines[0] + "\n" + "".join(",".join(r) + "\n" for r in rows + [outside]) + "7,0.00"  # and a cut line
    (out / "results.partial.csv").write_text(text)
    p = subprocess.run(sweep_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    for why in ("1 journal row (sample index outside the design)",
                "1 journal row (friction_mu differs from the design's draw)",
                "1 journal row (status or figures unreadable)", "1 journal row (last line cut"):
        assert f"dropped {why}" in p.stderr, p.stderr
    # (pass 42) a row outside the design was said "their samples run again": nothing runs for it
    assert "(sample index outside the design) at " in p.stderr and \
        "line 12; not samples of this design: nothing runs for them" in p.stderr, p.stderr
    assert "8 already done, 16 to run" in p.stderr
    assert marked_samples(out) == set(range(10)) - {3, 4}
    column = dict(zip(s.header(), s.csv_header()))  # contact.clearance -> contact_clearance_m
    with open(out / "results.csv") as f:
        for r in csv.DictReader(f):
            drawn = s.design.row_values(s.design.draw(int(r["sample"])))
            assert [float(r[column[c]]) for c in s.design.columns()] == drawn
    dropped = json.loads((out / "summary.json").read_text())["journal_rows_dropped"]
    assert dropped == {"sample index outside the design": 1, "friction_mu differs from the design's draw": 1,
                       "status or figures unreadable": 1, "last line cut by an interruption": 1}


def test_a_value_edited_in_results_csv_is_dropped_naming_its_column_and_line(spec, tmp_path):
    """A finished sweep keeps no journal: --resume reads results.csv, and a
    row whose dispersed value was edited by hand is named by column and line."""
    out = tmp_path / "o"
    s, header = forged_journal(spec, out, range(N))
    (out / "results.partial.csv").rename(out / "results.csv")
    lines = (out / "results.csv").read_text().split("\n")
    row = lines[5].split(",")  # sample 4, line 6
    row[header.index("friction.mu")] = "0.2"
    lines[5] = ",".join(row)
    (out / "results.csv").write_text("\n".join(lines))
    p = subprocess.run(sweep_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert f"dropped 1 row (friction_mu differs from the design's draw) at {out / 'results.csv'} line 6;" \
        in p.stderr, p.stderr
    assert "23 already done, 1 to run" in p.stderr and marked_samples(out) == set(range(N)) - {4}
    dropped = json.loads((out / "summary.json").read_text())["journal_rows_dropped"]
    assert dropped == {"friction_mu differs from the design's draw": 1}


def journal_rows(out):
    try:
        return max(0, (out / "results.partial.csv").read_text().count("\n") - 1)
    except FileNotFoundError:
        return 0


def wait_for(cond, proc, timeout=300):
    t0 = time.time()
    while not cond():
        assert proc.poll() is None, "the program ended before the test could interrupt it"
        assert time.time() - t0 < timeout
        time.sleep(0.05)


def descendants(proc):
    return [c for c in psutil.Process(proc.pid).children(recursive=True)]


def all_gone(procs, timeout=60):
    gone, alive = psutil.wait_procs(procs, timeout=timeout)
    return not alive


@pytest.mark.parametrize("sig,group", [(signal.SIGINT, True), (signal.SIGTERM, False), (signal.SIGHUP, True)],
                         ids=["ctrl-c to the process group", "sigterm to the program", "hangup to the process group"])
def test_an_interrupted_sweep_says_one_line_and_keeps_its_journal(spec, tmp_path, sig, group):
    out = tmp_path / "o"
    proc = subprocess.Popen(sweep_cmd(spec, out, "--batch", "1", workers=2),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    wait_for(lambda: journal_rows(out) >= 3, proc)
    kids = descendants(proc)
    os.killpg(proc.pid, sig) if group else proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 2 and lines[0].startswith("sweep: 24 samples"), err
    kept = journal_rows(out)
    assert f"{kept} samples kept" in lines[1] and "--resume" in lines[1], err
    assert kept >= 3 and all_gone(kids)  # the cluster's processes were shut down
    p = subprocess.run(sweep_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0 and f"{kept} already done" in p.stderr, p.stderr


def test_a_signal_after_the_sweep_has_finished_is_no_silent_143(spec, tmp_path):
    # (pass 71) SIGTERM just after the last line: exit 143 and no word, every output written (the interpreter's
    # finalization had put the default action back). Now ignored there: exit 0, or, landing before, said.
    out, err_path = tmp_path / "o", tmp_path / "err.txt"
    with open(err_path, "w") as err:
        proc = subprocess.Popen(sweep_cmd(spec, out), stdout=subprocess.DEVNULL, stderr=err)
        deadline = time.time() + 300
        while " samples in " not in err_path.read_text() and proc.poll() is None and time.time() < deadline:
            time.sleep(0.001)
        time.sleep(0.01)  # into the interpreter's finalization, where the default action was back
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=60)
    text = err_path.read_text()
    assert "Traceback" not in text, text
    assert proc.returncode == 0 or (proc.returncode == 143 and "sweep: interrupted (SIGTERM)" in text), \
        (proc.returncode, text)
    assert len(list(csv.reader((out / "results.csv").open()))) == N + 1


def test_a_second_sweep_on_a_running_sweeps_folder_is_refused(spec, tmp_path):
    """Two sweeps on one folder would run samples twice into one journal and
    one of them die on the other's rename: the second is refused at once."""
    out = tmp_path / "o"
    first = subprocess.Popen(sweep_cmd(spec, out, "--batch", "1"), stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE, text=True)
    try:
        wait_for(lambda: journal_rows(out) >= 1, first)
        for args in (("--resume",), ()):
            p = subprocess.run(sweep_cmd(spec, out, *args), capture_output=True, text=True, timeout=120)
            assert p.returncode == 2, p.stderr
            assert "Traceback" not in p.stderr and (
                "another sweep, tuner or allocation is running in this folder" in p.stderr or "already holds a sweep" in p.stderr)
    finally:
        _, err = first.communicate(timeout=300)
    assert first.returncode == 0, err
    assert len(list(csv.reader((out / "results.csv").open()))) == N + 1  # the first sweep's rows, each once


TUNE = f"""
scene: {SCENES}/paper_clearance.yaml
controller: {CONTROLLER_CONFIG}
duration: 3.7
trials: 200
parallel_trials: 1
seed: 3
batch: 1
gains:
  azimuth.kp: {{loguniform: [5000, 80000]}}
"""


def test_a_tuner_on_a_folder_another_is_starting_in_is_told_so(tmp_path):
    # (pass 72) two tuners started together: the second found the first's study.db still empty and was told to
    # remove it ("holds no study ... remove it"), the running tuner's live file
    import fcntl
    (tmp_path / "t.yaml").write_text(TUNE)
    out = tmp_path / "o"
    out.mkdir()
    (out / "study.db").write_bytes(b"")  # as the first tuner has just made it
    fd = os.open(out, os.O_RDONLY | os.O_DIRECTORY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # the first tuner's hold on the folder
        p = subprocess.run([sys.executable, "-m", "gimbalsim.tune", str(tmp_path / "t.yaml"), "--out", str(out),
                            "--no-progress", "--workers", "1"], capture_output=True, text=True, timeout=120)
    finally:
        os.close(fd)
    assert p.returncode == 2 and "another sweep, tuner or allocation is running in this folder" in p.stderr, p.stderr
    assert "remove it" not in p.stderr and (out / "study.db").exists()


def test_a_signal_inside_a_librarys_cleanup_is_not_logged_again(capsys):
    """The race CI met: SIGINT landed in SQLAlchemy's connection reset (a
    finalizer), which logs the exception with its traceback through the
    last-resort handler before passing it on; the console keeps the
    program's one line, and other errors still show."""
    import logging
    from gimbalsim import _cluster
    old = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    try:
        _cluster.raise_on_signals()
    finally:
        signal.signal(signal.SIGINT, old[0])
        signal.signal(signal.SIGTERM, old[1])

    def record(exc):
        try:
            raise exc
        except BaseException:
            return logging.LogRecord("sqlalchemy.pool.impl.QueuePool", logging.ERROR, __file__, 1,
                                     "Exception during reset or similar", None, sys.exc_info())
    logging.lastResort.handle(record(_cluster.Interrupted(signal.SIGINT)))
    assert capsys.readouterr().err == ""
    logging.lastResort.handle(record(ValueError("a real error")))
    assert "a real error" in capsys.readouterr().err


def test_a_signal_swallowed_by_a_finalizer_still_interrupts(capsys):
    """The race CI met next: SIGTERM landed inside SQLAlchemy's session
    cleanup (a finalizer), where Python prints the exception and drops it,
    and the tune ran on to exit 0. The signal is kept: the loops raise it
    again, and nothing is printed."""
    from gimbalsim import _cluster
    old = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM), sys.unraisablehook

    class SignalledWhileFinalized:
        def __del__(self):
            os.kill(os.getpid(), signal.SIGTERM)
            for _ in range(100000):  # the handler runs at a bytecode boundary, in here
                pass

    try:
        _cluster.raise_on_signals()
        SignalledWhileFinalized()  # finalized at once: its Interrupted is dropped by Python
        assert capsys.readouterr().err == ""
        with pytest.raises(_cluster.Interrupted) as e:
            _cluster.raise_if_interrupted()
        assert e.value.signum == signal.SIGTERM
    finally:
        signal.signal(signal.SIGINT, old[0])
        signal.signal(signal.SIGTERM, old[1])
        sys.unraisablehook = old[2]
        _cluster._received.clear()


@pytest.mark.parametrize("sig,group", [(signal.SIGINT, True), (signal.SIGTERM, False)],
                         ids=["ctrl-c to the process group", "sigterm to the program"])
def test_an_interrupted_tune_says_one_line_and_keeps_its_trials(tmp_path, sig, group):
    (tmp_path / "t.yaml").write_text(TUNE)
    out = tmp_path / "o"
    proc = subprocess.Popen([sys.executable, "-m", "gimbalsim.tune", str(tmp_path / "t.yaml"), "--out", str(out),
                             "--no-progress", "--workers", "2"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, start_new_session=True)
    wait_for(lambda: (out / "trials.csv").exists(), proc)
    kids = descendants(proc)
    os.killpg(proc.pid, sig) if group else proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, err
    # past the start's stepping line (sampling: auto changes this scene's, _sampling.py), one line
    lines = [line for line in err.splitlines() if line.strip() and not line.startswith("tune: stepping")]
    assert len(lines) == 1 and "trials kept in" in lines[0], err
    kept = int(lines[0].split("): ")[1].split()[0])
    with open(out / "trials.csv") as f:
        assert kept >= 1 and len(list(csv.DictReader(f))) == kept
    assert all_gone(kids)


def test_a_sample_journaled_twice_differently_keeps_neither_row(spec, tmp_path):
    # (pass 34) the first of two differing rows stayed (here an edited one) and the second was dropped, while the
    # resume said "their samples run again": neither is trusted now, and the sample is run again
    out = tmp_path / "o"
    s, header = forged_journal(spec, out, range(N))
    lines = (out / "results.partial.csv").read_text().split("\n")
    edited = lines[5].split(",")  # sample 4, line 6
    edited[header.index("pointing_error_max")] = "250"
    lines.insert(7, ",".join(edited))  # a second, different row of sample 4 at line 8
    (out / "results.partial.csv").write_text("\n".join(lines))
    p = subprocess.run(sweep_cmd(spec, out, "--resume"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "dropped 2 journal rows (sample journaled twice, differently)" in p.stderr and "lines 6, 8" in p.stderr, \
        p.stderr
    assert "23 already done, 1 to run" in p.stderr and marked_samples(out) == set(range(N)) - {4}


def test_check_makes_the_refusal_of_a_folder_another_run_holds(spec, tmp_path):
    # (pass 87) --check --resume said nothing (exit 0) while the run itself refused the held folder
    import fcntl
    out = tmp_path / "o"
    out.mkdir()
    fd = os.open(out, os.O_RDONLY | os.O_DIRECTORY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # another run's hold on the folder
        p = subprocess.run(sweep_cmd(spec, out, "--check", "--resume"), capture_output=True, text=True, timeout=120)
    finally:
        os.close(fd)
    assert p.returncode == 2 and "another sweep, tuner or allocation is running in this folder" in p.stderr, p.stderr
    assert list(out.iterdir()) == []
