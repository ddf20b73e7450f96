"""Pointing indices as ECSS-E-ST-60-10C defines them, per run and over an
ensemble of units.

Per run (one unit), over one phase [t_start, t_end) of a uniformly sampled
error signal e(t) (rad; one column per axis, the norm is taken):

- APE, absolute performance error: the worst |e(t)| in the phase.
- RPE, relative performance error over windows of length dt_window: the
  worst |e(t) - mean of e over a window containing t|, over every window of
  that length inside the phase (sliding by one sample).
- PDE, performance drift error: the worst |mean of e over a window -
  mean of e over the window dt_separation later|, both inside the phase.
- Knowledge error (AKE): the APE of the estimate's error against truth,
  i.e. of (estimated error - true error).

The statistical interpretation is "worst time in the phase" per unit and
"ensemble of units" across the sweep: the index at level p (default
99.73 %) is the p-quantile of the units' worst values. Its confidence bounds
come from order statistics, which hold for any distribution: the number of
units below the true quantile is Binomial(n, p), so [X_(r), X_(s)] covers it
with probability sum_{k=r}^{s-1} C(n,k) p^k (1-p)^(n-k).

A figure over a window the run did not reach is NaN with a reason
(IndexValue.reason), never 0.
"""

from dataclasses import dataclass
import math

import numpy as np

# The ensemble statistics live in _ensemble.py; they are this module's API.
from ._ensemble import (  # noqa: F401
    LEVEL_3SIGMA, MAX_REQUIREMENT_RAD, QuantileBound, Verdict, coverage, min_units, quantile_bound,
    requirement_verdict, _ranks, _is_count, _is_number)


@dataclass(frozen=True)
class IndexValue:
    """One index of one unit: value [rad], or NaN and the reason it has none."""
    value: float
    reason: str = ""

    @property
    def ok(self):
        return math.isfinite(self.value)


def _nan(reason):
    return IndexValue(float("nan"), reason)


def _phase_slice(t_s, t_start, t_end):
    """Rows of t_s in [t_start, t_end), after checking the time base is uniform."""
    t_s = _real_array(t_s, "t_s", "a time [s]")
    if t_s.ndim != 1 or len(t_s) < 2:
        raise ValueError("t_s: need a 1-D time base of at least 2 samples")
    step = np.diff(t_s)
    dt = float(np.median(step))
    if not np.all(np.isfinite(t_s)):  # an infinite last time made the spacing's tolerance infinite
        raise ValueError("t_s: every time must be finite")
    # Uniform to a part in 1e4 of the step, plus what doubles can hold at these times (at 1e10 s, 2e-6 s).
    tol = 1e-4 * abs(dt) + 8.0 * float(np.spacing(np.max(np.abs(t_s))))
    if not dt > 0 or np.max(np.abs(step - dt)) > tol:
        raise ValueError("t_s: the samples must be uniformly spaced in time")
    if not (_is_number(t_start) and _is_number(t_end) and math.isfinite(t_start) and t_end >= t_start):
        raise ValueError(f"phase [{t_start}, {t_end}) s: need a finite start and an end not before it")
    rows = np.flatnonzero((t_s >= t_start - 1e-12) & (t_s < t_end - 1e-12))
    return rows, dt


def _window_samples(length_s, dt, name):
    """A window length as a whole number of samples; refuses one that is not."""
    if not (_is_number(length_s) and math.isfinite(length_s) and length_s > 0):
        raise ValueError(f"{name} = {length_s!r} s: need a finite length above 0 (a real number)")
    n = round(length_s / dt)
    if n < 1 or abs(n * dt - length_s) > 1e-9 * max(1.0, length_s):
        raise ValueError(f"{name} = {length_s} s is not a whole number of samples of {dt} s")
    return n


def _real_array(x, name, what):
    """x as a float array; an array of complex numbers (numpy dropped the
    imaginary part: 1e-4j read as an error of 0), of bools ([False, True] read
    as times) or of text is refused naming the argument (ValueError)."""
    a = np.asarray(x)
    if a.dtype.kind not in "iuf":
        raise ValueError(f"{name}: {what} is a real number, got {a.dtype} values"
                         + (" (their imaginary part would be dropped)" if a.dtype.kind == "c" else ""))
    return a.astype(float)


