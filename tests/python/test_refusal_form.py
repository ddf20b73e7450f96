"""A controller configuration refused is said in the exit-code table's form
by every program that reads one (docs/usage.md "Exit codes", row 2): each
problem on an `error: ...` line, then `<program>: refused, nothing run`, exit
2 (pass 61: pointing_controller printed "configuration refused:" and the
problem bare, which a script looking for the table's line misses)."""
import subprocess

import pytest

from conftest import BIN, SOURCE

BAD = "azimuth:\n  kp: -5\n"
PAPER = str(SOURCE / "tools" / "scenes" / "paper_ideal.yaml")


@pytest.mark.parametrize("program,args", [
    ("pointing_controller", ["{cfg}", "--duration", "1"]),
    ("pointing_controller", ["--set", "azimuth.kp=-5", "--duration", "1"]),
    ("controller_sweep", ["--scene", PAPER, "--config", "{cfg}"]),
    ("gimbalsim_controller_floor", ["--config", "{cfg}"]),
])
def test_a_refused_configuration_is_said_in_the_tables_form(tmp_path, program, args):
    cfg = tmp_path / "bad.yaml"
    cfg.write_text(BAD)
    p = subprocess.run([str(BIN / program), *[a.format(cfg=cfg) for a in args]], cwd=tmp_path, capture_output=True,
                       text=True, timeout=60)
    lines = p.stderr.splitlines()
    assert p.returncode == 2, p.stderr
    assert lines[-1] == f"{program}: refused, nothing run", p.stderr
    assert any(line.startswith("error: ") and "key 'azimuth.kp': must be in [0, 1e+09], got -5" in line
               for line in lines), p.stderr
