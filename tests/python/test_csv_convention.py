"""One CSV convention for every CSV the project writes (docs/usage.md "CSV
files"): numpy's genfromtxt(names=True) and the csv module read the same
names, each a unit-suffixed identifier (t_s, theta1_rad, bore_x); numbers
read back as the very doubles written, never -0. Checked on the files the
programs write: gimbalsim simulate, Run.to_csv, firmware_sim --truth-csv
(the writer gimbalsim_log2csv shares), gimbalsim_pointing_study's two CSVs."""
import csv
import re
import subprocess

import numpy as np
import pytest

import gimbalsim
from conftest import BIN, CONTROLLER_CONFIG, run_cli, scene_path

NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def check_convention(path):
    """The names as the csv module and numpy read them (equal), and the rows."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = rows[0]
    for n in names:
        assert NAME.match(n), f"{path}: column name {n!r} is not an identifier numpy keeps as it is"
    assert len(set(names)) == len(names), f"{path}: repeated column names"
    table = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8", max_rows=1)
    assert table.dtype.names == tuple(names), f"{path}: numpy reads {table.dtype.names}"
    # Text cells are never quoted (numpy's genfromtxt reads no quotes): no reader splits them differently.
    text = open(path, newline="").read()
    assert '"' not in text, f"{path}: a quoted cell"
    for r in rows[1:]:
        assert len(r) == len(names), f"{path}: a row of {len(r)} cells under {len(names)} names"
        for cell in r:
            assert not re.fullmatch(r"-0(\.0*)?(e[+-]?\d+)?", cell), f"{path}: a -0 cell"
            assert not re.fullmatch(r"-?\d+\.0+", cell), f"{path}: a whole number written with a fraction ({cell})"
    return names, rows[1:]


def test_simulate_csv_and_run_to_csv(tmp):
    sets = {"sim.duration": 0.2, "friction.law": "coulomb_stick"}
    run_cli("simulate", scene_path("paper_clearance"), *[a for k, v in sets.items() for a in ("--set", f"{k}={v}")],
            "--out", tmp / "cli.csv")
    run = gimbalsim.simulate(gimbalsim.load_scene(scene_path("paper_clearance"), sets))
    run.to_csv(tmp / "py.csv")
    assert (tmp / "cli.csv").read_bytes() == (tmp / "py.csv").read_bytes()
    names, rows = check_convention(tmp / "cli.csv")
    for n in ("t_s", "theta1_rad", "dtheta1_rad_per_s", "ecc2_m", "fn2_N", "bore_x", "mom_lx_Nms", "energy_J"):
        assert n in names
    # Round trip: the CSV's numbers are the run's doubles of its columns, bit for bit.
    shown = [gimbalsim.COLUMNS.index(c) for c in run.columns]
    assert np.array_equal(np.array([[float(c) for c in r] for r in rows]), run.rows[:, shown])


def test_firmware_sim_truth_csv(tmp):
    out = tmp / "truth.csv"
    p = subprocess.run([str(BIN / "firmware_sim"), str(scene_path("paper_ideal")), "--duration", "0.05",
                        "--lcm-url", "memq://", "--rt-priority", "0", "--truth-csv", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    names, rows = check_convention(out)
    for n in ("utime_us", "seq", "sim_time_s", "theta1_rad", "tau1_Nm", "mom_lx_Nms", "pointing_error_rad"):
        assert n in names
    assert len(rows) >= 50


def test_pointing_study_csvs(tmp):
    out = tmp / "study"
    out.mkdir()  # no program creates a folder it is given
    p = subprocess.run([str(BIN / "gimbalsim_pointing_study"), "--config", str(CONTROLLER_CONFIG),
                        "--ideal-scene", str(scene_path("paper_ideal")),
                        "--clearance-scene", str(scene_path("paper_clearance")),
                        "--clearances", "2.5e-4", "--duration", "0.2", "--out", str(out)],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    names, _ = check_convention(out / "pointing_error.csv")
    assert names == ["t_s", "error_ideal_rad", "error_c0p25mm_rad"]
    names, _ = check_convention(out / "summary.csv")
    assert "clearance_m" in names and "peak_track_rad" in names


def test_text_cells_read_alike_in_numpy_and_the_csv_module(tmp):
    # A reason with a comma, quotes and a '#' (numpy's comment) is one cell for every reader.
    from gimbalsim import _output
    path = tmp / "t.csv"
    _output.write_csv(path, [["run", "reason_text", "x_m"], ["a", 'stopped, "cap" at --set #1\nagain', "1.5"]])
    names, rows = check_convention(path)
    assert rows == [["a", "stopped; 'cap' at --set no. 1 again", "1.5"]]
    table = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert str(table["reason_text"]) == rows[0][1] and float(table["x_m"]) == 1.5
