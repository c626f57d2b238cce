"""Measured import graph of src/rvsim (issue 31), lazy (function-level) imports included.

Usage:  python scripts/refactor/imports.py [ROOT] [--edges] [--json FILE]
        ROOT defaults to /work/main/src/rvsim.

Every ``import``/``from ... import`` anywhere in a module (module level, inside functions,
inside ``try``/``if TYPE_CHECKING``) is read with ``ast``; relative imports are resolved against
the module's package.  ``from pkg import name`` counts as an import of ``pkg.name`` when that is
a module, else of ``pkg``.  Reported:

* package-level graph (rvsim.X -> rvsim.Y, X != Y) and its cycles (strongly connected
  components, plus one shortest cycle through each edge of a component);
* module-level cycles (SCCs of the module graph);
* imports of private modules (a ``_name`` path component) across packages;
* "upward" imports for the layer order of LAYERS below.
"""
from __future__ import annotations

import ast
import json
import sys
from collections import defaultdict, deque
from pathlib import Path

#: Two layer tables (low number = lower layer; a module may import from its own layer or below).
#: BRIEF is the order the task states: geometry/parameters -> physics -> engines -> studies ->
#: analysis -> report/plots -> cli.  PROPOSED is the order the measured graph supports
#: (docs/architecture.md draft): analysis is a library of pure functions that imports nothing
#: of rvsim but errors and is used by the engines (catalogue) and the studies, so it sits at
#: the bottom; the figure and HTML building blocks sit below the studies that draw their own
#: reports, the folder reports above them.  ``rvsim`` itself (the facade) is not layered:
#: ``import rvsim.x`` runs it anyway, and ``from rvsim import __version__`` is excluded.
#: ``rvsim.physics`` does not exist on main yet; both tables list it.
BRIEF = {
    "rvsim.units": 0, "rvsim.errors": 0, "rvsim._files": 0, "rvsim._json": 0,
    "rvsim._fingerprint": 0, "rvsim._stopping": 0, "rvsim._jit": 0, "rvsim._cache_guard": 0,
    "rvsim.data": 0,
    "rvsim.parameters": 1, "rvsim.geometry": 1, "rvsim.fe": 1,
    "rvsim.physics": 2, "rvsim.bearings": 2, "rvsim.friction": 2, "rvsim.analytical": 2,
    "rvsim.dynamics": 3, "rvsim.quasistatic": 3,
    "rvsim.doe": 4, "rvsim.tolerance": 4, "rvsim.testrig": 4,
    "rvsim.analysis": 5, "rvsim.joint_model": 5,
    "rvsim.plots": 6, "rvsim.report": 6, "rvsim._efficiency_report": 6, "rvsim.html": 6,
    "rvsim.cli": 7, "rvsim.__main__": 7,
}
BRIEF_NAMES = {0: "foundation", 1: "inputs/geometry", 2: "physics", 3: "engines", 4: "studies",
               5: "analysis", 6: "report/plots", 7: "cli"}
PROPOSED = {
    "rvsim.units": 0, "rvsim.errors": 0, "rvsim._files": 0, "rvsim._json": 0,
    "rvsim._fingerprint": 0, "rvsim._stopping": 0, "rvsim._jit": 0, "rvsim._cache_guard": 0,
    "rvsim.data": 0,
    "rvsim.parameters": 1, "rvsim.analysis": 1,
    "rvsim.geometry": 2, "rvsim.fe": 2,
    "rvsim.physics": 3, "rvsim.bearings": 3, "rvsim.friction": 3, "rvsim.analytical": 3,
    "rvsim.dynamics": 4, "rvsim.quasistatic": 4,
    "rvsim.plots": 5, "rvsim.html": 5,
    "rvsim.doe": 6, "rvsim.tolerance": 6, "rvsim.testrig": 6,
    "rvsim.report": 7, "rvsim._efficiency_report": 7, "rvsim.joint_model": 7,
    "rvsim.cli": 8, "rvsim.__main__": 8,
}
PROPOSED_NAMES = {0: "foundation", 1: "inputs+metrics", 2: "geometry/fe", 3: "physics",
                  4: "engines", 5: "figures/html", 6: "studies", 7: "reports", 8: "cli"}
TABLES = {"brief": (BRIEF, BRIEF_NAMES), "proposed": (PROPOSED, PROPOSED_NAMES)}
LAYERS, LAYER_NAMES = PROPOSED, PROPOSED_NAMES


