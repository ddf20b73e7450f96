"""Issue 41, "Hostile and careless input" (pass 21), the scripts' side: a
script's console log goes into its output folder by the writer's rules, after
the program has checked and written its own outputs. `| tee "$OUT/x.log"`
made a named --out that did not exist, and on a refused run emptied a
previous log, a link's target, or a scene hard-linked under the log's name."""
import os
import subprocess

import pytest

from conftest import BIN, SOURCE

SCRIPTS = {"study": ("tools/pointing_study/run_pointing_study.sh", "gimbalsim_pointing_study", "study.log",
                     "out/pointing_study"),
           "floor": ("tools/pointing_study/run_controller_floor.sh", "gimbalsim_controller_floor", "floor.log",
                     "out/controller_floor")}


def _run(tmp_path, which, *args, root=SOURCE):
    """The script (of the tree at root: the checkout, or a _repository_copy) with a build of the one program it
    runs (no cmake: a stand-in that does nothing), from tmp/work."""
    script, program, _, _ = SCRIPTS[which]
    build, fake, work = tmp_path / "build", tmp_path / "fakebin", tmp_path / "work"
    for d in (build / "bin", fake, work):
        d.mkdir(parents=True, exist_ok=True)
    (build / "CMakeCache.txt").write_text("")
    if not (build / "bin" / program).exists():
        (build / "bin" / program).symlink_to(BIN / program)
    (fake / "cmake").write_text("#!/bin/sh\nexit 0\n")
    (fake / "cmake").chmod(0o755)
    env = dict(os.environ, GIMBALSIM_BUILD=str(build), PATH=f"{fake}:{os.environ['PATH']}")
    return subprocess.run(["bash", str(root / script), *args], cwd=work, env=env, capture_output=True, text=True,
                          timeout=300)


@pytest.mark.parametrize("which", ["study", "floor"])
@pytest.mark.parametrize("planted", ["previous", "link", "hardlink"])
def test_a_refused_run_leaves_the_log_and_what_it_points_at_as_they_were(tmp_path, which, planted):
    _, _, log_name, out = SCRIPTS[which]
    folder = tmp_path / "work" / out
    folder.mkdir(parents=True)
    victim = tmp_path / "victim.yaml"
    victim.write_text("the user's scene\n")
    log = folder / log_name
    if planted == "previous":
        log.write_text("the previous run's log\n")
    elif planted == "link":
        log.symlink_to(victim)
    else:
        os.link(victim, log)
    before = log.read_text()
    p = _run(tmp_path, which, "--clearances", "0")
    assert p.returncode == 2, p.stderr
    # the log's own check comes first (a link: refused before any run, pass 23), else the program's refusal
    assert ("symbolic link" in p.stderr) == (planted == "link") and ("--clearances" in p.stderr) != (planted == "link")
    assert log.read_text() == before and victim.read_text() == "the user's scene\n"


def test_the_study_script_makes_no_named_out_folder_for_a_refused_run(tmp_path):
    named = tmp_path / "not" / "there"
    p = _run(tmp_path, "study", "--clearances", "0", "--out", str(named))
    assert p.returncode == 2, p.stderr
    assert not (tmp_path / "not").exists()


@pytest.mark.parametrize("which,flag", [("floor", "--ideal-scene"), ("floor", "--clearance-scene"),
                                        ("study", "--ideal-scene")])
def test_a_scene_the_script_gives_is_the_users_to_replace(tmp_path, which, flag):
    # (pass 35) the scripts gave their own --ideal-scene/--clearance-scene too: the user's got CLI11's "At Most 1
    # required but received 2", after the script had made its default out/ folder, left there empty
    scene = SOURCE / "tools/scenes" / ("paper_ideal.yaml" if flag == "--ideal-scene" else "paper_clearance.yaml")
    p = _run(tmp_path, which, f"{flag}={scene}", "--clearances", "0")
    assert p.returncode == 2 and "--clearances" in p.stderr and "At Most 1" not in p.stderr, p.stderr
    assert not (tmp_path / "work" / "out").exists()  # a refused run costs nothing
    (tmp_path / "work" / "out").mkdir()  # a folder the user had is theirs: kept
    p = _run(tmp_path, which, flag, str(scene), "--clearances", "0")
    assert p.returncode == 2 and "At Most 1" not in p.stderr, p.stderr
    assert (tmp_path / "work" / "out").is_dir() and not list((tmp_path / "work" / "out").iterdir())


