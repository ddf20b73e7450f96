"""The plotting scripts of tools/ end as the programs do (docs/usage.md "Exit
codes", "Output files"): a bad input or an output that breaks the rules is one
line naming the file (and line), exit 2, and nothing written; never a
traceback, never a folder made for the user."""
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import BIN, SOURCE

sys.path.insert(0, str(SOURCE / "tools" / "paper"))
sys.path.insert(0, str(SOURCE / "tools" / "pointing_study"))
from paper_data import REQUIRED  # noqa: E402
from test_page_columns import WORKPREC_HEADER  # noqa: E402  (gimbalsim_workprec's CSV)
from test_page_rules import POINTING_HEADER  # noqa: E402  (the study's summary.csv)

BENCH = SOURCE / "tools" / "hil" / "plot_bench.py"
STUDY = SOURCE / "tools" / "pointing_study" / "plot_pointing_study.py"
PAPER = SOURCE / "tools" / "paper" / "plot_paper.py"
TRUTH_HEADER = "sim_time_s,theta1_rad,theta2_rad,tau1_Nm,tau2_Nm,pointing_error_rad,faults\n"


def run(script, *args):
    return subprocess.run([sys.executable, str(script), *map(str, args)], capture_output=True, text=True, timeout=120)


def refused(p, *words):
    assert p.returncode == 2, (p.returncode, p.stderr)
    assert "Traceback" not in p.stderr
    for w in words:
        assert str(w) in p.stderr, p.stderr


@pytest.fixture
def truth(tmp):
    path = tmp / "truth.csv"
    path.write_text(TRUTH_HEADER + "0,0,0,0,0,1e-3,0\n0.001,0,0,0,0,2e-3,1\n")
    return path


def test_bench_plot_writes_and_refuses_bad_outputs(tmp, truth):
    p = run(BENCH, truth, "--out", tmp / "ok.png")
    assert p.returncode == 0, p.stderr
    # the window [2.5, inf) s is one the run never reached: n/a with its reason, as every summary says it
    assert "max after 2.5 s n/a (window [2.5, inf) s not reached: run ended at" in p.stdout, p.stdout
    p = run(BENCH, truth, "--out", tmp / "ok.png", "--after", "0")
    assert p.returncode == 0 and "max after 0 s" in p.stdout and "n/a" not in p.stdout, p.stdout
    # (pass 61) a run ending at the window's start, its time summed tick by tick, has not passed it
    summed = tmp / "summed.csv"
    summed.write_text(TRUTH_HEADER + "0,0,0,0,0,1e-3,0\n0.0010000000000000002,0,0,0,0,2e-3,0\n")
    p = run(BENCH, summed, "--out", tmp / "ok.png", "--after", "0.001")
    assert p.returncode == 0 and "max after 0.001 s n/a (window [0.001, inf) s not reached" in p.stdout, p.stdout
    assert (tmp / "ok.png").stat().st_size > 1000
    refused(run(BENCH, truth, "--out", tmp / "missing" / "x.png"), "missing", "does not exist")
    refused(run(BENCH, truth, "--out", truth), "the same file as the input")
    os.symlink(tmp / "victim.png", tmp / "link.png")
    refused(run(BENCH, truth, "--out", tmp / "link.png"), "symbolic link")
    assert not (tmp / "victim.png").exists()
    refused(run(BENCH, truth, "--out", "/dev/full"), "not a regular file")


def test_bench_plot_draws_no_invented_floor_for_an_error_of_exactly_0(tmp):
    # An ideal run's error of exactly 0 was drawn as a line at 1e-12 on the log axis, with no word about it.
    sys.path.insert(0, str(BENCH.parent))
    from plot_bench import log_series
    drawn, note = log_series(np.array([0.0, 1e-4, 0.0, 2e-4]))
    assert np.array_equal(np.isnan(drawn), [True, False, True, False]) and list(drawn[[1, 3]]) == [1e-4, 2e-4]
    assert note == "exactly 0 in 2 of 4 rows: gaps on the log axis"
    drawn, note = log_series(np.zeros(3))
    assert np.isnan(drawn).all() and note == "0 throughout: nothing drawn on the log axis"
    assert log_series(np.array([1e-3, 2e-3]))[1] == ""
    zero = tmp / "zero.csv"
    zero.write_text(TRUTH_HEADER + "0,0,0,0,0,0,0\n0.001,0,0,0,0,0,0\n")
    p = run(BENCH, zero, "--out", tmp / "z.png")
    assert p.returncode == 0 and "  pointing error 0 throughout: nothing drawn on the log axis\n" in p.stdout, p.stderr
    zero.write_text(TRUTH_HEADER + "0,0,0,0,0,0,0\n0.001,0,0,0,0,-1e-4,0\n")  # an angle's size is never below 0
    refused(run(BENCH, zero, "--out", tmp / "n.png"), f"{zero}:3: column pointing_error_rad: -0.0001 is negative")
    assert not (tmp / "n.png").exists()


def test_bench_plot_gives_no_figure_for_a_plant_stopped_in_its_first_step(tmp):
    # (pass 86) one row at t = 0 gave "end 0.000e+00 rad" and "0 throughout", where firmware_sim says n/a
    truth = tmp / "first_step.csv"
    p = subprocess.run([str(BIN / "firmware_sim"), str(SOURCE / "tools/scenes/paper_clearance.yaml"), "--set",
                        "initial.dtheta1=5", "--set", "sim.velocity_limit=1", "--duration", "0.01", "--lcm-url",
                        "memq://", "--truth-csv", str(truth)], capture_output=True, text=True, timeout=60)
    assert p.returncode == 3 and "the plant's first step failed" in p.stdout, (p.stdout, p.stderr)
    p = run(BENCH, truth, "--out", tmp / "first_step.png")
    assert p.returncode == 0, p.stderr
    assert "pointing error: n/a (the plant's first step failed: no step completed)" in p.stdout, p.stdout
    assert "end 0.000e+00" not in p.stdout and "0 throughout" not in p.stdout, p.stdout


