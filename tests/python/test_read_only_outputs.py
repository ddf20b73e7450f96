"""The exit-code table (docs/usage.md "Exit codes"; issue 41, class 10) for
every program's outputs: a folder that takes no file (read-only) is "an
output could not be written", 4, before anything runs; a path no output may
take (a symbolic link) is a refused argument, 2. Both say the flag."""
import os
import resource
import subprocess

import pytest

from conftest import BIN, SCENES, SOURCE

IDEAL = str(SCENES / "paper_ideal.yaml")
CLEARANCE = str(SCENES / "paper_clearance.yaml")

# program, its arguments around the output (OUT), the flag its message names
CASES = {
    "simulate": (["gimbalsim", "simulate", IDEAL, "--out", "OUT"], "OUT"),
    "firmware_truth": (["firmware_sim", IDEAL, "--lcm-url", "memq://", "--duration", "0.01",
                        "--truth-csv", "OUT"], "--truth-csv"),
    "firmware_ticks": (["firmware_sim", IDEAL, "--lcm-url", "memq://", "--duration", "0.01",
                        "--tick-log", "OUT"], "--tick-log"),
    "controller_floor": (["gimbalsim_controller_floor", "--duration", "2.6", "--clearances", "2.5e-4",
                          "--ideal-scene", IDEAL, "--clearance-scene", CLEARANCE, "--markdown", "OUT"],
                         "--markdown"),
    "record": (["gimbalsim_record", "OUT", "--lcm-url", "memq://", "--duration", "0.1"], "OUT"),
    "pointing_study": (["gimbalsim_pointing_study", "--duration", "0.01", "--clearances", "5e-4",
                        "--ideal-scene", IDEAL, "--clearance-scene", CLEARANCE, "--out", "OUTDIR"], "config.txt"),
    "workprec": (["gimbalsim_workprec", "--quick", "--no-mujoco", "--scenes", "paper_ideal",
                  "--scenes-dir", str(SCENES), "--policies", str(SOURCE / "tools" / "workprec" / "policies.yaml"),
                  "--policy", "plain", "--out", "OUTDIR"], "workprec.csv"),
}


def command(case, folder):
    args, _ = CASES[case]
    out = str(folder / "result.out")
    cmd = [str(BIN / args[0])] + [out if a == "OUT" else str(folder) if a == "OUTDIR" else a for a in args[1:]]
    return cmd, out


def run_in_read_only(folder, cmd):
    """cmd with folder read-only: a read-only bind mount for root (who writes through modes), else mode 0555."""
    if os.geteuid() == 0:
        if subprocess.run(["unshare", "-m", "true"], capture_output=True).returncode != 0:
            pytest.fail("root without `unshare -m`: no way to make a folder read-only here")
        wrapped = ["unshare", "-m", "sh", "-c", 'mount --bind -o ro "$0" "$0" && exec "$@"', str(folder), *cmd]
        return subprocess.run(wrapped, capture_output=True, text=True, timeout=120)
    os.chmod(folder, 0o555)
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    finally:
        os.chmod(folder, 0o755)


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_read_only_folder_is_an_output_that_cannot_be_written(tmp_path, case):
    folder = tmp_path / "ro"
    folder.mkdir()
    cmd, out = command(case, folder)
    p = run_in_read_only(folder, cmd)
    assert p.returncode == 4, (p.returncode, p.stderr)
    assert "error:" in p.stderr, p.stderr
    assert "Read-only file system" in p.stderr or "Permission denied" in p.stderr, p.stderr
    assert "cannot be written" in p.stderr, p.stderr
    assert os.listdir(folder) == []
    # nothing ran: no run's figures on stdout, no reference computed
    assert "reference:" not in p.stdout and "ideal " not in p.stdout, p.stdout


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_link_under_the_outputs_name_is_refused(tmp_path, case):
    folder = tmp_path / "out"
    folder.mkdir()
    cmd, out = command(case, folder)
    if "OUTDIR" in CASES[case][0]:  # a folder's program: a link under one of its files' names
        out = str(folder / CASES[case][1])
    os.symlink(tmp_path / "elsewhere", out)
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert "symbolic link" in p.stderr and CASES[case][1].replace("OUT", out) in p.stderr, p.stderr
    assert not (tmp_path / "elsewhere").exists()


@pytest.mark.parametrize("case", ["simulate", "firmware_truth", "firmware_ticks"])
def test_a_file_size_limit_is_an_output_that_cannot_be_written(tmp_path, case):
    # ulimit -f: SIGXFSZ had killed the program (exit 153) and left its temporaries behind
    cmd, out = command(case, tmp_path)
    cmd = [("1" if a == "0.01" else a) for a in cmd]  # a run whose output passes the limit

    def small_files():
        resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))

    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120, preexec_fn=small_files)
    assert p.returncode == 4, (p.returncode, p.stderr)
    assert "File too large" in p.stderr, p.stderr
    assert os.listdir(tmp_path) == [], os.listdir(tmp_path)