@pytest.mark.parametrize("which", ["study", "floor"])
def test_a_file_where_the_scripts_folder_goes_is_refused_not_a_bug(tmp_path, which):
    # (pass 36) mkdir's "Not a directory" ended the script with exit 1, which usage.md calls a bug
    (tmp_path / "work").mkdir()
    (tmp_path / "work" / "out").write_text("the user's\n")
    p = _run(tmp_path, which, "--clearances", "2.5e-4")
    assert p.returncode == 2 and "out is not a folder" in p.stderr and "nothing run" in p.stderr, p.stderr
    assert (tmp_path / "work" / "out").read_text() == "the user's\n"


def test_the_study_script_saves_its_log_beside_the_results(tmp_path):
    p = _run(tmp_path, "study", "--quick", "--clearances", "2.5e-4", "--clearance-scene",
             str(SOURCE / "tools/scenes/paper_clearance.yaml"), "--sensors", "perfect", "--duration", "3.6")
    assert p.returncode == 0, p.stderr
    folder = tmp_path / "work/out/pointing_study"
    assert "wrote " in (folder / "study.log").read_text()
    assert (folder / "summary.csv").is_file()


@pytest.mark.parametrize("which", ["study", "floor"])
def test_a_log_named_as_one_of_the_runs_inputs_is_refused_not_written_over_it(tmp_path, which):
    # (pass 22) the log was saved over the scene or configuration the run had read under its name
    script, _, log_name, out = SCRIPTS[which]
    folder = tmp_path / "work" / out
    folder.mkdir(parents=True)
    log = folder / log_name
    if which == "study":
        log.write_bytes((SOURCE / "tools/scenes/paper_clearance.yaml").read_bytes())
        args = ["--clearance-scene", str(log), "--clearances", "2.5e-4", "--duration", "3.6", "--sensors", "perfect",
                "--out", str(folder)]
    else:
        log.write_bytes((SOURCE / "controllers/config/default.yaml").read_bytes())
        args = ["--config", str(log), "--clearances", "2.5e-4", "--duration", "2.6"]
    before = log.read_bytes()
    p = _run(tmp_path, which, *args)
    assert p.returncode == 2, p.stderr
    # the refusal speaks as the script the user ran, not as the helper that saves its log (pass 84)
    name = script.rsplit("/", 1)[1]
    assert f"{name}: error: " in p.stderr and f"{log_name}: the same file as the input" in p.stderr, p.stderr
    assert "save_output.py" not in p.stderr, p.stderr
    assert log.read_bytes() == before


def test_a_log_that_would_be_refused_costs_no_run(tmp_path):
    # (pass 23) the log's name was checked only after the study had replaced its outputs
    folder = tmp_path / "work" / "named"
    folder.mkdir(parents=True)
    (folder / "pointing_error.csv").write_text("the previous run's\n")
    scene = tmp_path / "myscene.yaml"
    scene.write_bytes((SOURCE / "tools/scenes/paper_clearance.yaml").read_bytes())
    os.link(scene, folder / "study.log")  # the log's name, a hard link to an input given under another name
    p = _run(tmp_path, "study", "--clearance-scene", str(scene), "--clearances", "2.5e-4", "--duration", "3.6",
             "--sensors", "perfect", "--out", str(folder))
    assert p.returncode == 2, p.stderr
    assert "study.log: the same file as the input" in p.stderr, p.stderr
    assert (folder / "pointing_error.csv").read_text() == "the previous run's\n"
    assert scene.read_bytes() == (SOURCE / "tools/scenes/paper_clearance.yaml").read_bytes()


def _repository_copy(tmp_path):
    """The scripts' own tree (tools/, the writer's rules, an empty docs/results/) in tmp: whatever a script
    writes into "the repository" lands here, never in the checkout under test."""
    import shutil
    repo = tmp_path / "repo"
    shutil.copytree(SOURCE / "tools", repo / "tools", ignore=shutil.ignore_patterns("__pycache__"))
    (repo / "python" / "gimbalsim").mkdir(parents=True)
    for module in ("_output.py", "_csv_cells.py", "_console.py", "_number.py", "_early_signals.py", "_flags.py"):
        shutil.copy(SOURCE / "python" / "gimbalsim" / module, repo / "python" / "gimbalsim" / module)
    (repo / "docs" / "results").mkdir(parents=True)
    return repo


