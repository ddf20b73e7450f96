"""A resume trusts no journal row: a figure the sweep never writes (negative,
infinite, nan in an ok row whose reason does not name it, not the sweep's
number text), a fingerprint that is not the sweep's, or applied_ columns
that are not what the draw applies when loaded, drop the row and its sample
runs again (docs/python.md "The journal"); never a traceback, never a bad
number carried into results.csv. A replay refuses a row that is not whole."""
import csv
import json
import math
import shutil
import subprocess
import sys

import pytest

from conftest import SCENES, row_verdict, spec_of

OPEN = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.05}}
samples: 3
seed: 2
parameters:
  contact.clearance: {{uniform: [1.0e-4, 3.0e-4]}}
  initial.ecc: {{disk: {{radius: 2.5e-4}}}}
"""
CLOSED = f"""
scene: {SCENES}/paper_clearance.yaml
set: {{sim.duration: 0.4}}
controller: default
controller_set: {{profile.slew_start: 0.0, profile.slew_time: 0.2, profile.hold_time: 0.1}}
samples: 6
seed: 3
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
  controller.azimuth.kp: {{uniform: [2000.0, 4000.0]}}
indices:
  ape: {{}}
"""


def rows_alone(spec, samples):
    """{sample: its row as the sweep writes it}, each run in this process."""
    from gimbalsim._sample import sample_alone
    return {i: sample_alone(spec, i)[0] for i in samples}


@pytest.fixture(scope="module")
def open_loop(tmp_path_factory):
    spec = spec_of(tmp_path_factory.mktemp("open"), OPEN)
    return spec, rows_alone(spec, range(3))


def test_the_open_loops_own_rows_are_trusted(open_loop):
    spec, rows = open_loop
    status = [r[spec.csv_header().index("status")] for r in rows.values()]
    assert "ok" in status and "refused:initial.ecc" in status  # both kinds of row, as written
    assert [row_verdict(spec, r) for r in rows.values()] == [None] * 3


BAD_FIGURES = [
    ({"pointing_error_max_rad": "-0.5"}, "pointing_error_max_rad is negative"),
    ({"pointing_error_max_rad": "inf"}, "pointing_error_max_rad is infinite"),
    ({"peak_contact_force_N": "nan"}, "peak_contact_force_N is nan in an ok row"),
    ({"peak_contact_force_N": ""}, "peak_contact_force_N is empty in an ok row"),
    ({"peak_contact_force_N": "5.00"}, "peak_contact_force_N is not a number as the sweep writes one"),
    ({"impacts": "1.5"}, "impacts is not a whole number"),
    ({"wall_time_s": "nan"}, "wall_time_s is nan: only a crashed sample"),
    ({"base_scene_sha256": "0" * 64}, "base_scene_sha256 is not this sweep's fingerprint"),
    ({"applied_contact_clearance_m": "0.0002"}, "applied_contact_clearance_m differs from what the draw applies"),
    ({"applied_initial_ecc_1_m": "inf"}, "applied_initial_ecc_1_m differs from what the draw applies"),
    ({"applied_differs": "contact.clearance"}, "applied_differs differs from what the draw applies"),
    ({"status": "crashed"}, "holds"),
]


@pytest.mark.parametrize("cells,reason", BAD_FIGURES, ids=[r for _, r in BAD_FIGURES])
def test_an_ok_row_the_sweep_did_not_write_is_not_trusted(open_loop, cells, reason):
    spec, rows = open_loop
    ok = next(r for r in rows.values() if r[spec.csv_header().index("status")] == "ok")
    assert reason in (row_verdict(spec, ok, **cells) or "")


def test_a_refusal_must_be_the_one_the_draw_gives(open_loop):
    spec, rows = open_loop
    header = spec.csv_header()
    refused = next(r for r in rows.values() if r[header.index("status")].startswith("refused:"))
    ok = next(r for r in rows.values() if r[header.index("status")] == "ok")
    assert "status is not the refusal" in row_verdict(spec, refused, status="refused:friction.mu")
    assert "holds" in row_verdict(spec, refused, pointing_error_max_rad="0.1")
    # the ok sample's draw recorded as refused, without figures: the scene takes that draw
    blank = {h: "" for h in header if h.startswith(("applied_", "pointing", "peak", "impacts", "continuous", "max_tilt"))}
    assert "a refusal, but the scene takes" in row_verdict(spec, ok, status="refused:initial.ecc", **blank)
    # a crashed row holds its parameters and fingerprints only
    assert row_verdict(spec, ok, status="crashed", wall_time_s="nan", **blank) is None


@pytest.fixture(scope="module")
def closed_sweep(tmp_path_factory):
    folder = tmp_path_factory.mktemp("closed")
    (folder / "spec.yaml").write_text(CLOSED)
    p = sweep(folder / "spec.yaml", "--out", folder / "ref", "--workers", "1")
    assert p.returncode == 0, p.stderr
    return folder


def sweep(*args):
    return subprocess.run([sys.executable, "-m", "gimbalsim.sweep", *map(str, args), "--no-progress"],
                          capture_output=True, text=True, timeout=600)


def read(path):
    with open(path, newline="") as f:
        return list(csv.reader(f))


def test_a_closed_loops_nan_needs_its_reason(closed_sweep):
    from gimbalsim.sweep import SweepSpec
    spec = SweepSpec(closed_sweep / "spec.yaml")
    row = read(closed_sweep / "ref" / "results.csv")[1]
    assert row_verdict(spec, row) is None
    assert "ape_track_rad is nan in an ok row" in row_verdict(spec, row, ape_track_rad="nan")
    assert "ape_track_rad is nan in an ok row" in row_verdict(spec, row, ape_track_rad="nan", reason="ape_hold: no tick")
    assert row_verdict(spec, row, ape_track_rad="nan", reason="ape_track: the run ended at 0.3 s") is None
    stop = "simulation stopped at t = 0.3 s: a velocity exceeded sim.velocity_limit (diverging)"
    assert row_verdict(spec, row, ape_track_rad="nan", status="sim.velocity_limit",
               reason=stop + " | ape_track: the run stopped") is None


def test_resume_drops_bad_rows_and_runs_their_samples_again(closed_sweep, tmp_path):
    """The defect: a negative figure ended the resume in a traceback (indices.py),
    an inf, a nan in an ok row without a reason, a wrong fingerprint or applied
    value were kept and written into results.csv."""
    reference = read(closed_sweep / "ref" / "results.csv")
    header = reference[0]
    out = tmp_path / "out"
    shutil.copytree(closed_sweep / "ref", out)
    (out / "results.csv").unlink()
    rows = [list(r) for r in reference[1:]]
    bad = [("ape_track_rad", "-0.5", "is negative"), ("ape_track_rad", "inf", "is infinite"),
           ("ape_track_rad", "nan", "is nan in an ok row"),
           ("base_scene_sha256", "0" * 64, "is not this sweep's fingerprint"),
           ("applied_controller_azimuth_kp_Nm_per_rad", "2500", "differs from what the draw applies")]
    for row, (column, text, _) in zip(rows, bad):
        row[header.index(column)] = text
    (out / "results.partial.csv").write_text("".join(",".join(r) + "\n" for r in [header] + rows))
    p = sweep(closed_sweep / "spec.yaml", "--out", out, "--workers", "1", "--resume")
    assert p.returncode == 0 and "Traceback" not in p.stderr, p.stderr
    for number, (column, _, reason) in enumerate(bad, 2):  # each named with its line in the file read
        assert f"dropped 1 journal row ({column} {reason}" in p.stderr, p.stderr
        assert f") at {out / 'results.partial.csv'} line {number}; their samples run again" in \
            next(line for line in p.stderr.splitlines() if f"({column} {reason}" in line), p.stderr
    assert "6 samples, 1 already done, 5 to run" in p.stderr, p.stderr
    w = header.index("wall_time_s")
    again = read(out / "results.csv")
    assert [r[:w] + r[w + 1:] for r in again] == [r[:w] + r[w + 1:] for r in reference]
    assert all(math.isfinite(float(r[header.index("ape_track_rad")])) for r in again[1:])
    dropped = json.loads((out / "summary.json").read_text())["journal_rows_dropped"]
    assert len(dropped) == len(bad) and set(dropped.values()) == {1}


def test_resume_reads_results_csv_beside_the_journal(closed_sweep, tmp_path):
    """(pass 35) A folder holding results.csv and a journal (a finished sweep resumed, then stopped): the
    resume read the journal alone, kept its hand-edited row of sample 0, and ran the samples results.csv
    held again. Now a sample with a different row in each file runs again, and results.csv's others count."""
    reference = read(closed_sweep / "ref" / "results.csv")
    header = reference[0]
    a = header.index("ape_track_rad")
    out = tmp_path / "out"
    shutil.copytree(closed_sweep / "ref", out)
    edited = list(reference[1])
    edited[a] = "0.25"  # a figure the sweep could write, not sample 0's
    (out / "results.partial.csv").write_text("".join(",".join(r) + "\n" for r in [header, edited, reference[2]]))
    p = sweep(closed_sweep / "spec.yaml", "--out", out, "--workers", "1", "--resume")
    assert p.returncode == 0 and "Traceback" not in p.stderr, p.stderr
    why = "sample with two different rows, in results.csv and results.partial.csv"
    assert f"dropped 1 journal row ({why}) at {out / 'results.partial.csv'} line 2;" in p.stderr, p.stderr
    assert f"dropped 1 row ({why}) at {out / 'results.csv'} line 2;" in p.stderr, p.stderr
    assert "6 samples, 5 already done, 1 to run" in p.stderr, p.stderr  # sample 0 alone, not 2..5 again
    w = header.index("wall_time_s")
    again = read(out / "results.csv")
    assert [r[:w] + r[w + 1:] for r in again] == [r[:w] + r[w + 1:] for r in reference]
    assert json.loads((out / "summary.json").read_text())["journal_rows_dropped"] == {why: 2}


