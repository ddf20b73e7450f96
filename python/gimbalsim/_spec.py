"""Spec files of the sweep and the tuner: YAML read with the position of
every key, and refusals that name the spec's key, line and column."""
import math
import os
import pathlib
import re
import stat

import yaml

from ._errors import SpecError  # defined beside the exit-code table (_errors.py)
from ._spec_yaml import MAP, SEQ, STANDARD_TAGS, SpecLoader, Unexpanded, scalar


class Node:
    """A YAML value with its position: ``value`` (plain Python: dict of Node,
    list of Node, or a scalar), ``line`` and ``column`` (1-based)."""

    __slots__ = ("value", "line", "column")

    def __init__(self, value, line, column):
        self.value, self.line, self.column = value, line, column

    def plain(self):
        """The value without positions."""
        if isinstance(self.value, dict):
            return {k: v.plain() for k, v in self.value.items()}
        if isinstance(self.value, list):
            return [v.plain() for v in self.value]
        return self.value


MAX_SPEC_BYTES = 1 << 20  # a spec is a page of text; anything larger is a mistake
MAX_SPEC_NODES = 100_000  # values after alias expansion
# What splits or reorders a displayed line: refused anywhere in a spec, comments too (pass 105), and what YAML does
# not take as text (YAML 1.2, 5.1); in a value, what escapes ("\e]0;x\a", "\u0000") make (pass 90, 94, 97).
_LAYOUT = "\x85\u061c\u200e\u200f\u2028-\u202e\u2066-\u2069"
_UNPRINTABLE = re.compile(f"[^\t\n\r\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]|[{_LAYOUT}]|\r(?!\n)")
_CONTROL = re.compile(f"[\x00-\x08\x0a-\x1f\x7f-\x9f{_LAYOUT}]")


def shown_text(text):
    """text as a refusal may print it: each _CONTROL character as <U+XXXX> (the C++ shownText's rule)."""
    return _CONTROL.sub(lambda m: f"<U+{ord(m.group()):04X}>", text)


