"""Closed-loop sweep specs refused at their line: unknown and out-of-range
keys, keys a closed loop or the controller's own settings never read (a
dispersed value would be recorded but never act), indices and phases the run
cannot support."""
import pytest

from conftest import CONTROLLER_CONFIG
from test_sweep_closed import DURATION, SPEC

REFUSALS = [
    ("controller_set: {profile.slew_start: 0.0,", "controller_set: {nope.key: 1,", "controller_set.nope.key",
     "not a key of the controller"),
    # (pass 114) a grid point given twice ran its units twice into one pooled budget, in any spelling of it
    (("phases: [", "phases: ["), ("grid:\nphases: [", "  controller.elevation.kp: [2000.0, 3000.0, 2000]\nphases: ["),
     "grid.controller.elevation.kp", "2000 given twice (items 1 and 3): a grid point runs once"),
    (("phases: [", "phases: ["), ("grid:\nphases: [", "  sensors.gyro_noise: [0.0, -0.0]\nphases: ["),
     "grid.sensors.gyro_noise", "-0.0 given twice (items 1 and 2)"),
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}", "  controller.nope: {uniform: [1.0, 2.0]}",
     "parameters.controller.nope", "not a key of the controller configuration"),
    (("phases: [", "phases: ["), ("grid:\nphases: [", "  controller.azimuth.kpp: [2000.0, 4000.0]\nphases: ["),
     "grid.controller.azimuth.kpp",
     "not a key of the controller configuration (see gimbalsim.controller_keys() or docs/controller_keys.md): "
     "azimuth.kpp"),
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}", "  controller.azimuth.kp: {uniform: [-5.0, 4000.0]}",
     "parameters.controller.azimuth.kp", "the controller refuses"),
    ("controller_set: {profile.slew_start: 0.0,", "controller_set: {azimuth.kp: -1.0, profile.slew_start: 0.0,",
     "controller_set.azimuth.kp", "the controller refuses"),
    ("  rpe: {window: 0.05}", "  rpe: {}", "indices.rpe.window", "missing"),
    # keys a closed loop never reads: a dispersed value would be recorded, never act
    # a profile key whose segment begins after the run's end, for every value drawn (the spec's profile: slew
    # [0, 0.2), hold to 0.3 s, track after; the run ends at 0.5 s)
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}", "  controller.profile.hold_time: {uniform: [0.35, 0.6]}",
     "parameters.controller.profile.hold_time", "the track it shapes begins at 0.55 s at the earliest"),
    # ... judged with the lowest of each key that places the segment, dispersed or not
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}",
     "  controller.profile.track_ramp_time: {uniform: [1.0, 8.0]}\n  controller.profile.hold_time: {choice: [0.4, 0.5]}",
     "parameters.controller.profile.track_ramp_time", "the track it shapes begins at 0.6000000000000001 s at the earliest"),
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}", "  controller.profile.slew_start: {uniform: [0.6, 0.9]}",
     "parameters.controller.profile.slew_start", "the slew it shapes begins at 0.6 s at the earliest"),
    # (pass 53) ... or at it: the last tick sees the angle before the segment, its command acts after the run
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}", "  controller.profile.slew_start: {uniform: [0.5, 0.9]}",
     "parameters.controller.profile.slew_start", "the slew it shapes begins at 0.5 s at the earliest"),
    # (pass 55) a dispersed profile key is judged at its range's ends: refused where every value misses a phase
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}", "  controller.profile.slew_time: {uniform: [1.0, 2.0]}",
     "parameters.controller.profile.slew_time", "at every value tried (its range's ends): the run ends at "
     "sim.duration 0.5 s, inside phase 'slew' [0, 1) s: its indices would be NaN for every sample"),
    # (pass 55) a motor limit above the controller's own on both axes, at every value: it clips nothing
    ("  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "  torque.limit: {choice: [[100.0, 100.0], [500.0, 500.0]]}",
     "parameters.torque.limit", "every value given is at or above the controller's own command limits"),
    ("  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "  sim.duration: {uniform: [0.4, 0.5]}",
     "parameters.sim.duration",
     "not read by this sweep's runs (every closed loop of a study runs one length: a sweep's set: sim.duration"),
    ("  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "  torque.tau2: {uniform: [1.0, 2.0]}",
     "parameters.torque.tau2", "the controller commands the torque"),
    ("  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "  sim.output_interval: {choice: [0.001, 0.01]}",
     "parameters.sim.output_interval", "the closed loop records every control period"),
    # (pass 56) a step drawn from a range divides no control period: every sample was refused at its run
    ("  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "  sim.step: {uniform: [1.0e-4, 1.0e-3]}",
     "parameters.sim.step", "uniform: a closed loop's sim.step is given as a choice of steps that divide "
     "control.period"),
    # ... and the same keys under set: (scene keys given for every sample), whatever their value
    ("set: {sim.duration: 0.5}", "set: {sim.duration: 0.5, torque.tau1: 2.0}", "set.torque.tau1",
     "not read by this sweep's runs (the controller commands the torque): the value given would be recorded"),
    ("set: {sim.duration: 0.5}", "set: {sim.duration: 0.5, sim.output_interval: 0.01}", "set.sim.output_interval",
     "not read by this sweep's runs (the closed loop records every control period)"),
    ("set: {sim.duration: 0.5}", "set: {sim.duration: 0.5, sim.momentum_tol: 1.0e-3}", "set.sim.momentum_tol",
     "not read by this sweep's runs (the closed loop checks no invariant"),
    # ... and a controller_set key another setting switches off, as the same key under parameters
    ("controller_set: {", "controller_set: {pointing.accel_feedforward: profile, plant.base_mass: 500, ",
     "controller_set.plant.base_mass", "not read by this sweep's runs (the controller reads it only with "
     "pointing.accel_feedforward model; it has pointing.accel_feedforward profile)"),
    ("controller_set: {", "controller_set: {control.anti_windup: clamping, azimuth.aw_gain: 5, ",
     "controller_set.azimuth.aw_gain", "reads it only with control.anti_windup back_calculation"),
    # a controller key another setting switches off (the status rates are used, not the differenced ones)
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}", "  controller.control.rate_filter_hz: {uniform: [60, 190]}",
     "parameters.controller.control.rate_filter_hz", "reads it only with control.rate_source difference"),
    # the anti-windup gain acts only under back-calculation
    (("controller_set: {", "  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}"),
     ("controller_set: {control.anti_windup: clamping, ", "  controller.azimuth.aw_gain: {uniform: [1, 30]}"),
     "parameters.controller.azimuth.aw_gain", "reads it only with control.anti_windup back_calculation"),
    # ... also when the setting is dispersed over values none of which reads it
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}",
     "  controller.azimuth.aw_gain: {uniform: [1, 30]}\n  controller.control.anti_windup: {choice: [clamping, none]}",
     "parameters.controller.azimuth.aw_gain", "for every value of controller.control.anti_windup the study gives"),
    # under the model feed-forward (the default) the fixed-base inertia law and the base-rate filter are off
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}",
     "  controller.gimbal.azimuth_inertia_cos2: {uniform: [1.0, 9.0]}",
     "parameters.controller.gimbal.azimuth_inertia_cos2", "with pointing.accel_feedforward profile or inertial"),
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}",
     "  controller.pointing.base_accel_filter_hz: {uniform: [10.0, 90.0]}",
     "parameters.controller.pointing.base_accel_filter_hz", "with pointing.accel_feedforward inertial; it has pointing.accel_feedforward model"),
    # ... and under another feed-forward the plant model is off
    (("controller_set: {", "  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}"),
     ("controller_set: {pointing.accel_feedforward: profile, ", "  controller.plant.base_mass: {uniform: [900, 1100]}"),
     "parameters.controller.plant.base_mass", "reads it only with pointing.accel_feedforward model; it has pointing.accel_feedforward profile"),
    # a star tracker that is out for the whole run takes no sample: its noise never acts
    (("set: {sim.duration: 0.5}", "  sensors.star_tracker_noise:"),
     ("set: {sim.duration: 0.5, sensors.star_tracker_outage: [0.0, 0.5]}", "  sensors.star_tracker_noise:"),
     "parameters.sensors.star_tracker_noise", "covers the whole run"),
    # ... also when the outage is dispersed over values that all cover the run, or no sample is delivered in it
    (("  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}",),
     ("  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}\n"
      "  sensors.star_tracker_outage: {choice: [[0.0, 1.0e9], [0.0, 5.0]]}",),
     "parameters.sensors.star_tracker_noise", "for every value of sensors.star_tracker_outage the study gives"),
    (("set: {sim.duration: 0.5}", "  sensors.star_tracker_noise:"),
     ("set: {sim.duration: 0.5, sensors.star_tracker_latency: 0.6}", "  sensors.star_tracker_noise:"),
     "parameters.sensors.star_tracker_noise", "no shorter than the run (0.5 s): no star tracker sample is delivered"),
    # the estimator's gains act only on the star tracker's samples
    (("set: {sim.duration: 0.5}", "  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}"),
     ("set: {sim.duration: 0.5, sensors.star_tracker_outage: [0.0, 0.5]}",
      "  controller.estimator.k_p: {uniform: [0.1, 1.0]}"),
     "parameters.controller.estimator.k_p", "covers the whole run"),
    # the joint mode with the profile's feed-forward reads no gimbal geometry
    (("controller_set: {", "  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}"),
     ("controller_set: {pointing.mode: joint, pointing.accel_feedforward: profile, ",
      "  controller.gimbal.joint1_axis: {choice: [[0, 0, 1], [0, 0.2, 1]]}"),
     "parameters.controller.gimbal.joint1_axis", "reads it only with pointing.mode inertial or with "
     "pointing.accel_feedforward model"),
    # the boresight is read only by the inertial mode's IK: the joint mode's model feed-forward (the default)
    # computes the plant's dynamics, which no boresight enters (controllers/src/model_feedforward.cpp)
    (("controller_set: {", "  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}"),
     ("controller_set: {pointing.mode: joint, ",
      "  controller.gimbal.boresight: {choice: [[1, 0, 0], [1, 0.1, 0]]}"),
     "parameters.controller.gimbal.boresight", "reads it only with pointing.mode inertial; it has pointing.mode joint"),
    # the closed loop checks no invariant (firmware_sim steps without dynamics' InvariantMonitor)
    ("  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "  sim.momentum_tol: {choice: [0.0, 1.0e-300]}",
     "parameters.sim.momentum_tol", "the closed loop checks no invariant"),
    ("  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "  sim.energy_tol: {choice: [0.0, 1.0e-300]}",
     "parameters.sim.energy_tol", "the closed loop checks no invariant"),
    # the contact's stops and work cap with both joints ideal: there is no contact
    (("set: {sim.duration: 0.5}", "  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}"),
     ("set: {sim.duration: 0.5, structure.joint2: ideal}", "  sim.penetration_limit: {choice: [0.0, 1.0e-3]}"),
     "parameters.sim.penetration_limit", "both joints are ideal: no contact, nothing penetrates"),
    (("set: {sim.duration: 0.5}", "  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}"),
     ("set: {sim.duration: 0.5, structure.joint2: ideal}", "  sim.max_substeps: {choice: [0, 100]}"),
     "parameters.sim.max_substeps", "both joints are ideal: no contact to sub-step"),
    # every sensor noise 0: the seed draws nothing that acts
    ("  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}", "  sensors.seed: {choice: [1, 2]}",
     "parameters.sensors.seed", "is 0: nothing random to seed"),
    # ... also when the one noise dispersed is 0 in every value the study gives
    ("  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}",
     "  sensors.seed: {choice: [1, 2]}\n  sensors.gyro_noise: {choice: [0.0]}",
     "parameters.sensors.seed", "for every value of sensors.gyro_noise the study gives"),
    # ... and when the only noise is the antenna's, which the controller does not read
    (("set: {sim.duration: 0.5}", "  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}"),
     ("set: {sim.duration: 0.5, sensors.tracker_noise: 1.0e-3, sensors.antenna_gyro_noise: 1.0e-4}",
      "  sensors.seed: {choice: [1, 2]}"),
     "parameters.sensors.seed", "is 0: nothing random to seed"),
    # (pass 112) joint pointing with the profile's feed-forward and no loop at the antenna: the attitude estimate
    # reaches no command; without a knowledge index the attitude sensors' and the estimator's keys act on nothing
    (("  knowledge: {requirement: 1.0e-12}", "controller_set: {",
      "  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}"),
     ("", "controller_set: {pointing.mode: joint, pointing.accel_feedforward: profile, ",
      "  sensors.gyro_noise: {uniform: [0.0, 1.0e-2]}"),
     "parameters.sensors.gyro_noise", "the attitude estimate reaches no command; only the knowledge index reads it"),
    (("  knowledge: {requirement: 1.0e-12}", "controller_set: {",
      "  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}"),
     ("", "controller_set: {pointing.mode: joint, pointing.accel_feedforward: profile, ",
      "  controller.estimator.k_i: {uniform: [0.0, 1.0]}"),
     "parameters.controller.estimator.k_i", "pointing.mode joint with pointing.accel_feedforward profile and no "
     "loop at the antenna (the scene's sensors.antenna is none: no sensor on the antenna, the loop closes on the "
     "encoders): the attitude estimate reaches no command"),
    # the scene's label: no run reads it
    ("  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "  name: {choice: [a, b]}", "parameters.name",
     "the scene's label: no run reads it"),
    # the antenna's sensors and the controller's loop at the antenna act only together: a scene with
    # sensors.antenna tracker_gyro and a controller with antenna.tracker use
    ("  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}", "  sensors.tracker_noise: {uniform: [0.0, 2.0e-5]}",
     "parameters.sensors.tracker_noise", "the scene's sensors.antenna is none: no sensor on the antenna"),
    ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}", "  controller.antenna.bandwidth: {uniform: [8, 12]}",
     "parameters.controller.antenna.bandwidth", "the scene's sensors.antenna is none"),
    (("set: {sim.duration: 0.5}", "controller_set: {", "  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}"),
     ("set: {sim.duration: 0.5, sensors.antenna: tracker_gyro}", "controller_set: {antenna.tracker: ignore, ",
      "  sensors.tracker_noise: {uniform: [0.0, 2.0e-5]}"),
     "parameters.sensors.tracker_noise", "the controller's antenna.tracker is ignore: it reads no antenna sensor"),
    ("controller_set: {", "controller_set: {antenna.tracker: ignore, ",
     "controller_set.antenna.tracker", "the scene's sensors.antenna is none"),
    # the boresight tracker out for the whole run: its noise never acts, nor a seed only it would read
    (("set: {sim.duration: 0.5}", "  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}"),
     ("set: {sim.duration: 0.5, sensors.antenna: tracker_gyro, sensors.tracker_outage: [0, 100]}",
      "  sensors.tracker_noise: {uniform: [0.0, 2.0e-5]}"),
     "parameters.sensors.tracker_noise",
     "sensors.tracker_outage [0, 100] s covers the whole run: no boresight tracker sample is taken"),
    (("set: {sim.duration: 0.5}", "  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}"),
     ("set: {sim.duration: 0.5, sensors.antenna: tracker_gyro, sensors.tracker_outage: [0, 100], "
      "sensors.tracker_noise: 1.0e-5}", "  sensors.seed: {choice: [1, 2]}"),
     "parameters.sensors.seed", "is 0: nothing random to seed"),
    # a journal that cannot tilt (joint 2 planar)
    ("  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}", "  initial.tilt2: {disk: {radius: 1.0e-3}}",
     "parameters.initial.tilt2", "joint 2's bearing is planar: it cannot tilt"),
    ("  rpe: {window: 0.05}", "  rpe: {window: .nan}", "indices.rpe.window", "expected a finite number, got nan"),
    ("  ape: {level: 0.5, confidence: 0.5, requirement: 1.0}", "  ape: {level: 0.5, confidence: 0.5, requirement: .inf}",
     "indices.ape.requirement", "expected a number in (0.0, 3.141592653589793]"),
    ("  ape: {level: 0.5, confidence: 0.5, requirement: 1.0}", "  ape: {level: 0.5, confidence: 0.5, requirement: 1e400}",
     "indices.ape.requirement", "float '1e400' does not read: it is beyond the largest double"),  # (pass 38: 'inf')
    # a requirement of 0 or -0 rad: every unit fails, a verdict from no question
    ("  ape: {level: 0.5, confidence: 0.5, requirement: 1.0}", "  ape: {level: 0.5, confidence: 0.5, requirement: -0.0}",
     "indices.ape.requirement", "expected a number in (0.0, 3.141592653589793], got -0.0"),
    # NaN is refused with the same range (it said ">= 0.0", a range that took 0)
    ("  ape: {level: 0.5, confidence: 0.5, requirement: 1.0}", "  ape: {level: 0.5, confidence: 0.5, requirement: .nan}",
     "indices.ape.requirement", "expected a number in (0.0, 3.141592653589793], got nan"),
    # above pi rad (no pointing error is larger) every unit meets it: PASS from no question (pass 70: 1e308)
    ("  ape: {level: 0.5, confidence: 0.5, requirement: 1.0}", "  ape: {level: 0.5, confidence: 0.5, requirement: 1e308}",
     "indices.ape.requirement", "expected a number in (0.0, 3.141592653589793], got 1e+308"),
    ("  ape: {level: 0.5, confidence: 0.5, requirement: 1.0}", "  ape: {level: 0.5, confidence: 0.5, requirement: 3.2}",
     "indices.ape.requirement", "expected a number in (0.0, 3.141592653589793], got 3.2"),
    ("  rpe: {window: 0.05}", "  rpe: {window: 0.0505}", "indices.rpe.window", "whole number of control periods"),
    # the C++ keys' whole-multiple rule (relative 1e-12), not a looser one of the spec's own
    ("  rpe: {window: 0.05}", "  rpe: {window: 0.05000000001}", "indices.rpe.window",
     "whole number of control periods"),
    ("  rpe: {window: 0.05}", "  rpe: {window: 0.05, span: 2}", "indices.rpe.span", "unknown key"),
    ("  rpe: {window: 0.05}", "  rms: {window: 0.05}", "indices.rms", "unknown index"),
    ("  ape: {level: 0.5, confidence: 0.5, requirement: 1.0}", "  ape: {level: 1.5}", "indices.ape.level",
     "expected a number"),
    ("phases: [slew, hold, track, {late: [0.4, 0.5]}]", "phases: [slew, cruise]", "phases", "unknown phase 'cruise'"),
    # (pass 78) a window of its own named as a profile phase: reported as the profile's track, its window unsaid
    ("phases: [slew, hold, track, {late: [0.4, 0.5]}]", "phases: [{track: [0.36, 0.39]}]", "phases.track",
     "'track' is the profile's own phase (give it bare, as track); name a window of your own otherwise"),
    ("phases: [slew, hold, track, {late: [0.4, 0.5]}]", "phases: [{late: [6.0, 5.0]}]", "phases.late",
     "expected [t0, t1] in s with 0 <= t0 < t1, got [6.0, 5.0]"),
    # (pass 60) an end that is not finite was told "0 <= t0 < t1", which [0.1, inf] meets
    ("phases: [slew, hold, track, {late: [0.4, 0.5]}]", "phases: [{late: [0.1, .inf]}]", "phases.late",
     "expected [t0, t1], two finite times in s, got [0.1, inf] (a phase to the run's end ends at sim.duration)"),
    ("phases: [slew, hold, track, {late: [0.4, 0.5]}]", "phases: [{late: [0.1, .nan]}]", "phases.late",
     "two finite times in s, got [0.1, nan]"),
    # a run that ends before or inside a phase, or a phase shorter than an index's window
    ("phases: [slew, hold, track, {late: [0.4, 0.5]}]", "phases: [slew, hold, track, {late: [5.0, 6.0]}]",
     "phases.late", "the run ends at sim.duration 0.5 s, before phase 'late' [5, 6) s"),
    ("phases: [slew, hold, track, {late: [0.4, 0.5]}]", "phases: [slew, {late: [0.4, 0.6]}]",
     "phases.late", "the run ends at sim.duration 0.5 s, inside phase 'late' [0.4, 0.6) s"),
    # a phase between two ticks: no sample could have a figure there
    ("phases: [slew, hold, track, {late: [0.4, 0.5]}]", "phases: [slew, hold, track, {late: [0.4001, 0.4009]}]",
     "phases.late", "phase 'late' [0.4001, 0.4009) s holds no control tick (one every 0.001 s)"),
    ("  pde: {window: 0.02, separation: 0.05}", "  pde: {window: 0.06, separation: 0.05}", "indices.pde",
     "the window 0.06 s plus separation 0.05 s is longer than phase 'hold' [0.2, 0.30000000000000004) s of this run"),
    # a window or separation longer than the run: said so, not "not whole control periods" (1e300) or "not finite"
    ("  pde: {window: 0.02, separation: 0.05}", "  pde: {window: 0.02, separation: 1e300}", "indices.pde.separation",
     "1e+300 s is longer than the run (sim.duration 0.5 s): no phase can hold it"),
    ("  pde: {window: 0.02, separation: 0.05}", "  pde: {window: 1e300, separation: 0.05}", "indices.pde.window",
     "1e+300 s is longer than the run (sim.duration 0.5 s)"),
    ("  pde: {window: 0.02, separation: 0.05}", "  pde: {window: 0.02, separation: .inf}", "indices.pde.separation",
     "inf s is longer than the run (sim.duration 0.5 s)"),
    ("  rpe: {window: 0.05}", "  rpe: {window: 1e300}", "indices.rpe.window",
     "1e+300 s is longer than the run (sim.duration 0.5 s)"),
    ("  rpe: {window: 0.05}", "  rpe: {window: .inf}", "indices.rpe.window", "inf s is longer than the run"),
    (f"controller: {CONTROLLER_CONFIG}", "controller: no_such.yaml", "controller", "no such file"),
    # a folder or a device is there but holds no file: said so, not "no such file"
    (f"controller: {CONTROLLER_CONFIG}", "controller: /tmp", "controller", "/tmp is a folder; expected a file"),
    (f"controller: {CONTROLLER_CONFIG}", "controller: /dev/null", "controller",
     "/dev/null is not a regular file (a pipe or a device); expected a file"),
    # a name longer than the file system allows (found by fuzz_spec): refused, not an OSError
    (f"controller: {CONTROLLER_CONFIG}", "controller: " + "x" * 300 + ".yaml", "controller",
     "not a usable file path (File name too long)"),
    (f"controller: {CONTROLLER_CONFIG}\n", "", "controller_set", "only for a closed-loop sweep"),
    (f"set: {{sim.duration: 0.5}}\ncontroller: {CONTROLLER_CONFIG}\ncontroller_set: {{profile.slew_start: 0.0, "
     "profile.slew_time: 0.2, profile.hold_time: 0.1}",
     f"set: {{sim.duration: 0.501}}\ncontroller: {CONTROLLER_CONFIG}\ncontroller_set: {{control.period: 0.002}}",
     "set.sim.duration", "whole control periods"),
]


