"""The LCM URL of the four programs that speak LCM is read once, the same
way: a malformed one is a bad argument (exit 2, usage.md "Exit codes"),
whether it comes from --lcm-url or from LCM_DEFAULT_URL when the flag is not
given; nothing is run or written. (Pass 35: an option given twice, which LCM
reads as the last, and empty options were taken; a bad LCM_DEFAULT_URL was
exit 5, "LCM could not start".)"""
import os
import subprocess

import pytest

from conftest import BIN, SCENES

PROGRAMS = {"firmware_sim": [str(SCENES / "paper_ideal.yaml"), "--duration", "0.01", "--rt-priority", "0"],
            "pointing_controller": ["--duration", "0.01", "--idle-exit", "0.1"],
            "gimbalsim_record": ["{tmp}/rec.log", "--duration", "0.01"],
            "torque_replay": ["{tmp}/no_such_truth.csv"]}


def run(program, tmp_path, *extra, env_url=None):
    env = {k: v for k, v in os.environ.items() if k != "LCM_DEFAULT_URL"}
    if env_url is not None:
        env["LCM_DEFAULT_URL"] = env_url
    args = [a.format(tmp=tmp_path) for a in PROGRAMS[program]]
    return subprocess.run([str(BIN / program), *args, *extra], capture_output=True, text=True, timeout=60, env=env)


@pytest.mark.parametrize("program", sorted(PROGRAMS))
@pytest.mark.parametrize("url,why", [("udpm://239.255.76.67:7863?ttl=1&ttl=0", "option 'ttl' given twice"),
                                     ("udpm://239.255.76.67:7863?transmit_only=false&transmit_only=true",
                                      "option 'transmit_only' given twice"),
                                     ("udpm://239.255.76.67:7863?ttl=0&", "an empty option"),
                                     ("udpm://239.255.76.67:7863?&&ttl=0", "an empty option"),
                                     ("udpm://239.255.76.67:7863?", "an empty option")])
def test_a_malformed_url_is_a_bad_argument_from_the_flag_and_from_the_environment(program, url, why, tmp_path):
    p = run(program, tmp_path, "--lcm-url", url)
    assert p.returncode == 2 and why in p.stderr and f"--lcm-url: LCM URL '{url}'" in p.stderr, p.stderr
    p = run(program, tmp_path, env_url=url)
    assert p.returncode == 2 and why in p.stderr, p.stderr
    assert f"LCM_DEFAULT_URL (the URL without --lcm-url): LCM URL '{url}'" in p.stderr, p.stderr
    assert not list(tmp_path.iterdir())  # nothing written: gimbalsim_record's log not begun


def test_a_flag_given_wins_over_a_bad_environment(tmp_path):
    p = run("firmware_sim", tmp_path, "--lcm-url", "memq://", env_url="udpm://239.255.76.67:07863")
    assert p.returncode == 0, p.stderr
