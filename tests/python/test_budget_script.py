"""tools/sweeps/run_pointing_budget.sh: a user's spec writes to the user's
output folder and leaves the project's pages alone; only the shipped budget
regenerates docs/results/pointing_budget.md. Run in a copy of the files the
script touches, so a regression cannot write into the source tree."""
import hashlib
import os
import pathlib
import shutil
import subprocess

from conftest import CONTROLLER_CONFIG, SCENES, SOURCE

SPEC = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.5}}
controller: {CONTROLLER_CONFIG}
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.2, profile.hold_time: 0.1}}
samples: 2
seed: 3
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
phases: [slew, hold, track]
indices:
  ape: {{level: 0.5, confidence: 0.5, requirement: 1.0}}
"""


def digest(folder):
    h = hashlib.sha256()
    for p in sorted(folder.rglob("*")):
        if p.is_file():
            h.update(str(p.relative_to(folder)).encode() + p.read_bytes())
    return h.hexdigest()


def test_a_users_spec_writes_its_own_folder_and_no_project_page(tmp_path):
    root = tmp_path / "checkout"
    for rel in ("tools/sweeps/run_pointing_budget.sh", "tools/lib/console.sh", "tools/lib/children.sh",
                "tools/lib/build_dir.sh",
                "tools/pages/results_page.py", "tools/pages/results_index.py", "docs/results/pointing_budget.md",
                "docs/results/README.md"):
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(SOURCE / rel, root / rel)
    for png in (SOURCE / "docs" / "results").glob("pointing_budget_*.png"):
        shutil.copy(png, root / "docs" / "results" / png.name)
    before = digest(root / "docs")
    work = tmp_path / "work"
    (work / "out").mkdir(parents=True)
    (work / "my_budget.yaml").write_text(SPEC)
    # the package the tests use: PYTHONPATH is BUILD/python
    env = dict(os.environ, GIMBALSIM_BUILD=str(pathlib.Path(os.environ["PYTHONPATH"]).parent))
    p = subprocess.run(["bash", str(root / "tools/sweeps/run_pointing_budget.sh"), "my_budget.yaml", "--workers", "1"],
                       cwd=work, capture_output=True, text=True, timeout=600, env=env)
    assert p.returncode == 0, p.stderr
    out = work / "out" / "pointing_budget-my_budget"
    assert (out / "report.md").is_file() and (out / "results.csv").is_file()
    assert digest(root / "docs") == before, "a user's budget changed the project's pages"

    # --out names the folder instead; a relative GIMBALSIM_BUILD is read where the user stands, as the spec is
    (work / "mybuild").symlink_to(pathlib.Path(env["GIMBALSIM_BUILD"]))
    env["GIMBALSIM_BUILD"] = "mybuild"
    p = subprocess.run(["bash", str(root / "tools/sweeps/run_pointing_budget.sh"), "my_budget.yaml", "--out",
                        "out/mine", "--workers", "1"], cwd=work, capture_output=True, text=True, timeout=600, env=env)
    assert p.returncode == 0, p.stderr
    assert (work / "out" / "mine" / "report.md").is_file()
    assert digest(root / "docs") == before


def test_the_shipped_page_cannot_be_sent_elsewhere(tmp_path):
    # Without a SPEC the script regenerates the project's page: an --out there is refused before anything runs.
    env = dict(os.environ, GIMBALSIM_BUILD=str(pathlib.Path(os.environ["PYTHONPATH"]).parent))
    for args in (["--out", str(tmp_path / "x")], ["--out=" + str(tmp_path / "x")]):  # --out=DIR got past the guard
        p = subprocess.run(["bash", str(SOURCE / "tools/sweeps/run_pointing_budget.sh"), *args],
                           capture_output=True, text=True, timeout=60, env=env)
        assert p.returncode == 2, args
        assert "name the spec" in p.stderr
        assert not (tmp_path / "x").exists()


def test_a_spec_after_an_option_is_told_to_go_first(tmp_path):
    # (pass 90) `--check my.yaml` went to the shipped budget's sweeps: "unrecognized arguments: my.yaml"
    env = dict(os.environ, GIMBALSIM_BUILD=str(pathlib.Path(os.environ["PYTHONPATH"]).parent))
    (tmp_path / "my.yaml").write_text(SPEC)
    (tmp_path / "my.txt").write_text(SPEC)  # (pass 93) a spec not named .yaml went to the sweeps all the same
    for args in (["--check", "my.yaml"], ["--spatial", "--check", "my.yaml"], ["--check", "my.txt"]):
        p = subprocess.run(["bash", str(SOURCE / "tools/sweeps/run_pointing_budget.sh"), *args], cwd=tmp_path,
                           capture_output=True, text=True, timeout=60, env=env)
        assert p.returncode == 2 and f"{args[-1]}: a spec goes first, before the options" in p.stderr, (args, p.stderr)
        assert "unrecognized" not in p.stderr and not (tmp_path / "out").exists()


def test_a_refused_shipped_spec_leaves_the_previous_results(tmp_path):
    # The shipped budget regenerates out/pointing_budget/: a spec refused (or a run that fails)
    # must leave the previous results there, and write no page.
    root = tmp_path / "checkout"
    for rel in ("tools/sweeps/run_pointing_budget.sh", "tools/lib/console.sh", "tools/lib/children.sh",
                "tools/lib/build_dir.sh",
                "tools/pages/results_page.py", "tools/pages/results_index.py", "docs/results/pointing_budget.md"):
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(SOURCE / rel, root / rel)
    (root / "tools/sweeps/pointing_budget.yaml").write_text(SPEC.replace("samples: 2", "samples: 2\nsampels: 3"))
    previous = root / "out" / "pointing_budget"
    previous.mkdir(parents=True)
    (previous / "results.csv").write_text("the previous run's\n")
    before = digest(root / "docs")
    env = dict(os.environ, GIMBALSIM_BUILD=str(pathlib.Path(os.environ["PYTHONPATH"]).parent))
    p = subprocess.run(["bash", str(root / "tools/sweeps/run_pointing_budget.sh"), "--workers", "1"],
                       capture_output=True, text=True, timeout=300, env=env)
    assert p.returncode == 2, p.stderr
    assert "key 'sampels': unknown key" in p.stderr
    assert (previous / "results.csv").read_text() == "the previous run's\n"
    assert sorted(os.listdir(root / "out")) == ["pointing_budget"]  # no half-made folder left
    assert digest(root / "docs") == before


def test_a_refused_spec_makes_no_out_folder(tmp_path):
    # Where the user stands holds no out/: a spec the sweep refuses leaves none behind (it did).
    work = tmp_path / "work"
    work.mkdir()
    (work / "bad.yaml").write_text(SPEC.replace("samples: 2", "samples: 2\nsampels: 3"))
    env = dict(os.environ, GIMBALSIM_BUILD=str(pathlib.Path(os.environ["PYTHONPATH"]).parent))
    p = subprocess.run(["bash", str(SOURCE / "tools/sweeps/run_pointing_budget.sh"), "bad.yaml", "--workers", "1"],
                       cwd=work, capture_output=True, text=True, timeout=300, env=env)
    assert p.returncode == 2 and "key 'sampels': unknown key" in p.stderr, p.stderr
    assert sorted(os.listdir(work)) == ["bad.yaml"]
    # the shipped budget's run too (in a copy of what it touches), out/ made for it and taken back
    root = tmp_path / "checkout"
    for rel in ("tools/sweeps/run_pointing_budget.sh", "tools/lib/console.sh", "tools/lib/children.sh",
                "tools/lib/build_dir.sh",
                "tools/pages/results_page.py", "tools/pages/results_index.py"):
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(SOURCE / rel, root / rel)
    (root / "tools/sweeps/pointing_budget.yaml").write_text(SPEC.replace("samples: 2", "samples: 2\nsampels: 3"))
    p = subprocess.run(["bash", str(root / "tools/sweeps/run_pointing_budget.sh"), "--workers", "1"],
                       capture_output=True, text=True, timeout=300, env=env)
    assert p.returncode == 2 and not (root / "out").exists(), p.stderr


def checkout_with_spec(tmp_path, spec_text=None):
    """TMP/checkout: a copy of what the shipped budget's run touches, no out/; its spec the shipped one, or
    spec_text."""
    root = tmp_path / "checkout"
    for rel in ("tools/sweeps/run_pointing_budget.sh", "tools/lib/console.sh", "tools/lib/children.sh",
                "tools/lib/build_dir.sh",
                "tools/sweeps/pointing_budget.yaml", "tools/pages/results_page.py", "tools/pages/results_index.py",
                "tools/pages/output_file.py", "python/gimbalsim/_output.py", "python/gimbalsim/_csv_cells.py",
                "python/gimbalsim/_console.py",
                "python/gimbalsim/_number.py", "python/gimbalsim/_early_signals.py",
                "python/gimbalsim/_flags.py",
                "tools/lib/console.sh", "docs/results/pointing_budget.md", "docs/results/README.md"):
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(SOURCE / rel, root / rel)
    if spec_text is not None:
        (root / "tools/sweeps/pointing_budget.yaml").write_text(spec_text)
    return root


def checkout_with_previous_results(tmp_path):
    """checkout_with_spec, out/pointing_budget/ holding a previous run's results."""
    root = checkout_with_spec(tmp_path)
    previous = root / "out" / "pointing_budget"
    previous.mkdir(parents=True)
    (previous / "results.csv").write_text("the previous run's\n")
    return root, previous


