"""simulate() and Run.to_csv against `gimbalsim simulate`: the very bytes of
the CSV, the same summary (all but the wall-clock times), the same stop."""
import json

import pytest

import gimbalsim
from conftest import run_cli, scene_path

CASES = [
    ("paper_ideal", {}),
    ("paper_clearance", {}),
    ("paper_clearance", {"friction.mu": 0.1, "contact.clearance": 3.0e-4, "sim.substep_policy": "adaptive",
                         "friction.law": "coulomb_stick",
                         "initial.ecc": [1.0e-4, -5.0e-5], "sim.duration": 2.0}),
    ("stickslip_clearance", {"sim.duration": 1.0}),
    ("paper_both_spatial", {"sim.duration": 0.3, "structure.joint1": "planar"}),  # joint 1's and the per-end columns
]
TIMES = {"wall_time_s", "step_time_s"}
CLI_ONLY = {"overrides"}  # the command line's record of its --set; a Python scene's overrides are the caller's code


def cli_run(name, overrides, tmp):
    sets = [a for kv in gimbalsim.as_overrides(overrides) for a in ("--set", kv)]
    out, summ = tmp / f"cli_{name}.csv", tmp / f"cli_{name}.json"
    p = run_cli("simulate", scene_path(name), *sets, "--out", out, "--summary", summ, check=False)
    return p, out.read_bytes(), json.loads(summ.read_text())


@pytest.mark.parametrize("name,overrides", CASES, ids=[f"{n}{'+sets' if o else ''}" for n, o in CASES])
def test_csv_bytes_and_summary_equal_the_command_line(name, overrides, tmp):
    p, cli_csv, cli_summary = cli_run(name, overrides, tmp)
    assert p.returncode == 0, p.stderr
    run = gimbalsim.simulate(gimbalsim.load_scene(scene_path(name), overrides))
    run.to_csv(tmp / "py.csv")
    assert (tmp / "py.csv").read_bytes() == cli_csv
    strip = lambda s: {k: v for k, v in s.items() if k not in TIMES | CLI_ONLY}
    py_summary = dict(run.summary, scene=cli_summary["scene"])
    assert strip(py_summary) == strip(cli_summary)
    assert cli_summary["overrides"] == gimbalsim.as_overrides(overrides) and "overrides" not in run.summary
    assert run.rows.shape == (cli_summary["rows"], len(gimbalsim.COLUMNS))
    # The CSV's names are the columns' with the unit as a suffix (docs/usage.md "CSV files"): t -> t_s, bore_x.
    header = cli_csv.split(b"\n", 1)[0].decode().split(",")
    assert len(header) == len(run.columns)
    assert all(h == c or h.startswith(c + "_") for c, h in zip(run.columns, header)), header
    assert tuple(run.columns) == run.scene.columns


def test_a_scenes_columns_follow_its_joint_kinds(tmp_path):
    # The paper's kinds keep their 42 columns; a clearance joint 1 adds its six, a spatial joint its five.
    def cols(name, **over):
        return gimbalsim.load_scene(scene_path(name), over).columns
    paper = cols("paper_clearance")
    assert len(paper) == 42 and paper[-1] == "energy" and cols("paper_ideal") == paper
    assert cols("paper_both_planar")[42:] == ("ecc1_x", "ecc1_y", "ecc1", "delta1", "fn1", "ft1")
    assert cols("paper_spatial2")[42:] == ("tilt2", "delta2_minus", "delta2_plus", "fn2_minus", "fn2_plus")
    both = cols("paper_both_spatial")
    assert both == tuple(c for c in gimbalsim.COLUMNS if c in both) and len(both) == len(gimbalsim.COLUMNS)
    sim = gimbalsim.Simulator(gimbalsim.load_scene(scene_path("paper_spatial2")))
    assert tuple(sim.output()) == cols("paper_spatial2")
    # A column the scene does not write says so; a CSV is only ever a scene's columns.
    run = gimbalsim.simulate(gimbalsim.load_scene(scene_path("paper_spatial2"), {"sim.duration": 0.01}))
    with pytest.raises(KeyError, match="not a column of this run"):
        run.columns["tilt1"]
    wrong = list(run.columns)[:-5] + ["tilt1", "delta1_minus", "delta1_plus", "fn1_minus", "fn1_plus"]
    for bad in (wrong, []):
        with pytest.raises(ValueError, match="a scene's output columns"):
            gimbalsim._gimbalsim._write_csv(str(tmp_path / "x.csv"), run.rows, [], bad)
    assert not (tmp_path / "x.csv").exists()


def test_the_tilt_column_is_the_journals_tilt(tmp):
    # A spatial elevation journal tilts in the paper's manoeuvre, up to about its bearing's 2c/L.
    scene = gimbalsim.load_scene(scene_path("paper_spatial2"), {"sim.duration": 0.5})
    run = gimbalsim.simulate(scene)
    assert run.ok, run.summary.get("error")
    tilt = run.columns["tilt2"]
    v = {k: float(x) for k, x in scene.values().items() if k in ("contact.bearing_radius", "contact.journal_radius",
                                                                  "contact.bearing_length")}
    limit = 2 * (v["contact.bearing_radius"] - v["contact.journal_radius"]) / v["contact.bearing_length"]
    assert 0.1 * limit < tilt.max() < 1.2 * limit
    assert tilt.max() <= run.summary["clearance_joints"]["joint2"]["max_tilt_rad"]
    ends = run.summary["clearance_joints"]["joint2"]["ends"]
    assert ends["minus"]["impacts"] + ends["plus"]["impacts"] == run.summary["impacts"]


def test_a_stopped_run_keeps_its_good_rows_and_names_the_limit(tmp):
    overrides = {"sim.max_substeps": 3}
    p, cli_csv, cli_summary = cli_run("paper_clearance", overrides, tmp)
    assert p.returncode == 3
    run = gimbalsim.simulate(gimbalsim.load_scene(scene_path("paper_clearance"), overrides))
    assert not run.ok
    assert run.summary["status"] == "failed"
    assert run.summary["stop"] == cli_summary["stop"]
    assert run.summary["stop"]["key"] == "sim.max_substeps"
    assert 0 < len(run.rows) == cli_summary["rows"]
    run.to_csv(tmp / "py.csv")
    assert (tmp / "py.csv").read_bytes() == cli_csv


def test_reference_integrator_matches_the_command_line(tmp):
    overrides = {"sim.duration": 0.05, "friction.law": "ambrosio"}  # the reference needs a continuous law
    sets = [a for kv in gimbalsim.as_overrides(overrides) for a in ("--set", kv)]
    run_cli("simulate", scene_path("paper_clearance"), *sets, "--integrator", "reference", "--out", tmp / "c.csv")
    run = gimbalsim.simulate(gimbalsim.load_scene(scene_path("paper_clearance"), overrides), integrator="reference")
    run.to_csv(tmp / "p.csv")
    assert (tmp / "p.csv").read_bytes() == (tmp / "c.csv").read_bytes()
    with pytest.raises(ValueError, match="integrator"):
        gimbalsim.simulate(gimbalsim.load_scene(scene_path("paper_ideal")), integrator="euler")


def test_to_csv_refuses_an_unwritable_path_naming_it(tmp):
    run = gimbalsim.simulate(gimbalsim.load_scene(scene_path("paper_ideal"), {"sim.duration": 0.01}))
    target = tmp / "no_such_dir" / "run.csv"
    with pytest.raises(OSError) as e:
        run.to_csv(target)
    assert str(target) in str(e.value)
