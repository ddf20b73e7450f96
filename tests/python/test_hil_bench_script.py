"""tools/hil/run_hil_bench.sh writes as the programs do: a link under an
output's name is refused before anything runs, a refused or failed run
leaves --out as it was (it had deleted the previous results first, then
written the refusal through the link), and a run that ends well replaces
the previous run's files whole."""
import os
import subprocess

from conftest import BIN, SOURCE

SCRIPT = SOURCE / "tools" / "hil" / "run_hil_bench.sh"


def bench(out, *args, build=None, cwd=None):
    env = {**os.environ, "GIMBALSIM_BUILD": build or str(BIN.parent)}  # the tests' build, never a build of its own
    return subprocess.run(["bash", str(SCRIPT), "--out", str(out), "--port", "7741", *args], capture_output=True,
                          text=True, timeout=300, env=env, cwd=cwd)


def files(folder):
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def test_a_link_under_an_output_name_is_refused_before_anything_runs(tmp_path):
    out = tmp_path / "bo"
    out.mkdir()
    (tmp_path / "victim.txt").write_text("victim\n")
    (out / "controller.txt").symlink_to("../victim.txt")
    p = bench(out, "--duration", "0.2", "--no-plot")
    assert p.returncode == 2 and "controller.txt: a link" in p.stderr, p.stderr
    assert (tmp_path / "victim.txt").read_text() == "victim\n" and sorted(os.listdir(out)) == ["controller.txt"]


def test_a_refused_run_changes_nothing_and_a_good_one_replaces_the_old_files(tmp_path):
    out = tmp_path / "bo"
    out.mkdir()
    (out / "truth.csv").write_text("precious\n")
    (out / "bench.png").write_text("an old plot\n")
    before = files(out)
    p = bench(out, "--duration", "-1", "--no-plot")
    assert p.returncode == 2 and "nothing in" in p.stderr and "--duration" in p.stderr, p.stderr
    assert files(out) == before  # no .run.* folder left, nothing deleted or written
    p = bench(out, "--duration", "0.2", "--no-plot")
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(out)) == ["controller.csv", "controller.txt", "firmware.txt", "truth.csv"]
    rows = (out / "truth.csv").read_text().splitlines()
    assert rows[0].startswith("utime_us,seq,sim_time_s") and len(rows) == 1 + 201  # t = 0 .. 0.2 s every 1 ms


def test_out_must_be_a_folder_and_a_refused_run_leaves_none_it_made(tmp_path):
    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to("real")
    p = bench(tmp_path / "link", "--duration", "0.2", "--no-plot")
    assert p.returncode == 2 and "a link or not a folder" in p.stderr and not os.listdir(tmp_path / "real"), p.stderr
    (tmp_path / "afile").write_text("x\n")
    p = bench(tmp_path / "afile", "--duration", "0.2", "--no-plot")
    assert p.returncode == 2 and "a link or not a folder" in p.stderr, p.stderr
    p = bench(tmp_path / "new", "--duration", "-1", "--no-plot")
    assert p.returncode == 2 and not (tmp_path / "new").exists(), p.stderr


def test_a_relative_build_is_read_where_the_user_stands_and_never_built(tmp_path):
    (tmp_path / "b").symlink_to(BIN.parent)
    (tmp_path / "o").mkdir()
    p = bench("o", "--duration", "0.2", "--no-plot", build="b", cwd=tmp_path)
    assert p.returncode == 0 and (tmp_path / "o" / "truth.csv").is_file(), p.stderr
    p = bench("o", "--duration", "0.2", "--no-plot", build="nowhere", cwd=tmp_path)
    assert p.returncode == 2 and "GIMBALSIM_BUILD=nowhere: no " in p.stderr, p.stderr
