"""The 19th black-box pass, the programs' side: no abbreviated flag gets past
a program's own refusals, the budget page's --check checks the options the
run would take, a stray file beside the pages stops no page, and an
allocation range narrower than the values it writes is refused."""
import os
import pathlib
import subprocess
import sys

import pytest

from test_budget_script import SPEC, checkout_with_spec, spatial_checkout_with_a_fake_sweep
from test_pass16_outputs import ALLOCATE, BASE, SWEEP, TUNE, line_of, tool, write_spec


@pytest.mark.parametrize("program,text", [("sweep", SWEEP), ("tune", TUNE), ("allocate", BASE + ALLOCATE)],
                         ids=["sweep", "tune", "allocate"])
def test_an_abbreviated_flag_is_refused_not_taken_for_another(tmp_path, program, text):
    # --ou was taken for --out, --che for --check: past the budget script's own refusal of --out
    spec = write_spec(tmp_path, text)
    p = subprocess.run([sys.executable, "-m", f"gimbalsim.{program}", str(spec), "--ou", str(tmp_path / "o")],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "--ou" in p.stderr, p.stderr
    assert not (tmp_path / "o").exists()


def test_the_page_script_refuses_what_the_sweep_would(tmp_path):
    # The shipped page's run, in a copy of what it touches, its spec a tiny one; the real sweep's refusals.
    root = checkout_with_spec(tmp_path, SPEC)
    env = dict(os.environ, GIMBALSIM_BUILD=str(pathlib.Path(os.environ["PYTHONPATH"]).parent))
    script = str(root / "tools/sweeps/run_pointing_budget.sh")
    for args in (["--ou", str(tmp_path / "x")], ["--che"], ["--check", "--bogus"], ["--check", "--workers", "0"]):
        p = subprocess.run(["bash", script, *args], capture_output=True, text=True, timeout=120, env=env)
        assert p.returncode == 2, (args, p.stderr)
        assert not (tmp_path / "x").exists() and not (root / "out").exists(), args


def test_a_stray_file_beside_the_pages_stops_no_page(tmp_path):
    # A Latin-1 notes.md stopped the index after the page was written (exit 4, the page changed),
    # a FIFO hung it for ever, a dangling link failed it.
    root, previous = spatial_checkout_with_a_fake_sweep(tmp_path)
    results = root / "docs/results"
    (results / "notes.md").write_bytes(b"caf\xe9 notes\n")
    os.mkfifo(results / "zz.md")
    (results / "gone.md").symlink_to(tmp_path / "nowhere")
    env = dict(os.environ, GIMBALSIM_BUILD=str(tmp_path / "fakebuild"), FAKE_SWEEP="whole")
    p = subprocess.run(["bash", str(root / "tools/sweeps/run_pointing_budget.sh"), "--spatial"],
                       capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 0, p.stderr
    for name in ("notes.md", "zz.md", "gone.md"):
        assert f"docs/results/{name} left out of the index" in p.stderr, (name, p.stderr)
    index = (results / "README.md").read_text()
    assert "](pointing_budget_spatial.md)" in index and "](pointing_budget.md)" in index, index


# The second's interior point rounded to 1.0e-4, below its low end, and was tried (pass 20).
@pytest.mark.parametrize("narrow", ["[1.0e-4, 1.0000000000000003e-4]", "[1.0000000000001e-4, 1.0000000000004e-4]"])
def test_an_allocation_range_narrower_than_its_written_values_is_refused(tmp_path, narrow):
    text = (BASE + ALLOCATE).replace("range: [1.0e-5, 3.0e-4]", f"range: {narrow}")
    assert text != BASE + ALLOCATE
    spec = write_spec(tmp_path, text)
    p = tool("allocate", spec, tmp_path / "out")
    assert p.returncode == 2, p.stderr
    assert f"{spec}:{line_of(text, 'range:')}:" in p.stderr and "too narrow" in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()
