"""The package's layout: no import circles, data flowing down the floors, every file in the
layout table of ``docs/DEVELOPING.md``; and the list of the longest functions
(``python tests/test_package_layout.py --longest 10``).

Import graph.

Every module under ``rotordyn_modal`` is parsed with :mod:`ast` (nothing is imported);
``import`` and ``from ... import`` statements become edges, relative ones resolved against
the module's package, ``from .pkg import name`` an edge to ``pkg.name`` when that is a
module and to ``pkg`` otherwise. Two graphs are checked:

* **all imports**, wherever they stand (a function's deferred import runs as surely as a
  module-level one, only later): no circle at all;
* **module-level imports** (what runs at import time, class bodies included): never up a
  floor. Upward imports inside functions are allowed only for the convenience methods
  listed in :data:`UPWARD_IN_FUNCTIONS` (results drawing themselves, the model building
  its own matrices).

Floors, lowest first (``docs/DEVELOPING.md``): the model and what it is made of, assembly,
the linear system, analyses and simulation, plotting and files, studies, the command line;
the package root (the public API) sits on top. The root's lazy ``importlib`` look-ups of
its public names are not statements and are not counted.
"""

from __future__ import annotations

import argparse
import ast
import functools
import re
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "rotordyn_modal"
DEVELOPING = PACKAGE.parent / "docs" / "DEVELOPING.md"
ROOT = PACKAGE.name

#: second component of a module name -> floor (anything not listed is on the model floor, 0)
FLOORS = {"assembly": 1, "linear_system": 2, "stiffness_spread": 2, "plausibility": 2, "analysis": 3, "simulation": 3, "plotting": 4, "io": 4,
          "study": 5, "report": 5, "cli": 6, "__main__": 7}
TOP = 7                                             # the package itself; __main__ (python -m) stands there too

#: (importing module prefix, imported module prefix) allowed upward inside functions only
UPWARD_IN_FUNCTIONS = {
    ("analysis.", "plotting"),                  # Result.plot(), .plot_orbits(), ...
    ("simulation.result", "plotting"),          # SimulationResult.plot()
    ("model", "assembly"),                      # Model.matrices()
    ("model", "linear_system"),                 # Model.state_space()
}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _module_level(tree):
    """Nodes that run when the module is imported: everything outside function bodies."""
    stack = list(tree.body)
    while stack:
        node = stack.pop()
        yield node
        if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            stack.extend(ast.iter_child_nodes(node))


def _targets(node, package: str, known) -> set[str]:
    if isinstance(node, ast.Import):
        return {alias.name for alias in node.names if alias.name in known}
    if not isinstance(node, ast.ImportFrom):
        return set()
    if node.level:
        base = package.split(".")[:len(package.split(".")) - node.level + 1]
        target = ".".join(base + ([node.module] if node.module else []))
    else:
        target = node.module or ""
    out = set()
    for alias in node.names:
        if f"{target}.{alias.name}" in known:
            out.add(f"{target}.{alias.name}")
        elif target in known:
            out.add(target)
    return out


def import_graph(module_level_only: bool = False) -> dict[str, set[str]]:
    """Module -> the package's modules it imports (names like ``rotordyn_modal.study.definition``)."""
    return {name: set(targets) for name, targets in _import_graph(module_level_only).items()}


@functools.lru_cache(maxsize=None)
def _tree(path: Path) -> ast.Module:
    """The syntax tree of a file of the package, parsed once per process for the import graphs
    and the function lengths (read only: walked, never changed)."""
    return ast.parse(path.read_text(encoding="utf-8"), filename=str(path))


@functools.lru_cache(maxsize=None)
def _import_graph(module_level_only: bool) -> dict[str, set[str]]:
    """:func:`import_graph`, parsed once per process (the package's files do not change during
    a test run; each test gets its own copy)."""
    known = modules()
    graph = {}
    for name, path in known.items():
        tree = _tree(path)
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        nodes = _module_level(tree) if module_level_only else ast.walk(tree)
        graph[name] = set().union(*(_targets(node, package, known) for node in nodes)) - {name}
    return graph


