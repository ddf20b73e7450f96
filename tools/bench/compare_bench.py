#!/usr/bin/env python3
"""Before/after speed of two gimbalsim_bench binaries, measured in one run.

    /usr/bin/python3 tools/bench/compare_bench.py OLD_BENCH NEW_BENCH \
        [--filter 'BM_(Rk4|Step)<'] [--rounds 5] [--min-time 0.2]

The two binaries run alternately, round after round (old, new, old, new, ...),
so that load on this shared machine falls on both alike. Each round is one
Google Benchmark pass of every matching benchmark; the table gives the median
CPU time over the rounds per binary and the ratio new / old (below 1: faster).
Exit 2 when a binary cannot be run or a benchmark is missing from one side.
"""
import argparse
import json
import statistics
import subprocess
import sys
import os
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pages"))
import output_file  # noqa: E402,F401  (its import keeps the console: a reader gone stops nothing)


ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def refuse(why):
    """Exit 2, as the docstring says, for a binary that cannot run or a side without a benchmark."""
    print(f"compare_bench: {why}; nothing compared", file=sys.stderr)
    sys.exit(2)


def run(side, binary, args):
    """binary's stdout, run where the benchmarks find their scenes (tools/scenes/ of this repository: a run from
    elsewhere failed and blamed OLD)."""
    try:
        return subprocess.run([binary, *args], check=True, capture_output=True, text=True, cwd=ROOT).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        told = (getattr(e, "stderr", "") or "").strip().splitlines()[-3:]
        refuse(f"{side.upper()} {binary}: cannot run it ({e}){''.join(chr(10) + '  ' + t for t in told)}")


def listed(side, binary, flt):
    """The benchmarks binary holds that the filter matches (a dry run of both sides before any timing)."""
    names = set(run(side, binary, [f"--benchmark_filter={flt}", "--benchmark_list_tests=true"]).split())
    if not names:
        refuse(f"{side.upper()} {binary}: no benchmark matches --filter {flt!r}")
    return names


def one_pass(side, binary, flt, min_time):
    out = run(side, binary, [f"--benchmark_filter={flt}", f"--benchmark_min_time={min_time}",
                             "--benchmark_format=json"])
    return {b["name"] + " [" + b["time_unit"] + "]": b["cpu_time"] for b in json.loads(out)["benchmarks"]}


def main():
    ap = argparse.ArgumentParser(allow_abbrev=False, description=__doc__.splitlines()[0])
    output_file.standard_flags(ap)
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("--filter", default="BM_(Rk4|Step)<")
    ap.add_argument("--rounds", type=output_file.arg_whole(1, 10**6), default=5)
    ap.add_argument("--min-time", type=output_file.arg_decimal(1e-3, 1e4), default=0.2,
                    help="seconds per benchmark per pass")
    a = ap.parse_args()
    binaries = {side: os.path.abspath(getattr(a, side)) for side in ("old", "new")}
    for side, binary in binaries.items():  # both checked before either is timed
        if not (os.path.isfile(binary) and os.access(binary, os.X_OK)):
            refuse(f"{side.upper()} {getattr(a, side)}: no such program (a gimbalsim_bench binary)")
    held = {side: listed(side, binary, a.filter) for side, binary in binaries.items()}
    if held["old"] != held["new"]:
        refuse(f"missing on one side: {', '.join(sorted(held['old'] ^ held['new']))}")
    times = {"old": {}, "new": {}}
    for _ in range(a.rounds):
        for side, binary in binaries.items():
            for name, t in one_pass(side, binary, a.filter, a.min_time).items():
                times[side].setdefault(name, []).append(t)
    names = sorted(set(times["old"]) | set(times["new"]))
    missing = [n for n in names if n not in times["old"] or n not in times["new"]]
    if missing:
        refuse(f"missing on one side: {', '.join(missing)}")
    print(f"{'benchmark [unit]':50s} {'old':>10s} {'new':>10s} {'new/old':>8s}   (median CPU time of {a.rounds} rounds)")
    for n in names:
        o, w = statistics.median(times["old"][n]), statistics.median(times["new"][n])
        print(f"{n:50s} {o:10.1f} {w:10.1f} {w / o:8.3f}")


if __name__ == "__main__":
    main()
