"""tools/hil/tune_sweep.py's flags and --keep folder, as docs/usage.md
promises for every program: a number is a plain decimal within the flag's
range (nan, -1, 0 never mean "the default", which only an absent flag gives;
' 5' and hex are refused), and --keep writes nothing through a symbolic link,
over an input or into a folder the user named that does not exist: each is
refused (exit 2, naming it) before any run, and nothing is written."""
import os
import subprocess
import sys

import pytest
from conftest import BIN, CONTROLLER_CONFIG, SCENES, SOURCE

SCRIPT = SOURCE / "tools" / "hil" / "tune_sweep.py"


def sweep(*args, cwd=None):
    config = [] if "--config" in args else ["--config", str(CONTROLLER_CONFIG)]  # given once (pass 78)
    return subprocess.run([sys.executable, str(SCRIPT), "--bin", str(BIN), *config,
                           "--scene", str(SCENES / "paper_ideal.yaml"), *args], capture_output=True, text=True,
                          timeout=120, cwd=cwd)


@pytest.mark.parametrize("mode", [["--in-process"], []])
@pytest.mark.parametrize("flag,value,why", [
    ("--duration", "nan", "'nan' is not a finite decimal number"),
    ("--duration", "-1", "must be in (0, 1e+09], got -1"),
    ("--duration", "0", "must be in (0, 1e+09], got 0"),
    ("--duration", "-0", "must be in (0, 1e+09], got -0"),
    ("--duration", " 5", "' 5' is not a finite decimal number"),
    ("--duration", "inf", "'inf' is not a finite decimal number"),
    ("--duration", "0x10", "'0x10' is not a finite decimal number"),
    ("--duration", "", "an empty value"),
    # (pass 55) read as controller_sweep reads it: 010 ran 10 s here, 04.0 ran 4 s
    ("--duration", "010", "'010' is not a number written without a leading zero"),
    ("--duration", "04.0", "'04.0' is not a number written without a leading zero"),
    ("--settle-tol", "01", "'01' is not a number written without a leading zero"),
    ("--omega", "5,,10", "an empty list item in '5,,10'"),
    ("--omega", "0", "must be in [0.001, 1e+06], got 0"),
    ("--omega", "nan", "'nan' is not a finite decimal number"),
    ("--omega", " 20", "' 20' is not a finite decimal number"),
    ("--settle-tol", "0", "must be in (0, 10], got 0"),
    ("--settle-tol", "nan", "'nan' is not a finite decimal number"),
])
def test_a_flag_number_outside_the_rule_is_refused_naming_the_flag(mode, flag, value, why):
    args = [flag, value] if flag == "--omega" else ["--omega", "20", flag, value]
    p = sweep(*mode, *args)
    assert p.returncode == 2, (p.stdout, p.stderr)
    # an empty value is refused by the parser itself, as every tools/ script's (pass 78: output_file.standard_flags)
    program = "tune_sweep.py" if value == "" else "tune_sweep"
    assert f"{program}: error: {flag}: {why}" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert p.stdout == ""  # nothing ran: no table


def victim_behind_a_link(tmp):
    (tmp / "victim.txt").write_text("victim\n")
    (tmp / "kp" / "omega_20").mkdir(parents=True)
    (tmp / "kp" / "omega_20" / "firmware.log").symlink_to("../../victim.txt")


def test_keep_refuses_a_link_under_a_runs_file_and_writes_nothing(tmp):
    victim_behind_a_link(tmp)
    p = sweep("--omega", "20", "--duration", "3.6", "--keep", str(tmp / "kp"))
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert "omega_20/firmware.log: is a symbolic link; not written through" in p.stderr, p.stderr
    assert (tmp / "victim.txt").read_text() == "victim\n"
    assert os.listdir(tmp / "kp" / "omega_20") == ["firmware.log"] and "gain set" not in p.stdout


@pytest.mark.parametrize("case,message", [
    ("missing parent", "--keep nodir/deeper: no such folder nodir (create it first)"),
    ("keep is a link", "--keep: linked: is a symbolic link; not written through"),
    ("set folder is a file", "--keep: kp/omega_20: exists and is not a folder"),
    ("an input under a name", "kp/omega_20/controller.yaml: the same file as the input"),
    ("two sets, one folder", "--keep: gain sets 'omega=20' and 'omega=20' would keep their runs in one folder"),
])
def test_keep_is_refused_before_any_run(tmp, case, message):
    keep, omega, extra = "kp", "20", []
    if case == "missing parent":
        keep = "nodir/deeper"
    elif case == "keep is a link":
        (tmp / "elsewhere").mkdir()
        (tmp / "linked").symlink_to("elsewhere")
        keep = "linked"
    elif case == "set folder is a file":
        (tmp / "kp").mkdir()
        (tmp / "kp" / "omega_20").write_text("mine\n")
    elif case == "an input under a name":
        (tmp / "kp" / "omega_20").mkdir(parents=True)
        (tmp / "mine.yaml").write_text(CONTROLLER_CONFIG.read_text())
        os.link(tmp / "mine.yaml", tmp / "kp" / "omega_20" / "controller.yaml")  # the configuration, hard linked
        extra = ["--config", "mine.yaml"]
    else:
        omega = "20,20"
    before = sorted(str(p.relative_to(tmp)) for p in tmp.rglob("*"))
    p = sweep("--omega", omega, "--duration", "3.6", "--keep", keep, *extra, cwd=tmp)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert f"tune_sweep: error: {message}" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert sorted(str(p.relative_to(tmp)) for p in tmp.rglob("*")) == before  # nothing made, nothing written


def test_keep_needs_the_lockstep_mode(tmp):
    p = sweep("--in-process", "--omega", "20", "--keep", str(tmp / "kp"))
    assert p.returncode == 2 and "tune_sweep: error: --keep needs the lockstep mode" in p.stderr, p.stderr
    assert not (tmp / "kp").exists()


def _netns_available():
    return subprocess.run(["unshare", "-n", "true"], capture_output=True).returncode == 0


@pytest.mark.skipif(not _netns_available(), reason="needs a private network namespace (unshare -n: root)")
def test_keep_is_made_in_a_folder_that_exists_and_holds_whole_files(tmp):
    # Run twice into the same --keep: each file replaced whole (renamed onto its name), the logs real files.
    for _ in range(2):
        p = sweep("--omega", "20", "--duration", "3.6", "--keep", "kp", cwd=tmp)
        assert p.returncode == 0, (p.stdout, p.stderr)
    run = tmp / "kp" / "omega_20"
    assert sorted(os.listdir(run)) == ["controller.csv", "controller.log", "controller.yaml", "firmware.log",
                                       "truth.csv"]
    assert all(not (run / n).is_symlink() and (run / n).stat().st_size > 0 for n in os.listdir(run))
    assert "firmware_sim: scene 'paper_ideal'" in (run / "firmware.log").read_text()
    assert "pointing_controller: answered 3600 statuses" in (run / "controller.log").read_text()


@pytest.mark.parametrize("keep", ["/proc/gimbalsim_keep", "/proc/self/gimbalsim_keep"])
def test_a_keep_folder_that_cannot_be_made_is_an_output_failure_in_one_line(keep):
    # pass 58: os.mkdir's FileNotFoundError ended the script in a traceback, exit 1 (the table: 4, one line)
    p = sweep("--omega", "20", "--duration", "3.6", "--keep", keep)
    assert p.returncode == 4, (p.returncode, p.stderr)
    assert p.stderr.startswith(f"tune_sweep: error: --keep: cannot make the folder {keep}: ") and \
        "Traceback" not in p.stderr and p.stderr.count("\n") == 1, p.stderr
