"""The Python side's one writer (python/gimbalsim/_output.py, the rules of
the C++ io::OutputFile) and its users (ClosedLoopRun.to_csv, the tools
through tools/pages/output_file.py; the sweep's files: test_sweep_journal.py),
the one mapping of exceptions to exit codes (_errors.py) against
program.hpp's Exit and docs/usage.md's table, and no import cycle inside
the package."""
import ast
import errno
import importlib.util
import itertools
import os
import re
import signal
import stat
import subprocess
import sys

import pytest

import gimbalsim
from gimbalsim import _errors, _output
from conftest import SOURCE, scene_path

PACKAGE = SOURCE / "python" / "gimbalsim"


def leftovers(folder, keep):
    """Files in folder other than keep (a temporary left behind shows here)."""
    return sorted(p.name for p in folder.iterdir() if p.name not in keep)


# ---- the writer's rules ----

def test_a_whole_file_is_written_synced_and_renamed_with_the_umask_mode(tmp_path, monkeypatch):
    synced = []
    real_fsync = os.fsync

    def fsync(fd):
        synced.append(stat.S_ISDIR(os.fstat(fd).st_mode))
        real_fsync(fd)

    monkeypatch.setattr(os, "fsync", fsync)
    old = os.umask(0o022)
    try:
        _output.write_text(tmp_path / "a.txt", "text\n")
    finally:
        os.umask(old)
    assert (tmp_path / "a.txt").read_text() == "text\n"
    assert synced == [False, True], "the file, then its folder after the rename"
    assert stat.S_IMODE((tmp_path / "a.txt").stat().st_mode) == 0o644  # 0666 less the umask, not mkstemp's 0600
    assert leftovers(tmp_path, {"a.txt"}) == []


def test_a_symbolic_link_under_the_name_is_refused_and_its_target_untouched(tmp_path):
    target = tmp_path / "target.csv"
    target.write_text("keep\n")
    (tmp_path / "link.csv").symlink_to(target)
    with pytest.raises(_output.OutputError, match="link.csv: is a symbolic link; not written through"):
        _output.write_text(tmp_path / "link.csv", "new\n")
    assert target.read_text() == "keep\n" and (tmp_path / "link.csv").is_symlink()
    assert leftovers(tmp_path, {"target.csv", "link.csv"}) == []


@pytest.mark.parametrize("kind", ["folder", "fifo"])
def test_a_non_regular_file_under_the_name_is_refused(tmp_path, kind):
    path = tmp_path / "x"
    path.mkdir() if kind == "folder" else os.mkfifo(path)
    with pytest.raises(_output.OutputError, match="exists and is not a regular file"):
        _output.write_bytes(path, b"x")
    assert leftovers(tmp_path, {"x"}) == []


def test_an_output_that_is_an_input_is_refused_by_any_spelling(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text("keep\n")
    os.link(scene, tmp_path / "hard.yaml")
    for spelling in (scene, tmp_path / "." / "scene.yaml", tmp_path / "hard.yaml"):
        with pytest.raises(_output.OutputError, match="the same file as the input"):
            _output.write_text(spelling, "new\n", inputs=[scene])
    assert scene.read_text() == "keep\n"
    # a new file: its folder and name identify it, so two spellings of one new name are one output
    with pytest.raises(_output.OutputError, match="the same file as another output"):
        _output.check_outputs([tmp_path / "new.csv", tmp_path / "." / "new.csv"])
    _output.write_text(tmp_path / "other.yaml", "fine\n", inputs=[scene, None, ""])
    assert leftovers(tmp_path, {"scene.yaml", "hard.yaml", "other.yaml"}) == []


def test_the_running_program_is_an_input_of_every_run(tmp_path, monkeypatch):
    # (pass 84) a program's --out naming its own executable replaced it (exit 0); here the interpreter's script
    script = tmp_path / "mine.py"
    script.write_text("import sys\nfrom gimbalsim import _output\n"
                      "try:\n    _output.write_text(sys.argv[0], 'csv\\n')\nexcept _output.OutputError as e:\n"
                      "    print(e)\n")
    p = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=60)
    assert p.stdout == f"{script}: the same file as this program ({script}); not overwritten\n", (p.stdout, p.stderr)
    assert script.read_text().startswith("import sys")
    real = os.path.realpath(sys.executable)
    monkeypatch.setenv("PATH", "/nowhere")  # in a folder on PATH it is refused as an executable there first
    with pytest.raises(_output.OutputError, match=r"the same file as this program"):
        _output.check_outputs([real])
    monkeypatch.undo()
    # (pass 85) Run.to_csv wrote through the C++ writer, which sees the interpreter but not the script it runs
    scene = os.path.join(os.environ["GIMBALSIM_SOURCE_DIR"], "tools/scenes/planar_ideal.yaml")
    script.write_text("import sys, warnings, gimbalsim\nwarnings.simplefilter('ignore')\n"
                      f"run = gimbalsim.simulate(gimbalsim.load_scene({scene!r}, {{'sim.duration': 0.01}}))\n"
                      "try:\n    run.to_csv(sys.argv[0])\nexcept OSError as e:\n    print(e)\n")
    p = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=60)
    assert p.stdout == f"{script}: the same file as this program ({script}); not overwritten\n", (p.stdout, p.stderr)
    assert script.read_text().startswith("import sys")


