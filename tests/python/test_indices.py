"""The ECSS pointing indices on signals whose APE, RPE and PDE are known in
closed form, empty windows as NaN with a reason, and the order-statistics
bounds against their exact binomial coverage (computed here independently,
with math.comb) and against sampling."""
import math

import numpy as np
import pytest

from gimbalsim import indices

DT = 1e-3
T = np.arange(0, 4000) * DT  # 0 .. 3.999 s


def test_constant_bias():
    e = np.tile([3e-5, -4e-5], (len(T), 1))  # |e| = 5e-5 rad
    assert indices.ape(T, e, 1.0, 3.0).value == pytest.approx(5e-5, rel=1e-12)
    # Window means come from running sums: round-off of order 1e-13 of the signal.
    assert indices.rpe(T, e, 1.0, 3.0, 0.2).value < 1e-12 * 5e-5
    assert indices.pde(T, e, 1.0, 3.0, 0.2, 0.5).value < 1e-12 * 5e-5


def test_sine_over_whole_periods():
    a, f = 7e-6, 2.0  # a window of 0.5 s holds one period: its mean is zero
    e = a * np.sin(2 * np.pi * f * T)
    assert indices.ape(T, e, 0.0, 4.0).value == pytest.approx(a, rel=1e-12)
    assert indices.rpe(T, e, 0.0, 4.0, 0.5).value == pytest.approx(a, rel=1e-9)
    assert indices.pde(T, e, 0.0, 4.0, 0.5, 1.0).value < 1e-12 * a


def test_ramp():
    r = 2e-5  # rad/s
    e = r * T
    # APE: the last sample inside [1, 3).
    assert indices.ape(T, e, 1.0, 3.0).value == pytest.approx(r * 2.999, rel=1e-12)
    # RPE: a window of m samples of a ramp deviates from its mean by r dt (m - 1) / 2 at its ends.
    m = 200
    assert indices.rpe(T, e, 1.0, 3.0, m * DT).value == pytest.approx(r * DT * (m - 1) / 2, rel=1e-9)
    # PDE: two window means 0.5 s apart differ by r * 0.5.
    assert indices.pde(T, e, 1.0, 3.0, 0.1, 0.5).value == pytest.approx(r * 0.5, rel=1e-9)


def test_rpe_is_the_largest_deviation_from_its_window_mean_over_every_window_and_axis():
    # Against the definition written out window by window: random drifting signals of one to three axes,
    # the worst deviation anywhere (a fast path that dropped an axis, a window or a chunk is caught).
    rng = np.random.default_rng(7)
    for trial in range(40):
        n, axes, m = int(rng.integers(30, 400)), int(rng.integers(1, 4)), int(rng.integers(2, 25))
        t = np.arange(n) * DT
        e = rng.normal(size=(n, axes)) * 1e-6 + np.outer(t, rng.normal(size=axes)) * 1e-4
        e[int(rng.integers(n)), int(rng.integers(axes))] += 3e-5  # one outlier on one axis
        expect = max(float(np.max(np.linalg.norm(e[i:i + m] - e[i:i + m].mean(axis=0), axis=1)))
                     for i in range(n - m + 1))
        got = [indices.rpe(t, e, 0.0, n * DT, m * DT, chunk_rows=c).value for c in (1, 5 * m * axes, 1 << 22)]
        assert got[0] == pytest.approx(expect, rel=1e-9) and got[0] == got[1] == got[2]


def test_knowledge_is_estimate_against_truth():
    truth = 1e-5 * np.sin(T)
    estimate = truth + 3e-6
    assert indices.knowledge(T, estimate, truth, 0.0, 4.0).value == pytest.approx(3e-6, rel=1e-9)


@pytest.mark.parametrize("call", [
    lambda: indices.ape(T, T, 5.0, 6.0),
    lambda: indices.rpe(T, T, 5.0, 6.0, 0.1),
    lambda: indices.pde(T, T, 5.0, 6.0, 0.1, 0.2),
])
def test_a_phase_the_run_never_reached_is_nan_with_a_reason(call):
    v = call()
    assert math.isnan(v.value) and not v.ok
    assert "never reached" in v.reason


