"""gimbalsim.tune stopped by a signal before its new study was recorded (pass
56): it advised --resume, which was refused ("empty: no study to resume"),
and a plain run was refused over the file left ("already holds a study"). A
study not recorded leaves nothing, the note says to run again without
--resume; an empty study.db found in --out is named for what it is."""
import signal
import subprocess

import gimbalsim.tune
from gimbalsim._errors import Interrupted
from test_tune_study import tune_cmd, write_spec


def test_a_signal_before_the_study_is_recorded_leaves_nothing_and_says_run_again(tmp_path, monkeypatch, capsys):
    spec = write_spec(tmp_path, 1)
    out = tmp_path / "o"

    def opened_then_signalled(spec_, out_, resume):
        out_.mkdir(exist_ok=True)
        (out_ / "study.db").write_bytes(b"")  # SQLite had made the file, not yet the study
        raise Interrupted(signal.SIGTERM)

    monkeypatch.setattr(gimbalsim.tune, "open_study", opened_then_signalled)
    code = gimbalsim.tune.main([str(spec), "--out", str(out), "--workers", "1", "--no-progress"])
    err = capsys.readouterr().err
    assert code == 128 + signal.SIGTERM, err
    assert "interrupted (SIGTERM): before the study was recorded, nothing kept in" in err, err
    assert "--resume to continue" not in err, err
    assert not out.exists()  # the folder it made goes too (pass 66: left empty)
    monkeypatch.undo()
    again = subprocess.run(tune_cmd(spec, out), capture_output=True, text=True, timeout=300)
    assert again.returncode == 0, again.stderr


def test_an_empty_study_file_is_named_for_what_it_is(tmp_path):
    spec = write_spec(tmp_path, 1)
    (tmp_path / "o").mkdir()
    (tmp_path / "o" / "study.db").write_bytes(b"")
    p = subprocess.run(tune_cmd(spec, tmp_path / "o"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 2, p.stderr
    assert "study.db holds no study of gimbalsim.tune (empty, or a tuner stopped before it recorded one): nothing " \
           "to resume; remove it, or use another --out" in p.stderr, p.stderr
    assert (tmp_path / "o" / "study.db").read_bytes() == b""  # not the tuner's to remove: it did not make it


def test_a_signal_after_the_study_is_recorded_says_resume_and_counts_no_trial_as_none(tmp_path, monkeypatch, capsys):
    spec = write_spec(tmp_path, 1)
    out = tmp_path / "o"
    real_open = gimbalsim.tune.open_study

    def recorded_then_signalled(*args):
        real_open(*args)
        raise Interrupted(signal.SIGTERM)

    monkeypatch.setattr(gimbalsim.tune, "open_study", recorded_then_signalled)
    code = gimbalsim.tune.main([str(spec), "--out", str(out), "--workers", "1", "--no-progress"])
    err = capsys.readouterr().err
    assert code == 128 + signal.SIGTERM, err
    # it said "0 finished trials kept in o/trials.csv", a file that did not exist
    assert f"interrupted (SIGTERM): no trial finished yet; the study is in {out / 'study.db'}: run again with " \
           "--resume to continue it" in err, err
    assert (out / "study.db").is_file() and not (out / "trials.csv").exists()