def test_an_executable_file_in_a_folder_on_path_is_refused(tmp_path, monkeypatch):
    # (pass 103, 107) the scripts' lists of the programs they run by name always missed one (realpath, rmdir,
    # then replaced by a benchmark's JSON); the same file outside PATH, without an execute bit, or a new name: taken
    (tmp_path / "bin").mkdir()
    for name in ("bin/prog", "bin/data", "tool"):
        (tmp_path / name).write_text("#!/bin/sh\n")
    os.chmod(tmp_path / "bin/prog", 0o755)
    os.chmod(tmp_path / "tool", 0o755)
    monkeypatch.setenv("PATH", f"/nowhere::{tmp_path / 'bin'}/:/usr/bin")
    with pytest.raises(_output.OutputRefused, match=rf"bin/prog: an executable file in {tmp_path / 'bin'}/, a "
                                                   r"folder on PATH \(a program anything run by name may be\); "
                                                   r"not overwritten"):
        _output.write_text(tmp_path / "bin/prog", "x\n")
    assert (tmp_path / "bin/prog").read_text() == "#!/bin/sh\n"
    for taken in ("bin/data", "tool", "bin/new"):
        _output.write_text(tmp_path / taken, "x\n")
        assert (tmp_path / taken).read_text() == "x\n"
    # (pass 108) a link in a PATH folder makes a file elsewhere a program run by that name
    (tmp_path / "bin" / "link").symlink_to("../tool")
    os.chmod(tmp_path / "tool", 0o755)  # the writer's file has no execute bit
    with pytest.raises(_output.OutputRefused, match=rf"tool: an executable file run as {tmp_path / 'bin'}/link on "
                                                   "PATH"):
        _output.write_text(tmp_path / "tool", "y\n")
    assert (tmp_path / "tool").read_text() == "x\n"
    monkeypatch.chdir(tmp_path / "bin")  # an empty entry of PATH is the current folder
    with pytest.raises(_output.OutputRefused, match=r"prog: an executable file in \., a folder on PATH"):
        _output.write_text("prog", "x\n")


def test_a_missing_folder_is_refused_not_made(tmp_path):
    with pytest.raises(_output.OutputError, match="its directory .* does not exist"):
        _output.write_text(tmp_path / "missing" / "a.txt", "x")
    assert not (tmp_path / "missing").exists()