def test_a_phase_between_two_samples_says_the_run_went_through_it():
    # (pass 53) samples at 0, 1 and 2 s, the phase [1.2, 1.5) s: the run covered it, no sample lies in it;
    # the reason said "never reached".
    t, e = np.array([0.0, 1.0, 2.0]), np.array([1e-4, 2e-4, 3e-4])
    v = indices.ape(t, e, 1.2, 1.5)
    assert math.isnan(v.value)
    assert v.reason == "no sample in the phase [1.2, 1.5) s: the run went through it between its samples at 1 and 2 s"
    assert "began after the phase [-1, -0.5) s" in indices.ape(t, e, -1.0, -0.5).reason
    assert "never reached the phase [2.5, 3) s" in indices.ape(t, e, 2.5, 3.0).reason


def test_a_run_ending_inside_the_phase_is_nan():
    v = indices.ape(T, T, 3.0, 5.0)
    assert math.isnan(v.value) and "ended at 3.999 s" in v.reason


def test_a_phase_shorter_than_its_window_is_nan():
    v = indices.rpe(T, T, 1.0, 1.1, 0.2)
    assert math.isnan(v.value) and "shorter than the RPE window" in v.reason
    v = indices.pde(T, T, 1.0, 1.5, 0.2, 0.4)
    assert math.isnan(v.value) and "shorter than the PDE window" in v.reason


def test_window_bounds_print_so_that_different_times_never_read_alike():
    # :g wrote 6 digits: a phase to 1.001001 s read "[1e-06, 1.001)", as if the run's last tick covered it
    t = np.arange(0, 1001) * DT  # 0 .. 1 s
    v = indices.ape(t, t, 1e-6, 1.001001)
    assert math.isnan(v.value) and v.reason == "the run ended at 1 s, inside the phase [1e-06, 1.001001) s"
    assert indices.seconds(0.1 + 0.2) == "0.30000000000000004" and indices.seconds(2.0) == "2"
    # window and separation as given, not their sum (0.2 + 0.4 rounds to 0.6000000000000001)
    v = indices.pde(T, T, 1.0, 1.5, 0.2, 0.4)
    assert v.reason == "the phase [1, 1.5) s is shorter than the PDE window 0.2 s plus separation 0.4 s"


def test_a_non_finite_signal_is_nan_not_a_number():
    e = T.copy()
    e[2500] = np.nan
    for v in (indices.ape(T, e, 2.0, 3.0), indices.rpe(T, e, 2.0, 3.0, 0.1),
              indices.pde(T, e, 2.0, 3.0, 0.1, 0.2)):
        assert math.isnan(v.value) and "not finite" in v.reason


@pytest.mark.parametrize("scale", [1e307, 1e200, 1e-170, 1e-300])
def test_a_finite_signal_far_from_one_gives_its_own_figures(scale):
    # (pass 35) |e| = 1.4e200 gave inf (the squares overflowed) and 1.4e-170 gave 0 (they vanished), with no
    # reason: each figure of a scaled signal is the unscaled one's, scaled
    t = np.arange(200) * 0.01
    e = np.random.default_rng(3).uniform(-1.0, 1.0, (200, 2))
    for call in (lambda x: indices.ape(t, x, 0.0, 2.0), lambda x: indices.rpe(t, x, 0.0, 2.0, 0.1),
                 lambda x: indices.pde(t, x, 0.0, 2.0, 0.1, 0.3)):
        plain, far = call(e), call(e * scale)
        assert plain.ok and far.ok and far.reason == "", far
        assert far.value == pytest.approx(plain.value * scale, rel=1e-12, abs=0.0), (far, plain)


