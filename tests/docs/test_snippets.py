"""Every snippet of the README and the docs that says which file of the
repository it shows (a fenced block right after a line naming the file in
backticks and ending with ':') is that file, byte for byte."""
import os
import pathlib
import re

SOURCE = pathlib.Path(os.environ.get("GIMBALSIM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


def documents():
    yield SOURCE / "README.md"
    yield from sorted((SOURCE / "docs").rglob("*.md"))
    for p in sorted(SOURCE.rglob("README.md")):
        rel = p.relative_to(SOURCE)
        if not any(part.startswith(("build", ".")) for part in rel.parts) and rel.parts[0] != "docs":
            if p != SOURCE / "README.md":
                yield p


def snippets_naming_a_file():
    """(document, line, path, block text) of each snippet that names a file."""
    for doc in documents():
        lines = doc.read_text().split("\n")
        i = 0
        while i < len(lines):
            if lines[i].startswith("```"):
                j = i - 1
                while j >= 0 and not lines[j].strip():
                    j -= 1
                intro = lines[j].rstrip() if j >= 0 else ""
                end = next(k for k in range(i + 1, len(lines)) if lines[k].startswith("```"))
                named = [p for p in re.findall(r"`([^`\s]+)`", intro) if (SOURCE / p).is_file()]
                if intro.endswith(":") and named:
                    yield doc.relative_to(SOURCE), i + 1, named[-1], "\n".join(lines[i + 1:end]) + "\n"
                i = end
            i += 1


def test_each_snippet_is_the_file_it_names():
    found = list(snippets_naming_a_file())
    assert found, "no snippet names a file: the rule above finds nothing to check"
    for doc, line, path, block in found:
        assert block == (SOURCE / path).read_text(), f"{doc}:{line}: the snippet differs from {path}"


def test_a_changed_snippet_is_caught(tmp_path, monkeypatch):
    """The check itself: a snippet one line off its file is reported."""
    global SOURCE
    (tmp_path / "docs").mkdir()
    (tmp_path / "spec.yaml").write_text("a: 1\nb: 2\n")
    (tmp_path / "README.md").write_text("The spec (`spec.yaml`):\n\n```yaml\na: 1\nb: 3\n```\n")
    monkeypatch.setattr(__import__(__name__), "SOURCE", tmp_path)
    found = list(snippets_naming_a_file())
    assert len(found) == 1 and found[0][3] != (tmp_path / "spec.yaml").read_text()
