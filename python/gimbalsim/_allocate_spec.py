"""An allocation spec: a closed-loop sweep spec plus its `allocate:` section,
checked whole at the spec's lines before anything runs, and the sweep spec of
each value tried (the spec's own text with `allocate:` left out and the key
given as a one-point grid, so every value sees the same draws of every other
key: dispersion.Design's common random numbers).

    allocate:
      key: contact.clearance        # one number key of the scene, or controller.<key>
      range: [2.0e-5, 2.0e-4]       # [the key's unit], lo < hi, both taken by the scene (or controller)
      direction: largest            # largest | smallest: the value sought
      index: ape                    # an index of the spec's indices: (default ape, knowledge)
      phase: track                  # a phase of the spec's phases:
      requirement: 1.0e-4           # [rad]
      level: 0.9973                 # optional (default 0.9973), in [0.5, 1)
      confidence: 0.95              # optional (default 0.95), in [0.5, 1)
      values: 8                     # the search's budget: sweeps run, in [3, 64]
      spacing: linear               # optional: linear | log (lo > 0)
"""
import json
import math
import re

import gimbalsim
from . import indices
from ._closed_spec import CONTROLLER_PREFIX, INDICES
from ._errors import SpecError
from ._spec import Spec
from ._allocate_search import scan_count, scan_values
from ._sweep_spec import NOT_READ, SweepSpec
from .dispersion import NUMERIC

KEYS = ("key", "range", "direction", "index", "phase", "requirement", "level", "confidence", "values", "spacing")
DIRECTIONS = ("largest", "smallest")
SPACINGS = ("linear", "log")
MIN_VALUES, MAX_VALUES = 3, 64  # three: two ends and one between, the fewest that can show a non-monotone index


def _bare(e):
    """A SpecError's message without its file:line: and key prefix."""
    where = f"{e.file}:{e.line}:{e.column}: " if e.file and e.line else (f"{e.file}: " if e.file else "")
    return str(e)[len(where) + (len(f"key '{e.key}': ") if e.key else 0):]