def fake_sweep(tmp_path):
    """TMP/fakebuild/python/gimbalsim: a stand-in sweep (FAKE_SWEEP) for GIMBALSIM_BUILD=TMP/fakebuild."""
    fake = tmp_path / "fakebuild" / "python" / "gimbalsim"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("")
    (fake / "sweep.py").write_text(FAKE_SWEEP)


def spatial_checkout_with_a_fake_sweep(tmp_path):
    """checkout_with_previous_results with the spatial specs, and fake_sweep."""
    root, previous = checkout_with_previous_results(tmp_path)
    for rel in ("tools/sweeps/pointing_budget_spatial.yaml", "tools/sweeps/pointing_budget_spatial_tracker.yaml"):
        shutil.copy(SOURCE / rel, root / rel)
    fake_sweep(tmp_path)
    return root, previous


def test_help_and_version_are_answered_before_anything(tmp_path):
    # --help went to the sweep, which printed its help and wrote nothing; the script then removed
    # out/pointing_budget/ and failed moving the missing new folder (exit 1, the previous results gone).
    root, previous = checkout_with_previous_results(tmp_path)
    script = root / "tools/sweeps/run_pointing_budget.sh"
    before = digest(root / "docs")
    work = tmp_path / "work"
    work.mkdir()
    built = str(pathlib.Path(os.environ["PYTHONPATH"]).parent)
    for build in (built, str(tmp_path / "nowhere")):  # the usage needs no package
        for args in (["--help"], ["-h"], ["--workers", "1", "--help"], ["my_budget.yaml", "--help"]):
            p = subprocess.run(["bash", str(script), *args], cwd=work, capture_output=True, text=True, timeout=60,
                               env=dict(os.environ, GIMBALSIM_BUILD=build))
            assert p.returncode == 0 and p.stderr == "", (args, p.stderr)
            assert "run_pointing_budget.sh MY_SPEC [--out DIR]" in p.stdout and "gimbalsim.sweep" in p.stdout, p.stdout
    p = subprocess.run(["bash", str(script), "--version"], cwd=work, capture_output=True, text=True, timeout=60,
                       env=dict(os.environ, GIMBALSIM_BUILD=built))
    assert p.returncode == 0 and p.stdout.startswith("gimbalsim.sweep "), p.stderr
    p = subprocess.run(["bash", str(script), "--version"], cwd=work, capture_output=True, text=True, timeout=60,
                       env=dict(os.environ, GIMBALSIM_BUILD=str(tmp_path / "nowhere")))
    assert p.returncode == 2 and "no gimbalsim package in" in p.stderr and p.stdout == "", p.stderr
    assert (previous / "results.csv").read_text() == "the previous run's\n"
    assert sorted(os.listdir(root / "out")) == ["pointing_budget"] and os.listdir(work) == []
    assert digest(root / "docs") == before


