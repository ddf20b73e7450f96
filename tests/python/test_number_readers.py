"""One number rule (docs/usage.md "Exit codes"): a number given to a flag of
a Python module or a tools/ script is read as the C++ programs read theirs
(base/program parse(), wholeNumber()). Each text below is given to
firmware_sim's --rate and --truth-every and to the Python readers with the same
range; both must take it or both refuse it. (Pass 34: the scripts refused
'+5' and the package's --until '+0.1', which every program takes.)"""
import argparse
import subprocess
import sys

import pytest

from conftest import BIN, SOURCE

sys.path.insert(0, str(SOURCE / "tools" / "pages"))
import output_file  # noqa: E402

DECIMALS = ["5", "+5", "5.", ".5", "+.5e+1", "5E0", "0.5e-2", "1e6", "1e7", " 5", "5 ", "1_0", "0x1", "0x1p3",
            "inf", "nan", "", "e1", "1e", "--5", "5..0", "1e-400", "5e-324", "2e-310", "\u0665", "５",
            "010", "+010", "00.5", "0.5", "0e1"]  # (pass 42) a real flag took 010 as 10 where a whole one refused it
WHOLES = ["1", "+1", "01", "007", "1000000000", "1000000001", "0", "-1", "+", "-", " 1", "1 ", "1_0", "0x1",
          "1e0", "1.0", "", "\u0661", "--1", "+-1"]


def cpp_takes(flag, text):
    """Whether firmware_sim takes `text` for `flag` (it then stops at the missing scene, naming that instead)."""
    p = subprocess.run([str(BIN / "firmware_sim"), f"{flag}={text}", "/nonexistent/scene.yaml"],
                       capture_output=True, text=True, timeout=30)
    assert p.returncode == 2 and "Traceback" not in p.stderr, (flag, text, p.returncode, p.stderr)
    return flag not in p.stderr


def py_takes(read, text):
    try:
        read(text)
    except argparse.ArgumentTypeError:
        return False
    return True


@pytest.mark.parametrize("text", DECIMALS)
def test_a_real_flag_is_read_as_the_programs_read_it(text):
    assert py_takes(output_file.arg_decimal(0.001, 1e6), text) == cpp_takes("--rate", text), repr(text)


@pytest.mark.parametrize("text", WHOLES)
def test_a_whole_flag_is_read_as_the_programs_read_it(text):
    cpp = cpp_takes("--truth-every", text)
    assert py_takes(output_file.arg_whole(1, 10**9), text) == cpp, repr(text)
    from gimbalsim import _cluster  # --replay, --batch, --max-samples and --workers of the modules
    assert py_takes(lambda t: 1 <= _cluster.whole_number(t) <= 10**9 or _raise(), text) == cpp, repr(text)


def _raise():
    raise argparse.ArgumentTypeError("out of range")


@pytest.mark.parametrize("text", [t for t in DECIMALS if t != "1e7"])  # beyond --rate's range, not its reading
def test_until_relwidth_is_read_as_a_real_flag(text):
    from gimbalsim._until import Until
    from gimbalsim._spec import SpecError

    class Closed:  # the least of a closed-loop spec that --until reads before its width
        indices = [type("Ix", (), {"name": "ape"})()]
        phases = [("track", None)]

    spec = type("Spec", (), {"closed": Closed, "grid": None, "samples": 2})()
    try:
        Until(f"ape:track:{text}", spec, 10)
        taken = True
    except SpecError as e:
        assert "RELWIDTH must be a plain decimal number > 0" in str(e), str(e)
        taken = False
    assert taken == cpp_takes("--rate", text), repr(text)  # each text --rate takes here is > 0


def test_a_leading_zero_is_refused_where_c_reads_octal():
    # (pass 36) firmware_sim took --truth-every 010 as 8 (CLI11 reads it as C does, octal) where the modules read 10
    for text in ("010", "08", "+010", "-01"):
        assert not cpp_takes("--truth-every", text), text
        assert not py_takes(output_file.arg_whole(-100, 100), text), text
    assert cpp_takes("--truth-every", "10") and cpp_takes("--truth-every", "+8")
    for text in ("010", "+010", "00.5"):  # ... and a real flag alike (pass 42: --rate 01000 ran at 1000 Hz)
        assert not cpp_takes("--rate", text) and not py_takes(output_file.arg_decimal(0.001, 1e6), text), text
    assert cpp_takes("--rate", "0.5") and cpp_takes("--rate", "10")