class Spec:
    """A spec file: ``root`` (a Node), ``path``, and ``refuse(key, message,
    node)`` raising SpecError at the node's position. Its paths are read
    against ``folder`` (default: the spec's own; a replay reads a sweep's copy
    of its spec against the original's), then ``workdir`` (a replay: the
    sweep's working directory, where its relative paths fell back to), then
    the current directory."""

    def __init__(self, path, folder=None, workdir=None, text=None):
        if text is not None:  # a spec derived from the file's own text (gimbalsim.allocate): its lines are the file's
            data = text.encode("utf-8")
        self.path = pathlib.Path(path)
        self.folder = pathlib.Path(folder) if folder is not None else self.path.parent
        self.workdir = pathlib.Path(workdir) if workdir else None
        # Said as the C++ readers say it: what the path is, or the system's reason (not "not readable").
        try:
            st = self.path.stat()
            if stat.S_ISDIR(st.st_mode) or not stat.S_ISREG(st.st_mode):
                kind = "a folder" if stat.S_ISDIR(st.st_mode) else "not a regular file (a pipe or a device)"
                raise SpecError(f"{kind}; expected a spec file", file=str(path))
            if st.st_size > MAX_SPEC_BYTES:
                raise SpecError(f"larger than {MAX_SPEC_BYTES} bytes", file=str(path))
            if text is None:
                data = self.path.read_bytes()
        except OSError as e:
            raise SpecError(f"cannot open spec file: {e.strerror}", file=str(path)) from None
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as e:
            line = data[:e.start].count(b"\n") + 1
            column = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
            raise SpecError(f"not UTF-8 text (byte 0x{data[e.start]:02x} at offset {e.start})", file=str(path),
                            line=line, column=column)
        bad = _UNPRINTABLE.search(text)
        if bad:  # PyYAML's refusal named an offset in "<unicode string>", on two lines (the C++ loader's rule)
            line = text.count("\n", 0, bad.start()) + 1
            column = bad.start() - (text.rfind("\n", 0, bad.start()) + 1) + 1
            why = ("splits or reorders the line an editor shows (refused anywhere in a file, comments too)"
                   if re.fullmatch(f"[{_LAYOUT}]", bad.group()) else
                   "without a line feed after it (a lone carriage return) splits the line an editor shows for one "
                   "reader and not another (refused anywhere in a file, comments too)" if bad.group() == "\r" else
                   "(a control character) is not YAML text")
            raise SpecError(f"character U+{ord(bad.group()):04X} {why}",
                            file=str(path), line=line, column=column)
        self.source_text = text  # as read (a sweep keeps a copy)
        try:
            # The composer only: no object construction; values are built node by node below.
            tree = yaml.compose(text, Loader=SpecLoader)
        except yaml.YAMLError as e:
            mark = getattr(e, "problem_mark", None)
            raise SpecError(f"not valid YAML: {getattr(e, 'problem', e)}", file=str(path),
                            line=mark.line + 1 if mark else None, column=mark.column + 1 if mark else None)
        except Unexpanded as e:
            raise SpecError(str(e), file=str(path), line=e.mark.line + 1, column=e.mark.column + 1) from None
        except RecursionError:  # the composer recurses per level: 1000 brackets reach Python's limit first
            raise SpecError("nested too deeply (more than 16 levels)", file=str(path)) from None
        if tree is None or not isinstance(tree, yaml.MappingNode):
            raise SpecError("a spec must be a mapping of keys", file=str(path))
        self._nodes = 0
        self.root = self._convert(tree, "", 0)

    def _convert(self, n, key, depth):
        line, col = n.start_mark.line + 1, n.start_mark.column + 1
        self._nodes += 1
        if self._nodes > MAX_SPEC_NODES:  # aliases can multiply a small text (nested anchors)
            raise SpecError(f"more than {MAX_SPEC_NODES} values", key=key, file=str(self.path), line=line, column=col)
        if depth > 16:
            raise SpecError("nested too deeply", key=key, file=str(self.path), line=line, column=col)
        if n.tag not in STANDARD_TAGS:
            raise SpecError(f"unsupported tag {n.tag} (a spec takes numbers, names, lists and mappings)",
                            key=key, file=str(self.path), line=line, column=col)
        if isinstance(n, yaml.MappingNode):
            if n.tag != MAP:
                raise SpecError(f"a mapping tagged {n.tag}", key=key, file=str(self.path), line=line, column=col)
            out = {}
            for k, v in n.value:
                if not isinstance(k, yaml.ScalarNode):
                    raise SpecError("a mapping key must be a plain name", key=key, file=str(self.path),
                                    line=k.start_mark.line + 1, column=k.start_mark.column + 1)
                name = k.value
                self._no_control(name, key, k)
                if name in out:
                    raise SpecError("given twice", key=f"{key}.{name}" if key else name, file=str(self.path),
                                    line=k.start_mark.line + 1, column=k.start_mark.column + 1)
                child = self._convert(v, f"{key}.{name}" if key else name, depth + 1)
                child_line, child_col = k.start_mark.line + 1, k.start_mark.column + 1
                out[name] = Node(child.value, child_line, child_col)
            return Node(out, line, col)
        if isinstance(n, yaml.SequenceNode):
            if n.tag != SEQ:
                raise SpecError(f"a list tagged {n.tag}", key=key, file=str(self.path), line=line, column=col)
            return Node([self._convert(v, key, depth + 1) for v in n.value], line, col)
        self._no_control(n.value, key, n)
        try:
            return Node(scalar(n), line, col)
        except (ValueError, yaml.YAMLError) as e:
            # a long text is cut, visibly: '1000...' is not the 1e39 its first 40 digits read as (pass 42)
            shown = n.value if len(n.value) <= 40 else f"{n.value[:40]}... ({len(n.value)} characters)"
            raise SpecError(f"{n.tag.rsplit(':', 1)[-1]} '{shown}' does not read: {e}", key=key,
                            file=str(self.path), line=line, column=col)

    def _no_control(self, text, key, n):
        if bad := _CONTROL.search(text):
            at = Node(None, n.start_mark.line + 1, n.start_mark.column + 1)
            self.refuse(key, f"character U+{ord(bad.group()):04X} (a control character, from an escape) at "
                        f"position {bad.start()}: no text a spec holds", at)

    def refuse(self, key, message, node=None):
        raise SpecError(message, key=key, file=str(self.path), line=node.line if node else None,
                        column=node.column if node else None)

    def get(self, name, default=None):
        return self.root.value.get(name, default)

    def check_keys(self, allowed):
        for name, node in self.root.value.items():
            if name not in allowed:
                self.refuse(name, f"unknown key (expected one of {', '.join(sorted(allowed))})", node)

    def path_of(self, name, node):
        """A path given in the spec: against the spec file's folder (then a replay's workdir), then the
        current directory."""
        if not isinstance(node.value, str):
            self.refuse(name, "expected a file path", node)
        if not node.value.strip():  # '' named the spec's own folder: "is a folder" (pass 87)
            self.refuse(name, f"an empty path {node.value!r}: name a file", node)
        p = pathlib.Path(node.value)
        workdir = [self.workdir / p] if self.workdir is not None else []
        for candidate in ([p] if p.is_absolute() else [self.folder / p, *workdir, pathlib.Path.cwd() / p]):
            try:
                if candidate.is_file():
                    return candidate.resolve()
                if candidate.exists():  # a folder, a pipe or a device: there, but nothing a run can read
                    kind = "a folder" if candidate.is_dir() else "not a regular file (a pipe or a device)"
                    self.refuse(name, f"{node.value[:80]} is {kind}; expected a file", node)
            except OSError as e:  # a name too long, a loop of links: not a path the spec can mean
                self.refuse(name, f"not a usable file path ({e.strerror}): {node.value[:80]}", node)
        # a replay reads a sweep's copy against the original's folder: say where it looked
        beside = "beside the spec" if self.folder == self.path.parent else \
            f"in {self.folder}, the sweep's spec's folder"
        sweep_cwd = f", then in {self.workdir}, the sweep's working directory" if self.workdir is not None else ""
        self.refuse(name, f"no such file: {node.value} (looked {beside}{sweep_cwd}, then in the current directory)",
                    node)

    def integer(self, name, node, lo, hi):
        v = node.value
        if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
            self.refuse(name, f"expected a whole number in [{lo}, {hi}], got {v!r}", node)
        return v

    def number(self, name, node, lo=float("-inf"), hi=float("inf"), above=False):
        """A finite number in [lo, hi] ((lo, hi] with above: lo itself refused)."""
        v = node.value  # never Inf or NaN: a requirement of .inf gave a verdict "against inf rad"
        low_ok = lambda x: x > lo if above else x >= lo  # noqa: E731
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or \
                not (low_ok(v) and v <= hi):
            opening = "(" if above else "["
            rng = (f"a number in {opening}{lo}, {hi}]" if math.isfinite(lo) and math.isfinite(hi)
                   else f"a finite number {'>' if above else '>='} {lo}" if math.isfinite(lo) else "a finite number")
            self.refuse(name, f"expected {rng}, got {v!r}", node)
        return float(v)

    def mapping(self, name, node):
        if not isinstance(node.value, dict):
            self.refuse(name, "expected a mapping", node)
        return node.value

    def known_mapping(self, name, known, what, aliases=None):
        """The top-level mapping `name` ({} when absent) whose keys must all be
        in `known`; an unknown one is refused at its line as "not a key of
        the <what>", and so is a second spelling of one key (aliases: old
        name -> key; friction1.mu is joint1.friction.mu): only one would act."""
        node = self.get(name)
        body = self.mapping(name, node) if node is not None else {}
        seen = {}
        for key, n in body.items():
            if key not in known:
                self.refuse(f"{name}.{key}", f"not a key of the {what}", n)
            canonical = (aliases or {}).get(key, key)
            if canonical in seen:
                self.refuse(f"{name}.{key}", f"the same key as {name}.{seen[canonical]}: give it once", n)
            seen[canonical] = key
        return body

    def text(self, name, node):
        if not isinstance(node.value, str):
            self.refuse(name, f"expected a name, got {_shown(node.value)}", node)
        return node.value

    def value(self, name, node):
        """A key's value as `--set` takes it: a number, a name, true/false, or a
        vector (a list of numbers); None, mappings and nested lists are refused."""
        v = node.value
        if isinstance(v, list) and v and all(_is_number(e.value) for e in v):
            return node.plain()
        if v is None or isinstance(v, (dict, list)):
            self.refuse(name, f"expected a number, a name or a list of numbers, got {_shown(node.plain())}", node)
        return v