FAKE_SWEEP = '''
import os, pathlib, sys
out = pathlib.Path(sys.argv[sys.argv.index("--out") + 1])
how = os.environ["FAKE_SWEEP"]
if "--check" in sys.argv:  # the script's check of every spec before any runs
    sys.exit(2 if os.environ.get("FAKE_REFUSE") and os.environ["FAKE_REFUSE"] in sys.argv[1] else 0)
if os.environ.get("FAKE_LOG"):  # which specs ran
    with open(os.environ["FAKE_LOG"], "a") as log:
        log.write(sys.argv[1] + "\\n")
if os.environ.get("FAKE_PARTIAL_FOR") and os.environ["FAKE_PARTIAL_FOR"] in sys.argv[1]:  # half a folder
    how = "partial"
if os.environ.get("FAKE_INTERRUPT_EMPTY_FOR") and os.environ["FAKE_INTERRUPT_EMPTY_FOR"] in sys.argv[1] \
        and "--resume" not in sys.argv:  # interrupted before it wrote anything
    sys.exit(143)
if os.environ.get("FAKE_PLANT") and "spatial_tracker" in sys.argv[1]:  # a link planted while the budgets run
    os.symlink(os.environ["FAKE_PLANT_TARGET"], os.environ["FAKE_PLANT"])
if os.environ.get("FAKE_INTERRUPT_FOR") and os.environ["FAKE_INTERRUPT_FOR"] in sys.argv[1] \
        and "--resume" not in sys.argv:  # interrupted: its samples kept in a journal
    out.mkdir()
    (out / "results.partial.csv").write_text("half\\n")
    sys.exit(130)
if how != "nothing":
    out.mkdir(exist_ok="--resume" in sys.argv)
    (out / "results.partial.csv").unlink(missing_ok=True)
    (out / "results.csv").write_text("the new run's\\n")
if how == "whole":
    (out / "summary.json").write_text("{}\\n")
    (out / "report.md").write_text("# budget\\n\\n![ape](plots/ape_cdf.png)\\n")
    (out / "plots").mkdir(exist_ok=True)
    (out / "plots" / "ape_cdf.png").write_bytes(b"png")
'''


