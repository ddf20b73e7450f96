"""tools/hil/run_hil_bench.sh writes as the programs do: a link under an
output's name is refused before anything runs, a refused or failed run
leaves --out as it was (it had deleted the previous results first, then
written the refusal through the link), and a run that ends well replaces
the previous run's files whole."""
import os
import re
import shutil
import subprocess
import time

import pytest

from conftest import BIN, CONTROLLER_CONFIG, SOURCE

SCRIPT = SOURCE / "tools" / "hil" / "run_hil_bench.sh"


def bench(out, *args, build=None, cwd=None):
    env = {**os.environ, "GIMBALSIM_BUILD": build or str(BIN.parent)}  # the tests' build, never a build of its own
    port = [] if "--port" in args else ["--port", "7741"]  # a port the test gives is the only one (a flag once)
    return subprocess.run(["bash", str(SCRIPT), "--out", str(out), *port, *args], capture_output=True,
                          text=True, timeout=300, env=env, cwd=cwd)


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


def test_an_output_in_out_that_is_a_program_on_path_is_refused_before_anything_runs(tmp_path, monkeypatch):
    # (pass 111) truth.csv in --out, an executable that a folder on PATH holds or a link there names, was replaced
    # by the run's CSV (exit 0): the script moves its outputs into --out itself
    out = tmp_path / "bo"
    out.mkdir()
    (tmp_path / "path").mkdir()
    shutil.copy(shutil.which("true"), out / "truth.csv")
    (tmp_path / "path" / "truthtool").symlink_to(out / "truth.csv")
    (tmp_path / "hidden").mkdir()  # (pass 113) a dot-named link: the glob skipped it
    (tmp_path / "hidden" / ".hid").symlink_to(out / "truth.csv")
    before = (out / "truth.csv").read_bytes()
    for on_path, says in ((tmp_path / "path", f"run as {tmp_path / 'path'}/truthtool on PATH"),
                          (tmp_path / "hidden", f"run as {tmp_path / 'hidden'}/.hid on PATH"),
                          (out, f"in {out}, a folder on PATH")):
        monkeypatch.setenv("PATH", f"{on_path}:{os.environ['PATH']}")
        p = bench(out, "--duration", "0.2", "--no-plot")
        assert p.returncode == 2 and f"truth.csv: an output that is an executable file {says}" in p.stderr, p.stderr
        assert (out / "truth.csv").read_bytes() == before and sorted(os.listdir(out)) == ["truth.csv"]
        monkeypatch.undo()


def test_a_refused_run_changes_nothing_and_a_good_one_replaces_the_old_files(tmp_path):
    out = tmp_path / "bo"
    out.mkdir()
    (out / "truth.csv").write_text("precious\n")
    (out / "bench.png").write_text("an old plot\n")
    before = files(out)
    p = bench(out, "--duration", "0.2", "--no-plot", "--", "--truth-every", "0")  # refused by firmware_sim in the run
    assert p.returncode == 2 and "nothing in" in p.stderr and "--truth-every" in p.stderr, p.stderr
    assert files(out) == before  # no .run.* folder left, nothing deleted or written
    p = bench(out, "--duration", "0.2", "--no-plot")
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(out)) == ["controller.csv", "controller.txt", "firmware.txt", "truth.csv"]
    rows = (out / "truth.csv").read_text().splitlines()
    assert rows[0].startswith("utime_us,seq,sim_time_s") and len(rows) == 1 + 201  # t = 0 .. 0.2 s every 1 ms


def test_the_folder_of_a_run_whose_script_died_is_removed_by_the_next_run(tmp_path):
    # (pass 76) a script killed where no trap runs (SIGKILL, a machine that stopped) left out/.run.XXXXXX, hundreds
    # of MB, for good: a run's folder is named by its script's pid, and the next run removes the dead ones only
    out = tmp_path / "bo"
    dead_pid = 4194303  # above the kernel's pid_max limit (2^22): no process has it
    (out / f".run.{dead_pid}.a1b2c3" / "sub").mkdir(parents=True)
    (out / f".run.{dead_pid}.a1b2c3" / "sub" / "truth.csv").write_text("old run\n")
    live = out / f".run.{os.getpid()}.d4e5f6"  # this test's own pid: alive
    live.mkdir()
    (out / ".run.notapid").mkdir()
    (tmp_path / "elsewhere").mkdir()
    (out / f".run.{dead_pid}.link").symlink_to(tmp_path / "elsewhere")
    p = bench(out, "--duration", "0.2", "--no-plot")
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(out)) == sorted([f".run.{dead_pid}.link", f".run.{os.getpid()}.d4e5f6", ".run.notapid",
                                              "controller.csv", "controller.txt", "firmware.txt", "truth.csv"])
    assert (tmp_path / "elsewhere").is_dir()


