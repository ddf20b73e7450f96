"""gimbalsim.tune into a folder whose study.db cannot be made: one line,
exit 4, the system's reason, and advice that fits it ("free the space" only
where the file opens and its write failed), nothing left behind (pass 59: a
read-only file system ended in tracebacks and exit 1; a folder that refuses
new files was told to free the space)."""
import subprocess
import sys

import pytest

from test_tune_study import tune_cmd, write_spec


def _mount_ns_available():
    return subprocess.run(["unshare", "-m", "true"], capture_output=True).returncode == 0


@pytest.mark.skipif(not _mount_ns_available(), reason="needs a private mount namespace (unshare -m: root)")
def test_a_study_on_a_read_only_file_system_is_one_line_exit_4(tmp_path):
    spec = write_spec(tmp_path, 1)
    ro = tmp_path / "ro"
    (ro / "out").mkdir(parents=True)
    cmd = " ".join(f"'{c}'" for c in tune_cmd(spec, ro / "out"))
    p = subprocess.run(["unshare", "-m", "sh", "-c", f"mount --bind '{ro}' '{ro}' && "
                        f"mount -o remount,bind,ro '{ro}' && {cmd}"], capture_output=True, text=True, timeout=300)
    assert p.returncode == 4, p.stderr
    assert "Traceback" not in p.stderr, p.stderr
    last = p.stderr.splitlines(keepends=True)[-1]  # (after the line saying how the runs step)
    assert last == (f"tune: error: cannot write the study {ro / 'out' / 'study.db'}: (sqlite3.OperationalError) "
                        "unable to open database file (Read-only file system); fix the cause and run again "
                        "(nothing was kept)\n"), p.stderr
    assert list((ro / "out").iterdir()) == []


def test_a_folder_that_refuses_new_files_is_not_told_to_free_space(tmp_path):
    spec = write_spec(tmp_path, 1)
    p = subprocess.run(tune_cmd(spec, "/sys/kernel/mm"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 4, p.stderr
    last = p.stderr.splitlines(keepends=True)[-1]
    assert last.startswith("tune: error: cannot write the study /sys/kernel/mm/study.db: ") and \
        "Traceback" not in p.stderr and "free the space" not in p.stderr and "fix the cause and run again" in \
        last and "(Permission denied)" in last, p.stderr


if __name__ == "__main__":
    sys.exit(pytest.main([__file__]))