@pytest.mark.parametrize("old,new,key,message", REFUSALS)
def test_a_bad_key_is_refused_at_its_line(tmp_path, old, new, key, message):
    from gimbalsim.sweep import SpecError, SweepSpec
    text = SPEC.replace(f"set: {{sim.duration: {DURATION}}}", "set: {sim.duration: 0.5}")
    # a tuple: several replacements, the refused line the last one's
    old, new = (old, new) if isinstance(old, tuple) else ((old,), (new,))
    for o, n in zip(old, new):
        assert o in text
        text = text.replace(o, n)
    new = new[-1]
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(SpecError) as e:
        SweepSpec(path)
    assert e.value.key == key, str(e.value)
    assert message in str(e.value)
    lines = text.split("\n")
    mark = new.strip().split("\n")[0] or key
    assert e.value.line == next(n for n, line in enumerate(lines, 1) if mark in line), str(e.value)


def test_a_grid_over_a_controller_key_is_taken_in_closed_loop(tmp_path):
    # it was checked against the scene's keys before the controller's were known: "not a key of the scene"
    from gimbalsim.sweep import SweepSpec
    text = SPEC.replace("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}\n", "")
    (tmp_path / "grid.yaml").write_text(text.replace("phases: [", "grid:\n  controller.azimuth.kp: [2000, 4000]\n"
                                                     "phases: [", 1))
    s = SweepSpec(tmp_path / "grid.yaml")
    assert s.grid == [("controller.azimuth.kp", [2000, 4000])] and len(s.design) == 12
    assert [s.design.draw(i)["controller.azimuth.kp"] for i in (0, 6)] == [2000, 4000]


