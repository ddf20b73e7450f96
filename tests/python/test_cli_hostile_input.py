"""Issue 13 (files), process level: `gimbalsim simulate` refuses malformed
scenes, non-regular scene paths, overflowing counts and unsafe outputs with
exit 2 before running; a failed write exits 4 naming the file and leaves no
file under the name; SIGINT and SIGTERM stop a run after a whole row with the
CSV and a summary saying "interrupted" (exit 128 + signal)."""
import json
import os
import resource
import signal
import subprocess
import time

import pytest

from conftest import BIN, SOURCE, run_cli, scene_path

IDEAL = scene_path("paper_ideal")


def refused(*args):
    p = run_cli(*args, check=False)
    assert p.returncode == 2, p.stderr
    return p.stderr


@pytest.mark.parametrize(
    "text, expect",
    [
        ("[a, b]: 1\n", "scene.yaml:1:1: a mapping key must be a plain name"),
        ("sim: &a\n  duration: *a\n", "scene.yaml:1:6: key 'sim': anchors (&name) are not accepted"),
        ("a: &a [x, x]\nb: &b [*a, *a]\nc: [*b, *b]\n", "scene.yaml:1:4: key 'a': anchors"),
        ("a: " + "[" * 5000 + "]" * 5000 + "\n", "key 'a': nested deeper than 16 levels"),
        ("sim:\n  duration: 1\n---\nsim: {}\n", "scene.yaml:3:1: more than one YAML document"),
        ("sim:\n  duration: 1\n  duration: 2\n", "scene.yaml:3:3: key 'sim.duration': given twice"),
        ("sim:\n  duration: [1, 2\n", "scene.yaml:"),
        ("sim:\n  duration: 1e300\n", "scene.yaml:2:3: key 'sim.duration': gives 1e+303 steps"),
    ],
)
def test_malformed_scene_exits_2_with_place_and_key(tmp, text, expect):
    scene = tmp / "scene.yaml"
    scene.write_text(text)
    err = refused("simulate", scene, "--out", tmp / "o.csv")
    assert expect in err
    assert not (tmp / "o.csv").exists()


def test_set_value_refused_with_its_index(tmp):
    err = refused("simulate", IDEAL, "--set", "sim.duration=0.1", "--set", "sim.step=&a 1", "--out", tmp / "o.csv")
    assert "--set #2 'sim.step=&a 1': key 'sim.step': anchors" in err


def test_non_regular_scene_paths_are_refused_unread(tmp):
    fifo = tmp / "fifo"
    os.mkfifo(fifo)
    for path, kind in [(tmp, "a directory"), ("/dev/zero", "a character device"), (fifo, "a FIFO")]:
        err = refused("simulate", path, "--out", tmp / "o.csv")
        assert f"{path}: cannot open scene file: {kind}, not a regular file" in err


def test_outputs_must_be_distinct_from_each_other_and_the_scene(tmp):
    scene = tmp / "scene.yaml"
    scene.write_bytes(IDEAL.read_bytes())
    err = refused("simulate", scene, "--out", tmp / "o.csv", "--summary", f"{tmp}/./o.csv")
    assert "the same file as another output" in err
    err = refused("simulate", scene, "--out", f"{tmp}/./scene.yaml")
    assert "the same file as the input" in err
    assert scene.read_bytes() == IDEAL.read_bytes()
    assert not (tmp / "o.csv").exists()


def test_symlink_and_device_outputs_are_refused(tmp):
    target = tmp / "target.csv"
    target.write_text("keep\n")
    (tmp / "link.csv").symlink_to(target)
    assert "link.csv: is a symbolic link" in refused("simulate", IDEAL, "--out", tmp / "link.csv")
    assert target.read_text() == "keep\n"
    assert "/dev/full: exists and is not a regular file" in refused("simulate", IDEAL, "--out", "/dev/full")


def _limit_file_size():
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (64 * 1024, resource.RLIM_INFINITY))


def test_a_failed_write_exits_4_naming_the_file_and_leaves_no_file(tmp):
    """A full disk, without root: RLIMIT_FSIZE makes write() fail (EFBIG)."""
    out = tmp / "o.csv"
    out.write_text("previous\n")
    p = subprocess.run([str(BIN / "gimbalsim"), "simulate", str(IDEAL), "--out", str(out), "--summary",
                        str(tmp / "s.json")], capture_output=True, text=True, timeout=300,
                       preexec_fn=_limit_file_size)
    assert p.returncode == 4, p.stderr
    assert f"{out}: write failed: File too large" in p.stderr
    assert out.read_text() == "previous\n"
    assert not (tmp / "s.json").exists()
    assert sorted(x.name for x in tmp.iterdir()) == ["o.csv"], "no temporary left"


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_signal_ends_the_run_after_a_whole_row(tmp, sig):
    out, summary = tmp / "o.csv", tmp / "s.json"
    proc = subprocess.Popen([str(BIN / "gimbalsim"), "simulate", str(IDEAL), "--set", "sim.duration=1e5",
                             "--set", "sim.momentum_tol=0", "--out", str(out), "--summary", str(summary)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # Wait until rows are being written (the temporary beside the name grows), then signal.
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        temps = [x for x in tmp.iterdir() if x.name.startswith(".o.csv.")]
        if temps and temps[0].stat().st_size > 200_000:
            break
        time.sleep(0.05)
    else:
        proc.kill()
        pytest.fail("no rows written")
    assert not out.exists(), "the name appears only when the run has ended"
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 128 + sig, err
    lines = out.read_text().split("\n")
    assert lines[-1] == "", "the CSV ends with a whole row"
    header, rows = lines[0].split(","), lines[1:-1]
    assert len(rows) > 100
    assert all(len(r.split(",")) == len(header) for r in rows)
    s = json.loads(summary.read_text())
    assert s["status"] == "interrupted"
    assert s["rows"] == len(rows)
    assert float(rows[-1].split(",")[0]) == pytest.approx(s["t_end_s"], rel=1e-11)
    assert signal.Signals(sig).name in s["error"]
    assert s["t_end_s"] < 1e5


def test_workprec_refuses_an_input_or_a_link_under_its_csv_before_running(tmp_path):
    # its policy table under the CSV's name was overwritten with the results (exit 0); a link ran
    # every point before exit 4
    table = tmp_path / "workprec.csv"
    table.write_text((SOURCE / "tools" / "workprec" / "policies.yaml").read_text())
    before = table.read_text()
    cmd = [str(BIN / "gimbalsim_workprec"), "--quick", "--no-mujoco", "--out", str(tmp_path)]
    p = subprocess.run(cmd + ["--policies", str(table)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "gimbalsim_workprec: error: --out:" in p.stderr, p.stderr
    assert table.read_text() == before
    (tmp_path / "link").mkdir()
    os.symlink(tmp_path / "elsewhere.csv", tmp_path / "link" / "workprec.csv")
    shipped = ["--policies", str(SOURCE / "tools" / "workprec" / "policies.yaml")]
    p = subprocess.run(cmd[:-1] + [str(tmp_path / "link")] + shipped, capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "link" in p.stderr and "points" not in p.stdout, p.stderr