def module_name(root: Path, path: Path) -> str:
    rel = path.relative_to(root.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def collect(root: Path):
    """{module: [(target, lineno, lazy, names)]} for every module under root."""
    files = {module_name(root, p): p for p in sorted(root.rglob("*.py"))}
    modules = set(files)
    imports: dict[str, list[tuple[str, int, bool, tuple[str, ...]]]] = {}
    for mod, path in files.items():
        is_pkg = path.name == "__init__.py"
        package = mod if is_pkg else mod.rpartition(".")[0]
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        lazy_lines = set()
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
                for sub in ast.walk(node):
                    if isinstance(sub, (ast.Import, ast.ImportFrom)):
                        lazy_lines.add(id(sub))
        found = []
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name == "rvsim" or alias.name.startswith("rvsim."):
                        found.append((alias.name, node.lineno, id(node) in lazy_lines, ()))
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = package.split(".")
                    base = base[:len(base) - (node.level - 1)]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                if not (target == "rvsim" or target.startswith("rvsim.")):
                    continue
                names = tuple(a.name for a in node.names)
                submods = [f"{target}.{n}" for n in names if f"{target}.{n}" in modules]
                for s in submods:
                    found.append((s, node.lineno, id(node) in lazy_lines, (s.rpartition(".")[2],)))
                rest = tuple(n for n in names if f"{target}.{n}" not in modules)
                if rest or not submods:
                    found.append((target, node.lineno, id(node) in lazy_lines, rest))
        imports[mod] = sorted(set(found), key=lambda t: (t[1], t[0]))
    return files, imports


def unit(mod: str) -> str:
    """The top-level unit: rvsim.dynamics._kernel -> rvsim.dynamics; rvsim.units -> rvsim.units."""
    parts = mod.split(".")
    return ".".join(parts[:2]) if len(parts) > 1 else mod


def sccs(graph: dict[str, set[str]]) -> list[list[str]]:
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]
    sys.setrecursionlimit(10000)

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
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(out, key=lambda c: (-len(c), c))


def shortest_path(graph, a, b):
    prev, queue = {a: None}, deque([a])
    while queue:
        v = queue.popleft()
        if v == b:
            path = []
            while v is not None:
                path.append(v)
                v = prev[v]
            return path[::-1]
        for w in sorted(graph.get(v, ())):
            if w not in prev:
                prev[w] = v
                queue.append(w)
    return None


def layer(mod: str) -> int | None:
    u = unit(mod)
    return LAYERS.get(u)


def analyse(root: Path):
    files, imports = collect(root)
    modules = set(files)
    mod_graph: dict[str, set[str]] = defaultdict(set)
    pkg_edges: dict[tuple[str, str], list[tuple[str, int, bool, str]]] = defaultdict(list)
    private_cross, upward = [], []
    for mod, items in imports.items():
        for target, line, lazy, names in items:
            tgt = target
            while tgt not in modules and "." in tgt:   # e.g. rvsim.x.name -> rvsim.x
                tgt = tgt.rpartition(".")[0]
            if tgt != mod:
                mod_graph[mod].add(tgt)
            a, b = unit(mod), unit(tgt)
            if a != b and b != "rvsim":
                pkg_edges[(a, b)].append((mod, line, lazy, tgt))
            priv = [p for p in tgt.split(".")[1:] if p.startswith("_") and p != "__init__"]
            if priv and a != b:
                private_cross.append((mod, line, lazy, tgt, names))
            # private names imported across packages (from rvsim.x import _name)
            if a != b:
                pn = [n for n in names if n.startswith("_")]
                if pn and not priv:
                    private_cross.append((mod, line, lazy, tgt, tuple(pn)))
            la, lb = layer(mod), layer(tgt)
            if a != b and "rvsim" not in (a, b) and la is not None and lb is not None and lb > la:
                upward.append((mod, line, lazy, tgt, la, lb))
    pkg_graph: dict[str, set[str]] = defaultdict(set)
    for a, b in pkg_edges:
        pkg_graph[a].add(b)
    return files, imports, mod_graph, pkg_edges, pkg_graph, private_cross, upward


