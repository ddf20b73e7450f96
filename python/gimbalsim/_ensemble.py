"""Statistics over an ensemble of units (gimbalsim.indices' second half, public
there): the level-quantile of the units' figures with its distribution-free
order-statistics bounds, the number of units a question needs, and a
requirement's verdict. A unit without a figure counts as worst."""
from dataclasses import dataclass
import functools
import math
import numbers

import numpy as np
from scipy import stats

LEVEL_3SIGMA = 0.9973  # the budget's default level: "3 sigma" in ECSS tables
# [rad] no pointing error (the angle between two directions) exceeds pi: a larger requirement is met by every
# unit whatever it does, a PASS from no question (1e308 passed and drew a blank CDF, pass 70)
MAX_REQUIREMENT_RAD = math.pi


# --- ensemble statistics ---------------------------------------------------

def coverage(n, level, r, s):
    """Exact probability that [X_(r), X_(s)] (1-based order statistics of n
    independent units, X_(0) = -inf, X_(n+1) = +inf) contains the level-quantile:
    P(r <= Binomial(n, level) <= s - 1)."""
    if not _is_count(n):  # 10**30 failed inside numpy
        raise ValueError(f"coverage: need a whole n in [0, 1e12], got n={n!r}")
    level = _check_level("level", level)  # 0.3 gave a probability for no budget's question (pass 82)
    if not (_is_count(r, n + 1) and _is_count(s, n + 1) and r <= s):
        # r > s gave a negative probability, r = 1.5 a number for no order statistic
        raise ValueError(f"coverage: need ranks 0 <= r <= s <= n + 1, got r={r}, s={s}, n={n}")
    return float(stats.binom.cdf(s - 1, n, level) - stats.binom.cdf(r - 1, n, level))


@dataclass(frozen=True)
class QuantileBound:
    """The level-quantile of an ensemble with its distribution-free bounds."""
    n: int                 # units counted (a unit with no figure counts as worst)
    n_missing: int         # units whose figure is NaN (treated as +inf: unknown is not good)
    level: float           # the quantile's level, e.g. 0.9973
    confidence: float      # the bounds' confidence, e.g. 0.95
    estimate: float        # X_(ceil(n level)): the empirical quantile
    upper: float           # one-sided upper confidence bound X_(s), or NaN
    upper_rank: int        # s (1-based), or 0 when n cannot support the bound
    low: float             # two-sided interval [low, high], or NaN
    high: float
    supported: bool        # n is large enough for the one-sided bound at this confidence
    reason: str            # why a figure is NaN, or +inf (it falls on a unit without a figure)

    @property
    def min_units(self):
        """Fewest units for which even the worst one bounds the quantile."""
        return min_units(self.level, self.confidence)


def _is_number(x):
    return isinstance(x, numbers.Real) and not isinstance(x, (bool, np.bool_))


def _is_count(x, most=10**12):
    """A whole number in [0, most] (a bool is no count)."""
    return isinstance(x, numbers.Integral) and not isinstance(x, (bool, np.bool_)) and 0 <= x <= most


def _check_question(level, confidence):
    """A budget's question: a quantile at or above the median (ECSS: 68.27 %,
    95.45 %, 99.73 %) at a confidence at least even. Below, a level of 5e-324
    was a question of nothing, and two units could PASS it."""
    return _check_level("level", level), _check_level("confidence", confidence)


def _check_level(name, x):
    """A level or a confidence in [0.5, 1), as a float: a Fraction or a Decimal
    passed the check, then failed inside numpy (pass 56)."""
    if not (_is_number(x) and 0.5 <= x < 1.0):
        raise ValueError(f"{name} must lie in [0.5, 1), got {x!r} (level and confidence both)")
    return float(x)


def min_units(level, confidence):
    """Smallest n with P(max of n units >= the level-quantile) >= confidence:
    1 - level^n >= confidence."""
    level, confidence = _check_question(level, confidence)  # level 1 divided by 0, confidence 0 said 0 units
    return math.ceil(math.log(1.0 - confidence) / math.log(level))


@functools.lru_cache(maxsize=256)
def _ranks(n, level, confidence):
    """Order-statistic ranks (1-based) for n units: s, the one-sided upper
    bound's (smallest s with P(Bin(n, level) <= s - 1) >= confidence), and
    (r, s2) the equal-tailed two-sided interval's; a rank of n + 1 means
    "beyond the worst unit", r = 0 "below the best"."""
    cdf = stats.binom.cdf(np.arange(n + 1), n, level)  # cdf[k] = P(Bin <= k)
    s = int(np.searchsorted(cdf, confidence, side="left")) + 1
    tail = (1.0 - confidence) / 2.0
    r = int(np.searchsorted(cdf, tail, side="right"))  # largest r with P(Bin <= r - 1) <= tail
    s2 = int(np.searchsorted(cdf, 1.0 - tail, side="left")) + 1
    return s, r, s2


def _unit_figures(values):
    """The per-unit figures as a 1-D array: pointing errors are magnitudes,
    so a negative one is a caller's mistake (a signed error, not its norm)."""
    raw = np.asarray(values)
    if raw.size and raw.dtype.kind not in "iuf":  # '1' and True were read as figures
        raise ValueError(f"values: a figure per unit is a number [rad], got {raw.dtype} values")
    x = raw.astype(float)
    if x.ndim != 1:  # a 2-D array counted each of its cells as a unit
        raise ValueError(f"values: one figure per unit (1-D), got shape {x.shape}")
    negative = np.flatnonzero(x < 0.0)
    if len(negative):
        raise ValueError(f"values: a pointing error is a magnitude >= 0 rad; unit {negative[0]} has "
                         f"{x[negative[0]]!r} ({len(negative)} negative in all)")
    return x


