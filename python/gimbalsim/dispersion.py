"""Dispersed parameters: the distributions a spec gives for scene (or
controller) keys, and the draw of sample i, which depends only on (seed, i)
and the key: each key has its own random stream, PCG64 seeded by
SeedSequence(seed, spawn_key=(i, crc32(key))), so the draws are the same on
any machine, in any order, and adding a parameter does not change the others.

Distributions (the spec's syntax):
    key: {uniform: [lo, hi]}
    key: {loguniform: [lo, hi]}                       # 0 < lo <= hi
    key: {normal: {mean: m, sd: s, min: a, max: b}}   # truncated by redrawing; min, max optional: an end
                                                      # not given is mean -/+ TAIL_SD sd (NORMAL_TAIL)
    key: {choice: [v1, v2, ...]}                      # numbers, names or vectors
    key: {disk: {radius: r}}                          # vec2 keys: a point uniform in a disk
    key: {disk: {within: contact.clearance, fraction: 0.95}}   # radius = fraction x that key's value
                                                      # (a key in the disk key's unit: a clearance for an ecc)
    key: {ball: {radius: r}}                          # vec3 keys: a point uniform in a ball (a gyro bias)
"""
import json
import math
import zlib

import numpy as np

NUMERIC = ("number", "int")
# A normal never reaches beyond mean +/- TAIL_SD sd: there the two-sided tail holds 1e-6 of it (scipy
# norm.isf(0.5e-6) = 4.8916), a draw beyond is redrawn, and each end is tried on the scene before anything
# runs, as a range's ends are. Unbounded, a normal's draws reached any value, and a sweep whose scene refuses
# its far tail (a negative friction.mu, a negative clearance) ran those samples as refused and exited 0.
TAIL_SD = 4.8916
NORMAL_TAIL = "1e-6 two-sided tail"
DISTRIBUTIONS = ("uniform", "loguniform", "normal", "choice", "disk", "ball")
# An inertia's row cells, in the six-number spelling the scene takes: either spelling of a choice ([Ixx, Iyy, Izz]
# or six numbers) has one column per entry, so a row has as many cells as its header (pass 76: a choice of
# inertias wrote each as three cells under one column).
INERTIA_PARTS = ("xx", "yy", "zz", "xy", "xz", "yz")


