"""The layout rules of the house, checked on the source with `ast` (no imports executed).

- No import cycles between modules (package `__init__` re-exports aside).
- A sub-package uses another only through its public names: no module imports a private
  module (`_name`) or a private name of a different sub-package.
- Dependencies between sub-packages point one way (the sub-package graph is acyclic), the
  command line is a leaf, and library modules stay under about 500 lines.
"""

import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
PACKAGES = ("teflon_jax", "identification")
MAX_LINES = 500


def _modules():
    mods = {}
    for pkg in PACKAGES:
        for f in (ROOT / pkg).rglob("*.py"):
            name = ".".join(f.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
            mods[name] = f
    return mods


MODULES = _modules()


def _is_package(name):
    return MODULES[name].name == "__init__.py"


def _imports(name):
    """(target module or package, imported names) for every import in module `name`."""
    f = MODULES[name]
    base = name.split(".") if _is_package(name) else name.split(".")[:-1]
    out = []
    for node in ast.walk(ast.parse(f.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                parts = base[: len(base) - node.level + 1]
                target = ".".join(parts + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            out.append((target, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            out += [(a.name, []) for a in node.names]
    return out


def _resolve(target, names):
    """Modules a statement really reaches (`from pkg import _mod` reaches pkg._mod)."""
    hits = [target] if target in MODULES else []
    hits += [f"{target}.{n}" for n in names if f"{target}.{n}" in MODULES]
    return hits


def _subpackage(name):
    parts = name.split(".")
    return ".".join(parts[:2]) if len(parts) > 1 else parts[0]


def _module_graph():
    graph = {}
    for name in MODULES:
        if _is_package(name):
            continue
        deps = set()
        for target, names in _imports(name):
            for hit in _resolve(target, names):
                if hit != name and not _is_package(hit):
                    deps.add(hit)
                elif hit != name and hit != name.rsplit(".", 1)[0]:
                    # `from .pkg import x` runs pkg/__init__, which imports its modules
                    deps.update(d for d in MODULES if d.startswith(hit + ".") and not _is_package(d)
                                and d.rsplit(".", 1)[0] == hit)
        graph[name] = deps
    return graph


def _cycles(graph):
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in graph:
        if v not in index:
            visit(v)
    return found


def test_no_import_cycles_between_modules():
    graph = {
        m: {d for d in deps if _subpackage(d) == _subpackage(m)} for m, deps in _module_graph().items()
    }
    assert _cycles(graph) == []


def test_subpackages_depend_on_each_other_one_way():
    graph = {}
    for m, deps in _module_graph().items():
        graph.setdefault(_subpackage(m), set()).update(
            _subpackage(d) for d in deps if _subpackage(d) != _subpackage(m)
        )
    assert _cycles(graph) == []


def test_no_private_imports_across_subpackages():
    offences = []
    for name in MODULES:
        own = _subpackage(name)
        for target, names in _imports(name):
            if not target.startswith(PACKAGES):
                continue
            if _subpackage(target) == own and target.count(".") >= 1:
                continue
            parts = target.split(".")
            private_module = any(p.startswith("_") and p != "__init__" for p in parts)
            private_names = [n for n in names if n.startswith("_")]
            if private_module or private_names:
                offences.append(f"{name}: from {target} import {', '.join(names)}")
    assert offences == []


def test_command_line_is_a_leaf():
    # teflon_jax/__main__.py (`python -m teflon_jax`) is the command line's other door.
    users = [
        m for m in MODULES
        if not m.startswith(("teflon_jax.cli", "teflon_jax.__main__"))
        for target, _ in _imports(m) if target.startswith("teflon_jax.cli")
    ]
    assert users == []


@pytest.mark.parametrize("name", sorted(m for m in MODULES if not _is_package(m)))
def test_library_modules_are_short(name):
    lines = len(MODULES[name].read_text().splitlines())
    assert lines <= MAX_LINES, f"{MODULES[name]} has {lines} lines"


TEXT_SUFFIXES = {".py", ".md", ".toml", ".json", ".csv", ".sh", ".yml", ".yaml", ".txt", ""}
CONFLICT_MARKERS = ("<<<<<<< ", "=======", ">>>>>>> ")


def _unmerged_lines(path):
    """Lines of `path` that are merge-conflict markers left behind, as (number, text)."""
    lines = path.read_text(errors="replace").splitlines()
    return [(i + 1, line) for i, line in enumerate(lines)
            if line.startswith(CONFLICT_MARKERS[::2]) or line == CONFLICT_MARKERS[1]]


def test_no_merge_conflict_markers_are_left_in_the_sources_and_docs():
    folders = [*PACKAGES, "tests", "docs", "benchmarks", "data", ".ci"]
    files = [f for folder in folders for f in (ROOT / folder).rglob("*") if f.is_file() and f.suffix in TEXT_SUFFIXES]
    files += [ROOT / "README.md", ROOT / "pyproject.toml", ROOT / "mkdocs.yml"]
    left = {str(f.relative_to(ROOT)): _unmerged_lines(f) for f in files if f.exists()}
    assert {k: v for k, v in left.items() if v} == {}


def test_the_marker_check_finds_a_left_conflict(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("text\n<<<<<<< HEAD\nours\n=======\ntheirs\n>>>>>>> branch\n=== a heading rule\n")
    assert [n for n, _ in _unmerged_lines(page)] == [2, 4, 6]


def test_the_rules_catch_a_cycle_and_a_private_import():
    # the checks themselves: a made-up graph with a cycle is found, one without is not
    assert _cycles({"a": {"b"}, "b": {"a"}}) == [["a", "b"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []
