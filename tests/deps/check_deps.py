#!/usr/bin/env python3
"""The dependency rules of gimbalsim (issue 19), checked on the target graph
and on the include lines. Exits 1 on a forbidden edge, one line each:

    rule N: <from> -> <to> (<file>:<line> includes "<header>")
    rule N: <from> -> <to> (target A links B [via X, Y])

and 0 with a one-line summary otherwise (2: the inputs could not be read).

The rules ("under F": the folder F or any folder below it):
  1. dynamics -> LCM: no target under dynamics/ links LCM (PkgConfig::LCM,
     liblcm) or a target under lcmtypes/ (gimbalsim_lcmtypes, the contract,
     lcm_wire), directly or transitively; no file under dynamics/ includes
     <lcm/...>, a generated LCM type "gimbalsim/<name>_t.hpp" or a header
     under lcmtypes/. The dynamics only the dynamics: gimbalsim_dynamics (the
     folder dynamics/ itself, not its sub-libraries) links no other project
     target and its files include no project header outside it.
  2. plant -> controller: nothing under firmware_sim/ links a target or
     includes a header under controllers/.
  3. controller -> plant: nothing under controllers/ links a target or
     includes a header under firmware_sim/.
  4. anything -> tools: nothing outside tools/ and tests/ links a target or
     includes a header under tools/.
  5. lcm_wire -> above the base: nothing under lcmtypes/lcm_wire/ links a
     target or includes a header outside itself and base/ (no dynamics, no
     LCM library: the bench's own receiver and log files).
  6. contract -> plant or controller: nothing under lcmtypes/contract/ links a
     target or includes a header under firmware_sim/ or controllers/.
  7. base -> above it: nothing under base/ (input, io, program) links a target
     or includes a header outside base/, LCM included.
tests/ may link and include anything; python/ (the extension wires plant and
controller) may link both.

The target graph: with --build-dir, the sources are configured once more in a
scratch directory with that build's cache settings (its CMakeCache.txt as a
-C script, its generator), asking CMake for --graphviz (every link edge:
PUBLIC, PRIVATE and INTERFACE, to project, INTERFACE, imported and plain
libraries) and for the file API's codemodel (the folder of each target that
has sources). The build directory itself is only read: a configure in place
would rewrite its generated files. With --dot, a graphviz file is read as is
(tests feed synthetic graphs that way). INTERFACE libraries, absent from the
codemodel, and every target with --dot get their folder from the
add_library/add_executable/pybind11_add_module lines of the CMakeLists.txt
files; a graph node that is no project target is an external library.

The include lines: every C/C++ file of the source tree outside tests/, build
directories and hidden folders; "x" is looked up beside the including file,
then as a path suffix among the tree's files; an unresolved
gimbalsim/<folder>/... goes to the folder holding include/gimbalsim/<folder>.
A header belongs to the folder of the nearest CMakeLists.txt above it.

Usage: check_deps.py [--source DIR] (--build-dir DIR | --dot FILE)
"""

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from collections import deque

CXX_EXTENSIONS = ('.c', '.cc', '.cpp', '.cxx', '.h', '.hh', '.hpp', '.hxx', '.ipp', '.inl', '.tpp')
LCM = 'LCM'  # the LCM library, as the "to" of a rule 1 line
GENERATED_LCM_TYPE = re.compile(r'^gimbalsim/[A-Za-z0-9_]+_t\.hpp$')
EXTERNAL_LCM = re.compile(r'^(PkgConfig::LCM|lcm::[A-Za-z0-9_-]+|lcm|-llcm|(.*/)?liblcm\.(so[.0-9]*|a))$')
INCLUDE = re.compile(r'^[ \t]*#[ \t]*include[ \t]*([<"])([^>"\n]+)[>"]', re.M)
DECLARATION = re.compile(r'\b(?:add_library|add_executable|pybind11_add_module)\s*\(\s*([A-Za-z0-9_.+:-]+)([^)]*)\)')


# --- folders -----------------------------------------------------------------

def under(path, folder):
    """True if the relative path (or folder) `path` is `folder` or below it."""
    return path == folder or path.startswith(folder + '/')


def skipped_dir(rel, name, abspath):
    return (name.startswith('.') or name in ('__pycache__', 'dist') or name.endswith('.egg-info')
            or ('/' not in rel and name.startswith('build'))
            or os.path.exists(os.path.join(abspath, 'CMakeCache.txt')))


def walk_tree(root):
    """Relative paths of the tree's files, build directories and hidden folders left out."""
    files = []
    for dirpath, dirnames, filenames in os.walk(root):
        reldir = os.path.relpath(dirpath, root).replace(os.sep, '/')
        reldir = '' if reldir == '.' else reldir
        dirnames[:] = sorted(d for d in dirnames
                             if not skipped_dir(reldir + '/' + d if reldir else d, d, os.path.join(dirpath, d)))
        for f in sorted(filenames):
            files.append(reldir + '/' + f if reldir else f)
    return files