def test_the_previous_results_go_only_for_a_whole_new_folder(tmp_path):
    # A sweep (here a stand-in: no real sweep runs) that ends well but leaves no folder, or half of one,
    # must not cost the previous results; a whole one replaces them and makes the page.
    root, previous = checkout_with_previous_results(tmp_path)
    fake_sweep(tmp_path)
    before = digest(root / "docs")
    for how in ("nothing", "partial"):
        env = dict(os.environ, GIMBALSIM_BUILD=str(tmp_path / "fakebuild"), FAKE_SWEEP=how)
        p = subprocess.run(["bash", str(root / "tools/sweeps/run_pointing_budget.sh")], capture_output=True, text=True,
                           timeout=60, env=env)
        assert p.returncode == 1 and "left no whole budget" in p.stderr, (how, p.stderr)
        assert (previous / "results.csv").read_text() == "the previous run's\n", how
        assert sorted(os.listdir(root / "out")) == ["pointing_budget"], how
        assert digest(root / "docs") == before, how
    env["FAKE_SWEEP"] = "whole"
    p = subprocess.run(["bash", str(root / "tools/sweeps/run_pointing_budget.sh")], capture_output=True, text=True,
                       timeout=60, env=env)
    assert p.returncode == 0, p.stderr
    assert (previous / "results.csv").read_text() == "the new run's\n"
    assert sorted(os.listdir(root / "out")) == ["pointing_budget"]
    assert (root / "docs/results/pointing_budget_ape_cdf.png").read_bytes() == b"png"
    assert "](pointing_budget_ape_cdf.png)" in (root / "docs/results/pointing_budget.md").read_text()


