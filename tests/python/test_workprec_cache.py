"""gimbalsim_workprec's reference cache (issue 41, class 6): a cache cut short
is computed again, never trusted; a link, folder or device under a cache's
name is refused before anything runs; a cache that cannot be written leaves
every point measured and written, and the run exits 4."""
import csv
import os
import resource
import signal
import subprocess

from conftest import BIN, SOURCE

POLICIES = SOURCE / "tools" / "workprec" / "policies.yaml"


def workprec_cmd(out, *extra):
    return [str(BIN / "gimbalsim_workprec"), "--quick", "--no-mujoco", "--scenes", "paper_ideal",
           "--scenes-dir", str(SOURCE / "tools" / "scenes"), "--policies", str(POLICIES),
           "--policy", "plain", "--repeats", "1", "--out", str(out), *extra]


def workprec(out, *extra):
    return subprocess.run(workprec_cmd(out, *extra), capture_output=True, text=True, timeout=300)


def errors(out):
    with open(out / "workprec.csv") as f:
        return [(r["h_s"], r["bore_err_max_rad"]) for r in csv.DictReader(f)]


def test_a_cache_cut_short_is_computed_again(tmp_path):
    first = workprec(tmp_path)
    assert first.returncode == 0, first.stderr
    (cache,) = tmp_path.glob("ref_paper_ideal_*.csv")
    whole = cache.read_text()
    want = errors(tmp_path)
    # the file as a full disk or a stopped copy leaves it: its last rows gone
    lines = whole.splitlines(keepends=True)
    cache.write_text("".join(lines[: len(lines) // 2]))
    again = workprec(tmp_path)
    assert again.returncode == 0, again.stderr
    assert "holds" in again.stderr and "computed again" in again.stderr, again.stderr
    assert "cached" not in again.stdout
    assert errors(tmp_path) == want  # the truncated reference had cut every point's comparison short
    assert cache.read_text() == whole
    # cut inside the last number: six numbers still, one digit short, and no final newline
    cache.write_text(whole[:-3])
    again = workprec(tmp_path)
    assert again.returncode == 0 and "cut short inside its last line" in again.stderr, again.stderr
    assert errors(tmp_path) == want and cache.read_text() == whole
    # a row that is not six numbers is not read either
    cache.write_text(whole.replace("\n", "\nx,1,2,3,4,5\n", 3).replace("\nx,1,2,3,4,5\n", "\n", 2))
    third = workprec(tmp_path)
    assert third.returncode == 0 and "is not six plain finite decimals" in third.stderr, third.stderr
    # a cell strtod reads but no writer of ours writes (hex, a leading blank): computed again, not used
    for cell in ("0x1p-3", " 0.125"):
        rows = whole.split("\n")
        cells = rows[2].split(",")
        rows[2] = ",".join([cells[0], cell] + cells[2:])  # the first row under the header line and column names
        cache.write_text("\n".join(rows))
        p = workprec(tmp_path)
        assert p.returncode == 0 and "row 1 is not six plain finite decimals" in p.stderr, (cell, p.stderr)
        assert errors(tmp_path) == want and cache.read_text() == whole
    # a row deleted and the last repeated: the count holds, the rows are not the reference's
    rows = whole.split("\n")
    edited = rows[:5] + rows[6:-1] + [rows[-2], ""]
    assert len(edited) == len(rows)
    cache.write_text("\n".join(edited))
    p = workprec(tmp_path)
    assert p.returncode == 0 and "its rows are not the ones it was written with (edited)" in p.stderr, p.stderr
    assert errors(tmp_path) == want and cache.read_text() == whole
    # the whole cache is used
    fourth = workprec(tmp_path)
    assert fourth.returncode == 0 and "cached" in fourth.stdout and "computed again" not in fourth.stderr


def test_a_link_under_a_caches_name_is_refused_before_running(tmp_path):
    first = workprec(tmp_path)
    (cache,) = tmp_path.glob("ref_paper_ideal_*.csv")
    target = tmp_path / "elsewhere.csv"
    cache.rename(target)
    os.symlink(target, cache)
    p = workprec(tmp_path)
    assert p.returncode == 2, p.stderr
    assert f"{cache}: a reference cache must be a regular file" in p.stderr
    assert "reference:" not in p.stdout  # nothing ran
    cache.unlink()
    cache.mkdir()
    p = workprec(tmp_path)
    assert p.returncode == 2 and "a reference cache must be a regular file" in p.stderr, p.stderr
    assert first.returncode == 0


def test_a_cache_that_cannot_be_written_exits_4_with_every_point_written(tmp_path):
    first = workprec(tmp_path)
    assert first.returncode == 0, first.stderr
    want = errors(tmp_path)
    (cache,) = tmp_path.glob("ref_paper_ideal_*.csv")
    csv_size, cache_size = (tmp_path / "workprec.csv").stat().st_size, cache.stat().st_size
    assert csv_size < cache_size
    cache.unlink()
    (tmp_path / "workprec.csv").unlink()

    def small_files():  # a file-size limit between the two: the cache's write fails, the CSV's not
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, ((csv_size + cache_size) // 2,) * 2)

    cmd = workprec_cmd(tmp_path)
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300, preexec_fn=small_files)
    assert p.returncode == 4, p.stderr
    assert "gimbalsim_workprec: error: reference not cached:" in p.stderr, p.stderr
    assert "scene skipped" not in p.stdout
    assert errors(tmp_path) == want  # every point measured against the reference and written
    assert not list(tmp_path.glob("ref_*.csv")) and not list(tmp_path.glob(".*tmp"))


def test_a_refused_scene_in_the_list_costs_nothing(tmp_path):
    """Every scene is loaded before any runs: one the list names but cannot
    load refuses the whole run (exit 2) before a point is measured or a
    reference cached, wherever it stands in --scenes."""
    cmd = workprec_cmd(tmp_path)
    cmd[cmd.index("paper_ideal")] = "paper_ideal,nosuch"
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 2, r.stderr
    assert "scene nosuch refused" in r.stderr and "nothing run" in r.stderr, r.stderr
    assert "[paper_ideal]" not in r.stdout, r.stdout  # no scene was measured
    assert sorted(os.listdir(tmp_path)) == [], os.listdir(tmp_path)