def check_out_dir(out, spec_path):
    """--out must be a folder (existing or not) and not the spec itself: refused
    (SpecError, exit 2) before anything runs. The folder is the sweep's or the
    study's own output: it is made if missing, but the folder it goes in must
    exist, as for every output of the project (docs/usage.md "Output files")."""
    out = pathlib.Path(out)
    if out.is_symlink():  # every output is written into the folder named, never through a link (docs/usage.md)
        raise SpecError(f"--out {out}: is a link (to {os.readlink(out)}): name the folder itself")
    if out.exists() and not out.is_dir():
        same = pathlib.Path(spec_path).exists() and out.resolve() == pathlib.Path(spec_path).resolve()
        raise SpecError(f"--out {out}: " + ("is the spec file itself" if same else "exists and is not a folder"))
    for parent in out.absolute().parents:  # the folder is made later: no file may stand in its way
        if parent.exists():
            if not parent.is_dir():
                raise SpecError(f"--out {out}: {parent} is a file, not a folder")
            break
    parent = out.absolute().parent
    if not out.exists() and not parent.is_dir():
        raise SpecError(f"--out {out}: the folder it goes in, {parent}, does not exist (create it first)")
    # e.g. an allocation's values/<i>/: its own sweep's, not the user's
    refuse_inside_tool_folder("--out", out)


