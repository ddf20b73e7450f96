"""tools/pages/results_page.py, the writer of every page in docs/results/: the
header has the regenerate command, machine, commit and date lines; the write
is atomic (an existing page is untouched when the write fails); the index
lists the pages."""
import errno
import os
import pathlib
import platform
import re
import subprocess
import sys
import time

import pytest

from conftest import SOURCE

sys.path.insert(0, str(SOURCE / "tools" / "pages"))
import results_page  # noqa: E402

WRITER = SOURCE / "tools" / "pages" / "results_page.py"


def test_header_has_command_machine_commit_date_and_load(tmp_path):
    page = tmp_path / "study.md"
    results_page.write_page(page, "A study", "bash tools/run_study.sh --quick", "| a | b |\n|---|---|\n| 1 | 2 |\n",
                            summary="one line", t0=repr(time.time() - 100), load0="0.50 0.40 0.30 1/100 42")
    lines = page.read_text().splitlines()
    assert lines[0] == results_page.MARK
    assert lines[1] == "# A study"
    assert lines[3] == "Regenerate: `bash tools/run_study.sh --quick`"
    machine, com, date, run = lines[5:9]
    m = re.fullmatch(r"- Machine: (.+), (\d+) cores?, kernel (\S+)", machine)
    assert m, machine
    assert int(m.group(2)) == os.cpu_count()
    assert m.group(3) == platform.release()
    if os.path.exists("/proc/cpuinfo") and "model name" in open("/proc/cpuinfo").read():
        assert m.group(1) == results_page.cpu_model()
    assert re.fullmatch(r"- Commit: ([0-9a-f]{4,40}(-dirty)?|unknown \(not a git work tree\))", com), com
    head = subprocess.run(["git", "-C", str(SOURCE), "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    if head.returncode == 0:
        assert com.split()[-1].removesuffix("-dirty") == head.stdout.strip()
    assert re.fullmatch(r"- Date: \d{4}-\d\d-\d\d \d\d:\d\d UTC", date), date
    assert re.match(r"- Run: 10\d s wall; ", run) and "0.50 0.40 0.30 at start" in run, run
    assert "| 1 | 2 |" in lines
    # The index beside it lists the page with its title, summary and command.
    index = (tmp_path / "README.md").read_text()
    assert "[A study](study.md): one line" in index
    assert "`bash tools/run_study.sh --quick`" in index


def test_failed_write_leaves_the_existing_page_untouched(tmp_path, monkeypatch):
    page = tmp_path / "study.md"
    page.write_text("the committed page\n")

    def full_disk(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(results_page.os, "fsync", full_disk)
    with pytest.raises(OSError):
        results_page.write_page(page, "A study", "cmd", "new body", index=False)
    assert page.read_text() == "the committed page\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.md"], "no temporary left behind"


def test_symlinked_page_is_refused_and_its_target_untouched(tmp_path):
    target = tmp_path / "elsewhere.md"
    target.write_text("keep\n")
    (tmp_path / "study.md").symlink_to(target)
    # (pass 45) a refusal of the writer's rules, exit 2 as every script's (it was an OSError: exit 4)
    with pytest.raises(results_page.output_file.Refused, match="symbolic link"):
        results_page.write_page(tmp_path / "study.md", "A study", "cmd", "body", index=False)
    assert target.read_text() == "keep\n"


def test_command_line_writes_the_page_and_exits_4_on_a_failed_write(tmp_path):
    body = tmp_path / "body.md"
    body.write_text("Body text.\n")
    out = tmp_path / "results" / "x.md"
    out.parent.mkdir()
    p = subprocess.run([sys.executable, str(WRITER), "--page", str(out), "--title", "X", "--command", "make x",
                        "--body", str(body), "--summary", "s"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    text = out.read_text()
    assert text.splitlines()[3] == "Regenerate: `make x`" and text.rstrip().endswith("Body text.")
    assert (out.parent / "README.md").exists()
    # A folder that takes no file (read-only): nothing written, exit 4 naming the problem.
    if os.geteuid() == 0 and subprocess.run(["unshare", "-m", "true"], capture_output=True).returncode != 0:
        pytest.fail("root without `unshare -m`: no way to make a folder read-only here")
    before = out.read_bytes()
    cmd = [sys.executable, str(WRITER), "--page", str(out), "--title", "Y", "--command", "make y", "--body", str(body)]
    if os.geteuid() == 0:  # root writes through modes: a read-only bind mount
        cmd = ["unshare", "-m", "sh", "-c", 'mount --bind -o ro "$0" "$0" && exec "$@"', str(out.parent), *cmd]
    else:
        out.parent.chmod(0o555)
    try:
        p = subprocess.run(cmd, capture_output=True, text=True)
    finally:
        out.parent.chmod(0o755)
    assert p.returncode == 4 and "results_page: " in p.stderr, (p.returncode, p.stderr)
    assert out.read_bytes() == before


def test_the_command_line_keeps_the_writers_rules(tmp_path):
    # (pass 45) the page overwrote its own --body (exit 0), made a missing folder, a link page was exit 4, a
    # missing --body a bare Errno with exit 4, a FIFO --body blocked: each is refused, exit 2, nothing written
    body = tmp_path / "body.md"
    body.write_text("Body text.\n")
    (tmp_path / "target.md").write_text("keep\n")
    (tmp_path / "link.md").symlink_to(tmp_path / "target.md")
    os.mkfifo(tmp_path / "fifo.md")
    (tmp_path / "notes").mkdir()
    (tmp_path / "notes" / "README.md").write_text("my notes\n")
    cases = [("body.md", "body.md", "the same file as the input"),
             ("nodir/x.md", "body.md", "its directory nodir does not exist"),
             ("link.md", "body.md", "symbolic link"),
             ("x.md", "nosuch.md", "--body nosuch.md: cannot be read (No such file or directory)"),
             ("x.md", "fifo.md", "--body fifo.md: not a regular file (a FIFO)"),
             ("x.md", ".", "--body .: not a regular file (a folder)"),
             ("notes/x.md", "body.md", "notes/README.md: not an index this writer made")]
    listing = sorted(p.name for p in tmp_path.rglob("*"))
    for page, src, said in cases:
        p = subprocess.run([sys.executable, str(WRITER), "--page", page, "--title", "X", "--command", "make x",
                            "--body", src], cwd=tmp_path, capture_output=True, text=True, timeout=20)
        assert p.returncode == 2 and "results_page: error: " in p.stderr and said in p.stderr, (page, src, p.stderr)
        assert sorted(q.name for q in tmp_path.rglob("*")) == listing, (page, src)
    assert body.read_text() == "Body text.\n" and (tmp_path / "target.md").read_text() == "keep\n"
    assert (tmp_path / "notes" / "README.md").read_text() == "my notes\n"


def test_dirty_ignores_the_results_folder_only(tmp_path):
    # A scratch repository: a committed tool and a committed page.
    def git(*a):
        subprocess.run(["git", "-C", str(tmp_path), *a], check=True, capture_output=True)

    git("init", "-q")
    (tmp_path / "docs" / "results").mkdir(parents=True)
    (tmp_path / "tool.py").write_text("x = 1\n")
    (tmp_path / "docs" / "results" / "p.md").write_text("page\n")
    git("add", ".")
    git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "c")
    assert not results_page.commit(tmp_path).endswith("-dirty")
    (tmp_path / "docs" / "results" / "p.md").write_text("regenerated page\n")
    assert not results_page.commit(tmp_path).endswith("-dirty")
    (tmp_path / "tool.py").write_text("x = 2\n")
    assert results_page.commit(tmp_path).endswith("-dirty")


@pytest.mark.parametrize("script", ["tools/pointing_study/pointing_page.py", "tools/paper/paper_page.py",
                                    "tools/workprec/workprec_page.py"])
def test_a_page_scripts_dir_is_read_from_where_the_user_stands(script, tmp_path):
    # (pass 43) --dir was joined to the repository and a missing folder or file ended in a traceback (exit 1)
    page = SOURCE / "docs" / "results" / {"pointing_page": "closed_loop_clearance.md", "paper_page": "paper.md",
                                          "workprec_page": "workprec.md"}[pathlib.Path(script).stem]
    before = page.read_bytes()
    (tmp_path / "empty").mkdir()
    default = "out/" + {"pointing_page": "pointing_study", "paper_page": "paper",
                        "workprec_page": "workprec"}[pathlib.Path(script).stem]
    (tmp_path / default).mkdir(parents=True)  # (pass 44) spelled as the default, it was the repository's
    for folder, said in (("nope", "argument --dir: nope: no such folder"),
                         ("empty", f"{tmp_path / 'empty'}/"), (default, f"{tmp_path / default}/")):
        p = subprocess.run([sys.executable, str(SOURCE / script), "--dir", folder, "--command", "x"], cwd=tmp_path,
                           capture_output=True, text=True, timeout=60)
        assert p.returncode == 2 and said in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert page.read_bytes() == before  # refused before writing anything


def test_the_pointing_page_ratio_is_na_over_no_figure():
    # (pass 43) a run that never reached its track printed a bare nan as its ratio to the ideal
    sys.path.insert(0, str(SOURCE / "tools" / "pointing_study"))
    import pointing_page
    nan = float("nan")
    assert pointing_page._ratio(nan, 1e-7) == "n/a" and pointing_page._ratio(2e-7, nan) == "n/a"
    assert pointing_page._ratio(2e-7, 0.0) == "n/a" and pointing_page._ratio(3e-7, 1e-7) == "3"


def test_a_page_scripts_empty_dir_is_refused(tmp_path):
    # (pass 44) --dir '' was read as the current folder
    p = subprocess.run([sys.executable, str(SOURCE / "tools/pointing_study/pointing_page.py"), "--dir", "",
                        "--command", "x"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert p.returncode == 2 and "argument --dir: an empty value" in p.stderr, p.stderr


MEASURING = [("tools/hil/hil_speed.py", "bench_timing.md", []), ("tools/hil/worst_tick.py", "worst_tick.md", []),
             ("tools/bench/perf_report.py", "performance.md", []),
             ("tools/bench/loop_cost.py", "closed_loop_cost.md", ["--results"]),
             ("tools/bench/tick_parts.py", "bench_tick.md", ["--results"]),
             ("tools/bench/sweep_scaling.py", "sweep_scaling.md", ["--results"]),
             ("tools/sweeps/budget_speed.py", "budget_speed.md", ["--results"])]


@pytest.mark.parametrize("script,page,args", MEASURING, ids=[m[1] for m in MEASURING])
def test_a_measuring_script_refuses_its_page_before_it_measures(script, page, args, tmp_path):
    # (pass 45) a page that breaks the rules was found when written, after the measurements (exit 4, or a
    # traceback where the script ended without run_script); each checks it before anything runs, exit 2
    import shutil
    from conftest import BIN
    for part in ("tools", "docs/results"):
        shutil.copytree(SOURCE / part, tmp_path / part, symlinks=True)
    shutil.copytree(SOURCE / "python" / "gimbalsim", tmp_path / "python" / "gimbalsim",
                    ignore=shutil.ignore_patterns("*.so", "__pycache__"))
    shutil.copy(SOURCE / "CMakeLists.txt", tmp_path)
    (tmp_path / "build").symlink_to(BIN.parent)
    (tmp_path / "docs" / "results" / page).unlink(missing_ok=True)
    (tmp_path / "docs" / "results" / page).symlink_to(tmp_path / "elsewhere.md")
    args = args or (["--results", "--build", "build"] if "hil" in script else ["--build", "build"])
    p = subprocess.run([sys.executable, str(tmp_path / script), *args], cwd=tmp_path, capture_output=True,
                       text=True, timeout=120, env={**os.environ, "PYTHONPATH": str(BIN.parent / "python")})
    assert p.returncode == 2 and f"docs/results/{page}: is a symbolic link" in p.stderr, (p.returncode, p.stderr)
    assert "Traceback" not in p.stderr and not (tmp_path / "elsewhere.md").exists()
    assert not (tmp_path / "out").exists(), "nothing measured"


@pytest.mark.parametrize("script", ["tools/hil/hil_speed.py", "tools/hil/worst_tick.py", "tools/bench/tick_parts.py"])
@pytest.mark.parametrize("name,value", [("GIMBALSIM_RESULTS_T0", "abc"), ("GIMBALSIM_RESULTS_LOAD0", "1e3 1 1")])
def test_a_start_inherited_from_the_environment_is_checked_before_measuring(script, name, value, tmp_path):
    # (pass 46) the start a namespace's exec carries in the environment was read only when the page was written
    from conftest import BIN
    args = ["--results", "--build", str(BIN.parent)] + (["--skip-sweep", "--skip-long"] if "hil_speed" in script
                                                        else [])
    p = subprocess.run([sys.executable, str(SOURCE / script), *args], cwd=tmp_path, capture_output=True, text=True,
                       timeout=60, env={**os.environ, name: value, "GIMBALSIM_SPEED_INSIDE": "1"})
    assert p.returncode == 2 and f"error: {name}: " in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert "x real time" not in p.stdout, "nothing measured"


def test_a_study_whose_clearance_runs_have_no_track_figure_says_so(tmp_path, monkeypatch):
    # (pass 53) every clearance run stopped before its track: the page's summary said "up to 2.06e-06 rad
    # (ideal)", the ideal's own figure as the clearances' worst, and the clearance plot drew no clearance point
    # with nothing said
    import csv
    from conftest import BIN, SCENES
    sys.path.insert(0, str(SOURCE / "tools" / "pointing_study"))
    import plot_pointing_study
    import pointing_page
    subprocess.run([str(BIN / "gimbalsim_pointing_study"), "--clearances", "1e-4", "--duration", "3.6", "--sensors",
                    "perfect", "--out", str(tmp_path), "--ideal-scene", str(SCENES / "paper_ideal.yaml"),
                    "--clearance-scene", str(SCENES / "paper_clearance.yaml")], check=True, capture_output=True,
                   timeout=120)
    with open(tmp_path / "summary.csv") as f:
        rows = list(csv.DictReader(f))
    assert [r["run"] for r in rows] == ["ideal", "c=0.1mm"]
    rows[1].update(peak_track_rad="nan", rms_track_rad="nan", track_ticks="0", controller_limited_track_ticks="nan",
                   status="stop:sim.velocity_limit", stop_reason="the plant stopped after t = 3 s",
                   track_reason="track window [3.5; inf) s not reached: run ended at 3 s")
    with open(tmp_path / "summary.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    md, summary = pointing_page._page(tmp_path)
    assert f"Per tick: {tmp_path}/pointing_error.csv; figures: {tmp_path}/pointing_error_vs_time.png" in "\n".join(md)
    assert summary.endswith("rad ideal, no clearance run has a figure while tracking"), summary
    texts = []
    monkeypatch.setattr(plot_pointing_study, "savefig",
                        lambda fig, out, dpi: texts.extend(t.get_text() for t in fig.axes[0].texts))
    plot_pointing_study.plot_clearance(plot_pointing_study.read_summary(str(tmp_path)),
                                       str(tmp_path / "c.png"))
    assert texts == ["no clearance run has a figure while tracking"], texts


@pytest.mark.parametrize("field", ["title", "command", "summary", "body"])
@pytest.mark.parametrize("bad,code", [("\x1b]0;pwn\x07", "001B"), ("\u2028", "2028"), ("\u202e", "202E"),
                                      ("\u061c", "061C")])
def test_a_control_character_in_a_page_is_refused(tmp_path, field, bad, code):
    # (pass 92) --title "a ESC]0;pwn BEL b" landed in the page and the index: cat set the terminal's title;
    # (pass 94) a line separator split it, a right-to-left override reversed it
    page = tmp_path / "p.md"
    texts = {"title": "A study", "command": "cmd", "summary": "one line", "body": "| a |\n"}
    texts[field] = f"a{bad}b" if field != "body" else f"| a |\n{bad}\n"
    with pytest.raises(results_page.output_file.Refused, match=rf"the {field}: character U\+{code} \(a control"):
        results_page.write_page(page, texts["title"], texts["command"], texts["body"], texts["summary"], index=False)
    assert not page.exists()


def test_a_summary_cannot_end_its_comment_and_a_title_cannot_end_its_link(tmp_path):
    # (pass 98) --summary 'x --> # forged' closed the page's hidden summary comment (the rest showed as text), and a
    # title with ']' closed the index's link text early
    page = tmp_path / "p.md"
    for bad, mark in (("x --> # forged", "-->"), ("a <!-- b", "<!--"), ("a --!> b", "--!>")):
        with pytest.raises(results_page.output_file.Refused, match=f"the summary: '{mark}' would end or open"):
            results_page.write_page(page, "T", "cmd", "| a |\n", bad, index=False)
    # (pass 100) and the title (a '<!--' in the index hid every entry after it), the command's code span
    for title, command, named in (("T <!-- x", "cmd", "the title: '<!--'"), ("T", "x` <!-- y", "the command: '<!--'"),
                                  ("T", "echo `date`", "the command: '`'")):
        with pytest.raises(results_page.output_file.Refused, match=named):
            results_page.write_page(page, title, command, "| a |\n", "s", index=False)
    assert not page.exists()
    results_page.write_page(page, "Gains [rad] ](x.md)", "cmd", "| a |\n", "one line")
    index = (tmp_path / "README.md").read_text()
    assert "- [Gains \\[rad\\] \\](x.md)](p.md): one line" in index, index


def test_a_titles_backslash_or_backtick_and_a_summarys_backtick_are_escaped_in_the_index(tmp_path):
    # (pass 102) a title ending in '\\' escaped its link's ']'; a backtick in the title or summary paired with the
    # command's code span: the index line's link and code span broke
    results_page.write_page(tmp_path / "p.md", "a \\", "bash x.sh", "| a |\n", "s `code")
    results_page.write_page(tmp_path / "q.md", "a `b", "bash y.sh", "| a |\n", "t")
    index = (tmp_path / "README.md").read_text()
    assert "- [a \\\\](p.md): s \\`code (" in index and "; `bash x.sh`)" in index, index
    assert "- [a \\`b](q.md): t (" in index and "; `bash y.sh`)" in index, index


@pytest.mark.parametrize("field", ["title", "command"])
def test_a_line_feed_in_a_pages_title_or_command_is_refused(tmp_path, field):
    # (pass 96) --title $'T\n<!-- summary: forged -->\n# Second' forged the page's summary line (read by the index)
    # and a second heading; the body's lines and the summary's (folded into one) are theirs
    page = tmp_path / "p.md"
    texts = {"title": "A study", "command": "cmd", "summary": "one\nline", "body": "| a |\n| b |\n"}
    texts[field] = "T\n<!-- summary: forged -->\n# Second"
    with pytest.raises(results_page.output_file.Refused, match=rf"the {field}: character U\+000A \(a control"):
        results_page.write_page(page, texts["title"], texts["command"], texts["body"], texts["summary"], index=False)
    assert not page.exists()
    texts[field] = "one line"
    results_page.write_page(page, texts["title"], texts["command"], texts["body"], texts["summary"], index=False)
    assert "<!-- summary: one line -->" in page.read_text()


@pytest.mark.parametrize("name", ["zz\n- [forged](x.md): p.md", "a b.md", "a](x).md", "page.txt", "README.md", "x.md/",
                                  "x.md/."])
def test_a_pages_name_is_one_the_index_can_link(tmp_path, name):
    # (pass 104) a line feed in --page forged an index row that every later --index kept; ']' or ')' broke the link;
    # a .txt page was indexed when written and dropped by the next --index; (pass 106) x.md/ was written as x.md
    with pytest.raises(results_page.output_file.Refused, match="a page's name is NAME.md") as e:
        results_page.write_page(f"{tmp_path}/{name}", "T", "cmd", "| a |\n", "s")
    assert repr(f"{tmp_path}/{name}") in str(e.value), str(e.value)  # named as given (pass 108: the '/' was dropped)
    assert os.listdir(tmp_path) == []


def test_a_summary_line_in_the_body_is_not_the_pages_summary(tmp_path):
    # (pass 104) with no --summary, a body line '<!-- summary: ... -->' became the index's summary
    results_page.write_page(tmp_path / "p.md", "T", "cmd", "body\n<!-- summary: forged -->\n", "")
    assert "- [T](p.md): (" in (tmp_path / "README.md").read_text()
