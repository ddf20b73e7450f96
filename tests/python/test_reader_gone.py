"""Issue 41 (pass 28), class 7/10: a console whose reader is gone (`2>&1 |
head -1`) stops no program, Python tool or script (docs/usage.md "Exit
codes"): the lines are dropped, the outputs written, the exit code the
run's. The C++ programs were killed by SIGPIPE (141, no CSV), plot_bench.py
ended in a BrokenPipeError traceback (1, its figure removed), and
run_hil_bench.sh was killed with its outputs never moved into --out."""
import os
import shutil
import subprocess

from conftest import BIN, SOURCE, scene_path


def gone(command, cwd, env=None):
    """command's own exit code with its console piped into a reader that leaves at once."""
    p = subprocess.run(["bash", "-c", f'{command} 2>&1 | true; echo "rc=${{PIPESTATUS[0]}}"'], cwd=cwd,
                       capture_output=True, text=True, timeout=300, env={**os.environ, **(env or {})})
    return int(p.stdout.strip().rsplit("rc=", 1)[-1])


def test_a_program_runs_to_its_end_and_a_refusal_stays_a_refusal(tmp_path):
    simulate = f"'{BIN}/gimbalsim' simulate '{scene_path('paper_clearance')}' --set sim.duration=0.2 --out s.csv"
    assert gone(simulate, tmp_path) == 0
    assert (tmp_path / "s.csv").read_text().count("\n") > 100  # the run whole
    assert gone(f"'{BIN}/firmware_sim' --rate 0", tmp_path) == 2


def test_the_bench_script_moves_its_run_into_place(tmp_path):
    out = tmp_path / "bo"
    code = gone(f"bash '{SOURCE}/tools/hil/run_hil_bench.sh' --duration 0.3 --out '{out}' --port 7743", tmp_path,
                env={"GIMBALSIM_BUILD": str(BIN.parent)})
    assert code == 0
    assert sorted(os.listdir(out)) == ["bench.png", "controller.csv", "controller.txt", "firmware.txt", "truth.csv"]
    assert (out / "firmware.txt").read_text().count("firmware_sim:") >= 2  # the log whole, its console gone
    # and plot_bench, a Python tool, drew its figure with nobody reading
    assert gone(f"/usr/bin/python3 '{SOURCE}/tools/hil/plot_bench.py' '{out}/truth.csv' --out p.png", tmp_path) == 0
    assert (tmp_path / "p.png").stat().st_size > 1000


def test_help_version_and_refusals_keep_their_codes(tmp_path):
    # (pass 29) argparse's --help and --version in the modules and the tools' scripts, and the bash scripts'
    # usage (sed | sed under pipefail), ended 1 or 4 with nobody reading
    env = {"PYTHONPATH": str(BIN.parent / "python")}
    for module in ("sweep", "tune", "allocate"):
        assert gone(f"/usr/bin/python3 -m gimbalsim.{module} --version", tmp_path, env) == 0, module
        assert gone(f"/usr/bin/python3 -m gimbalsim.{module} --bogus", tmp_path, env) == 2, module
    for script in ("tools/sweeps/budget_speed.py", "tools/bench/compare_bench.py", "tools/hil/hil_speed.py"):
        assert gone(f"/usr/bin/python3 '{SOURCE}/{script}' --help", tmp_path) == 0, script
    assert gone(f"bash '{SOURCE}/tools/hil/run_hil_bench.sh' --help", tmp_path) == 0
    assert gone(f"bash '{SOURCE}/tools/hil/run_hil_bench.sh' --bogus", tmp_path) == 2
    assert gone(f"bash '{SOURCE}/tools/sweeps/run_pointing_budget.sh' --help", tmp_path) == 0


def test_the_benchmark_script_runs_from_anywhere_and_leaves_no_temporary(tmp_path):
    # (pass 29) it ran build/bin/gimbalsim_bench relative to where the user stood (127), its table printer ended
    # in a BrokenPipeError (1), and every run left /tmp/gimbalsim_bench.*.json behind
    before = set(os.listdir("/tmp"))
    code = gone(f"REPS=2 BENCH='{BIN}/gimbalsim_bench' bash '{SOURCE}/tools/bench/run_bench.sh' "
                "--benchmark_filter=BM_Rk4 --benchmark_min_time=0.01", tmp_path)
    assert code == 0
    assert not {x for x in set(os.listdir("/tmp")) - before if x.startswith("gimbalsim_bench.")}