def refuse_inside_tool_folder(flag, path):
    """path (given as flag) refused (SpecError, exit 2) when one of its folders
    (its folder and their ancestors) is a tool's output folder (_INSIDE):
    a sweep's, tune's or allocate's --out, or a replay's --out and --plot."""
    # where path really goes, '..' and links resolved: walked as named, DIR/../x was refused as inside DIR
    for folder in pathlib.Path(path).resolve().parents:
        held = next((what for what, names in _INSIDE if all((folder / n).exists() for n in names)), None)
        if held is not None:
            raise SpecError(f"{flag} {path}: lies inside {held} ({folder}), whose files and folders are its own; "
                            f"give {flag} outside it")


# A folder that is a tool's output (the names only that tool writes): no other run's --out goes inside it.
_INSIDE = (("an allocation", ("allocation_spec.json",)), ("a tuning study", ("study.db",)),
           ("a sweep", ("spec.json", "inputs.json")))


def check_outputs_not_inputs(outputs, inputs):
    """An output that is also an input (the spec or a file it reads, by its
    name or a hard link), a folder of outputs holding one, a file where an
    output's folder goes, or a link or special file under an output's name is
    refused (SpecError, exit 2) before anything runs: found at the end, the
    study's work would be lost."""
    ins = [pathlib.Path(p).resolve() for p in inputs if p is not None]
    for o in outputs:
        o = pathlib.Path(o)
        # A link (or a pipe, a device) under an output's name: refused now, not after every sample ran (exit 4).
        if o.is_symlink() or (o.exists() and not o.is_file() and not o.is_dir()):
            raise SpecError(f"{o}: " + ("a symbolic link" if o.is_symlink() else "not a regular file") +
                            " where this run writes its output; an output is never written through one: remove it, "
                            "or use another --out")
        if o.parent.exists() and not o.parent.is_dir():  # a file where the outputs' folder (plots/) goes
            raise SpecError(f"{o.parent}: not a folder where this run writes {o.name}: remove it, or use another --out")
        given, o = o, o.resolve()
        for i in ins:
            if i == o or o in i.parents:
                raise SpecError(f"{i}: an input of this run and {'its output' if i == o else 'inside its output folder'} "
                                f"{o}; move it out of --out, or use another --out")
            if _same_file(i, o):  # a hard link: the input under the output's name, else refused after the run
                raise SpecError(f"{given}: the same file as the input {i} (a hard link), where this run writes its "
                                f"output; move it out of --out, or use another --out")


def _same_file(a, b):
    """a and b are one file (device and inode): False when either is missing."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return False


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _shown(v):
    if v is None:
        return "null (nothing)"
    if isinstance(v, dict):
        return "a mapping"
    if isinstance(v, list):  # a YAML list holds Nodes: shown by their values, never as Python objects
        return "a list" if not v else "[" + ", ".join(_shown(getattr(e, "value", e)) for e in v)[:60] + "]"
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."
