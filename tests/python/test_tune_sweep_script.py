"""tools/hil/tune_sweep.py (the gain sweep over LCM): a --duration that ends before
the track, where every figure but the torques is measured, is refused before
any run (exit 2 naming --duration), as controller_sweep refuses it; the
documented commands run over LCM, both programs reading the one file."""
import subprocess
import sys

import pytest
from conftest import BIN, CONTROLLER_CONFIG, SOURCE


def test_a_duration_that_ends_before_the_track_is_refused():
    p = subprocess.run([sys.executable, str(SOURCE / "tools" / "hil" / "tune_sweep.py"), "--bin", str(BIN), "--config",
                        str(CONTROLLER_CONFIG), "--omega", "20", "--duration", "2"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert "--duration: track window [3.5, inf) s not reached: run ended at 2 s" in p.stderr, p.stderr
    assert "gain set" not in p.stdout  # no table: nothing ran


def _netns_available():
    return subprocess.run(["unshare", "-n", "true"], capture_output=True).returncode == 0


@pytest.mark.skipif(not _netns_available(), reason="needs a private network namespace (unshare -n: root)")
def test_documented_gain_set_runs_over_lcm(tmp):
    # docs/bench.md "Gain sweep", as written (shorter: one omega and one gain set):
    # firmware_sim --profile reads the file the script writes from --print-config.
    p = subprocess.run([sys.executable, str(SOURCE / "tools" / "hil" / "tune_sweep.py"), "--bin", str(BIN), "--omega", "20",
                        "--gain-set", "azimuth.kd=0,elevation.kd=0", "--keep", str(tmp / "sweep")],
                       capture_output=True, text=True, timeout=300, cwd=SOURCE)
    assert p.returncode == 0, (p.stdout, p.stderr)
    rows = [l for l in p.stdout.splitlines() if l.startswith(("omega=20", "azimuth.kd=0"))]
    assert len(rows) == 2, p.stdout
    assert "run failed" not in p.stdout
    rms = [float(r.split()[2]) for r in rows]  # rms_truth [rad]
    assert all(0.0 < x < 1.0 for x in rms), rows


@pytest.mark.skipif(not _netns_available(), reason="needs a private network namespace (unshare -n: root)")
def test_lockstep_and_in_process_measure_the_joint_error_alike():
    # Both modes' max_e_trk is the reference against the true angles: lockstep read the controller's
    # error against the encoder (6.4e-6 rad against 3.5e-6 in process for omega 20).
    def max_e_trk(*mode):
        p = subprocess.run([sys.executable, str(SOURCE / "tools" / "hil" / "tune_sweep.py"), "--bin", str(BIN),
                            "--omega", "20", "--duration", "4", *mode], capture_output=True, text=True, timeout=300)
        assert p.returncode == 0, (p.stdout, p.stderr)
        lines = p.stdout.splitlines()
        h = next(i for i, l in enumerate(lines) if "max_e_trk" in l)  # each mode's own table: a header, a row
        col = lines[h].split().index("max_e_trk") - lines[h].startswith("gain set")  # two words, one cell
        return float(lines[h + 1].split()[col])
    lockstep, in_process = max_e_trk(), max_e_trk("--in-process")
    assert lockstep == pytest.approx(in_process, rel=1e-3), (lockstep, in_process)  # gains printed %.6g vs %.17g


@pytest.mark.parametrize("mode,program", [(["--in-process"], "controller_sweep"), ([], "firmware_sim")])
def test_a_program_not_built_is_named_with_its_build_command(tmp, mode, program):
    # docs/bench.md: --in-process runs controller_sweep, which the README's commands do not build.
    p = subprocess.run([sys.executable, str(SOURCE / "tools" / "hil" / "tune_sweep.py"), "--bin", str(tmp), "--omega",
                        "20", *mode], capture_output=True, text=True, timeout=60)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert f"cmake --build build -j2 --target {program}" in p.stderr and "Traceback" not in p.stderr, p.stderr


@pytest.mark.skipif(not _netns_available(), reason="needs a private network namespace (unshare -n: root)")
@pytest.mark.parametrize("mode", [[], ["--in-process"]])
def test_a_plant_stop_is_a_stopped_row_and_exit_3_in_both_modes(mode):
    # the lockstep mode reported "run failed: firmware_sim exit 3" and exit 1 (pass 56); in process: a row, 3
    p = subprocess.run([sys.executable, str(SOURCE / "tools" / "hil" / "tune_sweep.py"), "--bin", str(BIN), "--omega",
                        "20", "--duration", "3.6", "--scene-set", "sim.velocity_limit=0.001", *mode],
                       capture_output=True, text=True, timeout=300, cwd=SOURCE)
    assert p.returncode == 3, (p.stdout, p.stderr)
    assert "stopped: " in p.stdout and "run failed" not in p.stdout, p.stdout
    assert "sim.velocity_limit" in p.stdout, p.stdout


@pytest.mark.skipif(not _netns_available(), reason="needs a private network namespace (unshare -n: root)")
def test_no_settling_is_na_with_its_reason_as_in_process():
    # a band no run settles in: lockstep printed inf (pass 56), controller_sweep n/a with the reason
    def settle_cell(*mode):
        p = subprocess.run([sys.executable, str(SOURCE / "tools" / "hil" / "tune_sweep.py"), "--bin", str(BIN),
                            "--omega", "20", "--duration", "3.6", "--settle-tol", "1e-9", *mode],
                           capture_output=True, text=True, timeout=300, cwd=SOURCE)
        assert p.returncode == 0, (p.stdout, p.stderr)
        return p.stdout
    for out in (settle_cell(), settle_cell("--in-process")):
        assert "n/a" in out and "the joint error did not stay below settle_tol 1e-09 rad before tracking started at " \
            "3.5 s" in out, out
        assert " inf " not in out, out


@pytest.mark.skipif(not _netns_available(), reason="needs a private network namespace (unshare -n: root)")
def test_commands_rejected_in_a_row_are_a_stopped_row_naming_why():
    # the bench ends a run whose every answer the plant rejects (torque.limit 1 N m: the slew's commands are
    # beyond 10 x it); the row says that, not "the plant stopped"
    p = subprocess.run([sys.executable, str(SOURCE / "tools" / "hil" / "tune_sweep.py"), "--bin", str(BIN), "--omega",
                        "20", "--duration", "3.6", "--scene-set", "torque.limit=[1,1]"],
                       capture_output=True, text=True, timeout=300, cwd=SOURCE)
    assert p.returncode == 3, (p.stdout, p.stderr)
    assert "stopped: lockstep: no valid command answered the last 10 statuses" in p.stdout, p.stdout
