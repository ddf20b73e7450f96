"""Mutation fuzzer of the sweep and tuning spec readers (SweepSpec, TuneSpec),
in-process: no atheris among Debian's packages, so mutations are random
(bytes, YAML tokens, lines of other seeds) from a fixed seed, and an input
that reaches a refusal (or an acceptance) not seen before joins the corpus.

An input that raises anything but SpecError, runs longer than --timeout
seconds, or needs more memory than --memory-mb is a crash, saved to
CRASHES/fuzz_spec-<kind>-<sha1>. Prints the libFuzzer targets' summary line
of tools/ci/fuzz.sh; exit 1 when anything crashed.

    PYTHONPATH=build/python python3 tests/fuzz/fuzz_spec.py [--seconds S | --runs N] [--seed K]
        [--corpus DIR] [--crashes DIR] [--timeout S] [--memory-mb M] [FILE...]

FILE... replays those inputs only (a crash's file, say). In corpus files,
@ROOT@ stands for the source tree (seeds name the project's scenes)."""
import argparse
import hashlib
import os
import pathlib
import random
import re
import resource
import sys
import tempfile
import threading
import time
import traceback

ROOT = pathlib.Path(__file__).resolve().parents[2]
NAME = "fuzz_spec"

# YAML and spec tokens the mutations insert: the classes of issue-time crashes and their neighbours
TOKENS = ["null", "~", "", "!!binary aGVsbG8=", "2024-01-01", "2001-12-14t21:59:43.10-05:00", "1e-4", "1E5", ".nan",
          "-.inf", ".inf", "0x1F", "0o17", "010", "1_000", "1:20", "yes", "no", "true", "!!float 1", "!!int x",
          "!!str 3", "!foo bar", "!!python/object:os.system x", "!!set {a}", "!!omap [a: 1]", "{}", "[]", "[[1, 2]]",
          "{a: 1}", "&a [1, 2]", "*a", "<<: {x: 1}", "1e400", "-1", "0", "99999999999999999999999", "1e-320",
          "\xff", "\x00", "\t", "'", "\"", "#", ": ", "- ", "? ", "|\n  x", "uniform", "loguniform", "normal",
          "choice", "disk", "within", "fraction", "radius", "center", "mean", "sd", "min", "max",
          "{uniform: [1, 2]}", "{loguniform: [0, 1]}", "{choice: [null]}", "{choice: [{a: 1}]}",
          "{disk: {within: contact.clearance}}", "{disk: {within: friction.mu, fraction: 2}}",
          "{disk: {within: sim.duration}}", "{normal: {mean: 0, sd: 1e-300}}", "[1.0e-4, 8.0e-4]",
          "contact.clearance", "friction.mu", "initial.ecc", "friction.law", "sim.duration", "azimuth.kp",
          "torque.tau2", "sensors.star_tracker_noise", "samples", "seed", "grid", "set", "parameters", "gains",
          "plants", "objective", "metric", "percentile", "trials", "batch", "duration", "controller_set",
          "max_track", "rms_track", "[5.0, 20.0]", "[0, 1, 2, 3, 4, 5, 6, 7, 8, 9]",
          # the closed-loop sweep's phases and indices (issue-time refusals: infinite windows, empty phases)
          "controller", "default", "phases", "indices", "window", "separation", "level", "confidence",
          "requirement", "ape", "rpe", "pde", "knowledge", "slew", "hold", "track", "{late: [0.4, 0.5]}",
          "{window: .inf}", "{window: 0}", "[slew, hold, track]", "profile.hold_time", "control.period"]


class Hang(Exception):
    pass