def test_a_run_whose_plant_stopped_keeps_its_outputs_and_ends_with_3(tmp_path):
    # (pass 27) the plant's stop (exit 3) writes its truth up to the stop, which the script threw away: a
    # script keeps a stopped run's outputs and ends with 3 (usage.md "Scripts in tools/"); the plot shows
    # the run up to the stop, not the frozen rows after it
    out = tmp_path / "bo"
    p = bench(out, "--duration", "0.8", "--", "--set", "sim.velocity_limit=0.001")
    assert p.returncode == 3 and "the plant stopped" in p.stderr, p.stderr
    assert sorted(os.listdir(out)) == ["bench.png", "controller.csv", "controller.txt", "firmware.txt", "truth.csv"]
    assert "the plant stopped after t = 0.5" in p.stdout, p.stdout
    # (pass 35) one stop time: firmware_sim's PLANT FAULT line said the failed step's (0.16 s beside 0.159 s)
    stop = re.search(r"the plant stopped after t = ([0-9.]+) s", p.stdout).group(1)
    assert f"PLANT FAULT, the plant stopped after t = {stop} s, its last good state" in \
        (out / "firmware.txt").read_text(), (stop, (out / "firmware.txt").read_text())
    rows = (out / "truth.csv").read_text().splitlines()
    assert len(rows) == 1 + 801 and rows[-1].endswith(",8,0"), rows[-1]  # every tick; the last frozen, flagged
    # (pass 28) the frozen rows are left out of the plot, not out of the count of plant-fault ticks
    flagged = sum(1 for r in rows[1:] if int(r.split(",")[-2]) & 8)
    assert f"plant fault {flagged} ({flagged} of them the frozen rows after the stop)" in p.stdout, p.stdout
    # (pass 29) firmware_sim's summary measured the frozen state against the moving profile (max 1.55e-2 rad
    # where the plant never exceeded 3.9e-6): its figures are over the plant's own ticks
    column = rows[0].split(",").index("pointing_error_rad")
    moving = max(float(r.split(",")[column]) for r in rows[1:] if not int(r.split(",")[-2]) & 8)
    summary = (out / "firmware.txt").read_text()
    assert f"against the profile: max {moving:.3e}," in summary, summary
    # (pass 31) one stop time: every reader names the last good state, the frozen rows' time
    frozen_t = rows[-1].split(",")[rows[0].split(",").index("sim_time_s")]
    assert f"the plant stopped after t = {float(frozen_t):g} s, its last good state (its step to t = " in summary
    # (pass 30) and so does pointing_controller's: its window is judged at the stop, not at its last status
    controller = (out / "controller.txt").read_text()
    assert f"the plant stopped after t = {float(frozen_t):g} s, its last good status (FAULT_PLANT_FAULT" in controller
    assert "run ended at 0.799 s" not in controller and f"run ended at {float(frozen_t):g} s" in controller, controller
    # (pass 29) a frozen row's fault flags that are no set of bits: refused as on any row, before the stop is read
    edited = rows[:-1] + [rows[-1].rsplit(",", 2)[0] + ",1e300,0"]
    (tmp_path / "edited.csv").write_text("\n".join(edited) + "\n")
    q = subprocess.run(["/usr/bin/python3", str(SOURCE / "tools/hil/plot_bench.py"), str(tmp_path / "edited.csv"),
                        "--out", str(tmp_path / "e.png")], capture_output=True, text=True, timeout=120)
    assert q.returncode == 2 and f"edited.csv:{len(rows)}: column faults: 1e+300 is not a set of fault bits" in q.stderr
    assert "Warning" not in q.stderr, q.stderr


