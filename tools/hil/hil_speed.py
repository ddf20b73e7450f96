#!/usr/bin/python3
"""Speed of the hardware-in-the-loop bench on this machine (prints figures;
not a test). firmware_sim + pointing_controller over LCM udpm (ttl=0) in a
private network namespace (unshare -n, else unshare -rn), figures parsed from
firmware_sim's exit summary.

 (i)   rate sweep, real time, SCHED_FIFO, clearance scene with the controller:
       per control rate, overruns, wake-up lateness p50/p99/max, compute per
       tick p50/p99, commands missed. A rate divides 1 kHz (a whole number of
       the scene's 1 ms steps per tick) or is a multiple of 1 kHz up to 50 kHz
       (--set sim.step=1/rate, one RK4 step per tick, contact sub-step 20 us;
       the controller's control.period 1/rate).
       "Sustains" = zero overruns and lateness p99 < 10 % of the period over
       the whole run. Both processes run under chrt -f 60 (--chrt) so the
       controller and firmware_sim's LCM thread are not starved by other work
       on this 2-core machine; the loop thread is SCHED_FIFO 80. Optionally
       again with --spin (busy-wait the last part of each period).
 (ii)  lockstep speed: simulated seconds per wall second, paper_ideal and
       paper_clearance with the controller over udpm, median of 3 runs, in
       three ways: both processes sleeping in poll() between messages (the
       default; firmware_sim holds idle CPUs awake, --cpu-dma-latency-us 0),
       both held to one CPU (taskset -c CPU), both busy-polling
       (--spin-us 100). Against the in-process closed loop (controller_sweep
       --omega 20, the default configuration's bandwidth; its start-up
       subtracted: a 4 s run) it gives the process boundary per tick: lockstep wall
       time per tick minus the in-process loop's.
 (iii) 60 s at 1 kHz real time: wake-up lateness and status -> command round
       trip (p50/p99/p99.9/max).

The machine's floor: in (i) and (iii) cyclictest (Debian rt-tests) runs at
the same period, SCHED_FIFO priority and CPU as firmware_sim's loop thread
(--cpu, default 1, passed to both; the controller and firmware_sim's
communication thread run on the other CPUs), half of its time just before and half
just after each firmware_sim run (interleaved in the same minutes); the
tables give firmware_sim's wake-up lateness percentiles (p50, p99, p99.9,
max) next to cyclictest's and their ratios (firmware_sim / cyclictest: 1 =
the machine's own floor).

Usage:
  /usr/bin/python3 tools/hil/hil_speed.py [--seconds 10] [--rates 1000,2000,4000,5000,8000,10000]
      [--spin 0.3] [--long 60] [--cpu 1] [--build build] [--skip-sweep] [--skip-lockstep] [--skip-long]
      [--results]

--results also writes everything printed into docs/results/bench_timing.md
(header by tools/pages/results_page.py: machine, commit, date, load at start and end).
"""
import argparse
import os
import time
import re
import statistics
import subprocess
import sys
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pages"))
import output_file  # noqa: E402,F401  (its import keeps the console: a reader gone stops nothing)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.path.join(ROOT, "build/bin")  # --build changes it
CFG = os.path.join(ROOT, "controllers/config/default.yaml")
SCENES = os.path.join(ROOT, "tools/scenes")
URL = "udpm://239.255.76.67:7667?ttl=0"


def load():
    return open("/proc/loadavg").read().split()[:3]


def enter_namespace():
    """Re-run this script inside a fresh network namespace with a multicast route on lo."""
    if os.environ.get("GIMBALSIM_SPEED_INSIDE") == "1":
        return
    setup = "ip link set lo up && ip route add 224.0.0.0/4 dev lo"
    for ns in (["unshare", "-n"], ["unshare", "-rn"]):
        if subprocess.run(ns + ["sh", "-c", setup], capture_output=True).returncode == 0:
            os.environ["GIMBALSIM_SPEED_INSIDE"] = "1"
            print(f"hil_speed: private network namespace ({' '.join(ns)}), {URL}", flush=True)
            os.execvp(ns[0], ns + ["sh", "-c", setup + ' && exec /usr/bin/python3 "$0" "$@"', sys.argv[0]] + sys.argv[1:])
    sys.exit("hil_speed: neither `unshare -n` nor `unshare -rn` gives a network namespace here")