def _as_columns(e, name="e"):
    e = _real_array(e, name, "a pointing error [rad]")
    e = e[:, None] if e.ndim == 1 else e
    if e.ndim != 2 or e.shape[1] == 0:
        raise ValueError(f"e: need one row per sample of one or more axes, got shape {e.shape}")
    return e


def seconds(t):
    """A time as the shortest text that reads back as the same double ("2.0"
    as "2"): :g printed a phase ending at 1.000001 s as "[1e-06, 1)"."""
    text = repr(float(t))
    return text[:-2] if text.endswith(".0") else text


def _coverage_reason(rows, t_s, t_start, t_end, dt):
    """Why a phase has no figure, or "" when the run covered it whole. An
    open-ended phase [t_start, inf) (a controller's track) ends with the run:
    reaching it is covering it."""
    phase = f"the phase [{seconds(t_start)}, {seconds(t_end)}) s"
    if not t_end > t_start:  # a profile that gives the phase no time (profile.hold_time 0)
        return f"{phase} is empty"
    if len(rows) == 0:
        inside = t_s[0] <= t_start and t_s[-1] > t_start  # the run went through it between two samples (pass 53)
        if inside:
            before, after = t_s[t_s <= t_start][-1], t_s[t_s > t_start][0]
            return (f"no sample in {phase}: the run went through it between its samples at {seconds(before)} "
                    f"and {seconds(after)} s")
        if t_end <= t_s[0]:
            return f"the run ({seconds(t_s[0])} to {seconds(t_s[-1])} s) began after {phase}"
        return f"the run ({seconds(t_s[0])} to {seconds(t_s[-1])} s) never reached {phase}"
    if not t_s[-1] > t_start + 1e-9:  # docs/usage.md: a figure over a window needs the last sample after its start
        return f"the run ended at {seconds(t_s[-1])} s, at the start of {phase}"
    if t_s[0] > t_start + 1e-9:
        return f"the run began at {seconds(t_s[0])} s, inside {phase}"
    if math.isfinite(t_end) and t_s[rows[-1]] + dt < t_end - 1e-9:
        return f"the run ended at {seconds(t_s[-1])} s, inside {phase}"
    return ""


def _phase_signal(t_s, e, t_start, t_end):
    rows, dt = _phase_slice(t_s, t_start, t_end)
    e = _as_columns(e)
    if len(e) != len(np.asarray(t_s)):
        raise ValueError("e: need one row per time sample")
    return rows, dt, e[rows], _coverage_reason(rows, np.asarray(t_s, dtype=float), t_start, t_end, dt)


def _scaled(seg):
    """(seg / 2^k, k): the squares behind a norm overflow above about 1e154
    and vanish below 1e-154 (pass 35: |e| = 1.4e200 gave inf, 1.4e-170 gave
    0). A power of two keeps every digit, and a signal inside [2^-400, 2^400]
    is left as it is (k = 0): its figures are the same doubles as ever."""
    big = float(np.max(np.abs(seg))) if seg.size else 0.0
    if big == 0.0 or 2.0**-400 <= big <= 2.0**400:
        return seg, 0
    k = math.frexp(big)[1]
    return np.ldexp(seg, -k), k


def _unscaled(x, k):
    """x * 2^k as an IndexValue; a figure beyond the largest double (|e| near
    1.8e308 on two axes) is NaN with its reason, never inf (pass 36: a traceback)."""
    with np.errstate(over="ignore"):  # beyond the largest double: said below
        x = float(np.ldexp(x, k))
    return IndexValue(x) if math.isfinite(x) else _nan("the figure is beyond the largest double")


NOT_FINITE = "the error signal is not finite inside the phase"


def ape(t_s, e, t_start, t_end):
    """Absolute performance error: max |e| over the phase [rad]."""
    rows, _, seg, why = _phase_signal(t_s, e, t_start, t_end)
    if why:
        return _nan(why)
    if not np.all(np.isfinite(seg)):
        return _nan(NOT_FINITE)
    seg, k = _scaled(seg)
    return _unscaled(np.max(np.linalg.norm(seg, axis=1)), k)


