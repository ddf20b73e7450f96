"""tools/run_paper.sh, the main job, in a copy of tools/ (its out/paper/ is
the copy's; the build is the tests'): the previous set of runs stays whole
when an override is refused by any scene or a run stops part-way."""
import os
import shutil
import subprocess

from conftest import BIN, SOURCE

RUNS = ("ideal", "clearance", "spatial")


def copy_of_tools(tmp_path):
    """The script, what it sources and reads, with bootstrap.sh a no-op (the packages are the build's)."""
    root = tmp_path / "repo"
    (root / "tools").mkdir(parents=True)
    for part in ("run_paper.sh", "lib", "scenes", "paper", "pages"):
        src = SOURCE / "tools" / part
        (shutil.copytree if src.is_dir() else shutil.copy)(src, root / "tools" / part)
    shutil.copytree(SOURCE / "python" / "gimbalsim", root / "python" / "gimbalsim")  # the plots' one writer
    (root / "tools" / "bootstrap.sh").write_text("exit 0\n")
    out = root / "out" / "paper"
    out.mkdir(parents=True)
    for run in RUNS:  # a previous set, as a reader would find it
        (out / f"{run}.csv").write_text(f"previous {run}\n")
        (out / f"{run}.json").write_text(f'{{"previous": "{run}"}}\n')
    return root, out


def run_paper(root, *overrides):
    env = dict(os.environ, GIMBALSIM_BUILD=str(BIN.parent))
    return subprocess.run(["bash", str(root / "tools" / "run_paper.sh"), *overrides], capture_output=True, text=True,
                          timeout=600, env=env)


def previous_set_kept(out):
    return all((out / f"{run}.csv").read_text() == f"previous {run}\n" for run in RUNS) and \
        sorted(p.name for p in out.iterdir()) == sorted(f"{run}.{ext}" for run in RUNS for ext in ("csv", "json"))


def test_an_override_one_scene_refuses_runs_none(tmp_path):
    # (pass 68) coulomb_stick, which the spatial scene refuses, came after the ideal and clearance runs had
    # replaced theirs, and the exit said "refused, nothing run"
    root, out = copy_of_tools(tmp_path)
    p = run_paper(root, "sim.duration=0.1", "friction.law=coulomb_stick")
    assert p.returncode == 2 and "key 'friction.law': coulomb_stick" in p.stderr, p.stderr
    assert "refused, nothing run" in p.stderr and previous_set_kept(out), sorted(os.listdir(out))


def test_a_run_that_stops_part_way_leaves_the_previous_set(tmp_path):
    # the ideal scene runs whole, the clearance scene stops on sim.max_substeps: the set is not replaced in part
    root, out = copy_of_tools(tmp_path)
    p = run_paper(root, "sim.duration=0.1", "sim.max_substeps=2")
    assert p.returncode == 3 and "more work in one step than sim.max_substeps allows" in p.stderr, p.stderr
    assert previous_set_kept(out), sorted(os.listdir(out))


def test_runs_the_plot_refuses_leave_the_previous_set(tmp_path):
    # (pass 69) structure.joint2=ideal passes every scene's check and runs, then the plot refuses a clearance
    # run without clearance: the three runs had replaced the previous ones before it, and the exit said 2
    root, out = copy_of_tools(tmp_path)
    p = run_paper(root, "sim.duration=0.1", "structure.joint2=ideal")
    assert p.returncode == 2 and "joint 2 has no clearance" in p.stderr, p.stderr
    assert previous_set_kept(out), sorted(os.listdir(out))


def test_a_link_or_a_folder_under_an_output_name_is_refused_before_anything_runs(tmp_path):
    # (pass 71) a folder under a figure's name cost the whole run, then exit 4; a link under plot_summary.txt or a
    # figure was replaced without a word, while one under ideal.csv was refused; out/paper or out/paper/plots as
    # a link had every output written through it
    for case, make in [("figure folder", lambda out: (out / "plots" / "fig06_eccentricity.png").mkdir(parents=True)),
                       ("summary link", lambda out: (out / "plot_summary.txt").symlink_to(out.parent / "elsewhere")),
                       ("figure link", lambda out: ((out / "plots").mkdir(),
                                                    (out / "plots" / "fig07_contact_force.png").symlink_to(
                                                        out.parent / "elsewhere.png"))),
                       ("plots link", lambda out: (out / "plots").symlink_to(out.parent, target_is_directory=True)),
                       ("out link", None)]:
        root, out = copy_of_tools(tmp_path / case.replace(" ", "_"))
        if make is None:
            real = out.parent / "real_paper"
            out.rename(real)
            out.symlink_to(real, target_is_directory=True)
        else:
            make(out)
        p = run_paper(root, "sim.duration=0.1")
        assert p.returncode == 2, (case, p.stderr)
        assert ("a symbolic link; not written through" in p.stderr or "a folder where an output goes" in p.stderr) \
            and "nothing run" in p.stderr, (case, p.stderr)
        assert "== [3/4] simulations" not in p.stdout, (case, p.stdout)
        assert not (out.parent / "elsewhere").exists() and not (out.parent / "elsewhere.png").exists(), case