CHRT = []  # ["chrt", "-f", PRIO] when --chrt is allowed here


def run_pair(scene, seconds, rate=1000, lockstep=False, fw_extra=(), ctl_extra=(), both=(), controller=None):
    """Controller + firmware_sim, each started under `both` (e.g. taskset); returns firmware_sim's stdout (the exit
    summary). `controller`: the argv of a stand-in for pointing_controller (torque_replay), which must exit 0."""
    rt = [] if lockstep else CHRT
    # Real time: the controller on the other CPUs, as a bench keeps the plant's loop CPU to itself.
    others = sorted(os.sched_getaffinity(0) - {CPU[0]})
    pin = ["taskset", "-c", ",".join(map(str, others))] if not lockstep and CPU[0] >= 0 and others else []
    ctl_cmd = controller or [os.path.join(BIN, "pointing_controller"), CFG, "--lcm-url", URL, "--idle-exit", "2"]
    ctl = subprocess.Popen([*both, *pin, *rt, *ctl_cmd, *ctl_extra], stdout=subprocess.DEVNULL,
                           stderr=subprocess.PIPE if controller else subprocess.DEVNULL, text=True)
    try:
        cmd = [*both, *rt, os.path.join(BIN, "firmware_sim"), scene, "--rate", str(rate), "--duration", str(seconds),
               "--profile", CFG, "--lcm-url", URL, *fw_extra]
        if lockstep:
            cmd.append("--lockstep")
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=seconds * 20 + 60)
        if r.returncode != 0:
            sys.exit(f"hil_speed: firmware_sim exited {r.returncode}: {' '.join(cmd)}\n{r.stderr}")
    finally:
        err = ctl.communicate(timeout=30)[1]
    if controller and ctl.returncode != 0:
        sys.exit(f"hil_speed: {os.path.basename(ctl_cmd[0])} exited {ctl.returncode}: {err.strip()[-300:]}")
    return r.stdout + r.stderr


RT_PRIORITY = 80  # firmware_sim's loop thread (its --rt-priority default) and cyclictest's
CPU = [1]         # --cpu: firmware_sim's loop thread and cyclictest's thread


def cyclictest(period_us, seconds):
    """cyclictest's wake-up latency histogram [us] -> {us: count} (one thread, SCHED_FIFO RT_PRIORITY, pinned)."""
    cmd = ["cyclictest", "-m", "-q", "-t", "1", "-p", str(RT_PRIORITY), "-i", str(int(round(period_us))),
           "-D", f"{max(1, int(round(seconds)))}", "-h", "100000"]
    if CPU[0] >= 0:
        cmd += ["-a", str(CPU[0])]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=seconds + 60)
    if r.returncode != 0:
        sys.exit(f"hil_speed: cyclictest failed ({' '.join(cmd)}): {r.stderr}")
    hist, mx = {}, 0.0
    for line in r.stdout.splitlines():
        m = re.match(r"^(\d+) (\d+)$", line)
        if m and int(m.group(2)) > 0:
            hist[int(m.group(1))] = hist.get(int(m.group(1)), 0) + int(m.group(2))
        m = re.match(r"^# Max Latencies: (\d+)", line)
        if m:
            mx = max(mx, float(m.group(1)))
    hist["max"] = mx
    return hist


def merge(a, b):
    out = dict(a)
    for k, v in b.items():
        out[k] = max(out.get(k, 0), v) if k == "max" else out.get(k, 0) + v
    return out


def quantiles(hist):
    """p50, p99, p99.9 [us] as firmware_sim's histogram reports them (upper edge of the 1 us bin), and the max."""
    n = sum(v for k, v in hist.items() if k != "max")
    out = []
    for p in (0.5, 0.99, 0.999):
        want, acc = max(1.0, p * n), 0
        for k in sorted(k for k in hist if k != "max"):
            acc += hist[k]
            if acc >= want:
                out.append(min(k + 1.0, hist["max"]))
                break
        else:
            out.append(hist["max"])
    return out + [hist["max"]]


