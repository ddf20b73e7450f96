#!/usr/bin/env python3
"""Scaling of gimbalsim.sweep on this machine, its engine's overhead per
sample, and what it predicts for a bigger cluster.

    /usr/bin/python3 tools/bench/sweep_scaling.py [--samples 200] [--duration 0.5] [--build DIR]
        [--closed-samples 60] [--results]

(--results also writes docs/results/sweep_scaling.md through tools/pages/results_page.py.)

1. Two sweeps, each run three ways: 1 and 2 local workers, then a separate
   dask-scheduler with two dask-worker processes (on loopback) named by
   --scheduler. Open loop: paper_clearance over the tolerance spec's
   parameters, sim.duration shortened. Closed loop: the shipped budget's
   spec (tools/sweeps/pointing_budget.yaml) cut to --closed-samples units.
   For each: samples per second, mean run time per sample, the engine's
   overhead per sample (worker time not spent in our tasks: scheduling,
   serialisation, result rows; target at most 5 ms), and whether the three
   runs wrote the same rows (all but the wall time): they must.
2. The scheduler's own cost: N empty tasks through a 2-worker cluster,
   seconds per task.
3. The prediction for W workers: each worker does a sample per (run +
   overhead); the scheduler can hand out at most 1 / (cost per task) tasks per
   second, each of `batch` samples.
"""
import argparse
import contextlib
import csv
import json
import os
import pathlib
import shlex
import socket
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
import output_file  # noqa: E402  (the one reading of a flag's number)
from output_file import run_script, write_text  # noqa: E402  (the package's one writer)


def spec_text(samples, duration):
    return f"""scene: {ROOT}/tools/scenes/paper_clearance.yaml
set: {{sim.duration: {duration}}}
samples: {samples}
seed: 11
parameters:
  contact.clearance: {{uniform: [1.0e-4, 8.0e-4]}}
  friction.mu: {{uniform: [0.15, 0.35]}}
  contact.restitution: {{uniform: [0.8, 0.98]}}
  initial.ecc: {{disk: {{within: contact.clearance, fraction: 1.0}}}}
"""


def closed_spec_text(samples):
    """The shipped budget's spec, its first `samples` units (each key has its own stream: the same units)."""
    text = (ROOT / "tools/sweeps/pointing_budget.yaml").read_text()
    text = text.replace("scene: ../scenes/", f"scene: {ROOT}/tools/scenes/")
    assert "samples: 1109" in text and f"scene: {ROOT}" in text, "tools/sweeps/pointing_budget.yaml changed shape"
    return text.replace("samples: 1109", f"samples: {samples}")


def run(spec, out, batch, *how):
    """The sweep of spec into out, how: ("--workers", "N") or ("--scheduler", ADDRESS); its engine figures."""
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", str(out), *how, "--batch",
                        str(batch), "--no-progress"], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(p.stderr)
    return json.loads((out / "summary.json").read_text())["engine"]


def rows(out):
    """results.csv without its wall-time column: what must not depend on how the sweep ran."""
    with open(out / "results.csv", newline="") as f:
        table = list(csv.reader(f))
    w = table[0].index("wall_time_s")
    return [r[:w] + r[w + 1:] for r in table]


