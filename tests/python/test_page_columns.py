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


def _pointing_row(peak="2e-06", track_ticks="5001", limited_track="0", run="paper_ideal_perfect", c="0"):
    return (f"{run},paper_ideal,perfect,{c},{peak},1e-06,3e-06,{track_ticks},0,{limited_track},0,ideal/ideal,nan,nan,"
            "nan,nan,encoders,ok,,,\n")


@pytest.mark.parametrize("peak,said", [(" 1e-3", "' 1e-3' is not a finite decimal number"),
                                       ("-2", "-2 is outside [0, 3.14159]"),
                                       ("1e-400", "'1e-400' is too small for a double"),
                                       ("abc", "'abc' is not a finite decimal number"),
                                       ("inf", "'inf' is not a finite decimal number")])
def test_a_pointing_cell_the_study_cannot_write_is_refused(tmp_path, peak, said):
    # (pass 49) an unreadable cell was a bare n/a, -2 a peak on the page, ' 1e-3' taken, 1e-400 shown as 0
    repo = _page_repository(tmp_path)
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "summary.csv").write_text(POINTING_HEADER + _pointing_row(peak))
    before = _pages(repo)
    p = _run(repo, "tools/pointing_study/pointing_page.py", "--dir", "d", cwd=tmp_path)
    _refused_and_kept(p, repo, before, f"summary.csv:2: column peak_track_rad: {said}")


def test_what_the_pointing_study_writes_makes_the_page(tmp_path):
    repo = _page_repository(tmp_path)
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "summary.csv").write_text(
        POINTING_HEADER + _pointing_row() + _pointing_row("nan", "0", "nan", "paper_clearance_c=0.1mm", "0.0001"))
    p = _run(repo, "tools/pointing_study/pointing_page.py", "--dir", "d", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    page = (repo / "docs" / "results" / "closed_loop_clearance.md").read_text()
    assert "| paper_clearance_c=0.1mm | paper_ideal | perfect | encoders | 0.1 | n/a | 1.00e-06 |" in page
    assert "| 0 / n/a |" in page and "peak error while tracking 2e-06 rad ideal" in page


WORKPREC_HEADER = ("scene,policy,h_s,substep_s,sweep_key,sweep_value,ok,cpu_s_per_sim_s,bore_err_max_rad,substeps,"
                   "pareto\n")


@pytest.mark.parametrize("row,said", [
    ("paper_clearance,plain,0.001,nan,,,1,0.5,-1,100,1\n", "column bore_err_max_rad: -1 is outside [0, inf]"),
    ("paper_clearance,plain,0.001,nan,,,1,0.5,1e-400,100,1\n", "'1e-400' is too small for a double"),
    ("paper_clearance,adaptive,0.001,nan,,,1,0.5,1e-07,100,1\n", "column substep_s: nan is no figure"),
    ("paper_clearance,plain,0.001,nan,,,1 ,0.5,1e-07,100,1\n", "column ok: '1 ' is no flag"),
    ("paper_clearance,plain,0.001,nan,,,yes,0.5,1e-07,100,1\n", "column ok: 'yes' is no flag"),
    ("paper_clearance,plain,0.001,nan,,,1,0.5,1e-07,1.5,1\n", "column substeps: '1.5' is no whole number")])
def test_a_workprec_point_the_tool_cannot_write_is_refused(tmp_path, row, said):
    # (pass 49) an ok point with error -1 was named cheapest, 1e-400 shown as 0, an adaptive point's nan sub-step
    # put on the page and its index line; an ok cell '1 ' or 'yes' was a failed point without a word
    repo = _page_repository(tmp_path)
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "workprec.csv").write_text(WORKPREC_HEADER + row)
    before = _pages(repo)
    _refused_and_kept(_run(repo, "tools/workprec/workprec_page.py", "--dir", "d", cwd=tmp_path), repo, before,
                      said)


def _bench(**change):
    row = {"run_type": "aggregate", "run_name": "BM_Y", "aggregate_name": "median", "cpu_time": 5.0,
           "time_unit": "ns", "repetitions": 3}
    rows = [dict(row), dict(row, aggregate_name="min", cpu_time=4.0)]
    rows[0].update(change)
    return json.dumps({"context": {}, "benchmarks": rows})


@pytest.mark.parametrize("change,said", [({"repetitions": None}, "repetitions None"),
                                         ({"repetitions": 0}, "repetitions 0"),
                                         ({"repetitions": -1}, "repetitions -1"),
                                         ({"cpu_time": -1.0}, "cpu_time -1.0"),
                                         ({"cpu_time": 0}, "cpu_time 0"),
                                         ({"time_unit": "xs"}, "cpu_time 5.0 'xs'")])
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


def _png_claiming(path, width, height):
    """A PNG whose header claims width x height pixels (its data is never read)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
                     + chunk(b"IDAT", zlib.compress(b"\0")) + chunk(b"IEND", b""))


@pytest.mark.parametrize("case,said", [
    ("jpeg", "a JPEG image"), ("large", "a PNG image of 5000 x 5000 pixels"), ("bomb", "decompression bomb"),
    ("json NaN", "NaN is no JSON number"), ("json Infinity", "Infinity is no JSON number"),
    ("json -1", "impacts -1 is no figure"), ("json null", "substeps None is no figure"),
    ("json 0 step", "integrator.step_s 0 is no figure"),
    ("summary x : y", "no 'max pointing error : <rad>' line"), ("set", "'free text' is no override")])
def test_a_paper_run_output_the_tools_cannot_write_is_refused(tmp_path, case, said):
    # (pass 49) a decompression bomb was a traceback, a JPEG named .png was taken, the run summaries' NaN, -1, null
    # and Infinity were put on the page, a summary "x : y" made a page, and --set took any text
    repo = _page_repository(tmp_path)
    run = tmp_path / "run"
    _paper_run(run, "  x : y\n" if case == "summary x : y" else "  max pointing error : 1.0e-03 rad\n")
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
    extra = ["--set", "free text"] if case == "set" else []
    _refused_and_kept(_run(repo, "tools/paper/paper_page.py", "--dir", str(run), *extra, cwd=tmp_path), repo, before,
                      said)
