"""The dependency rules (check_deps.py, issue 19).

test_tree_has_no_forbidden_edge: the real tree and this build's target graph
(ctest deps_rules). The others (ctest deps_checker) show the checker reads the
real graph, and reports one forbidden include and one forbidden link edge per
rule, with its number: in a synthetic mini-tree with a synthetic graph, in a
copy of the real tree, and in a copy with its CMakeLists.txt given a
forbidden link.

The real tree: GIMBALSIM_SOURCE_DIR (default: this checkout); the build:
GIMBALSIM_BUILD_DIR (default: <source>/build).
"""

import os
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
CHECKER = os.path.join(HERE, 'check_deps.py')
SOURCE = os.environ.get('GIMBALSIM_SOURCE_DIR') or os.path.normpath(os.path.join(HERE, '..', '..'))


def build_dir():
    d = os.environ.get('GIMBALSIM_BUILD_DIR') or os.path.join(SOURCE, 'build')
    if not os.path.isfile(os.path.join(d, 'CMakeCache.txt')):
        pytest.skip(f'no configured build directory at {d} (set GIMBALSIM_BUILD_DIR)')
    return d


def check(*args):
    """(exit status, the violation lines, the whole output) of the checker."""
    run = subprocess.run([sys.executable, CHECKER, *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, timeout=600)
    return run.returncode, [l for l in run.stdout.splitlines() if l.startswith('rule ')], run.stdout


# --- the real tree ---------------------------------------------------------------

def test_tree_has_no_forbidden_edge():
    status, violations, out = check('--source', SOURCE, '--build-dir', build_dir())
    assert status == 0 and not violations, out
    assert 'no forbidden edge' in out.splitlines()[-1], out


def test_real_graph_is_read():
    """The folders and the links the rules need come through (so that no rule passes by reading nothing)."""
    status, _, out = check('--source', SOURCE, '--build-dir', build_dir(), '--print-targets')
    assert status in (0, 1), out
    targets = {}
    for line in out.splitlines():
        if line.startswith('target '):
            name, rest = line[len('target '):].split(' ', 1)
            folder, links = rest.split(' -> ')
            targets[name] = (folder.strip('[]'), set(links.split()))
    expected = {'gimbalsim_dynamics': 'dynamics', 'gimbalsim_input': 'base/input',
                'gimbalsim_scene': 'dynamics/scene', 'gimbalsim_lcmtypes': 'lcmtypes',
                'gimbalsim_contract': 'lcmtypes/contract', 'gimbalsim_lcm_wire': 'lcmtypes/lcm_wire',
                'gimbalsim_firmware_sim': 'firmware_sim', 'firmware_sim': 'firmware_sim',
                'gimbalsim_controllers': 'controllers', 'pointing_controller': 'controllers',
                'gimbalsim': 'tools', '_gimbalsim': 'python'}
    for name, folder in expected.items():
        assert name in targets and targets[name][0] == folder, (name, targets.get(name), out)
    # an INTERFACE library's links and an imported target: the way to LCM
    assert {'PkgConfig::LCM', 'gimbalsim_contract'} <= targets['gimbalsim_lcmtypes'][1], out
    assert 'gimbalsim_lcmtypes' in targets['firmware_sim'][1], out
    summary = out.splitlines()[-1]
    assert int(summary.split()[0]) >= 20 and int(summary.split()[2]) >= 200, summary


# --- a synthetic mini-tree and graph ------------------------------------------------

def library(folder, target, name, header_text='#pragma once\n', source_text=None):
    """A library folder: CMakeLists.txt, include/gimbalsim/<name>/<name>.hpp, src/<name>.cpp."""
    return {
        f'{folder}/CMakeLists.txt': f'add_library({target} src/{name}.cpp)  # sources\n',
        f'{folder}/include/gimbalsim/{name}/{name}.hpp': header_text,
        f'{folder}/src/{name}.cpp': source_text or f'#include "gimbalsim/{name}/{name}.hpp"\n',
    }


MINI_TREE = {
    'CMakeLists.txt': 'project(mini)\nadd_subdirectory(dynamics)\n',
    'dynamics/CMakeLists.txt': 'add_library(gimbalsim_dynamics src/model.cpp)\n',
    'dynamics/include/gimbalsim/dynamics/model.hpp': '#pragma once\n#include <Eigen/Core>\n',
    'dynamics/src/model.cpp': ('#include "gimbalsim/dynamics/model.hpp"\n#include <cmath>\n'
                               '// #include <lcm/lcm-cpp.hpp>\n'
                               '/* #include "gimbalsim/controllers/pid.hpp"\n   #include "gimbalsim/input/input.hpp" */\n'
                               'const char *s = "/* #include <lcm/lcm.h> */";\n'),
    **library('base/input', 'gimbalsim_input', 'input'),
    **library('base/io', 'gimbalsim_io', 'io'),
    **library('dynamics/scene', 'gimbalsim_scene', 'scene',
              '#pragma once\n#include "gimbalsim/dynamics/model.hpp"\n#include "gimbalsim/input/input.hpp"\n'),
    **library('dynamics/pointing', 'gimbalsim_pointing', 'pointing',
              '#pragma once\n#include "gimbalsim/dynamics/model.hpp"\n'),
    'lcmtypes/CMakeLists.txt': ('add_subdirectory(contract)\nadd_library(gimbalsim_lcmtypes INTERFACE)\n'
                                'target_link_libraries(gimbalsim_lcmtypes INTERFACE PkgConfig::LCM)\n'),
    'lcmtypes/gimbal_command_t.lcm': 'package gimbalsim;\nstruct gimbal_command_t { int64_t seq; }\n',
    'lcmtypes/contract/CMakeLists.txt': 'add_library(gimbalsim_contract INTERFACE)\n',
    'lcmtypes/contract/include/gimbalsim/contract/messages.hpp': '#pragma once\n#include <Eigen/Core>\n',
    **library('lcmtypes/lcm_wire', 'gimbalsim_lcm_wire', 'lcm_wire',
              '#pragma once\n#include "gimbalsim/io/io.hpp"\n'),
    'firmware_sim/CMakeLists.txt': ('add_library(gimbalsim_firmware_sim src/firmware.cpp)\n'
                                    'add_executable(firmware_sim programs/main.cpp)\n'),
    'firmware_sim/include/gimbalsim/firmware_sim/firmware.hpp': (
        '#pragma once\n#include "gimbalsim/scene/scene.hpp"\n#include "gimbalsim/contract/messages.hpp"\n'),
    'firmware_sim/src/firmware.cpp': '#include "gimbalsim/firmware_sim/firmware.hpp"\n',
    'firmware_sim/programs/app.hpp': '#pragma once\n#include "gimbalsim/firmware_sim/firmware.hpp"\n',
    'firmware_sim/programs/main.cpp': ('#include "app.hpp"\n#include <lcm/lcm-cpp.hpp>\n'
                                  '#include "gimbalsim/gimbal_command_t.hpp"\n#include "gimbalsim/lcm_wire/lcm_wire.hpp"\n'),
    'controllers/CMakeLists.txt': ('add_library(gimbalsim_controllers src/pid.cpp)\n'
                                   'add_executable(pointing_controller programs/main.cpp)\n'),
    'controllers/include/gimbalsim/controllers/pid.hpp': (
        '#pragma once\n#include "gimbalsim/scene/scene.hpp"\n#include "gimbalsim/contract/messages.hpp"\n'),
    'controllers/src/pid.cpp': '#include "gimbalsim/controllers/pid.hpp"\n',
    'controllers/programs/main.cpp': ('#include "gimbalsim/controllers/pid.hpp"\n#include <lcm/lcm-cpp.hpp>\n'
                                 '#include "gimbalsim/gimbal_command_t.hpp"\n'),
    'tools/CMakeLists.txt': 'add_executable(gimbalsim cli/main.cpp)\nadd_subdirectory(workprec)\n',
    'tools/cli/main.cpp': '#include "gimbalsim/scene/scene.hpp"\n#include "gimbalsim/controllers/pid.hpp"\n',
    'tools/workprec/CMakeLists.txt': 'add_library(gimbalsim_workprec_lib STATIC workprec.cpp)\n',
    'tools/workprec/workprec.hpp': '#pragma once\n#include "gimbalsim/scene/scene.hpp"\n',
    'tools/workprec/workprec.cpp': '#include "workprec.hpp"\n',
    'python/CMakeLists.txt': 'pybind11_add_module(_gimbalsim src/module.cpp)\n',
    'python/src/module.cpp': ('#include "gimbalsim/controllers/pid.hpp"\n'
                              '#include "gimbalsim/firmware_sim/firmware.hpp"\n'),
    'tests/CMakeLists.txt': 'add_executable(all_test all_test.cpp)\n',
    'tests/all_test.cpp': ('#include "workprec.hpp"\n#include <lcm/lcm-cpp.hpp>\n'
                           '#include "gimbalsim/controllers/pid.hpp"\n#include "gimbalsim/firmware_sim/firmware.hpp"\n'),
}

MINI_GRAPH = {
    'gimbalsim_dynamics': ['Eigen3::Eigen', 'Boost::headers'],
    'gimbalsim_input': ['Eigen3::Eigen', 'yaml-cpp'],
    'gimbalsim_io': [],
    'gimbalsim_scene': ['gimbalsim_dynamics', 'gimbalsim_input'],
    'gimbalsim_pointing': ['gimbalsim_dynamics', 'gimbalsim_input'],
    'gimbalsim_contract': ['Eigen3::Eigen'],
    'gimbalsim_lcmtypes': ['gimbalsim_contract', 'PkgConfig::LCM'],
    'gimbalsim_lcm_wire': ['gimbalsim_io'],
    'gimbalsim_firmware_sim': ['gimbalsim_scene', 'gimbalsim_contract'],
    'firmware_sim': ['gimbalsim_firmware_sim', 'gimbalsim_lcmtypes', 'gimbalsim_lcm_wire', 'Threads::Threads'],
    'gimbalsim_controllers': ['gimbalsim_scene', 'gimbalsim_contract'],
    'pointing_controller': ['gimbalsim_controllers', 'gimbalsim_lcmtypes', 'gimbalsim_lcm_wire'],
    'gimbalsim': ['gimbalsim_scene', 'gimbalsim_controllers'],
    'gimbalsim_workprec_lib': ['gimbalsim_scene'],
    '_gimbalsim': ['gimbalsim_controllers', 'gimbalsim_firmware_sim', 'Python3::Module'],
    'all_test': ['gimbalsim_workprec_lib', 'gimbalsim_controllers', 'gimbalsim_firmware_sim', 'gimbalsim_lcmtypes',
                 'gimbalsim_pointing'],
}


def write_tree(root, files):
    for rel, text in files.items():
        path = os.path.join(root, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, 'w') as f:
            f.write(text)


def write_dot(path, graph):
    """A graph in the format of cmake --graphviz (node ids, labels, edges with comments)."""
    ids = {}
    lines = ['digraph "gimbalsim" {', 'node [', '  fontsize = "12"', '];']
    for a, links in graph.items():
        for name in [a, *links]:
            if name not in ids:
                ids[name] = f'node{len(ids)}'
                lines.append(f'    "{ids[name]}" [ label = "{name}", shape = octagon ];')
        for b in links:
            lines.append(f'    "{ids[a]}" -> "{ids[b]}" [ style = dotted ] // {a} -> {b}')
    lines.append('}')
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')


@pytest.fixture
def mini(tmp_path):
    root = tmp_path / 'src'
    write_tree(str(root), MINI_TREE)
    return root


def check_mini(root, extra_edges=()):
    graph = {a: list(b) for a, b in MINI_GRAPH.items()}
    for a, b in extra_edges:
        graph.setdefault(a, []).append(b)
    dot = root.parent / 'targets.dot'
    write_dot(str(dot), graph)
    return check('--source', str(root), '--dot', str(dot))


def append_line(root, rel, line):
    """Appends a line to a file of the tree; its line number."""
    path = os.path.join(str(root), rel)
    with open(path) as f:
        text = f.read()
    if text and not text.endswith('\n'):
        text += '\n'
    with open(path, 'w') as f:
        f.write(text + line + '\n')
    return text.count('\n') + 1


def test_mini_tree_is_clean(mini):
    status, violations, out = check_mini(mini)
    assert status == 0 and violations == [], out
    assert out.splitlines()[-1].endswith('include lines, no forbidden edge'), out


# file, included header, the expected line's start (rule, from -> to)
INJECTED_INCLUDES = [
    ('dynamics/src/model.cpp', '<lcm/lcm-cpp.hpp>', 'rule 1: dynamics -> LCM'),
    ('dynamics/scene/src/scene.cpp', '"gimbalsim/gimbal_command_t.hpp"', 'rule 1: dynamics/scene -> lcmtypes'),
    ('dynamics/pointing/include/gimbalsim/pointing/pointing.hpp', '"gimbalsim/contract/messages.hpp"',
     'rule 1: dynamics/pointing -> lcmtypes/contract'),
    ('dynamics/include/gimbalsim/dynamics/model.hpp', '"gimbalsim/input/input.hpp"',
     'rule 1: dynamics -> base/input'),
    ('firmware_sim/src/firmware.cpp', '"gimbalsim/controllers/pid.hpp"', 'rule 2: firmware_sim -> controllers'),
    ('controllers/src/pid.cpp', '"gimbalsim/firmware_sim/firmware.hpp"', 'rule 3: controllers -> firmware_sim'),
    # a header that does not exist yet: gimbalsim/firmware_sim/ is the plant's include path
    ('controllers/include/gimbalsim/controllers/pid.hpp', '"gimbalsim/firmware_sim/not_yet.hpp"',
     'rule 3: controllers -> firmware_sim'),
    ('python/src/module.cpp', '"workprec.hpp"', 'rule 4: python -> tools/workprec'),
    ('dynamics/scene/src/scene.cpp', '"../../../tools/workprec/workprec.hpp"', 'rule 4: dynamics/scene -> tools/workprec'),
    ('base/io/src/io.cpp', '"gimbalsim/dynamics/model.hpp"', 'rule 7: base/io -> dynamics'),
    ('base/input/include/gimbalsim/input/input.hpp', '<lcm/lcm-cpp.hpp>', 'rule 7: base/input -> LCM'),
    ('firmware_sim/programs/main.cpp', '<workprec.hpp>', 'rule 4: firmware_sim -> tools/workprec'),
    ('lcmtypes/lcm_wire/src/lcm_wire.cpp', '"gimbalsim/dynamics/model.hpp"', 'rule 5: lcmtypes/lcm_wire -> dynamics'),
    ('lcmtypes/contract/include/gimbalsim/contract/messages.hpp', '"gimbalsim/firmware_sim/firmware.hpp"',
     'rule 6: lcmtypes/contract -> firmware_sim'),
    ('lcmtypes/contract/include/gimbalsim/contract/messages.hpp', '"gimbalsim/controllers/pid.hpp"',
     'rule 6: lcmtypes/contract -> controllers'),
]


@pytest.mark.parametrize('rel,header,expected', INJECTED_INCLUDES, ids=[f'{e[:6]}-{r}' for r, _, e in INJECTED_INCLUDES])
def test_injected_include_is_reported(mini, rel, header, expected):
    line = append_line(mini, rel, f'#include {header}')
    status, violations, out = check_mini(mini)
    assert status == 1, out
    assert violations == [f'{expected} ({rel}:{line} includes {header})'], out


# injected link edges, the expected lines (a forbidden edge also shows where it
# lets an in-scope target reach a forbidden one through it)
INJECTED_LINKS = [
    ([('gimbalsim_scene', 'gimbalsim_lcmtypes')],
     ['rule 1: dynamics/scene -> lcmtypes (target gimbalsim_scene links gimbalsim_lcmtypes)']),
    ([('gimbalsim_io', 'PkgConfig::LCM')],
     ['rule 7: base/io -> LCM (target gimbalsim_io links PkgConfig::LCM)',
      'rule 5: lcmtypes/lcm_wire -> LCM (target gimbalsim_lcm_wire links PkgConfig::LCM via gimbalsim_io)']),
    ([('gimbalsim_io', '/usr/lib/x86_64-linux-gnu/liblcm.so')],
     ['rule 7: base/io -> LCM (target gimbalsim_io links /usr/lib/x86_64-linux-gnu/liblcm.so)',
      'rule 5: lcmtypes/lcm_wire -> LCM (target gimbalsim_lcm_wire links /usr/lib/x86_64-linux-gnu/liblcm.so via gimbalsim_io)']),
    ([('gimbalsim_pointing', 'gimbalsim_controllers')],
     ['rule 1: dynamics/pointing -> lcmtypes/contract '
      '(target gimbalsim_pointing links gimbalsim_contract via gimbalsim_controllers)']),
    ([('gimbalsim_dynamics', 'gimbalsim_input')],
     ['rule 1: dynamics -> base/input (target gimbalsim_dynamics links gimbalsim_input)']),
    ([('gimbalsim_firmware_sim', 'gimbalsim_controllers')],
     ['rule 2: firmware_sim -> controllers (target gimbalsim_firmware_sim links gimbalsim_controllers)']),
    ([('gimbalsim_controllers', 'gimbalsim_firmware_sim')],
     ['rule 3: controllers -> firmware_sim (target gimbalsim_controllers links gimbalsim_firmware_sim)']),
    ([('_gimbalsim', 'gimbalsim_workprec_lib')],
     ['rule 4: python -> tools/workprec (target _gimbalsim links gimbalsim_workprec_lib)']),
    ([('pointing_controller', 'gimbalsim_workprec_lib')],
     ['rule 4: controllers -> tools/workprec (target pointing_controller links gimbalsim_workprec_lib)']),
    ([('gimbalsim_lcm_wire', 'gimbalsim_dynamics')],
     ['rule 5: lcmtypes/lcm_wire -> dynamics (target gimbalsim_lcm_wire links gimbalsim_dynamics)']),
    ([('gimbalsim_lcm_wire', 'gimbalsim_scene')],
     ['rule 5: lcmtypes/lcm_wire -> dynamics/scene (target gimbalsim_lcm_wire links gimbalsim_scene)']),
    ([('gimbalsim_input', 'gimbalsim_scene')],
     ['rule 7: base/input -> dynamics/scene (target gimbalsim_input links gimbalsim_scene)']),
    ([('gimbalsim_contract', 'gimbalsim_firmware_sim')],
     ['rule 3: controllers -> firmware_sim '
      '(target gimbalsim_controllers links gimbalsim_firmware_sim via gimbalsim_contract)',
      'rule 3: controllers -> firmware_sim '
      '(target pointing_controller links gimbalsim_firmware_sim via gimbalsim_lcmtypes, gimbalsim_contract)',
      'rule 6: lcmtypes/contract -> firmware_sim (target gimbalsim_contract links gimbalsim_firmware_sim)']),
    ([('gimbalsim_contract', 'gimbalsim_controllers')],
     ['rule 2: firmware_sim -> controllers (target firmware_sim links gimbalsim_controllers '
      'via gimbalsim_lcmtypes, gimbalsim_contract)',
      'rule 2: firmware_sim -> controllers '
      '(target gimbalsim_firmware_sim links gimbalsim_controllers via gimbalsim_contract)',
      'rule 6: lcmtypes/contract -> controllers (target gimbalsim_contract links gimbalsim_controllers)']),
]


@pytest.mark.parametrize('edges,expected', INJECTED_LINKS, ids=[f'{e[0][:6]}-{a}-{b}' for [(a, b)], e in INJECTED_LINKS])
def test_injected_link_is_reported(mini, edges, expected):
    status, violations, out = check_mini(mini, edges)
    assert status == 1, out
    assert sorted(violations) == sorted(expected), out


def test_allowed_edges_are_not_reported(mini):
    """tests/ links and includes anything; python/ and tools/ link plant and controller."""
    edges = [('all_test', 'gimbalsim'), ('gimbalsim_workprec_lib', 'gimbalsim_firmware_sim'),
             ('gimbalsim_workprec_lib', 'gimbalsim_lcmtypes'), ('_gimbalsim', 'gimbalsim_lcmtypes')]
    append_line(mini, 'tests/all_test.cpp', '#include "gimbalsim/gimbal_command_t.hpp"')
    append_line(mini, 'tools/workprec/workprec.cpp', '#include "gimbalsim/firmware_sim/firmware.hpp"')
    status, violations, out = check_mini(mini, edges)
    assert status == 0 and violations == [], out


def test_unreadable_inputs_are_refused(mini, tmp_path):
    empty = tmp_path / 'empty.dot'
    empty.write_text('digraph "x" {\n}\n')
    status, _, out = check('--source', str(mini), '--dot', str(empty))
    assert status == 2 and 'no project target in the graph' in out, out
    status, _, out = check('--source', str(mini), '--build-dir', str(tmp_path))
    assert status == 2 and 'no CMakeCache.txt' in out, out


# --- a copy of the real tree -------------------------------------------------------------

def copy_tree(dest):
    """The real tree without build directories and hidden folders."""
    def ignore(d, names):
        top = os.path.abspath(d) == os.path.abspath(SOURCE)
        return [n for n in names
                if n.startswith('.') or n == '__pycache__'
                or (top and (n.startswith('build') or n in ('out', 'dist')))
                or os.path.exists(os.path.join(d, n, 'CMakeCache.txt'))]
    shutil.copytree(SOURCE, dest, ignore=ignore)
    return dest


def test_injected_includes_in_a_copy_of_the_tree(tmp_path):
    """One new file per rule in the real layout, each reported at its line with its rule."""
    root = copy_tree(tmp_path / 'src')
    names = [f for _, _, fs in os.walk(root) for f in fs]
    tools_headers = sorted(os.path.relpath(os.path.join(d, f), root).replace(os.sep, '/')
                           for d, _, fs in os.walk(root / 'tools') for f in fs
                           if f.endswith('.hpp') and names.count(f) == 1
                           and os.path.exists(os.path.join(d, 'CMakeLists.txt')))
    assert tools_headers, 'no header of its own name beside a CMakeLists.txt under tools/'
    tools_header = tools_headers[0]  # e.g. tools/stress/stress_check.hpp
    injected = [  # new file, include, the expected line's start
        ('dynamics/src/injected.cpp', '<lcm/lcm-cpp.hpp>', 'rule 1: dynamics -> LCM'),
        ('dynamics/scene/src/injected.cpp', '"gimbalsim/contract/messages.hpp"',
         'rule 1: dynamics/scene -> lcmtypes/contract'),
        ('dynamics/include/gimbalsim/dynamics/injected.hpp', '"gimbalsim/input/key_registry.hpp"',
         'rule 1: dynamics -> base/input'),
        ('firmware_sim/src/injected.cpp', '"gimbalsim/controllers/pid.hpp"', 'rule 2: firmware_sim -> controllers'),
        ('controllers/src/injected.cpp', '"gimbalsim/firmware_sim/firmware.hpp"',
         'rule 3: controllers -> firmware_sim'),
        ('python/src/injected.cpp', f'"{os.path.basename(tools_header)}"',
         f'rule 4: python -> {os.path.dirname(tools_header)}'),
        ('lcmtypes/lcm_wire/src/injected.cpp', '"gimbalsim/dynamics/model.hpp"',
         'rule 5: lcmtypes/lcm_wire -> dynamics'),
        ('lcmtypes/contract/include/gimbalsim/contract/injected.hpp', '"gimbalsim/firmware_sim/firmware.hpp"',
         'rule 6: lcmtypes/contract -> firmware_sim'),
        ('base/io/src/injected.cpp', '"gimbalsim/scene/scene.hpp"', 'rule 7: base/io -> dynamics/scene'),
    ]
    for rel, header, _ in injected:
        write_tree(str(root), {rel: f'// injected by test_check_deps.py\n#include {header}\n'})
    dot = tmp_path / 'targets.dot'
    write_dot(str(dot), MINI_GRAPH)  # the graph does not matter here
    status, violations, out = check('--source', str(root), '--dot', str(dot))
    assert status == 1, out
    for rel, header, expected in injected:
        assert f'{expected} ({rel}:2 includes {header})' in violations, (rel, out)
    assert not [v for v in violations if 'injected' not in v and not v.startswith('rule 3: ')], out


def test_injected_links_in_a_copy_of_the_tree(tmp_path):
    """Forbidden links added to the real CMakeLists.txt, read through the build's configure."""
    build = build_dir()
    root = copy_tree(tmp_path / 'src')
    with open(root / 'CMakeLists.txt', 'a') as f:
        f.write('\n# injected by test_check_deps.py\n'
                'target_link_libraries(gimbalsim_pointing PRIVATE gimbalsim_lcmtypes)\n'
                'target_link_libraries(gimbalsim_lcm_wire PUBLIC gimbalsim_dynamics)\n'
                'target_link_libraries(gimbalsim_record PRIVATE gimbalsim_stress_lib)\n')
    status, violations, out = check('--source', str(root), '--build-dir', build)
    assert status == 1, out
    for expected in [
            'rule 1: dynamics/pointing -> lcmtypes (target gimbalsim_pointing links gimbalsim_lcmtypes)',
            'rule 5: lcmtypes/lcm_wire -> dynamics (target gimbalsim_lcm_wire links gimbalsim_dynamics)',
            'rule 4: firmware_sim -> tools/stress (target gimbalsim_record links gimbalsim_stress_lib)']:
        assert expected in violations, out