class Parameter:
    """One dispersed key: ``key``, ``kind``, ``args``, and where the spec gave it."""

    def __init__(self, key, kind, args, key_type, node):
        self.key, self.kind, self.args, self.type, self.node = key, kind, args, key_type, node
        self.stream = zlib.crc32(key.encode())

    def columns(self):
        if self.type == "vec2":
            return [f"{self.key}[0]", f"{self.key}[1]"]
        if self.type == "vec3":
            return [f"{self.key}[0]", f"{self.key}[1]", f"{self.key}[2]"]
        if self.type == "inertia":
            return [f"{self.key}[{part}]" for part in INERTIA_PARTS]
        return [self.key]

    def row_values(self, value):
        if self.type == "inertia":
            return inertia6(value)
        return list(value) if isinstance(value, (list, tuple)) else [value]

    def draw(self, rng, context):
        a = self.args
        if self.kind == "uniform":
            x = float(rng.uniform(a[0], a[1]))
        elif self.kind == "loguniform":
            x = float(math.exp(rng.uniform(math.log(a[0]), math.log(a[1]))))
        elif self.kind == "normal":
            lo, hi = normal_ends(a)
            for _ in range(100_000):
                x = float(rng.normal(a["mean"], a["sd"]))
                if lo <= x <= hi:
                    break
            else:
                raise RuntimeError(f"{self.key}: no normal draw inside [min, max] in 100000 tries")
        elif self.kind == "choice":
            return a[int(rng.integers(len(a)))]
        elif self.kind == "ball":  # uniform in the ball: a uniform direction, radius R u^(1/3)
            d = rng.normal(size=3)
            d *= a["radius"] * rng.uniform() ** (1.0 / 3.0) / max(np.linalg.norm(d), 1e-300)
            return [float(v) for v in d]
        else:  # disk
            radius = a["radius"] if "radius" in a else a["fraction"] * float(context[a["within"]])
            r, phi = radius * math.sqrt(rng.uniform()), rng.uniform(0.0, 2.0 * math.pi)
            c = a.get("center", [0.0, 0.0])
            return [c[0] + r * math.cos(phi), c[1] + r * math.sin(phi)]
        return int(round(x)) if self.type == "int" else x

    def extremes(self):
        """Values at the ends of the range, to try on the scene before anything runs."""
        a = self.args
        if self.kind in ("uniform", "loguniform"):
            return list(a)
        if self.kind == "normal":  # the ends it draws between: min and max, or its tails (TAIL_SD); rounded as drawn
            return [int(round(v)) for v in normal_ends(a)] if self.type == "int" else list(normal_ends(a))
        if self.kind == "choice":
            return list(a)
        if self.kind == "ball":
            return [[a["radius"], 0.0, 0.0], [0.0, 0.0, -a["radius"]]]
        if "radius" in a:
            return self._rim(a["radius"])
        # a disk within a key: the rim its scene value gives (check_within); one it is dispersed with, trials() only
        return [t[self.key] for t in self.trials() if len(t) == 1]

    def spreads(self):
        """Whether two draws can differ: a range of width 0 (uniform [a, a], a
        disk or ball of radius 0, a choice of one value) draws one value, and
        one narrower than 1e-12 of its ends (pass 36: a double's step) draws
        roundings of one: no tolerance anyone builds to."""
        a = self.args
        if self.kind in ("uniform", "loguniform", "normal"):  # a normal by the ends it draws between (pass 38)
            lo, hi = normal_ends(a) if self.kind == "normal" else a
            return hi - lo > 1e-12 * max(abs(lo), abs(hi))
        if self.kind == "choice":  # numbers alike to 12 digits are one value (pass 37: two a double's step apart)
            return len({json.dumps(_to_12_digits(v), sort_keys=True) for v in a}) > 1
        if self.kind == "disk" and "within" in a:  # the radius each value of the within key gives (check_within)
            return any(r > 0 for _, r in getattr(self, "reach", ()))
        return a["radius"] > 0

    def end_note(self, value):
        """For a refusal of one of its ends: which end a normal's value is
        when it is a tail, not a min or max the spec gave ("" otherwise)."""
        a = self.args
        if self.kind != "normal" or float(value) in (a["min"], a["max"]):
            return ""
        side, sign = ("lower", "-") if value < a["mean"] else ("upper", "+")
        return (f"normal: its {side} tail, mean {sign} {TAIL_SD} sd = {value!r} (the {NORMAL_TAIL}: draws go no "
                f"further, and each end is tried on the scene; bound it with {'min' if sign == '-' else 'max'}): ")

    def _rim(self, radius):
        c = self.args.get("center", [0.0, 0.0])
        return [[c[0] + radius, c[1]], [c[0], c[1] - radius]]

    def trials(self):
        """The overrides to try on the scene before anything runs: each end
        alone, and a disk within a dispersed key at the rim each end of that
        key gives, with that value (a sample's scene holds both)."""
        if self.kind != "disk" or "radius" in self.args:
            return [{self.key: v} for v in self.extremes()]
        # a hair inside the rim: no draw reaches it (r = R sqrt(u), u < 1), and a clearance the scene derives as
        # R_i - R_j is rounded: a disk of fraction 1 within it would be refused for that last bit
        within = self.args["within"]
        return [{**({} if w is None else {within: w}), self.key: point}
                for w, r in getattr(self, "reach", ()) for point in self._rim(r * (1.0 - 1e-9))]


SCENE_KEYS = "a key of the scene (see gimbalsim.keys() or `gimbalsim keys`)"
CONTROLLER_KEYS = "a key of the controller configuration (see gimbalsim.controller_keys() or docs/controller_keys.md)"


