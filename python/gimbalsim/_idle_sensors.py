"""Sensor keys a closed loop never reads: those that act only through the
star tracker's or the boresight tracker's samples when none is taken or
delivered while it can act (an outage, a latency; the sample schedule of
firmware_sim's sample_schedule.hpp, mirrored here), sensors.seed with every
noise 0, and the antenna's keys where the loop does not close at the antenna."""
import collections
import itertools
import math

from . import _gimbalsim
from ._closed_spec import CONTROLLER_PREFIX
from ._idle_antenna import idle_at_antenna
from ._idle_estimate import idle_estimate
from .indices import seconds

# Keys that act only through the star tracker's samples: idle when none is delivered in the run.
_STAR_SAMPLE_KEYS = ("sensors.star_tracker_noise", "sensors.star_tracker_rate",
                     CONTROLLER_PREFIX + "estimator.k_p", CONTROLLER_PREFIX + "estimator.k_i")
# The estimator's gains act from the second star tracker sample on: the first sets the estimate (gain 1;
# controllers/src/attitude_estimator.cpp correct()).
_FROM_THE_SECOND_SAMPLE = (CONTROLLER_PREFIX + "estimator.k_p", CONTROLLER_PREFIX + "estimator.k_i")
# ... and through the boresight tracker's (sensors.antenna tracker_gyro); the controller's offset_rate moves
# the play offset only once a sample has measured it (controllers/src/tracker_fusion.cpp).
_TRACKER_SAMPLE_KEYS = ("sensors.tracker_noise", "sensors.tracker_bias", "sensors.tracker_rate",
                        CONTROLLER_PREFIX + "antenna.offset_rate")
_COMMAND_ONLY = (CONTROLLER_PREFIX + "antenna.offset_rate",)  # acts through the command, not the estimate

# How many of the run's last ticks' measurements no figure reads (unread_ticks). A measurement at tick k moves
# that tick's estimate, which the knowledge index reads, and its command, which the plant applies over
# (t_k+1, t_k+2] (firmware_sim/src/closed_loop.cpp: received after the plant advances): the truth shows it
# from tick k + 2 on, so a figure of the truth alone never sees the last two ticks' measurements.
KNOWLEDGE_AT_THE_END, KNOWLEDGE, TRUTH_ONLY = 0, 1, 2


# Every sensor noise drawn from sensors.seed's streams (firmware_sim: joint_sensors.hpp, attitude_sensors.hpp,
# antenna_sensors.hpp): with all of them 0 the seed draws nothing that acts.
# The antenna's noises (tracker, antenna gyro) draw from it too, and act where the loop closes at the antenna.
NOISE_KEYS = ("sensors.encoder_noise", "sensors.rate_noise", "sensors.gyro_noise", "sensors.gyro_bias_walk",
              "sensors.star_tracker_noise")
ANTENNA_NOISE_KEYS = ("sensors.tracker_noise", "sensors.antenna_gyro_noise")


# On a fixed base the star tracker reads the identity and a perfect gyro zero: without star tracker noise the
# estimator propagates the attitude exactly without a star tracker sample (firmware_sim: starTrackerRedundant).
_PERFECT_ATTITUDE = ("sensors.star_tracker_noise", "sensors.gyro_noise", "sensors.gyro_bias_walk",
                     "sensors.gyro_bias")


def idle_on_fixed_base(key, values, dispersed):
    """Why a key acting only through the star tracker's samples acts on
    nothing: a fixed base with a perfect gyro and star tracker (their keys
    given, all 0); else None."""
    if key not in _STAR_SAMPLE_KEYS + ("sensors.star_tracker_outage", "sensors.star_tracker_latency") or \
            str(values.get("structure.base", "floating")) != "fixed" or set(_PERFECT_ATTITUDE) & dispersed:
        return None
    if any(float(x) != 0.0 for k in _PERFECT_ATTITUDE for x in str(values.get(k, "0")).strip("[]").split(",")):
        return None
    return ("on a fixed base (structure.base fixed) the star tracker reads the identity and the gyro, perfect "
            "(sensors.gyro_noise, gyro_bias, gyro_bias_walk 0), zero: with sensors.star_tracker_noise 0 the "
            "estimator propagates the attitude exactly without a star tracker sample")


