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


def test_package_folder_without_its_extension_says_how_to_build_it(tmp):
    # What run_paper.sh leaves in build/python/ (the programs built, not the
    # extension): an import must fail naming the build command, not import an
    # empty namespace package that fails later on its first attribute.
    pkg = tmp / "gimbalsim"
    pkg.mkdir()
    for f in (SOURCE / "python" / "gimbalsim").glob("*.py"):
        (pkg / f.name).write_bytes(f.read_bytes())
    env = dict(os.environ, PYTHONPATH=str(tmp))
    p = subprocess.run([sys.executable, "-c", "import gimbalsim"], cwd=tmp, capture_output=True, text=True,
                       timeout=60, env=env)
    assert p.returncode != 0
    assert "extension module _gimbalsim is not built" in p.stderr
    assert "--target gimbalsim_python" in p.stderr


def test_readme_python_example_runs_as_written(tmp):
    # The README's Python block, run from the checkout as its text says.
    readme = (SOURCE / "README.md").read_text()
    block = readme.split("```python\n", 1)[1].split("```", 1)[0]
    p = subprocess.run([sys.executable, "-c", block], cwd=SOURCE, capture_output=True, text=True, timeout=300,
                       env=dict(os.environ))
    assert p.returncode == 0, p.stderr
    lines = p.stdout.split()
    assert float(lines[0]) > 0.0  # the journal's largest eccentricity [m]
    assert float(lines[-1]) < 1e-3  # the tracking error [rad]