def test_out_must_be_a_folder_and_a_refused_run_leaves_none_it_made(tmp_path):
    (tmp_path / "real").mkdir()
    (tmp_path / "link").symlink_to("real")
    p = bench(tmp_path / "link", "--duration", "0.2", "--no-plot")
    assert p.returncode == 2 and "a link or not a folder" in p.stderr and not os.listdir(tmp_path / "real"), p.stderr
    (tmp_path / "afile").write_text("x\n")
    p = bench(tmp_path / "afile", "--duration", "0.2", "--no-plot")
    assert p.returncode == 2 and "a link or not a folder" in p.stderr, p.stderr
    p = bench(tmp_path / "new", "--duration", "-1", "--no-plot")
    assert p.returncode == 2 and not (tmp_path / "new").exists(), p.stderr


def test_a_relative_build_is_read_where_the_user_stands_and_never_built(tmp_path):
    (tmp_path / "b").symlink_to(BIN.parent)
    (tmp_path / "o").mkdir()
    p = bench("o", "--duration", "0.2", "--no-plot", build="b", cwd=tmp_path)
    assert p.returncode == 0 and (tmp_path / "o" / "truth.csv").is_file(), p.stderr
    p = bench("o", "--duration", "0.2", "--no-plot", build="nowhere", cwd=tmp_path)
    assert p.returncode == 2 and "GIMBALSIM_BUILD=nowhere: no " in p.stderr, p.stderr


def test_a_bad_number_is_refused_naming_the_flag_not_what_the_script_made_of_it(tmp_path):
    # --rate 0 was refused as pointing_controller's "--set #1 'control.period=inf'", the period 1/--rate
    for args, says in ((["--rate", "0"], "run_hil_bench.sh: --rate: must be in [0.001, 1e+06], got 0"),
                       (["--rate", "abc"], "run_hil_bench.sh: --rate: 'abc' is not a plain decimal number"),
                       (["--duration", "inf"], "run_hil_bench.sh: --duration: 'inf' is not a plain decimal number"),
                       (["--port", "99999"], "run_hil_bench.sh: --port: must be a whole number in [1, 65535]"),
                       # (pass 31) LCM read 07815 as octal, the receivers as 7815: the processes never met (exit 6)
                       (["--port", "07815"], "without a leading zero, got '07815'"),
                       # (pass 36) passed by the script as 0 s, refused by pointing_controller under another name
                       (["--duration", "1e-400"], "run_hil_bench.sh: --duration: '1e-400' is too small for a double"),
                       (["--rate", "+0"], "run_hil_bench.sh: --rate: must be in [0.001, 1e+06], got +0"),
                       # (pass 74) 0 ran until a signal, and the signal removed the run with its folder
                       (["--duration", "0"], "run_hil_bench.sh: --duration: must be above 0, got 0 (0 runs until"),
                       (["--duration", "-0.0"], "run_hil_bench.sh: --duration: must be above 0, got -0.0"),
                       # (pass 66) awk read 10, firmware_sim refused it only after the controller had started
                       (["--rate", "010"], "run_hil_bench.sh: --rate: '010' is not a number written without a "
                                           "leading zero")):
        p = bench(tmp_path / "new", "--no-plot", *args)
        assert p.returncode == 2 and says in p.stderr and "control.period" not in p.stderr, p.stderr
        assert "firmware_sim" not in p.stderr and not (tmp_path / "new").exists(), p.stderr


def test_a_sign_is_part_of_a_number_as_the_programs_read_it(tmp_path):
    # (pass 36) '+1000' and '+0.2' were 'not a plain decimal number' here, taken by firmware_sim and the tools
    p = bench(tmp_path / "new", "--no-plot", "--rate", "+1000", "--duration", "+0.2")
    assert p.returncode == 0 and (tmp_path / "new" / "truth.csv").is_file(), p.stderr