class Tree:
    def __init__(self, root):
        self.root = os.path.abspath(root)
        self.files = walk_tree(self.root)
        self.file_set = set(self.files)
        self.cmake_dirs = {os.path.dirname(f) for f in self.files if os.path.basename(f) == 'CMakeLists.txt'}
        self.by_name = {}
        for f in self.files:
            self.by_name.setdefault(os.path.basename(f), []).append(f)
        # gimbalsim/<name> -> the folders holding include/gimbalsim/<name>
        self.include_homes = {}
        for d in {os.path.dirname(f) for f in self.files}:
            m = re.match(r'^(?:(.*)/)?include/gimbalsim/([^/]+)$', d)
            if m:
                self.include_homes.setdefault(m.group(2), set()).add(self.lib_folder(d + '/x'))

    def lib_folder(self, path):
        """The folder of the nearest CMakeLists.txt above `path` ('' = the top)."""
        d = os.path.dirname(path)
        while d and d not in self.cmake_dirs:
            d = os.path.dirname(d)
        return d

    def declared_targets(self):
        """target -> folder, from the CMakeLists.txt files (aliases and imported targets left out)."""
        out = {}
        for d in sorted(self.cmake_dirs):
            text = read_text(os.path.join(self.root, d, 'CMakeLists.txt'))
            text = re.sub(r'#[^\n]*', '', text)
            for name, rest in DECLARATION.findall(text):
                if {'ALIAS', 'IMPORTED'} & set(rest.split()):
                    continue
                out.setdefault(name, d)
        return out


def read_text(path):
    with open(path, encoding='utf-8', errors='replace') as f:
        return f.read()


# --- the target graph ----------------------------------------------------------

class Graph:
    def __init__(self):
        self.nodes = set()  # target and library names
        self.edges = {}     # name -> set of names it links

    def add_edge(self, a, b):
        self.nodes.update((a, b))
        if a != b:
            self.edges.setdefault(a, set()).add(b)


def parse_dot(text):
    """CMake's --graphviz output: node ids with labels, edges between ids."""
    graph = Graph()
    labels = {}
    node = re.compile(r'^\s*"([^"]+)"\s*\[\s*label\s*=\s*"((?:[^"\\]|\\.)*)"', re.M)
    edge = re.compile(r'^\s*"([^"]+)"\s*->\s*"([^"]+)"', re.M)
    for nid, label in node.findall(text):
        labels[nid] = re.sub(r'\\(.)', r'\1', label)
        graph.nodes.add(labels[nid])
    for a, b in edge.findall(text):
        if a not in labels or b not in labels:
            raise ValueError(f'edge {a} -> {b} between undeclared nodes')
        graph.add_edge(labels[a], labels[b])
    return graph


GRAPHVIZ_OPTIONS = """\
set(GRAPHVIZ_EXECUTABLES TRUE)
set(GRAPHVIZ_STATIC_LIBS TRUE)
set(GRAPHVIZ_SHARED_LIBS TRUE)
set(GRAPHVIZ_MODULE_LIBS TRUE)
set(GRAPHVIZ_INTERFACE_LIBS TRUE)
set(GRAPHVIZ_OBJECT_LIBS TRUE)
set(GRAPHVIZ_UNKNOWN_LIBS TRUE)
set(GRAPHVIZ_EXTERNAL_LIBS TRUE)
set(GRAPHVIZ_CUSTOM_TARGETS FALSE)
set(GRAPHVIZ_IGNORE_TARGETS "")
set(GRAPHVIZ_GENERATE_PER_TARGET FALSE)
set(GRAPHVIZ_GENERATE_DEPENDERS FALSE)
"""


def cache_as_script(cache_text):
    """The user-visible entries of a CMakeCache.txt as a -C script, plus its generator."""
    lines, generator = [], None
    for line in cache_text.splitlines():
        m = re.match(r'^([A-Za-z0-9_.+-]+):([A-Z]+)=(.*)$', line)
        if not m:
            continue
        name, kind, value = m.groups()
        if name == 'CMAKE_GENERATOR' and kind == 'INTERNAL':
            generator = value
        if kind not in ('BOOL', 'STRING', 'PATH', 'FILEPATH', 'UNINITIALIZED') or name == 'CMAKE_MAKE_PROGRAM':
            continue
        value = value.replace('\\', '\\\\').replace('"', '\\"').replace('$', '\\$')
        lines.append(f'set({name} "{value}" CACHE {kind} "")')
    return '\n'.join(lines) + '\n', generator