def test_a_figure_beyond_the_largest_double_is_nan_with_its_reason():
    # (pass 36) |e| of 1.7e308 on two axes: a traceback (OverflowError) from the scaling back
    t = np.arange(100) * 0.01
    e = np.full((100, 2), 1.7e308)
    e[::2] *= -1.0
    for v in (indices.ape(t, e, 0.0, 1.0), indices.rpe(t, e, 0.0, 1.0, 0.1)):
        assert math.isnan(v.value) and v.reason == "the figure is beyond the largest double", v


def test_a_window_that_is_not_whole_samples_is_refused():
    with pytest.raises(ValueError, match="RPE window"):
        indices.rpe(T, T, 0.0, 4.0, 0.0105)
    with pytest.raises(ValueError, match="uniformly spaced"):
        indices.ape(np.array([0.0, 0.001, 0.003]), np.zeros(3), 0.0, 1.0)


def _coverage_by_comb(n, p, r, s):
    """P(r <= Binomial(n, p) <= s - 1), term by term in logarithms (no scipy)."""
    def log_term(k):
        return (math.lgamma(n + 1) - math.lgamma(k + 1) - math.lgamma(n - k + 1)
                + k * math.log(p) + (n - k) * math.log1p(-p))
    return sum(math.exp(log_term(k)) for k in range(r, s))


@pytest.mark.parametrize("n,level", [(30, 0.9), (200, 0.95), (2000, 0.9973)])
def test_bounds_cover_at_least_the_confidence_exactly(n, level):
    rng = np.random.default_rng(1)
    q = indices.quantile_bound(rng.random(n), level, 0.95)
    assert q.supported
    s = q.upper_rank
    # P(X_(s) >= quantile) = P(Bin(n, level) <= s - 1): at least 95 %, and s is the smallest such rank.
    assert _coverage_by_comb(n, level, 0, s) >= 0.95
    assert _coverage_by_comb(n, level, 0, s - 1) < 0.95
    assert indices.coverage(n, level, 0, s) == pytest.approx(_coverage_by_comb(n, level, 0, s), abs=1e-12)


def test_upper_bound_coverage_by_sampling():
    # Uniform(0, 1) units: the level-quantile is the level itself.
    n, level, trials = 300, 0.99, 4000
    rng = np.random.default_rng(7)
    hits = 0
    for _ in range(trials):
        q = indices.quantile_bound(rng.random(n), level, 0.9)
        hits += q.upper >= level
    exact = indices.coverage(n, level, 0, q.upper_rank)
    se = math.sqrt(exact * (1 - exact) / trials)
    assert abs(hits / trials - exact) < 4 * se
    assert exact >= 0.9


def test_too_few_units_is_marked_never_printed_bare():
    q = indices.quantile_bound(np.linspace(0, 1, 20), indices.LEVEL_3SIGMA, 0.95)
    assert not q.supported and math.isnan(q.upper)
    m = indices.min_units(0.9973, 0.95)
    assert 1 - 0.9973**m >= 0.95 > 1 - 0.9973 ** (m - 1)  # the worst of m units bounds it, of m - 1 not
    assert f"at least {m} are needed" in q.reason


def test_missing_units_count_as_worst():
    n = 2000
    s = indices.quantile_bound(np.zeros(n)).upper_rank
    above = n - s  # units sorted above the bound's rank
    q = indices.quantile_bound(np.r_[np.zeros(n - above), np.full(above, np.nan)])
    assert q.n_missing == above and q.upper == 0.0
    q = indices.quantile_bound(np.r_[np.zeros(n - above - 1), np.full(above + 1, np.nan)])
    assert q.upper == math.inf  # one more unit without a figure reaches the bound