@pytest.mark.parametrize("program,args", [("firmware_sim", ["--truth-csv=", "--lockstep"]),
                                          ("gimbalsim", ["simulate", "--out=", "--summary", "s.json"]),
                                          ("pointing_controller", ["--lcm-url=", "--duration", "1"])])
def test_a_flag_with_nothing_after_its_equals_sign_takes_no_other_argument(program, args, tmp_path):
    # (pass 36) CLI11 read '--truth-csv=' as '--truth-csv' and took the next argument, '--lockstep', for the file
    p = subprocess.run([str(BIN / program), str(SOURCE / "tools/scenes/paper_ideal.yaml"), *args], cwd=tmp_path,
                       capture_output=True, text=True, timeout=30)
    flag = next(a for a in args if a.endswith("="))
    assert p.returncode == 2 and f"{flag}: an empty value after the '='" in p.stderr, p.stderr
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("text", ["1e-400", "4e-320", "2e-310", "1e400", "-1e400", "1e-300", "2.5e-308", "0e-400",
                                  "0.0", "+0.25", ".5", "1" + "0" * 400, "-1" + "0" * 309, "5"])
def test_a_spec_number_is_read_as_a_scene_file_number(text, tmp_path):
    # (pass 38) a sweep spec read `friction.mu: 1e-400` as 0 and ran it, where the scene file's `mu: 1e-400` is
    # refused at its line: a number the text names and the double lost is no number (0 means "off")
    from gimbalsim._spec import Spec, SpecError
    scene = (SOURCE / "tools/scenes/paper_clearance.yaml").read_text().replace("  mu: 0.25\n", f"  mu: {text}\n")
    (tmp_path / "s.yaml").write_text(scene)
    p = subprocess.run([str(BIN / "gimbalsim"), "simulate", "s.yaml", "--set", "sim.duration=0.001", "--out", "o.csv"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert p.returncode in (0, 2), p.stderr
    cpp = p.returncode == 0
    assert cpp or "key 'friction.mu'" in p.stderr, p.stderr
    (tmp_path / "spec.yaml").write_text(f"set: {{friction.mu: {text}}}\n")
    try:
        taken = Spec(tmp_path / "spec.yaml").root.value["set"].value["friction.mu"].value
    except SpecError as e:
        assert "spec.yaml:1:" in str(e), str(e)  # (pass 39: 10^400, a traceback)
        # the text whole, or visibly cut (pass 42: 10^400 was quoted as its first 40 digits, 1e39, which reads)
        assert (f"'{text}'" if len(text) <= 40 else f"'{text[:40]}... ({len(text)} characters)'") in str(e), str(e)
        taken = None
    assert (taken is not None) == cpp, (text, taken, p.stderr)
    assert taken is None or taken == float(text)


SCRIPT_FLAGS = [("tools/hil/hil_speed.py", "--seconds"), ("tools/hil/worst_tick.py", "--seconds"),
                ("tools/bench/perf_report.py", "--min-time"), ("tools/bench/sweep_scaling.py", "--duration"),
                ("tools/bench/tick_parts.py", "--seconds"), ("tools/bench/compare_bench.py", "--min-time"),
                ("tools/bench/sweep_scaling.py", "--samples"), ("tools/bench/loop_cost.py", "--reps")]


@pytest.mark.parametrize("script,flag", SCRIPT_FLAGS)
@pytest.mark.parametrize("text", ["0200", "2_00", "nan", "inf", " 2"])
def test_the_bench_scripts_read_their_numbers_as_the_programs_do(script, flag, text):
    # (pass 43) these scripts read numbers with float()/int(): 0200, 2_00, nan and inf were taken
    p = subprocess.run([sys.executable, str(SOURCE / script), f"{flag}={text}"], capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 2 and f"argument {flag}" in p.stderr and "Traceback" not in p.stderr, (script, p.stderr)


@pytest.mark.parametrize("script", ["tools/hil/hil_speed.py", "tools/bench/perf_report.py"])
@pytest.mark.parametrize("text", ["010", "1000,,2000", "1000,", "0x5", "-5", "0", " 5", "1_0"])
def test_a_list_of_rates_is_read_item_by_item(script, text):
    # (pass 44) hil_speed --rates took 010, ' 5', 1_0, -5 and 0, dropped an empty item, and 0x5 was a traceback
    p = subprocess.run([sys.executable, str(SOURCE / script), f"--rates={text}"], capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 2 and "argument --rates" in p.stderr and "Traceback" not in p.stderr, (text, p.stderr)
