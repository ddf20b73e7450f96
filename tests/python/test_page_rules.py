"""Issue 41 (pass 46), the results pages' writer and the scripts that call it: a page's start time and load
are numbers the header can say (a bad one is refused, exit 2, never a traceback or "nan s wall"); the body
on stdin is read as a file is; the index never replaces a hand-written README.md; every script that writes a
page checks it before its study runs, and a missing program is a refusal (2), not a bug (1)."""
import os
import shutil
import subprocess
import sys

import pytest

from conftest import BIN, SOURCE

WRITER = SOURCE / "tools" / "pages" / "results_page.py"
POINTING_HEADER = ("run,scene,sensors,clearance_m,peak_track_rad,rms_track_rad,peak_run_rad,track_ticks,"
                   "controller_limited_ticks,controller_limited_track_ticks,motor_limited_ticks,joints,max_tilt1_rad,"
                   "max_tilt2_rad,play_onset1_s,play_onset2_s,loop_sensors,status,stop_reason,track_reason,"
                   "onset_reason\n")  # the pointing study's summary.csv (study_run.cpp summaryCsv)


def _writer(*args, cwd, stdin=None):
    return subprocess.run([sys.executable, str(WRITER), *args], cwd=cwd, input=stdin, capture_output=True,
                          timeout=60)


DATE_WRITES = "is not as date +%s.%N writes a time (digits, a point, digits)"


@pytest.mark.parametrize("flag,value,said", [("--t0", "abc", "'abc' " + DATE_WRITES),
                                             ("--t0", "", "an empty value"),
                                             ("--t0", "nan", "'nan' " + DATE_WRITES),
                                             ("--t0", "1e300", "'1e300' " + DATE_WRITES),
                                             ("--t0", "0", "'0' " + DATE_WRITES),
                                             # (pass 67) a page said "Run: 796384552 s wall" for these
                                             ("--t0", "1e9", "'1e9' " + DATE_WRITES),
                                             ("--t0", "+1700000000", "'+1700000000' " + DATE_WRITES),
                                             ("--t0", "1000000000", "1000000000 is no start time of a study run "
                                                                    "on this machine"),
                                             ("--load0", "abc", "'abc' is not /proc/loadavg"),
                                             ("--load0", "0.5 nan 1", "'0.5 nan 1' is not /proc/loadavg"),
                                             ("--load0", "01 2 3", "'01 2 3' is not /proc/loadavg"),
                                             # (pass 49) none of these is the kernel's 0.52
                                             *[("--load0", f"{x} 0.10 0.10", f"'{x} 0.10 0.10' is not /proc/loadavg")
                                               for x in ("1e-400", "-0", "+0.50", "1e3", "1" * 20, "0.5")]])
def test_a_start_the_header_cannot_say_is_refused(tmp_path, flag, value, said):
    # (pass 46) --t0 abc ended in a traceback after the rules were checked; nan wrote "Run: nan s wall"
    (tmp_path / "b.md").write_text("body\n")
    p = _writer("--page", "x.md", "--title", "T", "--command", "c", "--body", "b.md", f"{flag}={value}",
                cwd=tmp_path)
    err = p.stderr.decode()
    assert p.returncode == 2 and f"argument {flag}: {said}" in err and "Traceback" not in err, err
    assert sorted(q.name for q in tmp_path.iterdir()) == ["b.md"]


