"""The import graph of src/rvsim has no circles and no upward imports (issue 31;
docs/architecture.md).

Every ``import`` and ``from ... import`` of every module is read with ``ast``, wherever it
stands: at module level, inside functions (lazy imports), under ``try`` or ``TYPE_CHECKING``.
Relative imports are resolved; ``from pkg import name`` counts as an import of ``pkg.name``
when that is a module.  Three checks:

* **layers**: a module imports only from its own layer or below (:data:`LAYERS`); every
  upward import still allowed is listed in :data:`ALLOWED_UPWARD` with the step of issue 31
  that removes it;
* **package circles**: the graph of top-level units (``rvsim.doe -> rvsim.tolerance``) has no
  cycle once the edges in :data:`ALLOWED_UPWARD` and :data:`ALLOWED_CYCLE` are taken out;
* **module circles**: neither has the graph of modules (same allowances).

The allow-lists only shrink: an entry the code no longer has fails the test too
(``test_allow_lists_hold_only_what_exists``), so a step that removes a violation also removes
its entry.  ``python tests/unit/test_import_layers.py`` prints today's violations as Python
literals.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "rvsim"

#: the layer of every top-level unit of rvsim (low = lower).  ``rvsim`` itself (the facade,
#: which re-exports lazily) is not layered: ``import rvsim.x`` runs it anyway.
LAYERS = {
    # 0 foundation: no physics, no numba kernels; imported by everything
    "rvsim.units": 0, "rvsim.errors": 0, "rvsim._files": 0, "rvsim._json": 0,
    "rvsim._fingerprint": 0, "rvsim._stopping": 0, "rvsim._jit": 0, "rvsim._cache_guard": 0,
    "rvsim.data": 0, "rvsim._matplotlib": 0, "rvsim._display": 0, "rvsim._keywords": 0,
    # 1 inputs and metrics: parameter sets; pure functions of curves and tables
    "rvsim.parameters": 1, "rvsim.analysis": 1,
    # 2 geometry and finite-element tables
    "rvsim.geometry": 2, "rvsim.fe": 2,
    # 3 physics: laws, elements, the one force evaluation; constants of bearings and friction
    "rvsim.physics": 3, "rvsim.bearings": 3, "rvsim.friction": 3, "rvsim.analytical": 3,
    # 4 engines
    "rvsim.dynamics": 4, "rvsim.quasistatic": 4,
    # 5 figures and HTML building blocks
    "rvsim.plots": 5, "rvsim.html": 5,
    # 6 studies
    "rvsim.doe": 6, "rvsim.tolerance": 6, "rvsim.testrig": 6,
    # 7 reports of run folders and exported models
    "rvsim.report": 7, "rvsim._efficiency_report": 7, "rvsim.joint_model": 7,
    # 8 command line
    "rvsim.cli": 8, "rvsim.__main__": 8,
}

#: (importer module, imported module) upward imports still allowed, each with its reason (steps
#: 1-8 of issue 31 removed every other entry; docs/architecture.md "Layers")
ALLOWED_UPWARD = {
    # kept (step 4, option (a) of the plan; docs/decisions.md "Issue 31 ... steps 4-8"): the
    # public rvsim.parameters.validate (and load_toml, with_values, which call it) must refuse a
    # bad geometry, so it forwards lazily to the checks that need geometry, now all in
    # geometry.checks; removing it means moving validate out of parameters (an API change)
    ("rvsim.parameters._io", "rvsim.geometry.checks"),
}

#: (importer module, imported module) edges inside one layer that close a circle, each with its
#: reason
ALLOWED_CYCLE: set = set()


def _module_name(path: Path) -> tuple[str, bool]:
    parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
    is_package = parts[-1] == "__init__"
    if is_package:
        parts.pop()
    return ".".join(parts), is_package


def read_imports() -> dict[str, set[str]]:
    """{module: {imported rvsim module}} for every module under src/rvsim, lazy ones included."""
    files = {_module_name(p): p for p in sorted(SRC.rglob("*.py"))}
    modules = {name for name, _ in files}
    graph: dict[str, set[str]] = {}
    for (name, is_package), path in files.items():
        package = name if is_package else name.rpartition(".")[0]
        found: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")[:len(package.split(".")) - node.level + 1]
                    module = ".".join(base + ([node.module] if node.module else []))
                else:
                    module = node.module or ""
                subs = [f"{module}.{a.name}" for a in node.names if f"{module}.{a.name}" in modules]
                targets = subs + ([module] if len(subs) < len(node.names) else [])
            for target in targets:
                if not (target == "rvsim" or target.startswith("rvsim.")):
                    continue
                while target not in modules and "." in target:
                    target = target.rpartition(".")[0]
                if target != name and target != "rvsim":
                    found.add(target)
        graph[name] = found
    return graph


def unit(module: str) -> str:
    return ".".join(module.split(".")[:2])


def upward_imports(graph) -> set[tuple[str, str]]:
    out = set()
    for a, targets in graph.items():
        for b in targets:
            ua, ub = unit(a), unit(b)
            if ua == ub or "rvsim" in (ua, ub):
                continue
            if LAYERS[ub] > LAYERS[ua]:
                out.add((a, b))
    return out


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one node (Tarjan, iterative)."""
    index, low, on_stack, stack, out = {}, {}, set(), [], []
    counter = 0
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph.get(root, ()))))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            v, children = work[-1]
            for w in children:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph.get(w, ())))))
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    component = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        component.append(w)
                        if w == v:
                            break
                    if len(component) > 1:
                        out.append(sorted(component))
    return out