def parse_parameter(spec, section, key, node, key_types, known_as=SCENE_KEYS):
    """A Parameter from `key: {distribution: args}` in spec section `section`;
    refuses (SpecError) an unknown key, distribution or argument. `known_as`
    says whose keys `key_types` lists, for the refusal of one that is not."""
    where = f"{section}.{key}"
    if key not in key_types:
        spec.refuse(where, f"not {known_as}", node)
    ktype = key_types[key]
    body = spec.mapping(where, node)
    if len(body) != 1:
        spec.refuse(where, f"give one distribution: {{{' | '.join(DISTRIBUTIONS)}: ...}}", node)
    kind, arg = next(iter(body.items()))
    if kind not in DISTRIBUTIONS:
        spec.refuse(where, f"unknown distribution '{kind}' (expected one of {', '.join(DISTRIBUTIONS)})", arg)
    plain = arg.plain()
    if kind in ("uniform", "loguniform", "normal") and ktype not in NUMERIC:
        spec.refuse(where, f"{kind} needs a number key; {key} is {ktype}", arg)
    if kind in ("uniform", "loguniform"):
        if not isinstance(plain, list) or len(plain) != 2:
            spec.refuse(where, f"{kind} expects [lo, hi], two finite numbers with lo <= hi, got {plain!r}", arg)
        for name, v in zip(("lo", "hi"), plain):  # (pass 41) a bound that is no number was said "not lo <= hi"
            if not _is_number(v):
                spec.refuse(where, f"{kind} expects [lo, hi], two finite numbers: {name} {_not_a_number(v)}", arg)
        if not plain[0] <= plain[1]:
            spec.refuse(where, f"{kind} expects [lo, hi] with lo <= hi, got [{plain[0]!r}, {plain[1]!r}]", arg)
        if kind == "loguniform" and not plain[0] > 0:
            spec.refuse(where, "loguniform expects 0 < lo", arg)
        args = [float(v) for v in plain]
    elif kind == "normal":
        if not isinstance(plain, dict) or set(plain) - {"mean", "sd", "min", "max"} or not {"mean", "sd"} <= set(plain):
            spec.refuse(where, "normal expects {mean: m, sd: s, min: a, max: b} (min, max optional)", arg)
        for name, v in plain.items():
            if not _is_number(v):
                spec.refuse(where, f"normal: mean, sd, min and max must be finite numbers: {name} {_not_a_number(v)}",
                            arg)
        args = {"mean": float(plain["mean"]), "sd": float(plain["sd"]),
                "min": float(plain.get("min", -math.inf)), "max": float(plain.get("max", math.inf))}
        if not args["sd"] > 0 or not args["min"] < args["max"]:
            spec.refuse(where, "normal needs sd > 0 and min < max", arg)
        lo, hi = normal_ends(args)
        if not lo < hi or not all(math.isfinite(v) for v in (lo, hi)):
            spec.refuse(where, f"normal: [min, max] lies beyond mean +/- {TAIL_SD} sd (the {NORMAL_TAIL}), or its "
                        "ends overflow: no draw inside", arg)
        lo, hi = (lo - args["mean"]) / args["sd"], (hi - args["mean"]) / args["sd"]
        if 0.5 * (math.erf(hi / math.sqrt(2)) - math.erf(lo / math.sqrt(2))) < 1e-3:
            spec.refuse(where, "normal: [min, max] holds less than 0.1 % of the distribution", arg)
    elif kind == "choice":
        if not isinstance(arg.value, list) or not arg.value:
            spec.refuse(where, "choice expects a non-empty list of values", arg)
        args = [spec.value(where, v) for v in arg.value]
        if ktype == "inertia":
            for v, v_node in zip(args, arg.value):
                if inertia6(v) is None:
                    spec.refuse(where, "choice: an inertia is [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz], "
                                f"got {v!r}", v_node)
    elif kind == "ball":
        if ktype != "vec3":
            spec.refuse(where, f"ball needs a vec3 key; {key} is {ktype}", arg)
        if not (isinstance(plain, dict) and set(plain) == {"radius"} and _is_number(plain["radius"])
                and plain["radius"] >= 0):
            spec.refuse(where, "ball expects {radius: r} with r >= 0", arg)
        args = plain
    else:
        if ktype != "vec2":
            spec.refuse(where, f"disk needs a vec2 key; {key} is {ktype}", arg)
        # fraction scales a within key only: beside a radius it would be read and never act
        if not isinstance(plain, dict) or not (set(plain) <= {"radius", "within", "fraction", "center"}) \
                or (("radius" in plain) == ("within" in plain)) or ("fraction" in plain and "radius" in plain):
            spec.refuse(where, "disk expects {radius: r} or {within: key, fraction: f} (center optional)", arg)
        if "radius" in plain and not (_is_number(plain["radius"]) and plain["radius"] >= 0):
            spec.refuse(where, "disk: radius must be a number >= 0", arg)
        if "within" in plain:
            if not isinstance(plain["within"], str) or key_types.get(plain["within"]) not in NUMERIC:
                spec.refuse(where, f"disk: within must name a number key, got {plain['within']!r}", arg)
            plain.setdefault("fraction", 1.0)
            if not (_is_number(plain["fraction"]) and 0 <= plain["fraction"] <= 1):
                spec.refuse(where, "disk: fraction must be in [0, 1]", arg)
        if "center" in plain and not (isinstance(plain["center"], list) and len(plain["center"]) == 2
                                      and all(_is_number(v) for v in plain["center"])):
            spec.refuse(where, "disk: center must be [x, y]", arg)
        args = plain
    return Parameter(key, kind, args, ktype, node)


