"""An outage key that acts on nothing: the star tracker's or the boresight
tracker's outage window that takes and drops no sample a figure of the run
reads, judged at each value of its sampling a study gives (_idle_keys)."""

from ._closed_spec import CONTROLLER_PREFIX
from ._idle_sensors import _delivered
from .indices import seconds

# (pass 94) an outage holding no sample at every rate a choice gives was taken: its sampling decides it
OUTAGE_DECIDERS = {f"sensors.{s}_outage": (f"sensors.{s}_rate", f"sensors.{s}_latency", CONTROLLER_PREFIX +
                                            "control.period") for s in ("star_tracker", "tracker")}


def idle_outage(key, values, dispersed, unread):
    """(pass 93) Why an outage key acts on nothing: with its tracker's rate, latency, the control period and the
    run's length fixed, it takes or drops no sample delivered while a figure can read it (_delivered)."""
    sensor = {"sensors.star_tracker_outage": "star_tracker", "sensors.tracker_outage": "tracker"}.get(key)
    keys = (f"sensors.{sensor}_rate", CONTROLLER_PREFIX + "control.period", f"sensors.{sensor}_latency", "sim.duration")
    if sensor is None or set(keys) & dispersed or not all(k in values for k in (keys[0], keys[1], keys[3])):
        return None
    start, end = (float(x) for x in str(values[key]).strip("[]").split(","))
    rate, period, latency, duration = (float(values.get(k, 0.0)) for k in keys)
    n = _delivered(0.0, 0.0, duration, rate, period, latency, unread, most=10**6) if duration * rate <= 1e5 else None
    if not end > start or n is None or _delivered(start, end, duration, rate, period, latency, unread, n + 1) != n:
        return None
    return (f"{key} [{seconds(start)}, {seconds(end)}] s takes and drops no sample a figure of the run reads (one "
            f"every {seconds(1.0 / rate)} s, latency {seconds(latency)} s): it would change nothing but its flag")
