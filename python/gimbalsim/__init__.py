"""gimbalsim from Python: scenes, whole runs, a simulator stepped call by
call, the project's pointing controller and its closed loop; numpy in and
out, the same numbers as the command line.

    import gimbalsim
    scene = gimbalsim.load_scene("tools/scenes/paper_clearance.yaml", {"sim.duration": 1.0})
    run = gimbalsim.simulate(scene)
    run.columns["ecc2"]         # numpy array, one value per output row [m]
    run.to_csv("run.csv")       # the bytes `gimbalsim simulate` writes

Stepping, simulating and closed loops release the GIL: separate Simulators
run in parallel threads; calls on one Simulator run one after the other.
"""

from ._early_signals import report_early_signals

report_early_signals()  # `python3 -m gimbalsim.X` starting: a signal while the package imports says so

import functools  # noqa: E402
import json  # noqa: E402
import numbers  # noqa: E402
import os  # noqa: E402

import numpy as np  # noqa: E402

from ._errors import OutputError, SceneError, SimulationStopped  # noqa: E402

try:
    from . import _gimbalsim
except ImportError as e:  # a build folder whose extension was never built (only the programs were)
    _here = os.path.dirname(os.path.abspath(__file__))
    raise ImportError(
        f"gimbalsim: the extension module _gimbalsim is not built in {_here} ({e}); build it with "
        "`cmake --build build -j2 --target gimbalsim_python` (build/ being that build folder), "
        "or install the package (docs/python_install.md)") from e
from . import _csv_cells, _output  # noqa: E402
from ._arguments import checked_sources as _checked_sources, real_argument as _real_argument  # noqa: E402
from ._arguments import scene_argument as _scene_argument  # noqa: E402
from . import _checked_methods  # noqa: E402
from ._gimbalsim import COLUMNS, Scene, Simulator, State
from ._record import Columns as _Columns, frozen as _frozen  # noqa: E402
from ._scene_warnings import SceneWarning, warn_loaded as _warn_loaded  # noqa: E402
from ._spec import shown_text as _shown_text  # noqa: E402

_checked_methods.install()  # number arguments checked before the binding converts them
__version__ = _gimbalsim.__version__  # the one version string, also every program's --version

__all__ = [
    "COLUMNS", "Scene", "Simulator", "State", "Controller", "Run", "ClosedLoopRun",
    "SceneError", "SceneWarning", "SimulationStopped", "OutputError",
    "load_scene", "load_scene_text", "keys", "key_aliases", "controller_keys", "simulate", "closed_loop",
    "format_value", "as_overrides",
]


def format_value(value, key="?"):
    """A Python value as the text `--set key=value` accepts: numbers in the
    shortest form that reads back exactly, strings as they are, lists (or
    numpy arrays) for vectors."""
    if isinstance(value, np.ndarray) and value.ndim == 0:  # np.array(0.01) is a number, as np.float64 is
        return format_value(value.item(), key)
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
    return _overrides_and_labels(overrides)[0]


def _overrides_and_labels(overrides, sources=None):
    """The "key=value" strings and, for each, where it came from in messages:
    sources[key] (a label, or (file, line) of a spec), else "overrides['key']"
    for a dict entry and "overrides[i]" for a list item."""
    if overrides is None:
        return [], []
    sources = _checked_sources(sources)
    if isinstance(overrides, dict):
        texts = [f"{k}={format_value(v, k)}" for k, v in overrides.items()]
        return texts, [sources.get(k, f"overrides[{k!r}]") for k in overrides]
    if isinstance(overrides, str):
        raise TypeError("overrides: give a dict {key: value} or a list of 'key=value' strings")
    texts = [str(o) for o in overrides]
    return texts, [sources.get(t.split("=", 1)[0], f"overrides[{i}]") for i, t in enumerate(texts)]


def _relabelled(error, texts, labels):
    """SceneError `error` with each "--set #k 'text'" (the command line's place of an override) replaced by the
    override's own label: "overrides['key'] (text)" or "spec.yaml:LINE (text)", whose file and line then fill the
    problem's fields."""
    message = str(error)
    problems = []
    for p in error.problems:
        p = dict(p)
        k = p.get("set_index")
        if k and 0 < k <= len(labels):
            label = labels[k - 1]
            if isinstance(label, tuple):
                p["file"], p["line"] = str(label[0]), int(label[1])
                label = f"{label[0]}:{label[1]}"
            shown = _shown_text(texts[k - 1])  # as the C++ place shows it (pass 108: it was not relabelled)
            old, new = f"--set #{k} '{shown}'", f"{label} ({shown})"
            p["text"] = p["text"].replace(old, new, 1)
            p["source"] = label
            message = message.replace(old, new)
        problems.append(p)
    return SceneError(message, problems)