def inertia6(v):
    """An inertia in any spelling the scene takes (three numbers, six, or the
    3x3 matrix a scene prints for a loaded one) as [Ixx, Iyy, Izz, Ixy, Ixz,
    Iyz]; None for a value that is no inertia (or a 3x3 that is not symmetric)."""
    if not isinstance(v, (list, tuple)):
        return None
    if len(v) == 3 and all(isinstance(row, (list, tuple)) and len(row) == 3 for row in v):
        m = [[float(x) if _is_number(x) else math.nan for x in row] for row in v]
        if any(m[r][c] != m[c][r] for r, c in ((0, 1), (0, 2), (1, 2))):
            return None
        return [m[0][0], m[1][1], m[2][2], m[0][1], m[0][2], m[1][2]]
    if len(v) not in (3, 6) or not all(_is_number(x) for x in v):
        return None
    return [float(x) for x in v] + [0.0] * (6 - len(v))


def _to_12_digits(v):
    """v with each number rounded to 12 significant digits (a choice's values compared for spread)."""
    if isinstance(v, list):
        return [_to_12_digits(x) for x in v]
    return float(f"{v:.12g}") + 0.0 if _is_number(v) else v  # + 0.0: -0.0 is 0.0 (pass 38: it drew as a spread)


def normal_ends(a):
    """(lo, hi) a normal {mean, sd, min, max} draws between: its min and max,
    each no further than TAIL_SD sd from the mean."""
    return max(a["min"], a["mean"] - TAIL_SD * a["sd"]), min(a["max"], a["mean"] + TAIL_SD * a["sd"])


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _not_a_number(v):
    """What a value that _is_number refuses is, for its refusal: "got inf (not finite)", "got '0x10' (not a
    number)", as the scene loader says it of a key's value."""
    if isinstance(v, float):
        return f"got {v} (not finite)"
    return f"got {v!r} (not a number)"


def design_size(grid, samples):
    """Samples in a design, counted without building it."""
    return samples * math.prod(len(values) for _, values in grid)


