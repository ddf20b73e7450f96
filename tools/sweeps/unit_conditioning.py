"""How well a closed-loop budget unit's figures are defined (for
budget_speed.py): the unit's fine run again with its journal started
NUDGE_M away (the initial eccentricity `initial.ecc` moved by +-NUDGE_M
along u1 and along u2: four runs), and how far each figure moves from the
fine run's. NUDGE_M is far below anything a bearing is built or measured
to, so a figure that moves beyond a tolerance under it is not defined to
that tolerance: where the loop meets a branch point (an impact that only
just happens, a stick that only just holds), two runs as close as two
roundings of one state take different branches, and no sampling can hold
that figure closer to a fine run's than the fine run holds to itself.

The spread found is a lower bound of how ill-defined a figure is (four
nudges need not find every branch), so a unit counts as ill-defined only
where a nudge moved its figure beyond the tolerance."""
import json
import math
from concurrent.futures import ProcessPoolExecutor

NUDGE_M = 1.0e-12  # [m] the journal centre's initial position, moved along u1 and u2
KEY = "initial.ecc"  # both journals' initial eccentricity (unless a scene gives a joint its own)


def _nudges(ecc):
    x, y = ecc
    return [[x + NUDGE_M, y], [x - NUDGE_M, y], [x, y + NUDGE_M], [x, y - NUDGE_M]]


_SPEC = {}  # one checked spec per worker process and path


def _nudged_figures(spec_path, unit, figure_keys):
    """[{figure key: value or NaN}] of unit's four nudged runs, or a reason
    (text) when the unit has no nudge to make."""
    import gimbalsim
    from gimbalsim._sample import run_one
    from gimbalsim._sweep_spec import SweepSpec
    spec = _SPEC.get(spec_path) or _SPEC.setdefault(spec_path, SweepSpec(spec_path))
    values = spec.design.draw(unit)
    if KEY in values:
        ecc = [float(v) for v in values[KEY]]
    else:
        try:
            ecc = [float(v) for v in json.loads(spec.base.values()[KEY])]
        except (KeyError, ValueError, TypeError):
            return f"the scene has no {KEY} to nudge"
    out = []
    for nudge in _nudges(ecc):
        try:
            r = run_one(spec.base, spec.closed, {**values, KEY: nudge})
        except gimbalsim.SceneError as e:
            r = {"status": "refused", "reason": str(e)}
        if str(r.get("status", "")).startswith("refused"):  # (an ideal joint has no journal to nudge)
            return f"{KEY} nudged by {NUDGE_M:g} m is refused: {r.get('reason', '')}"
        ok = r.get("status") == "ok"
        out.append({k: float(r[k]) if ok and r.get(k) is not None else math.nan for k in figure_keys})
    return out


def _distance(x, y):
    """|x - y|; 0 when neither has a figure, inf when one has."""
    if math.isfinite(x) and math.isfinite(y):
        return abs(x - y)
    return 0.0 if math.isfinite(x) == math.isfinite(y) else math.inf


def spreads(spec_path, units, figure_keys, fine_rows, workers):
    """{unit: {figure key: largest |nudged - fine| [rad]}} (inf where a
    nudged run or the fine run has no figure), or {unit: reason} where no
    nudge could be made. fine_rows: {unit: row of the fine run's
    results.csv}, whose columns are the figure keys with "_rad"."""
    units = sorted(units)
    # a few hundred runs at most, on this machine, for one page: a process pool, not a Dask cluster
    with ProcessPoolExecutor(max_workers=max(1, min(workers, len(units) or 1))) as pool:
        found = list(pool.map(_nudged_figures, [str(spec_path)] * len(units), units, [figure_keys] * len(units)))
    result = {}
    for unit, runs in zip(units, found):
        if isinstance(runs, str):
            result[unit] = runs
            continue
        row = fine_rows[unit]
        fine = {k: float(row[f"{k}_rad"]) if row["status"] == "ok" and row[f"{k}_rad"] not in ("", None) else math.nan
                for k in figure_keys}
        result[unit] = {k: max(_distance(r[k], fine[k]) for r in runs) for k in figure_keys}
    return result


def ill_defined(found, spread):
    """{index-phase key: the units beyond its tolerance whose fine figure
    moves beyond it too when nudged}; found: budget_speed.compare's records
    ({"key", "tol", "beyond"}), spread: spreads()."""
    return {c["key"]: [u for u in c["beyond"] if isinstance(spread.get(u), dict) and
                       spread[u].get(c["key"], 0.0) > c["tol"]] for c in found}