@contextlib.contextmanager
def separate_cluster(workers=2):
    """A dask-scheduler and `workers` dask-worker processes on loopback, as on a cluster; yields the address."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    procs = [subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                              **quiet)]
    try:
        for _ in range(workers):
            procs.append(subprocess.Popen(["dask-worker", address, "--nthreads", "1", "--no-dashboard", "--host",
                                           "127.0.0.1"], env=dict(os.environ), **quiet))
        from distributed import Client
        with Client(address, timeout="30s") as c:
            c.wait_for_workers(workers, timeout=60)
        yield address
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            p.wait(timeout=30)


WAYS = ("1 local worker", "2 local workers", "dask-scheduler + 2 dask-workers")


def three_ways(spec, d, batch):
    """{way: engine figures} of the sweep run the three ways, and whether all wrote the same rows."""
    e = {WAYS[0]: run(spec, d / "w1", batch, "--workers", "1"),
         WAYS[1]: run(spec, d / "w2", batch, "--workers", "2")}
    with separate_cluster() as address:
        e[WAYS[2]] = run(spec, d / "s2", batch, "--scheduler", address)
    same = rows(d / "w1") == rows(d / "w2") == rows(d / "s2")
    return e, same


def noop(x):
    return x


def scheduler_cost(n):
    from distributed import Client, LocalCluster
    import logging
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None, silence_logs=logging.ERROR) as c, \
            Client(c) as client:
        client.gather(client.map(noop, range(50)))  # warm up
        t0 = time.perf_counter()
        client.gather(client.map(noop, range(n), pure=False))
        return (time.perf_counter() - t0) / n


def engine_table(e, same):
    md = ["| how it ran | samples/s | run per sample | engine overhead per sample | overhead / run "
          "| end wait per sample | warm-up |",
          "|---|---|---|---|---|---|---|"]
    for way, x in e.items():
        md.append(f"| {way} | {x['samples_per_s']:.2f} | {x['mean_run_s'] * 1e3:.1f} ms | "
                  f"{x['engine_overhead_per_sample_s'] * 1e3:.2f} ms | "
                  f"{x['engine_overhead_per_sample_s'] / x['mean_run_s']:.1%} | "
                  f"{x['drain_idle_per_sample_s'] * 1e3:.2f} ms | {x['warm_up_s']:.2f} s |")
    worst = max(x["engine_overhead_per_sample_s"] for x in e.values())
    md += ["", f"Worst engine overhead per sample: **{worst * 1e3:.2f} ms** (target: at most 5 ms): the workers' "
               "time on anything but the tasks while tasks were left. The end wait is apart: each worker's time "
               "after its last task, with nothing left to run (it shrinks with more samples per worker), and so is the "
               "warm-up: every worker's import of the package, once, before the first task. The three "
               f"runs wrote {'**the same rows**' if same else '**different rows**'} (results.csv but its wall time)."]
    return md, worst


def report(a, open_e, open_same, closed_e, closed_same, per_task):
    """The figures as Markdown (printed, and the body of docs/results/sweep_scaling.md)."""
    md = [f"Two sweeps, each run with 1 and then 2 local Dask workers, then with a separate `dask-scheduler` and "
          f"two `dask-worker` processes (loopback) named by `--scheduler`; {a.batch} samples per task; then "
          f"{a.noop_tasks} empty tasks through a 2-worker cluster.", "",
          f"## Open loop: {a.samples} samples of paper_clearance", "",
          f"Over the tolerance spec's parameters (clearance, friction coefficient, restitution, initial "
          f"eccentricity), sim.duration {a.duration} s.", ""]
    table, open_worst = engine_table(open_e, open_same)
    md += table
    md += ["", f"## Closed loop: the shipped budget's first {a.closed_samples} units", "",
           "`tools/sweeps/pointing_budget.yaml` (paper_clearance, 5 s, the default controller, the bearing's "
           "tolerance and the sensors dispersed) cut to its first units.", ""]
    table, closed_worst = engine_table(closed_e, closed_same)
    md += table
    e1, e2 = open_e[WAYS[0]], open_e[WAYS[1]]
    eff = e2["samples_per_s"] / (2 * e1["samples_per_s"])
    md += ["", f"Scaling efficiency 1 -> 2 local workers (open loop): **{eff:.0%}** (on 2 cores shared with "
           "whatever else runs: see the load average in the header).", "",
           "## The scheduler and a bigger cluster", "",
           f"Scheduler: {per_task * 1e3:.2f} ms per empty task ({1 / per_task:.0f} tasks/s through 2 workers).", "",
           "Prediction for W workers: each worker does a sample per (run + overhead) of the open loop's 1-worker "
           "row; the scheduler hands out at most 1 / (cost per task) tasks per second, each of the batch's "
           "samples:", "",
           "| workers | predicted samples/s | bound by | scheduler load |", "|---|---|---|---|"]
    run_s = e1["mean_run_s"] + e1["engine_overhead_per_sample_s"]
    for w in (10, 100, 1000):
        demand = w / run_s / a.batch  # tasks/s the workers would ask for
        rate = min(w / run_s, a.batch / per_task)
        md.append(f"| {w} | {rate:.0f} | {'workers' if demand * per_task < 1 else 'scheduler'} | "
                  f"{demand * per_task:.0%} of its task rate |")
    return "\n".join(md) + "\n", eff, max(open_worst, closed_worst)


def main():
    ap = argparse.ArgumentParser(
        allow_abbrev=False, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    output_file.standard_flags(ap)
    ap.add_argument("--samples", type=output_file.arg_whole(1, 10**7), default=200, help="open-loop samples")
    ap.add_argument("--duration", type=output_file.arg_decimal(1e-3, 1e6), default=0.5,
                    help="sim.duration of each open-loop sample [s]")
    ap.add_argument("--closed-samples", type=output_file.arg_whole(1, 10**7), default=60,
                    help="closed-loop units of the shipped budget")
    ap.add_argument("--batch", type=output_file.arg_whole(1, 10**7), default=5)
    ap.add_argument("--noop-tasks", type=output_file.arg_whole(1, 10**7), default=2000)
    ap.add_argument("--results", action="store_true", help="also write docs/results/sweep_scaling.md")
    output_file.add_build(ap, holding="python/")
    a = ap.parse_args()
    try:  # the sweeps it times run the --build's package (PYTHONPATH alone was read: GIMBALSIM_BUILD ignored)
        output_file.import_package(a.build)
    except output_file.Refused as e:
        ap.error(str(e))
    for name, value, low in (("--samples", a.samples, 2), ("--closed-samples", a.closed_samples, 2),
                             ("--batch", a.batch, 1), ("--noop-tasks", a.noop_tasks, 1)):
        if not low <= value <= 1_000_000:
            ap.error(f"{name} must be a whole number in [{low}, 1000000]")
    if not 0.01 <= a.duration <= 100.0:
        ap.error("--duration must be in [0.01, 100] s")
    if a.results:  # refused now, not after the measurements
        import results_page
        results_page.check_page(ROOT / "docs/results/sweep_scaling.md")
    t0, load0 = time.time(), open("/proc/loadavg").read()
    with tempfile.TemporaryDirectory() as d:
        d = pathlib.Path(d)
        (d / "open").mkdir()
        (d / "closed").mkdir()
        write_text(d / "open.yaml", spec_text(a.samples, a.duration))
        write_text(d / "closed.yaml", closed_spec_text(a.closed_samples))
        open_e, open_same = three_ways(d / "open.yaml", d / "open", a.batch)
        closed_e, closed_same = three_ways(d / "closed.yaml", d / "closed", a.batch)
    per_task = scheduler_cost(a.noop_tasks)
    text, eff, worst = report(a, open_e, open_same, closed_e, closed_same, per_task)
    print(text)
    if not (open_same and closed_same):
        sys.exit("sweep_scaling: the three ways of running a sweep wrote different rows: not a result to publish")
    if a.results:
        command = "/usr/bin/python3 tools/bench/sweep_scaling.py " + " ".join(
            shlex.quote(x) for x in sys.argv[1:])
        results_page.write_page(ROOT / "docs/results/sweep_scaling.md", "Sweep scaling on Dask", command.strip(),
                                text, summary=f"{open_e[WAYS[1]]['samples_per_s']:.1f} samples/s on 2 workers, "
                                f"scaling 1 -> 2 workers {eff:.0%}, engine overhead at most {worst * 1e3:.2f} ms "
                                "per sample", t0=t0, load0=load0)
        print("sweep_scaling: wrote docs/results/sweep_scaling.md")


if __name__ == "__main__":
    sys.exit(run_script("sweep_scaling", main))