def quantile_bound(values, level=LEVEL_3SIGMA, confidence=0.95):
    """The level-quantile of the per-unit values, with its order-statistics
    confidence bounds. NaN values count as +inf (a unit without a figure is
    never assumed good)."""
    level, confidence = _check_question(level, confidence)
    x = _unit_figures(values)
    n = len(x)
    missing = int(np.count_nonzero(~np.isfinite(x)))
    if missing == n:  # nothing seen: no quantile, however many units were drawn
        return QuantileBound(n, n, level, confidence, *([float("nan")] * 2), 0, float("nan"), float("nan"), False,
                             "no units" if n == 0 else f"no unit has a figure (all {n} without one)")
    xs = np.sort(np.where(np.isfinite(x), x, np.inf))
    estimate = float(xs[min(n, max(1, math.ceil(n * level))) - 1])
    s, r, s2 = _ranks(n, level, confidence)
    supported = s <= n
    upper = float(xs[s - 1]) if supported else float("nan")
    two_sided = r >= 1 and s2 <= n
    low = float(xs[r - 1]) if two_sided else float("nan")
    high = float(xs[s2 - 1]) if two_sided else float("nan")
    reason = ""
    if not supported:
        reason = (f"{n} units cannot bound the {level:.4%} quantile at {confidence:.0%} "
                  f"confidence (at least {min_units(level, confidence)} are needed)")
    elif not two_sided:
        reason = f"{n} units give only a one-sided bound at {confidence:.0%} confidence"
    worst = [name for name, v in (("estimate", estimate), ("upper bound", upper), ("interval's high end", high))
             if v == np.inf]  # an inf with no word read as a figure seen (pass 84)
    if worst:
        why = (f"the {' and the '.join(worst)} {'falls' if len(worst) == 1 else 'fall'} on the {missing} unit(s) "
               "without a finite figure, counted as worst (+inf)")
        reason = f"{reason}; {why}" if reason else why
    return QuantileBound(n, missing, level, confidence, estimate, upper, s if supported else 0,
                         low, high, supported, reason)


@dataclass(frozen=True)
class Verdict:
    """A requirement against an ensemble: PASS when, at the stated confidence,
    at least `level` of all units meet it."""
    requirement: float     # [rad]
    n: int
    n_meeting: int
    fraction: float        # n_meeting / n
    lower: float           # Clopper-Pearson lower bound of the fraction at `confidence` (NaN without a unit)
    level: float
    confidence: float
    passed: bool
    reason: str = ""       # why the ensemble cannot decide it (too few units, none): FAIL by default, never PASS
    note: str = ""         # said beside the verdict: every figure there is exactly 0 rad, so it answers nothing

    @property
    def text(self):
        return "PASS" if self.passed else "FAIL"


def requirement_verdict(values, requirement, level=LEVEL_3SIGMA, confidence=0.95):
    """PASS/FAIL of `requirement` [rad] with the probability that a unit meets it.
    NaN values count as not meeting it."""
    level, confidence = _check_question(level, confidence)  # a verdict at level 0 would be PASS for anything
    # NaN gave FAIL, inf PASS, and 0 (or -0) FAIL for every unit: no question a budget asks
    if not (_is_number(requirement) and math.isfinite(requirement) and 0.0 < requirement <= MAX_REQUIREMENT_RAD):
        raise ValueError(f"requirement must be an angle in (0, pi] rad, got {requirement!r}")
    requirement = float(requirement)
    x = _unit_figures(values)
    n = len(x)
    k = int(np.count_nonzero(np.isfinite(x) & (x <= requirement)))
    # (pass 78) no unit bounds no fraction: NaN with the reason below, not a bound of 0
    lower = float("nan") if n == 0 else 0.0 if k == 0 else float(stats.beta.ppf(1.0 - confidence, k, n - k + 1))
    # Even with every unit meeting it, the lower bound is (1 - confidence)^(1/n): fewer units can never PASS.
    need = min_units(level, confidence)
    reason = ("no unit: nothing to judge" if n == 0 else
              f"no unit has a figure (all {n} without one): none meets it" if not np.isfinite(x).any() else
              f"{n} units cannot show {level:.4%} at {confidence:.0%} confidence even if every one meets it: "
              f"at least {need} needed" if n < need else "")
    # (pass 70, 73) figures all exactly 0, every unit's or those the units without one leave: a PASS on them
    # says nothing about the units
    with_figure = int(np.count_nonzero(np.isfinite(x)))
    note = ""
    if with_figure and not np.any(x[np.isfinite(x)] != 0.0):
        note = ("every unit's figure is exactly 0 rad" if with_figure == n else
                f"every figure is exactly 0 rad ({with_figure} of {n} units have one, the others count as worst)")
        note += ": the verdict says nothing about the units (no motion in the phase? perfect sensors?)"
    return Verdict(float(requirement), n, k, k / n if n else float("nan"), lower, level,
                   confidence, n > 0 and lower >= level, reason, note)
