"""An allocation's value folders as its own: a value whose replay files or
report are not whole is finished again on --resume (not read back), a folder
planted under values/<i> while the allocation runs is exit 4 with the values
before it kept, and no other run's --out goes inside a tool's folder.

The runs are cheap: test_allocate.py's scene, four units a value."""
import json
import shutil
import subprocess
import sys

import pytest

import gimbalsim.allocate
from test_pass16_outputs import ALLOCATE, BASE, SWEEP, TUNE, finished, tool, write_spec  # noqa: F401 (finished: a fixture)


# ---- class 2: a resume reads back only a value its replay and report can use ----

def test_a_resume_writes_each_values_report_and_replay_files_again_from_its_rows(tmp_path, finished):
    spec, first, code, answer = finished
    out = tmp_path / "out"
    shutil.copytree(first, out)
    values = out / "values"
    budget = {k: json.loads((first / "values" / str(k) / "summary.json").read_text())["budget"] for k in range(3)}
    assert budget[1] != budget[2]
    (values / "0" / "inputs.json").write_text("garbage{")
    (values / "0" / "summary.json").write_text('{"plots": []}')
    (values / "0" / "report.md").write_text("")
    for name in ("report.md", "summary.json"):  # another value's report in value 1's folder
        shutil.copy(first / "values" / "2" / name, values / "1" / name)
    plot = next((values / "2" / "plots").iterdir())
    plot.unlink()
    p = tool("allocate", spec, out, "--resume")
    assert p.returncode == code, p.stderr
    assert p.stderr.count("(read back)") == 3, p.stderr  # no sample ran again
    assert json.loads((out / "allocation.json").read_text())["values"] == answer["values"]
    for k in range(3):  # each value's own figures and report, and its units replay from its folder
        assert json.loads((values / str(k) / "summary.json").read_text())["budget"] == budget[k], k
        assert (values / str(k) / "report.md").read_text() != ""
        p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(values / str(k)), "--replay", "0", "--out",
                            str(tmp_path / f"replay{k}.csv")], capture_output=True, text=True, timeout=120)
        assert p.returncode == 0, (k, p.stderr)
    assert (values / "1" / "report.md").read_text() != (first / "values" / "2" / "report.md").read_text()
    assert plot.is_file()


# ---- class 10: planted while the allocation runs: exit 4, "move it away, --resume" ----

@pytest.mark.parametrize("planted", ["link", "sweep"])
def test_a_value_folder_planted_while_the_allocation_runs_is_exit_4(tmp_path, monkeypatch, capsys, planted):
    spec = write_spec(tmp_path, BASE + ALLOCATE)
    out, victim = tmp_path / "out", tmp_path / "victim"
    victim.mkdir()
    real_sweep = gimbalsim.allocate.sweep

    def sweep_then_plant(sub, folder, **kwargs):
        summary = real_sweep(sub, folder, **kwargs)
        if folder.name == "0":  # the next value's folder, made by someone else meanwhile
            if planted == "link":
                (folder.parent / "1").symlink_to(victim)
            else:
                (folder.parent / "1").mkdir()
                (folder.parent / "1" / "spec.json").write_text("another sweep's\n")
        return summary

    monkeypatch.setattr(gimbalsim.allocate, "sweep", sweep_then_plant)
    code = gimbalsim.allocate.main([str(spec), "--out", str(out), "--workers", "1", "--no-progress"])
    err = capsys.readouterr().err
    assert code == 4, err
    assert f"{out / 'values' / '1'}: appeared while the allocation ran" in err, err
    assert "run again with --resume" in err, err
    assert not any(victim.iterdir())
    assert (out / "values" / "0" / "results.csv").is_file(), "the value before it kept"


# ---- class 7: no --out inside another tool's folder ----

INSIDE = [("sweep", "allocation_spec.json", "values/0", "an allocation"),
          ("tune", "allocation_spec.json", "values/5", "an allocation"),
          ("sweep", "study.db", "mine", "a tuning study"),
          ("allocate", "spec.json inputs.json", "plots/x", "a sweep")]


@pytest.mark.parametrize("program,marks,below,what", INSIDE, ids=[f"{p}-{w.split()[-1]}" for p, _, _, w in INSIDE])
def test_an_out_inside_another_tools_folder_is_refused(tmp_path, program, marks, below, what):
    text = {"allocate": BASE + ALLOCATE, "sweep": SWEEP, "tune": TUNE}[program]
    spec = write_spec(tmp_path, text)
    held = tmp_path / "held"
    (held / below).parent.mkdir(parents=True)
    for name in marks.split():
        (held / name).write_text("")
    p = tool(program, spec, held / below)
    assert p.returncode == 2 and f"lies inside {what} ({held})" in p.stderr, p.stderr
    assert not (held / below).exists()
