"""The Python API's checks of number arguments: what numpy or pybind11 would
take silently (a bool as 1, a text parsed, a complex's imaginary part
dropped) is a TypeError naming the argument."""
import numbers
import os

import numpy as np

from . import _gimbalsim


def real_array(values, name):
    """values as a float array, refusing what numpy would take silently:
    complex numbers (the imaginary part dropped), text ('1' parsed), bools
    and objects (TypeError naming the argument)."""
    a = np.asarray(values)
    if a.dtype.kind not in "iuf":
        raise TypeError(f"{name}: expected real numbers, got an array of {a.dtype} "
                        f"({'the imaginary part would be dropped' if a.dtype.kind == 'c' else 'not numbers'})")
    return a.astype(np.float64)


def real_number(value, name):
    """A real, finite-or-not number argument (a bool, a complex or a text is
    none: pybind11 raised a bare TypeError, or took True as 1)."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        value = value.item()  # np.array(0.5) is a number as np.float64(0.5) is
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name}: expected a real number, got {type(value).__name__} {value!r}")
    return float(value)


def real_list(values, name):
    """A 1-D sequence of real numbers as a list of floats (real_array's refusals; a number or a table is no list:
    ValueError naming the argument and its shape, where pybind11 dumped its signatures)."""
    a = real_array(values, name)
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a list of real numbers, got an array of shape {a.shape}")
    return a.tolist()


def flag_list(values, name):
    """A sequence of True/False as a list of bools: pybind11 took any number (1, 2.5) and None as a flag."""
    try:
        flags = list(values)
    except TypeError:  # a bare True or a 0-d array is no list of flags
        raise TypeError(f"{name}: expected a list of True/False, got {type(values).__name__} {values!r:.80}") from None
    for i, f in enumerate(flags):
        if not isinstance(f, (bool, np.bool_)):
            raise TypeError(f"{name}[{i}]: expected True or False, got {type(f).__name__} {f!r:.80}")
    return [bool(f) for f in flags]


def whole_number(value, name):
    """An int (numpy's too), not a bool or a float: pybind11 took True as 1 and refused 1.0 naming no argument."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: expected a whole number, got {type(value).__name__} {value!r:.80}")
    return int(value)


def real_argument(value, name, hi):
    """A number argument in (0, hi]: a bool, a string or NaN is no number of
    it ("3" ran, True ran for 1 s, a NaN band gave a settling time of 0)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name}: expected a number, got {type(value).__name__} {value!r}")
    if not 0.0 < float(value) <= hi:
        raise ValueError(f"{name} must be in (0, {hi:g}], got {float(value)!r}")
    return float(value)


def scene_argument(scene, who):
    """A Scene, or a TypeError saying how to get one (pybind11's own listed the binding's signatures)."""
    if not isinstance(scene, _gimbalsim.Scene):
        raise TypeError(f"{who}: scene must be a gimbalsim.Scene (gimbalsim.load_scene(path)), "
                        f"got {type(scene).__name__} {scene!r:.80}")
    return scene


def checked_sources(sources):
    """load_scene's sources: {key: a label, or (file, line) of a spec}; another entry is a TypeError naming its key
    (a line that is no whole number ended a refusal as int()'s bare "invalid literal")."""
    if sources is None:
        return {}
    if not isinstance(sources, dict):
        raise TypeError(f"sources: expected a dict {{key: label or (file, line)}}, got {type(sources).__name__}")
    for key, label in sources.items():
        if isinstance(label, str):
            continue
        if not (isinstance(label, tuple) and len(label) == 2 and isinstance(label[0], (str, os.PathLike))
                and isinstance(label[1], numbers.Integral) and not isinstance(label[1], (bool, np.bool_))):
            raise TypeError(f"sources[{key!r}]: a source is a label (a str) or a (file, line) pair, the line a whole "
                            f"number; got {type(label).__name__} {label!r:.80}")
    return sources