def test_the_spatial_page_holds_both_budgets_or_neither(tmp_path):
    # --spatial: the tilting bearing's budget on the encoders only and with the antenna's sensors,
    # each into its own out/ folder, one page; nothing replaced unless both budgets completed.
    root, previous = spatial_checkout_with_a_fake_sweep(tmp_path)
    results = root / "docs/results"
    (results / "pointing_budget_ape_cdf.png").write_bytes(b"the planar page's")
    (results / "pointing_budget_spatial_rpe_slew_cdf.png").write_bytes(b"stale")
    spatial_out = root / "out" / "pointing_budget_spatial"
    spatial_out.mkdir()
    (spatial_out / "results.csv").write_text("the previous spatial run's\n")
    script = str(root / "tools/sweeps/run_pointing_budget.sh")
    env = dict(os.environ, GIMBALSIM_BUILD=str(tmp_path / "fakebuild"), FAKE_SWEEP="whole",
               FAKE_PARTIAL_FOR="spatial_tracker")
    before = digest(root / "docs")
    p = subprocess.run(["bash", script, "--spatial"], capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 1 and "left no whole budget" in p.stderr, p.stderr
    assert (spatial_out / "results.csv").read_text() == "the previous spatial run's\n"
    assert sorted(os.listdir(root / "out")) == ["pointing_budget", "pointing_budget_spatial"]
    assert digest(root / "docs") == before
    del env["FAKE_PARTIAL_FOR"]
    p = subprocess.run(["bash", script, "--spatial", "--workers", "1"], capture_output=True, text=True, timeout=60,
                       env=env)
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(root / "out")) == ["pointing_budget", "pointing_budget_spatial",
                                                "pointing_budget_spatial_tracker"]
    assert (spatial_out / "results.csv").read_text() == "the new run's\n"
    assert (previous / "results.csv").read_text() == "the previous run's\n", "the planar budget's results kept"
    page = (results / "pointing_budget_spatial.md").read_text()
    encoders, antenna = page.index("## The loop on the encoders only"), page.index("## The loop at the antenna")
    assert encoders < page.index("](pointing_budget_spatial_ape_cdf.png)") < antenna < \
        page.index("](pointing_budget_spatial_tracker_ape_cdf.png)"), page
    assert "Regenerate: `bash tools/sweeps/run_pointing_budget.sh --spatial --workers 1`" in page
    for name in ("pointing_budget_spatial_ape_cdf.png", "pointing_budget_spatial_tracker_ape_cdf.png"):
        assert (results / name).read_bytes() == b"png", name
    assert (results / "pointing_budget_ape_cdf.png").read_bytes() == b"the planar page's"
    assert not (results / "pointing_budget_spatial_rpe_slew_cdf.png").exists(), "a stale plot of this page left"
    # Refused before any budget runs: a spec the sweep refuses (the second one was checked only after the
    # first budget's run), a link at the page or at one of its plots (found after the results were replaced).
    log = tmp_path / "ran.log"
    env["FAKE_LOG"] = str(log)
    before = digest(root / "docs")
    p = subprocess.run(["bash", script, "--spatial"], capture_output=True, text=True, timeout=60,
                       env=dict(env, FAKE_REFUSE="spatial_tracker"))
    assert p.returncode == 2 and not log.exists(), p.stderr
    for planted in (results / "pointing_budget_spatial.md", results / "pointing_budget_spatial_tracker_ape_cdf.png"):
        victim = tmp_path / "victim"
        victim.write_text("keep\n")
        planted.unlink()
        planted.symlink_to(victim)
        p = subprocess.run(["bash", script, "--spatial"], capture_output=True, text=True, timeout=60, env=env)
        assert p.returncode == 2 and "a symbolic link or not a regular file" in p.stderr, p.stderr
        assert not log.exists() and victim.read_text() == "keep\n", planted
        planted.unlink()
        planted.write_bytes(b"png")
    assert (spatial_out / "results.csv").read_text() == "the new run's\n"
    # a spec runs alone, not as part of the shipped page
    p = subprocess.run(["bash", script, "--spatial", "my.yaml"], capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 2 and "--spatial runs the shipped spatial budgets" in p.stderr, p.stderr


def test_a_sweeps_check_runs_and_writes_nothing(tmp_path):
    # sweep --check: what the script asks of every spec before any budget runs
    import sys
    (tmp_path / "good.yaml").write_text(SPEC)
    (tmp_path / "bad.yaml").write_text(SPEC.replace("samples: 2", "samples: 2\nsampels: 3"))
    for name, code in (("good.yaml", 0), ("bad.yaml", 2)):
        p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(tmp_path / name), "--out",
                            str(tmp_path / "out"), "--check"], capture_output=True, text=True, timeout=120)
        assert p.returncode == code, p.stderr
        assert sorted(os.listdir(tmp_path)) == ["bad.yaml", "good.yaml"]
    assert "key 'sampels': unknown key" in p.stderr