def test_a_run_ending_before_the_profiles_track_is_refused_at_its_duration(tmp_path):
    from gimbalsim.sweep import SpecError, SweepSpec
    # no phases key: the profile's slew [0, 0.2), hold [0.2, 0.3) and track from 0.3 s
    text = SPEC.replace(f"set: {{sim.duration: {DURATION}}}", "set: {sim.duration: 0.3}")
    text = text.replace("phases: [slew, hold, track, {late: [0.4, 0.5]}]\n", "")
    text = text.replace("  rpe: {window: 0.05}\n  pde: {window: 0.02, separation: 0.05}\n", "")
    path = tmp_path / "short.yaml"
    path.write_text(text)
    with pytest.raises(SpecError) as e:
        SweepSpec(path)
    # the profile's track starts at 0.2 + 0.1 = 0.30000000000000004 s, which :g printed as 0.3; it runs to the
    # run's end, [t0, inf) (pass 61: named [0.30000000000000004, 0.30000000100000004), a window of nothing)
    assert e.value.key == "sim.duration" and "before phase 'track' [0.30000000000000004, inf) s" in str(e.value), \
        str(e.value)
    assert e.value.line == text.split("\n").index("set: {sim.duration: 0.3}") + 1
    (tmp_path / "ok.yaml").write_text(text.replace("sim.duration: 0.3", "sim.duration: 0.32"))
    assert [p for p, _ in SweepSpec(tmp_path / "ok.yaml").closed.phases] == ["slew", "hold", "track"]
    # (pass 87) a track starting inside the last period: its first tick is the run's last, no figure either
    late = text.replace("profile.slew_start: 0.0,", "profile.slew_start: 0.0005,")  # the track from 0.3005 s
    (tmp_path / "last.yaml").write_text(late.replace("sim.duration: 0.3", "sim.duration: 0.301"))
    with pytest.raises(SpecError) as e:
        SweepSpec(tmp_path / "last.yaml")
    assert "at the first control tick of phase 'track'" in str(e.value), str(e.value)
    (tmp_path / "ok.yaml").write_text(late.replace("sim.duration: 0.3", "sim.duration: 0.302"))
    assert [p for p, _ in SweepSpec(tmp_path / "ok.yaml").closed.phases] == ["slew", "hold", "track"]


