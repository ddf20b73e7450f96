"""Paths for the Python package's tests: the sources, the command-line
programs of the same build (GIMBALSIM_BIN), and helpers to run them."""
import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("GIMBALSIM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
BIN = pathlib.Path(os.environ.get("GIMBALSIM_BIN", SOURCE / "build" / "bin"))
SCENES = SOURCE / "tools" / "scenes"
CONTROLLER_CONFIG = SOURCE / "controllers" / "config" / "default.yaml"


def scene_path(name):
    return SCENES / f"{name}.yaml"


def run_cli(*args, check=True):
    """Runs build/bin/gimbalsim with args; returns the CompletedProcess."""
    p = subprocess.run([str(BIN / "gimbalsim"), *map(str, args)], capture_output=True, text=True, timeout=300)
    if check and p.returncode != 0:
        raise AssertionError(f"gimbalsim {' '.join(map(str, args))} exited {p.returncode}: {p.stderr}")
    return p


@pytest.fixture
def tmp(tmp_path):
    return tmp_path


def spec_of(tmp_path, text, name="spec.yaml"):
    """The sweep spec `text`, written to tmp_path/name and loaded."""
    from gimbalsim.sweep import SweepSpec
    (tmp_path / name).write_text(text)
    return SweepSpec(tmp_path / name)


def row_verdict(spec, row, **cells):
    """A resume's verdict (_journal.check_row) on a journal row with cells (CSV names) replaced."""
    from gimbalsim._journal import check_row
    header = spec.csv_header()
    row = list(row)
    for name, text in cells.items():
        row[header.index(name)] = text
    return check_row(spec, row, len(header))
