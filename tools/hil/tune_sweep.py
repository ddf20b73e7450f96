#!/usr/bin/python3
"""Gain sweep of the pointing controller in LOCKSTEP over LCM.

For each gain set, runs firmware_sim --lockstep and pointing_controller
together over udpm on loopback inside a private network namespace (so runs
never see another bench's traffic and work on any machine; needs root for
`unshare -n`), then prints one table row per set:

  settle [s]    after the slew's end until max |joint error| (encoder angles,
                controller's log) stays below --settle-tol for the rest of the
                hold; inf if it never does before tracking starts
  rms/max truth pointing error during tracking [rad] (firmware_sim's truth:
                boresight vs the profile's line of sight; includes the base's
                reaction rotation, which encoders cannot see)
  max joint err during tracking [rad] (encoder)
  max |torque| applied per axis [N m] (truth)

Gain sets: --omega W1,W2,... gives triple-pole sets (kd = 3 J w, kp = 3 J w^2,
ki = J w^3, J = the configured inertia of each axis); --gain-set "k=v,k=v"
(repeatable) gives explicit controller overrides. Both processes read ONE
configuration file per run, written from `pointing_controller --print-config`,
so the controller's profile and the truth's target are the same.
--in-process runs build/bin/controller_sweep instead (library + dynamics in one
process, no LCM, no root needed).

Example:
  /usr/bin/python3 tools/hil/tune_sweep.py --scene tools/scenes/paper_clearance.yaml --omega 5,10,20,40
"""
import argparse
import csv
import math
import os
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools", "pages"))
from output_file import Refused, run_script, write_text  # noqa: E402  (the package's one writer)
URL = "udpm://239.255.76.67:7667?ttl=0"


def parse_args():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scene", default=os.path.join(ROOT, "tools/scenes/paper_clearance.yaml"))
    p.add_argument("--scene-set", action="append", default=[], help="scene override key=value (firmware_sim --set)")
    p.add_argument("--config", default=os.path.join(ROOT, "controllers/config/default.yaml"))
    p.add_argument("--set", action="append", default=[], help="controller override key=value for every run")
    p.add_argument("--omega", default="", help="comma-separated closed-loop bandwidths [rad/s] (triple pole)")
    p.add_argument("--gain-set", action="append", default=[], help='explicit set, e.g. "azimuth.kp=1e4,elevation.kp=1e4"')
    p.add_argument("--duration", type=float, default=0.0, help="simulated seconds (default: track start + 5 s)")
    p.add_argument("--settle-tol", type=float, default=1e-4, help="settling band on the joint error [rad]")
    p.add_argument("--bin", default=os.path.join(ROOT, "build/bin"), help="directory with firmware_sim, pointing_controller")
    p.add_argument("--keep", default="", help="keep each run's config and logs in this directory")
    p.add_argument("--in-process", action="store_true", help="run controller_sweep (no LCM) instead")
    a = p.parse_args()
    if not a.omega and not a.gain_set:
        a.omega = "5,10,20,40"
    return a


def print_config(args, extra):
    cmd = [os.path.join(args.bin, "pointing_controller"), args.config, "--print-config"]
    for s in args.set + extra:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise Refused("configuration refused:\n" + r.stderr.rstrip())
    return dict(line.split("=", 1) for line in r.stdout.splitlines() if "=" in line)


def gain_sets(args, base):
    sets = []
    for w in [float(x) for x in args.omega.split(",") if x.strip()]:
        s = []
        for axis in ("azimuth", "elevation"):
            J = float(base[axis + ".inertia"])
            s += [f"{axis}.kp={3 * J * w * w:.6g}", f"{axis}.ki={J * w ** 3:.6g}", f"{axis}.kd={3 * J * w:.6g}"]
        sets.append((f"omega={w:g}", s))
    for g in args.gain_set:
        sets.append((g, [x.strip() for x in g.split(",") if x.strip()]))
    return sets


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def run_lockstep(args, cfg, workdir):
    period = float(cfg["control.period"])
    track_start = float(cfg["profile.slew_start"]) + float(cfg["profile.slew_time"]) + float(cfg["profile.hold_time"])
    duration = args.duration if args.duration > 0 else track_start + 5.0
    cfg_path = os.path.join(workdir, "controller.yaml")
    write_text(cfg_path, "# written by tools/hil/tune_sweep.py from pointing_controller --print-config\n" +
               "".join(f"{k}: {v}\n" for k, v in cfg.items()))
    ctl_csv, truth_csv = os.path.join(workdir, "controller.csv"), os.path.join(workdir, "truth.csv")
    pc = [os.path.join(args.bin, "pointing_controller"), cfg_path, "--lcm-url", URL, "--log-csv", ctl_csv,
          "--duration", repr(duration), "--idle-exit", "10"]
    fw = [os.path.join(args.bin, "firmware_sim"), args.scene, "--lockstep", "--duration", repr(duration),
          "--rate", repr(1.0 / period), "--profile", cfg_path, "--truth-csv", truth_csv, "--lcm-url", URL,
          "--start-timeout", "10"]
    for s in args.scene_set:
        fw += ["--set", s]
    q = lambda c: " ".join(shlex.quote(x) for x in c)
    script = (f"ip link set lo up && ip route add 224.0.0.0/4 dev lo && "
              f"{{ {q(pc)} 2>{shlex.quote(os.path.join(workdir, 'controller.log'))} & "
              f"{q(fw)} >{shlex.quote(os.path.join(workdir, 'firmware.log'))} 2>&1; rc=$?; wait; exit $rc; }}")
    t0 = time.monotonic()
    r = subprocess.run(["unshare", "-n", "sh", "-c", script])
    wall = time.monotonic() - t0
    if r.returncode != 0:  # the logs' last lines, whole
        tails = []
        for name in ("firmware.log", "controller.log"):
            with open(os.path.join(workdir, name), errors="replace") as f:
                lines = f.read().splitlines()[-8:]
            if lines:
                tails.append(f"{name}:\n    " + "\n    ".join(lines))
        return None, f"firmware_sim exit {r.returncode}\n  " + "\n  ".join(tails)
    return metrics(args, cfg, read_csv(ctl_csv), read_csv(truth_csv), duration, wall), ""