def test_bench_plot_refuses_bad_input_naming_the_line(tmp):
    bad = tmp / "bad.csv"
    bad.write_text(TRUTH_HEADER + "0,0,0,0,0,1e-3,0\n0.001,0,x,0,0,2e-3,0\n")
    refused(run(BENCH, bad, "--out", tmp / "a.png"), f"{bad}:3", "theta2_rad")
    bad.write_text(TRUTH_HEADER + "0,0,0,0,0,1e-3,0.5\n")
    refused(run(BENCH, bad, "--out", tmp / "a.png"), f"{bad}:2", "faults")
    bad.write_text(TRUTH_HEADER + "0,0,0,0,0,1e-3,0\n0.001,0,inf,0,0,2e-3,0\n")  # was taken as a number
    refused(run(BENCH, bad, "--out", tmp / "a.png"), f"{bad}:3", "not a finite decimal number")
    bad.write_text(TRUTH_HEADER.replace("faults", "theta1_rad") + "0,0,0,0,0,1e-3,0\n")
    refused(run(BENCH, bad, "--out", tmp / "a.png"), "column theta1_rad appears twice")
    good = tmp / "good.csv"
    good.write_text(TRUTH_HEADER + "0,0,0,0,0,1e-3,0\n")
    refused(run(BENCH, good, "--out", tmp / "a.xyz"), "not a figure format")  # was a traceback after plotting
    os.mkfifo(tmp / "fifo")  # would block a reader that opens it
    refused(run(BENCH, tmp / "fifo", "--out", tmp / "a.png"), "not a regular file")
    refused(run(BENCH, tmp / "truth.csv", "--out", tmp / "a.png"), "cannot read")
    assert not (tmp / "a.png").exists()


def test_bench_plot_refuses_a_bad_cell_in_a_column_it_does_not_plot(tmp):
    # A word in fn2_plus_N, base_x_m or utime_us was plotted (exit 0) while the same in theta2_rad was refused;
    # torque_replay refuses the file (every cell of every column is the writer's plain finite decimal).
    header = "utime_us," + TRUTH_HEADER.rstrip("\n") + ",base_x_m,fn2_plus_N\n"
    rows = ["1000,0,0,0,0,0,1e-3,0,0,0", "2000,0.001,0,0,0,0,2e-3,0,0,1.5e-150", "3000,0.002,0,0,0,0,2e-3,0,0,0"]
    bad = tmp / "bad.csv"
    bad.write_text(header + "\n".join(rows) + "\n")
    p = run(BENCH, bad, "--out", tmp / "ok.png")
    assert p.returncode == 0, p.stderr
    (tmp / "ok.png").unlink()
    for column, cell, said in [("fn2_plus_N", "x", "not a finite decimal number: 'x'"),
                               ("base_x_m", "nan", "not a finite decimal number: 'nan'"),
                               ("utime_us", "", "not a finite decimal number: ''"),
                               ("fn2_plus_N", "0x10", "not a finite decimal number: '0x10'"),
                               ("base_x_m", "1e400", "not a finite decimal number: '1e400'"),
                               ("fn2_plus_N", "1e-400", "'1e-400' underflows a double")]:
        edited = [r.split(",") for r in rows]
        edited[2][header.rstrip("\n").split(",").index(column)] = cell
        bad.write_text(header + "\n".join(",".join(r) for r in edited) + "\n")
        refused(run(BENCH, bad, "--out", tmp / "a.png"), f"{bad}:4: column {column}: {said}")
    for text, said in [((header + "\n".join(rows) + "\n").replace("\n", "\r\n"), f"{bad}:1: ends in CR (CRLF"),
                       ("\ufeff" + header + "\n".join(rows) + "\n", f"{bad}:1: starts with a byte-order mark")]:
        bad.write_bytes(text.encode())
        refused(run(BENCH, bad, "--out", tmp / "a.png"), said, "not as firmware_sim writes a truth CSV")
    assert not (tmp / "a.png").exists()


def test_bench_plot_refuses_a_truth_csv_with_ticks_cut_out(tmp):
    # (pass 70) rows cut out of a truth CSV (seq 0, 1, 3) were plotted as one run, a line drawn across the gap;
    # a CSV of every N-th tick (--truth-every N) or a log begun late is one run and is plotted
    header = "seq," + TRUTH_HEADER
    good = tmp / "every2.csv"
    good.write_text(header + "4,0,0,0,0,0,1e-3,0\n6,0.002,0,0,0,0,2e-3,0\n8,0.004,0,0,0,0,2e-3,0\n")
    p = run(BENCH, good, "--out", tmp / "ok.png")
    assert p.returncode == 0 and (tmp / "ok.png").exists(), p.stderr
    cut = tmp / "cut.csv"
    cut.write_text(header + "0,0,0,0,0,0,1e-3,0\n1,0.001,0,0,0,0,2e-3,0\n3,0.003,0,0,0,0,2e-3,0\n")
    refused(run(BENCH, cut, "--out", tmp / "a.png"), f"{cut}:4: seq 3 after 1, where the rows before step by 1: "
            "ticks cut out")
    cut.write_text(header + "1,0,0,0,0,0,1e-3,0\n0,0.001,0,0,0,0,2e-3,0\n")
    refused(run(BENCH, cut, "--out", tmp / "a.png"), f"{cut}:3: seq 0 after 1", "out of order")
    cut.write_text(header + "0,0,0,0,0,0,1e-3,0\n1.5,0.001,0,0,0,0,2e-3,0\n")
    refused(run(BENCH, cut, "--out", tmp / "a.png"), f"{cut}:3: column seq: 1.5 is not a tick number")
    assert not (tmp / "a.png").exists()


def study_row(run="ideal", scene="paper_ideal", c="0", status="ok", rms="1e-6", peak="2e-6", ticks="1",
              limited_track="0", track_reason=""):
    """A summary.csv row as gimbalsim_pointing_study writes it (POINTING_HEADER's columns)."""
    return (f"{run},{scene},perfect,{c},{peak},{rms},3e-06,{ticks},0,{limited_track},0,ideal/ideal,nan,nan,nan,nan,"
            f"encoders,{status},,{track_reason},\n")


def study_dir(tmp):
    d = tmp / "study"
    d.mkdir()
    (d / "pointing_error.csv").write_text("t_s,error_ideal_rad\n0,1e-6\n0.001,2e-6\n")
    (d / "summary.csv").write_text(POINTING_HEADER + study_row())
    return d


def test_pointing_study_plot_draws_the_first_sensor_set_against_time(tmp):
    # (pass 56 follow-up) a --scene-set sensor key labels the sets "perfect except ...": with two sets the time
    # plot drew only runs labelled "perfect", none, and refused the study
    from plot_pointing_study import shown_in_time_plot
    rows = [dict(run=run, scene=scene, sensors=sensors, clearance_m=c) for run, scene, sensors, c in (
        ("ideal_perfect", "paper_ideal", "perfect except sensors.gyro_noise=1e-5", 0.0),
        ("c=0.5mm_perfect", "paper_clearance", "perfect except sensors.gyro_noise=1e-5", 5e-4),
        ("ideal_realistic", "paper_ideal", "realistic except sensors.gyro_noise=1e-5", 0.0),
        ("c=0.5mm_realistic", "paper_clearance", "realistic except sensors.gyro_noise=1e-5", 5e-4))]
    assert shown_in_time_plot(rows) == ["ideal_perfect", "c=0.5mm_perfect"]


