"""How well a closed-loop budget unit's figures are defined (for
budget_speed.py): the unit's fine run again with its journal started
NUDGE_M away (the initial eccentricity that places each journal, initial.ecc or
the joint's own initial.eccJ, moved by +-NUDGE_M along u1 and along u2:
four runs), and how far each figure moves from the
fine run's. NUDGE_M is far below anything a bearing is built or measured
to, so a figure that moves beyond a tolerance under it is not defined to
that tolerance: where the loop meets a branch point (an impact that only
just happens, a stick that only just holds), two runs as close as two
roundings of one state take different branches, and no sampling can hold
that figure closer to a fine run's than the fine run holds to itself.

The spread found is a lower bound of how ill-defined a figure is (four
nudges need not find every branch), so a unit counts as ill-defined only
where a nudge moved its figure beyond the tolerance.

A figure the nudges hold may still be one the fine run has not settled:
the same run at the fine sub-step divided by each of REFINE (the scene's
own law) moves it beyond the tolerance. Then the fine run is no reference
for that unit to the tolerance, and a distance from it says nothing of
the sampling under test (refined=... in spreads)."""
import functools
import json
import math
import sys
from concurrent.futures import ProcessPoolExecutor

NUDGE_M = 1.0e-12  # [m] the journal centre's initial position, moved along u1 and u2
# the fine run again at its sub-step divided by each: has it settled? Plain Coulomb's chatter makes a figure
# wander, not converge, as the sub-step shrinks (a budget unit's rpe_track: +2.0e-6 rad from 5 us at 1.25 us,
# +0.2e-6 at 0.3125 us): two close refinements can both land near the fine figure, so one goes much further
REFINE = (2, 4, 16)
DIRECTIONS = ((1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0))


def _keys_in_effect(values, scene):
    """The initial-eccentricity keys that place a journal: for each joint with
    a bearing, its own initial.eccJ when the sample or the scene gives it,
    else the shared initial.ecc (dynamics/scene/src/bearing_keys.cpp)."""
    from gimbalsim._idle_keys import _own_key  # the package's one naming of a joint's own key
    keys = []
    for j in (1, 2):
        if values.get(f"structure.joint{j}", scene.get(f"structure.joint{j}")) in (None, "ideal"):
            continue
        own = _own_key(j, "initial.ecc")
        key = own if own in values or own in scene else "initial.ecc"
        if key not in keys:
            keys.append(key)
    return keys


def _position(values, scene, key):
    return [float(v) for v in (values[key] if key in values else json.loads(scene[key]))]


_SPEC = {}  # one checked spec per worker process and path


def _runs(spec, values, figure_keys, overrides):
    """[{figure key: value or NaN}] of the unit's fine run again under each
    (label, {key: value}) of overrides, or a reason (text) naming the label
    of the first run refused."""
    import gimbalsim
    from gimbalsim._sample import run_one
    out = []
    for label, keys in overrides:
        try:
            r = run_one(spec.base, spec.closed, {**values, **keys})
        except gimbalsim.SceneError as e:
            r = {"status": "refused", "reason": str(e)}
        if str(r.get("status", "")).startswith("refused"):
            return f"{label} is refused: {r.get('reason', '')}"
        ok = r.get("status") == "ok"
        out.append({k: float(r[k]) if ok and r.get(k) is not None else math.nan for k in figure_keys})
    return out


def _spec(spec_path):
    from gimbalsim._sweep_spec import SweepSpec
    return _SPEC.get(spec_path) or _SPEC.setdefault(spec_path, SweepSpec(spec_path))


def _nudged_figures(spec_path, unit, figure_keys):
    """The unit's four nudged runs (_runs), or a reason (text) when the
    unit has no nudge to make."""
    spec = _spec(spec_path)
    values, scene = spec.design.draw(unit), spec.base.values()
    keys = _keys_in_effect(values, scene)
    if not keys:
        return "both joints are ideal: no journal to nudge"
    try:
        start = {k: _position(values, scene, k) for k in keys}
    except (KeyError, ValueError, TypeError):
        return f"no initial position of {', '.join(keys)} to nudge"
    label = f"{', '.join(keys)} nudged by {NUDGE_M:g} m"
    return _runs(spec, values, figure_keys, [(label, {k: [x + dx * NUDGE_M, y + dy * NUDGE_M]
                                                      for k, (x, y) in start.items()}) for dx, dy in DIRECTIONS])