class AllocationSpec:
    """The checked allocation: ``key``, ``unit``, ``lo``, ``hi``, ``direction``,
    ``index``, ``phase``, ``requirement`` [rad], ``level``, ``confidence``,
    ``values`` (budget), ``log`` (spacing), ``is_int``; ``sweep_at(v)`` the
    sweep spec of one value; ``fingerprint`` what a resume must match."""

    def __init__(self, path):
        spec = Spec(path)
        self.path, self.text = spec.path, spec.source_text
        root = spec.root.value
        if "allocate" not in root:
            spec.refuse("allocate", "missing: an allocation spec is a closed-loop sweep spec with an allocate: "
                        "section (key, range, direction, index, phase, requirement, values)")
        if "controller" not in root:
            spec.refuse("allocate", "an allocation judges a closed loop's pointing index: name its controller "
                        "(controller: default or a configuration file)", root["allocate"])
        if "grid" in root:  # a grid would mix design points into the units judged at each value
            spec.refuse("grid", "an allocation's key is its own grid: give the other keys under parameters",
                        root["grid"])
        self._check_layout(spec, root)
        node = root["allocate"]
        body = spec.mapping("allocate", node)
        for k, n in body.items():
            if k not in KEYS:
                spec.refuse(f"allocate.{k}", f"unknown key (expected one of {', '.join(KEYS)})", n)
        for k in ("key", "range", "direction", "index", "phase", "values"):
            if k not in body:
                spec.refuse(f"allocate.{k}", "missing", node)
        self._read_key(spec, root, body)
        self.direction = spec.text("allocate.direction", body["direction"])
        if self.direction not in DIRECTIONS:
            spec.refuse("allocate.direction", f"expected {' or '.join(DIRECTIONS)}, got {self.direction!r}",
                        body["direction"])
        self.log = spec.text("allocate.spacing", body["spacing"]) == "log" if "spacing" in body else False
        if "spacing" in body and body["spacing"].value not in SPACINGS:
            spec.refuse("allocate.spacing", f"expected {' or '.join(SPACINGS)}, got {body['spacing'].value!r}",
                        body["spacing"])
        self._read_range(spec, body["range"])
        self.values = spec.integer("allocate.values", body["values"], MIN_VALUES, MAX_VALUES)
        # The values tried are written with 12 digits: a range narrower than that scans the same value twice.
        if not self.is_int and len(scan_values(self)) < scan_count(self.values):
            spec.refuse("allocate.range", f"[{self.lo!r}, {self.hi!r}] is too narrow for its "
                        f"{scan_count(self.values)} scan values, which repeat at 12 significant digits: give a "
                        "wider range", body["range"])
        self.index = spec.text("allocate.index", body["index"])
        if self.index not in INDICES:
            spec.refuse("allocate.index", f"unknown index (expected one of {', '.join(INDICES)})", body["index"])
        self.phase = spec.text("allocate.phase", body["phase"])
        # The sweep part, checked at every value the scan tries (both ends among them; its refusals name the
        # spec's own lines). A refusal of a value (the scene's or controller's range, a phase the run does not
        # reach) holds over an interval of the key: a value bisected between two accepted ones is accepted too.
        scanned = sorted(scan_values(self))
        self._refusals = {}  # value -> the sweep's refusal of it (None: accepted), each value checked once
        self._ends = [self.sweep_at(v, spec, body, scanned) for v in scanned]
        closed = self._ends[0].closed
        if self.index not in [ix.name for ix in closed.indices]:
            spec.refuse("allocate.index", f"'{self.index}' is not among the spec's indices "
                        f"({', '.join(ix.name for ix in closed.indices)}): name it under indices:", body["index"])
        if self.phase not in [p for p, _ in closed.phases]:
            spec.refuse("allocate.phase", f"'{self.phase}' is not among the spec's phases "
                        f"({', '.join(p for p, _ in closed.phases)})", body["phase"])
        self._read_question(spec, root, body, next(ix for ix in closed.indices if ix.name == self.index))
        need = indices.min_units(self.level, self.confidence)
        if self._ends[0].samples < need:
            spec.refuse("samples", f"{self._ends[0].samples} units cannot show {self.level:.4%} at "
                        f"{self.confidence:.0%} confidence even if every one meets the requirement: at least {need} "
                        "(indices.min_units)", root["samples"])
        sweep = json.loads(self._ends[0].fingerprint)
        sweep.pop("grid")
        self.fingerprint = json.dumps({"sweep": sweep, "allocate": self.plain()}, sort_keys=True)

    def _check_layout(self, spec, root):
        """Each top-level key on a line of its own at column 1: the sweep of a
        value leaves allocate: out by its lines, keeping every other line."""
        lines = sorted(n.line for n in root.values())
        if any(n.column != 1 for n in root.values()) or len(set(lines)) != len(lines):
            spec.refuse("allocate", "write the spec as a block mapping, each top-level key at the start of its own "
                        "line", root["allocate"])
        start = root["allocate"].line
        self._cut = (start, min([ln for ln in lines if ln > start], default=None))

    def _read_key(self, spec, root, body):
        node = body["key"]
        key = spec.text("allocate.key", node)
        aliases = gimbalsim.key_aliases()
        units = {k["key"]: (k["type"], k["unit"]) for k in gimbalsim.keys()}
        units.update({old: units[new] for old, new in aliases.items()})
        units.update({CONTROLLER_PREFIX + k["key"]: (k["type"], k["unit"]) for k in gimbalsim.controller_keys()})
        if key not in units:
            spec.refuse("allocate.key", "not a key of the scene (gimbalsim.keys()) nor controller.<a key of the "
                        "controller> (docs/controller_keys.md)", node)
        ktype, self.unit = units[key]
        if ktype not in NUMERIC:
            spec.refuse("allocate.key", f"{key} is {ktype}: an allocation searches a number key", node)
        self.key, self.is_int = key, ktype == "int"
        canonical = aliases.get(key, key)
        # Refused, not taken out: a budget's dispersion of the key silently dropped would change the question.
        for section in ("parameters", "set", "controller_set"):
            given = root[section].value if section in root and isinstance(root[section].value, dict) else {}
            for k, n in given.items():
                name = CONTROLLER_PREFIX + k if section == "controller_set" else k
                if aliases.get(name, name) == canonical:
                    spec.refuse("allocate.key", f"{key} is also given under {section}: (line {n.line}); the "
                                "allocation sets it to each value it tries: remove it there", node)

    def _read_range(self, spec, node):
        v = node.value
        ok = isinstance(v, list) and len(v) == 2 and all(
            isinstance(e.value, (int, float)) and not isinstance(e.value, bool) and math.isfinite(e.value) for e in v)
        if not ok:
            spec.refuse("allocate.range", f"expected [lo, hi], two finite numbers in {self.unit or '-'}, got "
                        f"{node.plain()!r}", node)
        lo, hi = (e.value for e in v)
        if not lo < hi:
            spec.refuse("allocate.range", f"[{lo!r}, {hi!r}] is {'empty' if lo == hi else 'reversed'}: give [lo, hi] "
                        "with lo < hi (direction: says which end is sought)", node)
        if self.is_int and not all(isinstance(e.value, int) for e in v):
            spec.refuse("allocate.range", f"{self.key} is a whole number: give whole ends", node)
        if self.log and not lo > 0:
            spec.refuse("allocate.range", f"spacing: log needs lo > 0, got {lo!r}", node)
        self.lo, self.hi = (int(lo), int(hi)) if self.is_int else (float(lo), float(hi))

    def _read_question(self, spec, root, body, given):
        """level, confidence and requirement: allocate's, else the index's own
        under indices:, else the defaults; both, they must agree (one question)."""
        index_node = root["indices"].value.get(self.index) if "indices" in root else None
        for k, default in (("level", indices.LEVEL_3SIGMA), ("confidence", 0.95), ("requirement", None)):
            value = getattr(given, k)
            here = body.get(k)
            there = index_node is not None and isinstance(index_node.value, dict) and k in index_node.value
            if here is not None:
                mine = (spec.number(f"allocate.{k}", here, 0.0, indices.MAX_REQUIREMENT_RAD, above=True)
                        if k == "requirement" else
                        spec.number(f"allocate.{k}", here, 0.5, 1 - 1e-9))  # indices' question: [0.5, 1)
                if there and mine != value:
                    spec.refuse(f"allocate.{k}", f"{mine!r} differs from indices.{self.index}.{k} {value!r} "
                                f"(line {index_node.value[k].line}): give it once", here)
                value = mine
            elif not there:
                value = default
            if value is None:
                spec.refuse("allocate.requirement", f"missing: the {self.index} bound [rad] the allocation must "
                            "meet", root["allocate"])
            setattr(self, k, float(value))

    def text_at(self, value):
        """The sweep spec's text at one value: the spec's lines with allocate:
        blanked (every other line where it was) and the key as a one-point grid."""
        lines = self.text.split("\n")
        start, end = self._cut
        for k in range(start - 1, (end - 1) if end else len(lines)):
            lines[k] = ""
        lines[start - 1] = "# allocate: left out; gimbalsim.allocate sets its key by the grid on the last line"
        body = "\n".join(lines)
        return body + ("" if body.endswith("\n") else "\n") + f"grid: {{{self.key}: [{self.value_text(value)}]}}\n"

    def value_text(self, value):
        return str(int(value)) if self.is_int else repr(float(value))

    def sweep_at(self, value, spec=None, body=None, scanned=()):
        """The SweepSpec of one value. A refusal of the value itself is named,
        when checking (body: the allocate: section), at the range's line (the
        scene's or controller's range, a phase its runs do not reach, a value
        the runs do not read where others of the scan are read) or the key's
        (a key the runs read at no value scanned), else as the sweep names it."""
        try:
            return SweepSpec(self.path, text=self.text_at(value))
        except SpecError as e:
            if spec is None:
                raise
            point = f"{self.key} = {self.value_text(value)}: "  # a grid point's own refusal names it already
            if not (e.key or "").startswith("grid."):
                # (pass 78) another key refused at this value alone (friction.v_a where friction.mu = 0) is this
                # value's refusal: named at the range, not as if the key acted at no value the scan tries
                others = [v for v in scanned if v != value]
                if not any(self._accepted(v) for v in others):
                    # (pass 79) the scan's other values are refused too: their refusal is the spec's problem
                    # (friction.v_a >= the scene's v_b), not this value's own (v_a idle where mu = 0)
                    e = next((x for x in map(self._refusal_at, others) if x is not None), e)
                    raise SpecError(self._at_this_value(_bare(e)), e.key, e.file, e.line, e.column) from None
                spec.refuse("allocate.range", f"{point}key '{e.key}': {self._at_this_value(_bare(e))} (the scan's "
                            "other values are accepted: give a range without this value)", body["range"])
            why = _bare(e)
            never_read = self._not_read(e, value) and not any(self._read_at(v) for v in scanned if v != value)
            where = "key" if never_read else "range"
            spec.refuse(f"allocate.{where}", why if why.startswith(point) else point + why, body[where])

    def _at_this_value(self, why):
        """A refusal of the sweep at one value, read in the scan's terms: that sweep gives the key one value,
        so its "for every value of KEY the study gives" is not the allocation's (the scan gives others)."""
        def without_key(m):
            rest = [k for k in m.group(1).split(", ") if k != self.key]
            return f", for every value of {', '.join(rest)} the study gives" if rest else ""
        return re.sub(r", for every value of ([^()]*?) the study gives", without_key, why)

    def _not_read(self, e, value):
        """Whether the sweep's refusal e of this value says its runs do not read the key there."""
        return _bare(e).removeprefix(f"{self.key} = {self.value_text(value)}: ").startswith(NOT_READ)

    def _refusal_at(self, value):
        """The sweep's refusal of this value, or None when it is accepted (checked once per value)."""
        if value not in self._refusals:
            try:
                SweepSpec(self.path, text=self.text_at(value))
                self._refusals[value] = None
            except SpecError as e:
                self._refusals[value] = e
        return self._refusals[value]

    def _accepted(self, value):
        """Whether the sweep of this value is accepted."""
        return self._refusal_at(value) is None

    def _read_at(self, value):
        """Whether the runs read the key at this value (a slew_start past the run's end is read at none)."""
        e = self._refusal_at(value)
        return e is None or not self._not_read(e, value)

    def plain(self):
        return {"key": self.key, "unit": self.unit, "range": [self.lo, self.hi], "direction": self.direction,
                "index": self.index, "phase": self.phase, "requirement_rad": self.requirement, "level": self.level,
                "confidence": self.confidence, "values": self.values, "spacing": "log" if self.log else "linear"}

    def input_files(self):
        return self._ends[0].input_files()
