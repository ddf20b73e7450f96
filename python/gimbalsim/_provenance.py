"""What a sweep's sample really ran with: each dispersed key as the loaded
scene (or controller) applied it, read back after loading, and fingerprints of
the base scene and controller configuration, so that a replay can tell whether
its inputs are still the sweep's (docs/python.md "Sweeps").

A fingerprint is the SHA-256 (hex) of the UTF-8 text `key=value\\n` of every key
of the loaded object, sorted by key, each value as `values()` gives it (the
text `--set` reads back exactly)."""
import functools
import hashlib

import gimbalsim
from ._closed_spec import CONTROLLER_PREFIX
from . import dispersion

APPLIED = "applied."       # code name of a column: applied.<design column>
DIFFERS = "applied_differs"  # the keys whose applied value is not the drawn one, space-separated
SCENE_FINGERPRINT = "base_scene_sha256"
CONTROLLER_FINGERPRINT = "controller_config_sha256"


def canonical_text(values):
    """The text a fingerprint hashes: `key=value` lines, sorted by key."""
    return "".join(f"{k}={values[k]}\n" for k in sorted(values))


def fingerprint(values):
    return hashlib.sha256(canonical_text(values).encode("utf-8")).hexdigest()


def fingerprints(spec):
    """{column: fingerprint} of the spec's base scene and, for a closed-loop
    spec, its controller configuration; the columns in this order (computed
    once per spec)."""
    if getattr(spec, "_fingerprints", None) is None:
        out = {SCENE_FINGERPRINT: fingerprint(spec.base.values())}
        if spec.closed is not None:  # the controller the closed-loop spec loaded
            out[CONTROLLER_FINGERPRINT] = fingerprint(spec.closed.controller._values_text())
        spec._fingerprints = out
    return spec._fingerprints


def columns(spec):
    """The provenance columns' code names, after the sweep's own columns."""
    return [APPLIED + c for c in spec.design.columns()] + [DIFFERS] + list(fingerprints(spec))


def csv_names(spec, csv_name, units):
    """columns() by the CSV convention: applied.contact.clearance ->
    applied_contact_clearance_m, applied.initial.ecc[0] -> applied_initial_ecc_0_m."""
    names = []
    for c in spec.design.columns():
        plain = c.replace(".", "_").replace("[", "_").replace("]", "")
        names.append(csv_name("applied_" + plain, units.get(c.split("[")[0], "")))
    return names + [DIFFERS] + list(fingerprints(spec))


@functools.lru_cache(maxsize=None)
def _key_types():
    types = {k["key"]: k["type"] for k in gimbalsim.keys()}
    types.update({old: types[key] for old, key in gimbalsim.key_aliases().items()})
    for k in gimbalsim.controller_keys():  # as given, and as a closed-loop design names them
        types[k["key"]] = types[CONTROLLER_PREFIX + k["key"]] = k["type"]
    return types


# Keys with no value of their own: the scene sets another key from them. For
# each, (the value the model runs with, from the loaded values; the key it
# sets and the value that key gets when the draw is applied as drawn).
def _clearance(prefix):
    """<prefix>clearance: sets <prefix>journal_radius = <prefix>bearing_radius - c.
    A joint's own key is in the values only where the scene gave it
    (KeyTable::values); else the shared contact.* one acts."""
    def get(v, name):
        return float(v.get(prefix + name, v["contact." + name]))
    return (lambda v: get(v, "bearing_radius") - get(v, "journal_radius"),
            prefix + "journal_radius", lambda v, c: get(v, "bearing_radius") - float(c))


# Both bearings' (contact.*) and each joint's own (jointN.contact.*); the old
# spelling contact1.* is read as joint1.contact.*.
_DERIVED = {prefix + "clearance": _clearance(prefix)
            for prefix in ("contact.", "joint1.contact.", "joint2.contact.")}
_DERIVED["contact1.clearance"] = _clearance("joint1.contact.")