def _refined_figures(spec_path, unit, figure_keys, fine_substep):
    """The unit's fine run at fine_substep / k for each k of REFINE (_runs)."""
    spec = _spec(spec_path)
    return _runs(spec, spec.design.draw(unit), figure_keys,
                 [(f"the fine sub-step / {k}", {"sim.substep": fine_substep / k}) for k in REFINE])


def _distance(x, y):
    """|x - y|; NaN when neither has a figure (nothing compared), inf when one has."""
    if math.isfinite(x) and math.isfinite(y):
        return abs(x - y)
    return math.nan if math.isfinite(x) == math.isfinite(y) else math.inf


def spreads(spec_path, units, figure_keys, fine_rows, workers, refined=None):
    """{unit: {figure key: largest |nudged - fine| [rad]}} (inf where a
    nudged run or the fine run has no figure), or {unit: reason} where no
    nudge could be made. fine_rows: {unit: row of the fine run's
    results.csv}, whose columns are the figure keys with "_rad". refined:
    the fine sub-step [s]: the runs are the fine run's at it / REFINE
    instead of the nudged ones (has the fine run settled the figure?)."""
    units = sorted(units)
    probe = _nudged_figures if refined is None else functools.partial(_refined_figures, fine_substep=refined)
    # a few hundred runs at most, on this machine, for one page: a process pool, not a Dask cluster
    with ProcessPoolExecutor(max_workers=max(1, min(workers, len(units) or 1))) as pool:
        found = list(pool.map(probe, [str(spec_path)] * len(units), units, [figure_keys] * len(units)))
    result = {}
    for unit, runs in zip(units, found):
        if isinstance(runs, str):
            result[unit] = runs
            continue
        row = fine_rows[unit]
        fine = {k: float(row[f"{k}_rad"]) if row["status"] == "ok" and row[f"{k}_rad"] not in ("", None) else math.nan
                for k in figure_keys}
        # the largest move; NaN only when no nudged run nor the fine run has the figure
        result[unit] = {k: max((d for d in (_distance(r[k], fine[k]) for r in runs) if not math.isnan(d)),
                               default=math.nan) for k in figure_keys}
    return result


def classify(found, spread):
    """{index-phase key: (ill, held, unjudged)}: of the units beyond its
    tolerance, those whose fine figure moves beyond it too when nudged, those
    whose figure held under every nudge, and those no nudge could judge (no
    figure in any run, or no nudge made); found: budget_speed.compare's
    records ({"key", "tol", "beyond"}), spread: spreads()."""
    out = {}
    for c in found:
        moves = {u: spread[u].get(c["key"], math.nan) if isinstance(spread.get(u), dict) else math.nan
                 for u in c["beyond"]}
        out[c["key"]] = ([u for u, d in moves.items() if d > c["tol"]], [u for u, d in moves.items() if d <= c["tol"]],
                         [u for u, d in moves.items() if math.isnan(d)])
    return out


def verdict(claim, answer, named, skipped, reasons):
    """One verdict line of budget_speed's page: "claim: answer; label: a, b;
    ...; skipped: reason; reason.", each (label, items) of named and the
    reasons a probe was not made shown only when there are any."""
    parts = [answer] + [f"{label}: {', '.join(items)}" for label, items in named if items]
    if reasons:
        parts.append(f"{skipped}: {'; '.join(reasons)}")
    return f"{claim}: {'; '.join(parts)}."


if __name__ == "__main__":  # (pass 35) run as a script it took any arguments and did nothing, exit 0
    print("unit_conditioning.py: error: a module of tools/sweeps/budget_speed.py, not a program: run "
          "budget_speed.py, which nudges the units beyond its tolerance", file=sys.stderr)
    sys.exit(2)
