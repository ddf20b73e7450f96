"""An outage key that acts on nothing: the star tracker's or the boresight
tracker's outage window that takes and drops no sample a figure of the run
reads, judged at each value of its sampling a study gives (_idle_keys)."""

from ._closed_spec import CONTROLLER_PREFIX
from ._idle_sensors import _delivered, _Given
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
    """Whether, for every rate, control period and latency within spans ((lo, hi) each), no sample that can act
    is taken or falls due in the outage [start, end]: sample j (at j / rate) is taken within a period after it
    and falls due latency later, rounded up to a tick; one that may touch the outage acts (in doubt: acts)."""
    (r_lo, r_hi), (t_lo, t_hi), (l_lo, l_hi) = spans
    if not (0.0 < r_lo and 0.0 < t_lo and 0.0 <= l_lo):
        return False
    late = duration - unread * t_lo + 1e-9 * duration  # beyond it, past the last acting tick at any period
    if late * r_hi > 1e6:
        return False  # too many samples to go through: not judged
    j = 0
    while j / r_hi <= late:
        take_lo, take_hi = (0.0, 0.0) if j == 0 else (j / r_hi, j / r_lo + t_hi)
        due_lo, due_hi = take_lo + l_lo, take_hi + l_hi + t_hi
        if due_lo <= late and (take_lo <= end and take_hi >= start or due_lo <= end and due_hi >= start):
            return False
        j += 1
    return True