def test_the_benchmark_scripts_out_is_never_a_script_it_runs(tmp_path):
    # (pass 101) OUT=tools/lib/console.sh replaced the library the script sources with the JSON (the next run a
    # syntax error), OUT=run_bench.sh the script itself (exit 0): from a copy, so that a failure writes over it
    for part in ("tools", "python"):
        shutil.copytree(SOURCE / part, tmp_path / "repo" / part, symlinks=True)
    script = tmp_path / "repo" / "tools" / "bench" / "run_bench.sh"
    for target in ("tools/lib/console.sh", "tools/bench/run_bench.sh", "tools/pages/save_output.py"):
        before = (tmp_path / "repo" / target).read_bytes()
        p = subprocess.run(["bash", str(script), "--benchmark_filter=BM_ForwardDynamics<FixedIdeal>$",
                            "--benchmark_min_time=0.01"], capture_output=True, text=True, timeout=120, cwd=tmp_path,
                           env={**os.environ, "BENCH": str(BIN / "gimbalsim_bench"), "REPS": "2",
                                "OUT": str(tmp_path / "repo" / target)})
        assert p.returncode == 2 and "the same file as the input" in p.stderr, (target, p.stderr)
        assert (tmp_path / "repo" / target).read_bytes() == before, target


def test_the_benchmark_scripts_out_is_never_a_program_it_runs(tmp_path):
    # (pass 103) OUT=/usr/bin/mktemp was taken: the programs the script runs from PATH are inputs too (here a copy
    # first on PATH, so that a failure writes over the copy)
    # (pass 107) and realpath, which tools/lib/build_dir.sh runs and no list held: every executable file in a
    # folder on PATH is refused
    (tmp_path / "bin").mkdir()
    for program in ("mktemp", "realpath"):
        shutil.copy(shutil.which(program), tmp_path / "bin" / program)
        before = (tmp_path / "bin" / program).read_bytes()
        p = subprocess.run(["bash", str(SOURCE / "tools" / "bench" / "run_bench.sh"),
                            "--benchmark_filter=BM_ForwardDynamics<FixedIdeal>$", "--benchmark_min_time=0.01"],
                           capture_output=True, text=True, timeout=120, cwd=tmp_path,
                           env={**os.environ, "BENCH": str(BIN / "gimbalsim_bench"), "REPS": "2",
                                "PATH": f"{tmp_path / 'bin'}:{os.environ['PATH']}",
                                "OUT": str(tmp_path / "bin" / program)})
        assert p.returncode == 2 and f"an executable file in {tmp_path / 'bin'}, a folder on PATH" in p.stderr, \
            p.stderr
        assert (tmp_path / "bin" / program).read_bytes() == before


