"""Issue 41, "Hostile and careless input" (pass 24), class 3, the sensor
keys: a dispersed latency is judged with the outage (every sample lost at
every latency given), and a sample due at the run's last tick acts only
where a figure reads that tick's estimate (knowledge over the track phase).
Each refusal is checked against the runs themselves: the values refused
give the same figures, the value accepted does not."""
import numpy as np
import pytest

import gimbalsim
from conftest import scene_path
from test_pass16_outputs import tool, write_spec
from test_pass18_python import check

# 0.5 s; the star tracker at 10 Hz: samples at 0.1 s steps, those to 0.35 s in the outage; the one at 0.4 s
# falls due 0.1004 s or more later, after the run's last tick (0.5 s), and is lost
SPEC = """scene: {scene}
set: {{sim.duration: 0.5, {outage}}}
controller: default
controller_set: {{profile.slew_start: 0.1, profile.slew_time: 0.1, profile.hold_time: 0.1}}
samples: 2
seed: 1
{dispersion}
phases: [slew, hold, track]
indices: {{{indices}}}
"""
STAR = {"scene": scene_path("paper_clearance"), "outage": "sensors.star_tracker_outage: [0, 0.35]"}
# the boresight tracker at 10 Hz, every sample to 0.45 s in the outage; the one at 0.5 s past the last tick
TRACKER = {"scene": scene_path("paper_spatial2_tracker"),
           "outage": "sensors.tracker_rate: 10, sensors.tracker_outage: [0, 0.45]"}

LATENCIES = [(STAR, "parameters:\n  sensors.star_tracker_latency: {uniform: [0.1004, 0.2]}", True),
             (STAR, "parameters:\n  sensors.star_tracker_latency: {choice: [0.1004, 0.2]}", True),
             (STAR, "grid:\n  sensors.star_tracker_latency: [0.1004, 0.2]", True),
             # the noise too, while the latency is drawn: no sample it could act on is delivered
             (STAR, "parameters:\n  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}\n"
                    "  sensors.star_tracker_latency: {uniform: [0.1004, 0.2]}", True),
             (STAR, "parameters:\n  sensors.star_tracker_latency: {uniform: [0.05, 0.2]}", False),  # 0.45 s: acts
             (STAR, "parameters:\n  sensors.star_tracker_latency: {choice: [0.05, 0.2]}", False),
             (TRACKER, "parameters:\n  sensors.tracker_latency: {uniform: [0.01, 0.05]}", True)]


@pytest.mark.parametrize("base,dispersion,refused", LATENCIES, ids=[str(i) for i in range(len(LATENCIES))])
def test_a_dispersed_latency_is_judged_with_the_outage(tmp_path, base, dispersion, refused):
    spec = write_spec(tmp_path, SPEC.format(**base, dispersion=dispersion, indices="ape: {}, knowledge: {}"))
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        first = dispersion.split("\n")[1].split(":")[0].strip()
        assert f"{first}'" in p.stderr and "no " in p.stderr and "sample is delivered" in p.stderr, p.stderr