def test_no_figure_at_all_is_no_quantile_and_bad_arguments_are_refused():
    q = indices.quantile_bound(np.full(2000, np.nan))  # enough units, none seen
    assert not q.supported and math.isnan(q.estimate) and math.isnan(q.upper)
    assert q.n_missing == 2000 and "no unit has a figure" in q.reason
    with pytest.raises(ValueError, match="unit 1 has -0.5"):  # a signed error, not its magnitude
        indices.quantile_bound([0.1, -0.5, 0.2])
    with pytest.raises(ValueError, match="magnitude"):
        indices.requirement_verdict([0.1, -1e-9], 1.0)
    with pytest.raises(ValueError, match="r <= s"):  # r > s gave a negative probability
        indices.coverage(10, 0.5, 6, 4)
    with pytest.raises(ValueError, match="level"):
        indices.coverage(10, 1.5, 1, 4)
    for level in (0.3, 1e-300, 0.0):  # a quantile below the median is no budget's question, here as in quantile_bound
        with pytest.raises(ValueError, match=r"level must lie in \[0.5, 1\), got"):
            indices.coverage(10, level, 1, 2)
    with pytest.raises(ValueError, match="r <= s"):  # no order statistic has rank 1.5
        indices.coverage(10, 0.5, 1.5, 3.7)
    with pytest.raises(ValueError, match="requirement must be an angle"):  # was a TypeError
        indices.requirement_verdict([1e-5] * 2000, "1e-4")
    with pytest.raises(ValueError, match=r"level must lie in \[0.5, 1\)"):  # two units gave PASS
        indices.requirement_verdict([1e-5] * 2, 1e-4, level=5e-324, confidence=0.5)
    t = np.arange(1001) * 0.001
    t_inf = t.copy()
    t_inf[-1] = math.inf  # made the spacing's tolerance infinite: a figure came out
    with pytest.raises(ValueError, match="every time must be finite"):
        indices.ape(t_inf, np.ones(1001), 0.0, math.inf)
    t_far = 1e10 + t
    t_far[500] += 5.0  # at 1e10 s the tolerance was 10 s: a gap of 5 s passed as uniform
    with pytest.raises(ValueError, match="uniformly spaced"):
        indices.ape(t_far, np.ones(1001), 1e10, math.inf)
    assert indices.ape(1e10 + t, np.ones(1001), 1e10, math.inf).value == 1.0  # what doubles hold there is uniform
    with pytest.raises(ValueError, match="whole n in"):  # 10**30 failed inside numpy; a bool is no count
        indices.coverage(10**30, 0.5, 1, 5)
    with pytest.raises(ValueError, match="whole n in"):
        indices.coverage(True, 0.5, 1, 1)
    for figures in (["1", "2"], [True, False]):  # read as 1.0 and 0.0
        with pytest.raises(ValueError, match="a figure per unit is a number"):
            indices.quantile_bound(figures, 0.5, 0.5)
    v = indices.requirement_verdict([math.nan] * 10, 1.0, 0.5, 0.5)
    assert not v.passed and "no unit has a figure (all 10 without one)" in v.reason  # was FAIL with no reason
    t = np.arange(100) * 0.01
    with pytest.raises(ValueError, match=r"phase \[0.1, 0.5\)"):  # a string start: TypeError naming nothing
        indices.ape(t, np.ones(100), "0.1", 0.5)
    for bad in (0, -1, 2.5, True):  # 0 or less never advanced through the windows; True is no row count
        with pytest.raises(ValueError, match="chunk_rows"):
            indices.rpe(t, np.ones(100), 0.0, 1.0, 0.1, chunk_rows=bad)


def test_requirement_verdict_clopper_pearson():
    # All n units meet it: the one-sided lower bound is (1 - c)^(1/n).
    v = indices.requirement_verdict(np.zeros(2000), 1e-5)
    assert v.lower == pytest.approx(0.05 ** (1 / 2000), rel=1e-9) and v.passed
    v = indices.requirement_verdict(np.zeros(500), 1e-5)
    assert v.lower == pytest.approx(0.05 ** (1 / 500), rel=1e-9) and not v.passed
    v = indices.requirement_verdict(np.r_[np.zeros(1990), np.ones(10)], 0.5)
    assert v.n_meeting == 1990 and not v.passed