def test_a_configuration_the_controller_refuses_is_its_refusal_not_firmware_sims(tmp_path):
    # It ran, firmware_sim waited for a controller that had refused, and the script said "firmware_sim exited with 6".
    config = tmp_path / "bad.yaml"
    config.write_text(CONTROLLER_CONFIG.read_text().replace("  kp: 21120 ", "  kp: -5 ", 1))
    p = bench(tmp_path / "new", "--no-plot", "--duration", "0.1", "--config", str(config), "--", "--start-timeout", "1")
    assert p.returncode == 2, p.stderr
    assert "key 'azimuth.kp': must be in [0, 1e+09], got -5" in p.stderr, p.stderr
    says = f"run_hil_bench.sh: pointing_controller refused --config {config} with control.period = 1/--rate = 1/1000 s,"
    assert says + " --duration 0.1 (exit 2, its message above); nothing run" in p.stderr, p.stderr
    assert "firmware_sim" not in p.stderr and not (tmp_path / "new").exists(), p.stderr
    # the inertial feed-forward's filter at 10 Hz (each filter is checked only where the law reads it: the rate
    # filter with rate_source difference, pass 21's F8; the base's with accel_feedforward inertial, pass 55)
    inertial = tmp_path / "inertial.yaml"
    inertial.write_text(CONTROLLER_CONFIG.read_text().replace("accel_feedforward: model", "accel_feedforward: inertial"))
    p = bench(tmp_path / "new", "--no-plot", "--duration", "0.1", "--rate", "10", "--config", str(inertial))
    assert p.returncode == 2 and "key 'pointing.base_accel_filter_hz': must be below the Nyquist frequency" in \
        p.stderr, p.stderr
    assert "pointing_controller refused --config" in p.stderr and "1/--rate = 1/10 s" in p.stderr, p.stderr


def test_an_output_that_is_one_of_the_inputs_is_refused_before_anything_runs(tmp_path):
    # A scene sitting in --out as truth.csv was read, then replaced by the truth CSV (exit 0).
    scene = (SOURCE / "tools" / "scenes" / "paper_clearance.yaml").read_bytes()
    out = tmp_path / "b1"
    out.mkdir()
    (out / "truth.csv").write_bytes(scene)
    p = bench("b1", "--duration", "0.2", "--no-plot", "--scene", "b1/truth.csv", cwd=tmp_path)
    assert p.returncode == 2, p.stderr
    assert "b1/truth.csv: an output that is the input --scene b1/truth.csv" in p.stderr, p.stderr
    assert files(out) == {"truth.csv": scene}  # nothing run, nothing written
    # the config under a hard link's name, and a --faults file passed through to firmware_sim (absolute, or
    # relative: read where the user stands, as every path the script is given)
    (tmp_path / "ctl.yaml").write_bytes(CONTROLLER_CONFIG.read_bytes())
    os.link(tmp_path / "ctl.yaml", out / "controller.txt")
    p = bench(out, "--duration", "0.2", "--no-plot", "--config", str(tmp_path / "ctl.yaml"))
    assert p.returncode == 2 and "controller.txt: an output that is the input --config" in p.stderr, p.stderr
    (out / "controller.txt").unlink()
    (out / "firmware.txt").write_text("scheduled_faults: []\n")
    for faults in (["--faults", str(out / "firmware.txt")], ["--faults=b1/firmware.txt"]):
        p = bench(out, "--duration", "0.2", "--no-plot", "--", *faults, cwd=tmp_path)
        assert p.returncode == 2 and "firmware.txt: an output that is the input --faults (after --)" in p.stderr, p.stderr
    assert sorted(os.listdir(out)) == ["firmware.txt", "truth.csv"]
    assert (out / "firmware.txt").read_text() == "scheduled_faults: []\n"
    # an input under an output's name in a fresh --out is no file yet: refused, no folder made
    p = bench(tmp_path / "fresh", "--duration", "0.2", "--no-plot", "--scene", str(tmp_path / "fresh" / "truth.csv"))
    assert p.returncode == 2 and "no such file" in p.stderr and not (tmp_path / "fresh").exists(), p.stderr


# ---- issue 41 classes 6 and 7: an output named after -- never clashes with the script's; a value that is a flag

def run(*args, cwd):
    env = {**os.environ, "GIMBALSIM_BUILD": str(BIN.parent)}
    return subprocess.run(["bash", str(SCRIPT), "--port", "7741", *map(str, args)], capture_output=True, text=True,
                          timeout=60, env=env, cwd=cwd)


def refused_fast(says, *args, cwd):
    t0 = time.monotonic()
    p = run(*args, cwd=cwd)
    took = time.monotonic() - t0
    assert p.returncode == 2 and says in p.stderr, (args, p.returncode, p.stderr)
    assert "nothing run" in p.stderr and "firmware_sim:" not in p.stderr and took < 5, (args, took, p.stderr)
    return p