def test_an_output_that_is_an_input_scene_by_a_hard_link_is_refused_before_anything_runs(tmp_path):
    # (pass 76) plot_summary.txt hard-linked to a scene the runs read was replaced without a word, where the
    # programs refuse an output that is the same file as an input
    root, out = copy_of_tools(tmp_path)
    scene = root / "tools" / "scenes" / "paper_clearance.yaml"
    os.link(scene, out / "plot_summary.txt")
    p = run_paper(root, "sim.duration=0.1")
    assert p.returncode == 2, p.stderr
    assert "plot_summary.txt is the same file as the input tools/scenes/paper_clearance.yaml" in p.stderr and \
        "nothing run" in p.stderr, p.stderr
    assert "== [3/4] simulations" not in p.stdout and (out / "plot_summary.txt").samefile(scene)


def test_a_stop_during_the_runs_says_the_previous_set_is_kept(tmp_path):
    # (pass 71) gimbalsim said "rename failed" as the script's exit removed the staging folder under it; (pass 72)
    # nothing said what a stop had left
    import signal
    import time
    root, out = copy_of_tools(tmp_path)
    env = dict(os.environ, GIMBALSIM_BUILD=str(BIN.parent))
    proc = subprocess.Popen(["bash", str(root / "tools" / "run_paper.sh"), "sim.duration=60"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env, start_new_session=True)
    deadline = time.time() + 120
    while not list(out.glob(".runs.*/.ideal.csv.*")) and time.time() < deadline:  # the first run is writing
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 143, err
    assert "run_paper.sh: interrupted (SIGTERM); the previous outputs are kept" in err, err
    assert "rename failed" not in err, err
    assert previous_set_kept(out), sorted(os.listdir(out))


def test_a_folder_put_under_an_output_name_during_the_runs_keeps_the_previous_set(tmp_path):
    # the names are checked again before the moves: one folder come meanwhile, and nothing is moved (exit 4)
    import time
    root, out = copy_of_tools(tmp_path)
    env = dict(os.environ, GIMBALSIM_BUILD=str(BIN.parent))
    proc = subprocess.Popen(["bash", str(root / "tools" / "run_paper.sh")], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)
    deadline = time.time() + 120
    while not list(out.glob(".runs.*")) and time.time() < deadline:  # past the first check: the runs started
        time.sleep(0.01)
    (out / "plot_summary.txt").mkdir()
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 4, err
    assert ("run_paper.sh: out/paper/plot_summary.txt is a folder where an output goes: move it away; the "
            "previous outputs are kept") in err, err
    (out / "plot_summary.txt").rmdir()
    assert previous_set_kept(out), sorted(os.listdir(out))


def test_a_relative_build_is_read_where_the_user_stands(tmp_path):
    # (pass 80) a relative GIMBALSIM_BUILD was read against the repository: the user's own build was never used,
    # and a name missing there was configured inside the checkout
    root, out = copy_of_tools(tmp_path)
    here = tmp_path / "here"
    here.mkdir()
    (here / "mybuild").symlink_to(BIN.parent, target_is_directory=True)
    (root / "mybuild").mkdir()  # the same name in the repository, not a build: never read
    env = dict(os.environ, GIMBALSIM_BUILD="mybuild")
    p = subprocess.run(["bash", str(root / "tools" / "run_paper.sh"), "sim.duration=0.1"], capture_output=True,
                       text=True, timeout=600, env=env, cwd=here)
    assert p.returncode == 0, p.stderr
    assert f"Release build in {here / 'mybuild'}/" in p.stdout and (out / "ideal.json").read_text() != \
        '{"previous": "ideal"}\n', p.stdout
    env["GIMBALSIM_BUILD"] = "nowhere"  # missing where the user stands: refused, nothing configured anywhere
    p = subprocess.run(["bash", str(root / "tools" / "run_paper.sh"), "sim.duration=0.1"], capture_output=True,
                       text=True, timeout=600, env=env, cwd=here)
    assert p.returncode == 2 and f"GIMBALSIM_BUILD=nowhere: {here / 'nowhere'} is not a configured build" in \
        p.stderr, p.stderr
    assert not (here / "nowhere").exists() and not (root / "nowhere").exists() and "[3/4]" not in p.stdout
