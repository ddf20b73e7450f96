"""Pass 14 of the tools' refusals: run_hil_bench.sh's flags with no value
(D5) and the firmware_sim files after -- (D6), the one writer's empty
output path (D12), and plot_paper's cells and CSV forms named as the other
readers name them (D13)."""
import os
import subprocess
import sys
import time

import pytest

from conftest import BIN, SOURCE, run_cli, scene_path

SCRIPT = SOURCE / "tools" / "hil" / "run_hil_bench.sh"
PLOT_BENCH = SOURCE / "tools" / "hil" / "plot_bench.py"
PLOT_PAPER = SOURCE / "tools" / "paper" / "plot_paper.py"
sys.path.insert(0, str(SOURCE / "tools" / "pages"))
import output_file  # noqa: E402


def bench(*args, cwd=None):
    env = {**os.environ, "GIMBALSIM_BUILD": str(BIN.parent)}  # the tests' build, never a build of its own
    port = [] if "--port" in args else ["--port", "7743"]  # a port the test gives is the only one (a flag once)
    return subprocess.run(["bash", str(SCRIPT), *port, *map(str, args)], capture_output=True, text=True,
                          timeout=300, env=env, cwd=cwd)


# ---- D5: a value flag with no value is a refusal naming it (exit 2), not bash's "unbound variable" (exit 1)

@pytest.mark.parametrize("flag", ["--duration", "--scene", "--config", "--rate", "--out", "--port"])
def test_bench_value_flag_without_a_value_is_refused_naming_it(tmp_path, flag):
    p = bench(flag, cwd=tmp_path)
    assert p.returncode == 2, p.stderr
    assert f"run_hil_bench.sh: {flag}: needs a value" in p.stderr and "unbound" not in p.stderr, p.stderr
    assert not os.listdir(tmp_path)


@pytest.mark.parametrize("flag", ["--duration", "--scene", "--config", "--rate", "--out", "--port"])
def test_bench_value_flag_with_an_empty_value_is_refused_naming_it(tmp_path, flag):
    p = bench(flag, "", "--no-plot", cwd=tmp_path)
    assert p.returncode == 2 and f"run_hil_bench.sh: {flag}: an empty value" in p.stderr, p.stderr


# ---- D6: files after -- are the user's, read where the user stands; a refusal costs nothing

def test_bench_relative_faults_after_dashdash_is_read_where_the_user_stands(tmp_path):
    (tmp_path / "hb").mkdir()
    (tmp_path / "myfaults.yaml").write_bytes((SOURCE / "tools" / "faults" / "demo.yaml").read_bytes())
    p = bench("--out", "hb", "--duration", "0.3", "--no-plot", "--", "--faults", "myfaults.yaml", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "hb" / "truth.csv").is_file()
    p = bench("--out", "hb", "--duration", "0.3", "--no-plot", "--", "--faults=myfaults.yaml", cwd=tmp_path)
    assert p.returncode == 0, p.stderr


def test_bench_relative_faults_that_is_an_output_is_refused(tmp_path):
    (tmp_path / "hb").mkdir()
    (tmp_path / "hb" / "firmware.txt").write_text("old\n")
    p = bench("--out", "hb", "--duration", "0.2", "--no-plot", "--", "--faults", "hb/firmware.txt", cwd=tmp_path)
    assert p.returncode == 2 and "an output that is the input --faults" in p.stderr, p.stderr
    assert (tmp_path / "hb" / "firmware.txt").read_text() == "old\n"


def test_bench_missing_file_after_dashdash_is_refused_up_front_and_fast(tmp_path):
    (tmp_path / "hb").mkdir()
    for extra in (["--faults", "nofile.yaml"], ["--faults", "."]):
        t0 = time.monotonic()
        p = bench("--out", "hb", "--duration", "0.2", "--no-plot", "--", *extra, cwd=tmp_path)
        took = time.monotonic() - t0
        assert p.returncode == 2 and f"--faults {extra[1]}" in p.stderr, p.stderr
        assert "pointing_controller" not in p.stderr and took < 5, (took, p.stderr)
        assert not os.listdir(tmp_path / "hb")


def test_bench_profile_after_dashdash_is_refused_naming_config(tmp_path):
    (tmp_path / "hb").mkdir()
    cfg = SOURCE / "controllers" / "config" / "default.yaml"
    for extra in (["--profile", str(cfg)], [f"--profile={cfg}"], ["--truth-csv", "t.csv"]):
        t0 = time.monotonic()
        p = bench("--out", "hb", "--duration", "0.2", "--no-plot", "--", *extra, cwd=tmp_path)
        assert p.returncode == 2 and "At Most 1" not in p.stderr and time.monotonic() - t0 < 5, p.stderr
        assert "the script sets it" in p.stderr, p.stderr
    assert "use --config" in p.stderr or "--out" in p.stderr


