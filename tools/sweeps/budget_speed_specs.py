"""The two specs budget_speed.py runs, derived from the user's: the default
run (the spec as written, its samples cut by --samples) and the fine run
(sampling: scene, sim.substep --fine-substep under the fixed policy); each
read and checked as the sweep reads it before anything runs."""
import json
import math
import pathlib
import sys

if __name__ == "__main__":  # (pass 79) run alone it ended in a traceback (its imports are budget_speed.py's)
    print("budget_speed_specs.py: error: a module of tools/sweeps/budget_speed.py, not a program: run "
          "budget_speed.py, which derives these specs", file=sys.stderr)
    sys.exit(2)

from output_file import Refused  # noqa: E402 (tools/pages, on the path budget_speed.py sets)

FINE_KEYS = ("sim.substep", "sim.substep_policy")  # what the fine run sets: a spec may not set or disperse them


def derived_specs(spec_path, samples, fine_substep):
    """(the user's spec as a plain dict, {run: its spec's text}, {"scene", "controller": the paths as the
    sweep found them, links unresolved}): the spec
    read and checked as the sweep reads it (its YAML, its paths: SweepSpec;
    a refusal names the user's file, line and key), its scene and controller
    made absolute, its samples cut (samples); the fine run with sampling
    scene and set: sim.substep fine_substep under the fixed policy. A spec
    that sets or disperses those has no fine run: refused at its line."""
    import gimbalsim
    from gimbalsim._errors import SpecError
    from gimbalsim._spec import Spec
    from gimbalsim._sweep_spec import SweepSpec
    try:
        spec = Spec(spec_path)
        root = spec.root.value
        if "controller" not in root:
            spec.refuse("controller", "missing: not a closed-loop sweep spec (the budget needs its controller)")
        aliases = gimbalsim.key_aliases()
        for section in ("set", "parameters", "grid"):
            node = root.get(section)
            for key, n in (node.value.items() if node is not None and isinstance(node.value, dict) else ()):
                if aliases.get(key, key) in FINE_KEYS:
                    spec.refuse(f"{section}.{key}", "the fine run sets sim.substep (--fine-substep) under the fixed "
                                "policy: a spec that sets or disperses it has no fine run to compare with; leave "
                                "it out", n)
        user = SweepSpec(spec_path)
    except SpecError as e:
        raise Refused(str(e)) from None
    plain = spec.root.plain()
    given = {"scene": user.scene_path, **({"controller": user.closed.controller_path}
                                          if user.closed.controller_path is not None else {})}
    for key, path in given.items():
        plain[key] = str(pathlib.Path(path).resolve())
    if samples is not None:
        if samples > user.samples:  # (pass 38) it ran the spec's 2 units for --samples 4, silently
            raise Refused(f"--samples {samples}: {spec_path} has {user.samples} samples; give at most that")
        plain["samples"] = samples
    fine = {**plain, "sampling": "scene",
            "set": {**(plain.get("set") or {}), "sim.substep": fine_substep, "sim.substep_policy": "fixed"}}
    return plain, {name: "".join(f"{json.dumps(k)}: {_yaml(v)}\n" for k, v in x.items())
                   for name, x in (("default", plain), ("fine", fine))}, given


def _yaml(x):
    """x as YAML the sweep reads back as x (its YAML 1.2 numbers): JSON's
    forms, where every name is quoted and every number reads as one, and
    YAML's for the infinities JSON lacks. Why not yaml.safe_dump: it writes
    for YAML 1.1, leaving a name such as 1e-4 bare, which the sweep reads as
    a number."""
    if isinstance(x, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))}: {_yaml(v)}" for k, v in x.items()) + "}"
    if isinstance(x, list):
        return "[" + ", ".join(_yaml(v) for v in x) + "]"
    if isinstance(x, float) and not math.isfinite(x):
        return ".nan" if math.isnan(x) else (".inf" if x > 0 else "-.inf")
    return json.dumps(x)


def check_derived(path, name):
    """The sweep's own check of a derived spec, in process: a refusal says
    which run's spec and what was added, never only the temporary's name."""
    from gimbalsim._errors import SpecError
    from gimbalsim._sweep_spec import SweepSpec
    try:
        SweepSpec(path)
    except SpecError as e:
        added = "the samples cut" if name == "default" else \
            "sampling: scene, sim.substep and sim.substep_policy fixed added under set:"
        what = f"key '{e.key}': " if e.key else ""
        raise Refused(f"the {name} run's spec (yours with {added}) is refused: {what}"
                      f"{str(e).split(what, 1)[-1] if what else str(e)}") from None
