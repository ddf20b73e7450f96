"""The README's examples, as a newcomer runs them right after its two
commands: each program or package they use is built by a command run before
it, every Python is Debian's /usr/bin/python3, and no output lands where
git would see it (a file in the checkout's root, say)."""
import os
import pathlib
import re
import shlex
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("GIMBALSIM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
OUTPUT_OPTIONS = ("--out", "--truth-csv", "--summary", "--log-csv", "--tick-log")


def commands(text):
    """Every command line of the text's sh blocks and inline code, in order
    (a backslash continues a line)."""
    out = []
    for block in re.findall(r"```sh\n(.*?)```", text, re.S):
        out += [c for c in block.replace("\\\n", " ").split("\n") if c.strip() and not c.startswith("#")]
    out += [c for c in re.findall(r"`([^`\n]+)`", re.sub(r"```.*?```", "", text, flags=re.S))
            if re.match(r"(PYTHONPATH=\S+ )?(/usr/bin/)?python3 |bash |build/bin/|cmake ", c)]
    return out


def examples(readme):
    return readme.split("## Examples", 1)[1].split("\n## ", 1)[0]


def built_by(script):
    """The CMake targets a script builds (its `cmake --build ... --target A B` lines)."""
    text = (SOURCE / script).read_text()
    return {t for line in re.findall(r"--target ([^\n]+)", text) for t in line.split() if re.fullmatch(r"\w+", t)}


def test_every_python_is_debians():
    for c in commands((SOURCE / "README.md").read_text()):
        for m in re.finditer(r"(\S*)python3\b", c):
            assert m.group(1) == "/usr/bin/", f"README: '{c}' runs {m.group(0)}, not /usr/bin/python3"


def test_every_output_is_ignored_by_git():
    if subprocess.run(["git", "-C", str(SOURCE), "rev-parse"], capture_output=True).returncode != 0:
        pytest.skip("not a git checkout")
    outputs = []
    for c in commands((SOURCE / "README.md").read_text()):
        words = shlex.split(c, comments=True)
        outputs += [words[i + 1] for i, w in enumerate(words[:-1]) if w in OUTPUT_OPTIONS]
    assert len(outputs) >= 4, outputs  # the rule finds the README's outputs
    for path in outputs:
        p = subprocess.run(["git", "-C", str(SOURCE), "check-ignore", "-q", "--no-index", path])
        assert p.returncode == 0, f"README writes {path}, which git does not ignore"


def code_in_order(text):
    """(kind, code) of the text in reading order: "sh" per line of an sh block,
    "python" per Python block, "inline" per inline code span."""
    fence = None
    for line in text.split("\n"):
        if line.startswith("```"):
            fence = line[3:] if fence is None else None
            if fence == "python":
                yield "python", ""
        elif fence == "sh":
            yield "sh", line
        elif fence is None:
            yield from (("inline", c) for c in re.findall(r"`([^`]+)`", line))


def test_each_example_uses_only_what_is_built_before_it():
    readme = (SOURCE / "README.md").read_text()
    built = built_by("tools/run_paper.sh")  # the main job, run first
    assert "gimbalsim" in built
    for kind, code in code_in_order(examples(readme)):
        for script in re.findall(r"bash (tools/\S+\.sh)", code):
            built |= built_by(script)
        for targets in re.findall(r"cmake --build build\S* -j2 --target ((?:\w+ ?)+)", code):
            built |= set(targets.split())
        for program in re.findall(r"build/bin/(\w+)", code):
            assert program in built, f"README example '{code.strip()}': nothing before it builds {program}"
        if kind == "python" or code.startswith("PYTHONPATH="):
            assert "gimbalsim_python" in built, f"README example '{code.strip()}': nothing before it builds the package"


def test_the_rules_above_catch_a_bad_readme(monkeypatch, tmp_path):
    (tmp_path / "tools").mkdir()
    (tmp_path / "tools" / "run_paper.sh").write_text("cmake --build x -j2 --target gimbalsim\n")
    (tmp_path / "README.md").write_text(
        "## Examples\n\n```sh\nbuild/bin/firmware_sim a.yaml --truth-csv truth.csv\npython3 -m x\n"
        "build/bin/gimbalsim simulate s --out out/a.csv --summary out/a.json --log-csv out/l.csv\n```\n")
    monkeypatch.setattr(__import__(__name__), "SOURCE", tmp_path)
    with pytest.raises(AssertionError, match="nothing before it builds firmware_sim"):
        test_each_example_uses_only_what_is_built_before_it()
    with pytest.raises(AssertionError, match="not /usr/bin/python3"):
        test_every_python_is_debians()