@pytest.mark.parametrize("results", [False, True])
def test_the_floor_script_writes_the_projects_page_only_when_asked(tmp_path, results):
    # a trial with other arguments (one clearance, a short run) replaced docs/results/controller_floor.md
    repo = _repository_copy(tmp_path)
    args = ["--clearances", "2.5e-4", "--duration", "2.6"] + (["--results"] if results else [])
    p = _run(tmp_path, "floor", *args, root=repo)
    work = tmp_path / "work"
    assert p.returncode == 0, p.stderr
    assert (work / "out/controller_floor/floor.log").is_file()
    page = repo / "docs/results/controller_floor.md"
    assert page.is_file() == results
    if results:
        assert "Regenerate: `bash tools/pointing_study/run_controller_floor.sh --clearances 2.5e-4 --duration 2.6 " \
            "--results`" in page.read_text()


def test_a_floor_whose_plant_stops_keeps_its_log_beside_its_outputs(tmp_path):
    # (pass 25) the program's exit 3 ended the script before the log was saved: the new body.md sat beside
    # the previous run's floor.log
    folder = tmp_path / "work" / "out" / "controller_floor"
    folder.mkdir(parents=True)
    (folder / "floor.log").write_text("the previous run's log\n")
    p = _run(tmp_path, "floor", "--clearances", "2e-4", "--duration", "3.6", "--scene-set", "sim.velocity_limit=0.5")
    assert p.returncode == 3, p.stderr
    log = (folder / "floor.log").read_text()
    assert "the previous run's log" not in log and "c=0.2mm" in log, log


def test_a_study_whose_every_run_stops_ends_as_the_study_did(tmp_path):
    # (pass 25) the plot refused a study with no figure while tracking, and the script exited 2 ("refused,
    # nothing run") after every output had been written
    p = _run(tmp_path, "study", "--quick", "--sensors", "perfect", "--clearance-scene",
             str(SOURCE / "tools/scenes/paper_clearance.yaml"), "--scene-set", "sim.velocity_limit=0.5")
    assert p.returncode == 3, p.stderr
    assert "no plot (the study ran, exit 3)" in p.stderr, p.stderr
    assert (tmp_path / "work/out/pointing_study/study.log").is_file()


@pytest.mark.parametrize("which,flag", [("floor", "--help"), ("study", "--version"), ("study", "-h")])
def test_help_and_version_leave_the_previous_log(tmp_path, which, flag):
    # (pass 26) the answer was saved as the log over the previous run's, and the study re-plotted
    _, program, log_name, out = SCRIPTS[which]
    folder = tmp_path / "work" / out
    folder.mkdir(parents=True)
    (folder / log_name).write_text("the previous run's log\n")
    p = _run(tmp_path, which, flag)
    assert p.returncode == 0, p.stderr
    assert (program in p.stdout) if flag == "--version" else ("Usage" in p.stdout or "usage" in p.stdout), p.stdout
    assert (folder / log_name).read_text() == "the previous run's log\n"


def test_a_study_with_no_figure_while_tracking_ends_as_the_study_did(tmp_path):
    # (pass 26) 1 s runs end before tracking: the study exits 0, the plot has nothing to draw, the script said 2
    p = _run(tmp_path, "study", "--quick", "--sensors", "perfect", "--clearance-scene",
             str(SOURCE / "tools/scenes/paper_clearance.yaml"), "--duration", "1")
    assert p.returncode == 0, p.stderr
    assert "no plot (the study ran, exit 0)" in p.stderr, p.stderr


