"""--until INDEX:PHASE:RELWIDTH: a closed-loop sweep grows in batches of the
spec's `samples` until that index's confidence interval, relative to its
estimate, is at most RELWIDTH, or --max-samples. Sample i's values depend only
on (seed, i), so the rows do not depend on where the batches fell."""
import math

from . import _budget, _number
from ._spec import SpecError


class Until:
    def __init__(self, text, spec, max_samples):
        parts = text.split(":")
        if spec.closed is None:
            raise SpecError("--until needs a closed-loop sweep (a spec naming its controller)")
        if spec.grid:
            raise SpecError("--until grows the random draws: not with a grid (every grid point would move)")
        if len(parts) != 3:
            raise SpecError(f"--until {text!r}: expected INDEX:PHASE:RELWIDTH, e.g. ape:track:0.2")
        names = [ix.name for ix in spec.closed.indices]
        phases = [p for p, _ in spec.closed.phases]
        if parts[0] not in names:
            raise SpecError(f"--until {text!r}: index {parts[0]!r} is not one of the spec's ({', '.join(names)})")
        if parts[1] not in phases:
            raise SpecError(f"--until {text!r}: phase {parts[1]!r} is not one of the spec's ({', '.join(phases)})")
        # a plain decimal as written, as every number flag (' 0.1' and '1_0' are float()'s, not ours)
        self.width, why = _number.flag_decimal(parts[2])
        if not (self.width is not None and self.width > 0):  # inf would stop at once, "converged" to nothing
            raise SpecError(f"--until {text!r}: RELWIDTH must be a plain decimal number > 0 (e.g. 0.2 for 20 %)"
                            + (f": {why}" if why else ""))
        if max_samples < spec.samples:
            raise SpecError(f"--max-samples {max_samples} is below the spec's samples {spec.samples}")
        self.index = spec.closed.indices[names.index(parts[0])]
        self.phase, self.max_samples, self.text = parts[1], max_samples, text

    def check(self, spec, rows):
        """(stop?, a dict for the summary) after the rows so far."""
        e = _budget.entry(spec, rows, self.index, self.phase)
        width = _budget.relative_width(e)
        stopped = "width" if width <= self.width else ("cap" if len(rows) >= self.max_samples else None)
        out = {"until": self.text, "relative_width_target": self.width,
               "relative_width": width if math.isfinite(width) else None, "samples": len(rows),
               "max_samples": self.max_samples, "stopped_by": stopped}
        if not math.isfinite(width):  # no number over nothing: the reason instead (JSON has no Infinity)
            out["relative_width_note"] = (_open_end(e) if e["interval_rad"][1] is None
                                          else "the estimate is 0: a width relative to it has no value")
        return stopped is not None, out

    @staticmethod
    def width_text(u):
        """The relative width for the console: a number, or n/a with its reason."""
        w = u["relative_width"]
        return f"{w:.3g}" if w is not None else f"n/a ({u['relative_width_note']})"

    def grow(self, spec):
        """The design with one more batch of the spec's samples (capped)."""
        spec.design.extend_to(min(self.max_samples, len(spec.design) + spec.samples))


def _open_end(e):
    """Why an index's interval has no upper end: too few units for its level
    and confidence, for a two-sided interval, or too few with a figure (a unit
    without one is worst)."""
    if e["n_missing"] == e["n"]:  # (pass 38) said "too few units" where none had a figure
        return (f"the interval has no upper end: none of the {e['n']} units has a figure, and a unit without "
                "one counts as worst")
    if e["n"] < e["min_units"]:
        return (f"the interval has no upper end: {e['n']} units are too few for the {100 * e['level']:g} % level "
                f"at {100 * e['confidence']:g} % confidence (at least {e['min_units']})")
    if e.get("two_sided") is False:  # (pass 59) enough units for the bound, too few for a two-sided interval
        return (f"the interval has no upper end: {e['n']} units give only a one-sided bound at "
                f"{100 * e['confidence']:g} % confidence (the two-sided interval the width needs takes more)")
    return (f"the interval has no upper end: {e['n_missing']} of {e['n']} units have no figure, and a unit without "
            "one counts as worst")
