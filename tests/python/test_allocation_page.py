"""run_pointing_budget.sh --allocation: the shipped tolerance allocations
(encoders only, and with the antenna's sensors) into out/<spec name>/ each and
one page, docs/results/allocation.md, with each allocation's plot beside it.
The runs are a stand-in allocate (no real allocation runs: one costs an hour);
gimbalsim.allocate --check, which the script asks of both specs before any
run, is the real one."""
import os
import subprocess

from conftest import SOURCE
from test_budget_script import checkout_with_previous_results, digest

SPECS = ("allocation_clearance_encoders", "allocation_clearance")

FAKE_ALLOCATE = '''
import os, pathlib, sys
out = pathlib.Path(sys.argv[sys.argv.index("--out") + 1])
name = pathlib.Path(sys.argv[1]).stem
if "--check" in sys.argv:
    sys.exit(2 if os.environ.get("FAKE_REFUSE") == name else 0)
if os.environ.get("FAKE_LOG"):
    with open(os.environ["FAKE_LOG"], "a") as log:
        log.write(name + "\\n")
out.mkdir(exist_ok="--resume" in sys.argv)
(out / "allocation_spec.json").write_text("{}\\n")
if os.environ.get("FAKE_FAIL") == name:  # a failure after its first value: kept for --resume
    sys.exit(4)
for f in ("allocation.json", "allocation.csv"):
    (out / f).write_text(name + "\\n")
(out / "allocation.png").write_bytes(name.encode())
(out / "allocation.md").write_text(f"# Allocation: {name}\\n\\n![quantile](allocation.png)\\n")
sys.exit(3 if name.endswith("encoders") else 0)  # the encoders: no value meets, an answer all the same
'''


def checkout(tmp_path):
    root, _ = checkout_with_previous_results(tmp_path)
    for name in SPECS:
        (root / f"tools/sweeps/{name}.yaml").write_bytes((SOURCE / f"tools/sweeps/{name}.yaml").read_bytes())
    fake = tmp_path / "fakebuild" / "python" / "gimbalsim"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("")
    (fake / "allocate.py").write_text(FAKE_ALLOCATE)
    env = dict(os.environ, GIMBALSIM_BUILD=str(tmp_path / "fakebuild"))
    return root, str(root / "tools/sweeps/run_pointing_budget.sh"), env


def run(script, env, *args):
    return subprocess.run(["bash", script, *args], capture_output=True, text=True, timeout=60, env=env)


def test_the_allocation_page_holds_both_answers_and_their_plots(tmp_path):
    root, script, env = checkout(tmp_path)
    results = root / "docs/results"
    p = run(script, env, "--allocation", "--workers", "1")
    assert p.returncode == 0, p.stderr  # the encoders' "no value meets" (exit 3) is an answer, not a failure
    page = (results / "allocation.md").read_text()
    assert "Regenerate: `bash tools/sweeps/run_pointing_budget.sh --allocation --workers 1`" in page
    encoders, antenna = page.index("## The loop on the encoders only"), page.index("## The loop at the antenna")
    assert encoders < page.index("## Allocation: allocation_clearance_encoders") < \
        page.index("](allocation_clearance_encoders.png)") < antenna < page.index("](allocation_clearance.png)"), page
    for name in SPECS:
        assert (results / f"{name}.png").read_bytes() == name.encode()
        assert (root / "out" / name / "allocation.json").read_text() == name + "\n"
    assert "allocation.md" in (results / "README.md").read_text()


def test_a_refusal_or_a_failure_leaves_the_previous_page_and_results(tmp_path):
    root, script, env = checkout(tmp_path)
    assert run(script, env, "--allocation").returncode == 0
    before = digest(root / "docs")
    log = tmp_path / "ran.log"
    # the second spec refused by its check: nothing runs (it was found only after the first one's hour)
    p = run(script, dict(env, FAKE_REFUSE="allocation_clearance", FAKE_LOG=str(log)), "--allocation")
    assert p.returncode == 2 and not log.exists(), p.stderr
    # the second allocation fails: the first one's new run is kept for --resume, nothing replaced
    p = run(script, dict(env, FAKE_FAIL="allocation_clearance"), "--allocation")
    assert p.returncode == 4 and "--resume" in p.stderr, p.stderr
    assert digest(root / "docs") == before
    assert (root / "out/allocation_clearance_encoders.new/allocation.json").exists()
    p = run(script, env, "--allocation", "--resume")
    assert p.returncode == 0, p.stderr
    assert not any(n.endswith(".new") for n in os.listdir(root / "out"))
    # a spec runs alone, not as part of the shipped page
    p = run(script, env, "--allocation", "my.yaml")
    assert p.returncode == 2 and "--allocation runs the shipped allocations" in p.stderr, p.stderr


def test_allocate_check_answers_as_a_run_would_and_writes_nothing(tmp_path):
    spec = str(SOURCE / "tools/sweeps/allocation_clearance.yaml")
    allocate = ["/usr/bin/python3", "-m", "gimbalsim.allocate", spec, "--check"]
    p = subprocess.run(allocate + ["--out", str(tmp_path / "new")], capture_output=True, text=True, timeout=120,
                       env=os.environ)
    assert p.returncode == 0 and "nothing run" in p.stderr and os.listdir(tmp_path) == [], p.stderr
    (tmp_path / "held" / "values").mkdir(parents=True)
    p = subprocess.run(allocate + ["--out", str(tmp_path / "held")], capture_output=True, text=True, timeout=120,
                       env=os.environ)
    assert p.returncode == 2 and "already holds an allocation" in p.stderr, p.stderr
    p = subprocess.run(allocate + ["--out", str(tmp_path / "none"), "--resume"], capture_output=True, text=True,
                       timeout=120, env=os.environ)
    assert p.returncode == 2 and "no allocation to resume" in p.stderr, p.stderr
    assert sorted(os.listdir(tmp_path)) == ["held"] and os.listdir(tmp_path / "held") == ["values"]
