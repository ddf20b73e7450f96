#!/usr/bin/python3
"""Gain sweep of the pointing controller in LOCKSTEP over LCM.

For each gain set, runs firmware_sim --lockstep and pointing_controller
together over udpm on loopback inside a private network namespace (so runs
never see another bench's traffic and work on any machine; needs root for
`unshare -n`), then prints one table row per set:

  settle [s]    after the slew's end until max |joint error| (the controller's
                reference against the true joint angles of firmware_sim's truth,
                as --in-process measures it) stays below --settle-tol for the
                rest of the hold; inf if it never does before tracking starts
  rms/max truth pointing error during tracking [rad] (firmware_sim's truth:
                boresight vs the profile's line of sight; includes the base's
                reaction rotation, which encoders cannot see)
  max joint err during tracking [rad] (reference against the true angles)
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
import output_file  # noqa: E402  (standard_flags)
from output_file import OutputError, Refused, check_before_writing, open_output, run_script, write_text  # noqa: E402
URL = "udpm://239.255.76.67:7667?ttl=0"
STOPPED = 3  # the exit-code table's "the run stopped" (firmware_sim's, controller_sweep's)
# What each run writes in its folder (--keep DIR/<gain set>/, else a temporary one).
RUN_FILES = ("controller.yaml", "controller.csv", "truth.csv", "controller.log", "firmware.log")
# The flags' ranges: controller_sweep's (--omega, --duration, --settle-tol), so both modes take the same values.
OMEGA, DURATION, SETTLE_TOL = (1e-3, 1e6, False), (0.0, 1e9, True), (0.0, 10.0, True)  # (lo, hi, lo excluded)


def parse_args():
    p = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    p.add_argument("--scene", default=os.path.join(ROOT, "tools/scenes/paper_clearance.yaml"))
    p.add_argument("--scene-set", action="append", default=[], help="scene override key=value (firmware_sim --set)")
    p.add_argument("--config", default=os.path.join(ROOT, "controllers/config/default.yaml"))
    p.add_argument("--set", action="append", default=[], help="controller override key=value for every run")
    p.add_argument("--omega", help="comma-separated closed-loop bandwidths [rad/s] (triple pole), each in "
                   "[0.001, 1e+06] (default: 5,10,20,40 without --gain-set)")
    p.add_argument("--gain-set", action="append", default=[],
                   help='explicit set, e.g. "azimuth.kp=1e4,elevation.kp=1e4"')
    p.add_argument("--duration", help="simulated seconds, in (0, 1e+09] (default: track start + 5 s)")
    p.add_argument("--settle-tol", default="1e-4", help="settling band on the joint error [rad], in (0, 10]")
    p.add_argument("--bin", default=os.path.join(output_file.default_build(), "bin"),
                   help="directory with firmware_sim, pointing_controller (default: GIMBALSIM_BUILD's bin/, else "
                        "the checkout's build/bin)")
    p.add_argument("--keep", help="keep each run's config and logs in this folder (made if missing, in a folder "
                   "that exists; lockstep only)")
    p.add_argument("--in-process", action="store_true", help="run controller_sweep (no LCM) instead")
    a = p.parse_args()
    if a.omega is None and not a.gain_set:
        a.omega = "5,10,20,40"
    # A number is a plain decimal within the flag's range (docs/usage.md): nan, -1, 0 or ' 5' never mean the default.
    if a.omega is not None and "" in a.omega.split(","):
        raise Refused("--omega: an empty value" if a.omega == "" else f"--omega: an empty list item in {a.omega!r}")
    a.omegas = [number("--omega", x, OMEGA) for x in a.omega.split(",")] if a.omega is not None else []
    a.duration = None if a.duration is None else number("--duration", a.duration, DURATION)
    a.settle_tol = number("--settle-tol", a.settle_tol, SETTLE_TOL)
    if a.keep == "":
        raise Refused("--keep: an empty value")
    return a


def number(flag, text, limits):
    """A flag's number: a plain finite decimal in its range, else Refused naming the flag."""
    lo, hi, lo_excluded = limits
    # the project's one reading of a flag's number, as controller_sweep reads it: 010 or 04.0 is refused
    # (it ran 10 s and 4 s here while controller_sweep refused them, pass 55)
    v, why = output_file._number.flag_decimal(text)
    if why:
        raise Refused(f"{flag}: {why}")
    if not ((lo < v) if lo_excluded else (lo <= v)) or v > hi:
        raise Refused(f"{flag}: must be in {'(' if lo_excluded else '['}{lo:g}, {hi:g}], got {text}")
    return v


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
    for w in args.omegas:
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
    duration = args.duration if args.duration is not None else track_start + 5.0
    cfg_path = os.path.join(workdir, "controller.yaml")
    write_text(cfg_path, "# written by tools/hil/tune_sweep.py from pointing_controller --print-config\n" +
               "".join(f"{k}: {v}\n" for k, v in cfg.items()), args.inputs)
    ctl_csv, truth_csv = os.path.join(workdir, "controller.csv"), os.path.join(workdir, "truth.csv")
    pc = [os.path.join(args.bin, "pointing_controller"), cfg_path, "--lcm-url", URL, "--log-csv", ctl_csv,
          "--duration", repr(duration), "--idle-exit", "10"]
    fw = [os.path.join(args.bin, "firmware_sim"), args.scene, "--lockstep", "--duration", repr(duration),
          "--rate", repr(1.0 / period), "--profile", cfg_path, "--truth-csv", truth_csv, "--lcm-url", URL,
          "--start-timeout", "10"]
    for s in args.scene_set:
        fw += ["--set", s]
    q = lambda c: " ".join(shlex.quote(x) for x in c)
    # The logs go through the one writer (never through a link under their names): the programs write into
    # its temporaries' descriptors, renamed onto the names when the run has ended.
    with open_output(os.path.join(workdir, "controller.log"), "wb", args.inputs) as ctl_log, \
            open_output(os.path.join(workdir, "firmware.log"), "wb", args.inputs) as fw_log:
        c, f = ctl_log.fileno(), fw_log.fileno()
        script = (f"ip link set lo up && ip route add 224.0.0.0/4 dev lo && "
                  f"{{ {q(pc)} 2>&{c} & {q(fw)} >&{f} 2>&1; rc=$?; wait; exit $rc; }}")
        t0 = time.monotonic()  # bash, not sh: dash takes no descriptor above 9
        r = subprocess.run(["unshare", "-n", "bash", "-c", script], pass_fds=(c, f))
        wall = time.monotonic() - t0
    if r.returncode == STOPPED:  # the plant stopped: a row that says so, as controller_sweep's (it was a failure)
        with open(os.path.join(workdir, "firmware.log"), errors="replace") as f:
            # a plant stop's line, or the lockstep's end over commands the plant rejected in a row
            said = [line for line in f.read().splitlines() if "stopped after" in line or "no valid command" in line]
        return None, (said[-1].split(": ", 1)[-1] if said else "firmware_sim exit 3 (the run stopped)"), STOPPED
    if r.returncode != 0:  # the logs' last lines, whole
        tails = []
        for name in ("firmware.log", "controller.log"):
            with open(os.path.join(workdir, name), errors="replace") as f:
                lines = f.read().splitlines()[-8:]
            if lines:
                tails.append(f"{name}:\n    " + "\n    ".join(lines))
        return None, f"firmware_sim exit {r.returncode}\n  " + "\n  ".join(tails), r.returncode
    return metrics(args, cfg, read_csv(ctl_csv), read_csv(truth_csv), duration, wall), "", 0