def _same(drawn, applied):
    number = lambda v: isinstance(v, (int, float)) and not isinstance(v, bool)
    if number(drawn) and number(applied):
        return float(drawn) == float(applied)
    return gimbalsim.format_value(drawn) == gimbalsim.format_value(applied)


_SHARED = {"initial.ecc1": "initial.ecc", "initial.ecc2": "initial.ecc"}  # a joint's own key -> the shared one


def applied(scene_values, drawn):
    """The applied columns of a sample: each drawn key ({key: value}, in the
    design's order) as the loaded object holds it (scene_values: {key: --set
    text}, scene and controller keys together), one value per vector element;
    then the keys the load did not apply as drawn, space-separated (equal
    after the text round trip counts as applied). A derived key records the
    value the model runs with (contact.clearance: bearing_radius -
    journal_radius, which may differ from the draw in the last bit) and is
    checked on the key it sets (journal_radius == bearing_radius - drawn)."""
    types = _key_types()
    values, differs = [], []
    for key, want in drawn.items():
        want = list(want) if isinstance(want, (list, tuple)) else [want]
        if key in _DERIVED:
            model_value, sets, expected = _DERIVED[key]
            got = [model_value(scene_values)]
            ok = float(scene_values.get(sets, scene_values["contact.journal_radius"])) == expected(scene_values, want[0])
        else:
            canonical = gimbalsim.key_aliases().get(key, key)
            # A joint's own key that a scene lists only where it was given (initial.ecc1,
            # initial.ecc2 beside initial.ecc): absent, it has the shared value.
            text = scene_values.get(canonical, scene_values.get(_SHARED.get(canonical, "")))
            got = [None] if text is None else gimbalsim._typed(text, types.get(key, "string"))
            got = list(got) if isinstance(got, list) else [got]
            if types.get(key) == "inertia":  # compared and written in the design's six-number spelling
                want = dispersion.inertia6(want)
                got = dispersion.inertia6([got[0:3], got[3:6], got[6:9]] if len(got) == 9 else got) or [None]
            ok = text is not None and len(got) == len(want) and all(_same(w, g) for w, g in zip(want, got))
            got = (got + [None] * len(want))[:len(want)]  # a column per drawn element, whatever was loaded
        values += got
        if not ok:
            differs.append(key)
    return values + [" ".join(differs)]


def values(spec, result):
    """The provenance columns' values of a sample: result["applied"] (from
    applied(), None when no scene was loaded: refused or crashed) and the base
    fingerprints."""
    a = result.get("applied")
    if a is None:
        a = [None] * (len(spec.design.columns()) + 1)
    return list(a) + list(fingerprints(spec).values())


SPEC_COPY = "spec.yaml"
INPUTS = "inputs.json"


def record_inputs(spec, out, write):
    """At a sweep's start, what a replay needs beside results.csv: a copy of
    the spec (DIR/spec.yaml) and DIR/inputs.json (where the spec was, whose
    folder its paths are read against, and the base fingerprints). write(path,
    text) writes a file whole or raises."""
    import json
    import pathlib

    write(out / SPEC_COPY, spec.spec_text)
    spec_path = pathlib.Path(spec.spec_path).absolute()
    # workdir: where a relative path of the spec fell back to (a replay from elsewhere looks there too);
    # spec_sha256: the spec file as it was, which a replay compares (an allocation's value sweep runs a text
    # made from its spec, never equal to the file: compared with the copy, it read as edited, pass 56)
    write(out / INPUTS, json.dumps({"spec": str(spec_path), "spec_folder": str(spec.spec_folder),
                                    "workdir": str(pathlib.Path.cwd()), "scene": str(spec.scene_path),
                                    "spec_sha256": file_sha256(spec_path), "fingerprints": fingerprints(spec)},
                                   indent=2) + "\n")


def file_sha256(path):
    """The SHA-256 of a file's bytes (hex), or None when it cannot be read."""
    import hashlib
    try:
        with open(path, "rb") as f:
            return hashlib.sha256(f.read()).hexdigest()
    except OSError:
        return None
