#!/usr/bin/env python3
"""Per-call cost of the Python package against the C++ step (issue 11's figures).

    /usr/bin/python3 tools/bench/py_bench.py [--repeats 7] [--build DIR]   (the package of DIR/python)

For each scene: the C++ step (one Simulator.step(n=N) call, N large: the call's
overhead spread over N steps), Simulator.step(n=1) called N times from Python,
the batch form run(torques) with N rows, an empty call step(n=0) (the
call's own cost) and output() alone; then two threads
each stepping their own Simulator against one thread doing both jobs. Prints
medians over the repeats and the ratios, all measured in this one run.
"""
import argparse
import pathlib
import statistics
import threading
import time

import numpy as np

import os
import sys
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pages"))
import output_file  # noqa: E402  (its import keeps the console: a reader gone stops nothing)

gimbalsim = None  # the --build's package, imported once the flags are read (it was imported first: a traceback)

ROOT = pathlib.Path(__file__).resolve().parents[2]


def median_time(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def bench_scene(name, overrides, n, repeats):
    scene = gimbalsim.load_scene(ROOT / "tools" / "scenes" / f"{name}.yaml", overrides)
    tau = np.tile([5.0, 10.0], (n, 1))

    def fresh():
        return gimbalsim.Simulator(scene)

    def cpp():
        fresh().step(5.0, 10.0, n=n)

    def py_loop():
        sim = fresh()
        for _ in range(n):
            sim.step(5.0, 10.0)

    def batch():
        fresh().run(tau)

    sim_out = fresh()
    sim_out.step(5.0, 10.0, n=100)

    def empty_calls():
        for _ in range(n):
            sim_out.step(5.0, 10.0, n=0)

    def outputs():
        for _ in range(n):
            sim_out.output()

    t_cpp = median_time(cpp, repeats) / n
    t_loop = median_time(py_loop, repeats) / n
    t_batch = median_time(batch, repeats) / n
    t_out = median_time(outputs, repeats) / n
    t_call = median_time(empty_calls, repeats) / n
    print(f"{name:<16} {scene.variant:<28} {t_cpp*1e6:9.2f} {t_loop*1e6:9.2f} {t_loop/t_cpp:7.2f}x "
          f"{t_batch*1e6:9.2f} {t_batch/t_cpp:7.2f}x {t_call*1e6:9.2f} {t_out*1e6:9.2f}")
    return scene


def bench_threads(scene, n, repeats):
    def job():
        gimbalsim.Simulator(scene).step(5.0, 10.0, n=n)

    def one_thread():
        job()
        job()

    def two_threads():
        ts = [threading.Thread(target=job) for _ in range(2)]
        for t in ts:
            t.start()
        for t in ts:
            t.join()

    t1 = median_time(one_thread, repeats)
    t2 = median_time(two_threads, repeats)
    print(f"two jobs of {n} steps ({scene.name}): one thread {t1*1e3:.1f} ms, two threads {t2*1e3:.1f} ms: "
          f"speed-up {t1/t2:.2f}x (ideal 2x on 2 free cores)")


def main():
    ap = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(ap)
    ap.add_argument("--repeats", type=output_file.arg_whole(1, 1000), default=7, help="measurements per point (median)")
    ap.add_argument("--steps", type=output_file.arg_whole(1, 10**7), default=5000, help="steps per measurement")
    output_file.add_build(ap, holding="python/")
    a = ap.parse_args()
    return output_file.run_script("py_bench.py", lambda: measure(a))


def measure(a):
    global gimbalsim
    gimbalsim = output_file.import_package(a.build)
    print(f"medians of {a.repeats} repeats, {a.steps} steps each; times per step [us]")
    print(f"{'scene':<16} {'variant':<28} {'C++ step':>9} {'py step':>9} {'ratio':>8} {'batch':>9} {'ratio':>8} "
          f"{'step(n=0)':>9} {'output()':>9}")
    bench_scene("paper_ideal", {}, a.steps, a.repeats)
    clearance = bench_scene("paper_clearance", {}, a.steps, a.repeats)
    bench_scene("paper_clearance", {"sim.substep_policy": "adaptive", "friction.law": "coulomb_stick", "sim.step": 2e-3, "sim.substep_tol": 1e-6,
                                    "sim.output_interval": 2e-3}, a.steps, a.repeats)
    bench_threads(clearance, a.steps, a.repeats)


if __name__ == "__main__":
    sys.exit(main())
