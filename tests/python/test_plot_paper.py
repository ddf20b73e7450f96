"""The main job's figures (tools/paper/plot_paper.py) with the spatial run: fig 19
and the spatial column of pointing_error.csv, checked against the angle
computed here from the runs' own boresight columns; mismatched runs refused."""
import csv
import subprocess
import sys

import numpy as np

from conftest import SOURCE, run_cli, scene_path

PLOT = SOURCE / "tools" / "paper" / "plot_paper.py"


def simulate(tmp, scene, duration):
    out = tmp / f"{scene}.csv"
    run_cli("simulate", scene_path(scene), "--set", f"sim.duration={duration}", "--out", out,
            "--summary", tmp / f"{scene}.json")
    return out


def plot(*args):
    return subprocess.run([sys.executable, str(PLOT), *map(str, args)], capture_output=True, text=True, timeout=300)


def columns(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def test_spatial_run_gives_fig19_and_its_pointing_error(tmp):
    ideal, clear, spatial = (simulate(tmp, s, 0.1) for s in ("paper_ideal", "paper_clearance", "paper_spatial2"))
    out = tmp / "plots"
    out.mkdir()
    p = plot("--ideal", ideal, "--clearance", clear, "--spatial", spatial,
             "--spatial-summary", tmp / "paper_spatial2.json", "--out", out)
    assert p.returncode == 0, p.stderr
    assert (out / "fig19_joint_kinds.png").stat().st_size > 10_000
    pe = columns(out / "pointing_error.csv")
    a, b = columns(ideal), columns(spatial)
    bi = np.stack([a["bore_x"], a["bore_y"], a["bore_z"]], axis=1)
    bs = np.stack([b["bore_x"], b["bore_y"], b["bore_z"]], axis=1)
    cos = np.clip(np.sum(bi * bs, axis=1), -1.0, 1.0)
    expected = np.arccos(cos)  # the angle between unit vectors, another formula than the tool's
    assert np.allclose(pe["t_s"], a["t_s"])
    assert np.max(np.abs(pe["pointing_error_spatial_rad"] - expected)) < 1e-7
    assert expected[-1] > 1e-4  # the spatial journal tilts: the antenna moves off the ideal's
    assert "largest tilt" in p.stdout and "spatial joint 2" in p.stdout


def test_spatial_run_over_another_time_is_refused(tmp):
    ideal, clear = simulate(tmp, "paper_ideal", 0.1), simulate(tmp, "paper_clearance", 0.1)
    spatial = simulate(tmp, "paper_spatial2", 0.05)
    p = plot("--ideal", ideal, "--clearance", clear, "--spatial", spatial, "--out", tmp)
    assert p.returncode == 2
    assert str(spatial) in p.stderr and "same time" in p.stderr


def test_spatial_summary_without_spatial_run_is_refused(tmp):
    p = plot("--ideal", "a.csv", "--clearance", "b.csv", "--spatial-summary", "s.json", "--out", tmp)
    assert p.returncode == 2
    assert "--spatial-summary needs --spatial" in p.stderr


def test_a_clearance_run_without_contact_says_none_and_an_ideal_run_is_refused(tmp):
    ideal, clearance = (tmp / "i.csv", tmp / "c.csv")
    for scene, out in (("paper_ideal", ideal), ("paper_clearance", clearance)):  # no torque: the journal rests
        run_cli("simulate", scene_path(scene), "--set", "sim.duration=0.1", "--set", "torque.tau1=0",
                "--set", "torque.tau2=0", "--out", out, "--summary", out.with_suffix(".json"))
    for summary in ([], ["--clearance-summary", clearance.with_suffix(".json")]):  # the summary had a traceback
        (tmp / "o").mkdir(exist_ok=True)
        p = plot("--ideal", ideal, "--clearance", clearance, "--out", tmp / "o", *summary)
        assert p.returncode == 0, p.stderr
        assert "peak contact force          : none: no contact" in p.stdout, p.stdout
        assert "clearance c                 : 0.5 mm" in p.stdout, p.stdout
    p = plot("--ideal", ideal, "--clearance", ideal, "--out", tmp / "o")  # the ideal run given twice
    assert p.returncode == 2 and "joint 2 has no clearance" in p.stderr, p.stderr


def test_runs_or_summaries_given_swapped_are_refused_naming_the_flag(tmp):
    # The ideal and clearance runs' summaries swapped drew the page ("joint-2 force peaks: clearance 16 N / ideal 873 N").
    ideal, clear, spatial = (simulate(tmp, s, 0.1) for s in ("paper_ideal", "paper_clearance", "paper_spatial2"))
    s_ideal, s_clear = tmp / "paper_ideal.json", tmp / "paper_clearance.json"
    out = tmp / "plots"
    out.mkdir()
    p = plot("--ideal", ideal, "--clearance", clear, "--ideal-summary", s_clear, "--clearance-summary", s_ideal, "--out", out)
    assert p.returncode == 2, p.stderr
    assert f"--ideal-summary {s_clear}: its run ('paper_clearance') has joint 2 planar, the run of --ideal {ideal} " \
           "has joint 2 ideal: is it another run's summary?" in p.stderr, p.stderr
    p = plot("--ideal", ideal, "--clearance", clear, "--clearance-summary", s_ideal, "--out", out)
    assert p.returncode == 2 and f"--clearance-summary {s_ideal}: its run ('paper_ideal') has joint 2 ideal" in p.stderr
    p = plot("--ideal", clear, "--clearance", clear, "--out", out)  # the clearance run where the ideal one belongs
    assert p.returncode == 2 and f"--ideal {clear}: joint 2 has planar clearance (ecc - delta up to 0.0005 m): " \
        "is it the clearance run? --ideal takes the run of an ideal joint 2" in p.stderr, p.stderr
    p = plot("--ideal", clear, "--clearance", ideal, "--out", out)
    assert p.returncode == 2 and f"--ideal {clear}: joint 2 has planar clearance" in p.stderr, p.stderr
    p = plot("--ideal", ideal, "--clearance", clear, "--spatial", clear, "--out", out)
    assert p.returncode == 2 and f"--spatial {clear}: joint 2 has planar clearance (no tilt2_rad column)" in p.stderr
    p = plot("--ideal", ideal, "--clearance", clear, "--spatial", spatial, "--spatial-summary", s_clear, "--out", out)
    assert p.returncode == 2 and f"--spatial-summary {s_clear}: its run ('paper_clearance') has joint 2 planar" in p.stderr
    assert list(out.iterdir()) == []
    p = plot("--ideal", ideal, "--clearance", clear, "--ideal-summary", s_ideal, "--clearance-summary", s_clear, "--out", out)
    assert p.returncode == 0 and "(summary)" in p.stdout.split("peak contact force")[1].splitlines()[0], p.stderr


def test_the_ideal_at_the_clearance_peak_is_only_read_inside_the_ideal_run(tmp):
    # (pass 56) an ideal run that ended before the clearance peak gave "ideal X N at t = <past its end>":
    # np.interp held its last value there
    ideal, clear = simulate(tmp, "paper_ideal", 0.005), simulate(tmp, "paper_clearance", 0.1)
    (tmp / "o").mkdir()
    p = plot("--ideal", ideal, "--clearance", clear, "--clearance-summary", tmp / "paper_clearance.json",
             "--out", tmp / "o")
    assert p.returncode == 0, p.stderr
    assert "vs ideal at the same time : n/a (the ideal run ended at 0.005 s, before the clearance peak at" \
        in p.stdout, p.stdout
    assert "-> ratio" not in p.stdout, p.stdout


def test_a_summary_holding_nan_is_refused_not_read_past(tmp):
    # (pass 67 candidate) Python's json takes NaN; the figure fell back to the CSV's own counts with no word,
    # yet gimbalsim never writes NaN in a summary (a figure it has not is null): it is no summary of a run.
    ideal, clear = (simulate(tmp, s, 0.1) for s in ("paper_ideal", "paper_clearance"))
    s_clear = tmp / "paper_clearance.json"
    text = s_clear.read_text()
    assert '"peak_contact_force_N"' in text
    bad = tmp / "nan.json"
    bad.write_text(text.replace('"peak_contact_force_N": ', '"peak_contact_force_N": NaN, "was": ', 1))
    out = tmp / "plots"
    out.mkdir()
    p = plot("--ideal", ideal, "--clearance", clear, "--clearance-summary", bad, "--out", out)
    assert p.returncode == 2 and f"{bad}: holds NaN, which is not JSON: not a run's summary as gimbalsim writes it" \
        in p.stderr, p.stderr
    assert "Traceback" not in p.stderr and list(out.iterdir()) == []


def test_a_summary_figure_out_of_range_is_refused_at_its_key(tmp):
    # (pass 68) a peak contact force of -5 N, and one at t = 1e308 s of a 0.1 s run, were printed as the run's peak;
    # a figure given as text fell back to the CSV's samples without a word
    import json
    ideal, clear = (simulate(tmp, s, 0.1) for s in ("paper_ideal", "paper_clearance"))
    summary = json.loads((tmp / "paper_clearance.json").read_text())
    out = tmp / "plots"
    out.mkdir()
    for key, value, said in [("peak_contact_force_N", "-5.0", "a force below 0"),
                             ("t_peak_contact_force_s", "1e308", "after the run's end at 0.1 s"),
                             ("peak_contact_force_N", '"12"', "not a finite number"),
                             ("peak_joint2_force_N", "1e400", "not a finite number"),  # json reads inf
                             ("impacts", "1.5", "not a whole number")]:
        bad = tmp / "bad.json"
        bad.write_text(json.dumps({**summary, key: "VALUE"}).replace('"VALUE"', value))
        p = plot("--ideal", ideal, "--clearance", clear, "--clearance-summary", bad, "--out", out)
        assert p.returncode == 2 and f"--clearance-summary {bad}: {key} = " in p.stderr and said in p.stderr, \
            (key, p.stderr)
        assert "Traceback" not in p.stderr and list(out.iterdir()) == []
    # the run's own summary, its figures in range, is read
    p = plot("--ideal", ideal, "--clearance", clear, "--clearance-summary", tmp / "paper_clearance.json", "--out", out)
    assert p.returncode == 0 and "(summary)" in p.stdout, p.stderr


def test_a_run_cut_inside_its_last_number_is_refused(tmp):
    # (pass 69) a CSV whose last line lost its end and three digits was read, the cut row plotted as data
    ideal, clear = simulate(tmp, "paper_ideal", 0.1), simulate(tmp, "paper_clearance", 0.1)
    lines = clear.read_bytes().split(b"\n")[:60]
    cut = tmp / "cut.csv"
    cut.write_bytes(b"\n".join(lines)[:-3])
    out = tmp / "plots"
    out.mkdir()
    p = plot("--ideal", ideal, "--clearance", cut, "--out", out)
    assert p.returncode == 2, p.stderr
    assert f"{cut}:60: the last line has no line end" in p.stderr, p.stderr
    assert list(out.iterdir()) == []


def test_a_summary_of_another_run_is_refused(tmp):
    # (pass 69) a summary of a run at another clearance, or of a shorter run, was read beside the CSV: it printed
    # a "true" peak below the CSV's sampled maximum and the other run's impacts
    ideal, clear = simulate(tmp, "paper_ideal", 0.1), simulate(tmp, "paper_clearance", 0.1)
    other = tmp / "other"
    other.mkdir()
    run_cli("simulate", scene_path("paper_clearance"), "--set", "sim.duration=0.1", "--set", "contact.clearance=2e-4",
            "--out", other / "c.csv", "--summary", other / "wider.json")
    run_cli("simulate", scene_path("paper_clearance"), "--set", "sim.duration=0.05", "--out", other / "s.csv",
            "--summary", other / "shorter.json")
    out = tmp / "plots"
    out.mkdir()
    for summary, said in (("wider.json", "final_state.q.theta1"), ("shorter.json", "rows = 51, its CSV has 101")):
        p = plot("--ideal", ideal, "--clearance", clear, "--clearance-summary", other / summary, "--out", out)
        assert p.returncode == 2, p.stderr
        assert f"--clearance-summary {other / summary}: {said}" in p.stderr and "another run's summary" in p.stderr
    assert list(out.iterdir()) == []
    p = plot("--ideal", ideal, "--clearance", clear, "--clearance-summary", tmp / "paper_clearance.json", "--out", out)
    assert p.returncode == 0, p.stderr
