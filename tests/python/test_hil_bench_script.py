"""tools/hil/run_hil_bench.sh writes as the programs do: a link under an
output's name is refused before anything runs, a refused or failed run
leaves --out as it was (it had deleted the previous results first, then
written the refusal through the link), and a run that ends well replaces
the previous run's files whole."""
import os
import subprocess

from conftest import BIN, SOURCE

SCRIPT = SOURCE / "tools" / "hil" / "run_hil_bench.sh"


def bench(out, *args):
    env = {**os.environ, "GIMBALSIM_BUILD": str(BIN.parent)}  # the tests' build, never a build of its own
    return subprocess.run(["bash", str(SCRIPT), "--out", str(out), "--port", "7741", *args], capture_output=True,
                          text=True, timeout=300, env=env)


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