def _labelled_call(call, texts, labels):
    """call() with a refusal's override places relabelled."""
    try:
        return call()
    except SceneError as e:
        raise _relabelled(e, texts, labels) from None


def _check_path(path, what):
    """A path argument as str; one holding a NUL byte is refused (the C
    library would read the file named by the part before it)."""
    path = os.fspath(path)
    if isinstance(path, bytes):
        path = os.fsdecode(path)
    if "\0" in path:
        raise ValueError(f"{what} {path!r} holds a NUL byte: refused")
    return path


def _input_path(path, what):
    """A file to read, as _check_path; an empty one is refused too: the C++
    takes "" for "none" (Controller: the defaults, closed_loop: no faults),
    where the command line refuses `--faults ""` (exit 2)."""
    path = _check_path(path, what)
    if not path:
        raise ValueError(f"{what}: an empty path names no file (give None for none)")
    return path


def load_scene(path, overrides=None, sources=None):
    """Loads and validates a scene file; overrides is a dict of scene keys to
    values, applied after the file (what `--set` accepts). Raises SceneError;
    a problem with an override names it overrides['key'], or sources[key]
    when given (a label, or (file, line) of a spec's entry)."""
    path = _input_path(path, "scene path")
    texts, labels = _overrides_and_labels(overrides, sources)
    return _warn_loaded(_labelled_call(lambda: _gimbalsim._load_scene(path, texts), texts, labels), texts, labels)


def load_scene_text(yaml_text, origin="<text>", overrides=None, sources=None):
    """The same from YAML text; `origin` names it in messages."""
    texts, labels = _overrides_and_labels(overrides, sources)
    scene = _labelled_call(lambda: _gimbalsim._load_scene_text(yaml_text, origin, texts), texts, labels)
    return _warn_loaded(scene, texts, labels)


def _replace(self, overrides, sources=None):
    """A new scene: this one's every value, then the overrides (dict or
    "key=value" list; sources as for load_scene)."""
    texts, labels = _overrides_and_labels(overrides, sources)
    # _replaced lays the overrides after every value of this scene: their indices follow those
    try:
        scene = self._replaced(texts)
    except SceneError as e:
        base = [f"{k}={v}" for k, v in self.values().items()]
        raise _relabelled(e, base + texts, [f"{self.path}: {t.split('=', 1)[0]}" for t in base] + labels) from None
    return _warn_loaded(scene, texts, labels, said=len(self.values()))


def _scene_repr(self):
    differs = self._non_default()
    return (f"<gimbalsim.Scene {self.path!r} ({self.variant}): "
            + (f"differs from the defaults in {', '.join(differs)}>" if differs else "the defaults>"))


Scene.replace = _replace
Scene.__repr__ = _scene_repr


def keys():
    """Every scene key: dicts with key, type, unit, check, default, meaning."""
    return _gimbalsim._keys()


@functools.lru_cache(maxsize=None)
def _aliases():
    return dict(_gimbalsim._key_aliases())  # fixed for the build: read once (the sweep asks per row)


def key_aliases():
    """The scene keys' old spellings, still read: {old spelling: key}
    (friction1.mu: joint1.friction.mu; docs/scene_keys.md)."""
    return dict(_aliases())


def controller_keys():
    """Every controller configuration key, as keys() lists scene keys."""
    return _gimbalsim._controller_keys()