def metrics(args, cfg, ctl, truth, duration, wall):
    period = float(cfg["control.period"])
    slew_end = float(cfg["profile.slew_start"]) + float(cfg["profile.slew_time"])
    track_start = slew_end + float(cfg["profile.hold_time"])
    last_unsettled, hold_seen, max_err_track = slew_end, False, math.nan  # nan: no track row (never 0)
    # The joint error against the true angle (truth.csv, the status's seq), as controller_sweep measures
    # it: the controller's own err_* is against the encoder, up to half a count (6e-6 rad) off.
    true_angle = {int(r["seq"]): (float(r["theta1_rad"]), float(r["theta2_rad"])) for r in truth}
    for row in ctl:
        th1, th2 = true_angle[int(row["seq"])]
        e = max(abs(float(row["ref_az_rad"]) - th1), abs(float(row["ref_el_rad"]) - th2))
        if row["segment"] == "hold":
            hold_seen = True
            if e >= args.settle_tol:
                last_unsettled = float(row["t_s"]) + period
        elif row["segment"] == "track":
            max_err_track = e if math.isnan(max_err_track) else max(max_err_track, e)
    settle = last_unsettled - slew_end if hold_seen and last_unsettled < track_start - 0.5 * period else math.nan
    errs = [float(r["pointing_error_rad"]) for r in truth if int(r["seq"]) * period >= track_start - 0.5 * period]
    rms = math.sqrt(sum(e * e for e in errs) / len(errs)) if errs else math.nan
    tau1 = max(abs(float(r["tau1_Nm"])) for r in truth)
    tau2 = max(abs(float(r["tau2_Nm"])) for r in truth)
    # no settling time is n/a with its reason, as controller_sweep says it (it printed inf, pass 56)
    settle_why = "" if not math.isnan(settle) else (
        f"the joint error did not stay below settle_tol {args.settle_tol:g} rad before tracking started at "
        f"{track_start:g} s" if hold_seen else "no hold tick")
    return dict(settle=settle, settle_why=settle_why, rms=rms, max_truth=max(errs) if errs else math.nan,
                max_err=max_err_track,
                tau1=tau1, tau2=tau2, speed=duration / wall, answered=len(ctl))