def with_floor(period_us, seconds, run):
    """cyclictest for seconds/2, run(), cyclictest for seconds/2: run's output and the merged histogram's quantiles."""
    a = cyclictest(period_us, seconds / 2)
    out = run()
    b = cyclictest(period_us, seconds / 2)
    return out, quantiles(merge(a, b))


def lateness(out):
    """firmware_sim's wake-up lateness p50, p99, p99.9, max [us] from its exit summary."""
    return grab(out, r"wake-up lateness \[us\]: p50 (\S+)  p99 (\S+)  p99\.9 (\S+)  max (\S+)", 4)


def ratios(fw, floor):
    return " / ".join(f"{f / c:.2g}" if c > 0 else "inf" for f, c in zip(fw, floor))


def grab(text, pattern, n=1):
    m = re.search(pattern, text)
    if not m:
        sys.exit(f"hil_speed: no match for {pattern!r} in\n{text}")
    return [float(x) for x in m.groups()[:n]] if n > 1 else float(m.group(1))


def sweep(rates, seconds, spin_fraction):
    scene = os.path.join(SCENES, "paper_clearance.yaml")
    title = "plain clock_nanosleep" if spin_fraction == 0 else f"--spin-us = {spin_fraction:g} x period"
    print(f"\n(i) control rate sweep, real time, paper_clearance + pointing_controller, {seconds:g} s each, {title}"
          f"  [load before: {' '.join(load())}]")
    print("| rate [Hz] | period [us] | sim.step [s] | overruns (% of ticks) | late ticks | lateness p50 / p99 / p99.9 / max [us] "
          "| cyclictest p50 / p99 / p99.9 / max [us] | ratio p50 / p99 / p99.9 / max | compute p50 / p99 / max [us] "
          "| worst-case tick [us] | missed cmds | sched | sustains |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    best = None
    for rate in rates:
        period_us = 1e6 / rate
        step = 1e-3 if 1000 % rate == 0 else 1.0 / rate  # the scene's 1 ms when it divides the period
        fw = ["--set", f"sim.step={step!r}"]
        if spin_fraction > 0:
            fw += ["--spin-us", f"{spin_fraction * period_us:g}"]
        if CPU[0] >= 0:
            fw += ["--cpu", str(CPU[0])]
        out, floor = with_floor(period_us, seconds, lambda: run_pair(
            scene, seconds, rate=rate, fw_extra=fw, ctl_extra=["--set", f"control.period={1.0 / rate!r}"]))
        lat = lateness(out)
        lp99 = lat[1]
        cp50, cp99, cmax = grab(out, r"compute per tick \[us\]: p50 (\S+)  p99 (\S+)  max (\S+)", 3)
        bound = grab(out, r"worst-case bound (\S+)")
        late = int(grab(out, r"late ticks (\d+)"))
        over = int(grab(out, r"overruns (\d+)"))
        missed = int(grab(out, r"missed (\d+);"))
        fifo = "FIFO" if "SCHED_FIFO" in out else "OTHER"
        ok = over == 0 and lp99 < 0.1 * period_us
        if ok:
            best = rate
        ticks = int(grab(out, r"firmware_sim: (\d+) ticks"))
        print(f"| {rate} | {period_us:.0f} | {step:g} | {over} ({100.0 * over / max(ticks, 1):.2g} %) | {late} | "
              f"{' / '.join(f'{x:.0f}' for x in lat)} | {' / '.join(f'{x:.0f}' for x in floor)} | {ratios(lat, floor)} | "
              f"{cp50:.0f} / {cp99:.0f} / {cmax:.0f} | {bound:.0f} | {missed} | {fifo} | {'yes' if ok else 'no'} |", flush=True)
    print(f"highest rate sustained ({title}): {best if best else 'none of those tried'} Hz  "
          f"[load after: {' '.join(load())}]")


def in_process_us_per_tick(scene, seconds, runs=3):
    """Wall time per 1 ms tick of the in-process closed loop [us]: controller_sweep over 4 + `seconds`
    minus a 4 s run (the start-up; its figures need the track, from 3.5 s), median of `runs` pairs."""
    def wall(duration):
        t0 = time.perf_counter()
        subprocess.run([os.path.join(BIN, "controller_sweep"), "--scene", scene, "--config", CFG, "--omega", "20",
                        "--duration", f"{duration:g}"], check=True, capture_output=True)
        return time.perf_counter() - t0
    xs = [(wall(4.0 + seconds) - wall(4.0)) / (seconds * 1000.0) * 1e6 for _ in range(runs)]
    return statistics.median(xs)


LOCKSTEP_WAYS = (  # (name, prefix of both commands, flags of both processes)
    ("sleeping (default)", lambda: [], []),
    ("one CPU (taskset -c CPU, both)", lambda: ["taskset", "-c", str(max(CPU[0], 0))], []),
    ("busy-polling (--spin-us 100, both)", lambda: [], ["--spin-us", "100"]),
)


def lockstep_speed(seconds, runs=3):
    print(f"\n(ii) lockstep speed, {seconds:g} simulated s per run, median of {runs} runs  [load before: {' '.join(load())}]")
    print("| scene | the two processes | simulated s / wall s (runs) | median | wall per tick [us] | "
          "in-process loop per tick [us] | process boundary per tick [us] |")
    print("|---|---|---|---|---|---|---|")
    for name in ("paper_ideal", "paper_clearance"):
        scene = os.path.join(SCENES, name + ".yaml")
        inproc = in_process_us_per_tick(scene, seconds)
        for way, both, flags in LOCKSTEP_WAYS:
            xs = []
            for _ in range(runs):
                out = run_pair(scene, seconds, lockstep=True, fw_extra=flags, ctl_extra=flags, both=both())
                xs.append(grab(out, r"\(([\d.]+) x real time\)"))
            x = statistics.median(xs)
            per_tick = 1000.0 / x  # [us] of wall time per 1 ms tick
            print(f"| {name} | {way} | {', '.join(f'{x:.2f}' for x in xs)} | {x:.2f} | {per_tick:.1f} | {inproc:.1f} | "
                  f"{per_tick - inproc:.1f} |", flush=True)
    print(f"[load after: {' '.join(load())}]")


def long_run(seconds):
    print(f"\n(iii) {seconds:g} s at 1 kHz real time, paper_clearance + pointing_controller  [load before: {' '.join(load())}]")
    fw = ["--cpu", str(CPU[0])] if CPU[0] >= 0 else []
    out, floor = with_floor(1000.0, seconds, lambda: run_pair(os.path.join(SCENES, "paper_clearance.yaml"), seconds,
                                                              fw_extra=fw))
    for line in out.splitlines():
        if line.startswith("firmware_sim:") and "ticks" in line or line.startswith("  "):
            print(line)
    lat = lateness(out)
    print(f"  cyclictest (same period, priority {RT_PRIORITY}, CPU {CPU[0]}, {seconds / 2:g} s before + {seconds / 2:g} s after) "
          f"[us]: p50 {floor[0]:.0f}  p99 {floor[1]:.0f}  p99.9 {floor[2]:.0f}  max {floor[3]:.0f}")
    print(f"  firmware_sim / cyclictest: p50 / p99 / p99.9 / max = {ratios(lat, floor)}")
    print(f"[load after: {' '.join(load())}]")


def main():
    p = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(p)
    p.add_argument("--seconds", type=output_file.arg_decimal(1e-3, 1e6), default=10.0,
                   help="seconds per rate in the sweep")
    p.add_argument("--rates", type=output_file.arg_whole_list(1, 10**6), default="1000,2000,4000,5000,8000,10000",
                   help="control rates of the sweep [Hz]")
    p.add_argument("--spin", type=output_file.arg_decimal(0, 1), default=0.0,  # at most the period, firmware's 0.1 s
                   help="also sweep with --spin-us = this fraction of the period, in [0, 1] (0: only the plain sweep)")
    p.add_argument("--lockstep-seconds", type=output_file.arg_decimal(1e-3, 1e6), default=10.0)
    p.add_argument("--long", type=output_file.arg_decimal(1e-3, 1e6), default=60.0, help="seconds of the 1 kHz run")
    p.add_argument("--chrt", type=output_file.arg_whole(0, 99), default=60,
                   help="real-time runs: start both processes under SCHED_FIFO at this priority (chrt -f; the "
                        "firmware loop thread still raises itself to 80); 0 = SCHED_OTHER")
    p.add_argument("--cpu", type=output_file.arg_cpu, default=1,
                   help="CPU of firmware_sim's loop thread and of cyclictest's thread (-1: no pinning)")
    output_file.add_build(p)
    for skip in ("--skip-sweep", "--skip-lockstep", "--skip-long"):
        p.add_argument(skip, action="store_true")
    p.add_argument("--results", action="store_true", help="also write docs/results/bench_timing.md")
    a = p.parse_args()
    if a.spin * 1e6 / min(a.rates) > 1e5:  # firmware_sim --spin-us takes [0, 100000]: refused before any run
        p.error(f"--spin {a.spin:g} of the {1 / min(a.rates):g} s period (--rates {min(a.rates)}) is "
                f"{a.spin / min(a.rates):g} s, past firmware_sim's --spin-us bound of 0.1 s")
    # (pass 99) a tick firmware_sim cannot step (333 Hz) ended in an internal error after measuring the others
    if bad := [r for r in a.rates if 1000 % r and (r % 1000 or r > 50000)]:
        p.error(f"--rates {bad[0]}: paper_clearance ticks a whole number of its 1 ms steps, or one step of 1/rate for "
                "a multiple of 1 kHz up to 50 kHz (its 1 ms output interval, its 20 us contact sub-step)")
    import results_page  # (on the path set above)
    import timing_page  # (beside this script)
    t0, load0 = results_page.measured_start(os.path.join(ROOT, "docs/results/bench_timing.md"), a.results)
    global BIN
    BIN, CPU[0] = os.path.join(ROOT, a.build, "bin"), a.cpu
    for t in ("firmware_sim", "pointing_controller"):
        if not os.access(os.path.join(BIN, t), os.X_OK):
            raise output_file.Refused(f"{BIN}/{t} missing: cmake --build {a.build} -j2 --target firmware_sim "
                                      "pointing_controller")
    enter_namespace()
    sys.stdout = timing_page.Tee(sys.stdout) if a.results else sys.stdout
    if a.chrt > 0:
        if subprocess.run(["chrt", "-f", str(a.chrt), "true"], capture_output=True).returncode == 0:
            CHRT.extend(["chrt", "-f", str(a.chrt)])
        else:
            print(f"hil_speed: warning: chrt -f {a.chrt} refused here, processes run SCHED_OTHER")
    print(f"hil_speed: {os.cpu_count()} CPUs, kernel {os.uname().release}, load {' '.join(load())}; "
          f"real-time runs: controller and firmware_sim {'under ' + ' '.join(CHRT) if CHRT else 'SCHED_OTHER'} "
          "(firmware loop thread SCHED_FIFO 80)")
    if not a.skip_sweep:
        sweep(a.rates, a.seconds, 0.0)
        if a.spin > 0:
            sweep(a.rates, a.seconds, a.spin)
    if not a.skip_lockstep:
        lockstep_speed(a.lockstep_seconds)
    if not a.skip_long:
        long_run(a.long)
    if a.results:
        timing_page.write(os.path.join(ROOT, "docs/results/bench_timing.md"), sys.argv[1:], sys.stdout.copy.getvalue(),
                          t0, load0)
        sys.stdout = sys.stdout.out
        print("hil_speed: wrote docs/results/bench_timing.md")


if __name__ == "__main__":
    sys.exit(output_file.run_script("hil_speed", main))