def test_bench_firmware_refusal_in_the_run_ends_the_controller_promptly(tmp_path):
    (tmp_path / "hb").mkdir()
    (tmp_path / "bad.yaml").write_text("this: is not a fault schedule\n")
    t0 = time.monotonic()
    p = bench("--out", "hb", "--duration", "0.2", "--no-plot", "--", "--faults", "bad.yaml", cwd=tmp_path)
    assert p.returncode == 2 and "nothing in" in p.stderr, p.stderr
    assert time.monotonic() - t0 < 5 and "no status for" not in p.stderr, p.stderr
    assert not os.listdir(tmp_path / "hb")


# ---- D12: an empty output path is refused as an empty value by the one writer's checks, first

def write_truth(path):
    head = "sim_time_s,theta1_rad,theta2_rad,tau1_Nm,tau2_Nm,pointing_error_rad,faults\n"
    path.write_text(head + "".join(f"{i * 0.001},0.1,0.2,0,0,0.01,0\n" for i in range(5)))


def test_plot_bench_empty_out_is_an_empty_value(tmp_path):
    write_truth(tmp_path / "truth.csv")
    p = subprocess.run([sys.executable, str(PLOT_BENCH), "truth.csv", "--out", ""], capture_output=True, text=True,
                       timeout=120, cwd=tmp_path)
    assert p.returncode == 2 and "an empty value" in p.stderr and "figure format" not in p.stderr, p.stderr


def test_writer_checks_refuse_an_empty_path_first(tmp_path):
    for call in (lambda: output_file.check_before_writing([""], []),
                 lambda: output_file.check_before_writing([str(tmp_path / "a.png"), ""], []),
                 lambda: output_file.check_figure_format("")):
        with pytest.raises(output_file.Refused, match="an empty value"):
            call()
    with pytest.raises(output_file.Refused, match="^--out: an empty value"):
        output_file.check_before_writing([""], [], names=["--out"])
    output_file.check_before_writing([None, str(tmp_path / "a.png")], [])  # None: an output not asked for


# ---- D13: plot_paper names the file line, column and cell; a BOM or CR is named as plot_bench names it

@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    d = tmp_path_factory.mktemp("pp")
    for scene, name in (("paper_ideal", "pp_i.csv"), ("paper_clearance", "pp_c.csv")):
        run_cli("simulate", scene_path(scene), "--set", "sim.duration=0.05", "--out", d / name)
    return d


def plot_paper(d, clear_lines=None, raw=None):
    bad = d / "bad.csv"
    if raw is not None:
        bad.write_bytes(raw)
    else:
        bad.write_text("".join(line + "\n" for line in clear_lines))
    out = d / "plots"
    out.mkdir(exist_ok=True)
    return subprocess.run([sys.executable, str(PLOT_PAPER), "--ideal", d / "pp_i.csv", "--clearance", bad,
                           "--out", out], capture_output=True, text=True, timeout=300)


def with_cell(d, line, col, text):
    lines = (d / "pp_c.csv").read_text().splitlines()
    cells = lines[line - 1].split(",")
    name = lines[0].split(",")[col]
    cells[col] = text
    lines[line - 1] = ",".join(cells)
    return lines, name


@pytest.mark.parametrize("text, why", [("x", "not a finite decimal number: 'x'"),
                                       ("", "not a finite decimal number: ''"),
                                       ("nan", "not a finite decimal number: 'nan'"),
                                       ("inf", "not a finite decimal number: 'inf'"),
                                       ("1e999", "not a finite decimal number: '1e999'")])
def test_plot_paper_bad_cell_names_line_column_and_cell(runs, text, why):
    lines, name = with_cell(runs, 5, 3, text)
    p = plot_paper(runs, lines)
    assert p.returncode == 2, p.stderr
    assert f"bad.csv:5: column {name}: {why}" in p.stderr and "data row" not in p.stderr, p.stderr


def test_plot_paper_bom_and_crlf_are_named(runs):
    raw = (runs / "pp_c.csv").read_bytes()
    p = plot_paper(runs, raw=b"\xef\xbb\xbf" + raw)
    assert p.returncode == 2 and "bad.csv:1: starts with a byte-order mark" in p.stderr, p.stderr
    p = plot_paper(runs, raw=raw.replace(b"\n", b"\r\n"))
    assert p.returncode == 2 and "bad.csv:1: ends in CR (CRLF line ends)" in p.stderr, p.stderr


def test_plot_paper_good_runs_still_plot(runs):
    p = plot_paper(runs, raw=(runs / "pp_c.csv").read_bytes())
    assert p.returncode == 0, p.stderr
