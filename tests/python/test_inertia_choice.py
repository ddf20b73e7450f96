"""A choice of inertias (scene base.inertia, a closed loop's
controller.plant.base_inertia) writes one cell per entry, in the six-number
spelling, under a header with as many columns (pass 76: each inertia went out
as three cells under one column, so the status column read '100', a resume
ran the rows again and a replay refused them)."""
import csv

import pytest

from conftest import SCENES
from test_sweep_replay import sweep

OPEN = f"""scene: {SCENES / 'paper_ideal.yaml'}
set: {{sim.duration: 0.1}}
samples: 4
seed: 1
parameters:
  base.inertia: {{choice: [[1000, 100, 100], [1000, 100, 100.5, 1, 0, 0]]}}
"""
CLOSED = f"""scene: {SCENES / 'paper_ideal.yaml'}
set: {{sim.duration: 5.0}}
controller: default
samples: 2
seed: 1
parameters:
  controller.plant.base_inertia: {{choice: [[1000, 100, 100], [1000, 100, 100.5]]}}
"""


def _run(tmp_path, text):
    (tmp_path / "spec.yaml").write_text(text)
    p = sweep(tmp_path / "spec.yaml", "--out", tmp_path / "out", "--workers", "1", "--no-progress")
    assert p.returncode == 0, p.stderr
    with open(tmp_path / "out" / "results.csv", newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [dict(zip(rows[0], r)) for r in rows[1:]], [len(r) for r in rows[1:]]


@pytest.mark.parametrize("text,prefix", [(OPEN, "base_inertia"), (CLOSED, "controller_plant_base_inertia")])
def test_each_entry_has_its_column_and_every_row_runs(tmp_path, text, prefix):
    header, rows, widths = _run(tmp_path, text)
    assert set(widths) == {len(header)}, (widths, header)
    parts = [f"{prefix}_{p}_kgm2" for p in ("xx", "yy", "zz", "xy", "xz", "yz")]
    assert [h for h in header if h.startswith(prefix)] == parts, header
    assert [h for h in header if h.startswith("applied_" + prefix)] == ["applied_" + p for p in parts], header
    for r in rows:
        assert r["status"] == "ok", r
        assert r["applied_differs"] == "", r
        assert [float(r[p]) for p in parts] in ([1000, 100, 100, 0, 0, 0], [1000, 100, 100.5, 1, 0, 0],
                                               [1000, 100, 100.5, 0, 0, 0]), r
        assert [r[p] for p in parts] == [r["applied_" + p] for p in parts], r


def test_a_row_of_a_choice_of_inertias_is_resumed_and_replayed(tmp_path):
    _run(tmp_path, OPEN)
    p = sweep(tmp_path / "spec.yaml", "--out", tmp_path / "out", "--workers", "1", "--no-progress", "--resume")
    assert p.returncode == 0 and "0 to run" in p.stdout + p.stderr, p.stdout + p.stderr
    p = sweep(tmp_path / "out", "--replay", 1, "--out", tmp_path / "run.csv")
    assert p.returncode == 0 and "reproduces its row" in p.stderr, p.stdout + p.stderr


def test_a_value_that_is_no_inertia_is_refused_at_its_line(tmp_path):
    (tmp_path / "spec.yaml").write_text(OPEN.replace("[1000, 100, 100.5, 1, 0, 0]", "[1, 2]"))
    p = sweep(tmp_path / "spec.yaml", "--out", tmp_path / "out", "--workers", "1")
    assert p.returncode == 2, p.stderr
    assert "spec.yaml:6:" in p.stderr and "'parameters.base.inertia': choice: an inertia is [Ixx, Iyy, Izz]" \
        in p.stderr, p.stderr