@pytest.mark.parametrize("where", ["write", "fsync", "rename", "the caller"])
def test_a_failure_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch, where):
    path = tmp_path / "results.csv"
    path.write_text("the old file\n")

    def full(*a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    if where == "fsync":
        monkeypatch.setattr(os, "fsync", full)
    if where == "rename":
        monkeypatch.setattr(os, "replace", full)
    with pytest.raises(OSError) as e:
        with _output.open_output(path) as f:
            f.write("half of the new")
            if where == "write":
                full()
            if where == "the caller":
                raise OSError(errno.EIO, "the caller's own failure")
    assert isinstance(e.value, _output.OutputError)
    assert str(path) in str(e.value) and ("No space left" in str(e.value) or "caller" in str(e.value))
    assert path.read_text() == "the old file\n"
    assert leftovers(tmp_path, {"results.csv"}) == []


def test_an_exception_in_the_body_goes_on_and_removes_the_temporary(tmp_path):
    with pytest.raises(KeyError):
        with _output.open_output(tmp_path / "a.bin", "wb") as f:
            f.write(b"x")
            raise KeyError("not an output problem")
    assert leftovers(tmp_path, set()) == []


def test_planted_links_at_temporary_names_are_never_written_through(tmp_path, monkeypatch):
    victim = tmp_path / "victim"
    victim.write_text("keep\n")
    monkeypatch.setattr(_output, "_counter", itertools.count(0))
    planted = [f".out.csv.{os.getpid()}.{n}.tmp" for n in range(3)] + ["out.csv.tmp", ".out.csv.tmp"]
    for name in planted:
        (tmp_path / name).symlink_to(victim)
    _output.write_csv(tmp_path / "out.csv", [["t_s", "x_m"], ["0", "1.5"]])
    assert (tmp_path / "out.csv").read_bytes() == b"t_s,x_m\n0,1.5\n"
    assert not (tmp_path / "out.csv").is_symlink() and victim.read_text() == "keep\n"
    assert leftovers(tmp_path, {"victim", "out.csv", *planted}) == []


def test_savefig_writes_the_format_of_the_extension_through_the_temporary(tmp_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 0])
    _output.savefig(fig, tmp_path / "a.png", dpi=50)
    _output.savefig(fig, tmp_path / "a.svg")
    plt.close(fig)
    assert (tmp_path / "a.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert b"<svg" in (tmp_path / "a.svg").read_bytes()[:400]
    assert leftovers(tmp_path, {"a.png", "a.svg"}) == []


def test_savefig_close_closes_the_figure_written_or_not(tmp_path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    kept, closed, failed = plt.figure(), plt.figure(), plt.figure()
    _output.savefig(kept, tmp_path / "kept.png")
    _output.savefig(closed, tmp_path / "closed.png", close=True)
    with pytest.raises(_output.OutputError, match="does not exist"):
        _output.savefig(failed, tmp_path / "missing" / "failed.png", close=True)
    assert plt.fignum_exists(kept.number)
    assert not plt.fignum_exists(closed.number) and not plt.fignum_exists(failed.number)
    plt.close(kept)
    assert leftovers(tmp_path, {"kept.png", "closed.png"}) == []


def test_the_append_log_refuses_a_link_and_appends_synced(tmp_path):
    target = tmp_path / "target"
    target.write_text("keep\n")
    (tmp_path / "journal").symlink_to(target)
    with pytest.raises(_output.OutputError, match="symbolic link"):
        _output.open_append(tmp_path / "journal")
    (tmp_path / "journal").unlink()
    (tmp_path / "journal").write_text("header\n")
    fd = _output.open_append(tmp_path / "journal")
    try:
        _output.append_synced(fd, b"row\n", tmp_path / "journal")
    finally:
        os.close(fd)
    assert (tmp_path / "journal").read_text() == "header\nrow\n" and target.read_text() == "keep\n"


# ---- its users ----

def closed_run():
    return gimbalsim.closed_loop(gimbalsim.load_scene(scene_path("paper_ideal")), gimbalsim.Controller(None), 0.02)


def test_closed_loop_to_csv_goes_through_the_writer(tmp_path):
    run = closed_run()
    victim = tmp_path / "victim"
    victim.write_text("keep\n")
    (tmp_path / "ticks.csv.tmp").symlink_to(victim)  # the old fixed temporary name
    run.to_csv(tmp_path / "ticks.csv")
    assert victim.read_text() == "keep\n" and not (tmp_path / "ticks.csv").is_symlink()
    assert (tmp_path / "ticks.csv").read_text().count("\n") == len(run.columns["t"]) + 1
    # the run's inputs are refused by any spelling, and a link under the name
    scene = tmp_path / "scene.yaml"
    scene.write_text("keep\n")
    with pytest.raises(gimbalsim.OutputError, match="the same file as the input"):
        run.to_csv(tmp_path / "." / "scene.yaml", inputs=[scene])
    (tmp_path / "link.csv").symlink_to(victim)
    with pytest.raises(OSError, match="symbolic link"):
        run.to_csv(tmp_path / "link.csv")
    assert scene.read_text() == "keep\n" and victim.read_text() == "keep\n"
    assert leftovers(tmp_path, {"victim", "ticks.csv.tmp", "ticks.csv", "scene.yaml", "link.csv"}) == []


def test_the_tools_write_through_the_packages_writer(tmp_path, monkeypatch):
    """tools/pages/output_file.py is the package's writer loaded from the source
    tree (the same file), not a second one: it syncs, and refuses links."""
    spec = importlib.util.spec_from_file_location("tools_output_file", SOURCE / "tools" / "pages" / "output_file.py")
    tools_writer = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tools_writer)
    assert os.path.samefile(tools_writer._writer.__file__, PACKAGE / "_output.py")
    assert tools_writer.OutputError is tools_writer._writer.OutputError  # its writes are the package writer's
    synced = []
    real_fsync = os.fsync
    monkeypatch.setattr(os, "fsync", lambda fd: (synced.append(fd), real_fsync(fd)))
    tools_writer.write_text(tmp_path / "page.md", "page\n")
    assert (tmp_path / "page.md").read_text() == "page\n" and len(synced) == 2
    (tmp_path / "link.md").symlink_to(tmp_path / "page.md")
    with pytest.raises(OSError, match="symbolic link"):
        tools_writer.write_text(tmp_path / "link.md", "x")
    assert (tmp_path / "page.md").read_text() == "page\n"


def test_no_script_in_tools_or_module_in_the_package_writes_around_the_writer():
    """Every write of python/gimbalsim/ and tools/ goes through _output.py:
    no open(..., "w"/"a"/"x"), write_text/write_bytes of pathlib, savefig on
    a figure, json.dump to a file or os.replace outside it."""
    pattern = re.compile(r"""\bopen\([^)]*["'][wax]b?["']|(?<!output_file)(?<!_output)\.write_(text|bytes)\(|"""
                         r"""\bfig\.savefig\(|"""
                         r"""\bjson\.dump\(|\bos\.replace\(|\.tmp["']""")
    writers = {PACKAGE / "_output.py"}
    found = []
    for path in sorted(PACKAGE.glob("*.py")) + sorted((SOURCE / "tools").rglob("*.py")):
        if path in writers:
            continue
        for k, line in enumerate(path.read_text().splitlines(), 1):
            if pattern.search(line) and not line.lstrip().startswith("#"):
                found.append(f"{path.relative_to(SOURCE)}:{k}: {line.strip()}")
    assert found == []


# ---- one exit-code table ----

def cpp_exit_codes():
    text = (SOURCE / "base/program/include/gimbalsim/program/program.hpp").read_text()
    body = text[text.index("enum Exit"):]
    body = body[:body.index("};")]
    return {name: int(v) for name, v in re.findall(r"\b(k\w+)\s*=\s*(\d+)", body)}


def documented_exit_codes():
    text = (SOURCE / "docs/usage.md").read_text()
    table = text[text.index("## Exit codes"):text.index("## Input")]
    return {int(c) for c in re.findall(r"^\| (\d+) \|", table, re.M)}


def test_the_python_codes_are_the_cpp_table_and_the_documented_one():
    cpp = cpp_exit_codes()
    assert set(cpp.values()) == documented_exit_codes()
    python = {"kOk": _errors.EXIT_OK, "kInternal": _errors.EXIT_INTERNAL, "kRefused": _errors.EXIT_REFUSED,
              "kStopped": _errors.EXIT_STOPPED, "kOutput": _errors.EXIT_OUTPUT,
              "kNoPeer": _errors.EXIT_NO_PEER, "kNotReproduced": _errors.EXIT_NOT_REPRODUCED}
    assert {k: cpp.get(k) for k in python} == python
    assert _errors.EXIT_NOT_REPRODUCED not in (_errors.EXIT_INTERNAL, _errors.EXIT_REFUSED, _errors.EXIT_STOPPED,
                                               _errors.EXIT_OUTPUT)


def test_one_mapping_from_exceptions_to_exit_codes(capsys):
    from gimbalsim._cluster import Interrupted
    from gimbalsim._spec import SpecError

    cases = [(SpecError("bad", key="samples"), 2), (gimbalsim.SceneError("refused"), 2),
             (gimbalsim.OutputError("x.csv: write failed"), 4), (_errors.NotReproduced("differs"), 8),
             (_errors.NoCluster("--scheduler tcp://h:1: no Dask scheduler answered"), 6),
             (Interrupted(signal.SIGINT), 130), (Interrupted(signal.SIGTERM), 143), (ValueError("a bug"), None)]
    assert [_errors.exit_code(e) for e, _ in cases] == [code for _, code in cases]

    def raising(e):
        def body():
            raise e
        return body

    assert _errors.guarded_main("prog", lambda: 0) == 0
    assert _errors.guarded_main("prog", raising(_errors.NotReproduced("sample 2 differs"))) == 8
    assert _errors.guarded_main("prog", raising(Interrupted(signal.SIGTERM)),
                                {Interrupted: lambda e: ": 3 kept"}) == 143
    assert capsys.readouterr().err.splitlines() == ["prog: error: sample 2 differs", "prog: interrupted (SIGTERM): 3 kept"]
    with pytest.raises(ValueError):  # a bug is not mapped: its traceback, exit 1
        _errors.guarded_main("prog", raising(ValueError("a bug")))


# ---- no import cycle ----

def package_imports():
    """{module: {package modules it imports, at any depth of its code}} from the sources."""
    modules = {p.stem for p in PACKAGE.glob("*.py")}
    graph = {}
    for path in PACKAGE.glob("*.py"):
        edges = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                if node.level == 1 and node.module:
                    edges.add(node.module.split(".")[0])
                elif node.level == 1:
                    edges.update(a.name for a in node.names if a.name in modules)
                elif node.module and node.module.split(".")[0] == "gimbalsim":
                    parts = node.module.split(".")
                    edges.add(parts[1] if len(parts) > 1 else "__init__")
                    if len(parts) == 1:
                        edges.update(a.name for a in node.names if a.name in modules)
            elif isinstance(node, ast.Import):
                for a in node.names:
                    parts = a.name.split(".")
                    if parts[0] == "gimbalsim":
                        edges.add(parts[1] if len(parts) > 1 else "__init__")
        graph[path.stem] = {m for m in edges if m in modules and m != path.stem}
    return graph


def cycles(graph):
    """Every import cycle found by a depth-first walk, as module lists."""
    found, state = [], {}

    def walk(m, stack):
        state[m] = "open"
        stack.append(m)
        for n in sorted(graph.get(m, ())):
            if state.get(n) == "open":
                found.append(stack[stack.index(n):] + [n])
            elif n not in state:
                walk(n, stack)
        stack.pop()
        state[m] = "done"

    for m in sorted(graph):
        if m not in state:
            walk(m, [])
    return found


def test_the_package_has_no_import_cycle():
    graph = package_imports()
    assert {"_journal", "_sample", "_sweep_spec"} <= graph["replay"]  # the scan sees function-level imports too
    assert "sweep" not in graph["replay"] and "tune" not in graph["replay"]
    assert cycles(graph) == []
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == [["a", "b", "c", "a"]]  # the check finds one


def test_an_output_set_holds_back_the_programs_stop_signals():
    # _output.py, loaded without the package, names the stop signals itself: the same set as the programs stop on
    from gimbalsim import _early_signals, _output
    assert _output._HELD == set(_early_signals.STOP_SIGNALS) == {signal.SIGINT, signal.SIGTERM, signal.SIGHUP}