def test_a_study_with_nothing_to_plot_leaves_no_previous_figure_beside_its_results(tmp_path):
    # (pass 80) the previous study's figures stood beside the new CSVs as if they were theirs
    folder = tmp_path / "work/out/pointing_study"
    folder.mkdir(parents=True)
    for fig in ("pointing_error_vs_time.png", "pointing_error_vs_clearance.png"):
        (folder / fig).write_bytes(b"the previous study's figure")
    p = _run(tmp_path, "study", "--quick", "--sensors", "perfect", "--clearance-scene",
             str(SOURCE / "tools/scenes/paper_clearance.yaml"), "--duration", "1")
    assert p.returncode == 0 and "removed the previous study's" in p.stderr, p.stderr
    assert sorted(f.name for f in folder.glob("*.png")) == [], sorted(os.listdir(folder))


@pytest.mark.parametrize("planted", ["link", "folder", "input"])
def test_a_figure_name_the_plot_would_refuse_costs_no_run(tmp_path, planted):
    # (pass 80) a link under a figure's name was refused by the plot after the study had replaced its CSVs, and
    # the script, taking the refusal for "nothing to plot", ended 0 with the previous figure beside them
    folder = tmp_path / "work/out/pointing_study"
    folder.mkdir(parents=True)
    victim = tmp_path / "victim.txt"
    victim.write_text("victim\n")
    (folder / "pointing_error.csv").write_text("the previous study's series\n")
    figure = folder / "pointing_error_vs_time.png"
    scene = tmp_path / "myscene.yaml"  # (pass 81) a figure hard-linked to an input scene was written over
    scene.write_text((SOURCE / "tools/scenes/paper_clearance.yaml").read_text())
    {"link": lambda: figure.symlink_to(victim), "folder": figure.mkdir, "input": lambda: os.link(scene, figure)}[planted]()
    p = _run(tmp_path, "study", "--quick", "--sensors", "perfect", "--clearance-scene", str(scene))
    assert p.returncode == 2 and "pointing_error_vs_time.png" in p.stderr, p.stderr
    assert scene.samefile(figure) if planted == "input" else True
    assert (folder / "pointing_error.csv").read_text() == "the previous study's series\n"
    assert victim.read_text() == "victim\n" and not (folder / "summary.csv").exists()


def test_a_study_with_no_figure_while_tracking_keeps_the_page(tmp_path):
    # (pass 26) every run stopped: the page's summary read "peak error while tracking nan rad ideal"; (pass 50) the
    # committed page was then replaced by one of n/a in every tracking cell: no page, the study's own exit
    repo = _repository_copy(tmp_path)
    page = repo / "docs/results/closed_loop_clearance.md"
    before = page.read_bytes() if page.exists() else None
    p = _run(tmp_path, "study", "--results", "--quick", "--sensors", "perfect", "--clearance-scene",
             str(SOURCE / "tools/scenes/paper_clearance.yaml"), "--scene-set", "sim.velocity_limit=0.5", root=repo)
    assert p.returncode == 3, p.stderr
    assert "no page either: docs/results/closed_loop_clearance.md is kept as it was" in p.stderr, p.stderr
    assert (page.read_bytes() if page.exists() else None) == before