def graph_from_build(source, build_dir):
    """(graph, target -> folder) of the sources configured with build_dir's settings."""
    cache = os.path.join(build_dir, 'CMakeCache.txt')
    if not os.path.isfile(cache):
        raise ValueError(f'{build_dir}: no CMakeCache.txt (configure it first)')
    script, generator = cache_as_script(read_text(cache))
    cmake = shutil.which('cmake')
    m = re.search(r'^CMAKE_COMMAND:INTERNAL=(.*)$', read_text(cache), re.M)
    if m and os.path.isfile(m.group(1)):
        cmake = m.group(1)  # the build's own cmake
    with tempfile.TemporaryDirectory(prefix='gimbalsim_deps_') as tmp:
        scratch = os.path.join(tmp, 'build')
        os.makedirs(os.path.join(scratch, '.cmake/api/v1/query'))
        open(os.path.join(scratch, '.cmake/api/v1/query/codemodel-v2'), 'w').close()
        with open(os.path.join(scratch, 'CMakeGraphVizOptions.cmake'), 'w') as f:
            f.write(GRAPHVIZ_OPTIONS)
        with open(os.path.join(tmp, 'cache.cmake'), 'w') as f:
            f.write(script)
        dot = os.path.join(tmp, 'targets.dot')
        cmd = [cmake, '-S', source, '-B', scratch, '-C', os.path.join(tmp, 'cache.cmake'), f'--graphviz={dot}']
        if generator:
            cmd += ['-G', generator]
        run = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        if run.returncode != 0 or not os.path.isfile(dot):
            raise ValueError('cmake --graphviz failed:\n' + run.stdout[-4000:])
        graph = parse_dot(read_text(dot))
        folders = codemodel_folders(scratch)
    return graph, folders


def codemodel_folders(build_dir):
    """target -> source folder (relative) from a file API codemodel reply."""
    reply = os.path.join(build_dir, '.cmake/api/v1/reply')
    index = sorted(f for f in os.listdir(reply) if f.startswith('index-'))[-1]
    with open(os.path.join(reply, index)) as f:
        objects = json.load(f)['objects']
    model = next(o for o in objects if o['kind'] == 'codemodel')
    with open(os.path.join(reply, model['jsonFile'])) as f:
        codemodel = json.load(f)
    out = {}
    for config in codemodel['configurations'][:1]:
        for t in config['targets']:
            with open(os.path.join(reply, t['jsonFile'])) as f:
                target = json.load(f)
            src = target['paths']['source']
            out[target['name']] = '' if src == '.' else src.replace(os.sep, '/')
    return out


# --- rules ---------------------------------------------------------------------

def is_lcm(folder):
    return folder == LCM or under(folder, 'lcmtypes')


# Each rule: (number, applies to (from folder), forbidden (to folder)). A folder
# is relative to the source root; LCM stands for the LCM library.
RULES = [
    (1, lambda f: under(f, 'dynamics'), is_lcm),
    (1, lambda f: f == 'dynamics', lambda t: t != 'dynamics' and t != LCM),
    (2, lambda f: under(f, 'firmware_sim'), lambda t: under(t, 'controllers')),
    (3, lambda f: under(f, 'controllers'), lambda t: under(t, 'firmware_sim')),
    (4, lambda f: not (under(f, 'tools') or under(f, 'tests')), lambda t: under(t, 'tools')),
    (5, lambda f: under(f, 'lcmtypes/lcm_wire'), lambda t: not (under(t, 'lcmtypes/lcm_wire') or under(t, 'base'))),
    (6, lambda f: under(f, 'lcmtypes/contract'), lambda t: under(t, 'firmware_sim') or under(t, 'controllers')),
    (7, lambda f: under(f, 'base'), lambda t: not under(t, 'base')),
]


def shown(folder):
    return folder if folder else '(top)'


def check_graph(graph, folders):
    """Violations of the target graph: the nearest target in a rule's scope that reaches a forbidden one."""
    def folder_of(name):
        if name in folders:
            return folders[name]
        return LCM if EXTERNAL_LCM.match(name) else None  # other externals: no rule

    out = []
    for number, applies, forbidden in RULES:
        scope = {n for n in graph.nodes if folders.get(n) is not None and applies(folders[n])}
        for start in sorted(scope):
            parent = {start: None}
            queue = deque([start])
            while queue:
                node = queue.popleft()
                for nxt in sorted(graph.edges.get(node, ())):
                    if nxt in parent:
                        continue
                    parent[nxt] = node
                    f = folder_of(nxt)
                    if f is not None and forbidden(f) and nxt != start:
                        via = []
                        p = node
                        while p != start:
                            via.append(p)
                            p = parent[p]
                        how = f'target {start} links {nxt}' + (f' via {", ".join(reversed(via))}' if via else '')
                        out.append(f'rule {number}: {shown(folders[start])} -> {shown(f)} ({how})')
                    elif nxt not in scope:  # a target in scope answers for its own links
                        queue.append(nxt)
    return out


