"""gimbalsim from Python: scenes, whole runs, a simulator stepped call by
call, the project's pointing controller and its closed loop; numpy in and
out, the same numbers as the command line.

    import gimbalsim
    scene = gimbalsim.load_scene("tools/scenes/paper_clearance.yaml", {"sim.duration": 1.0})
    run = gimbalsim.simulate(scene)
    run.columns["ecc"]          # numpy array, one value per output row [m]
    run.to_csv("run.csv")       # the bytes `gimbalsim simulate` writes

Stepping, simulating and closed loops release the GIL: separate Simulators
run in parallel threads.
"""

import json
import numbers

import numpy as np

from . import _gimbalsim
from ._errors import SceneError, SimulationStopped
from ._gimbalsim import COLUMNS, Scene, Simulator, State

__version__ = _gimbalsim.__version__  # the one version string, also every program's --version

__all__ = [
    "COLUMNS", "Scene", "Simulator", "State", "Controller", "Run", "ClosedLoopRun",
    "SceneError", "SimulationStopped",
    "load_scene", "load_scene_text", "keys", "controller_keys", "simulate", "closed_loop",
    "format_value", "as_overrides",
]


def format_value(value, key="?"):
    """A Python value as the text `--set key=value` accepts: numbers in the
    shortest form that reads back exactly, strings as they are, lists (or
    numpy arrays) for vectors."""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        return repr(float(value))
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple, np.ndarray)):
        return "[" + ", ".join(format_value(v, key) for v in value) + "]"
    raise TypeError(f"override {key!r}: cannot use a {type(value).__name__} as a value")


def as_overrides(overrides):
    """A dict {key: value} (or an iterable of "key=value") as "key=value" strings, in order."""
    if overrides is None:
        return []
    if isinstance(overrides, dict):
        return [f"{k}={format_value(v, k)}" for k, v in overrides.items()]
    if isinstance(overrides, str):
        raise TypeError("overrides: give a dict {key: value} or a list of 'key=value' strings")
    return [str(o) for o in overrides]


def load_scene(path, overrides=None):
    """Loads and validates a scene file; overrides is a dict of scene keys to
    values, applied after the file (what `--set` accepts). Raises SceneError."""
    return _gimbalsim._load_scene(str(path), as_overrides(overrides))


def load_scene_text(yaml_text, origin="<text>", overrides=None):
    """The same from YAML text; `origin` names it in messages."""
    return _gimbalsim._load_scene_text(yaml_text, origin, as_overrides(overrides))


def _replace(self, overrides):
    """A new scene: this one's every value, then the overrides (dict or "key=value" list)."""
    return self._replaced(as_overrides(overrides))


Scene.replace = _replace


def keys():
    """Every scene key: dicts with key, type, unit, check, default, meaning."""
    return _gimbalsim._keys()


def controller_keys():
    """Every controller configuration key, as keys() lists scene keys."""
    return _gimbalsim._controller_keys()


class Run:
    """A whole run: ``rows`` (N, len(COLUMNS)), ``columns`` (dict of numpy
    arrays named as the CSV columns), ``summary`` (the summary JSON as a dict).
    A run stopped by numerical trouble holds the good rows; ``summary["status"]``
    is "failed" and ``summary["stop"]`` names the limit, as on the command line."""

    def __init__(self, rows, summary):
        self.rows = rows
        self.summary = summary
        self.columns = {name: rows[:, i] for i, name in enumerate(COLUMNS)}

    @property
    def ok(self):
        return self.summary["status"] == "ok"

    def to_csv(self, path):
        """Writes the CSV `gimbalsim simulate --out` writes for the same scene, byte for byte."""
        _gimbalsim._write_csv(str(path), self.rows)

    def __repr__(self):
        return f"<gimbalsim.Run {self.summary['name']!r} {self.summary['status']}: {len(self.rows)} rows>"


def simulate(scene, integrator="rk4"):
    """Runs the scene's constant torques for sim.duration (as `gimbalsim simulate`)."""
    rows, summary = _gimbalsim._simulate(scene, integrator)
    return Run(rows, json.loads(summary))


def Controller(config_path=None, overrides=None):
    """The project's pointing controller with the configuration at config_path
    (None: the built-in defaults) and overrides (dict of controller keys, as
    `pointing_controller --set`). Raises SceneError for a refused configuration."""
    return _gimbalsim.Controller("" if config_path is None else str(config_path), as_overrides(overrides))


class ClosedLoopRun:
    """A closed-loop run: ``summary`` (dict: ok, stop_key, errors, peaks) and
    ``columns`` (per control tick: t, references, true and measured angles,
    commanded and applied torques, truth pointing error [rad], ...)."""

    def __init__(self, summary, columns):
        self.summary = summary
        self.columns = columns

    @property
    def ok(self):
        return self.summary["ok"]

    def __repr__(self):
        return f"<gimbalsim.ClosedLoopRun ok={self.ok} ticks={self.summary['ticks']}>"


def closed_loop(scene, controller_config, duration, settle_tol=1.0e-3, faults=None):
    """The project's controller closed on the scene's plant in one process
    (firmware model + controller, as the bench in lockstep): the same numbers
    as the C++ in-process closed loop. controller_config is a Controller or a
    configuration file path; faults a fault schedule file (as firmware_sim
    --faults; its flags in columns["injected_faults"])."""
    ctrl = controller_config
    if not isinstance(ctrl, _gimbalsim.Controller):
        ctrl = Controller(controller_config)
    summary, columns = _gimbalsim._closed_loop(scene, ctrl, float(duration), float(settle_tol),
                                               "" if faults is None else str(faults))
    return ClosedLoopRun(summary, columns)
