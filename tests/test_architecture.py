"""The package's import structure: no import cycle between modules (deferred imports inside
functions included), and every import between subpackages goes down the layer order, so data
flows one way: inputs -> geometry -> operator -> solver -> result -> outputs.

Read from the source with :mod:`ast` (nothing is imported), so a new cycle or an upward import
fails here with the modules named.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "tribobem"

#: Layer of each top-level module or subpackage of tribobem: a module may import only from
#: layers below its own (or from its own subpackage).  ``<root>`` is ``tribobem/__init__.py``.
LAYERS = {
    "errors": 0, "_version": 0, "_solver_version": 0,
    "units": 1, "_fft": 1, "grid": 1, "materials": 1, "data": 1,
    "results": 2, "analytic": 2, "geometry": 2, "elasticity": 2,
    "interactions": 3,
    "solvers": 4,
    "output": 5,
    "analysis": 6, "two_scale": 6,
    "runs": 7,
    "scenario": 8,
    "sweep": 9, "validation": 9,
    "design": 10,
    "cli": 11, "<root>": 11,
}


def _modules() -> dict[str, Path]:
    out = {}
    for p in SRC.rglob("*.py"):
        parts = list(p.relative_to(SRC.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


def _imports(mods: dict[str, Path]) -> dict[str, set[str]]:
    """module -> the tribobem modules it imports (at module level or inside functions)."""
    edges: dict[str, set[str]] = defaultdict(set)
    for mod, path in mods.items():
        is_pkg = path.name == "__init__.py"
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = mod.split(".") if is_pkg else mod.split(".")[:-1]
                    base = base[: len(base) - (node.level - 1)]
                    name = ".".join(base + ([node.module] if node.module else []))
                else:
                    name = node.module or ""
                targets = [f"{name}.{a.name}" if f"{name}.{a.name}" in mods else name for a in node.names]
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            else:
                continue
            for t in targets:
                if not t.startswith("tribobem"):
                    continue
                while t not in mods and "." in t:
                    t = t.rsplit(".", 1)[0]
                if t != mod:
                    edges[mod].add(t)
    return edges


def _cycles(nodes, edges) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return out


def _layer_of(mod: str) -> str:
    parts = mod.split(".")
    return parts[1] if len(parts) > 1 else "<root>"


@pytest.fixture(scope="module")
def graph():
    mods = _modules()
    return mods, _imports(mods)


def test_the_reader_sees_the_package(graph):
    mods, edges = graph
    assert {"tribobem.runs.kind", "tribobem.scenario.schema", "tribobem.solvers.normal"} <= set(mods)
    # a known edge of each kind of import statement
    assert "tribobem.runs" in edges["tribobem.scenario.schema"]  # from ..runs import KINDS
    assert "tribobem.errors" in edges["tribobem.runs.kind"]


def test_no_import_cycle_between_modules(graph):
    mods, edges = graph
    cycles = _cycles(mods, edges)
    assert not cycles, "import cycles (deferred imports included): " + "; ".join(" <-> ".join(c) for c in cycles)


def test_imports_follow_the_layer_order(graph):
    mods, edges = graph
    unknown = sorted({_layer_of(m) for m in mods} - set(LAYERS))
    assert not unknown, f"give these subpackages a layer in LAYERS: {unknown}"
    upward = [f"{a} -> {b}" for a in sorted(edges) for b in sorted(edges[a])
              if _layer_of(a) != _layer_of(b) and LAYERS[_layer_of(a)] <= LAYERS[_layer_of(b)]]
    assert not upward, "imports against the layer order: " + ", ".join(upward)


def test_the_checker_catches_a_cycle_and_an_upward_import():
    """The two checks above on a made-up graph: they are not vacuous."""
    edges = {"tribobem.solvers.a": {"tribobem.runs.b"}, "tribobem.runs.b": {"tribobem.solvers.a"}}
    assert _cycles(set(edges), edges) == [["tribobem.runs.b", "tribobem.solvers.a"]]
    assert LAYERS[_layer_of("tribobem.solvers.a")] <= LAYERS[_layer_of("tribobem.runs.b")]


# Tests mirror the package: a test of tribobem/<sub>/... lives in tests/<sub>/; the top of tests/
# keeps the tests of the top-level modules (cli, units, errors) and the whole-project checks;
# tests/benchmarks and tests/studies test the repository's scripts outside the package.
TESTS = Path(__file__).resolve().parent
PROJECT_TESTS = {"test_architecture.py", "test_cli.py", "test_docs.py", "test_examples.py", "test_fuzz.py",
                 "test_interrupts.py", "test_units.py", "test_user_visible.py"}
SCRIPT_FOLDERS = {"benchmarks", "studies"}


def test_tests_mirror_the_package_folders():
    subpackages = {p.name for p in SRC.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    misplaced = []
    for path in TESTS.rglob("test_*.py"):
        folder = path.relative_to(TESTS).parts[0]
        if path.parent == TESTS:
            if path.name not in PROJECT_TESTS:
                misplaced.append(str(path.relative_to(TESTS)))
        elif folder not in subpackages | SCRIPT_FOLDERS:
            misplaced.append(str(path.relative_to(TESTS)))
    assert not misplaced, f"test files outside a folder named after a tribobem subpackage: {misplaced}"
    assert len(list(TESTS.glob("test_*.py"))) == len(PROJECT_TESTS)


def test_test_files_have_unique_names_outside_packages():
    # pytest imports a test file of a folder without __init__.py by its bare name: two such files
    # of one name make the second fail to collect ("import file mismatch")
    seen: dict[str, Path] = {}
    clashes = []
    for path in sorted(TESTS.rglob("test_*.py")):
        if (path.parent / "__init__.py").exists():
            continue
        if path.name in seen:
            clashes.append(f"{seen[path.name].relative_to(TESTS)} and {path.relative_to(TESTS)}")
        seen[path.name] = path
    assert not clashes, f"test files of the same name in folders without __init__.py: {clashes}"