def require_programs(args, names):
    """Each program in --bin, or exit 2 naming the command that builds it (never a traceback)."""
    missing = [n for n in names if not os.access(os.path.join(args.bin, n), os.X_OK)]
    if missing:
        raise Refused(f"{', '.join(missing)} not built in {args.bin}: "
                      f"cmake --build build -j2 --target {' '.join(missing)}")


def keep_folders(args, sets):
    """--keep DIR: each gain set's folder in it, checked before any run
    (Refused, exit 2, nothing written): DIR and each folder a real folder
    (made if missing, DIR in a folder that exists: never a folder the user
    named), no two sets in one folder, and no link, special file or input
    under any name a run writes (docs/usage.md "Output files")."""
    keep = args.keep
    parent = os.path.dirname(os.path.normpath(keep)) or "."
    folders = {}
    for name, _ in sets:
        folder = os.path.join(keep, name.replace("=", "_").replace(",", "_").replace(" ", "").replace("/", "_"))
        if folder in folders:
            raise Refused(f"--keep: gain sets {folders[folder]!r} and {name!r} would keep their runs in one folder "
                          f"{folder}")
        folders[folder] = name
    for d in [keep, *folders]:
        if os.path.islink(d):
            raise Refused(f"--keep: {d}: is a symbolic link; not written through (give its target)")
        if os.path.lexists(d) and not os.path.isdir(d):
            raise Refused(f"--keep: {d}: exists and is not a folder")
        if os.path.isdir(d) and d != keep:
            check_before_writing([os.path.join(d, n) for n in RUN_FILES], args.inputs)
    if not os.path.isdir(parent):
        raise Refused(f"--keep {keep}: no such folder {parent} (create it first)")
    return list(folders)