def test_an_empty_profile_phase_is_refused_when_named_and_left_out_otherwise(tmp_path):
    from gimbalsim.sweep import SpecError, SweepSpec
    # profile.hold_time 0: the hold [0.2, 0.2) s has no tick, so no sample could have a figure there.
    text = SPEC.replace("profile.hold_time: 0.1}", "profile.hold_time: 0.0}")
    text = text.replace("  pde: {window: 0.02, separation: 0.05}\n", "")
    (tmp_path / "named.yaml").write_text(text)
    with pytest.raises(SpecError) as e:
        SweepSpec(tmp_path / "named.yaml")
    assert e.value.key == "phases.hold" and "phase 'hold' [0.2, 0.2) s is empty" in str(e.value), str(e.value)
    assert e.value.line == text.split("\n").index("phases: [slew, hold, track, {late: [0.4, 0.5]}]") + 1
    (tmp_path / "default.yaml").write_text(text.replace("phases: [slew, hold, track, {late: [0.4, 0.5]}]\n", ""))
    assert [p for p, _ in SweepSpec(tmp_path / "default.yaml").closed.phases] == ["slew", "track"]


# Keys that act under other settings: a noise to seed, the boresight under the inertial mode.
READ = [("  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}",
         "  sensors.seed: {choice: [1, 2]}\n  sensors.gyro_noise: {choice: [0.0, 1.0e-6]}"),
        ("controller_set: {", "controller_set: {pointing.mode: inertial, "),
        ("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}",
         "  controller.gimbal.boresight: {choice: [[1, 0, 0], [1, 0.1, 0]]}")]


