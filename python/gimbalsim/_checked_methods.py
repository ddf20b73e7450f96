"""The methods of the extension's Simulator and Controller whose number
arguments are checked in Python before the binding converts them: pybind11
takes a bool as 1.0 (True ran as t = 1 s, pass 82) and numpy drops a
complex's imaginary part. install() puts them in place."""
import numpy as np

from . import _gimbalsim
from ._gimbalsim import COLUMNS
from ._arguments import real_array as _real_array, real_number as _real_number, scene_argument as _scene_argument
from ._arguments import flag_list as _flag_list, real_list as _real_list, whole_number as _whole_number

_simulator_init, _simulator_run, _simulator_step = (_gimbalsim.Simulator.__init__, _gimbalsim.Simulator.run,
                                                    _gimbalsim.Simulator.step)


def _init(self, scene):
    """A simulator at the scene's initial state (scene: a gimbalsim.Scene)."""
    _simulator_init(self, _scene_argument(scene, "Simulator"))


def _run(self, torques):
    """One step per row of torques (N, 2) [N m]; returns the (N, len(COLUMNS)) output rows after each step."""
    _fits_in_memory(torques)
    return _simulator_run(self, _real_array(torques, "torques [N m]"))


def _fits_in_memory(torques):
    """MemoryError before any copy when the torques' float copy and the output rows would not fit in the
    machine's free memory now: a broadcast view of 1e9 rows (16 bytes itself) grew the process until the kernel killed
    it (the arrays are committed page by page, so allocating them never failed). The whole-run calls' check."""
    shape = np.shape(torques)
    if len(shape) != 2:
        return  # the binding names the shape it needs
    _gimbalsim._fits_in_memory(float(shape[0]) * (shape[1] + len(COLUMNS)) * 8, f"torques [N m]: {shape[0]} rows",
                               f"their float copy and {len(COLUMNS)} output columns a row",
                               ": run them in parts (each run() goes on from where the last one ended)")


def _step(self, tau1, tau2, n=1):
    """Advance n steps with joint torques tau1, tau2 [N m] held; raises
    SimulationStopped on numerical trouble (the state is then the last good one)."""
    return _simulator_step(self, _real_number(tau1, "tau1 [N m]"), _real_number(tau2, "tau2 [N m]"), n)


_controller_update = _gimbalsim.Controller.update


def _update(self, t, theta1, theta2, dtheta1=0.0, dtheta2=0.0, gyro=None):
    """One control period: time [s], encoder angles [rad], rates [rad/s], base rate gyro [rad/s] (base frame;
    None = no sample); returns the command tau [N m] and what it saw. True is no time or angle (it ran as
    t = 1 s and commanded 50 N m, pass 82), as it is no torque of Simulator.step."""
    given = {"t [s]": t, "theta1 [rad]": theta1, "theta2 [rad]": theta2,
             "dtheta1 [rad/s]": dtheta1, "dtheta2 [rad/s]": dtheta2}
    t, theta1, theta2, dtheta1, dtheta2 = (_real_number(v, name) for name, v in given.items())
    if gyro is not None:
        gyro = [_real_number(g, f"gyro[{i}] [rad/s]") for i, g in enumerate(_three(gyro, "gyro [rad/s]"))]
    return _controller_update(self, t, theta1, theta2, dtheta1, dtheta2, gyro)


_state_init = _gimbalsim.State.__init__


def _state(self, variant, t, q, v, in_contact=(), v0=(), friction_mode=0, vt_floor=0.0, h_next=0.0):
    """A checkpoint from its fields (a pickle calls this too), checked as a scene is (ValueError naming the field);
    a field of the wrong type is a TypeError naming it: numpy dropped a complex q's imaginary part, pybind11
    took friction_mode=True as 1 and a contact flag 2.5 as True."""
    if not isinstance(variant, str):
        raise TypeError(f"State.variant: expected a variant name, got {type(variant).__name__} {variant!r:.80}")
    friction_mode = _whole_number(friction_mode, "State.friction_mode")
    if not -2**31 <= friction_mode < 2**31:  # past C's int, pybind11 listed its signatures
        raise ValueError(f"State.friction_mode = {friction_mode}: must be -1, 0 or 1")
    _state_init(self, variant, _real_number(t, "State.t"), _real_list(q, "State.q"), _real_list(v, "State.v"),
                _flag_list(in_contact, "State.in_contact"), _real_list(v0, "State.v0"), friction_mode,
                _real_number(vt_floor, "State.vt_floor"), _real_number(h_next, "State.h_next"))


def _three(values, name):
    """values, a sequence of 3 (x, y, z): a number, a 0-d array or another length got numpy's "iteration over a
    0-d array" or pybind11's signatures, naming no argument."""
    try:
        n = None if isinstance(values, (str, bytes)) else len(values)
    except TypeError:  # a number, a 0-d array
        n = None
    if n is None:
        raise TypeError(f"{name}: expected 3 real numbers (x, y, z), got {type(values).__name__} {values!r:.80}")
    if n != 3:
        raise ValueError(f"{name}: expected 3 real numbers (x, y, z), got {n}")
    return values


def install():
    """The checked methods in place of the binding's (called once, by the package)."""
    _gimbalsim.State.__init__ = _state
    _gimbalsim.Simulator.__init__, _gimbalsim.Simulator.run, _gimbalsim.Simulator.step = _init, _run, _step
    _gimbalsim.Controller.update = _update
