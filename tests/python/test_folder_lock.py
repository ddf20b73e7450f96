"""One writer per output folder (issue 41, class 7): the pointing study holds the same lock on its --out as
the Python sweeps and tuner (flock on the folder itself); a second writer is refused before it runs (pass 45:
two studies into one --out both exited 0, the folder holding whichever wrote last)."""
import fcntl
import os
import subprocess

from conftest import BIN, SCENES


def test_a_study_into_a_folder_another_run_holds_is_refused(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    cmd = [str(BIN / "gimbalsim_pointing_study"), "--duration", "0.01", "--clearances", "5e-4",
           "--ideal-scene", str(SCENES / "paper_ideal.yaml"), "--clearance-scene", str(SCENES / "paper_clearance.yaml"),
           "--out", str(out)]
    fd = os.open(out, os.O_RDONLY | os.O_DIRECTORY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # as a running sweep, tuner or study holds it
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    finally:
        os.close(fd)
    assert p.returncode == 2 and "--out: another run is writing this folder" in p.stderr, p.stderr
    assert not list(out.iterdir()), "nothing written"
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)  # the holder gone: it runs
    assert p.returncode == 0 and (out / "summary.csv").is_file(), p.stderr