def test_a_seed_with_a_noise_and_a_boresight_under_the_inertial_mode_are_accepted(tmp_path):
    from gimbalsim.sweep import SweepSpec
    text = SPEC
    for old, new in READ:
        assert old in text
        text = text.replace(old, new)
    (tmp_path / "ok.yaml").write_text(text)
    keys = {p.key for p in SweepSpec(tmp_path / "ok.yaml").parameters}
    assert {"sensors.seed", "controller.gimbal.boresight"} <= keys


def test_the_antenna_sensors_are_taken_where_the_loop_closes_at_the_antenna(tmp_path):
    # They were refused whatever the scene ("the controller does not use the antenna sensors yet"): a
    # budget with the tracker could not disperse its noise, bias or gyro.
    from gimbalsim.sweep import SweepSpec
    text = SPEC.replace(f"set: {{sim.duration: {DURATION}}}",
                        f"set: {{sim.duration: {DURATION}, sensors.antenna: tracker_gyro}}")
    text = text.replace("  sensors.star_tracker_noise: {uniform: [0.0, 2.0e-5]}",
                        "  sensors.tracker_noise: {uniform: [0.0, 2.0e-5]}\n"
                        "  sensors.antenna_gyro_bias: {ball: {radius: 1.0e-5}}\n"
                        "  controller.antenna.bandwidth: {uniform: [8, 12]}\n  sensors.seed: {choice: [1, 2]}")
    (tmp_path / "ok.yaml").write_text(text)
    keys = [p.key for p in SweepSpec(tmp_path / "ok.yaml").parameters]
    assert {"sensors.tracker_noise", "sensors.antenna_gyro_bias", "controller.antenna.bandwidth",
            "sensors.seed"} <= set(keys), keys