def test_pointing_study_plot_refuses_bad_cells_and_outputs(tmp):
    d = study_dir(tmp)
    assert run(STUDY, d).returncode == 0
    # "nan" is the CSV convention's figure without a value (a run that never reached the track): a run
    # without one is left out of the plot, beside one that has it ...
    (d / "summary.csv").write_text(POINTING_HEADER + study_row() + study_row(
        "c=0.1mm", "paper_clearance", "1e-4", rms="nan", peak="nan", ticks="0", limited_track="nan",
        track_reason="track window not reached"))
    p = run(STUDY, d)
    assert p.returncode == 0, p.stderr
    assert (d / "pointing_error_vs_clearance.png").exists()
    # ... but a study none of whose runs has one gets no plot (it drew two empty axes)
    (d / "summary.csv").write_text(POINTING_HEADER + study_row(
        rms="nan", peak="nan", ticks="0", limited_track="nan",
        track_reason="track window [3.5; inf) s not reached: run ended at 0.1 s"))
    refused(run(STUDY, d), "no run has a figure while tracking (track window [3.5; inf) s not reached")
    (d / "summary.csv").write_text(POINTING_HEADER + study_row())
    (d / "pointing_error.csv").write_text("t_s,error_ideal_rad\n0,0\n0.001,0\n")
    refused(run(STUDY, d), "pointing_error.csv: no run drawn against time has a pointing error above 0")
    (d / "pointing_error.csv").write_text("t_s,error_ideal_rad\n0,1e-6\n0.001,2e-6\n")
    (d / "summary.csv").write_text(POINTING_HEADER + study_row(c="zero"))
    refused(run(STUDY, d), "summary.csv:2", "clearance_m")
    (d / "summary.csv").write_text("run,scene\nideal,paper_ideal\n")
    refused(run(STUDY, d), "summary.csv", "no column")
    # (pass 70) the page's rules: a negative or a NaN peak on a run that tracked, CRLF, a negative error in time
    for text, said in [(POINTING_HEADER + study_row(peak="-2e-6"), "summary.csv:2: column peak_track_rad: -2e-6 is "
                        "outside [0, 3.14159]"),
                       (POINTING_HEADER + study_row(peak="nan"), "summary.csv:2: track_ticks 1 with peak_track_rad nan"),
                       ((POINTING_HEADER + study_row()).replace("\n", "\r\n"), "a carriage return on line 1")]:
        (d / "summary.csv").write_text(text)
        refused(run(STUDY, d), said)
    (d / "summary.csv").write_text(POINTING_HEADER + study_row())
    for text, said in [("t_s,error_ideal_rad\n0,1e-6\n0.001,-2e-6\n", "pointing_error.csv:3: column error_ideal_rad: "
                        "-2e-6 is outside [0, 3.14159]"),
                       ("t_s,error_ideal_rad\r\n0,1e-6\r\n", "pointing_error.csv:1: ends in CR (CRLF line ends)"),
                       ("t_s,error_ideal_rad\n0,1e-6\n0.001,2e-6", "pointing_error.csv:3: the last line has no line end"),
                       ("t_s,error_ideal_rad\n0.001,1e-6\n0.001,2e-6\n", "pointing_error.csv:3: column t_s: does "
                        "not increase"),
                       # (pass 81) a gap, a nan and a negative zero, none of which the study writes, were drawn
                       ("t_s,error_ideal_rad\n0,1e-6\n0.001,\n0.002,2e-6\n", "pointing_error.csv:4: column "
                        "error_ideal_rad: a value after the run's end (its empty cell on line 3)"),
                       ("t_s,error_ideal_rad\n0,1e-6\n0.001,nan\n", "pointing_error.csv:3: column error_ideal_rad: "
                        "'nan' is"),
                       ("t_s,error_ideal_rad\n0,-0\n0.001,2e-6\n", "pointing_error.csv:2: column error_ideal_rad: "
                        "'-0' is a negative zero")]:
        (d / "pointing_error.csv").write_text(text)
        refused(run(STUDY, d), said)
    (d / "pointing_error.csv").write_text("t_s,error_ideal_rad\n0,1e-6\n0.001,2e-6\n")
    (d / "pointing_error_vs_time.png").unlink()
    os.symlink(tmp / "victim.png", d / "pointing_error_vs_time.png")
    refused(run(STUDY, d), "symbolic link")
    assert not (tmp / "victim.png").exists()
    # the study's folder is the input: said as missing, not as an output's folder ("its directory ... does not exist")
    refused(run(STUDY, tmp / "nowhere"), "nowhere: no such folder (give gimbalsim_pointing_study's --out folder)")
    refused(run(STUDY, d / "summary.csv"), "summary.csv: not a folder")


def test_paper_plot_makes_no_folder_and_overwrites_no_input(tmp):
    csv = tmp / "run.csv"
    csv.write_text(",".join(REQUIRED) + "\n" + ",".join(["0"] * len(REQUIRED)) + "\n1\n")
    refused(run(PAPER, "--ideal", csv, "--clearance", csv, "--out", tmp / "plots"), "plots", "create it first")
    assert not (tmp / "plots").exists()
    (tmp / "plots").mkdir()
    clash = tmp / "plots" / "pointing_error.csv"
    clash.write_text(csv.read_text())
    refused(run(PAPER, "--ideal", clash, "--clearance", csv, "--out", tmp / "plots"), "the same file as the input")
    refused(run(PAPER, "--ideal", csv, "--clearance", csv, "--out", tmp), f"{csv}", "not a table of numbers")
    assert sorted(p.name for p in tmp.iterdir()) == ["plots", "run.csv"]
    # (pass 71) an --out that is a link to a folder had every figure written through it
    (tmp / "elsewhere").mkdir()
    (tmp / "link").symlink_to(tmp / "elsewhere", target_is_directory=True)
    for out in (tmp / "link", f"{tmp / 'link'}/"):
        refused(run(PAPER, "--ideal", csv, "--clearance", csv, "--out", out), "a symbolic link; not written through")
    assert list((tmp / "elsewhere").iterdir()) == []


