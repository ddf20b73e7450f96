"""The package's exceptions. SceneError and SimulationStopped are raised by
the C++ core with their fields set; OutputError by the one writer (_output.py)."""
from ._output import OutputError  # noqa: F401 (one of the package's exceptions)


class SceneError(ValueError):
    """A scene (or controller configuration) was refused.

    ``problems`` lists every problem found, each a dict with ``text`` (the
    message as the command line prints it), ``key``, ``file``, ``line``,
    ``column`` (1-based; None when not a file position) and ``set_index``
    (1-based index among the overrides; None when not an override); a problem
    with an override also has ``source``, the label its text starts with
    (``overrides['key']``, or ``spec.yaml:LINE`` from a spec, which then fills
    ``file`` and ``line``).
    ``key``, ``file``, ``line`` and ``column`` are the first problem's.
    """

    def __init__(self, message, problems=()):
        super().__init__(message)
        self.problems = list(problems)
        first = self.problems[0] if self.problems else {}
        self.key = first.get("key")
        self.file = first.get("file")
        self.line = first.get("line")
        self.column = first.get("column")
        self.set_index = first.get("set_index")

    @property
    def keys(self):
        """Every key named by a problem, in order."""
        return [p["key"] for p in self.problems if p.get("key")]


class SimulationStopped(RuntimeError):
    """A step hit numerical trouble. ``key`` is the scene key of the limit
    (e.g. ``sim.max_substeps``; "" when no setting names it), ``status`` the
    step status in words, ``time`` [s] where it stopped. Simulator.run adds
    ``steps_done`` and ``outputs`` (the good rows)."""

    def __init__(self, message, key="", status="", time=float("nan")):
        super().__init__(message)
        self.key = key
        self.status = status
        self.time = time