def idle_in_sensors(key, values, dispersed, takes=None, unread_ticks=TRUTH_ONLY):
    """Why a key that acts through the star tracker's or the boresight
    tracker's samples cannot act: an outage over the whole run [0,
    sim.duration] or over every sample instant within it (for every rate,
    control period and latency the study gives: takes), or a latency no
    shorter than the run (a sample is delivered latency after it is taken);
    or why sensors.seed cannot: every noise is 0. unread_ticks: how many of
    the run's last ticks' measurements no figure reads (KNOWLEDGE_AT_THE_END,
    KNOWLEDGE, TRUTH_ONLY; _last_acting_tick)."""
    if key == "sensors.seed":
        # the noises that act: the star tracker's and the antenna's only where their samples do
        def acts(k):
            return idle_in_sensors(k, values, dispersed, takes, unread_ticks) is None and \
                idle_estimate(k, values, dispersed, unread_ticks == TRUTH_ONLY) is None
        noises = tuple(k for k in NOISE_KEYS if acts(k)) + \
            tuple(k for k in ANTENNA_NOISE_KEYS if idle_at_antenna(k, values, dispersed) is None and acts(k))
        if set(noises) & dispersed or any(float(values.get(k, 0.0)) != 0.0 for k in noises):
            return None
        idle = [k for k in NOISE_KEYS if k not in noises]
        idle = f" ({', '.join(idle)} {'acts' if len(idle) == 1 else 'act'} on nothing a figure reads)" if idle else ""
        return "every sensor noise (" + ", ".join(noises) + ") is 0" + idle + ": nothing random to seed"
    for sensor, name, sample_keys in (("star_tracker", "star tracker", _STAR_SAMPLE_KEYS),
                                      ("tracker", "boresight tracker", _TRACKER_SAMPLE_KEYS)):
        outage, latency_key = f"sensors.{sensor}_outage", f"sensors.{sensor}_latency"
        reads_latency = key == latency_key
        # Each test needs only its own deciders fixed: a dispersed latency (the key itself or not) leaves the
        # outage's, which takes every sample whatever the latency.
        if not (key in sample_keys or reads_latency) or {outage, "sim.duration"} & dispersed:
            continue
        start, end = (float(x) for x in str(values.get(outage, "[0, 0]")).strip("[]").split(","))
        # a key that acts on the command alone is read by the truth alone
        duration, unread = float(values["sim.duration"]), TRUTH_ONLY if key in _COMMAND_ONLY else unread_ticks
        if start <= 0.0 and end >= duration:
            return f"{outage} [{seconds(start)}, {seconds(end)}] s covers the whole run: no {name} sample is taken"
        # The instants need the rate and the control period: fixed, exactly; dispersed, over every value drawn.
        rate_key, period = f"sensors.{sensor}_rate", CONTROLLER_PREFIX + "control.period"
        judged = not ({rate_key, period} & (dispersed | {key})) and rate_key in values and period in values
        given = _Given(takes, values, dispersed)
        combos = None if judged else given.combinations((rate_key, period))
        drawn = "" if combos is None else given.text((rate_key, period), ("Hz", "s"))
        if combos and all(_every_sample_lost(start, end, duration, r, T, None, unread) for r, T in combos):
            return (f"{outage} [{seconds(start)}, {seconds(end)}] s holds every {name} sample within the run for "
                    f"every {drawn}: no {name} sample is taken while it can act")
        if judged and _delivered(start, end, duration, float(values[rate_key]), float(values[period]), 0.0, unread,
                                 most=1) == 0:
            after = _first_take(_outage_ticks(start, end, float(values[period]))[1] + 1, float(values[rate_key]),
                                float(values[period])) * float(values[period])
            return (f"{outage} [{seconds(start)}, {seconds(end)}] s holds every {name} sample within the run "
                    f"(one every {seconds(1.0 / float(values[rate_key]))} s from 0, the next after the outage "
                    f"at {seconds(after)} s, too late to act{_unread_text(unread, duration)}): no {name} sample is "
                    "taken while it can act")
        # Sample 0 (taken at 0) falls due at the latency: after the last acting tick, no sample is delivered.
        periods, latencies = given.points(period), given.span(latency_key, default=0.0)
        lowest = None if latencies is None else latencies[0]
        if lowest is not None and _after_the_last_acting_tick(lowest, duration, periods, unread):
            return (f"{latency_key} {seconds(lowest)} s{' or more' if latency_key in dispersed else ''} is no shorter "
                    f"than the run ({seconds(duration)} s)"
                    f"{'' if lowest >= duration else _unread_text(unread, duration)}"
                    f": no {name} sample is delivered")
        # The rate decides only samples after the first: none falls due within the run at any rate drawn.
        rates = None if lowest is None else given.span(rate_key)
        rate_hi = None if rates is None else rates[1]
        if key == rate_key and key in dispersed and rate_hi is not None and rate_hi > 0.0 and \
                _after_the_last_acting_tick(1.0 / rate_hi + lowest, duration, periods, unread):
            return (f"only {name} sample 0 (at t = 0) falls due within the run at {rate_key} up to {rate_hi!r} Hz: "
                    "the rate decides no sample that acts")
        too_old = _dropped_as_too_old(sensor, name, latency_key, given)
        if reads_latency or latency_key in dispersed:
            if too_old is not None:
                return too_old
            # with the outage: every sample lost at every latency given (a range as itself: only a sample
            # lost at both ends counts, since a longer latency can carry a sample past the outage or into it)
            lost = given.combinations((rate_key, period, latency_key))
            if lost and all(_every_sample_lost(start, end, duration, r, T, L, unread) for r, T, L in lost):
                return (f"{outage} [{seconds(start)}, {seconds(end)}] s: for every "
                        f"{given.text((rate_key, period, latency_key), ('Hz', 's', 's'))}, every "
                        f"{name} sample taken outside the outage falls due in it (dropped) or after the run's last "
                        f"acting tick: no {name} sample is delivered while it can act")
            continue
        latency = float(values.get(latency_key, 0.0))
        # A sample taken outside the outage but delivered in it (dropped) or after the run acts on nothing.
        if judged and _delivered(start, end, duration, float(values[rate_key]), float(values[period]), latency,
                                 unread, most=1) == 0:
            return (f"{outage} [{seconds(start)}, {seconds(end)}] s with {latency_key} {seconds(latency)} s: every "
                    f"{name} sample taken outside the outage falls due in it (dropped) or too late to act (the "
                    f"run ends at {seconds(duration)} s{_unread_text(unread, duration)}): no {name} sample is "
                    "delivered while it can act")
        if combos and all(_every_sample_lost(start, end, duration, r, T, (latency, latency), unread)
                          for r, T in combos):
            return (f"{outage} [{seconds(start)}, {seconds(end)}] s with {latency_key} {seconds(latency)} s: for "
                    f"every {drawn}, every {name} sample taken outside the outage falls due in it (dropped) or "
                    f"after the run's last acting tick: no {name} sample is delivered while it can act")
        if too_old is not None:
            return too_old
        if key in _FROM_THE_SECOND_SAMPLE:
            one = _one_sample_at_most(start, end, duration, given, (rate_key, period, latency_key), unread)
            if one is not None:
                outage_text = f"{outage} [{seconds(start)}, {seconds(end)}] s and " if end > start else ""
                return (f"with {outage_text}{one}, at most one {name} sample "
                        f"is delivered while it can act: it sets the estimate, and the estimator's gains act from "
                        "the second on")
    return None