def make_folder(path):
    """A --keep folder made before its run; one that cannot be made (/proc/x, a full disk) is an output
    failure (exit 4) naming it, before the run, as every output of the exit-code table."""
    try:
        os.mkdir(path)
    except FileExistsError:
        if os.path.islink(path) or not os.path.isdir(path):  # made since the check: refused, not written through
            raise Refused(f"--keep: {path}: no longer a folder (a link or a file was put there)") from None
    except OSError as e:
        raise OutputError(f"--keep: cannot make the folder {path}: {e.strerror}") from None


def main():
    args = parse_args()
    args.inputs = [args.scene, args.config]
    require_programs(args, ["controller_sweep"] if args.in_process else ["firmware_sim", "pointing_controller"])
    if args.in_process:
        cmd = [os.path.join(args.bin, "controller_sweep"), "--scene", args.scene, "--config", args.config,
               "--omega", args.omega, "--settle-tol", repr(args.settle_tol)]
        cmd += sum([["--set", s] for s in args.set], []) + sum([["--scene-set", s] for s in args.scene_set], [])
        if args.duration is not None:
            cmd += ["--duration", repr(args.duration)]
        if args.gain_set or args.keep is not None:
            raise Refused(f"{'--gain-set' if args.gain_set else '--keep'} needs the lockstep mode (controller_sweep "
                          f"takes --omega only and writes no run files)")
        return subprocess.run(cmd).returncode
    base = print_config(args, [])
    track_start = sum(float(base[f"profile.{k}"]) for k in ("slew_start", "slew_time", "hold_time"))
    if args.duration is not None and args.duration <= track_start:  # every figure but the torques is the track's
        print(f"tune_sweep: error: --duration: track window [{track_start:g}, inf) s not reached: run ended at "
              f"{args.duration:g} s", file=sys.stderr)
        return 2
    sets = gain_sets(args, base)
    cfgs = [print_config(args, overrides) for _, overrides in sets]  # every set's refusal before any run
    folders = keep_folders(args, sets) if args.keep is not None else [None] * len(sets)
    print(f"# lockstep over LCM udpm (private network namespace): scene {os.path.basename(args.scene)}, "
          f"config {os.path.relpath(args.config, ROOT)}, settle band {args.settle_tol:g} rad")
    hdr = f"{'gain set':<34} {'settle_s':>9} {'rms_truth':>10} {'max_truth':>10} {'max_e_trk':>10} " \
          f"{'tau1max':>8} {'tau2max':>8} {'x_real':>7}"
    print(hdr)
    failed, stopped = [], 0
    for (name, _), cfg, workdir in zip(sets, cfgs, folders):
        if workdir is not None:
            make_folder(args.keep)
            make_folder(workdir)
            m, err, rc = run_lockstep(args, cfg, workdir)
        else:
            with tempfile.TemporaryDirectory(prefix="tune_sweep_") as workdir:
                m, err, rc = run_lockstep(args, cfg, workdir)
        if rc == STOPPED:
            print(f"{name:<34} stopped: {err}", flush=True)
            stopped += 1
            continue
        if m is None:
            print(f"{name:<34} run failed: {err}", flush=True)
            failed.append(rc)
            continue
        # a cell of one word (the columns split on blanks): the reason ends the row
        settle, why = ("n/a", f"  (settle_s n/a: {m['settle_why']})") if m["settle_why"] else (f"{m['settle']:.4g}", "")
        print(f"{name[:34]:<34} {settle:>9} {m['rms']:>10.3e} {m['max_truth']:>10.3e} {m['max_err']:>10.3e} "
              f"{m['tau1']:>8.3g} {m['tau2']:>8.3g} {m['speed']:>7.2f}{why}", flush=True)
    # the exit-code table's: a run that failed gives its own code (LCM 5, no peer 6), a plant stop 3
    if failed:
        return failed[0] if 2 <= failed[0] <= 8 else 1
    return STOPPED if stopped else 0


if __name__ == "__main__":
    sys.exit(run_script("tune_sweep", main))
