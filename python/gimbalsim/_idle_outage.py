"""An outage key that acts on nothing: the star tracker's or the boresight
tracker's outage window that takes and drops no sample a figure of the run
reads, judged at each value of its sampling a study gives (_idle_keys)."""

from ._closed_spec import CONTROLLER_PREFIX
from ._idle_sensors import _delivered, _Given, _last_acting_tick, _outage_ticks, _tick_at_or_after
from .indices import seconds

# (pass 94) an outage holding no sample at every rate a choice gives was taken: its sampling decides it
OUTAGE_DECIDERS = {f"sensors.{s}_outage": (f"sensors.{s}_rate", f"sensors.{s}_latency", CONTROLLER_PREFIX +
                                            "control.period") for s in ("star_tracker", "tracker")}


def idle_outage(key, values, dispersed, unread, takes=None):
    """(pass 93) Why an outage key acts on nothing: with its tracker's rate, latency, the control period and the
    run's length fixed, it takes or drops no sample delivered while a figure can read it (_delivered); (pass 96)
    with any of the three drawn from a range, none of any rate, period and latency in it can (_no_sample_in)."""
    sensor = {"sensors.star_tracker_outage": "star_tracker", "sensors.tracker_outage": "tracker"}.get(key)
    keys = (f"sensors.{sensor}_rate", CONTROLLER_PREFIX + "control.period", f"sensors.{sensor}_latency", "sim.duration")
    if sensor is None or keys[3] in dispersed or not all(k in values for k in (keys[0], keys[1], keys[3])):
        return None
    start, end = (float(x) for x in str(values[key]).strip("[]").split(","))
    duration = float(values[keys[3]])
    given = _Given(takes, values, dispersed)
    given_each = [given.intervals(k, 0.0 if k == keys[2] else None) for k in keys[:3]]
    if not end > start or any(g is None or len(g) != 1 for g in given_each):
        return None  # a list of values is judged value by value (own deciders: _idle_keys), a range here
    spans = [g[0] for g in given_each]
    (r_lo, r_hi), (t_lo, t_hi), (l_lo, l_hi) = spans
    if (r_lo, t_lo, l_lo) != (r_hi, t_hi, l_hi):
        if not _no_sample_in(start, end, duration, spans, unread):
            return None
        return (f"{key} [{seconds(start)}, {seconds(end)}] s takes and drops no sample a figure of the run reads "
                f"for every {given.text(keys[:3], ('Hz', 's', 's'))}: it would change nothing but its flag")
    rate, period, latency = r_lo, t_lo, l_lo
    n = _delivered(0.0, 0.0, duration, rate, period, latency, unread, most=10**6) if duration * rate <= 1e5 else None
    if n is None or _delivered(start, end, duration, rate, period, latency, unread, n + 1) != n:
        return None
    return (f"{key} [{seconds(start)}, {seconds(end)}] s takes and drops no sample a figure of the run reads (one "
            f"every {seconds(1.0 / rate)} s, latency {seconds(latency)} s): it would change nothing but its flag")


def _no_sample_in(start, end, duration, spans, unread):
    """Whether, for every rate and latency within spans ((lo, hi) each) at a fixed control period, no sample that
    can act is taken or falls due in the outage [start, end]: sample j (at j / rate) is taken at the first tick at
    or after it and falls due at the first at or after j / rate + latency (sample_schedule.hpp), each a range of
    ticks over the spans; one whose ranges meet the outage's ticks acts (in doubt: acts). A period drawn from a
    range is not judged."""
    (r_lo, r_hi), (period, t_hi), (l_lo, l_hi) = spans
    if not (0.0 < r_lo and 0.0 < period == t_hi and 0.0 <= l_lo) or duration * r_hi > 1e6:
        return False  # not judged (too many samples to go through)
    first, last = _outage_ticks(start, end, period)
    if first > last:  # (pass 104) between two ticks: no sample is taken or falls due in it, at any rate or latency
        return True
    acting = _last_acting_tick(duration, period, unread)
    j = 0
    while _tick_at_or_after(j / r_hi, period) <= acting:
        take = _tick_at_or_after(j / r_hi, period), _tick_at_or_after(j / r_lo, period)
        due = _tick_at_or_after(j / r_hi + l_lo, period), _tick_at_or_after(j / r_lo + l_hi, period)
        if due[0] <= acting and take[0] <= last and take[1] >= first or due[0] <= min(last, acting) and due[1] >= first:
            return False
        j += 1
    return True