@pytest.mark.parametrize("twice_in", ["results.partial.csv", "results.csv"])
def test_a_sample_one_file_holds_twice_is_trusted_in_neither(closed_sweep, tmp_path, twice_in):
    """(pass 39) One file held sample 0 twice, differently, the other a third row for it: the two were dropped
    ("their samples run again"), the third kept unchecked, and nothing ran again."""
    reference = read(closed_sweep / "ref" / "results.csv")
    header = reference[0]
    a = header.index("ape_track_rad")
    out = tmp_path / "out"
    shutil.copytree(closed_sweep / "ref", out)
    edited, other = list(reference[1]), list(reference[1])
    edited[a], other[a] = "0.25", "0.5"  # figures the sweep could write, neither sample 0's
    once_in = "results.csv" if twice_in == "results.partial.csv" else "results.partial.csv"
    (out / twice_in).write_text("".join(",".join(r) + "\n" for r in [header, reference[1], other] + reference[2:]))
    (out / once_in).write_text("".join(",".join(r) + "\n" for r in [header, edited] + reference[2:]))
    p = sweep(closed_sweep / "spec.yaml", "--out", out, "--workers", "1", "--resume")
    assert p.returncode == 0 and "Traceback" not in p.stderr, p.stderr
    assert f"(sample held twice, differently, in {twice_in}) at {out / once_in} line 2;" in p.stderr, p.stderr
    assert "6 samples, 5 already done, 1 to run" in p.stderr, p.stderr  # sample 0 runs again
    w = header.index("wall_time_s")
    again = read(out / "results.csv")
    assert [r[:w] + r[w + 1:] for r in again] == [r[:w] + r[w + 1:] for r in reference]


