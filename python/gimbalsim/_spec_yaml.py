"""How a spec's YAML is read: YAML 1.2's core schema for numbers (as the
scene loader reads them), anchors and aliases refused, each scalar by its
standard tag."""
import math
import re
import sys

import yaml

from ._number import underflowed


class Unexpanded(Exception):
    """An anchor or an alias in a spec, at its mark (refused as the scene loader refuses them)."""

    def __init__(self, mark, what):
        super().__init__(what)
        self.mark = mark


class SpecLoader(yaml.SafeLoader):
    """YAML 1.2's core schema for numbers, as the scene loader reads them:
    `1e-4` is a number (YAML 1.1 wants `1.0e-4`), `010` is ten, `1:20` and
    `1_000` are names. Dates, merge keys (`<<`) and `=` are not resolved: a
plain `2024-01-01` is a name. Anchors and aliases are refused, as the
scene loader refuses them (pass 81: a spec's alias copied one key's
distribution to another)."""

    def compose_node(self, parent, index):
        event = self.peek_event()
        if isinstance(event, yaml.AliasEvent):
            raise Unexpanded(event.start_mark, "aliases (*name) are not accepted: write the value out")
        if getattr(event, "anchor", None) is not None:
            raise Unexpanded(event.start_mark, "anchors (&name) are not accepted: write the value out")
        return super().compose_node(parent, index)


SpecLoader.yaml_implicit_resolvers = {
    first: [(tag, rx) for tag, rx in resolvers
            if tag not in ("tag:yaml.org,2002:int", "tag:yaml.org,2002:float", "tag:yaml.org,2002:timestamp",
                           "tag:yaml.org,2002:merge", "tag:yaml.org,2002:value")]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()}
_INT_RE = re.compile(r"^[-+]?[0-9]+$")
_FLOAT_RE = re.compile(r"^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?"
                       r"|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$")
SpecLoader.add_implicit_resolver("tag:yaml.org,2002:int", _INT_RE, list("-+0123456789"))
SpecLoader.add_implicit_resolver("tag:yaml.org,2002:float", _FLOAT_RE, list("-+0123456789."))

MAP, SEQ, STR = "tag:yaml.org,2002:map", "tag:yaml.org,2002:seq", "tag:yaml.org,2002:str"
STANDARD_TAGS = {MAP, SEQ, STR, "tag:yaml.org,2002:int", "tag:yaml.org,2002:float",
                  "tag:yaml.org,2002:bool", "tag:yaml.org,2002:null"}
_BOOLS = {"yes": True, "no": False, "true": True, "false": False, "on": True, "off": False}


def scalar(n):
    """A scalar by its (resolved or explicit) standard tag; anything else was
    refused before. ValueError when the text does not read as its tag."""
    text = n.value
    if n.tag == STR:
        return text
    if n.tag == "tag:yaml.org,2002:null":
        if text not in ("", "~", "null", "Null", "NULL"):
            raise ValueError("not a null")
        return None
    if n.tag == "tag:yaml.org,2002:bool":
        if text.lower() not in _BOOLS:
            raise ValueError("not true or false")
        return _BOOLS[text.lower()]
    if n.tag == "tag:yaml.org,2002:int":
        if not _INT_RE.match(text):
            raise ValueError("not a whole number")
        n = int(text)  # (pass 39) one past any double ended in math's OverflowError, a traceback
        if abs(n) > sys.float_info.max:
            raise ValueError("it is beyond the largest double (1.8e308)")
        return n
    if not _FLOAT_RE.match(text):  # an explicit !!float on something else
        raise ValueError("not a number")
    special = {".inf": math.inf, "+.inf": math.inf, "-.inf": -math.inf, ".nan": math.nan}
    if text.lower() in special:
        return special[text.lower()]
    x = float(text)  # a number the text names and the double lost is refused as the scene loader refuses it
    if not math.isfinite(x):
        raise ValueError("it is beyond the largest double (1.8e308)")
    if underflowed(text, x):
        raise ValueError("it underflows a double: give a magnitude of at least 2.2e-308, or 0 where the key "
                         "takes it")
    return x