def workprec_point(scene="A", h="0.001", ok="1", cpu="0.1", err="1e-6", force="0.01", note="", policy="plain"):
    """A workprec.csv row as gimbalsim_workprec writes it (WORKPREC_HEADER's columns)."""
    return (f"{scene},{policy},{h},nan,1e-08,,,{ok},{cpu},3,{err},1e-07,1e-07,1e-07,{force},1e-09,100,5,1,{note}\n")


def test_workprec_plot_refuses_a_foreign_csv_and_its_own_input(tmp):
    plot = SOURCE / "tools" / "workprec" / "plot_workprec.py"
    good = tmp / "w.csv"
    good.write_text(WORKPREC_HEADER + workprec_point())
    assert run(plot, good).returncode == 0 and (tmp / "w.png").exists()
    refused(run(plot, good, "--out", good), "the same file as the input")
    bad = tmp / "b.csv"
    bad.write_text(WORKPREC_HEADER + workprec_point(err="zz"))
    refused(run(plot, bad), f"{bad}:2", "bore_err_max_rad")
    bad.write_text("a,b\n1,2\n")
    refused(run(plot, bad), "no column")
    # a time or an error below 0 is none the tool writes: it was skipped without a word, or drawn at 1e-16
    for row, column in ((workprec_point(cpu="-1"), "cpu_s_per_sim_s"), (workprec_point(err="-1e-6"),
                                                                          "bore_err_max_rad")):
        bad.write_text(WORKPREC_HEADER + row)
        refused(run(plot, bad), f"{bad}:2: column {column}", "is outside [0, inf]")
    # (pass 69) the page's rules, which the plot did not have: CRLF, a step or a CPU time of 0 on a point that ran
    # ok, a negative error on a failed one, one point twice, nan in a column the plot does not draw
    for text, said in [((WORKPREC_HEADER + workprec_point()).replace("\n", "\r\n"), "a carriage return"),
                       (WORKPREC_HEADER + workprec_point(h="0"), f"{bad}:2: column h_s: 0.0 is no figure"),
                       (WORKPREC_HEADER + workprec_point(cpu="0"), f"{bad}:2: column cpu_s_per_sim_s: 0.0 is no fig"),
                       (WORKPREC_HEADER + workprec_point() + workprec_point(ok="0", err="-1"),
                        f"{bad}:3: column bore_err_max_rad: -1 is outside"),
                       (WORKPREC_HEADER + workprec_point() + workprec_point(cpu="0.2"),
                        f"{bad}:3: the point of line 2 again"),
                       (WORKPREC_HEADER + workprec_point(force="nan"), f"{bad}:2: column peak_force_err_rel: nan on")]:
        bad.write_text(text)
        refused(run(plot, bad), said)
    # nan there is the writer's, with its note, where the reference has no contact
    good.write_text(WORKPREC_HEADER + workprec_point(force="nan", note="peak_force_err_rel: no contact in the "
                                                     "reference"))
    assert run(plot, good).returncode == 0
    assert not (tmp / "b.png").exists()


def test_workprec_plot_finds_the_repositorys_csv_from_any_folder(tmp):
    # (pass 69) its default CSV was out/workprec/ of the working folder, and a missing one was named by the
    # folder of its PNG ("out/workprec/workprec.png: its directory out/workprec does not exist")
    repo = tmp / "repo"
    shutil.copytree(SOURCE / "tools" / "pages", repo / "tools" / "pages")
    shutil.copytree(SOURCE / "python" / "gimbalsim", repo / "python" / "gimbalsim")  # the one writer's rules
    (repo / "tools" / "workprec").mkdir(parents=True)
    for name in ("plot_workprec.py", "workprec_page.py"):  # the plot reads the CSV by the page's rules
        shutil.copy(SOURCE / "tools" / "workprec" / name, repo / "tools" / "workprec")
    plot = repo / "tools" / "workprec" / "plot_workprec.py"
    elsewhere = tmp / "elsewhere"
    elsewhere.mkdir()
    p = subprocess.run([sys.executable, str(plot)], capture_output=True, text=True, timeout=120, cwd=elsewhere)
    refused(p, f"{repo / 'out' / 'workprec' / 'workprec.csv'}: no such file")
    (repo / "out" / "workprec").mkdir(parents=True)
    (repo / "out" / "workprec" / "workprec.csv").write_text(WORKPREC_HEADER + workprec_point())
    p = subprocess.run([sys.executable, str(plot)], capture_output=True, text=True, timeout=120, cwd=elsewhere)
    assert p.returncode == 0, p.stderr
    assert (repo / "out" / "workprec" / "workprec.png").exists() and list(elsewhere.iterdir()) == []


SET_WRITER = """
import os, pathlib, signal, sys
sys.path.insert(0, {pages!r})
from output_file import OutputError, run_script, write_text
out = pathlib.Path(sys.argv[1])
def main():
    write_text(out / "a.txt", "a")
    write_text(out / "b.txt", "b")
    if sys.argv[2] == "fail":
        raise OutputError("c.txt: no space left on device")
    os.kill(os.getpid(), signal.SIGTERM)
sys.exit(run_script("writer", main, whole_set={whole}))
"""


@pytest.mark.parametrize("how,code,message", [("fail", 4, "writer: error: c.txt"),
                                              ("stop", 143, "writer: interrupted (SIGTERM)")])