def _one_sample_at_most(start, end, duration, given, keys, unread):
    """What the study gives keys (rate, period, latency), for a refusal, when
    at every combination at most one sample is delivered while it can act;
    else None. Judged only where each is a fixed value or a choice's (a
    range: None)."""
    combos = given.combinations(keys)
    if not combos or any(lo != hi for combo in combos for lo, hi in combo):
        return None
    for (rate, _), (period, _), (latency, _) in combos:
        n = _delivered(start, end, duration, rate, period, latency, unread, most=2)
        if n is None or n > 1:
            return None
    return given.text(keys, ("Hz", "s", "s"))


def _delivered(start, end, duration, rate, period, latency, unread, most):
    """How many samples are delivered at or before the last acting tick
    (_last_acting_tick), up to most (None: not numbers it can judge), as
    sample_schedule.hpp takes and delivers them: sample j belongs to j /
    rate and is taken at the first tick at or after it, one a tick, none in
    the outage [start, end] (active when end > start); delivered latency's
    ticks later, none in the outage. The one mirror of that schedule here."""
    if not (0.0 < rate <= 1e6 and period > 0.0 and latency >= 0.0):
        return None
    first, last = _outage_ticks(start, end, period) if end > start else (1, 0)
    last_acting, lag = _last_acting_tick(duration, period, unread), _tick_at_or_after(latency, period)
    delivered, s = 0, 0  # sample 0, taken at tick 0
    while s + lag <= last_acting:
        if first <= s <= last:  # taken in the outage: lost, and so is every take up to its end
            s = _first_take(last + 1, rate, period)
        elif first <= s + lag <= last:  # due in it: dropped, and so is every take due up to its end
            s = _first_take(last + 1 - lag, rate, period)
        else:
            delivered += 1
            if delivered >= most:
                return most
            s = _first_take(s + 1, rate, period)
    return delivered


