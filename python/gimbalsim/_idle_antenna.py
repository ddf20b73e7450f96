"""The antenna's keys where the loop does not close at the antenna: the
scene's antenna sensors and the controller's antenna.* keys act only
together (MODEL.md 11.6, 11.7)."""
from ._closed_spec import CONTROLLER_PREFIX

# The antenna's sensors (MODEL.md 11.6) and the controller's loop at the antenna (MODEL.md 11.7): they act
# only together, a scene with sensors.antenna tracker_gyro and a controller with antenna.tracker use.
ANTENNA_SENSOR_KEYS = ("sensors.antenna", "sensors.tracker_")
_ANTENNA_CONTROLLER = CONTROLLER_PREFIX + "antenna."
ANTENNA_TRACKER = CONTROLLER_PREFIX + "antenna.tracker"


def idle_at_antenna(key, values, dispersed):
    """Why an antenna sensor key (sensors.antenna*, sensors.tracker_*) or a
    controller antenna.* key cannot act: the loop does not close at the
    antenna (open_at_antenna; the key itself decides nothing)."""
    if not key.startswith(ANTENNA_SENSOR_KEYS + (_ANTENNA_CONTROLLER,)):
        return None
    return open_at_antenna(values, dispersed, key)


def open_at_antenna(values, dispersed, deciding=None):
    """Why the loop does not close at the antenna, or None when it does (or
    may: a decider dispersed): it closes only with the scene's
    sensors.antenna tracker_gyro and the controller's antenna.tracker use.
    deciding: a decider not judged here (the key being judged)."""
    if deciding != "sensors.antenna" and "sensors.antenna" not in dispersed and \
            str(values.get("sensors.antenna", "none")) != "tracker_gyro":
        return "the scene's sensors.antenna is none: no sensor on the antenna, the loop closes on the encoders"
    if deciding != ANTENNA_TRACKER and ANTENNA_TRACKER not in dispersed and \
            str(values.get(ANTENNA_TRACKER, "use")) != "use":
        return "the controller's antenna.tracker is ignore: it reads no antenna sensor"
    return None
