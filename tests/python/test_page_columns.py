"""Issue 41 (pass 49), the page scripts read a study's outputs by its writer's column rules: a cell the study
cannot have written (' 1e-3', -2 for an error, 1e-400 read as 0, '1 ' for a flag, a repetition count of 0, a
JSON NaN, a JPEG under a PNG's name) is refused (exit 2) naming where, and the committed page is kept; what the
study does write makes the page."""
import json
import struct
import subprocess
import sys
import zlib

import pytest

from test_page_rules import POINTING_HEADER, _page_repository, _pages, _paper_run


def _run(repo, script, *args, cwd):
    return subprocess.run([sys.executable, str(repo / script), *args, "--command", "c"], cwd=cwd,
                          capture_output=True, text=True, timeout=60)


def _refused_and_kept(p, repo, before, said):
    assert p.returncode == 2 and said in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert _pages(repo) == before


def _pointing_row(peak="2e-06", track_ticks="5001", limited_track="0", run="paper_ideal_perfect", c="0",
                  motor="0"):
    rms = "nan" if peak == "nan" else "1e-06"
    return (f"{run},paper_ideal,perfect,{c},{peak},{rms},3e-06,{track_ticks},0,{limited_track},{motor},ideal/ideal,nan,"
            "nan,nan,nan,encoders,ok,,,\n")


def _pointing_study(tmp_path, text, config=True):
    """A study folder as gimbalsim_pointing_study leaves it: summary.csv (text) and config.txt."""
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "summary.csv").write_bytes(text.encode())
    if config:
        (tmp_path / "d" / "config.txt").write_text("azimuth.kp: 7344\n")


@pytest.mark.parametrize("peak,said", [(" 1e-3", "' 1e-3' is not a finite decimal number"),
                                       ("-2", "-2 is outside [0, 3.14159]"),
                                       ("1e-400", "'1e-400' is too small for a double"),
                                       ("abc", "'abc' is not a finite decimal number"),
                                       ("inf", "'inf' is not a finite decimal number")])
def test_a_pointing_cell_the_study_cannot_write_is_refused(tmp_path, peak, said):
    # (pass 49) an unreadable cell was a bare n/a, -2 a peak on the page, ' 1e-3' taken, 1e-400 shown as 0
    repo = _page_repository(tmp_path)
    _pointing_study(tmp_path, POINTING_HEADER + _pointing_row(peak))
    before = _pages(repo)
    p = _run(repo, "tools/pointing_study/pointing_page.py", "--dir", "d", cwd=tmp_path)
    _refused_and_kept(p, repo, before, f"summary.csv:2: column peak_track_rad: {said}")


ROW, ROW_CLEARANCE = _pointing_row(), _pointing_row(run="paper_clearance_c=0.1mm", c="0.0001")


@pytest.mark.parametrize("text,config,said", [
    (POINTING_HEADER + _pointing_row(motor="banana"), True, "summary.csv:2: column motor_limited_ticks: 'banana'"),
    (POINTING_HEADER + ROW + _pointing_row("nan", "500", "0", "paper_clearance_c=0.1mm", "0.0001"), True,
     "summary.csv:3: track_ticks 500 with peak_track_rad nan"),
    ((POINTING_HEADER + ROW).replace("\n", "\r\n"), True, "a carriage return on line 1"),
    ("\ufeff" + POINTING_HEADER + ROW, True, "summary.csv: a byte-order mark"),
    (POINTING_HEADER + ROW + ROW_CLEARANCE + ROW, True, "summary.csv:4: run 'paper_ideal_perfect' again (line 2)"),
    (POINTING_HEADER + ROW + ROW_CLEARANCE, False, "config.txt: cannot be read"),
    (POINTING_HEADER + _pointing_row("nan", "0", "nan"), True, "no run has a figure while tracking")])
def test_a_pointing_study_its_program_cannot_write_makes_no_page(tmp_path, text, config, said):
    # (pass 50) an unread column, nan over 500 tracking ticks, CRLF and a run held twice made a page; a BOM was a
    # KeyError; a missing config.txt dropped its section; a study with no tracking replaced the page with n/a
    repo = _page_repository(tmp_path)
    _pointing_study(tmp_path, text, config)
    before = _pages(repo)
    _refused_and_kept(_run(repo, "tools/pointing_study/pointing_page.py", "--dir", "d", cwd=tmp_path), repo, before,
                      said)


