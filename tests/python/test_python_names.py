"""Every Python file of the project (the package, the tools, these tests) names only what it defines or imports:
pyflakes over the tree, every finding but an import kept for its name (a module's API, a pytest fixture) fails.
A name a script uses only at the end of a long run (pass 46: budget_speed.py's results_page, whose import a change
had moved, would have ended a whole budget run in a NameError) is found here, not after the run."""
import subprocess
import sys

from conftest import SOURCE

KEPT = ("imported but unused", "redefinition of unused")  # re-exports (# noqa: F401) and imported fixtures


def test_no_undefined_name_and_no_syntax_error_in_any_python_file():
    try:
        import pyflakes  # noqa: F401  (python3-pyflakes, installed by tools/bootstrap.sh)
    except ImportError:
        raise AssertionError("pyflakes missing: run tools/bootstrap.sh (python3-pyflakes)") from None
    p = subprocess.run([sys.executable, "-m", "pyflakes", "python", "tools", "tests"], cwd=SOURCE,
                       capture_output=True, text=True, timeout=300)
    found = [line for line in (p.stdout + p.stderr).splitlines() if line.strip() and not any(k in line for k in KEPT)]
    assert not found, "\n".join(found)