def test_the_benchmark_script_refuses_as_programs_do(tmp_path):
    # (pass 30) --help was a traceback, REPS=1 printed an empty table, BENCH=nope exited 127, OUT was written by
    # the bench itself (through a link, emptied by a filter that matched nothing), --benchmark_out landed in the
    # repository
    script = f"'{SOURCE}/tools/bench/run_bench.sh'"
    bench = f"BENCH='{BIN}/gimbalsim_bench'"
    (tmp_path / "real.json").write_text("{}\n")
    (tmp_path / "link.json").symlink_to("real.json")
    for command, words in ((f"bash {script} --help", None),
                           (f"REPS=1 {bench} bash {script}", "REPS=1: must be a whole number in [2, 1000]"),
                           # (pass 36) as the programs read a whole number: octal to C, so refused
                           (f"REPS=05 {bench} bash {script}", "REPS=05: must be a whole number in [2, 1000]"),
                           (f"BENCH=nope bash {script}", "no such program"),
                           (f"OUT=link.json REPS=2 {bench} bash {script} --benchmark_filter=BM_Rk4", "symbolic link"),
                           (f"OUT=real.json REPS=2 {bench} bash {script} --benchmark_filter=NOTHING", "matched none"),
                           (f"{bench} bash {script} --benchmark_out=x.json", "give OUT=FILE"),
                           # (pass 95) the space form was "given twice" (the script's own) and named no OUT
                           (f"{bench} bash {script} --benchmark_out x.json", "--benchmark_out: the script writes"),
                           # (pass 97) a listing dropped every other flag unchecked; =false ran the whole suite once
                           (f"{bench} bash {script} --benchmark_list_tests=true --bogus", "'--bogus': not a flag"),
                           (f"OUT=x.json {bench} bash {script} --benchmark_list_tests", "a listing runs nothing"),
                           (f"REPS=2 {bench} bash {script} --benchmark_list_tests=false --benchmark_filter=NOTHING",
                            "--benchmark_filter matched none")):
        p = subprocess.run(["bash", "-c", command], cwd=tmp_path, capture_output=True, text=True, timeout=300)
        assert p.returncode == (0 if words is None else 2) and (words is None or words in p.stderr), (command, p.stderr)
    assert (tmp_path / "real.json").read_text() == "{}\n" and not (tmp_path / "x.json").exists()
    # (pass 31) OUT over the benchmark program itself was written (the program replaced by its JSON); a listing ran
    # BENCH from the repository (127); --benchmark_repetitions passed by REPS's range
    mine = tmp_path / "mybench"
    mine.write_bytes((BIN / "gimbalsim_bench").read_bytes())
    mine.chmod(0o755)
    for command, words in ((f"BENCH=./mybench OUT=./mybench REPS=2 bash {script} --benchmark_filter=BM_Rk4",
                            "the same file as the input"),
                           (f"BENCH=./nope bash {script} --benchmark_list_tests=true", "no such program"),
                           (f"REPS=2 BENCH=./mybench bash {script} --benchmark_repetitions=1", "give REPS=N")):
        p = subprocess.run(["bash", "-c", command], cwd=tmp_path, capture_output=True, text=True, timeout=300)
        assert p.returncode == 2 and words in p.stderr, (command, p.stderr)
    assert mine.read_bytes() == (BIN / "gimbalsim_bench").read_bytes()
    p = subprocess.run(["bash", "-c", f"BENCH=./mybench bash {script} --benchmark_list_tests=true"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0 and "BM_Rk4" in p.stdout, p.stderr


def test_a_console_that_cannot_be_written_stops_nothing(tmp_path):
    # (pass 30) a closed stdout (>&-) was an AttributeError (120), a full device an OSError traceback (1)
    env = {"PYTHONPATH": str(BIN.parent / "python")}
    for redirect in (">&-", ">/dev/full"):
        p = subprocess.run(["bash", "-c", f"/usr/bin/python3 -m gimbalsim.sweep --help {redirect}"], cwd=tmp_path,
                           capture_output=True, text=True, timeout=120, env={**os.environ, **env})
        assert p.returncode == 0 and "Traceback" not in p.stderr, (redirect, p.stderr)
    p = subprocess.run(["bash", "-c", f"/usr/bin/python3 '{SOURCE}/tools/hil/plot_bench.py' --help >/dev/full"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and "Traceback" not in p.stderr, p.stderr


def shell(command, cwd, env=None):
    return subprocess.run(["bash", "-c", command], cwd=cwd, capture_output=True, text=True, timeout=300,
                          env={**os.environ, **(env or {})})


def test_a_closed_console_is_no_output_and_changes_no_exit_code(tmp_path):
    # (pass 31) a program started with `>&-` or `2>&-` gave descriptor 1 or 2 to its first output's temporary and
    # wrote its console into it (a truth CSV, config.txt); a Python module's closed stderr ended 1 (AttributeError)
    # with its results lost; a script's closed stdout failed its own awk (exit 2) or tee (exit 1, log not saved)
    study = (f"'{BIN}/gimbalsim_pointing_study' --ideal-scene '{scene_path('paper_ideal')}' --clearance-scene "
             f"'{scene_path('paper_clearance')}' --clearances 1e-4 --duration 0.5 --set profile.slew_time=0.1 "
             "--set profile.slew_start=0 --set profile.hold_time=0.05")
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    assert shell(f"{study} --out a >/dev/null", tmp_path).returncode == 0
    assert shell(f"{study} --out b >&- 2>&-", tmp_path).returncode == 0
    for name in ("config.txt", "summary.csv"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes(), name
    p = shell(f"'{BIN}/firmware_sim' '{scene_path('paper_clearance')}' --duration 0.02 --rt-priority 0 "
              "--lcm-url 'udpm://239.255.76.67:7745?ttl=0' --truth-csv t.csv 2>&- >&-", tmp_path)
    assert p.returncode == 0 and (tmp_path / "t.csv").read_text().startswith("utime_us,seq,"), p.stderr
    env = {"PYTHONPATH": str(BIN.parent / "python")}
    assert shell("/usr/bin/python3 -m gimbalsim.sweep --bogus 2>&-", tmp_path, env).returncode == 2
    spec = tmp_path / "s.yaml"
    spec.write_text(f"scene: {scene_path('paper_ideal')}\nset: {{sim.duration: 0.05}}\nsamples: 2\nseed: 1\n"
                    "parameters:\n  initial.theta1: {uniform: [0.0, 0.1]}\n")
    assert shell("/usr/bin/python3 -m gimbalsim.sweep s.yaml --out o --workers 1 --no-progress 2>&- >&-", tmp_path,
                 env).returncode == 0
    assert (tmp_path / "o" / "results.csv").is_file() and (tmp_path / "o" / "summary.json").is_file()
    build, fake = tmp_path / "build", tmp_path / "fakebin"
    (build / "bin").mkdir(parents=True)
    fake.mkdir()
    (build / "CMakeCache.txt").write_text("")
    (build / "bin" / "gimbalsim_controller_floor").symlink_to(BIN / "gimbalsim_controller_floor")
    (fake / "cmake").write_text("#!/bin/sh\nexit 0\n")  # the program is built: no cmake run
    (fake / "cmake").chmod(0o755)
    floor = (f"bash '{SOURCE}/tools/pointing_study/run_controller_floor.sh' --clearances 1e-4 --duration 0.4 "
             "--set profile.slew_time=0.1 --set profile.slew_start=0 --set profile.hold_time=0.05")
    env = {"GIMBALSIM_BUILD": str(build), "PATH": f"{fake}:{os.environ['PATH']}"}
    log = tmp_path / "out" / "controller_floor" / "floor.log"
    for redirect in (">/dev/full", ">&-"):
        if log.exists():
            log.unlink()
        assert shell(f"{floor} {redirect} 2>/dev/null", tmp_path, env).returncode == 0, redirect
        assert log.read_text().startswith("# 0.4 s per run"), redirect  # the log saved, whole
