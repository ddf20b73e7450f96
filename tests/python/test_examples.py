"""The README's Python examples (python/examples/) run and say what they claim."""
import os
import subprocess
import sys

from conftest import SOURCE


def run_example(name, *args, cwd):
    p = subprocess.run([sys.executable, str(SOURCE / "python" / "examples" / name), *args], cwd=cwd,
                       capture_output=True, text=True, timeout=300, env=dict(os.environ))
    assert p.returncode == 0, p.stderr
    return p.stdout


def test_paper_scene_writes_its_plot(tmp):
    out = run_example("paper_scene.py", "--duration", "0.2", "--out", str(tmp / "p.png"), cwd=tmp)
    assert (tmp / "p.png").stat().st_size > 10_000
    assert "paper_clearance: floating_ideal_planar_friction" in out


def test_python_controller_reaches_its_target(tmp):
    out = run_example("python_controller.py", cwd=tmp)
    final = float(out.split("rad after")[0].split()[-1])
    assert final < 1e-3


def test_checkpoint_replay_is_bit_for_bit(tmp):
    assert "replay identical bit for bit: True" in run_example("checkpoint_replay.py", cwd=tmp)