class Run:
    """A whole run: ``rows`` (N, len(COLUMNS)), ``columns`` (dict of numpy
    arrays named as its scene's ``Scene.columns``: the CSV columns without
    their unit suffix), ``summary`` (the summary JSON as a dict),
    ``scene`` (the Scene it ran). A run stopped by numerical trouble holds the
    good rows; ``summary["status"]`` is "failed" and ``summary["stop"]`` names
    the limit, as on the command line."""

    def __init__(self, rows, summary, scene=None):
        self.__setstate__({"_rows": rows, "summary": summary, "_scene": scene})

    def __setstate__(self, state):  # an unpickled run is read-only too (numpy unpickles a writeable array)
        state = {("_scene" if k == "scene" else k): v for k, v in state.items()}  # "scene": a pickle of before
        self.__dict__.update(state, _rows=_frozen(state["_rows"]))
        names = self.scene.columns if self.scene is not None else COLUMNS
        self._columns = _Columns({name: self._rows[:, COLUMNS.index(name)] for name in names})

    def __getstate__(self):
        return {k: v for k, v in self.__dict__.items() if k != "_columns"}

    # The run's record, read-only: an edit in place, or a new array under the name, was written by to_csv as the
    # run (passes 84, 86).
    rows = property(lambda self: self._rows, doc="the output rows, (N, len(COLUMNS)), read-only")
    columns = property(lambda self: self._columns, doc="the columns by name (views of rows), read-only")
    # to_csv never writes over the scene's file: another Scene (None) under the name let it (pass 90)
    scene = property(lambda self: self._scene, doc="the Scene it ran, read-only")

    @property
    def ok(self):
        return self.summary["status"] == "ok"

    def to_csv(self, path):
        """Writes the CSV `gimbalsim simulate --out` writes for the same scene,
        byte for byte, by the command line's output rules (OSError): its
        folder must exist; a link, a non-file or the run's scene file is refused."""
        inputs = [self.scene._file or self.scene.path] if self.scene is not None else []  # absolute: pass 92
        path = _check_path(path, "output path")
        _output.check_outputs([path], inputs)  # the script running too, which the C++ writer cannot see (pass 85)
        _gimbalsim._write_csv(path, self.rows, inputs, list(self.columns))

    def __repr__(self):
        scene = self.summary.get("scene") or (self.scene.path if self.scene is not None else "?")
        t_end = float(self.rows[-1, 0]) if len(self.rows) else 0.0
        stop = self.summary.get("stop") or {}
        why = f" ({stop.get('key') or stop.get('step_status')})" if not self.ok and stop else ""
        return (f"<gimbalsim.Run {self.summary.get('name', '')!r} of {scene!r}: {t_end:g} s, "
                f"{len(self.rows)} rows, {self.summary['status']}{why}>")


def simulate(scene, integrator="rk4"):
    """Runs the scene's constant torques for sim.duration (as `gimbalsim simulate`)."""
    if not isinstance(integrator, str):  # pybind11's own refusal lists signatures, not the choice
        raise TypeError(f"simulate: integrator must be 'rk4' or 'reference', got {type(integrator).__name__} "
                        f"{integrator!r}")
    rows, summary = _gimbalsim._simulate(_scene_argument(scene, "simulate"), integrator)
    return Run(rows, json.loads(summary), scene)


def _typed(text, key_type):
    """A value's --set text as the Python value of its key's type."""
    if key_type == "number":
        return float(text)
    if key_type == "int":
        return int(text)
    if key_type == "bool":
        return text == "true"
    if key_type.startswith("vec") or key_type == "inertia":
        return [float(x) for x in text.replace("[", " ").replace("]", " ").replace(",", " ").split()]
    return text


def _controller_values(self):
    """Every key with its value, typed as the key is (float, int, bool, str;
    a list of floats for a vector); Controller's overrides read them back exactly."""
    types = {k["key"]: k["type"] for k in _gimbalsim._controller_keys()}
    return {k: _typed(v, types.get(k, "string")) for k, v in self._values_text().items()}


_gimbalsim.Controller.values = _controller_values


def Controller(config_path=None, overrides=None, sources=None):
    """The project's pointing controller with the configuration at config_path (None: the built-in defaults,
    = controllers/config/default.yaml) and overrides (dict of controller keys, as `pointing_controller --set`;
    sources as for load_scene). Raises SceneError for a refused configuration."""
    path = "" if config_path is None else _input_path(config_path, "controller configuration path")
    texts, labels = _overrides_and_labels(overrides, sources)
    named = [f"{label[0]}:{label[1]}" if isinstance(label, tuple) else label for label in labels]  # closed_loop's
    return _labelled_call(lambda: _gimbalsim.Controller(path, texts, named), texts, labels)


def _unpickled(path, values, what):
    """A pickle's file name and values, refused when one holds a NUL byte (the name is an input of every output
    the object's runs write; a pickle is anyone's bytes)."""
    for i, v in enumerate(values):
        _check_path(v, f"the pickled {what}'s value #{i + 1}")
    return (_check_path(path, f"the pickled {what}'s file name") if path else path), values


def _unpickle_scene(path, values, file=""):
    """A pickled Scene: its values loaded again (checked as any scene); file: its absolute path (none before)."""
    return _gimbalsim._unpickle_scene(*_unpickled(path, values, "scene"), _check_path(file, "the pickled file"))


def _unpickle_controller(path, values, file=""):
    """A pickled Controller: its values loaded again (checked as any configuration)."""
    return _gimbalsim._unpickle_controller(*_unpickled(path, values, "controller"),
                                           _check_path(file, "the pickled file"))