def test_run_stress_refused_by_its_program_leaves_no_folder_it_made(tmp_path):
    # (pass 39) out/ and out/stress were made before gimbalsim_stress refused --duration -1 (exit 2), and stayed
    repo = _repository_copy(tmp_path)
    (repo / "build" / "bin").mkdir(parents=True)
    (repo / "build" / "CMakeCache.txt").write_text("")
    (repo / "build" / "bin" / "gimbalsim_stress").symlink_to(BIN / "gimbalsim_stress")
    fake = tmp_path / "fakebin"
    fake.mkdir()
    (fake / "cmake").write_text("#!/bin/sh\nexit 0\n")
    (fake / "cmake").chmod(0o755)
    env = dict(os.environ, PATH=f"{fake}:{os.environ['PATH']}")
    p = subprocess.run(["bash", str(repo / "tools/stress/run_stress.sh"), "--duration", "-1"], cwd=tmp_path,
                       env=env, capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "--duration" in p.stderr, p.stderr
    assert not (repo / "out").exists()
    (repo / "out").mkdir()  # a folder that was there is the user's: kept
    p = subprocess.run(["bash", str(repo / "tools/stress/run_stress.sh"), "--duration", "-1"], cwd=tmp_path,
                       env=env, capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and (repo / "out").is_dir() and not list((repo / "out").iterdir()), p.stderr


def test_save_output_reads_only_a_regular_log_and_never_writes_over_a_module_it_runs(tmp_path):
    # (pass 90) a FIFO as SOURCE blocked, /dev/zero was read until memory ran out, "" was read as a folder; a
    # DEST naming output_file.py, which the helper had loaded, was written over it (every later run broke)
    repo = tmp_path / "repo"  # a copy: a regression must not write over the checkout's own module
    for f in ["tools/pages/save_output.py", "tools/pages/output_file.py"] + \
            [f"python/gimbalsim/{m}.py" for m in ("_output", "_csv_cells", "_console", "_number", "_early_signals",
                                                  "_flags")]:
        (repo / f).parent.mkdir(parents=True, exist_ok=True)
        (repo / f).write_bytes((SOURCE / f).read_bytes())
    tool = repo / "tools/pages/save_output.py"
    os.mkfifo(tmp_path / "fifo")
    (tmp_path / "log.tmp").write_text("the log\n")
    cases = [(["fifo", "out.log"], "fifo: not a regular file"), (["/dev/zero", "out.log"], "not a regular file"),
             (["", "out.log"], "SOURCE: an empty path"),
             (["log.tmp", str(repo / "tools/pages/output_file.py")], "the same file as this program"),
             (["log.tmp", str(repo / "python/gimbalsim/_output.py")], "the same file as this program"),
             # (pass 116) the log itself as DEST was renamed over its own SOURCE
             (["log.tmp", "log.tmp"], "log.tmp: the same file as the input log.tmp")]
    for args, words in cases:
        p = subprocess.run(["/usr/bin/python3", str(tool), *args], cwd=tmp_path, capture_output=True, text=True,
                           timeout=20)
        assert p.returncode == 2 and words in p.stderr, (args, p.returncode, p.stderr)
    assert not (tmp_path / "out.log").exists()
    # (pass 92) and the compiled file of a module it runs (--check: a regression writes nothing)
    cached = subprocess.run(["/usr/bin/python3", "-c", "import argparse; print(argparse.__cached__)"],
                            capture_output=True, text=True).stdout.strip()
    if os.path.isfile(cached):
        p = subprocess.run(["/usr/bin/python3", str(tool), "--check", "log.tmp", cached], cwd=tmp_path,
                           capture_output=True, text=True, timeout=20)
        assert p.returncode == 2 and "the same file as this program" in p.stderr, p.stderr
    # (pass 102) an input glued to a short option, as a script may pass it (-sscene.yaml), was written over
    (tmp_path / "sc.yaml").write_text("name: x\n")
    # (pass 104) and in a comma list, a key=path value, a cluster of short options
    for arg in ("-ssc.yaml", "--scenes=a.yaml,sc.yaml", "scene=sc.yaml", "-vssc.yaml", "a.yaml,sc.yaml"):
        p = subprocess.run(["/usr/bin/python3", str(tool), "log.tmp", "sc.yaml", "--", arg], cwd=tmp_path,
                           capture_output=True, text=True, timeout=20)
        assert p.returncode == 2 and (tmp_path / "sc.yaml").read_text() == "name: x\n", (arg, p.stderr)
    p = subprocess.run(["/usr/bin/python3", str(tool), "--check", "log.tmp", "log.tmp"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=20)  # (pass 118) --check says so too
    assert p.returncode == 2 and "log.tmp: the same file as the input log.tmp" in p.stderr, p.stderr
    p = subprocess.run(["/usr/bin/python3", str(tool), "log.tmp", "out.log"], cwd=tmp_path, timeout=20)
    assert p.returncode == 0 and (tmp_path / "out.log").read_text() == "the log\n"


def test_save_output_copies_a_log_larger_than_its_memory(tmp_path):
    # (pass 92) SOURCE was read whole: a large log ended in a MemoryError traceback (or met the OOM killer)
    source = tmp_path / "big.log"
    with open(source, "wb") as f:
        f.truncate(200 << 20)  # sparse: 200 MiB of NUL costs no disk until copied
    p = subprocess.run(["bash", "-c", f"ulimit -v 120000; exec /usr/bin/python3 "
                        f"{SOURCE / 'tools/pages/save_output.py'} big.log out.log"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and "Traceback" not in p.stderr, p.stderr
    assert (tmp_path / "out.log").stat().st_size == 200 << 20