def test_what_the_pointing_study_writes_makes_the_page(tmp_path):
    repo = _page_repository(tmp_path)
    _pointing_study(tmp_path, POINTING_HEADER + ROW + _pointing_row("nan", "0", "nan", "paper_clearance_c=0.1mm",
                                                                     "0.0001"))
    p = _run(repo, "tools/pointing_study/pointing_page.py", "--dir", "d", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    page = (repo / "docs" / "results" / "closed_loop_clearance.md").read_text()
    assert "| paper_clearance_c=0.1mm | paper_ideal | perfect | encoders | 0.1 | n/a | n/a |" in page
    assert "| 0 / n/a |" in page and "peak error while tracking 2e-06 rad ideal" in page
    assert "azimuth.kp: 7344" in page


@pytest.mark.parametrize("ticks,said", [(1000, True), (3000, False)])
def test_the_pointing_page_counts_the_ticks_of_the_per_tick_csv(tmp_path, ticks, said):
    # the limit-cycle paragraph: a spatial run whose torque sat at its limit in more than 10 % of the study's ticks,
    # one per line of pointing_error.csv after its header (counted, not read whole)
    repo = _page_repository(tmp_path)
    spatial = ("paper_spatial2_c=0.1mm,paper_spatial2,perfect,0.0001,2e-06,1e-06,3e-06,500,200,0,0,ideal/spatial,"
               "nan,nan,nan,nan,encoders,ok,,,\n")
    _pointing_study(tmp_path, POINTING_HEADER + ROW + spatial)
    (tmp_path / "d" / "pointing_error.csv").write_text("t_s,a\n" + "0,0\n" * ticks)
    p = _run(repo, "tools/pointing_study/pointing_page.py", "--dir", "d", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    page = (repo / "docs" / "results" / "closed_loop_clearance.md").read_text()
    assert (f"In 1 of the 2 runs a torque command sits at its limit for more than 10 % of the {ticks} ticks "
            "(paper_spatial2)" in page) == said, page


WORKPREC_HEADER = ("scene,policy,h_s,substep_s,event_tol_s,sweep_key,sweep_value,ok,cpu_s_per_sim_s,repeats,"
                   "bore_err_max_rad,bore_err_end_rad,theta1_err_max_rad,theta2_err_max_rad,peak_force_err_rel,"
                   "momentum_drift_rel,substeps,impacts,pareto,note\n")  # points.cpp kCsvColumns


def _point(policy="plain", substep="nan", ok="1", err="1e-07", substeps="100", repeats="3", impacts="5", swept=","):
    return (f"paper_clearance,{policy},0.001,{substep},1e-08,{swept},{ok},0.5,{repeats},{err},1e-07,1e-07,1e-07,"
            f"0.01,1e-09,{substeps},{impacts},1,\n")


@pytest.mark.parametrize("row,said", [
    (_point(err="-1"), "column bore_err_max_rad: -1 is outside [0, inf]"),
    (_point(err="1e-400"), "'1e-400' is too small for a double"),
    (_point(policy="adaptive"), "column substep_s: nan is no figure"),
    (_point(ok="1 "), "column ok: '1 ' is no flag"), (_point(ok="yes"), "column ok: 'yes' is no flag"),
    (_point(substeps="1.5"), "column substeps: '1.5' is no whole number"),
    # (pass 50) columns the page does not show were not read at all
    (_point(repeats="banana"), "column repeats: 'banana' is no whole number"),
    (_point(impacts="-1"), "column impacts: -1 is outside"),
    # (pass 51) a swept key's value was shown as the setting, whatever it was
    (_point(swept="sim.substep_tol,banana"), "column sweep_value of sim.substep_tol: 'banana' is not a finite decimal number"),
    (_point(swept=",1e-6"), "column sweep_value: '1e-6' with no sweep_key"),
    # (pass 52) a value outside its key's range, and a key no policy sweeps
    (_point(swept="sim.substep_tol,999999"), "column sweep_value of sim.substep_tol: 999999 is outside (0, 1)"),
    (_point(swept="sim.substep_tol,0"), "column sweep_value of sim.substep_tol: 0 is outside (0, 1)"),
    (_point(swept="banana key,1e-6"), "column sweep_key: 'banana key' is no key the policy table sweeps"),
    # (pass 69) one point twice (which would the page show?), nan in a column the page does not show
    (_point() + _point(), "workprec.csv:3: the point of line 2 again"),
    (_point().replace(",0.01,", ",nan,"), "column peak_force_err_rel: nan on a point that ran ok without the note"),
    (_point().replace("1e-07,1e-07,1e-07,", "1e-07,nan,1e-07,"), "column bore_err_end_rad: nan is no figure")])
def test_a_workprec_point_the_tool_cannot_write_is_refused(tmp_path, row, said):
    # (pass 49) an ok point with error -1 was named cheapest, 1e-400 shown as 0, an adaptive point's nan sub-step
    # put on the page and its index line; an ok cell '1 ' or 'yes' was a failed point without a word
    repo = _page_repository(tmp_path)
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "workprec.csv").write_text(WORKPREC_HEADER + row)
    before = _pages(repo)
    _refused_and_kept(_run(repo, "tools/workprec/workprec_page.py", "--dir", "d", cwd=tmp_path), repo, before,
                      said)


def _bench(extra=(), **change):
    row = {"run_type": "aggregate", "run_name": "BM_Y", "aggregate_name": "median", "cpu_time": 5.0,
           "time_unit": "ns", "repetitions": 3}
    rows = [dict(row), dict(row, aggregate_name="min", cpu_time=4.0), *[dict(row, **e) for e in extra]]
    rows[0].update(change)
    return json.dumps({"context": {}, "benchmarks": rows})


@pytest.mark.parametrize("change,said", [({"repetitions": None}, "repetitions None"),
                                         ({"repetitions": 0}, "repetitions 0"),
                                         ({"repetitions": -1}, "repetitions -1"),
                                         ({"cpu_time": -1.0}, "cpu_time -1.0"),
                                         ({"cpu_time": 0}, "cpu_time 0"),
                                         ({"time_unit": "xs"}, "cpu_time 5.0 'xs'"),
                                         # (pass 50) each of these was shown
                                         ({"extra": [{"cpu_time": 6.0}]}, "a second 'median' aggregate"),
                                         ({"cpu_time": 3.0}, "min 4.0 ns above its median 3.0 ns"),
                                         ({"repetitions": 10**30}, "repetitions 1000000000000000000000000000000"),
                                         ({"cpu_time": 1e308}, "cpu_time 1e+308 'ns'")])
def test_a_benchmark_figure_google_benchmark_cannot_write_is_refused(tmp_path, change, said):
    # (pass 49) repetitions null, 0 or -1 and a CPU time <= 0 were put on the page
    repo = _page_repository(tmp_path)
    (tmp_path / "b.json").write_text(_bench(**change))
    before = _pages(repo)
    _refused_and_kept(_run(repo, "tools/bench/speed_page.py", "--bench-json", "b.json", "--no-mujoco", "t",
                           cwd=tmp_path), repo, before, said)


def test_a_benchmark_timed_in_microseconds_is_shown_in_nanoseconds(tmp_path):
    # (pass 49) it was dropped from the table without a word
    repo = _page_repository(tmp_path)
    (tmp_path / "b.json").write_text(_bench(time_unit="us"))
    p = _run(repo, "tools/bench/speed_page.py", "--bench-json", "b.json", "--no-mujoco", "t", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert "| BM_Y | 5000.0 | 4.0 |" in (repo / "docs" / "results" / "speed.md").read_text()


def test_a_bar_in_a_benchmark_name_stays_in_its_cell(tmp_path):
    # (pass 50) 'BM_X|evil' added a column to the table
    repo = _page_repository(tmp_path)
    (tmp_path / "b.json").write_text(_bench().replace("BM_Y", "BM_X|evil"))
    p = _run(repo, "tools/bench/speed_page.py", "--bench-json", "b.json", "--no-mujoco", "t", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert "| BM_X\\|evil | 5.0 | 4.0 |" in (repo / "docs" / "results" / "speed.md").read_text()


def _png_claiming(path, width, height):
    """A PNG whose header claims width x height pixels (its data is never read)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                     + chunk(b"IDAT", zlib.compress(b"\0")) + chunk(b"IEND", b""))


@pytest.mark.parametrize("case,said", [
    ("jpeg", "a JPEG image"), ("large", "a PNG image of 5000 x 5000 pixels"), ("bomb", "decompression bomb"),
    ("json NaN", "NaN is no JSON number"), ("json Infinity", "Infinity is no JSON number"),
    ("json -1", "impacts: -1 is outside [0, inf]"), ("json null", "substeps: None is no whole number"),
    ("json 0 step", "integrator.step_s: 0 is outside (0, inf]"),
    ("summary x : y", "no 'max pointing error : <rad>' line"),
    # (pass 50) each of these was put on the page; the overrides were a --set of any text, never compared
    ("  clearance c : nan mm (from x)\n", "a figure that is no number"),
    ("  joint-2 force peaks : clearance 872.8 N / ideal 0.0 N = inf (summary)\n", "a figure that is no number"),
    ("  peak contact force : -846.7 N at t = 0.03 s (summary)\n", "-846.7 N out of range"),
    ("  max pointing error : 99 rad (0.04122 deg) at t = 0.5 s\n", "99 rad out of range"),
    ("  final pointing error : 0.001 rad (0.05 deg) at t = -1 s\n", "-1 s out of range"),
    ("  final pointing error : 0.001 rad (0.5 deg) at t = 1 s\n", "0.001 rad is not 0.5 deg"),
    ("  impacts : 1.5 (summary)\n", "an impact count that is no whole number"),
    ("overrides differ", "were given different overrides")])
def test_a_paper_run_output_the_tools_cannot_write_is_refused(tmp_path, case, said):
    # (pass 49) a decompression bomb was a traceback, a JPEG named .png was taken, the run summaries' NaN, -1, null
    # and Infinity were put on the page, a summary "x : y" made a page
    repo = _page_repository(tmp_path)
    run = tmp_path / "run"
    line = case if case.startswith("  ") else ""
    _paper_run(run, "  x : y\n" if case == "summary x : y" else "  max pointing error : 1.0e-03 rad\n" + line)
    if case == "overrides differ":
        (run / "ideal.json").write_text((run / "ideal.json").read_text().replace("sim.duration=1", "sim.duration=2"))
    fig = run / "plots" / "fig06_eccentricity.png"
    if case == "jpeg":
        from PIL import Image
        fig.unlink()
        Image.new("RGB", (10, 10)).save(fig, format="JPEG")
    elif case in ("large", "bomb"):
        _png_claiming(fig, *((5000, 5000) if case == "large" else (20000, 20000)))
    elif case.startswith("json"):
        text = (run / "clearance.json").read_text()
        text = {"json NaN": text.replace('"t_end_s": 1', '"t_end_s": NaN'),
                "json Infinity": text.replace('"wall_time_s": 0.1', '"wall_time_s": Infinity'),
                "json -1": text.replace('"impacts": 0', '"impacts": -1'),
                "json null": text.replace('"substeps": 10', '"substeps": null'),
                "json 0 step": text.replace('"step_s": 0.001', '"step_s": 0')}[case]
        (run / "clearance.json").write_text(text)
    before = _pages(repo)
    _refused_and_kept(_run(repo, "tools/paper/paper_page.py", "--dir", str(run), cwd=tmp_path), repo, before, said)


def test_the_paper_page_names_the_overrides_its_runs_were_given(tmp_path):
    repo = _page_repository(tmp_path)
    _paper_run(tmp_path / "run")
    p = _run(repo, "tools/paper/paper_page.py", "--dir", str(tmp_path / "run"), cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert "Overrides given to both runs: `sim.duration=1`." in (repo / "docs" / "results" / "paper.md").read_text()