@pytest.mark.parametrize("knowledge,controller_set", [
    (True, "controller_set: {pointing.mode: joint, pointing.accel_feedforward: profile, "),  # the estimate's index
    (False, "controller_set: {pointing.mode: joint, pointing.accel_feedforward: model, "),  # the base's rate
    (False, "controller_set: {pointing.mode: inertial, pointing.accel_feedforward: profile, "),  # the references
    (False, "controller_set: {pointing.accel_feedforward: profile, ")])  # inertial pointing, the default
def test_the_attitude_estimates_keys_are_taken_where_a_figure_or_a_command_reads_them(tmp_path, knowledge,
                                                                                      controller_set):
    from gimbalsim.sweep import SweepSpec
    text = SPEC.replace("controller_set: {", controller_set)
    text = text if knowledge else text.replace("  knowledge: {requirement: 1.0e-12}", "")
    text = text.replace("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}",
                        "  sensors.gyro_noise: {uniform: [0.0, 1.0e-2]}\n"
                        "  controller.estimator.k_i: {uniform: [0.0, 1.0]}")
    (tmp_path / "ok.yaml").write_text(text)
    keys = {p.key for p in SweepSpec(tmp_path / "ok.yaml").parameters}
    assert {"sensors.star_tracker_noise", "sensors.gyro_noise", "controller.estimator.k_i"} <= keys, keys


