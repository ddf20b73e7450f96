"""Pass 62's findings from Python: a scene's text that is not printable UTF-8
is a refusal at its line (a traceback, exit 1, from the sweep; a NUL cut the
name short), and Simulator.run refuses more rows than memory can hold before
copying them (a 16-byte broadcast view of 1e9 rows grew the interpreter
until the kernel killed it)."""
import os
import subprocess
import sys

import numpy as np
import pytest

import gimbalsim
from conftest import SCENES


def scene_with_name(tmp_path, name_bytes):
    text = (SCENES / "paper_clearance.yaml").read_bytes()
    lines = [b"name: " + name_bytes if line.startswith(b"name:") else line for line in text.split(b"\n")]
    path = tmp_path / "scene.yaml"
    path.write_bytes(b"\n".join(lines))
    return path, 1 + next(i for i, line in enumerate(lines) if line.startswith(b"name:"))


@pytest.mark.parametrize("name, said", [(b"caf\xe9", "byte 0xe9 is not UTF-8 text"),
                                        (b"a\x00b", "character U+0000 (a control character) is not YAML text")])
def test_a_scene_that_is_not_printable_utf8_is_refused_at_its_line(tmp_path, name, said):
    scene, line = scene_with_name(tmp_path, name)
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.load_scene(str(scene))
    assert e.value.problems[0]["line"] == line and said in str(e.value), str(e.value)
    spec = tmp_path / "spec.yaml"
    spec.write_text(f"scene: {scene}\nset: {{sim.duration: 0.01}}\nsamples: 2\nseed: 1\n"
                    "parameters:\n  friction.mu: {uniform: [0.1, 0.3]}\n")
    for flags in (["--check"], ["--workers", "1", "--no-progress"]):
        p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", str(tmp_path / "o"), *flags],
                           capture_output=True, text=True, timeout=120)
        assert p.returncode == 2 and f"{scene}:{line}:" in p.stderr and said in p.stderr, (flags, p.stderr)
        assert "Traceback" not in p.stderr and not (tmp_path / "o").exists(), p.stderr


def test_run_refuses_more_rows_than_memory_holds_before_copying_them():
    sim = gimbalsim.Simulator(gimbalsim.load_scene(str(SCENES / "paper_clearance.yaml")))
    # twice what the machine's whole memory holds (never free, however the free memory moves meanwhile)
    memory = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    rows = 2 * memory // (8 * (2 + len(gimbalsim.COLUMNS)))
    with pytest.raises(MemoryError, match=f"torques \\[N m\\]: {rows} rows need .* GB .*run them in parts"):
        sim.run(np.broadcast_to(np.zeros(2), (rows, 2)))
    assert sim.t == 0.0
    assert sim.run(np.zeros((3, 2))).shape == (3, len(gimbalsim.COLUMNS))  # in parts, it goes on


@pytest.mark.parametrize("module, flags", [("sweep", ["--check"]), ("allocate", ["--check"]), ("tune", [])])
def test_a_spec_with_a_control_character_is_refused_at_its_line_in_one_line(tmp_path, module, flags):
    # PyYAML's refusal named an offset in "<unicode string>", on two lines (pass 63)
    spec = tmp_path / "spec.yaml"
    spec.write_bytes(b"scene: x.yaml\nsamples: 2\n#\x00x\nseed: 7\n")
    p = subprocess.run([sys.executable, "-m", f"gimbalsim.{module}", str(spec), "--out", str(tmp_path / "o"), *flags],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and p.stderr == f"{module}: error: {spec}:3:2: character U+0000 (a control character) " \
        "is not YAML text\n", p.stderr
    assert not (tmp_path / "o").exists()
