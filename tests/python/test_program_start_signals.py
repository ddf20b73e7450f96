"""A signal while a program of the package starts (`python3 -m gimbalsim.X`
importing numpy and the extension, most of a second) is one line and
128 + N, as later in the run: it was exit 143 with nothing said (pass 55).
A stand-in numpy that says it is being imported and then waits makes the
moment certain, not a matter of timing."""
import os
import signal
import subprocess
import sys
import time

import pytest

# Short sleeps, not one long one: a signal landing between the interpreter's last check and the
# sleep's system call does not wake that sleep (CI once waited out a sleep(60) so); the next check runs it.
FAKE_NUMPY = """
import pathlib, time
pathlib.Path({flag!r}).write_text("importing")
for _ in range(1200):
    time.sleep(0.05)
"""


# numpy, and json: the first module the package imported before its handler was in place (pass 56)
@pytest.mark.parametrize("stand_in", ["numpy", "json"])
@pytest.mark.parametrize("program", ["sweep", "tune", "allocate"])
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT, signal.SIGHUP])
def test_a_signal_while_importing_is_named_and_exits_128_plus_n(tmp_path, program, sig, stand_in):
    fake = tmp_path / "fake" / stand_in
    fake.mkdir(parents=True)
    flag = tmp_path / "flag"
    (fake / "__init__.py").write_text(FAKE_NUMPY.format(flag=str(flag)))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path / "fake"), *sys.path]))
    p = subprocess.Popen([sys.executable, "-m", f"gimbalsim.{program}", "spec.yaml", "--out", "o"], cwd=tmp_path,
                         env=env, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not flag.exists() and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    assert flag.exists(), p.communicate(timeout=5)[1] if p.poll() is not None else "numpy never imported"
    p.send_signal(sig)
    err = p.communicate(timeout=30)[1]
    name = signal.Signals(sig).name
    assert p.returncode == 128 + sig, (p.returncode, err)
    assert err == f"{program}: interrupted ({name}) while starting: nothing read or written\n", err
    assert sorted(os.listdir(tmp_path)) == ["fake", "flag"]  # no --out made