# The closed loop's tick columns that are not angles [rad] (to_csv names them by unit).
_TICK_UNITS = {"t": "s", "tau1_cmd": "Nm", "tau2_cmd": "Nm", "tau1_applied": "Nm", "tau2_applied": "Nm",
               "star_outage": "", "segment": "", "injected_faults": ""}


class ClosedLoopRun:
    """A closed-loop run: ``summary`` (dict: ok, stop_key, errors, peaks; a
    figure over a window the run did not reach is NaN and ``reasons`` maps
    its name to why) and
    ``columns`` (per control tick: t, references, true and measured angles,
    commanded and applied torques, truth pointing error [rad], ...; the error
    as a vector: los_error_x/y/z, the rotation [rad, inertial] from the target
    line of sight to the true boresight, and los_error_est_x/y/z, to the
    boresight the controller's estimate and encoders give, with the play's
    offset its antenna tracker measured)."""

    def __init__(self, summary, columns, inputs=()):
        self.summary = summary
        self.__setstate__({"summary": summary, "_columns": columns, "_inputs": tuple(inputs)})

    def __setstate__(self, state):  # the run's record, read-only as Run's (an unpickled one too)
        state = {("_inputs" if k == "inputs" else k): v for k, v in state.items()}  # "inputs": a pickle of before
        self.__dict__.update(state, _columns=_Columns({k: _frozen(v) for k, v in state["_columns"].items()}),
                             _rows=None)

    def __getstate__(self):
        return {k: v for k, v in self.__dict__.items() if k != "_rows"}  # rows: stacked again on first use

    columns = property(lambda self: self._columns, doc="the ticks' columns by name, read-only")
    # the files the run read, which to_csv never writes over (emptied, they let it: pass 90)
    inputs = property(lambda self: self._inputs, doc="the run's scene, controller and fault files, read-only")

    @property
    def ok(self):
        return self.summary["ok"]

    @property
    def rows(self):
        """The ticks as an (N, columns) array, in the order of ``columns``
        (stacked once, on first use); read-only, as is the attribute (a cached_property took another, pass 87)."""
        if self._rows is None:
            self._rows = _frozen(np.column_stack([np.asarray(v, dtype=float) for v in self.columns.values()]))
        return self._rows

    def to_csv(self, path, inputs=()):
        """Writes the ticks by the project's CSV convention (docs/usage.md
        "CSV files": names with their unit, numbers that read back exactly,
        never -0) through the package's one writer (_output.py: whole or not
        at all, by the output rules): OutputError, an OSError, when it cannot
        (its folder must exist; a link, a non-file, a file the run read (its
        scene, controller and fault files) or one of inputs (a path or
        several) at path is refused)."""
        path = _check_path(path, "output path")
        if isinstance(inputs, (str, bytes, os.PathLike)):  # one path, not its characters
            inputs = (inputs,)
        inputs = self.inputs + tuple(_check_path(p, "input path") for p in inputs)
        names = [_gimbalsim.csv_name(n, _TICK_UNITS.get(n, "rad")) for n in self.columns]
        _output.write_csv(path, [names] + [[_csv_cells.csv_number(x) for x in row] for row in self.rows], inputs)

    def __repr__(self):
        return f"<gimbalsim.ClosedLoopRun ok={self.ok} ticks={self.summary['ticks']}>"



def closed_loop(scene, controller_config, duration, settle_tol=1.0e-3, faults=None, _study=False):
    """The project's controller closed on the scene's plant in one process
    (firmware model + controller, as the bench in lockstep): the same numbers
    as the C++ in-process closed loop. controller_config is a Controller or a
    configuration file path; faults a fault schedule file (as firmware_sim
    --faults; its flags in columns["injected_faults"]). An outage the scene sets
    that acts on nothing is refused (SceneError), as firmware_sim refuses it."""
    duration = _real_argument(duration, "duration [s]", 1e9)
    settle_tol = _real_argument(settle_tol, "settle_tol [rad]", 10.0)  # as controller_sweep --settle-tol
    ctrl = controller_config
    if not isinstance(ctrl, _gimbalsim.Controller):
        ctrl = Controller(controller_config)
    faults = "" if faults is None else _input_path(faults, "fault schedule path")
    summary, columns = _gimbalsim._closed_loop(_scene_argument(scene, "closed_loop"), ctrl, duration, settle_tol,
                                               faults, not _study)  # a study judged its units (python.md)
    # absolute, taken when each was loaded: relative, a chdir before to_csv let it write over them (pass 92)
    read = [p for p in (scene._file or scene.path, ctrl._file, faults and os.path.abspath(faults)) if p]
    return ClosedLoopRun(summary, columns, read)