def test_the_shipped_page_is_made_in_a_checkout_without_out(tmp_path):
    # The specs' check ran before out/ was made, and refused every fresh checkout ("does not exist").
    root = checkout_with_spec(tmp_path, SPEC)
    env = dict(os.environ, GIMBALSIM_BUILD=str(pathlib.Path(os.environ["PYTHONPATH"]).parent))
    p = subprocess.run(["bash", str(root / "tools/sweeps/run_pointing_budget.sh"), "--workers", "1"],
                       capture_output=True, text=True, timeout=300, env=env)
    assert p.returncode == 0, p.stderr
    assert (root / "out/pointing_budget/results.csv").is_file()
    assert "Regenerate: `bash tools/sweeps/run_pointing_budget.sh --workers 1`" in \
        (root / "docs/results/pointing_budget.md").read_text()
    assert sorted(os.listdir(root)) == ["docs", "out", "python", "tools"], "no check folder left"


def test_the_real_sweep_finishes_an_interrupted_page_run_on_resume(tmp_path):
    # The specs' check took --resume too, of its own folder that never exists: every --resume was refused.
    import sys
    root = checkout_with_spec(tmp_path, SPEC)
    new = root / "out" / "pointing_budget.new"
    new.parent.mkdir()
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(root / "tools/sweeps/pointing_budget.yaml"),
                        "--out", str(new), "--workers", "1", "--no-progress"], capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stderr
    # as an interruption leaves it: the first sample's row in the journal, nothing else
    rows = (new / "results.csv").read_text().splitlines(keepends=True)
    shutil.rmtree(new)
    new.mkdir()
    (new / "results.partial.csv").write_text("".join(rows[:2]))
    env = dict(os.environ, GIMBALSIM_BUILD=str(pathlib.Path(os.environ["PYTHONPATH"]).parent))
    p = subprocess.run(["bash", str(root / "tools/sweeps/run_pointing_budget.sh"), "--resume", "--workers", "1"],
                       capture_output=True, text=True, timeout=300, env=env)
    assert p.returncode == 0, p.stderr
    assert "2 samples, 1 already done, 1 to run" in p.stderr, p.stderr
    assert (root / "out/pointing_budget/results.csv").read_text().splitlines()[:2] == \
        [r.rstrip("\n") for r in rows[:2]]
    assert not new.exists()
    assert "Regenerate: `bash tools/sweeps/run_pointing_budget.sh --workers 1`" in \
        (root / "docs/results/pointing_budget.md").read_text()