def test_a_tick_log_after_dashdash_under_one_of_the_scripts_outputs_is_refused_naming_both(tmp_path):
    # --tick-log ob3/truth.csv was written by firmware_sim, then replaced by the truth CSV (exit 0, the log lost)
    (tmp_path / "ob3").mkdir()
    (tmp_path / "ob3" / "truth.csv").write_text("precious\n")
    (tmp_path / "lnk").symlink_to("ob3")
    run_args = ("--duration", "0.2", "--out", "ob3", "--no-plot", "--")
    png = tmp_path / "ob3" / "bench.png"
    truth = "the same file as the output truth.csv in --out (ob3/truth.csv)"
    for tick, says in ((["--tick-log", "ob3/truth.csv"], truth),
                       (["--tick-log=./ob3/controller.txt"],
                        "the same file as the output controller.txt in --out (ob3/controller.txt)"),
                       (["--tick-log", "ob3/../ob3/firmware.txt"],
                        "the same file as the output firmware.txt in --out (ob3/firmware.txt)"),
                       (["--tick-log", "lnk/truth.csv"], truth),  # a link in the path
                       (["--tick-log", png], "the same file as the output bench.png in --out"),
                       (["--tick-log", "ob3/bench.lcmlog"], "the same file as the output bench.lcmlog in --out"),
                       (["--tick-log", "ob3/bench_ticks.csv"], "the name of an output in --out (ob3/bench_*.csv"),
                       (["--tick-log", "ob3/"], "the same file as the output folder --out (ob3)")):
        given = str(tick[-1]).split("=", 1)[-1]
        refused_fast(f"run_hil_bench.sh: --tick-log {given} (after --): {says}", *run_args, *tick, cwd=tmp_path)
    assert files(tmp_path / "ob3") == {"truth.csv": b"precious\n"}
    # a tick log beside the outputs under a name of its own is the user's, kept
    p = run(*run_args, "--tick-log", "ob3/ticks.csv", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(tmp_path / "ob3")) == ["controller.csv", "controller.txt", "firmware.txt", "ticks.csv",
                                                    "truth.csv"]


def test_a_tick_log_after_dashdash_that_is_an_input_or_given_twice_is_refused_before_anything_runs(tmp_path):
    # firmware_sim refused these itself, but only in the run, after the controller had started
    (tmp_path / "ob").mkdir()
    (tmp_path / "sc.yaml").write_bytes((SOURCE / "tools" / "scenes" / "paper_clearance.yaml").read_bytes())
    (tmp_path / "f.yaml").write_bytes((SOURCE / "tools" / "faults" / "demo.yaml").read_bytes())
    run_args = ("--duration", "0.2", "--scene", "sc.yaml", "--out", "ob", "--no-plot", "--")
    refused_fast("run_hil_bench.sh: --tick-log ./sc.yaml (after --): the same file as the input --scene sc.yaml",
                 *run_args, "--tick-log", "./sc.yaml", cwd=tmp_path)
    refused_fast("run_hil_bench.sh: --tick-log f.yaml (after --): the same file as the input --faults (after --) "
                 f"{tmp_path / 'f.yaml'}", *run_args, "--tick-log", "f.yaml", "--faults", "f.yaml", cwd=tmp_path)
    refused_fast(f"run_hil_bench.sh: --tick-log {CONTROLLER_CONFIG} (after --): the same file as the input --config",
                 *run_args, "--tick-log", CONTROLLER_CONFIG, cwd=tmp_path)
    refused_fast("run_hil_bench.sh: --tick-log after --: given twice (t.csv, ./t.csv)",
                 *run_args, "--tick-log", "t.csv", "--tick-log", "./t.csv", cwd=tmp_path)
    assert sorted(os.listdir(tmp_path)) == ["f.yaml", "ob", "sc.yaml"] and not os.listdir(tmp_path / "ob")