def test_a_key_under_a_dispersed_setting_is_accepted_when_one_value_reads_it(tmp_path):
    from gimbalsim.sweep import SweepSpec
    text = SPEC.replace("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}",
                        "  controller.azimuth.aw_gain: {uniform: [1, 30]}\n"
                        "  controller.control.anti_windup: {choice: [clamping, back_calculation]}")
    (tmp_path / "ok.yaml").write_text(text)
    assert [p.key for p in SweepSpec(tmp_path / "ok.yaml").parameters][-2:] == [
        "controller.azimuth.aw_gain", "controller.control.anti_windup"]


@pytest.mark.parametrize("key,draws", [("profile.hold_time", "uniform: [0.2, 0.6]"),
                                       ("profile.slew_start", "choice: [0.1, 0.7]"),
                                       ("profile.track_ramp_time", "uniform: [0.5, 1.0]")])
def test_a_profile_key_is_taken_when_one_value_reaches_its_segment_in_the_run(tmp_path, key, draws):
    # the track begins at 0.4 s with hold_time 0.2, the slew at 0.1 s: inside the 0.5 s run
    from gimbalsim.sweep import SweepSpec
    text = SPEC.replace(f"set: {{sim.duration: {DURATION}}}", "set: {sim.duration: 0.5}")
    text = text.replace("  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}", f"  controller.{key}: {{{draws}}}")
    (tmp_path / "ok.yaml").write_text(text)
    assert "controller." + key in {p.key for p in SweepSpec(tmp_path / "ok.yaml").parameters}