def test_a_row_journaled_twice_alike_counts_once_and_is_said_so(closed_sweep, tmp_path):
    # (pass 36) the message said "their samples run again" for a row kept once, nothing run again
    reference = read(closed_sweep / "ref" / "results.csv")
    out = tmp_path / "out"
    shutil.copytree(closed_sweep / "ref", out)
    (out / "results.csv").unlink()
    (out / "results.partial.csv").write_text("".join(",".join(r) + "\n" for r in reference + [reference[2]]))
    p = sweep(closed_sweep / "spec.yaml", "--out", out, "--workers", "1", "--resume")
    assert p.returncode == 0 and "6 samples, 6 already done, 0 to run" in p.stderr, p.stderr
    assert "(sample already journaled) at " in p.stderr and "line 8; the same row kept once" in p.stderr, p.stderr


def test_replay_refuses_a_row_that_is_not_whole(closed_sweep, tmp_path):
    out = tmp_path / "out"
    shutil.copytree(closed_sweep / "ref", out)
    lines = (out / "results.csv").read_text().splitlines(keepends=True)
    lines[3] = ",".join(lines[3].split(",")[:5]) + "\n"  # sample 2's row cut to 5 columns
    (out / "results.csv").write_text("".join(lines))
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(out), "--replay", "2", "--out",
                        str(tmp_path / "run.csv")], capture_output=True, text=True, timeout=600)
    assert p.returncode == 2 and "Traceback" not in p.stderr, p.stderr
    assert "results.csv:4: sample 2's row has 5 columns" in p.stderr and "--resume" in p.stderr, p.stderr


def test_rows_results_csv_holds_twice_are_named_in_its_own_words(closed_sweep, tmp_path):
    # (pass 40) results.csv's own duplicate rows were said "journaled"; an identical one is kept once
    reference = read(closed_sweep / "ref" / "results.csv")
    a = reference[0].index("ape_track_rad")
    out = tmp_path / "out"
    shutil.copytree(closed_sweep / "ref", out)
    (out / "results.partial.csv").write_text("".join(",".join(r) + "\n" for r in reference[:1]))
    other = list(reference[1])
    other[a] = "0.5"
    (out / "results.csv").write_text("".join(",".join(r) + "\n" for r in reference + [reference[2], other]))
    p = sweep(closed_sweep / "spec.yaml", "--out", out, "--workers", "1", "--resume")
    assert p.returncode == 0 and "Traceback" not in p.stderr, p.stderr
    assert "journaled" not in p.stderr, p.stderr
    assert f"(sample already in results.csv) at {out / 'results.csv'} line 8; the same row kept once" in p.stderr, \
        p.stderr
    assert f"(sample held twice, differently, in results.csv) at {out / 'results.csv'} lines 2, 9; " \
        "their samples run again" in p.stderr, p.stderr
    assert "6 samples, 5 already done, 1 to run" in p.stderr, p.stderr  # sample 0 runs again