def test_an_interrupted_page_run_is_finished_by_resume_and_two_runs_are_refused(tmp_path):
    # An interrupted budget's folder was removed by the script while the sweep said "run again with
    # --resume"; and two runs at once wrote the same page and index.
    import fcntl
    root, previous = spatial_checkout_with_a_fake_sweep(tmp_path)
    script = str(root / "tools/sweeps/run_pointing_budget.sh")
    env = dict(os.environ, GIMBALSIM_BUILD=str(tmp_path / "fakebuild"), FAKE_SWEEP="whole",
               FAKE_INTERRUPT_FOR="spatial_tracker")
    before = digest(root / "docs")
    p = subprocess.run(["bash", script, "--spatial"], capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 130, p.stderr
    assert "out/pointing_budget_spatial_tracker.new kept" in p.stderr and "--resume" in p.stderr, p.stderr
    assert (root / "out/pointing_budget_spatial_tracker.new/results.partial.csv").read_text() == "half\n"
    assert (root / "out/pointing_budget_spatial.new/results.csv").is_file(), "the finished budget kept too"
    assert digest(root / "docs") == before
    # without --resume the kept folder is refused, not overwritten
    p = subprocess.run(["bash", script, "--spatial"], capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 2 and "holds an interrupted budget" in p.stderr, p.stderr
    assert (root / "out/pointing_budget_spatial_tracker.new/results.partial.csv").is_file()
    # the page is one run's at a time: a second run while the first holds the script's lock is refused
    fd = os.open(root / "tools/sweeps/run_pointing_budget.sh", os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        p = subprocess.run(["bash", script, "--spatial", "--resume"], capture_output=True, text=True, timeout=60,
                           env=env)
        assert p.returncode == 2 and "another run_pointing_budget.sh is writing" in p.stderr, p.stderr
        p = subprocess.run(["bash", script], capture_output=True, text=True, timeout=60, env=env)
        assert p.returncode == 2 and "another run_pointing_budget.sh is writing" in p.stderr, p.stderr
    finally:
        os.close(fd)
    assert digest(root / "docs") == before
    p = subprocess.run(["bash", script, "--spatial", "--resume"], capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(root / "out")) == ["pointing_budget", "pointing_budget_spatial",
                                                "pointing_budget_spatial_tracker"]
    page = (root / "docs/results/pointing_budget_spatial.md").read_text()
    assert "Regenerate: `bash tools/sweeps/run_pointing_budget.sh --spatial`" in page, page


def test_an_interrupted_page_run_keeps_a_finished_budget_and_a_failed_page_changes_nothing(tmp_path):
    # Pass 18: an interruption before the second budget wrote its journal deleted the first, finished
    # budget; a link planted in the kept folder took the page's body; a page that could not be written
    # left docs/results half replaced; --check ran the sweeps and exited 1.
    root, previous = spatial_checkout_with_a_fake_sweep(tmp_path)
    script = str(root / "tools/sweeps/run_pointing_budget.sh")
    env = dict(os.environ, GIMBALSIM_BUILD=str(tmp_path / "fakebuild"), FAKE_SWEEP="whole")
    log = tmp_path / "ran.log"
    p = subprocess.run(["bash", script, "--spatial", "--check"], capture_output=True, text=True, timeout=60,
                       env=dict(env, FAKE_LOG=str(log)))
    assert p.returncode == 0 and "nothing run" in p.stderr and not log.exists(), p.stderr
    assert sorted(os.listdir(root / "out")) == ["pointing_budget"]
    p = subprocess.run(["bash", script, "--spatial"], capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 0, p.stderr
    results = root / "docs/results"
    page = results / "pointing_budget_spatial.md"
    plots_before = {n: (results / n).read_bytes() for n in os.listdir(results) if n.endswith(".png")}
    # interrupted as the second budget starts: the first, finished, is kept for --resume
    p = subprocess.run(["bash", script, "--spatial"], capture_output=True, text=True, timeout=60,
                       env=dict(env, FAKE_INTERRUPT_EMPTY_FOR="spatial_tracker"))
    assert p.returncode == 143, p.stderr
    assert "out/pointing_budget_spatial.new kept" in p.stderr, p.stderr
    assert (root / "out/pointing_budget_spatial.new/results.csv").is_file()
    victim = tmp_path / "victim"
    victim.write_text("keep\n")
    (root / "out/pointing_budget_spatial.new/page_body.md").symlink_to(victim)
    # the page cannot be written (a link planted at it while the budgets run): exit 4, nothing replaced
    page.unlink()
    target = tmp_path / "page_target"
    target.write_text("other\n")
    p = subprocess.run(["bash", script, "--spatial", "--resume"], capture_output=True, text=True, timeout=60,
                       env=dict(env, FAKE_PLANT=str(page), FAKE_PLANT_TARGET=str(target)))
    assert p.returncode == 4, p.stderr
    assert page.is_symlink() and target.read_text() == "other\n" and victim.read_text() == "keep\n"
    assert {n: (results / n).read_bytes() for n in os.listdir(results) if n.endswith(".png")} == plots_before
    assert not [n for n in os.listdir(results) if n.startswith(".")], "a backup folder left"
    assert (previous / "results.csv").read_text() == "the previous run's\n"
    page.unlink()
    p = subprocess.run(["bash", script, "--spatial", "--resume"], capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 0, p.stderr
    assert victim.read_text() == "keep\n" and page.is_file()
    assert sorted(os.listdir(root / "out")) == ["pointing_budget", "pointing_budget_spatial",
                                                "pointing_budget_spatial_tracker"]
    # a user's spec with --check, where no out/ is: none left
    work = tmp_path / "work"
    work.mkdir()
    p = subprocess.run(["bash", script, "my.yaml", "--check"], cwd=work, capture_output=True, text=True, timeout=60,
                       env=env)
    assert p.returncode == 0 and os.listdir(work) == [], p.stderr


def test_a_signal_to_the_script_alone_stops_its_sweep_too(tmp_path):
    # (pass 72) TERM to the script (not its process group) ended it with 143 at once while its sweep ran on,
    # orphaned, and rewrote --out afterwards
    import signal
    import time
    work = tmp_path / "work"
    work.mkdir()
    (work / "s.yaml").write_text(SPEC.replace("samples: 2", "samples: 40").replace("sim.duration: 0.5",
                                                                                 "sim.duration: 2.0"))
    env = dict(os.environ, GIMBALSIM_BUILD=str(pathlib.Path(os.environ["PYTHONPATH"]).parent))
    proc = subprocess.Popen(["bash", str(SOURCE / "tools/sweeps/run_pointing_budget.sh"), "s.yaml", "--out", "o",
                             "--workers", "1", "--batch", "1"], cwd=work, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env, start_new_session=True)
    journal = work / "o" / "results.partial.csv"
    deadline = time.time() + 300
    while not (journal.exists() and journal.read_text().count("\n") >= 2) and time.time() < deadline:
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)  # the script alone
    _, err = proc.communicate(timeout=120)
    assert proc.returncode in (143, -signal.SIGTERM), err  # (a shell says 143 for either)
    time.sleep(1.0)  # an orphan would go on writing its journal
    rows = journal.read_text().count("\n")
    time.sleep(2.0)
    assert journal.read_text().count("\n") == rows, "the sweep ran on after the script"
    assert "interrupted" in err and rows >= 2, err  # its journal whole, for --resume