@pytest.mark.parametrize("whole", [True, False])
def test_a_set_of_outputs_is_whole_or_gone_and_a_stop_is_no_traceback(tmp_path, how, code, message, whole):
    # plot_paper left four of its figures on a full disk, and on SIGTERM a temporary beside them; (pass 69) a
    # SIGTERM amid its figures left the previous set part removed: a set's files wait in their temporaries
    script = tmp_path / "w.py"
    script.write_text(SET_WRITER.format(pages=str(SOURCE / "tools" / "pages"), whole=whole))
    (tmp_path / "out").mkdir()
    for name in ("a.txt", "b.txt"):
        (tmp_path / "out" / name).write_text("previous")
    p = subprocess.run([sys.executable, str(script), str(tmp_path / "out"), how], capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == code and message in p.stderr and "Traceback" not in p.stderr, p.stderr
    left = {f.name: f.read_text() for f in (tmp_path / "out").iterdir()}  # no temporary either way
    assert left == ({"a.txt": "previous", "b.txt": "previous"} if whole else {"a.txt": "a", "b.txt": "b"})


def test_compare_verdicts_refuses_what_holds_no_stress_run(tmp_path):
    # (pass 29) two CSVs without a verdict column compared as "0 runs ... identical", exit 0; a missing file was a
    # traceback; --help exited 1
    tool = SOURCE / "tools/stress/compare_verdicts.py"
    (tmp_path / "other.csv").write_text("a,b\n1,2\n")
    (tmp_path / "empty.csv").write_text("group,scene,sets,verdict\n")
    (tmp_path / "one.csv").write_text("group,scene,sets,verdict\ng,paper_ideal,x,TRUSTWORTHY\n")
    # (pass 45) any text was compared as a verdict, and a run twice in one CSV was listed as in one CSV only
    (tmp_path / "bogus.csv").write_text("group,scene,sets,verdict\ng,paper_ideal,x,BOGUS\n")
    (tmp_path / "dup.csv").write_text("group,scene,sets,verdict\ng,paper_ideal,x,STOPPED\ng,paper_ideal,x,STOPPED\n")
    # (pass 30) a cut row was a TypeError, a FIFO blocked, a second verdict column was read silently, empty
    # verdicts compared as identical
    (tmp_path / "cut.csv").write_text("group,scene,sets,verdict\ng,paper_ideal\n")
    (tmp_path / "twice.csv").write_text("group,scene,sets,verdict,verdict\ng,paper_ideal,x,ok,bad\n")
    (tmp_path / "blank.csv").write_text("group,scene,sets,verdict\ng,paper_ideal,x,\n")
    os.mkfifo(tmp_path / "fifo.csv")
    for args, words in (([tmp_path / "cut.csv"] * 2, "cut.csv:2: not the header's 4 fields"),
                        ([tmp_path / "twice.csv"] * 2, "twice.csv:1: column verdict appears twice"),
                        ([tmp_path / "blank.csv"] * 2, "blank.csv:2: no verdict"),
                        ([tmp_path / "fifo.csv", tmp_path / "one.csv"], "fifo.csv: not a regular file"),
                        ([tmp_path / "other.csv"] * 2, "not a gimbalsim_stress CSV (no column group"),
                        ([tmp_path / "missing.csv", tmp_path / "one.csv"], "missing.csv: cannot read it"),
                        ([tmp_path / "empty.csv"] * 2, "empty.csv: no runs: nothing to compare"),
                        ([tmp_path / "one.csv", tmp_path / "bogus.csv"], "bogus.csv:2: verdict 'BOGUS' is none"),
                        ([tmp_path / "one.csv", tmp_path / "dup.csv"], "dup.csv:3: the run of line 2 again")):
        p = subprocess.run(["/usr/bin/python3", str(tool), *map(str, args)], capture_output=True, text=True, timeout=60)
        assert p.returncode == 2 and words in p.stderr and "Traceback" not in p.stderr, (args, p.stderr)
    p = subprocess.run(["/usr/bin/python3", str(tool), str(tmp_path / "one.csv"), str(tmp_path / "one.csv")],
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and "verdicts identical run for run" in p.stdout, p.stderr
    assert subprocess.run(["/usr/bin/python3", str(tool), "--help"], capture_output=True, timeout=60).returncode == 0


def test_gen_key_docs_reads_its_argument_as_a_program_does(tmp_path):
    # (pass 30) --help, --bogus and a folder that does not exist each ended in a FileNotFoundError traceback (1)
    tool = SOURCE / "tools/pages/gen_key_docs.py"
    for args, code, words in ((["--help"], 0, None), (["--bogus"], 2, "unrecognized arguments"),
                              ([str(tmp_path / "nowhere")], 2, "nowhere/gimbalsim: no such program")):
        p = subprocess.run(["/usr/bin/python3", str(tool), *args], capture_output=True, text=True, timeout=60)
        assert p.returncode == code and "Traceback" not in p.stderr, (args, p.stderr)
        assert words is None or words in p.stderr, (args, p.stderr)


def test_gen_key_docs_writes_both_tables_or_neither(tmp_path):
    # (pass 31) a bin folder without pointing_controller replaced docs/scene_keys.md, then refused (exit 2); programs
    # that printed nothing replaced both key tables by nothing (exit 0)
    root = tmp_path / "tree"
    (root / "tools").mkdir(parents=True)
    (root / "docs").mkdir()
    shutil.copytree(SOURCE / "tools/pages", root / "tools/pages")
    shutil.copytree(SOURCE / "python/gimbalsim", root / "python/gimbalsim")  # the writer the tools load by path
    for doc in ("scene_keys.md", "controller_keys.md"):
        shutil.copy(SOURCE / "docs" / doc, root / "docs" / doc)
    before = {doc: (root / "docs" / doc).read_text() for doc in ("scene_keys.md", "controller_keys.md")}
    half, empty = tmp_path / "half", tmp_path / "empty"
    for folder in (half, empty):
        folder.mkdir()
    keys = subprocess.run([str(BIN / "gimbalsim"), "keys", "--markdown"], capture_output=True, text=True).stdout
    (half / "gimbalsim").write_text(f"#!/bin/sh\ncat <<'X'\n{keys}| x.y | number | m | 0 | | one key more |\nX\n")
    for name in ("gimbalsim", "pointing_controller"):
        (empty / name).write_text("#!/bin/sh\nexit 0\n")
    for f in [half / "gimbalsim", empty / "gimbalsim", empty / "pointing_controller"]:
        f.chmod(0o755)
    # (pass 32) both tables good but the second document a link: the first was written, then the link refused
    more = tmp_path / "more"
    more.mkdir()
    for name, args in (("gimbalsim", "keys --markdown"), ("pointing_controller", "--keys --markdown")):
        table = subprocess.run([str(BIN / name), *args.split()], capture_output=True, text=True).stdout
        (more / name).write_text(f"#!/bin/sh\ncat <<'X'\n{table}| x.y | number | m | 0 | | one key more |\nX\n")
        (more / name).chmod(0o755)
    elsewhere = tmp_path / "controller_keys_copy.md"
    elsewhere.write_text(before["controller_keys.md"])
    (root / "docs" / "controller_keys.md").unlink()
    (root / "docs" / "controller_keys.md").symlink_to(elsewhere)
    for folder, words in ((half, "pointing_controller: no such program"), (empty, "printed no key table"),
                          (more, "symbolic link")):
        p = subprocess.run(["/usr/bin/python3", str(root / "tools/pages/gen_key_docs.py"), str(folder)],
                           capture_output=True, text=True, timeout=60)
        assert p.returncode == 2 and words in p.stderr and "updated" not in p.stdout, (folder, p.stdout, p.stderr)
        assert {doc: (root / "docs" / doc).read_text() for doc in before} == before
    # (pass 33) a document without the table's header, or not UTF-8: a bare line or a traceback, exit 1
    (root / "docs" / "controller_keys.md").unlink()
    headless = before["controller_keys.md"].replace("| key | type |", "|key | type |")
    (root / "docs" / "controller_keys.md").write_text(headless)
    scene = (root / "docs" / "scene_keys.md").read_bytes()
    for folder, words in ((more, "docs/controller_keys.md: no line '| key | type"), (more, "scene_keys.md: ")):
        if words.startswith("scene"):
            (root / "docs" / "scene_keys.md").write_bytes(scene.replace(b"| key |", b"| k\xe9y |", 1))
        p = subprocess.run(["/usr/bin/python3", str(root / "tools/pages/gen_key_docs.py"), str(folder)],
                           capture_output=True, text=True, timeout=60)
        assert p.returncode == 2 and words in p.stderr and "Traceback" not in p.stderr, (words, p.stderr)
        assert "updated" not in p.stdout, p.stdout


def test_the_tools_numbers_have_ranges_the_code_honours(tmp_path):
    # (pass 31) py_bench --repeats 0 ended in a StatisticsError traceback and --steps 0 in a ZeroDivisionError;
    # plot_bench --after took ' 1', -1 and 1e-400 (as 0)
    cases = [("tools/bench/py_bench.py", ["--repeats", "0"], "--repeats: must be a whole number in [1, 1000]"),
             ("tools/bench/py_bench.py", ["--steps", "0"], "--steps: must be a whole number in [1, 10000000]"),
             ("tools/bench/py_bench.py", ["--repeats", " 1"], "got ' 1'"),
             ("tools/hil/plot_bench.py", ["x.csv", "--out", "x.png", "--after", "-1"], "must be in [0, 1e+09]"),
             ("tools/hil/plot_bench.py", ["x.csv", "--out", "x.png", "--after", " 1"], "not a finite decimal"),
             ("tools/hil/plot_bench.py", ["x.csv", "--out", "x.png", "--after", "1e-400"], "too small for a double"),
             ("tools/hil/plot_bench.py", ["x.csv", "--out", "x.png", "--after", "5e-324"], "too small for a double"),
             # (pass 88) each ran until a program refused it mid-study (exit 1, or 0 with no real-time run)
             ("tools/hil/hil_speed.py", ["--cpu", "4095"], "must be -1 (no pinning) or a CPU this process may run on"),
             ("tools/hil/worst_tick.py", ["--cpu", "4095"], "must be -1 (no pinning) or a CPU this process may run"),
             ("tools/hil/hil_speed.py", ["--spin", "1000"], "--spin: must be in [0, 1], got 1000"),
             ("tools/hil/hil_speed.py", ["--rates", "5", "--spin", "1"], "past firmware_sim's --spin-us bound"),
             ("tools/hil/hil_speed.py", ["--rates", "1000,1000"], "1000 given twice in '1000,1000'"),
             # (pass 99) a rate firmware_sim cannot tick at ended in exit 1 after measuring the others
             ("tools/hil/hil_speed.py", ["--rates", "1000,333"], "--rates 333: paper_clearance ticks a whole number"),
             ("tools/hil/hil_speed.py", ["--rates", "60000"], "--rates 60000: paper_clearance ticks a whole number"),
             ("tools/hil/worst_tick.py", ["--realtime-seconds", "1e-300"], "0 (skip) or at least 0.001"),
             # (pass 91) a scene given twice started the study; NAME.yaml was looked up as NAME.yaml.yaml
             ("tools/hil/worst_tick.py", ["--realtime-scenes", "paper_ideal,paper_ideal"],
              "'paper_ideal' given twice in 'paper_ideal,paper_ideal'"),
             ("tools/hil/worst_tick.py", ["--realtime-scenes", "paper_ideal.yaml"],
              "'paper_ideal.yaml': give the scene's name without .yaml"),
             ("tools/hil/worst_tick.py", ["--realtime-scenes", "paper_ideal,,paper_clearance"], "an empty item"),
             ("tools/hil/worst_tick.py", ["--realtime-scenes", "./paper_ideal,paper_ideal"], "not a path")]
    for tool, args, words in cases:
        p = subprocess.run(["/usr/bin/python3", str(SOURCE / tool), *args], cwd=tmp_path, capture_output=True,
                           text=True, timeout=60, env={**os.environ, "PYTHONPATH": str(BIN.parent / "python")})
        assert p.returncode == 2 and words in p.stderr and "Traceback" not in p.stderr, (tool, args, p.stderr)
    assert not list(tmp_path.iterdir())


def test_run_stress_refuses_the_outputs_it_writes_itself(tmp_path):
    # (pass 31) --case was always refused by the program for the --csv the script adds, and a user's --csv was
    # CLI11's "At Most 1 required but received 2": said now by the script, before anything is built or run
    floor = subprocess.run(["bash", str(SOURCE / "tools/pointing_study/run_controller_floor.sh"), "--markdown",
                            "m.md"], cwd=tmp_path, capture_output=True, text=True, timeout=60)  # (pass 34)
    assert floor.returncode == 2 and "--markdown: the script writes out/controller_floor/body.md" in floor.stderr, \
        floor.stderr
    for args, words in ((["--case", "paper_clearance"], "--case: one scene writes nothing"),
                        (["--csv", "mine.csv"], "--csv: the script writes out/stress/stress.csv"),
                        (["--page-body=b.md"], "--page-body=b.md: the script writes")):
        p = subprocess.run(["bash", str(SOURCE / "tools/stress/run_stress.sh"), *args], cwd=tmp_path,
                           capture_output=True, text=True, timeout=60)
        assert p.returncode == 2 and words in p.stderr and "nothing run" in p.stderr, (args, p.stderr)
    assert not list(tmp_path.iterdir())


def test_one_at_a_time_never_holds_a_lock_nobody_else_sees(tmp_path, monkeypatch):
    # (pass 33) the holder removes the lock file as it ends: a run that opened the old file just before would lock
    # an orphan while a third run made and locked a new one, both running
    sys.path.insert(0, str(SOURCE / "tools" / "pages"))
    import output_file
    lock = tmp_path / ".out.lock"
    real = output_file.fcntl.flock

    def flock_after_the_holder_left(fd, op):
        lock.unlink(missing_ok=True)  # the holder ends between this run's open and its lock
        return real(fd, op)
    monkeypatch.setattr(output_file.fcntl, "flock", flock_after_the_holder_left)
    with pytest.raises(output_file.Refused, match="another run is writing it"):
        with output_file.one_at_a_time(lock, "--out x"):
            pass
    monkeypatch.setattr(output_file.fcntl, "flock", real)
    with output_file.one_at_a_time(lock, "--out x"):
        assert lock.exists()
    assert not lock.exists()
    # (pass 34) a link under the lock's name: the run made its target (outside --out) and removed the link
    lock.symlink_to(tmp_path / "elsewhere")
    with pytest.raises(output_file.Refused, match="a symbolic link"):
        with output_file.one_at_a_time(lock, "--out x"):
            pass
    assert lock.is_symlink() and not (tmp_path / "elsewhere").exists()
    # (pass 35) a pipe under the lock's name was taken as the lock, and removed when the run ended
    lock.unlink()
    os.mkfifo(lock)
    with pytest.raises(output_file.Refused, match="not a regular file"):
        with output_file.one_at_a_time(lock, "--out x"):
            pass
    assert lock.is_fifo()


PARSED = sorted(str(p.relative_to(SOURCE)) for p in (SOURCE / "tools").rglob("*.py")
                if "ArgumentParser(" in p.read_text() or "page_arguments(" in p.read_text())


@pytest.mark.parametrize("script", PARSED + ["tools/bench/run_bench.sh", "tools/hil/run_hil_bench.sh"])
def test_every_tools_script_answers_version_as_the_programs_do(script):
    # (pass 44) the scripts with a parser and the two wrappers refused --version (exit 2)
    import gimbalsim
    cmd = (["bash"] if script.endswith(".sh") else [sys.executable]) + [str(SOURCE / script), "--version"]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stdout == f"{os.path.basename(script)} {gimbalsim.__version__}\n", \
        (p.returncode, p.stdout, p.stderr)
    assert len(PARSED) >= 20  # the glob found the scripts



@pytest.mark.parametrize("script", PARSED)
def test_every_tools_parser_keeps_the_flag_rules(script):
    # (pass 78) compare_bench.py took --rounds 2 --rounds 3 and --filter= (every benchmark ran): every script's
    # parser starts with output_file.standard_flags (directly or through results_page.page_arguments)
    text = (SOURCE / script).read_text()
    assert "standard_flags(" in text or "page_arguments(" in text or script == "tools/pages/output_file.py", script


MODULES = sorted(str(p.relative_to(SOURCE)) for p in (SOURCE / "tools").rglob("*.py"))


@pytest.mark.parametrize("script", [m for m in MODULES if m not in PARSED])
def test_every_tools_module_run_as_a_program_is_refused(script):
    # (pass 79) budget_speed_specs.py ended in a traceback (exit 1), and five other modules of the scripts
    # (paper_data.py, plot_components.py, plot_joint_kinds.py, study_csv.py, output_file.py) took any argument,
    # did nothing and exited 0: a module run alone says what to run instead, exit 2, as unit_conditioning.py
    p = subprocess.run([sys.executable, str(SOURCE / script), "--bogus"], capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 2 and "not a program" in p.stderr and "Traceback" not in p.stderr, \
        (p.returncode, p.stderr)
    assert len(MODULES) > len(PARSED) >= 20  # the glob found the scripts and the modules


@pytest.mark.parametrize("script", PARSED)
def test_every_tools_script_refuses_an_unknown_flag(script):
    # the scripts with a parser: an unknown flag is exit 2, as in every program (usage.md's exit codes)
    p = subprocess.run([sys.executable, str(SOURCE / script), "--bogus-flag-79"], capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 2 and "Traceback" not in p.stderr, (p.returncode, p.stderr)


@pytest.mark.parametrize("args,named", [(("--rounds", "2", "--rounds", "3"), "--rounds: given twice"),
                                        (("--filter=",), "--filter: an empty value")])
def test_compare_bench_refuses_a_flag_twice_or_empty(args, named, tmp_path):
    bench = BIN / "gimbalsim_bench"
    p = subprocess.run([sys.executable, str(SOURCE / "tools/bench/compare_bench.py"), *args, str(bench), str(bench)],
                       capture_output=True, text=True, timeout=60, cwd=tmp_path)
    assert p.returncode == 2 and f"compare_bench.py: error: {named}" in p.stderr, (p.returncode, p.stderr)
    assert "BM_" not in p.stdout  # nothing timed


@pytest.mark.parametrize("flags,named", [(("--benchmark_filter=x", "--benchmark_filter=BM_Rk4"),
                                          "--benchmark_filter: given twice"),
                                         (("--benchmark_min_time=0x1",), "--benchmark_min_time: must be a plain"),
                                         (("--benchmark_min_time=nan",), "--benchmark_min_time: must be a plain"),
                                         (("--benchmark_repetitions=010",),
                                          "--benchmark_repetitions: must be a whole"),
                                         (("--benchmark_out_format=bogus",),
                                          "--benchmark_out_format: must be one of console, json, csv"),
                                         (("--benchmark_time_unit=yr",), "--benchmark_time_unit: must be one of ns"),
                                         (("--benchmark_enable_random_interleaving=maybe",),
                                          "--benchmark_enable_random_interleaving: must be one of true, false"),
                                         (("--benchmark_context=foo",), "--benchmark_context: must be KEY=VALUE"),
                                         # (pass 93) a key twice was taken; '[' ran nothing and exited 0
                                         (("--benchmark_context=a=1,a=2",),
                                          "--benchmark_context: must be KEY=VALUE[,KEY=VALUE...], each"),
                                         (("--benchmark_filter=[",),
                                          "--benchmark_filter: '[' is not a regular expression"),
                                         # (pass 95) counters aborted the run (SIGABRT); --v=abc, a word and a later
                                         # version's flag got the library's "unrecognized"; a bare string flag too
                                         (("--benchmark_perf_counters=CYCLES",),
                                          "--benchmark_perf_counters: this build's Google Benchmark"),
                                         (("--v=abc",), "--v: must be a whole number in [0, 10]"),
                                         (("--v=1", "--v=2"), "--v: given twice"),
                                         (("positional",), "'positional': not a flag of this program"),
                                         (("--benchmark_dry_run=true",), "'--benchmark_dry_run=true': not a flag"),
                                         (("--benchmark_filter",), "--benchmark_filter: takes a value after its '='")])
def test_the_benchmarks_read_their_flags_as_the_programs_do(flags, named, tmp_path):
    # (pass 78) a second filter won, 0x1 and 010 (ten repetitions) were taken, and min_time=nan never ended;
    # (pass 91) a format or time unit outside its choice printed the usage and exited 0, a bool took "maybe"
    p = subprocess.run([str(BIN / "gimbalsim_bench"), *flags], capture_output=True, text=True, timeout=60,
                       cwd=tmp_path)
    assert p.returncode == 2 and f"gimbalsim_bench: error: {named}" in p.stderr, (p.returncode, p.stderr)
    p = subprocess.run(["bash", str(SOURCE / "tools/bench/run_bench.sh"), *flags], capture_output=True, text=True,
                       timeout=60, cwd=tmp_path, env={**os.environ, "BENCH": str(BIN / "gimbalsim_bench")})
    told = "the script sets it; give REPS=N" if "repetitions" in named else \
        "the script writes the JSON" if "out_format" in named else named  # the script's own flags
    assert p.returncode == 2 and told in p.stderr, (p.returncode, p.stderr)


@pytest.mark.parametrize("program,filter_", [("gimbalsim_bench", "^BM_ForwardDynamics<FixedIdeal>$"),
                                             ("gimbalsim_bench_loop", "NOTHING"), ("gimbalsim_bench_tick", "NOTHING")])
def test_a_benchmarks_json_is_written_by_the_writers_rules(program, filter_, tmp_path):
    # (pass 86) --benchmark_out was the library's: it wrote over a scene the benchmarks read, through a link, over
    # the program itself, an empty file when nothing ran and a file beside a refused run
    shutil.copytree(SOURCE / "tools/scenes", tmp_path / "tools/scenes")
    shutil.copy(BIN / program, tmp_path / program)
    scene = tmp_path / "tools/scenes/paper_ideal.yaml"
    (tmp_path / "target.json").write_text("keep")
    (tmp_path / "link.json").symlink_to("target.json")
    before = {p: p.read_bytes() for p in (scene, tmp_path / program)}

    def bench(out, *more):
        return subprocess.run([str(tmp_path / program), f"--benchmark_filter={filter_}", "--benchmark_min_time=0.001",
                               f"--benchmark_out={out}", *more], capture_output=True, text=True, timeout=60,
                              cwd=tmp_path)
    for out, named in ((scene, "the same file as the input"), ("link.json", "is a symbolic link"),
                       (tmp_path / program, "the same file as this program")):
        p = bench(out)
        assert p.returncode == 2 and named in p.stderr and "refused, nothing run" in p.stderr, p.stderr
    assert all(p.read_bytes() == b for p, b in before.items()) and (tmp_path / "target.json").read_text() == "keep"
    p = subprocess.run([str(tmp_path / program), "--benchmark_filter=NOTHING", "--benchmark_out=none.json"],
                       capture_output=True, text=True, timeout=60, cwd=tmp_path)
    # (pass 95) a filter that matched none exited 0, as if it had measured: refused, as run_bench.sh refuses it
    assert p.returncode == 2 and "no benchmark ran: none.json not written" in p.stderr, p.stderr
    assert f"{program}: error: --benchmark_filter matched none of this program's benchmarks" in p.stderr, p.stderr
    assert not (tmp_path / "none.json").exists()
    if filter_ != "NOTHING":  # a run that ran is written whole, as the library writes it
        p = bench("good.json", "--benchmark_out_format=json")
        assert p.returncode == 0, p.stderr
        assert '"name": "BM_ForwardDynamics<FixedIdeal>"' in (tmp_path / "good.json").read_text()


@pytest.mark.parametrize("arg", ["--benchmark_filter=", "--benchmark_min_time="])
def test_the_bench_script_refuses_nothing_after_a_flags_equals(arg, tmp_path):
    # (pass 76) --benchmark_filter= ran every benchmark: nothing after '=' is refused, as by the programs
    p = subprocess.run(["bash", str(SOURCE / "tools/bench/run_bench.sh"), arg], capture_output=True, text=True,
                       timeout=60, cwd=tmp_path)
    assert p.returncode == 2 and f"run_bench.sh: {arg}: an empty value after the '='; nothing run" in p.stderr, p.stderr
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("variable,command", [
    ("REPS", ["bash", "tools/bench/run_bench.sh"]), ("OUT", ["bash", "tools/bench/run_bench.sh"]),
    ("BENCH", ["bash", "tools/bench/run_bench.sh"]), ("MUJOCO_REPEATS", ["bash", "tools/bench/run_bench.sh"]),
    ("GIMBALSIM_BUILD", ["bash", "tools/bench/run_bench.sh"]), ("GIMBALSIM_BUILD", ["bash", "tools/run_paper.sh"]),
    ("GIMBALSIM_BUILD", [sys.executable, "tools/bench/py_bench.py"]),
])
def test_a_variable_set_to_nothing_is_refused_as_an_empty_flag_value(variable, command, tmp_path):
    # (pass 84) REPS= ran 5 repetitions and OUT= kept no JSON: an empty value was taken as none given
    command = [c if c.startswith(("bash", "/")) else str(SOURCE / c) for c in command]
    p = subprocess.run(command, capture_output=True, text=True, timeout=60, cwd=tmp_path,
                       env={**os.environ, variable: ""})
    assert p.returncode == 2 and f"{variable}=: an empty value" in p.stderr and "nothing run" in p.stderr, p.stderr
    assert os.listdir(tmp_path) == []


def test_compare_bench_refuses_with_2_naming_the_side_before_timing_either(tmp_path):
    # (pass 76) a binary that cannot run ended with 1 (the docstring says 2), NEW was checked only after OLD had
    # been timed, and from outside the repository OLD was blamed for the scenes it could not find
    script = str(SOURCE / "tools/bench/compare_bench.py")
    ran = tmp_path / "old_ran"
    old = tmp_path / "old.sh"
    old.write_text(f"#!/bin/sh\ntouch '{ran}'\nexit 1\n")
    old.chmod(0o755)
    compare = lambda *args: subprocess.run([sys.executable, script, *map(str, args)], capture_output=True,  # noqa
                                           text=True, timeout=300, cwd=tmp_path)
    p = compare(old, tmp_path / "nosuch")
    assert p.returncode == 2 and "NEW " in p.stderr and "no such program" in p.stderr, p.stderr
    assert not ran.exists()
    p = compare(old, BIN / "gimbalsim_bench")
    assert p.returncode == 2 and f"OLD {old}: cannot run it" in p.stderr, p.stderr
    p = compare(BIN / "gimbalsim_bench", BIN / "gimbalsim_bench", "--filter", "BM_Rk4<FloatingIdeal>", "--rounds", 1,
                "--min-time", 0.01)
    assert p.returncode == 0 and "BM_Rk4<FloatingIdeal> [ns]" in p.stdout, p.stderr