def circles(graph) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index, low, on_stack, stack, found = {}, {}, set(), [], []
    counter = 0
    for start in graph:
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = counter
        counter += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = counter
                    counter += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def floor(name: str) -> int:
    parts = name.split(".")
    return TOP if len(parts) == 1 else FLOORS.get(parts[1], 0)


def _relative(name: str) -> str:
    return name.partition(".")[2]


def test_the_graph_sees_every_module_and_known_edges():
    graph = import_graph()
    assert len(graph) == len(list(PACKAGE.rglob("*.py")))
    assert f"{ROOT}.study.analyses" in graph[f"{ROOT}.study.definition"]
    assert f"{ROOT}.plotting" in graph[f"{ROOT}.analysis.campbell"]              # inside a function
    assert f"{ROOT}.errors" in import_graph(module_level_only=True)[f"{ROOT}.assembly"]


def test_circles_are_found_when_present():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": {"e"}}
    assert circles(graph) == [["a", "b", "c"]]


def test_no_import_circles():
    assert circles(import_graph()) == []


def test_module_level_imports_never_go_up_a_floor():
    upward = [(m, t) for m, targets in import_graph(module_level_only=True).items() for t in targets
              if floor(t) > floor(m)]
    assert upward == []


def test_upward_imports_in_functions_are_only_the_listed_conveniences():
    upward = sorted((_relative(m), _relative(t)) for m, targets in import_graph().items() for t in targets
                    if floor(t) > floor(m))
    unexpected = [(m, t) for m, t in upward
                  if not any(m.startswith(a) and t.startswith(b) for a, b in UPWARD_IN_FUNCTIONS)]
    assert unexpected == []


# ------------------------------------------------------------------------- layout table
def layout_rows() -> list[str]:
    """The rows of the layout table in ``docs/DEVELOPING.md``."""
    text = DEVELOPING.read_text(encoding="utf-8")
    section = text.split("## Layout", 1)[1].split("\n## ", 1)[0]
    return [line for line in section.splitlines() if line.startswith("|") and "rotordyn_modal" in line]


def _folder(row: str) -> str | None:
    found = re.search(r"`rotordyn_modal/(\w+)/`", row)
    return found.group(1) if found else None


def _files_named(row: str) -> set[str]:
    return set(re.findall(r"`(?:rotordyn_modal/)?(\w+\.py)`", row))


def test_every_file_of_the_package_is_in_the_layout_table():
    rows = layout_rows()
    named = {(_folder(row), name) for row in rows for name in _files_named(row)}
    files = {(None if path.parent == PACKAGE else path.parent.name, path.name)
             for path in PACKAGE.rglob("*.py") if path.name != "__init__.py" or path.parent == PACKAGE}
    assert sorted(files - named, key=str) == []


def test_every_file_in_the_layout_table_exists():
    for row in layout_rows():
        folder = _folder(row)
        for name in _files_named(row):
            assert (PACKAGE / (folder or "") / name).is_file(), (folder, name)


# ---------------------------------------------------------------------- longest functions
def longest_functions(count: int = 10) -> list[tuple[int, int, str, str]]:
    """The ``count`` longest functions: (lines, lines without the docstring, file:line, name)."""
    rows = []
    for path in sorted(PACKAGE.rglob("*.py")):
        for node in ast.walk(_tree(path)):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                body = node.body[1:] if ast.get_docstring(node) is not None and len(node.body) > 1 else node.body
                where = f"{path.relative_to(PACKAGE.parent)}:{node.lineno}"
                rows.append((node.end_lineno - node.lineno + 1, node.end_lineno - body[0].lineno + 1, where,
                             node.name))
    return sorted(rows, key=lambda row: (-row[0], row[2]))[:count]


def test_longest_functions_are_listed():
    rows = longest_functions(10)
    assert len(rows) == 10 and rows[0][0] >= rows[-1][0] >= rows[-1][1] > 0


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="List the package's longest functions.")
    parser.add_argument("--longest", type=int, default=10, metavar="N")
    for lines, code, where, name in longest_functions(parser.parse_args().longest):
        print(f"{lines:5d} lines {code:5d} code  {where}  {name}")
