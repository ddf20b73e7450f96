"""Spec files of the sweep and the tuner: YAML read with the position of
every key, and refusals that name the spec's key, line and column."""
import pathlib

import yaml


class SpecError(ValueError):
    """A spec was refused. ``key`` is the spec's key (dotted, e.g.
    ``parameters.friction.mu``), ``file``, ``line`` and ``column`` (1-based)
    where it is."""

    def __init__(self, message, key=None, file=None, line=None, column=None):
        where = f"{file}:{line}:{column}: " if file and line else (f"{file}: " if file else "")
        what = f"key '{key}': " if key else ""
        super().__init__(f"{where}{what}{message}")
        self.key, self.file, self.line, self.column = key, file, line, column


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


class Spec:
    """A spec file: ``root`` (a Node), ``path``, and ``refuse(key, message,
    node)`` raising SpecError at the node's position."""

    def __init__(self, path):
        self.path = pathlib.Path(path)
        if not self.path.is_file():
            raise SpecError("not a readable file", file=str(path))
        if self.path.stat().st_size > MAX_SPEC_BYTES:
            raise SpecError(f"larger than {MAX_SPEC_BYTES} bytes", file=str(path))
        text = self.path.read_text()
        try:
            # SafeLoader's composer: no object construction; aliases are refused below.
            tree = yaml.compose(text, Loader=yaml.SafeLoader)
        except yaml.YAMLError as e:
            mark = getattr(e, "problem_mark", None)
            raise SpecError(f"not valid YAML: {getattr(e, 'problem', e)}", file=str(path),
                            line=mark.line + 1 if mark else None, column=mark.column + 1 if mark else None)
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
        if isinstance(n, yaml.MappingNode):
            out = {}
            for k, v in n.value:
                if not isinstance(k, yaml.ScalarNode):
                    raise SpecError("a mapping key must be a plain name", key=key, file=str(self.path),
                                    line=k.start_mark.line + 1, column=k.start_mark.column + 1)
                name = k.value
                if name in out:
                    raise SpecError("given twice", key=f"{key}.{name}" if key else name, file=str(self.path),
                                    line=k.start_mark.line + 1, column=k.start_mark.column + 1)
                child = self._convert(v, f"{key}.{name}" if key else name, depth + 1)
                child_line, child_col = k.start_mark.line + 1, k.start_mark.column + 1
                out[name] = Node(child.value, child_line, child_col)
            return Node(out, line, col)
        if isinstance(n, yaml.SequenceNode):
            return Node([self._convert(v, key, depth + 1) for v in n.value], line, col)
        return Node(_scalar(n), line, col)

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
        """A path given in the spec: against the spec file's folder, then the current directory."""
        if not isinstance(node.value, str):
            self.refuse(name, "expected a file path", node)
        p = pathlib.Path(node.value)
        for candidate in ([p] if p.is_absolute() else [self.path.parent / p, pathlib.Path.cwd() / p]):
            if candidate.is_file():
                return candidate.resolve()
        self.refuse(name, f"no such file: {node.value} (looked beside the spec, then in the current directory)", node)

    def integer(self, name, node, lo, hi):
        v = node.value
        if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
            self.refuse(name, f"expected a whole number in [{lo}, {hi}], got {v!r}", node)
        return v

    def number(self, name, node, lo=float("-inf"), hi=float("inf")):
        v = node.value
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not (lo <= v <= hi):
            self.refuse(name, f"expected a number in [{lo}, {hi}], got {v!r}", node)
        return float(v)

    def mapping(self, name, node):
        if not isinstance(node.value, dict):
            self.refuse(name, "expected a mapping", node)
        return node.value


def check_out_dir(out, spec_path):
    """--out must be a folder (existing or not) and not the spec itself: refused
    (SpecError, exit 2) before anything runs."""
    import pathlib
    out = pathlib.Path(out)
    if out.exists() and not out.is_dir():
        same = pathlib.Path(spec_path).exists() and out.resolve() == pathlib.Path(spec_path).resolve()
        raise SpecError(f"--out {out}: " + ("is the spec file itself" if same else "exists and is not a folder"))


def _scalar(n):
    """A scalar by YAML's resolver (numbers, booleans, null, strings)."""
    loader = yaml.SafeLoader("")
    try:
        return loader.construct_object(n, deep=True)
    finally:
        loader.dispose()
