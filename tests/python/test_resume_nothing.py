"""A --resume names a study to finish: into a folder that does not exist, a sweep and an allocation are
refused (exit 2) and make nothing, as tune's is (pass 49: both started afresh and ran the whole study)."""
import subprocess
import sys

from test_allocate import ALLOCATE, BASE, write_spec


def test_a_sweep_resumed_into_a_missing_folder_runs_nothing(tmp_path):
    noisy = BASE.replace("{sim.duration: 0.3}", "{sim.duration: 0.3, sensors.star_tracker_noise: 1.0e-4}")
    spec = write_spec(tmp_path, noisy)
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", str(tmp_path / "new"),
                        "--workers", "1", "--no-progress", "--resume"], capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "new: no such folder: no sweep to resume; run without --resume" in p.stderr, p.stderr
    assert not (tmp_path / "new").exists()


def test_an_allocation_resumed_into_a_missing_folder_runs_nothing(tmp_path):
    spec = write_spec(tmp_path, BASE + ALLOCATE.format(requirement=1e-4, values=3))
    p = subprocess.run([sys.executable, "-m", "gimbalsim.allocate", str(spec), "--out", str(tmp_path / "new"),
                        "--workers", "1", "--no-progress", "--resume"], capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "new: no such folder: no allocation to resume" in p.stderr, p.stderr
    assert not (tmp_path / "new").exists()
