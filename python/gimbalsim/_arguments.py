"""The Python API's checks of number arguments: what numpy or pybind11 would
take silently (a bool as 1, a text parsed, a complex's imaginary part
dropped) is a TypeError naming the argument."""
import numbers

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
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name}: expected a real number, got {type(value).__name__} {value!r}")
    return float(value)


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
