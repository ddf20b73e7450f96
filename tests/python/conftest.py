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