def test_an_allocation_over_a_latency_no_sample_survives_is_refused(tmp_path):
    text = SPEC.format(**STAR, dispersion="parameters:\n  friction.mu: {uniform: [0.15, 0.35]}",
                       indices="knowledge: {}") + \
        ("allocate:\n  key: sensors.star_tracker_latency\n  range: [0.1004, 0.2]\n  direction: largest\n"
         "  index: knowledge\n  phase: track\n  requirement: 1.0e-4\n  level: 0.5\n  confidence: 0.5\n  values: 3\n")
    p = tool("allocate", write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2, p.stderr
    assert "key 'allocate.key'" in p.stderr and "sample is delivered" in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()


def _run(**sensors):
    scene = gimbalsim.load_scene(scene_path("paper_clearance"),
                                 {"sim.duration": 0.5, "sensors.star_tracker_outage": [0.0, 0.35],
                                  "sensors.star_tracker_noise": 1.0e-4, **sensors})
    ctrl = gimbalsim.Controller(None, {"profile.slew_start": 0.1, "profile.slew_time": 0.1,
                                       "profile.hold_time": 0.1})
    c = gimbalsim.closed_loop(scene, ctrl, 0.5).columns
    return np.column_stack([c[k] for k in ("los_error_x", "los_error_y", "los_error_z",
                                           "los_error_est_x", "los_error_est_y", "los_error_est_z")])


def test_the_latencies_refused_give_the_same_run_and_the_one_accepted_does_not():
    late, later, early = (_run(**{"sensors.star_tracker_latency": lat}) for lat in (0.1004, 0.2, 0.05))
    assert np.array_equal(late, later)
    assert not np.array_equal(late, early)


# the last tick: a sample due there moves only that tick's estimate, which knowledge over track reads
LAST = [("ape: {}", True), ("ape: {}, rpe: {window: 0.05}", True), ("ape: {}, knowledge: {}", False)]


@pytest.mark.parametrize("indices,refused", LAST, ids=[i for i, _ in LAST])
def test_a_sample_due_at_the_last_tick_acts_only_where_knowledge_reads_it(tmp_path, indices, refused):
    # 10 Hz, outage to 0.45 s: the sample at 0.5 s is taken and delivered at the run's last tick
    base = {**STAR, "outage": "sensors.star_tracker_outage: [0, 0.45]"}
    spec = write_spec(tmp_path, SPEC.format(**base, indices=indices, dispersion="parameters:\n"
                                            "  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}"))
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "key 'parameters.sensors.star_tracker_noise'" in p.stderr, p.stderr


def test_the_last_ticks_sample_moves_the_estimate_there_and_nothing_the_truth_reads():
    quiet, noisy = (_run(**{"sensors.star_tracker_outage": [0.0, 0.45], "sensors.star_tracker_noise": n})
                    for n in (0.0, 1.0e-3))
    assert np.array_equal(quiet[:, :3], noisy[:, :3])  # the truth, every tick
    assert np.array_equal(quiet[:-1, 3:], noisy[:-1, 3:])  # the estimate before the last tick
    assert not np.array_equal(quiet[-1, 3:], noisy[-1, 3:])


# (pass 89) On a fixed base the star tracker reads the identity and a perfect gyro zero: its outage, rate and
# latency and the estimator's gains change no estimate (the C++ fault check refuses such an outage too).
FIXED = {"scene": scene_path("paper_ideal"), "outage": "structure.base: fixed"}
ON_A_FIXED_BASE = [("parameters:\n  sensors.star_tracker_rate: {choice: [5, 10]}", "", True),
                   ("parameters:\n  sensors.star_tracker_outage: {choice: [[0.1, 0.2], [0.2, 0.3]]}", "", True),
                   ("parameters:\n  controller.estimator.k_p: {uniform: [0.2, 0.6]}", "", True),
                   ("parameters:\n  sensors.star_tracker_rate: {choice: [5, 10]}", ", sensors.gyro_noise: 1.0e-4",
                    False)]


@pytest.mark.parametrize("dispersion,gyro,refused", ON_A_FIXED_BASE, ids=[str(i) for i in range(len(ON_A_FIXED_BASE))])
def test_a_star_tracker_key_on_a_fixed_base_with_perfect_sensors_is_refused(tmp_path, dispersion, gyro, refused):
    base = {**FIXED, "outage": FIXED["outage"] + gyro}
    spec = write_spec(tmp_path, SPEC.format(**base, dispersion=dispersion, indices="ape: {}, knowledge: {}"))
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "on a fixed base (structure.base fixed) the star tracker reads the identity" in p.stderr, p.stderr


def test_a_star_tracker_outage_fault_on_a_fixed_base_is_refused_unless_the_gyro_can_drift(tmp_path):
    faults = tmp_path / "outage.yaml"
    faults.write_text("faults:\n  - {type: star_tracker_outage, start: 0.1, end: 0.3}\n")
    ctrl = gimbalsim.Controller(None, {})
    fixed = {"sim.duration": 0.5, "structure.base": "fixed"}
    with pytest.raises(gimbalsim.SceneError, match=r"outage.yaml:2:5: fault #1 \(star_tracker_outage\): on a fixed "
                                                   r"base .* the outage would be flagged and change no estimate"):
        gimbalsim.closed_loop(gimbalsim.load_scene(scene_path("paper_ideal"), fixed), ctrl, 0.5, faults=faults)
    noisy = gimbalsim.load_scene(scene_path("paper_ideal"), {**fixed, "sensors.gyro_noise": 1.0e-4})
    assert gimbalsim.closed_loop(noisy, ctrl, 0.5, faults=faults).columns["injected_faults"].any()


# (pass 90) a YAML escape in the spec's own text made a control character: refused for another reason, with the
# raw bytes printed (ESC]0;...BEL set the terminal's title, ESC[2J cleared it, a NUL cut the refusal)
ESCAPES = [('scene: "a\\e]0;pwned\\a.yaml"\nsamples: 2\n', "scene", "001B"),
           (f'scene: {scene_path("paper_clearance")}\nsamples: 2\nset: {{name: "a\\u0000b"}}\n', "set.name", "0000"),
           (f'scene: {scene_path("paper_clearance")}\nsamples: 2\nphases: ["\\e[2J"]\n', "phases", "001B"),
           (f'scene: {scene_path("paper_clearance")}\nsamples: 2\n"x\\x85y": 1\n', "", "0085"),
           # (pass 94) a line separator split the refusal, a right-to-left override reversed it
           (f'scene: {scene_path("paper_clearance")}\nsamples: 2\nparameters:\n  "friction.mu\\u2028": '
            '{uniform: [0.1, 0.2]}\n', "", "2028"),
           (f'scene: {scene_path("paper_clearance")}\nsamples: 2\nphases: ["a\\u202eb"]\n', "phases", "202E"),
           (f'scene: {scene_path("paper_clearance")}\nsamples: 2\nphases: ["a\\u061cb"]\n', "phases", "061C")]


@pytest.mark.parametrize("text,key,code", ESCAPES, ids=[str(i) for i in range(len(ESCAPES))])
def test_a_control_character_from_an_escape_in_a_spec_is_refused_at_its_place(tmp_path, text, key, code):
    p = check(write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2 and f"character U+{code} (a control character, from an escape)" in p.stderr, p.stderr
    assert f"key '{key}'" in p.stderr or not key, p.stderr
    assert not any(c in p.stderr for c in "\x00\x1b\x07\x85\u2028\u202e\u061c"), repr(p.stderr)


# (pass 105) a line separator in a comment showed an editor a line "mu: 0.9" the spec never held; PyYAML (YAML 1.1)
# reads U+2028 as a line break where the scene loader does not: refused anywhere in a spec, at its line and column
@pytest.mark.parametrize("mark", ["\u2028", "\u202e", "\u061c", "\u2066"])
def test_a_layout_character_in_a_spec_comment_is_refused_at_its_place(tmp_path, mark):
    text = f'scene: {scene_path("paper_clearance")}\nsamples: 2  # two{mark}  samples: 9\n'
    p = check(write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2 and f":2:18: character U+{ord(mark):04X} splits or reorders the line" in p.stderr, \
        p.stderr
    assert mark not in p.stderr, repr(p.stderr)


# (pass 114) a lone carriage return in a comment: PyYAML broke the line there and applied "samples: 9", which an
# editor (and the scene loader) showed inside the comment; a CR LF file stays a file
def test_a_lone_carriage_return_is_refused_at_its_place_and_crlf_lines_are_taken(tmp_path):
    text = f'scene: {scene_path("paper_clearance")}\nsamples: 2  # two\rsamples: 9\n'
    p = check(write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 2 and ":2:18: character U+000D without a line feed after it" in p.stderr, p.stderr
    text = (f'scene: {scene_path("paper_clearance")}\nsamples: 2\nseed: 1\nparameters:\n'
            '  contact.clearance: {uniform: [1.0e-4, 2.0e-4]}\n').replace("\n", "\r\n")
    p = check(write_spec(tmp_path, text), tmp_path / "out")
    assert p.returncode == 0, p.stderr


# (pass 108) an override holding such a character was refused with the command line's place ("--set #1 ..."):
# the shown text no longer matched the one the relabelling looked for
def test_an_override_holding_a_layout_character_is_named_as_the_caller_gave_it():
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.load_scene(scene_path("paper_clearance"), {"sim.step": "1\u202e"})
    assert str(e.value).startswith("overrides['sim.step'] (sim.step=1<U+202E>): key 'sim.step': character U+202E"), \
        str(e.value)
    with pytest.raises(gimbalsim.SceneError) as e:
        gimbalsim.Controller(None, {"bad\u202e": 1})
    assert "(bad<U+202E>=1): unknown key 'bad<U+202E>'" in str(e.value) and "--set #" not in str(e.value), str(e.value)
    assert "\u202e" not in str(e.value).split(" (", 1)[1], str(e.value)


# (pass 93) an outage between two samples of the 10 Hz star tracker takes and drops none: it acted on nothing but
# its flag (the bench refuses the same window as a fault and as a --set)
GAPS = [('sensors.star_tracker_outage: "[0.25, 0.28]"', "", True),
        ("", "parameters:\n  sensors.star_tracker_outage: {choice: [[0.25, 0.28], [0.31, 0.39]]}", True),
        ("", "parameters:\n  sensors.star_tracker_outage: {choice: [[0.25, 0.28], [0.15, 0.25]]}", False),
        # (pass 94) idle at every rate a choice gives (samples at 0.3 s and 0.333 s) was taken; at 4 Hz, 0.25 s is
        ('sensors.star_tracker_outage: "[0.21, 0.29]"', "parameters:\n  sensors.star_tracker_rate: {choice: [10, 3.0]}",
         True),
        ('sensors.star_tracker_outage: "[0.21, 0.29]"', "parameters:\n  sensors.star_tracker_rate: {choice: [10, 4.0]}",
         False),
        # (pass 96) and at every rate of a range: from 5 to 6 Hz samples fall in [0.167, 0.2] and [0.333, 0.4] s
        ('sensors.star_tracker_outage: "[0.21, 0.29]"', "parameters:\n  sensors.star_tracker_rate: {uniform: [5, 6]}",
         True),
        ('sensors.star_tracker_outage: "[0.21, 0.29]"', "parameters:\n  sensors.star_tracker_rate: {uniform: [4, 6]}",
         False),
        ('sensors.star_tracker_outage: "[0.21, 0.29]"',
         "parameters:\n  sensors.star_tracker_latency: {uniform: [0, 0.005]}", True),
        ('sensors.star_tracker_outage: "[0.21, 0.29]"',
         "parameters:\n  sensors.star_tracker_latency: {uniform: [0, 0.05]}", False),
        # (pass 98) the boresight tracker's (100 Hz): from 95 Hz its second sample is taken at 0.011 s at the
        # latest, due at 0.012 s at the latest with 1 ms of latency; the tick-wide bound took both
        ('sensors.tracker_outage: "[0.012, 0.018]"', "parameters:\n  sensors.tracker_rate: {uniform: [95, 100]}",
         True),
        ('sensors.tracker_outage: "[0.012, 0.018]", sensors.tracker_rate: 100',
         "parameters:\n  sensors.tracker_latency: {uniform: [0, 0.001]}", True),
        ('sensors.tracker_outage: "[0.012, 0.018]", sensors.tracker_rate: 100',
         "parameters:\n  sensors.tracker_latency: {uniform: [0, 0.0025]}", False),
        # (pass 104) a window between two 1 ms ticks holds no tick: nothing is taken or due in it at any rate
        ('sensors.tracker_outage: "[0.0123, 0.0127]"', "parameters:\n  sensors.tracker_rate: {uniform: [1000, 2000]}",
         True),
        ('sensors.star_tracker_outage: "[0.2003, 0.2007]"',
         "parameters:\n  sensors.star_tracker_rate: {uniform: [5, 20]}", True)]


@pytest.mark.parametrize("fixed,dispersion,refused", GAPS, ids=[str(i) for i in range(len(GAPS))])
def test_an_outage_holding_no_sample_is_refused(tmp_path, fixed, dispersion, refused):
    scene = "paper_spatial2_tracker" if "sensors.tracker_" in fixed + dispersion else "paper_clearance"
    base = {"scene": scene_path(scene), "outage": fixed or "sensors.star_tracker_noise: 1.0e-5"}
    spec = write_spec(tmp_path, SPEC.format(**base, dispersion=dispersion or "parameters:\n  friction.mu: "
                                            "{uniform: [0.15, 0.35]}", indices="ape: {}"))
    p = check(spec, tmp_path / "out")
    assert p.returncode == (2 if refused else 0), p.stderr
    if refused:
        assert "takes and drops no sample a figure of the run reads" in p.stderr, p.stderr