def test_a_verdict_too_few_units_can_give_says_why():
    # 0.05^(1/n) >= 0.9973 needs n >= 1109 (the shipped budget's size): 500 units meeting it all FAIL, with the count they lack
    v = indices.requirement_verdict(np.zeros(500), 1e-5)
    assert not v.passed and "500 units cannot show" in v.reason and "at least 1109 needed" in v.reason
    v = indices.requirement_verdict([], 1e-5)
    assert not v.passed and v.reason == "no unit: nothing to judge"
    assert math.isnan(v.lower) and math.isnan(v.fraction)  # (pass 78) no unit bounds no fraction: not a bound of 0
    assert indices.requirement_verdict(np.zeros(1109), 1e-5).passed
    assert indices.requirement_verdict(np.zeros(1109), 1e-5).reason == ""


def test_a_table_of_figures_is_not_a_list_of_units_and_min_units_checks_its_question():
    with pytest.raises(ValueError, match="one figure per unit"):
        indices.requirement_verdict([[1e-5] * 3] * 500, 1e-4, 0.995, 0.95)  # it counted 1500 units: PASS
    for level, confidence in ((1.0, 0.95), (0.5, 0.0)):  # ZeroDivisionError, and 0 units
        with pytest.raises(ValueError, match=r"must lie in \[0.5, 1\)"):
            indices.min_units(level, confidence)
    assert indices.min_units(0.9973, 0.95) == 1109


def test_a_verdict_at_a_degenerate_level_or_confidence_is_refused():
    for level, confidence in ((0.0, 0.95), (0.9973, 0.0), (1.0, 0.95), (0.9973, 1.0)):
        with pytest.raises(ValueError, match=r"must lie in \[0.5, 1\)"):
            indices.requirement_verdict([1e-6] * 100, 1e-3, level, confidence)
    # NaN gave FAIL, inf and 1e308 PASS, 0 FAIL: no question (no pointing error exceeds pi rad)
    for requirement in (math.nan, math.inf, -1e-6, 0.0, -0.0, 1e308, math.pi * (1 + 1e-15)):
        with pytest.raises(ValueError, match=r"requirement must be an angle in \(0, pi\] rad"):
            indices.requirement_verdict([1e-6] * 100, requirement)
    assert indices.requirement_verdict([1e-6] * 100, math.pi, 0.5, 0.5).passed  # pi itself is a question


def test_a_level_and_confidence_as_any_real_number_type_answer_as_their_floats():
    # (pass 56) a Fraction passed the range check, then numpy raised a bare TypeError
    from fractions import Fraction
    figures = np.linspace(1e-6, 1e-5, 1200)
    as_float = indices.requirement_verdict(figures, Fraction(1, 10**5), 0.9973, 0.95)
    as_fraction = indices.requirement_verdict(figures, Fraction(1, 10**5), Fraction(9973, 10000), Fraction(95, 100))
    assert (as_fraction.passed, as_fraction.lower) == (as_float.passed, as_float.lower)
    assert indices.min_units(Fraction(9973, 10000), Fraction(95, 100)) == 1109
    bound = indices.quantile_bound(figures, Fraction(9973, 10000), np.float32(0.95))
    assert bound.estimate == indices.quantile_bound(figures, 0.9973, float(np.float32(0.95))).estimate


def test_a_phase_the_run_covered_only_in_part_has_no_figure():
    late = T[T >= 1.0]  # the run began at 1 s, inside [0.5, 2)
    v = indices.ape(late, np.full(len(late), 1e-5), 0.5, 2.0)
    assert math.isnan(v.value) and "began at 1 s, inside the phase" in v.reason


def test_an_open_ended_phase_the_run_reached_has_its_figure():
    # A controller's track window [3.5, inf): it ends with the run, which reached it.
    e = np.where(T >= 3.5, 2e-5, 9e-5)
    assert indices.ape(T, e, 3.5, math.inf).value == 2e-5
    assert indices.rpe(T, e, 3.5, math.inf, 0.1).value < 1e-12 * 2e-5  # constant there: round-off of the running sums
    assert math.isnan(indices.ape(T, e, 4.5, math.inf).value)  # never reached