def test_a_start_as_the_run_scripts_note_it_is_taken(tmp_path):
    (tmp_path / "b.md").write_text("body\n")
    load = open("/proc/loadavg").read()
    import time
    p = _writer("--page", "x.md", "--title", "T", "--command", "c", "--body", "b.md", "--t0", f"{time.time() - 5:.9f}",
                "--load0", load, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    run = [line for line in (tmp_path / "x.md").read_text().splitlines() if line.startswith("- Run: ")][0]
    assert " s wall; load average (1, 5, 15 min) " + " ".join(load.split()[:3]) + " at start" in run, run


def test_a_body_on_stdin_is_read_as_a_file_is(tmp_path):
    # (pass 46) bytes that are not UTF-8 on stdin ended in a traceback (exit 1); from a file they were refused
    p = _writer("--page", "x.md", "--title", "T", "--command", "c", "--body", "-", cwd=tmp_path, stdin=b"a\xffb")
    err = p.stderr.decode()
    assert p.returncode == 2 and "--body -: not UTF-8 text (byte 1)" in err and "Traceback" not in err, err
    assert not list(tmp_path.iterdir())
    p = _writer("--page", "x.md", "--title", "T", "--command", "c", "--body", "-", cwd=tmp_path, stdin=b"fine\n")
    assert p.returncode == 0 and (tmp_path / "x.md").read_text().rstrip().endswith("fine"), p.stderr


def test_the_index_never_replaces_a_hand_written_readme(tmp_path):
    # (pass 46) --index replaced a README.md that --page refused; a README.md link was exit 4
    sys.path.insert(0, str(SOURCE / "tools" / "pages"))
    import results_page
    (tmp_path / "README.md").write_text("my notes\n")
    with pytest.raises(results_page.output_file.Refused, match="not an index this writer made"):
        results_page.write_index(tmp_path)
    assert (tmp_path / "README.md").read_text() == "my notes\n"
    (tmp_path / "README.md").unlink()
    (tmp_path / "README.md").symlink_to(tmp_path / "elsewhere.md")
    with pytest.raises(results_page.output_file.Refused, match="symbolic link"):
        results_page.write_index(tmp_path)
    assert not (tmp_path / "elsewhere.md").exists()
    (tmp_path / "README.md").unlink()
    results_page.write_index(tmp_path)  # none there: made, and then it is ours to rewrite
    results_page.write_index(tmp_path)
    assert results_page.MARK in (tmp_path / "README.md").read_text()


def test_check_and_index_take_their_own_flags_alone(tmp_path):
    (tmp_path / "README.md").write_text("my notes\n")
    p = _writer("--check", "--page", "x.md", cwd=tmp_path)
    assert p.returncode == 2 and b"README.md: not an index this writer made" in p.stderr, p.stderr
    (tmp_path / "README.md").unlink()
    assert _writer("--check", "--page", "x.md", cwd=tmp_path).returncode == 0
    assert not list(tmp_path.iterdir()), "--check writes nothing"
    for args, said in ((["--index", "--page", "x.md"], b"--index rewrites the index alone: leave out --page"),
                       (["--check", "--page", "x.md", "--title", "T"], b"--check takes --page alone")):
        p = _writer(*args, cwd=tmp_path)
        assert p.returncode == 2 and said in p.stderr, p.stderr


@pytest.mark.parametrize("script", ["tools/hil/hil_speed.py", "tools/hil/worst_tick.py", "tools/bench/loop_cost.py",
                                    "tools/bench/tick_parts.py", "tools/sweeps/budget_speed.py",
                                    "tools/bench/perf_report.py"])
def test_a_missing_program_is_a_refusal_read_where_the_user_stands(tmp_path, script):
    # (pass 46) sys.exit("... missing") was exit 1, the code for a bug; hil_speed's hint named build/ always.
    # (pass 66) a relative --build was read against the source tree, not where the user stands.
    p = subprocess.run([sys.executable, str(SOURCE / script), "--build", "nosuch"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 2 and f"cmake --build {tmp_path / 'nosuch'} " in p.stderr, p.stderr
    assert str(SOURCE / "nosuch") not in p.stderr and "Traceback" not in p.stderr, p.stderr
    # (pass 119) --build= was read as the folder the user stands in, whose bin/ would have run
    p = subprocess.run([sys.executable, str(SOURCE / script), "--build="], cwd=tmp_path, capture_output=True,
                       text=True, timeout=60)
    assert p.returncode == 2 and "argument --build: an empty value: name the build folder" in p.stderr, p.stderr


def _repository(tmp_path):
    """The tree the run scripts use, its build the one under test (no cmake: a stand-in that does nothing), and
    a hand-written README.md in its docs/results/."""
    repo = tmp_path / "repo"
    shutil.copytree(SOURCE / "tools", repo / "tools", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(SOURCE / "python" / "gimbalsim", repo / "python" / "gimbalsim",
                    ignore=shutil.ignore_patterns("__pycache__", "*.so"))
    shutil.copy(SOURCE / "CMakeLists.txt", repo)
    (repo / "docs" / "results").mkdir(parents=True)
    (repo / "docs" / "results" / "README.md").write_text("my notes\n")
    (repo / "build").symlink_to(BIN.parent)
    fake = tmp_path / "fakebin"
    fake.mkdir()
    (fake / "cmake").write_text("#!/bin/sh\nexit 0\n")
    (fake / "cmake").chmod(0o755)
    return repo, dict(os.environ, PATH=f"{fake}:{os.environ['PATH']}")


RUN_SCRIPTS = ["tools/stress/run_stress.sh", "tools/workprec/run_workprec.sh",
               "tools/pointing_study/run_pointing_study.sh", "tools/pointing_study/run_controller_floor.sh",
               "tools/run_paper.sh", "tools/bench/run_bench.sh", "tools/sweeps/run_pointing_budget.sh"]


@pytest.mark.parametrize("script", RUN_SCRIPTS, ids=[s.split("/")[-1] for s in RUN_SCRIPTS])
def test_a_run_script_checks_its_page_before_its_study(tmp_path, script):
    # (pass 46) run_stress.sh --results ran the study, replaced the previous out/stress/stress.csv, and only then
    # was its page refused; so did the other run scripts (the budget's checked links only)
    repo, env = _repository(tmp_path)
    previous = repo / "out" / "stress" / "stress.csv"
    previous.parent.mkdir(parents=True)
    previous.write_text("previous results\n")
    args = [] if "budget" in script else ["--results"]  # the budget's script always writes its page
    p = subprocess.run(["bash", str(repo / script), *args], cwd=tmp_path, env=env, capture_output=True,
                       text=True, timeout=300)
    assert p.returncode == 2 and "README.md: not an index this writer made" in p.stderr, (p.returncode, p.stderr)
    assert previous.read_text() == "previous results\n"
    assert (repo / "docs" / "results" / "README.md").read_text() == "my notes\n"
    assert sorted(q.name for q in (repo / "docs" / "results").iterdir()) == ["README.md"]
    assert sorted(q.name for q in (repo / "out").iterdir()) == ["stress"], "no study ran, no folder left"
    for ran in ("ideal ", "TRUSTWORTHY", "BM_", "sample"):  # a study's, a benchmark's, a sweep's lines
        assert ran not in p.stdout + p.stderr, (ran, p.stdout, p.stderr)


def test_a_start_after_now_is_refused(tmp_path):
    # (pass 47) a --t0 up to 60 s ahead was taken: the page said "Run: -55 s wall"
    import time
    (tmp_path / "b.md").write_text("body\n")
    p = _writer("--page", "x.md", "--title", "T", "--command", "c", "--body", "b.md", "--t0",
                f"{time.time() + 10:.3f}", cwd=tmp_path)
    assert p.returncode == 2 and b"is no start time" in p.stderr, p.stderr
    assert sorted(q.name for q in tmp_path.iterdir()) == ["b.md"]


@pytest.mark.parametrize("args,said", [(["--index", "--summary", "s"], "--index rewrites the index alone: leave out "
                                                                        "--summary"),
                                       (["--check", "--page", "x.md", "--summary", "s"], "leave out --summary"),
                                       (["--check"], "--check needs --page P"),
                                       (["--check", "--page", ""], "--page: an empty value")])
def test_check_and_index_drop_no_flag_silently(tmp_path, args, said):
    # (pass 47) --summary was taken and dropped by --index and --check; --check --page '' was "takes --page alone"
    p = _writer(*args, cwd=tmp_path)
    assert p.returncode == 2 and said.encode() in p.stderr, p.stderr
    assert not list(tmp_path.iterdir())


def _page_repository(tmp_path):
    """A copy of the page scripts' tree: what they write into docs/results/ lands here."""
    repo = tmp_path / "repo"
    for part in ("tools", "docs/results"):
        shutil.copytree(SOURCE / part, repo / part, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(SOURCE / "python" / "gimbalsim", repo / "python" / "gimbalsim",
                    ignore=shutil.ignore_patterns("__pycache__", "*.so"))
    shutil.copy(SOURCE / "CMakeLists.txt", repo)
    return repo


def _pages(repo):
    return {p.name: p.read_bytes() for p in (repo / "docs" / "results").iterdir()}


# (script, the study file it reads, the page it writes, the arguments around the study folder or file D)
PAGE_SCRIPTS = {"workprec": ("tools/workprec/workprec_page.py", "workprec.csv", ["--dir", "D"]),
                "pointing": ("tools/pointing_study/pointing_page.py", "summary.csv", ["--dir", "D"]),
                "speed": ("tools/bench/speed_page.py", "bench.json", ["--bench-json", "D/bench.json", "--no-mujoco",
                                                                       "test"])}


@pytest.mark.parametrize("which", sorted(PAGE_SCRIPTS))
@pytest.mark.parametrize("content,said", [("fifo", "not a regular file (a FIFO)"),
                                          (b"a\xffb", "not UTF-8 text"),
                                          ("no rows", "no rows: nothing to put on the page"),
                                          ("missing", "No such file or directory")])
def test_a_page_script_reads_its_study_by_the_rules_and_makes_no_page_of_nothing(tmp_path, which, content, said):
    # (pass 47) a FIFO blocked, bytes that are not UTF-8 or a JSON '{}' were a traceback (exit 1), and a study with
    # no rows replaced the committed page with empty tables
    script, name, args = PAGE_SCRIPTS[which]
    repo = _page_repository(tmp_path)
    study = tmp_path / "study"
    study.mkdir()
    target = study / name
    if content == "fifo":
        os.mkfifo(target)
    elif content == "no rows":
        target.write_text({"workprec.csv": WORKPREC_HEADER,
                           "summary.csv": POINTING_HEADER,
                           "bench.json": '{"context": {}, "benchmarks": []}'}[name])
    elif content != "missing":
        target.write_bytes(content)
    before = _pages(repo)
    p = subprocess.run([sys.executable, str(repo / script), *[a.replace("D", str(study)) for a in args],
                        "--command", "c"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert p.returncode == 2 and said in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert _pages(repo) == before


def test_a_bench_json_that_is_not_google_benchmarks_is_refused(tmp_path):
    repo = _page_repository(tmp_path)
    for text, said in (("{}", "not Google Benchmark's JSON"), ("[1]", "not Google Benchmark's JSON"),
                       ("{", "not as gimbalsim_bench writes them (JSONDecodeError"),
                       ('{"benchmarks": [{"run_type": "aggregate"}]}', "not as gimbalsim_bench writes them (KeyError")):
        (tmp_path / "b.json").write_text(text)
        p = subprocess.run([sys.executable, str(repo / "tools/bench/speed_page.py"), "--bench-json", "b.json",
                            "--no-mujoco", "test", "--command", "c"], cwd=tmp_path, capture_output=True, text=True,
                           timeout=60)
        assert p.returncode == 2 and said in p.stderr and "Traceback" not in p.stderr, (text, p.stderr)


@pytest.mark.parametrize("text,said", [('{"benchmarks": [1]}', "AttributeError"),
                                       ('{"context": [], "benchmarks": [{"run_type": "aggregate", "run_name": '
                                        '"BM_Y", "aggregate_name": "median", "cpu_time": 5, "repetitions": 3}, '
                                        '{"run_type": "aggregate", "run_name": "BM_Y", "aggregate_name": "min", '
                                        '"cpu_time": 4, "repetitions": 3}]}', "'context' is no object"),
                                       ('{"benchmarks": [{"run_type": "aggregate", "run_name": "BM_Y", '
                                        '"aggregate_name": "mean", "cpu_time": 5, "repetitions": 3}]}', "'median'"),
                                       ('{"benchmarks": [{"run_type": "aggregate", "run_name": "BM_Y", '
                                        '"aggregate_name": "median", "cpu_time": NaN, "repetitions": 3}]}',
                                        "cpu_time nan"),
                                       ('{"benchmarks": [{"run_type": "aggregate", "run_name": "BM_Y", '
                                        '"aggregate_name": "median", "cpu_time": 5}]}', "'repetitions'")])
def test_a_bench_json_with_a_figure_missing_makes_no_page(tmp_path, text, said):
    # (pass 48) items that were no objects were a traceback (exit 1); a median missing or a nan cpu_time wrote the
    # page with bare nan figures and an empty repetition count
    repo = _page_repository(tmp_path)
    before = _pages(repo)
    (tmp_path / "b.json").write_text(text)
    p = subprocess.run([sys.executable, str(repo / "tools/bench/speed_page.py"), "--bench-json", "b.json",
                        "--no-mujoco", "test", "--command", "c"], cwd=tmp_path, capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 2 and "not as gimbalsim_bench writes them" in p.stderr and said in p.stderr, p.stderr
    assert "Traceback" not in p.stderr and _pages(repo) == before


WORKPREC_HEADER = ("scene,policy,sweep_key,h_s,substep_s,ok,cpu_s_per_sim_s,bore_err_max_rad,substeps,pareto,"
                   "event_tol_s,repeats,bore_err_end_rad,theta1_err_max_rad,theta2_err_max_rad,peak_force_err_rel,"
                   "momentum_drift_rel,impacts,sweep_value\n")
WORKPREC_REST = ",1e-08,3,1e-07,1e-07,1e-07,0.01,1e-09,5,"  # the columns after pareto, as a point that ran ok


@pytest.mark.parametrize("row,said", [("paper_clearance,plain,,0.001,2e-05,1,,1e-06,100,1\n", "cpu_s_per_sim_s"),
                                      ("paper_clearance,plain,,0.001,2e-05,1,0,1e-06,100,1\n", "cpu_s_per_sim_s"),
                                      ("paper_clearance,plain,,0.001,2e-05,1,0.5,abc,100,1\n", "bore_err_max_rad")])
def test_a_workprec_point_that_ran_without_its_figures_makes_no_page(tmp_path, row, said):
    # (pass 48) a cell it could not read was nan, printed on the page and its index line; CPU 0 a ZeroDivisionError
    repo = _page_repository(tmp_path)
    before = _pages(repo)
    (tmp_path / "study").mkdir()
    (tmp_path / "study" / "workprec.csv").write_text(WORKPREC_HEADER + row.rstrip("\n") + WORKPREC_REST + "\n")
    p = subprocess.run([sys.executable, str(repo / "tools/workprec/workprec_page.py"), "--dir", "study", "--command",
                        "c"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert p.returncode == 2 and said in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert _pages(repo) == before


def _paper_run(folder, summary="  max pointing error : 1.0e-03 rad\n"):
    """A run folder as tools/run_paper.sh leaves it: the summaries paper_page reads and the three figures."""
    from PIL import Image
    (folder / "plots").mkdir(parents=True)
    (folder / "plot_summary.txt").write_text(summary)
    for name in ("ideal", "clearance"):
        (folder / f"{name}.json").write_text('{"status": "ok", "t_end_s": 1, "impacts": 0, "substeps": 10, '
                                             '"integrator": {"step_s": 0.001, "substep_s": 2e-05}, '
                                             '"wall_time_s": 0.1, "overrides": ["sim.duration=1"]}')
    for png in ("fig17_pointing_error.png", "fig18_joint2_force.png", "fig06_eccentricity.png"):
        Image.new("RGB", (110, 110), "white").save(folder / "plots" / png)


@pytest.mark.parametrize("case,said", [("no figure line", "no rows: nothing to put on the page"),
                                       ("third figure missing", "fig06_eccentricity.png: cannot be read"),
                                       ("third figure no PNG", "not a figure plot_paper.py writes"),
                                       ("third figure a FIFO", "not a regular file (a FIFO)"),
                                       ("hand-written index", "not an index this writer made")])
def test_the_paper_page_and_its_figures_are_one_set(tmp_path, case, said):
    # (pass 48) two of the three committed figures were replaced, then the third was missing (a traceback), a FIFO
    # (a hang) or the page refused: the committed page beside another run's figures
    repo = _page_repository(tmp_path)
    run = tmp_path / "run"
    _paper_run(run, "" if case == "no figure line" else "  max pointing error : 1.0e-03 rad\n")
    third = run / "plots" / "fig06_eccentricity.png"
    if case != "no figure line" and case != "hand-written index":
        third.unlink()
        if case == "third figure no PNG":
            third.write_text("no image")
        elif case == "third figure a FIFO":
            os.mkfifo(third)
    if case == "hand-written index":
        (repo / "docs" / "results" / "README.md").write_text("my notes\n")
    before = _pages(repo)
    p = subprocess.run([sys.executable, str(repo / "tools/paper/paper_page.py"), "--dir", str(run), "--command", "c"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert p.returncode == 2 and said in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert _pages(repo) == before
    if case == "hand-written index":  # the same run with the index the writer's: page and figures together
        (repo / "docs" / "results" / "README.md").unlink()
        p = subprocess.run([sys.executable, str(repo / "tools/paper/paper_page.py"), "--dir", str(run), "--command",
                            "c"], cwd=tmp_path, capture_output=True, text=True, timeout=60)
        assert p.returncode == 0, p.stderr
        after = _pages(repo)
        changed = sorted(n for n in after if after[n] != before.get(n))
        assert changed == ["README.md", "paper.md", "paper_eccentricity.png", "paper_joint2_force.png",
                           "paper_pointing.png"], changed


def test_budget_speed_writes_the_shipped_budgets_page_only_from_the_shipped_spec(tmp_path):
    # (pass 48) a 2-unit copy saved anywhere as pointing_budget.yaml replaced the shipped budget's page
    from conftest import BIN
    repo = _page_repository(tmp_path)
    (repo / "build").symlink_to(BIN.parent)
    (tmp_path / "copy").mkdir()
    shutil.copy(SOURCE / "tools/sweeps/pointing_budget.yaml", tmp_path / "copy" / "pointing_budget.yaml")
    before = _pages(repo)
    p = subprocess.run([sys.executable, str(repo / "tools/sweeps/budget_speed.py"), "--spec",
                        "copy/pointing_budget.yaml", "--results"], cwd=tmp_path, capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 2 and "--spec copy/pointing_budget.yaml is another file" in p.stderr, p.stderr
    assert _pages(repo) == before and not (repo / "out").exists()


def test_a_page_waits_while_another_writer_holds_the_results_folder(tmp_path):
    # (pass 51) two page scripts at once: each indexed the other's old page, and the index lost an entry
    import fcntl
    import time
    results = tmp_path / "results"
    results.mkdir()
    (tmp_path / "b.md").write_text("body\n")
    fd = os.open(results, os.O_RDONLY | os.O_DIRECTORY)
    fcntl.flock(fd, fcntl.LOCK_EX)  # as another writer holds it while it writes its page and the index
    try:
        p = subprocess.Popen([sys.executable, str(WRITER), "--page", str(results / "x.md"), "--title", "T",
                              "--command", "c", "--body", "b.md"], cwd=tmp_path, stderr=subprocess.PIPE)
        time.sleep(1.5)
        assert p.poll() is None and not (results / "x.md").exists(), "written while another writer held the folder"
    finally:
        os.close(fd)
    assert p.wait(timeout=60) == 0, p.stderr.read()
    assert "[T](x.md)" in (results / "README.md").read_text()