def _unread_text(unread, duration):
    """The ticks no figure reads, for a refusal: ", less its last tick(s) ..."."""
    return {KNOWLEDGE_AT_THE_END: "",
            KNOWLEDGE: ", less its last tick, whose command acts after the run and whose estimate no index reads",
            TRUTH_ONLY: ", less its last two ticks, which act only through commands applied after the run's "
                        "last tick"}[unread]


def _dropped_as_too_old(sensor, name, latency_key, given):
    """Why every sample arrives older than the controller keeps it, for every
    latency and control period the study gives (a period drawn from a range
    is not judged): the attitude estimator's ring (star tracker) or the
    boresight tracker's history of ticks drops it (_gimbalsim._sample_histories).
    A sample arrives at the first tick at or after t_s + latency: its age is
    the latency rounded up to whole ticks."""
    period_key = CONTROLLER_PREFIX + "control.period"
    periods, latency = given.points(period_key), given.span(latency_key)
    if periods is None or latency is None or not all(T > 0.0 for T in periods):
        return None
    lowest, held = latency[0], []
    for T in periods:
        star_span, ticks = _gimbalsim._sample_histories(T)
        lag = _tick_at_or_after(lowest, T)  # delivered at the first tick at or after t_s + latency: its age in ticks
        if sensor == "star_tracker" and lag < round(star_span / T) or sensor == "tracker" and lag < ticks:
            return None
        held.append(f"{seconds(star_span)} s" if sensor == "star_tracker" else f"{ticks} ticks of {seconds(T)} s")
    keeps = "its attitude estimator keeps" if sensor == "star_tracker" else "its tracker fusion keeps"
    lowest_text = f"{latency_key} {seconds(lowest)} s" + (" or more" if latency_key in given.dispersed else "")
    return (f"{lowest_text}: every {name} sample arrives older than the controller's history ({keeps} "
            f"{' or '.join(held)} at {period_key} {' or '.join(seconds(T) for T in periods)} s) and is dropped")


def _after_the_last_acting_tick(t, duration, periods, unread):
    """Whether a sample falling due at t [s] (at the first tick at or after
    it) is past the last acting tick at every period given; a period drawn
    from a range (None): only a t past the run's end counts."""
    if periods is None:
        return t > duration * (1 + 1e-9)
    return all(T > 0.0 and _tick_at_or_after(t, T) > _last_acting_tick(duration, T, unread) for T in periods)


Span = collections.namedtuple("Span", "lo hi")  # a number drawn from a range (uniform, loguniform, normal ends)


class _Given:
    """The values the study gives a key: its own when fixed, a choice's or a
    grid's each, a range's ends (takes: _idle_keys.takes_of)."""

    def __init__(self, takes, values, dispersed):
        self.takes, self.values, self.dispersed = takes or {}, values, dispersed

    def intervals(self, key, default=None):
        """[(lo, hi)]: a fixed value or each listed value as a point, a range
        as itself; a key not given as [(default,) * 2] (a latency: 0); None
        when not known as numbers."""
        if key in self.dispersed:
            t = self.takes.get(key)
        else:
            t = [self.values[key]] if key in self.values else None if default is None else [default]
        try:
            return [(t.lo, t.hi)] if isinstance(t, Span) else [(float(v), float(v)) for v in t]
        except (TypeError, ValueError):
            return None

    def span(self, key, default=None):
        """(lowest, highest) value of key [its unit], or None."""
        given = self.intervals(key, default)
        return None if given is None else (min(lo for lo, _ in given), max(hi for _, hi in given))

    def points(self, key):
        """The values of key as a list, or None when one is drawn from a range (or not a number)."""
        given = self.intervals(key)
        return None if given is None or any(lo != hi for lo, hi in given) else [lo for lo, _ in given]

    def combinations(self, keys):
        """Every combination of the intervals of `keys`, or None when one is
        not known as numbers or there are more than 4096."""
        per_key = [self.intervals(k) for k in keys]
        if any(given is None for given in per_key) or math.prod(map(len, per_key)) > 4096:
            return None
        return list(itertools.product(*per_key))

    def text(self, keys, units):
        """What the study gives keys, for a refusal: "k in [lo, hi] Hz", "k one of a, b s", "k v s"."""
        def one(k, unit):
            t = self.takes.get(k) if k in self.dispersed else None
            if isinstance(t, Span):
                return f"{k} in [{t.lo!r}, {t.hi!r}] {unit}"
            return f"{k} one of {', '.join(map(str, t))} {unit}" if t is not None else f"{k} {self.values.get(k)} {unit}"
        return " and ".join(one(k, unit) for k, unit in zip(keys, units))