def metrics(args, cfg, ctl, truth, duration, wall):
    period = float(cfg["control.period"])
    slew_end = float(cfg["profile.slew_start"]) + float(cfg["profile.slew_time"])
    track_start = slew_end + float(cfg["profile.hold_time"])
    last_unsettled, hold_seen, max_err_track = slew_end, False, math.nan  # nan: no track row (never 0)
    for row in ctl:
        e = max(abs(float(row["err_az_rad"])), abs(float(row["err_el_rad"])))
        if row["segment"] == "hold":
            hold_seen = True
            if e >= args.settle_tol:
                last_unsettled = float(row["t_s"]) + period
        elif row["segment"] == "track":
            max_err_track = e if math.isnan(max_err_track) else max(max_err_track, e)
    settle = last_unsettled - slew_end if hold_seen and last_unsettled < track_start - 0.5 * period else math.inf
    errs = [float(r["pointing_error_rad"]) for r in truth if int(r["seq"]) * period >= track_start - 0.5 * period]
    rms = math.sqrt(sum(e * e for e in errs) / len(errs)) if errs else math.nan
    tau1 = max(abs(float(r["tau1_Nm"])) for r in truth)
    tau2 = max(abs(float(r["tau2_Nm"])) for r in truth)
    return dict(settle=settle, rms=rms, max_truth=max(errs) if errs else math.nan, max_err=max_err_track,
                tau1=tau1, tau2=tau2, speed=duration / wall, answered=len(ctl))


def require_programs(args, names):
    """Each program in --bin, or exit 2 naming the command that builds it (never a traceback)."""
    missing = [n for n in names if not os.access(os.path.join(args.bin, n), os.X_OK)]
    if missing:
        raise Refused(f"{', '.join(missing)} not built in {args.bin}: cmake --build build -j2 --target {' '.join(missing)}")


def main():
    args = parse_args()
    require_programs(args, ["controller_sweep"] if args.in_process else ["firmware_sim", "pointing_controller"])
    if args.in_process:
        cmd = [os.path.join(args.bin, "controller_sweep"), "--scene", args.scene, "--config", args.config,
               "--omega", args.omega, "--settle-tol", repr(args.settle_tol)]
        cmd += sum([["--set", s] for s in args.set], []) + sum([["--scene-set", s] for s in args.scene_set], [])
        if args.duration > 0:
            cmd += ["--duration", repr(args.duration)]
        if args.gain_set:
            raise Refused("--gain-set needs the lockstep mode (controller_sweep takes --omega only)")
        return subprocess.run(cmd).returncode
    base = print_config(args, [])
    track_start = float(base["profile.slew_start"]) + float(base["profile.slew_time"]) + float(base["profile.hold_time"])
    if 0 < args.duration <= track_start:  # every figure but the torques is the track's (as controller_sweep refuses)
        print(f"tune_sweep: error: --duration: track window [{track_start:g}, inf) s not reached: run ended at "
              f"{args.duration:g} s", file=sys.stderr)
        return 2
    print(f"# lockstep over LCM udpm (private network namespace): scene {os.path.basename(args.scene)}, "
          f"config {os.path.relpath(args.config, ROOT)}, settle band {args.settle_tol:g} rad")
    hdr = f"{'gain set':<34} {'settle_s':>9} {'rms_truth':>10} {'max_truth':>10} {'max_e_trk':>10} " \
          f"{'tau1max':>8} {'tau2max':>8} {'x_real':>7}"
    print(hdr)
    failures = 0
    for name, overrides in gain_sets(args, base):
        cfg = print_config(args, overrides)
        if args.keep:
            workdir = os.path.join(args.keep, name.replace("=", "_").replace(",", "_").replace(" ", ""))
            os.makedirs(workdir, exist_ok=True)
            m, err = run_lockstep(args, cfg, workdir)
        else:
            with tempfile.TemporaryDirectory(prefix="tune_sweep_") as workdir:
                m, err = run_lockstep(args, cfg, workdir)
        if m is None:
            print(f"{name:<34} run failed: {err}")
            failures += 1
            continue
        print(f"{name[:34]:<34} {m['settle']:>9.4g} {m['rms']:>10.3e} {m['max_truth']:>10.3e} {m['max_err']:>10.3e} "
              f"{m['tau1']:>8.3g} {m['tau2']:>8.3g} {m['speed']:>7.2f}", flush=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(run_script("tune_sweep", main))
