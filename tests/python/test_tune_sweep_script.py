"""tools/tune_sweep.py (the gain sweep over LCM): a --duration that ends before
the track, where every figure but the torques is measured, is refused before
any run (exit 2 naming --duration), as controller_sweep refuses it."""
import subprocess
import sys

from conftest import BIN, CONTROLLER_CONFIG, SOURCE


def test_a_duration_that_ends_before_the_track_is_refused():
    p = subprocess.run([sys.executable, str(SOURCE / "tools" / "tune_sweep.py"), "--bin", str(BIN), "--config",
                        str(CONTROLLER_CONFIG), "--omega", "20", "--duration", "2"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2, (p.stdout, p.stderr)
    assert "--duration: track window [3.5, inf) s not reached: run ended at 2 s" in p.stderr, p.stderr
    assert "gain set" not in p.stdout  # no table: nothing ran