def test_a_tick_log_over_a_program_or_script_the_bench_runs_is_refused(tmp_path):
    # (pass 97) --tick-log $GIMBALSIM_BUILD/bin/pointing_controller replaced the controller with a 1.4 kB CSV
    # (exit 0): the programs and scripts the bench runs are inputs. A build of links to them, so that a failure
    # here meets firmware_sim's refusal to write through a link, never the build itself.
    (tmp_path / "build" / "bin").mkdir(parents=True)
    for t in ("firmware_sim", "pointing_controller", "gimbalsim_log2csv", "gimbalsim_record"):
        (tmp_path / "build" / "bin" / t).symlink_to(BIN / t)
    env = {**os.environ, "GIMBALSIM_BUILD": str(tmp_path / "build")}
    for target, named in ((tmp_path / "build" / "bin" / "pointing_controller", "the program"),
                          (tmp_path / "build" / "bin" / "gimbalsim_record", "the program")):
        p = subprocess.run(["bash", str(SCRIPT), "--port", "7741", "--duration", "0.2", "--out", "ob", "--no-plot",
                            "--", "--tick-log", str(target)], capture_output=True, text=True, timeout=60, env=env,
                           cwd=tmp_path)
        assert p.returncode == 2 and f"the same file as the input {named}" in p.stderr, (target, p.stderr)
        assert "nothing run" in p.stderr and "firmware_sim:" not in p.stderr, p.stderr
    assert not (tmp_path / "ob").exists() or not os.listdir(tmp_path / "ob")
    # (pass 99) and the scripts: itself, the plot, the libraries it sources (console.sh became a CSV, and every run
    # after died with exit 127); from a copy of the tools, so that a failure writes over the copy
    shutil.copytree(SOURCE / "tools", tmp_path / "repo" / "tools", symlinks=True)
    shutil.copytree(SOURCE / "controllers" / "config", tmp_path / "repo" / "controllers" / "config")
    script = tmp_path / "repo" / "tools" / "hil" / "run_hil_bench.sh"
    # (pass 101) and the interpreter it runs plot_bench.py with (its link only: a failure meets the link rule)
    p = subprocess.run(["bash", str(script), "--port", "7741", "--duration", "0.2", "--out", "ob", "--no-plot", "--",
                        "--tick-log", "/usr/bin/python3"], capture_output=True, text=True, timeout=60, env=env,
                       cwd=tmp_path)
    assert p.returncode == 2 and "the same file as the input the interpreter /usr/bin/python3" in p.stderr, p.stderr
    # (pass 103) and the other programs it runs from PATH (its sh was dash: a --tick-log over it was taken); a copy
    # first on PATH, so that a failure writes over the copy
    # (pass 107) rmdir, which no list of them held: every executable file in a folder on PATH is refused
    (tmp_path / "path").mkdir()
    for program in ("sh", "rmdir"):
        shutil.copy(shutil.which(program), tmp_path / "path" / program)
        p = subprocess.run(["bash", str(script), "--port", "7741", "--duration", "0.2", "--out", "ob", "--no-plot",
                            "--", "--tick-log", str(tmp_path / "path" / program)], capture_output=True, text=True,
                           timeout=60, env={**env, "PATH": f"{tmp_path / 'path'}:{os.environ['PATH']}"}, cwd=tmp_path)
        assert p.returncode == 2 and f"an executable file in {tmp_path / 'path'}, a folder on PATH" in p.stderr, \
            p.stderr
        assert (tmp_path / "path" / program).read_bytes() == open(shutil.which(program), "rb").read()
    for target in ("tools/hil/run_hil_bench.sh", "tools/hil/plot_bench.py", "tools/lib/console.sh",
                   "tools/lib/children.sh", "tools/lib/build_dir.sh"):
        before = (tmp_path / "repo" / target).read_bytes()
        p = subprocess.run(["bash", str(script), "--port", "7741", "--duration", "0.2", "--out", "ob", "--no-plot",
                            "--", "--tick-log", str(tmp_path / "repo" / target)], capture_output=True, text=True,
                           timeout=60, env=env, cwd=tmp_path)
        assert p.returncode == 2 and "the same file as the input the script" in p.stderr, (target, p.stderr)
        assert (tmp_path / "repo" / target).read_bytes() == before, target


