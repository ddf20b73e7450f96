#!/usr/bin/env python3
"""Scaling of gimbalsim.sweep on this machine, and what it predicts for a
bigger cluster (issue 12's figures).

    PYTHONPATH=build/python /usr/bin/python3 tools/bench/sweep_scaling.py [--samples 200] [--duration 0.5] [--results]

(--results also writes docs/results/sweep_scaling.md through tools/pages/results_page.py.)

1. The same sweep (paper_clearance over the tolerance spec's parameters,
   sim.duration shortened) with 1 and 2 local workers: samples per second,
   scaling efficiency, mean run time per sample, the engine's overhead per
   sample (worker time not spent in our tasks).
2. The scheduler's own cost: N empty tasks through a 2-worker cluster,
   seconds per task.
3. The prediction for W workers: each worker does a sample per (run +
   overhead); the scheduler can hand out at most 1 / (cost per task) tasks per
   second, each of `batch` samples.
"""
import argparse
import json
import pathlib
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "pages"))
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


def run(spec, out, workers, batch):
    p = subprocess.run([sys.executable, "-m", "gimbalsim.sweep", str(spec), "--out", str(out), "--workers",
                        str(workers), "--batch", str(batch), "--no-progress"], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(p.stderr)
    return json.loads((out / "summary.json").read_text())["engine"]


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


def report(a, e, per_task):
    """The figures as Markdown (printed, and the body of docs/results/sweep_scaling.md)."""
    md = [f"{a.samples} samples of paper_clearance over the tolerance spec's parameters (clearance, friction "
          f"coefficient, restitution, initial eccentricity), sim.duration {a.duration} s, {a.batch} samples per "
          f"task, through `python3 -m gimbalsim.sweep` with 1 and then 2 local Dask workers; then "
          f"{a.noop_tasks} empty tasks through a 2-worker cluster.", "",
          "| local workers | samples/s | run per sample | engine overhead per sample | overhead / run |",
          "|---|---|---|---|---|"]
    for w, x in e.items():
        md.append(f"| {w} | {x['samples_per_s']:.2f} | {x['mean_run_s'] * 1e3:.1f} ms | "
                  f"{x['engine_overhead_per_sample_s'] * 1e3:.2f} ms | "
                  f"{x['engine_overhead_per_sample_s'] / x['mean_run_s']:.1%} |")
    eff = e[2]["samples_per_s"] / (2 * e[1]["samples_per_s"])
    md += ["", f"Scaling efficiency 1 -> 2 workers: **{eff:.0%}** (on 2 cores shared with whatever else runs: "
           "see the load average in the header).", "",
           f"Scheduler: {per_task * 1e3:.2f} ms per empty task ({1 / per_task:.0f} tasks/s through 2 workers).", "",
           "Prediction for W workers: each worker does a sample per (run + overhead) of the 1-worker row; the "
           "scheduler hands out at most 1 / (cost per task) tasks per second, each of the batch's samples:", "",
           "| workers | predicted samples/s | bound by | scheduler load |", "|---|---|---|---|"]
    run_s = e[1]["mean_run_s"] + e[1]["engine_overhead_per_sample_s"]
    for w in (10, 100, 1000):
        demand = w / run_s / a.batch  # tasks/s the workers would ask for
        rate = min(w / run_s, a.batch / per_task)
        md.append(f"| {w} | {rate:.0f} | {'workers' if demand * per_task < 1 else 'scheduler'} | "
                  f"{demand * per_task:.0%} of its task rate |")
    return "\n".join(md) + "\n", eff


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=200)
    ap.add_argument("--duration", type=float, default=0.5, help="sim.duration of each sample [s]")
    ap.add_argument("--batch", type=int, default=5)
    ap.add_argument("--noop-tasks", type=int, default=2000)
    ap.add_argument("--results", action="store_true", help="also write docs/results/sweep_scaling.md")
    a = ap.parse_args()
    t0, load0 = time.time(), open("/proc/loadavg").read()
    with tempfile.TemporaryDirectory() as d:
        d = pathlib.Path(d)
        write_text(d / "spec.yaml", spec_text(a.samples, a.duration))
        e = {w: run(d / "spec.yaml", d / f"w{w}", w, a.batch) for w in (1, 2)}
    per_task = scheduler_cost(a.noop_tasks)
    text, eff = report(a, e, per_task)
    print(text)
    if a.results:
        import results_page
        command = "PYTHONPATH=build/python /usr/bin/python3 tools/bench/sweep_scaling.py " + " ".join(
            shlex.quote(x) for x in sys.argv[1:])
        results_page.write_page(ROOT / "docs/results/sweep_scaling.md", "Sweep scaling on Dask", command.strip(),
                                text, summary=f"{e[2]['samples_per_s']:.1f} samples/s on 2 workers, scaling "
                                f"1 -> 2 workers {eff:.0%}", t0=t0, load0=load0)
        print("sweep_scaling: wrote docs/results/sweep_scaling.md")


if __name__ == "__main__":
    sys.exit(run_script("sweep_scaling", main))
