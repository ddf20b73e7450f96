"""A run's record, read-only: the arrays and the columns by name that Run and ClosedLoopRun hold, which to_csv
writes as the run (an edit in place, or a new array under a name, was written as what the run computed)."""
import numpy as np

from ._gimbalsim import COLUMNS


def frozen(values):
    """A read-only copy that stays so: its memory is a bytes object, which numpy cannot make writeable again (an
    array owning its data could be, and to_csv then wrote the edit as the run, pass 86)."""
    a = np.ascontiguousarray(values)
    return np.frombuffer(a.tobytes(), dtype=a.dtype).reshape(a.shape)


class Columns(dict):
    """A run's columns by name, read-only (a copy, dict(run.columns), is the user's to edit); a name of COLUMNS
    its scene does not write says so (a joint without clearance has no joint-1 columns, a joint that is not
    spatial no tilt)."""

    def _refuse(self, *args, **kwargs):
        raise TypeError("a run's columns are its record, read-only: edit a copy (dict(run.columns))")

    __setitem__ = __delitem__ = __ior__ = update = pop = popitem = clear = setdefault = _refuse

    def __reduce__(self):  # unpickled through the constructor, not the refused __setitem__
        return Columns, (dict(self),)

    def __missing__(self, name):
        if name in COLUMNS:
            raise KeyError(f"{name!r}: not a column of this run (its scene's joints have none; "
                           f"Scene.columns lists what it writes)")
        raise KeyError(name)
