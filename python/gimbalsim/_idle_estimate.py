"""Keys that act only through the controller's attitude estimate: the star
tracker's, the gyro's and the estimator's gains. The estimate reaches the
plant only in inertial pointing (the joint references), through the model
feed-forward (the base's rate) or in the loop at the antenna (the load's rate:
the antenna gyro's less the base's); otherwise only the knowledge index reads
it (controllers/src/inertial_reference.cpp, tracker_fusion.cpp)."""
from ._closed_spec import CONTROLLER_PREFIX
from ._idle_antenna import open_at_antenna

ESTIMATE_KEYS = ("sensors.star_tracker_rate", "sensors.star_tracker_noise", "sensors.star_tracker_latency",
                 "sensors.star_tracker_outage", "sensors.gyro_bias", "sensors.gyro_bias_walk", "sensors.gyro_noise",
                 CONTROLLER_PREFIX + "estimator.k_p", CONTROLLER_PREFIX + "estimator.k_i")
_MODE, _FEEDFORWARD = CONTROLLER_PREFIX + "pointing.mode", CONTROLLER_PREFIX + "pointing.accel_feedforward"


def idle_estimate(key, values, dispersed, truth_only):
    """Why a key of the attitude estimate acts on nothing a figure reads:
    the figures read the truth alone (truth_only: no knowledge index) and
    the estimate reaches no command; else None (also when a decider is
    dispersed: not judged here)."""
    if not truth_only or key not in ESTIMATE_KEYS or {_MODE, _FEEDFORWARD} & dispersed:
        return None
    mode, feedforward = str(values.get(_MODE, "inertial")), str(values.get(_FEEDFORWARD, "model"))
    at_antenna = open_at_antenna(values, dispersed)
    if mode != "joint" or feedforward == "model" or at_antenna is None:
        return None
    return (f"the controller's pointing.mode joint with pointing.accel_feedforward {feedforward} and no loop at "
            f"the antenna ({at_antenna}): the attitude estimate reaches no command; only the knowledge "
            "index reads it, and the study has none")
