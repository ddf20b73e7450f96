"""Passes 62 and 63 from Python: text that is not printable UTF-8 is a
refusal at its line, in a scene (a traceback, exit 1, from the sweep; a NUL
cut the name short) or a spec (PyYAML's offset, on two lines), and no row a
sweep trusts (a resume kept one, written back with replacement characters);
Simulator.run refuses more rows than memory can hold before copying them (a
16-byte broadcast view of 1e9 rows grew the interpreter until the kernel
killed it)."""
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


def test_a_row_that_is_not_utf8_is_no_row_the_sweep_wrote(tmp_path):
    spec = tmp_path / "spec.yaml"
    spec.write_text(f"scene: {SCENES / 'paper_clearance.yaml'}\nset: {{sim.duration: 0.01}}\nsamples: 3\nseed: 1\n"
                    "parameters:\n  friction.mu: {uniform: [0.1, 0.3]}\n")
    out = tmp_path / "o"
    sweep = [sys.executable, "-m", "gimbalsim.sweep"]
    assert subprocess.run(sweep + [str(spec), "--out", str(out), "--workers", "1", "--no-progress"],
                          capture_output=True, timeout=300).returncode == 0
    results = out / "results.csv"
    lines = results.read_bytes().split(b"\n")
    lines[1] += b"\xe9"  # sample 0's row (line 2) ends in a Latin-1 byte
    results.write_bytes(b"\n".join(lines))
    p = subprocess.run(sweep + [str(out), "--replay", "1", "--out", str(tmp_path / "r1.csv")], capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 0, p.stderr  # the others' rows read as before (the whole file was refused)
    p = subprocess.run(sweep + [str(out), "--replay", "0", "--out", str(tmp_path / "r0.csv")], capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 2 and f"{results}:2: sample 0's row is not UTF-8 text" in p.stderr, p.stderr
    p = subprocess.run(sweep + [str(spec), "--out", str(out), "--resume", "--workers", "1", "--no-progress"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0 and f"dropped 1 row (not UTF-8 text) at {results} line 2" in p.stderr, p.stderr
    results.read_bytes().decode("utf-8")  # whole again: no byte kept, none replaced
    assert "\ufffd" not in results.read_text(encoding="utf-8")