def strip_comments(text):
    """C/C++ text with comments blanked (newlines kept) and string literals left alone."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if c == '/' and text.startswith('//', i):
            j = text.find('\n', i)
            j = n if j < 0 else j
            i = j
        elif c == '/' and text.startswith('/*', i):
            j = text.find('*/', i + 2)
            j = n if j < 0 else j + 2
            out.append('\n' * text.count('\n', i, j))
            i = j
        elif c in '"\'':
            j = i + 1
            while j < n and text[j] != c and text[j] != '\n':
                j += 2 if text[j] == '\\' else 1
            out.append(text[i:j + 1])
            i = j + 1
        else:
            out.append(c)
            i += 1
    return ''.join(out)


def include_lines(tree, path):
    text = strip_comments(read_text(os.path.join(tree.root, path)))
    for m in INCLUDE.finditer(text):
        yield text.count('\n', 0, m.start()) + 1, m.group(1), m.group(2).strip()


def resolve(tree, path, bracket, header):
    """The folders an include of `header` from `path` resolves to (empty: outside the project)."""
    if bracket == '<' and header.startswith('lcm/'):
        return [LCM]
    if bracket == '"':
        beside = os.path.normpath(os.path.join(os.path.dirname(path), header)).replace(os.sep, '/')
        if beside in tree.file_set:
            return [tree.lib_folder(beside)]
    header = os.path.normpath(header).replace(os.sep, '/')
    candidates = [f for f in tree.by_name.get(os.path.basename(header), ())
                  if f == header or f.endswith('/' + header)]
    if candidates:
        own = [f for f in candidates if tree.lib_folder(f) == tree.lib_folder(path)]
        return sorted({tree.lib_folder(f) for f in (own or candidates)})
    if GENERATED_LCM_TYPE.match(header):
        return ['lcmtypes']  # lcm-gen's output, in the build directory
    m = re.match(r'^gimbalsim/([^/]+)/', header)
    if m:
        return sorted(tree.include_homes.get(m.group(1), ()))
    return []


def check_includes(tree):
    """(violations, number of include lines read)."""
    out, count = [], 0
    for path in tree.files:
        if not path.endswith(CXX_EXTENSIONS) or under(path, 'tests'):
            continue
        source = tree.lib_folder(path)
        for line, bracket, header in include_lines(tree, path):
            count += 1
            seen = set()
            for to in resolve(tree, path, bracket, header):
                for number, applies, forbidden in RULES:
                    if (number, to) in seen or not applies(source) or not forbidden(to):
                        continue
                    seen.add((number, to))
                    b = '<>' if bracket == '<' else '""'
                    out.append(f'rule {number}: {shown(source)} -> {shown(to)} '
                               f'({path}:{line} includes {b[0]}{header}{b[1]})')
    return out, count


def main(argv=None):
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('--source', default=os.path.normpath(os.path.join(here, '..', '..')),
                    help='the source tree (default: this checkout)')
    graph_arg = ap.add_mutually_exclusive_group(required=True)
    graph_arg.add_argument('--build-dir', help='a configured build directory: its settings give the target graph')
    graph_arg.add_argument('--dot', help='a target graph written by cmake --graphviz')
    ap.add_argument('--print-targets', action='store_true',
                    help='print each project target with its folder and links, then check')
    args = ap.parse_args(argv)

    tree = Tree(args.source)
    try:
        folders = tree.declared_targets()
        if args.dot:
            graph = parse_dot(read_text(args.dot))
        else:
            graph, codemodel = graph_from_build(tree.root, os.path.abspath(args.build_dir))
            folders.update(codemodel)  # the file API's folder wins where it knows the target
        folders = {n: f for n, f in folders.items() if n in graph.nodes}
        if not folders:
            raise ValueError('no project target in the graph: nothing would be checked')
    except (OSError, ValueError) as e:
        print(f'check_deps: {e}', file=sys.stderr)
        return 2

    if args.print_targets:
        for n in sorted(folders):
            print(f'target {n} [{shown(folders[n])}] -> {" ".join(sorted(graph.edges.get(n, ())))}')
    violations = check_graph(graph, folders)
    include_violations, include_count = check_includes(tree)
    violations = list(dict.fromkeys(violations + include_violations))  # one line per edge and place
    for v in violations:
        print(v)
    if violations:
        print(f'{len(folders)} targets, {include_count} include lines, {len(violations)} forbidden edges')
        return 1
    print(f'{len(folders)} targets, {include_count} include lines, no forbidden edge')
    return 0


if __name__ == '__main__':
    sys.exit(main())