def report(root: Path, show_edges: bool = False) -> dict:
    files, imports, mod_graph, pkg_edges, pkg_graph, private_cross, upward = analyse(root)
    out: dict = {}
    print(f"# import graph of {root} ({len(files)} modules, "
          f"{sum(len(v) for v in imports.values())} rvsim imports, "
          f"{sum(1 for v in imports.values() for t in v if t[2])} of them lazy)\n")

    print("## package-level edges (importer -> imported: count [lazy])")
    for (a, b), uses in sorted(pkg_edges.items()):
        nl = sum(1 for u in uses if u[2])
        print(f"  {a:28s} -> {b:28s} {len(uses):3d}" + (f"  [{nl} lazy]" if nl else ""))
    print()

    comps = sccs(pkg_graph)
    out["package_cycles"] = comps
    print(f"## package-level cycles: {len(comps)} strongly connected component(s)")
    two_cycles = sorted({tuple(sorted((a, b))) for a in pkg_graph for b in pkg_graph[a]
                         if a in pkg_graph.get(b, ())})
    for comp in comps:
        print(f"  SCC ({len(comp)}): {', '.join(comp)}")
    print(f"  direct two-way pairs ({len(two_cycles)}):")
    for a, b in two_cycles:
        ab = pkg_edges[(a, b)]
        ba = pkg_edges[(b, a)]
        print(f"    {a} <-> {b}")
        for uses, label in ((ab, f"{a}->{b}"), (ba, f"{b}->{a}")):
            for mod, line, lazy, tgt in uses[:4]:
                print(f"        {label}: {mod}:{line} imports {tgt}" + (" (lazy)" if lazy else ""))
            if len(uses) > 4:
                print(f"        ... {len(uses) - 4} more")
    print()

    mcomps = sccs(mod_graph)
    out["module_cycles"] = mcomps
    print(f"## module-level cycles: {len(mcomps)} strongly connected component(s)")
    for comp in mcomps:
        print(f"  SCC ({len(comp)} modules): {', '.join(comp)}")
        # one shortest cycle per member, deduplicated
        seen = set()
        for m in comp:
            for n in sorted(mod_graph[m]):
                if n in comp:
                    back = shortest_path(mod_graph, n, m)
                    if back:
                        cyc = tuple([m] + back[:-1])
                        k = min(range(len(cyc)), key=lambda i: cyc[i])
                        cyc = cyc[k:] + cyc[:k]
                        if cyc not in seen and len(cyc) <= 8:
                            seen.add(cyc)
        for cyc in sorted(seen, key=lambda c: (len(c), c))[:12]:
            print("     cycle: " + " -> ".join(cyc + (cyc[0],)))
        if len(seen) > 12:
            print(f"     ... {len(seen) - 12} more short cycles")
    print()

    out["private_cross"] = [list(x[:4]) + [list(x[4])] for x in private_cross]
    print(f"## private modules / names imported across packages: {len(private_cross)} imports")
    by_pair = defaultdict(list)
    for mod, line, lazy, tgt, names in private_cross:
        by_pair[(unit(mod), tgt)].append((mod, line, lazy, names))
    for (importer, tgt), uses in sorted(by_pair.items()):
        nnames = sum(len(u[3]) for u in uses)
        print(f"  {importer:26s} -> {tgt:34s} {len(uses):2d} import(s), {nnames:3d} name(s)")
        for mod, line, lazy, names in uses:
            shown = ", ".join(names[:6]) + (f", ... (+{len(names) - 6})" if len(names) > 6 else "")
            print(f"      {mod}:{line}{' (lazy)' if lazy else ''}: {shown}")
    print()

    out["upward"] = [list(x) for x in upward]
    print(f"## upward imports (layer order {', '.join(f'{k}={v}' for k, v in LAYER_NAMES.items())}):"
          f" {len(upward)}")
    for mod, line, lazy, tgt, la, lb in sorted(upward, key=lambda u: (u[4] - u[5], u[0])):
        print(f"  {mod}:{line}{' (lazy)' if lazy else ''} [{LAYER_NAMES[la]}] -> {tgt} "
              f"[{LAYER_NAMES[lb]}]")
    unplaced = sorted({unit(m) for m in files if layer(m) is None} - {"rvsim"})
    if unplaced:
        print(f"\n!! units without a layer: {unplaced}")
    if show_edges:
        print("\n## every module's rvsim imports")
        for mod, items in sorted(imports.items()):
            for target, line, lazy, names in items:
                print(f"  {mod}:{line}{' L' if lazy else ''} -> {target} {', '.join(names)}")
    return out


if __name__ == "__main__":
    if "--layers" in sys.argv:
        LAYERS, LAYER_NAMES = TABLES[sys.argv[sys.argv.index("--layers") + 1]]
    args = [a for a in sys.argv[1:] if not a.startswith("--") and a not in TABLES]
    root = Path(args[0] if args else "/work/main/src/rvsim").resolve()
    result = report(root, "--edges" in sys.argv)
    if "--json" in sys.argv:
        Path(sys.argv[sys.argv.index("--json") + 1]).write_text(json.dumps(result, indent=1))