def _without_allowed(graph):
    allowed = ALLOWED_UPWARD | ALLOWED_CYCLE
    return {a: {b for b in targets if (a, b) not in allowed} for a, targets in graph.items()}


@pytest.fixture(scope="module")
def graph():
    return read_imports()


def test_every_unit_has_a_layer(graph):
    assert {unit(m) for m in graph} - {"rvsim"} <= set(LAYERS)


def test_no_upward_imports(graph):
    new = sorted(upward_imports(graph) - ALLOWED_UPWARD)
    assert not new, "upward imports (docs/architecture.md, layers):\n" + "\n".join(
        f"  {a} [{LAYERS[unit(a)]}] -> {b} [{LAYERS[unit(b)]}]" for a, b in new)


def test_no_package_circles(graph):
    packages: dict[str, set[str]] = defaultdict(set)
    for a, targets in _without_allowed(graph).items():
        for b in targets:
            if unit(a) != unit(b) and "rvsim" not in (unit(a), unit(b)):
                packages[unit(a)].add(unit(b))
    found = cycles(packages)
    assert not found, f"import circles between packages: {found}"


def test_no_module_circles(graph):
    found = cycles(_without_allowed(graph))
    assert not found, f"import circles between modules: {found}"


def test_allow_lists_hold_only_what_exists(graph):
    edges = {(a, b) for a, targets in graph.items() for b in targets}
    stale = sorted((ALLOWED_UPWARD | ALLOWED_CYCLE) - edges)
    assert not stale, f"remove these allow-list entries, the code no longer has them: {stale}"
    still_upward = ALLOWED_UPWARD & edges
    assert still_upward <= upward_imports(graph), \
        f"not upward (any more): {sorted(still_upward - upward_imports(graph))}"
    packages: dict[str, set[str]] = defaultdict(set)
    for a, b in edges:
        packages[unit(a)].add(unit(b))
    on_cycle = {(a, b) for a, b in ALLOWED_CYCLE
                if _reaches(graph, b, a) or (unit(a) != unit(b) and _reaches(packages, unit(b), unit(a)))}
    assert on_cycle == ALLOWED_CYCLE, \
        f"on no circle (any more), remove: {sorted(ALLOWED_CYCLE - on_cycle)}"


def _reaches(graph, start: str, goal: str) -> bool:
    seen, todo = {start}, [start]
    while todo:
        for w in graph.get(todo.pop(), ()):
            if w == goal:
                return True
            if w not in seen:
                seen.add(w)
                todo.append(w)
    return start == goal


if __name__ == "__main__":            # print today's violations, to refresh the allow-lists
    g = read_imports()
    print("upward:", sorted(upward_imports(g)))
    print("package/module cycles left after the upward edges:",
          cycles({a: {b for b in t if (a, b) not in upward_imports(g)} for a, t in g.items()}))
