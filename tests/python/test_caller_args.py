"""tools/lib/caller_args.sh: the scripts that cd to the repository read a
relative path where the user stands (usage.md "Scripts in tools/")."""
import subprocess

import pytest

from conftest import SOURCE

LIB = SOURCE / "tools" / "lib" / "caller_args.sh"


def abs_arg(caller, arg):
    script = f'CALLER="$1"; source "{LIB}"; cd /; abs_arg "$2"'
    p = subprocess.run(["bash", "-c", script, "bash", str(caller), arg], capture_output=True, text=True, timeout=30)
    assert p.returncode == 0, p.stderr
    return p.stdout


# a name missing where the user stands but looking like a path is theirs too (pass 25: the script read the
# repository's tools/scenes/paper_ideal.yaml for a user standing in an empty folder)
@pytest.mark.parametrize("arg,made", [("in.csv", "{c}/in.csv"), ("--csv=in.csv", "--csv={c}/in.csv"),
                                      ("sub/in.csv", "{c}/sub/in.csv"), ("missing.csv", "{c}/missing.csv"),
                                      ("--csv=missing.csv", "--csv={c}/missing.csv"),
                                      ("tools/scenes/paper_ideal.yaml", "{c}/tools/scenes/paper_ideal.yaml"),
                                      ("--quick", "--quick"), ("paper_ideal", "paper_ideal"),
                                      ("sim.duration=0.05", "sim.duration=0.05"),
                                      ("--long-set=sim.duration=0.05", "--long-set=sim.duration=0.05"),
                                      ("/etc/hostname", "/etc/hostname"), ("--x=/etc/hostname", "--x=/etc/hostname"),
                                      ("0.5", "0.5"), ("1e-3", "1e-3")])
def test_a_relative_path_that_names_a_file_where_the_user_stands_is_made_absolute(tmp_path, arg, made):
    (tmp_path / "sub").mkdir()
    (tmp_path / "in.csv").write_text("x\n")
    (tmp_path / "sub" / "in.csv").write_text("x\n")
    assert abs_arg(tmp_path, arg) == made.format(c=tmp_path)


def test_both_scripts_that_cd_to_the_repository_use_it():
    for script in ("tools/stress/run_stress.sh", "tools/workprec/run_workprec.sh"):
        text = (SOURCE / script).read_text()
        assert 'source "$ROOT/tools/lib/caller_args.sh"' in text and "abs_arg() {" not in text, script


# (pass 27) a number is never a path, even where a file of that name exists: --threads 1 beside a file "1"
@pytest.mark.parametrize("arg,made", [("1", "1"), ("--threads=1", "--threads=1"), ("0.5", "0.5"), ("1e-3", "1e-3"),
                                      ("./1", "{c}/./1"), ("paper_ideal", "{c}/paper_ideal")])
def test_a_number_stays_a_number_beside_a_file_of_its_name(tmp_path, arg, made):
    for name in ("1", "0.5", "1e-3", "paper_ideal"):
        (tmp_path / name).write_text("x\n")
    assert abs_arg(tmp_path, arg) == made.format(c=tmp_path)


def test_run_workprec_checks_its_figure_before_the_sweep(tmp_path):
    # (pass 81) a link under out/workprec/workprec.png was refused by the plot after the sweep had replaced
    # workprec.csv and its log (exit 2, "nothing run"): the figure's name is checked with the log's, before
    import os
    import shutil
    from conftest import BIN
    root = tmp_path / "repo"
    shutil.copytree(SOURCE / "tools", root / "tools")
    shutil.copytree(SOURCE / "python" / "gimbalsim", root / "python" / "gimbalsim")  # the one writer
    (root / "tools" / "bootstrap.sh").write_text("exit 0\n")
    (root / "build").symlink_to(BIN.parent, target_is_directory=True)
    fake = tmp_path / "fakebin"
    fake.mkdir()
    (fake / "cmake").write_text("#!/bin/sh\nexit 0\n")
    (fake / "cmake").chmod(0o755)
    out = root / "out" / "workprec"
    out.mkdir(parents=True)
    (out / "workprec.csv").write_text("the previous sweep\n")
    (out / "workprec.png").symlink_to(tmp_path / "victim.png")
    p = subprocess.run(["bash", str(root / "tools/workprec/run_workprec.sh"), "--quick", "--scenes", "paper_ideal",
                        "--no-mujoco"], capture_output=True, text=True, timeout=300, cwd=tmp_path,
                       env=dict(os.environ, PATH=f"{fake}:{os.environ['PATH']}"))
    assert p.returncode == 2 and "workprec.png" in p.stderr and "symbolic link" in p.stderr, p.stderr
    assert (out / "workprec.csv").read_text() == "the previous sweep\n" and not (tmp_path / "victim.png").exists()


def test_run_workprec_saves_its_log_and_clears_its_figure_when_the_sweep_exits_3(tmp_path):
    # (pass 86) a scene without a reference (exit 3) ended the script at the pipe: the new CSV stood beside the
    # previous run's log and figure
    import os
    from conftest import BIN
    out = SOURCE / "out" / "workprec"
    env = dict(os.environ, GIMBALSIM_BUILD=str(BIN.parent))
    args = ["--scenes", "paper_ideal", "--duration", "0.02", "--repeats", "1", "--no-mujoco", "--policy", "plain"]
    p = subprocess.run(["bash", str(SOURCE / "tools/workprec/run_workprec.sh"), *args, "--steps", "0.01,0.005"],
                       capture_output=True, text=True, timeout=300, cwd=tmp_path, env=env)
    assert p.returncode == 0 and (out / "workprec.png").is_file(), p.stderr
    p = subprocess.run(["bash", str(SOURCE / "tools/workprec/run_workprec.sh"), *args, "--steps", "0.01",
                        "--set", "initial.dtheta1=1", "--set", "sim.velocity_limit=0.5"],
                       capture_output=True, text=True, timeout=300, cwd=tmp_path, env=env)
    assert p.returncode == 3, p.stderr
    assert "reference run failed" in (out / "workprec.log").read_text()  # this run's log, not the previous one
    assert not (out / "workprec.png").exists() and "removed the previous run's out/workprec/workprec.png" in p.stderr