def test_a_value_that_is_a_flag_is_a_missing_value_and_a_name_with_one_dash_is_a_name(tmp_path):
    # --out --no-plot ended in dirname's "unrecognized option '--no-plot'" (exit 1)
    for args, says in ((["--out", "--no-plot"], "--out: needs a value, got the flag --no-plot"),
                       (["--out", "--log", "--no-plot"], "--out: needs a value, got the flag --log"),
                       (["--scene", "--out", "x"], "--scene: needs a value, got the flag --out"),
                       (["--config", "--"], "--config: needs a value, got the flag --"),
                       (["--out", "o", "--", "--tick-log", "--faults", "f.yaml"],
                        "--tick-log after --: needs a value, got the flag --faults")):
        p = run("--duration", "0.2", *args, cwd=tmp_path)
        assert p.returncode == 2 and f"run_hil_bench.sh: {says}" in p.stderr, (args, p.stderr)
        assert "dirname" not in p.stderr and "realpath" not in p.stderr, p.stderr
    assert not os.listdir(tmp_path)
    # -res is a legal folder name (and -sc.yaml a file's): a name, never an option of dirname, cd or realpath
    (tmp_path / "-sc.yaml").write_bytes((SOURCE / "tools" / "scenes" / "paper_clearance.yaml").read_bytes())
    p = run("--duration", "0.2", "--no-plot", "--out", "-res", "--scene", "-sc.yaml", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(tmp_path / "-res")) == ["controller.csv", "controller.txt", "firmware.txt", "truth.csv"]


def test_an_out_that_cannot_be_written_is_exit_4_said_by_the_script(tmp_path):
    # (pass 66) mkdir and mktemp failed under set -e: exit 1, a bash line number, no message of the script's
    p = bench("/proc/gimbalsim_bench", "--duration", "0.2", "--no-plot")
    assert p.returncode == 4 and "run_hil_bench.sh: --out /proc/gimbalsim_bench: cannot make it" in p.stderr, p.stderr
    p = bench("/proc/1", "--duration", "0.2", "--no-plot")  # a folder no file can be made in
    assert p.returncode == 4 and "run_hil_bench.sh: --out /proc/1: cannot write in it" in p.stderr, p.stderr
    assert "line " not in p.stderr, p.stderr


def test_a_recorder_that_failed_ends_the_run_with_its_code(tmp_path):
    # (pass 66) the recorder (its log on a full disk: exit 4) had ended; the script's own kill of it failed
    # under set -e: exit 1, "kill: No such process". A stand-in recorder that fails the same way.
    fake = tmp_path / "build" / "bin"
    fake.mkdir(parents=True)
    for name in ("firmware_sim", "pointing_controller", "gimbalsim_log2csv"):
        (fake / name).symlink_to(BIN / name)
    (fake / "gimbalsim_record").write_text("#!/bin/sh\necho 'gimbalsim_record: error: write failed: No space left "
                                           "on device' >&2\nexit 4\n")
    (fake / "gimbalsim_record").chmod(0o755)
    (tmp_path / "o").mkdir()
    (tmp_path / "o" / "truth.csv").write_text("previous\n")
    p = bench(tmp_path / "o", "--duration", "0.2", "--no-plot", "--log", build=str(fake.parent))
    assert p.returncode == 4 and "gimbalsim_record exited with 4; nothing in" in p.stderr, p.stderr
    assert "No such process" not in p.stderr and sorted(os.listdir(tmp_path / "o")) == ["truth.csv"], p.stderr
    assert (tmp_path / "o" / "truth.csv").read_text() == "previous\n"


@pytest.mark.parametrize("flag", [["--lcm-url", "udpm://239.255.76.67:7667?ttl=0"], ["--channel-prefix", "B2_"],
                                  ["--channel-prefix=B2_"]])
def test_a_flag_after_dashdash_that_would_split_the_pair_is_refused(tmp_path, flag):
    # (pass 88) --channel-prefix after -- went to firmware_sim alone: the controller never heard it, exit 6 after
    # firmware_sim's --start-timeout (30 s)
    t0 = time.monotonic()
    p = run("--duration", "0.2", "--out", "ob", "--no-plot", "--", *flag, cwd=tmp_path)
    says = f"run_hil_bench.sh: {flag[0].split('=')[0]} after --: the script sets it for firmware_sim: "
    assert p.returncode == 2 and says in p.stderr and "use --port; nothing run" in p.stderr, p.stderr
    assert time.monotonic() - t0 < 5 and not (tmp_path / "ob").exists(), p.stderr