@pytest.mark.parametrize("end,refused", [("0.5000001", False), ("0.501", False), ("0.5011", True)])
def test_a_phase_ending_within_the_last_ticks_period_is_covered(tmp_path, end, refused):
    # (pass 55) the run's last tick (0.5 s) holds for its period as gimbalsim.indices reads it: a phase ending
    # 1e-7 s past the run was refused as "NaN for every sample" while the indices gave it a value
    from gimbalsim.sweep import SpecError, SweepSpec
    text = SPEC.replace(f"set: {{sim.duration: {DURATION}}}", "set: {sim.duration: 0.5}") \
        .replace("{late: [0.4, 0.5]}", f"{{late: [0.4, {end}]}}")
    (tmp_path / "s.yaml").write_text(text)
    if refused:
        with pytest.raises(SpecError, match="inside phase 'late'"):
            SweepSpec(tmp_path / "s.yaml")
    else:
        assert SweepSpec(tmp_path / "s.yaml").closed.phases[-1] == ("late", (0.4, float(end)))


def test_a_motor_limit_below_the_controllers_on_one_axis_is_taken(tmp_path):
    from gimbalsim.sweep import SweepSpec
    text = SPEC.replace("  contact.clearance: {uniform: [1.0e-4, 8.0e-4]}",
                        "  torque.limit: {choice: [[10.0, 100.0], [500.0, 500.0]]}")
    (tmp_path / "ok.yaml").write_text(text)
    assert "torque.limit" in {p.key for p in SweepSpec(tmp_path / "ok.yaml").parameters}


@pytest.mark.parametrize("dispersion", ["parameters:\n  controller.profile.hold_time: {uniform: [0.1, 0.5]}\n",
                                        "parameters:\n  controller.azimuth.kp: {uniform: [2000.0, 4000.0]}\n"
                                        "grid:\n  controller.profile.hold_time: [0.1, 0.5]\n"])
def test_a_profile_phase_is_judged_at_the_values_the_runs_take(tmp_path, dispersion):
    # (pass 55) the default controller's hold_time (1 s) ends the hold past the 1 s run, but every value the
    # study gives ends it inside: it was refused as "NaN for every sample", judged at a profile no run uses
    from gimbalsim.sweep import SweepSpec
    from conftest import SCENES
    (tmp_path / "ok.yaml").write_text(
        f"scene: {SCENES}/paper_ideal.yaml\nset: {{sim.duration: 1.0}}\ncontroller: default\n"
        "controller_set: {profile.slew_start: 0.1, profile.slew_time: 0.3}\nsamples: 2\nseed: 3\n"
        f"{dispersion}phases: [hold]\nindices:\n  ape: {{}}\n")
    assert SweepSpec(tmp_path / "ok.yaml").closed.phases == [("hold", None)]


@pytest.mark.parametrize("controller_set", [True, False])
def test_a_bad_controller_file_is_named_not_an_empty_dict(tmp_path, controller_set):
    # (pass 40) "the controller refuses {}: c.yaml:2:..." printed a dict of nothing ahead of the file's line
    from gimbalsim.sweep import SpecError, SweepSpec
    (tmp_path / "c.yaml").write_text("azimuth:\n  kp: -1.0\n")
    text = SPEC.replace(f"controller: {CONTROLLER_CONFIG}", "controller: c.yaml")
    if not controller_set:
        text = "\n".join(line for line in text.split("\n") if not line.startswith("controller_set:"))
    (tmp_path / "spec.yaml").write_text(text)
    with pytest.raises(SpecError) as e:
        SweepSpec(tmp_path / "spec.yaml")
    said = str(e.value)
    assert e.value.key == "controller" and "{}" not in said, said
    assert f"the controller refuses its file{' and controller_set' if controller_set else ''}: " in said, said
    assert "c.yaml:2" in said and "azimuth.kp" in said, said
