#!/usr/bin/python3
"""Regenerates the key tables of the manual from the key registry:
docs/scene_keys.md from `gimbalsim keys --markdown` and
docs/controller_keys.md from `pointing_controller --keys --markdown`.

    /usr/bin/python3 tools/pages/gen_key_docs.py [BIN_DIR]     (default build/bin)

Only the table is replaced (from its header row to the first line that is not
a table row); the text around it stays. tests/base/key_registry_test.cpp fails
when a table differs from the registry.
"""
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
import output_file  # noqa: E402  (the package's one writer)
HEADER = "| key | type | unit | default | check | meaning |"
DOCS = [
    ("docs/scene_keys.md", ["gimbalsim", "keys", "--markdown"]),
    ("docs/controller_keys.md", ["pointing_controller", "--keys", "--markdown"]),
]


def replace_table(text, table):
    lines = text.splitlines(keepends=True)
    try:
        start = next(i for i, line in enumerate(lines) if line.rstrip("\n") == HEADER)
    except StopIteration:
        raise SystemExit(f"gen_key_docs.py: no line '{HEADER}' to replace")
    end = start
    while end < len(lines) and lines[end].startswith("|"):
        end += 1
    return "".join(lines[:start]) + table + "".join(lines[end:])


def main():
    bin_dir = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ROOT / "build" / "bin")
    for doc, cmd in DOCS:
        table = subprocess.run([str(bin_dir / cmd[0])] + cmd[1:], check=True, capture_output=True,
                               text=True).stdout
        path = ROOT / doc
        new = replace_table(path.read_text(), table)
        if new != path.read_text():
            output_file.write_text(path, new)  # the package's one writer (tools/pages/output_file.py)
            print(f"gen_key_docs.py: {doc} updated")
        else:
            print(f"gen_key_docs.py: {doc} unchanged")


if __name__ == "__main__":
    sys.exit(output_file.run_script("gen_key_docs", main))
