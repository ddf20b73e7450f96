"""The spec readers' fuzzer (tests/fuzz/fuzz_spec.py) as a test: its seed
corpus (one input per class of spec that once crashed the sweep or the
tuner) replayed, then a fixed number of mutants from a fixed seed. Any
exception but the spec's own refusal is a failure."""
import subprocess
import sys

from conftest import SOURCE

FUZZ = SOURCE / "tests" / "fuzz" / "fuzz_spec.py"
CORPUS = SOURCE / "tests" / "fuzz" / "corpus" / "fuzz_spec"


def fuzz(*args):
    return subprocess.run([sys.executable, str(FUZZ), *map(str, args)], capture_output=True, text=True, timeout=600)


def test_the_seed_corpus_is_refused_without_a_crash():
    files = sorted(CORPUS.iterdir())
    assert len(files) >= 8
    p = fuzz(*files)
    assert p.returncode == 0, p.stderr
    assert f"{len(files)} execs   0 crash" in p.stdout, p.stdout


def test_two_thousand_mutants_from_a_fixed_seed_crash_nothing(tmp_path):
    p = fuzz("--runs", 2000, "--seed", 1, "--corpus", tmp_path / "new", "--corpus", CORPUS,
             "--crashes", tmp_path / "crashes")
    assert p.returncode == 0, p.stderr
    assert "2000 execs   0 crash" in p.stdout, p.stdout