def _every_sample_lost(start, end, duration, rate, period, latency, unread):
    """Whether no sample acts, for every rate in rate = (lo, hi) Hz, control
    period in period = (lo, hi) s and (given) latency in latency = (lo, hi)
    s: each is taken in the outage [start, end], or (latency given) falls
    due in it or after the last acting tick. A point of each: exactly
    (_delivered). Otherwise sample j (at
    j/rate) is taken within a period after it and falls due latency later,
    rounded up to a tick: only a sample sure of being lost at both ends
    counts; one in doubt acts."""
    (r_lo, r_hi), (t_lo, t_hi) = rate, period
    l_lo, l_hi = (None, None) if latency is None else latency
    if not (end > start and 0.0 < r_lo <= r_hi and 0.0 < t_lo <= t_hi and (latency is None or 0.0 <= l_lo <= l_hi)):
        return False
    if r_lo == r_hi and t_lo == t_hi and l_lo == l_hi:  # a latency only delays a sample: none, as 0
        return _delivered(start, end, duration, r_lo, t_lo, l_lo or 0.0, unread, most=1) == 0
    # beyond it, past the last acting tick at any period
    late = duration - unread * t_lo + 1e-9 * duration
    if late * r_hi > 1e6:
        return False  # too many samples to go through: not judged
    j = 0
    while j / r_hi <= late:
        take_lo, take_hi = (0.0, 0.0) if j == 0 else (j / r_hi, j / r_lo + t_hi)
        if not start <= take_lo <= take_hi <= end:  # taken outside the outage, or may be
            if latency is None:
                return False
            due_lo, due_hi = take_lo + l_lo, take_hi + l_hi + t_hi
            if not (start <= due_lo <= due_hi <= end or due_lo > late):
                return False
        j += 1
    return True


def _outage_ticks(start, end, period):
    """The first and last control tick in the outage [start, end]: as
    attitude_sensors.hpp / antenna_sensors.hpp, the ticks t_k = k T with
    start - tol <= t_k <= end + tol, tol = 1e-9 T (rounding stepped over)."""
    tol = 1e-9 * period
    first, last = max(math.ceil((start - tol) / period), 0), math.floor((end + tol) / period)
    while first > 0 and (first - 1) * period >= start - tol:
        first -= 1
    while first * period < start - tol:
        first += 1
    while (last + 1) * period <= end + tol:
        last += 1
    while last > 0 and last * period > end + tol:
        last -= 1
    return first, last


def _first_take(m, rate, period):
    """The first tick at or after tick m that takes a sample: as
    sample_schedule.hpp, sample j belongs to j / rate and is taken in the
    first tick at or after it (ticksAtOrAfter), in an outage or not."""
    tick = lambda j: _tick_at_or_after(j * (1.0 / rate), period)  # noqa: E731
    j = max(math.floor(m * period * rate) - 2, 0)
    while tick(j) < m:
        j += 1
    return tick(j)


def _tick_at_or_after(t, period):
    """The first control tick at or after t [s] (ticksAtOrAfter in
    sample_schedule.hpp, its 1e-9 of a tick for rounding): a sample's take,
    or its age in ticks when t is a latency."""
    return math.ceil(t / period - 1e-9)


def _last_acting_tick(duration, period, unread):
    """The last tick whose measurement can act: the run's last, duration/T,
    less the ticks no figure reads (unread: KNOWLEDGE_AT_THE_END, a knowledge
    index over a phase that holds the last tick; KNOWLEDGE, one; TRUTH_ONLY,
    two: the command of tick k acts on the truth from tick k + 2)."""
    return round(duration / period) - unread
