#!/usr/bin/python3
"""Regenerates the key tables of the manual from the key registry:
docs/scene_keys.md from `gimbalsim keys --markdown` and
docs/controller_keys.md from `pointing_controller --keys --markdown`.

    /usr/bin/python3 tools/pages/gen_key_docs.py [BIN_DIR]     (default build/bin)

Only the table is replaced (from its header row to the first line that is not
a table row); the text around it stays. tests/base/key_registry_test.cpp fails
when a table differs from the registry.
"""
import argparse
import os
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
        raise output_file.Refused(f"no line '{HEADER}' to replace")
    end = start
    while end < len(lines) and lines[end].startswith("|"):
        end += 1
    return "".join(lines[:start]) + table + "".join(lines[end:])


def main():
    p = argparse.ArgumentParser(allow_abbrev=False, description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    p.add_argument("bin_dir", nargs="?", default=os.path.join(output_file.default_build(), "bin"),
                   help="the build's bin folder holding gimbalsim and pointing_controller (default: GIMBALSIM_BUILD's "
                        "bin/, else build/bin)")
    bin_dir = pathlib.Path(p.parse_args().bin_dir)
    updates = []  # every table read and checked before the first document is written: a refusal costs nothing
    for doc, cmd in DOCS:
        program = bin_dir / cmd[0]
        if not (program.is_file() and os.access(program, os.X_OK)):
            raise output_file.Refused(f"{program}: no such program (build it, or name the build's bin folder)")
        run = subprocess.run([str(program)] + cmd[1:], capture_output=True, text=True)
        if run.returncode != 0:
            raise output_file.Refused(f"{program} {' '.join(cmd[1:])} failed (exit {run.returncode}): "
                                      f"{run.stderr.strip()[-300:]}")
        table = run.stdout
        rows = table.splitlines()
        # the header, its rule and at least one key; every line a table row: an empty or foreign answer is no table
        if len(rows) < 3 or rows[0] != HEADER or not all(r.startswith("|") and r.endswith("|") for r in rows):
            raise output_file.Refused(f"{program} {' '.join(cmd[1:])} printed no key table (expected the header "
                                      f"'{HEADER}', its rule and one row per key)")
        path = ROOT / doc
        try:
            old = path.read_text(encoding="utf-8")
            updates.append((doc, path, old, replace_table(old, table)))
        except (OSError, UnicodeDecodeError, output_file.Refused) as e:  # a document it cannot regenerate: refused
            raise output_file.Refused(f"{doc}: {getattr(e, 'strerror', None) or e}") from None
    output_file.check_before_writing([path for _, path, old, new in updates if new != old])  # both, before either
    for doc, path, old, new in updates:
        if new != old:
            output_file.write_text(path, new)  # the package's one writer (tools/pages/output_file.py)
            print(f"gen_key_docs.py: {doc} updated")
        else:
            print(f"gen_key_docs.py: {doc} unchanged")


if __name__ == "__main__":
    sys.exit(output_file.run_script("gen_key_docs.py", main))