def seeds(extra_dirs):
    """(kind, text) of the project's specs (relative paths made absolute) and any corpus files."""
    out = []
    for kind, folder in (("sweep", ROOT / "tools" / "sweeps"), ("tune", ROOT / "tools" / "tuning")):
        for f in sorted(folder.glob("*.yaml")):
            text = f.read_bytes()
            text = text.replace(b"../../controllers/", str(ROOT / "controllers").encode() + b"/")
            text = text.replace(b"../scenes/", str(ROOT / "tools" / "scenes").encode() + b"/")
            out.append((kind, text))
    for d in extra_dirs:
        d = pathlib.Path(d)
        if d.is_dir():
            for f in sorted(p for p in d.iterdir() if p.is_file()):
                kind = "tune" if f.name.startswith("tune") else "sweep"
                out.append((kind, f.read_bytes().replace(b"@ROOT@", str(ROOT).encode())))
    return out


def mutate(rng, data, pool):
    data = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        op = rng.randrange(7)
        pos = rng.randint(0, len(data))
        if op == 0 and data:  # a byte changed
            data[min(pos, len(data) - 1)] = rng.randrange(256)
        elif op == 1:  # a token inserted
            data[pos:pos] = rng.choice(TOKENS).encode("utf-8", "surrogateescape")
        elif op == 2 and data:  # a value replaced by a token
            lines = bytes(data).split(b"\n")
            k = rng.randrange(len(lines))
            if b":" in lines[k]:
                head = lines[k].split(b":", 1)[0]
                lines[k] = head + b": " + rng.choice(TOKENS).encode("utf-8", "surrogateescape")
            data = bytearray(b"\n".join(lines))
        elif op == 3 and data:  # a range cut
            data[pos:pos + rng.randint(1, 40)] = b""
        elif op == 4 and data:  # a range repeated
            end = min(len(data), pos + rng.randint(1, 80))
            data[pos:pos] = data[pos:end] * rng.randint(1, 3)
        elif op == 5:  # a line of another input
            lines = rng.choice(pool)[1].split(b"\n")
            data[pos:pos] = rng.choice(lines) + b"\n"
        else:  # a line deleted
            lines = bytes(data).split(b"\n")
            if len(lines) > 1:
                del lines[rng.randrange(len(lines))]
            data = bytearray(b"\n".join(lines))
    return bytes(data[:1 << 16])