class Design:
    """The samples of a sweep: ``samples`` random draws of the parameters at
    each grid point (grid points in the spec's order, the first key slowest).
    Sample i is grid point i // samples with draw j = i % samples: every grid
    point sees the same draws (common random numbers). Grid points are
    computed from their index, never listed."""

    def __init__(self, parameters, grid, samples, seed, base_values):
        self.parameters = parameters          # [Parameter]
        self.grid_keys = [k for k, _ in grid]  # [(key, [values])]
        self.grid_values = [v for _, v in grid]
        self.samples, self.seed = samples, seed
        self.size = design_size(grid, samples)
        self.base_values = base_values        # scene values as text (for disk `within` of an undispersed key)

    def __len__(self):
        return self.size

    def extend_to(self, n):
        """The random draws 0..n-1 (--until grows a design so, a resume or a
        replay takes its extension back): sample i's values depend only on
        (seed, i), so extending never changes a drawn row. Not with a grid."""
        if self.grid_keys:
            raise ValueError("a design with a grid cannot grow")
        self.samples = self.size = n

    def grid_point(self, g):
        """Grid point g's values, the first key slowest (as itertools.product)."""
        point = []
        for values in reversed(self.grid_values):
            g, k = divmod(g, len(values))
            point.append(values[k])
        return point[::-1]

    def columns(self):
        cols = list(self.grid_keys)
        for p in self.parameters:
            cols += p.columns()
        return cols

    def draw(self, i):
        """Sample i's values: {key: value}, grid keys first, in spec order."""
        if not 0 <= i < len(self):
            raise IndexError(i)
        g, j = divmod(i, self.samples)
        values = dict(zip(self.grid_keys, self.grid_point(g)))
        context = {k: v for k, v in self.base_values.items()}
        context.update(values)
        # disks that take their radius from another key are drawn after it
        for p in sorted(self.parameters, key=lambda p: p.kind == "disk" and "within" in p.args):
            rng = np.random.Generator(np.random.PCG64(np.random.SeedSequence(self.seed, spawn_key=(j, p.stream))))
            values[p.key] = context[p.key] = p.draw(rng, context)
        return {k: values[k] for k in self.grid_keys + [p.key for p in self.parameters]}

    def row_values(self, values):
        out = [values[k] for k in self.grid_keys]
        for p in self.parameters:
            out += p.row_values(values[p.key])
        return out


def check_within(spec, section, parameters, grid_keys, base_values, grid=()):
    """A disk's `within` key must be in the disk key's unit (the radius is
    fraction x its value: an eccentricity's is a length, a clearance), and
    give a radius >= 0: its scene value when not dispersed (refused at the
    disk's line otherwise), else each end of its range or grid. Sets each
    such disk's reach [(that key's value, or None for the scene's, radius)],
    which extremes() and trials() put on the scene."""
    import gimbalsim
    from ._closed_spec import CONTROLLER_PREFIX
    units = {k["key"]: k["unit"] for k in gimbalsim.keys()}
    units.update({old: units[key] for old, key in gimbalsim.key_aliases().items()})
    units.update({CONTROLLER_PREFIX + k["key"]: k["unit"] for k in gimbalsim.controller_keys()})
    ends = {key: list(values) for key, values in grid}
    ends.update({p.key: p.extremes() for p in parameters if p.kind != "disk"})
    notes = {p.key: p for p in parameters if p.kind != "disk"}
    dispersed = set(grid_keys) | {p.key for p in parameters}
    for p in parameters:
        if p.kind != "disk" or "within" not in p.args:
            continue
        within, where = p.args["within"], f"{section}.{p.key}"
        if units.get(within) != units.get(p.key):
            spec.refuse(where, f"disk: within {within} is in {units.get(within) or '-'}, {p.key} in "
                        f"{units.get(p.key) or '-'}: the radius is fraction x {within}'s value, so it must be a key "
                        f"in {p.key}'s unit (an eccentricity's: a clearance, e.g. contact.clearance)", p.node)
        if within in dispersed:
            p.reach = []
            for w in ends.get(within, []):
                radius = p.args["fraction"] * float(w)
                note = notes[within].end_note(w) if within in notes else ""
                if not radius >= 0 and note:  # a normal's tail: refused at its own line, as the scene would
                    spec.refuse(f"{section}.{within}", f"{note}gives the disk of {p.key} (within {within}) "
                                "a radius < 0", notes[within].node)
                if not radius >= 0:
                    spec.refuse(where, f"disk: within {within}, which takes {w!r}: a radius < 0", p.node)
                p.reach.append((w, radius))
            continue
        try:
            radius = p.args["fraction"] * float(base_values[within])
        except (KeyError, ValueError):
            radius = math.nan
        if not radius >= 0:
            given = base_values.get(within)  # (pass 39) "(got None)": Python's word for a key the scene derives
            what = f"takes {given!r}, no number >= 0" if given is not None else \
                "is not one of the scene's own values (it derives it from other keys)"
            spec.refuse(where, f"disk: within {within} is not dispersed and {what}: disperse it or give radius",
                        p.node)
        p.reach = [(None, radius)]


if __name__ == "__main__":
    from gimbalsim._errors import not_a_program
    not_a_program("dispersion")