def test_an_infinite_or_empty_window_is_a_value_error_not_a_traceback():
    e = np.zeros(len(T))
    for bad in (math.inf, math.nan, 0.0, -0.1):
        with pytest.raises(ValueError, match="need a finite length above 0"):
            indices.rpe(T, e, 0.0, 3.0, bad)
    with pytest.raises(ValueError, match="need a finite start"):
        indices.ape(T, e, -math.inf, 3.0)


def test_a_phase_begun_by_the_runs_first_sample_and_an_empty_signal():
    t = np.arange(1.0, 6.0)  # 1 .. 5 s: no sample at 0
    v = indices.ape(t, np.full(len(t), 1e-3), 0.0, 3.0)
    assert math.isnan(v.value) and "began at 1 s" in v.reason
    assert indices.ape(t, np.full(len(t), 1e-3), 1.0, 3.0).value == 1e-3  # begins with the run: covered
    with pytest.raises(ValueError, match="one or more axes"):
        indices.ape(t, np.zeros((5, 0)), 1.0, 3.0)
    # a profile that gives a phase no time: no figure, with the reason (a sweep row, not a traceback)
    empty = indices.ape(T, np.zeros(len(T)), 2.5, 2.5)
    assert math.isnan(empty.value) and "is empty" in empty.reason
    assert indices.quantile_bound([math.nan] * 3000).reason.startswith("no unit has a figure")


def test_a_bound_that_falls_on_a_unit_without_a_figure_says_so():
    # (pass 84) the upper bound came out inf with an empty reason, read as a figure seen
    b = indices.quantile_bound([1e-4, math.inf], 0.5, 0.5)
    assert b.upper == math.inf and b.reason == ("the upper bound and the interval's high end fall on the 1 unit(s) "
                                                "without a finite figure, counted as worst (+inf)"), b
    b = indices.quantile_bound([1e-4, 2e-4, math.nan], 0.5, 0.5)
    assert b.upper == 2e-4 and b.high == math.inf and b.reason.startswith("the interval's high end falls on"), b
    b = indices.quantile_bound([1e-4] * 3 + [math.nan], 0.5, 0.9)
    assert b.reason == ("4 units give only a one-sided bound at 90% confidence; the upper bound falls on the 1 unit(s) "
                        "without a finite figure, counted as worst (+inf)"), b
    assert indices.quantile_bound([1e-4, 2e-4], 0.5, 0.5).reason == ""  # every figure seen: nothing to say


def test_a_phase_the_run_ends_at_and_mismatched_signals():
    # The last sample at the phase's start: no figure (docs/usage.md "Figures over a window"), open-ended or not.
    t = T[T <= 2.5]
    e = np.full(len(t), 1e-4)
    for end in (math.inf, 3.0):
        v = indices.ape(t, e, 2.5, end)
        assert math.isnan(v.value) and "at the start of the phase" in v.reason, v
    with pytest.raises(ValueError, match="same shape"):
        indices.knowledge(T, np.zeros((len(T), 3)), np.zeros((1, 3)), 0.0, 1.0)
    with pytest.raises(ValueError, match="1-D"):
        indices.quantile_bound(np.ones((3, 2)), 0.5, 0.5)


def test_a_verdict_over_figures_all_exactly_0_has_a_note():
    # (pass 73) requirement_verdict([0] * 2000, 1e-4) gave PASS with nothing said: it answers nothing
    v = indices.requirement_verdict([0.0] * 2000, 1e-4)
    assert v.passed and v.note.startswith("every unit's figure is exactly 0 rad: the verdict says nothing"), v
    v = indices.requirement_verdict([0.0] * 1999 + [float("nan")], 1e-4)
    assert v.note.startswith("every figure is exactly 0 rad (1999 of 2000 units have one"), v
    assert indices.requirement_verdict([0.0] * 1999 + [1e-9], 1e-4).note == ""
    assert indices.requirement_verdict([float("nan")] * 3, 1e-4).note == ""  # no figure: its reason says so