class Target:
    def __init__(self, tmp):
        import gimbalsim.sweep
        import gimbalsim.tune
        import optuna
        from gimbalsim._spec import SpecError

        optuna.logging.set_verbosity(optuna.logging.ERROR)
        self.sweep, self.tune, self.optuna, self.SpecError = gimbalsim.sweep, gimbalsim.tune, optuna, SpecError
        self.path = pathlib.Path(tmp) / "spec.yaml"

    def run(self, kind, data):
        """The outcome's signature (for the corpus) or raises what the reader raised."""
        self.path.write_bytes(data)
        try:
            if kind == "sweep":
                s = self.sweep.SweepSpec(self.path)
                n = len(s.design)
                for i in {0, n - 1, n // 2}:  # what a worker would do with the first, middle and last sample
                    s.design.row_values(s.design.draw(i))
                s.header()
                return "accepted sweep"
            s = self.tune.TuneSpec(self.path)
            for j in {0, s.batch - 1}:
                s.plants.draw(j)
            trial = self.optuna.create_study(sampler=self.optuna.samplers.RandomSampler(seed=0)).ask()
            gains = {p.key: self.tune.suggest(trial, p) for p in s.gains}
            import gimbalsim
            gimbalsim.Controller(s.controller_path, {**s.controller_set, **gains})
            return "accepted tune"
        except self.SpecError as e:
            # the refusal's kind: its key and the message without numbers or quoted values
            return f"{kind} {e.key} " + re.sub(r"'[^']*'|[-+]?[0-9][0-9.eE+-]*", "", str(e).split(": ", 2)[-1])[:60]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seconds", type=float, default=None)
    ap.add_argument("--runs", type=int, default=None)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--corpus", action="append", default=[], help="corpus folder (read; the first also written)")
    ap.add_argument("--crashes", default=None, help="crashes folder (default: none written)")
    ap.add_argument("--timeout", type=float, default=10.0, help="seconds per input")
    ap.add_argument("--memory-mb", type=int, default=4096, help="address space of the whole process")
    ap.add_argument("files", nargs="*")
    a = ap.parse_args(argv)
    if a.seconds is None and a.runs is None and not a.files:
        a.seconds = 60.0
    resource.setrlimit(resource.RLIMIT_AS, (a.memory_mb << 20, resource.getrlimit(resource.RLIMIT_AS)[1]))
    tmp = tempfile.TemporaryDirectory(prefix="fuzz_spec.")
    target = Target(tmp.name)
    rng = random.Random(a.seed)
    pool = seeds(a.corpus) if not a.files else [
        ("tune" if "tune" in pathlib.Path(f).name else "sweep",
         pathlib.Path(f).read_bytes().replace(b"@ROOT@", str(ROOT).encode())) for f in a.files]
    seen, execs, crashes, n_seeds = set(), 0, [], len(pool)
    current = {"data": None, "kind": None, "t0": None}
    stop = threading.Event()

    def save(tag, kind, data, text):
        crashes.append(text)
        print(f"{NAME}: {tag} on a {kind} spec:\n{text}", file=sys.stderr)
        if a.crashes:
            os.makedirs(a.crashes, exist_ok=True)
            name = pathlib.Path(a.crashes) / f"{NAME}-{kind}-{tag}-{hashlib.sha1(data).hexdigest()[:16]}"
            name.write_bytes(data)

    def summary():
        n = len(list(pathlib.Path(a.corpus[0]).iterdir())) if a.corpus and pathlib.Path(a.corpus[0]).is_dir() else 0
        span = f"{a.seconds:g}" if a.seconds is not None else "-"
        print(f"{NAME:<28} {span:>6} s {execs:>12} execs {len(crashes):>3} crash {n:>6} corpus files", flush=True)

    def watchdog():  # C++ holding the thread never returns to the alarm: the last word is here
        while not stop.wait(0.5):
            t0 = current["t0"]
            if t0 is not None and time.monotonic() - t0 > 2 * a.timeout:
                save("timeout", current["kind"], current["data"], f"no answer in {2 * a.timeout:g} s")
                summary()
                os._exit(1)
    threading.Thread(target=watchdog, daemon=True).start()

    import signal

    def alarm(signum, frame):
        raise Hang()
    signal.signal(signal.SIGALRM, alarm)

    t_end = time.monotonic() + a.seconds if a.seconds is not None else None
    queue = list(pool) if a.files else []
    while True:
        if a.files:
            if not queue:
                break
            kind, data = queue.pop(0)
        else:
            if (t_end is not None and time.monotonic() > t_end) or (a.runs is not None and execs >= a.runs):
                break
            if execs < n_seeds:  # every seed once as it is, then mutants
                kind, data = pool[execs]
            else:
                kind, data = rng.choice(pool)
                data = mutate(rng, data, pool)
        current.update(data=data, kind=kind, t0=time.monotonic())
        signal.setitimer(signal.ITIMER_REAL, a.timeout)
        try:
            outcome = target.run(kind, data)
        except Hang:
            save("timeout", kind, data, f"longer than {a.timeout:g} s")
            outcome = None
        except MemoryError:
            save("oom", kind, data, f"more than {a.memory_mb} MB")
            outcome = None
        except KeyboardInterrupt:
            break
        except BaseException:
            save("crash", kind, data, traceback.format_exc())
            outcome = None
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            current["t0"] = None
        execs += 1
        if outcome is not None and outcome not in seen:
            seen.add(outcome)
            if a.corpus and not a.files:
                os.makedirs(a.corpus[0], exist_ok=True)
                (pathlib.Path(a.corpus[0]) / f"{kind}-{hashlib.sha1(data).hexdigest()[:16]}").write_bytes(data)
                pool.append((kind, data))
            elif not a.files:
                pool.append((kind, data))
    stop.set()
    summary()
    return 1 if crashes else 0


if __name__ == "__main__":
    sys.exit(main())