def knowledge(t_s, e_estimate, e_truth, t_start, t_end):
    """Knowledge error: max |estimated error - true error| over the phase [rad]."""
    est, truth = _as_columns(e_estimate, "e_estimate"), _as_columns(e_truth, "e_truth")
    if est.shape != truth.shape:  # numpy would broadcast one row, or one axis, over the other
        raise ValueError(f"e_estimate {est.shape} and e_truth {truth.shape}: need the same shape")
    return ape(t_s, est - truth, t_start, t_end)


def _window_means(seg, m):
    """Mean of every window of m consecutive rows (sliding by one)."""
    c = np.vstack([np.zeros((1, seg.shape[1])), np.cumsum(seg, axis=0)])
    return (c[m:] - c[:-m]) / m


def rpe(t_s, e, t_start, t_end, window_s, chunk_rows=1 << 16):
    """Relative performance error over windows of window_s inside the phase [rad].
    chunk_rows bounds the deviations computed at once (elements): 1 << 16 keeps
    them in the CPU's cache, twice as fast as 1 << 22 on 1.5 s to 60 s phases."""
    if not (_is_count(chunk_rows, 2**62) and chunk_rows > 0):  # 0 or less looped forever
        raise ValueError(f"chunk_rows must be a whole number above 0, got {chunk_rows!r}")
    rows, dt, seg, why = _phase_signal(t_s, e, t_start, t_end)
    if why:
        return _nan(why)
    m = _window_samples(window_s, dt, "RPE window")
    if m < 2:  # a sample's deviation from its own mean: 0 by construction, no figure
        return _nan(f"the RPE window {seconds(window_s)} s holds one sample (of {seconds(dt)} s): its deviation "
                    "from its own mean is 0 by construction; give at least two samples")
    if len(seg) < m:
        return _nan(f"the phase [{seconds(t_start)}, {seconds(t_end)}) s is shorter than the RPE window "
                    f"{seconds(window_s)} s")
    if not np.all(np.isfinite(seg)):
        return _nan(NOT_FINITE)
    seg, k = _scaled(seg)
    means = _window_means(seg, m)
    # One axis at a time over contiguous columns: a reduction across the axes of a strided
    # (windows, axes, m) view cost two thirds of a closed-loop sample's indices. The squares add in
    # the same order, and the root of the largest is the largest root: the same doubles as before.
    columns = np.ascontiguousarray(seg.T)
    views = [np.lib.stride_tricks.sliding_window_view(c, m) for c in columns]  # (windows, m) per axis
    worst_sq = 0.0
    step = max(1, chunk_rows // max(1, m * seg.shape[1]))  # bounds the memory of one chunk
    for i in range(0, len(means), step):
        sq = None
        for a, view in enumerate(views):
            dev = view[i:i + step] - means[i:i + step, a, None]
            sq = dev * dev if sq is None else sq + dev * dev
        worst_sq = max(worst_sq, float(np.max(sq)))
    return _unscaled(math.sqrt(worst_sq), k)


def pde(t_s, e, t_start, t_end, window_s, separation_s):
    """Performance drift error: max |mean over a window - mean over the window
    separation_s later| with both windows inside the phase [rad]."""
    rows, dt, seg, why = _phase_signal(t_s, e, t_start, t_end)
    if why:
        return _nan(why)
    m = _window_samples(window_s, dt, "PDE window")
    k = _window_samples(separation_s, dt, "PDE separation")
    if len(seg) < m + k:
        return _nan(f"the phase [{seconds(t_start)}, {seconds(t_end)}) s is shorter than the PDE window "
                    f"{seconds(window_s)} s plus separation {seconds(separation_s)} s")
    if not np.all(np.isfinite(seg)):
        return _nan(NOT_FINITE)
    seg, scale_k = _scaled(seg)
    means = _window_means(seg, m)
    drift = means[k:] - means[:-k]
    return _unscaled(np.max(np.linalg.norm(drift, axis=1)), scale_k)


if __name__ == "__main__":
    from gimbalsim._errors import not_a_program
    not_a_program("indices")
