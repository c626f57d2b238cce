"""Largest modules (lines) and longest functions (lines, parameters) of src/rvsim, with ast.

Usage: python scripts/refactor/sizes.py [ROOT] [N]
"""
import ast
import sys
from pathlib import Path

root = Path(sys.argv[1] if len(sys.argv) > 1 else "/work/main/src/rvsim")
n = int(sys.argv[2]) if len(sys.argv) > 2 else 25
mods, funcs = [], []
for p in sorted(root.rglob("*.py")):
    text = p.read_text()
    rel = p.relative_to(root.parent)
    mods.append((len(text.splitlines()), str(rel)))
    tree = ast.parse(text)
    stack = [(tree, "")]
    while stack:
        node, prefix = stack.pop()
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                a = child.args
                params = len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) \
                    + bool(a.vararg) + bool(a.kwarg)
                if a.args and a.args[0].arg in ("self", "cls"):
                    params -= 1
                start = min([child.lineno] + [d.lineno for d in child.decorator_list])
                jit = any("njit" in ast.unparse(d) or "jit" in ast.unparse(d)
                          for d in child.decorator_list)
                funcs.append((child.end_lineno - child.lineno + 1, params,
                              f"{rel}:{child.lineno} {prefix}{child.name}", jit))
                stack.append((child, f"{prefix}{child.name}."))
            elif isinstance(child, ast.ClassDef):
                stack.append((child, f"{prefix}{child.name}."))
print(f"## largest modules (of {len(mods)}; total {sum(m[0] for m in mods)} lines)")
for lines, name in sorted(mods, reverse=True)[:n]:
    print(f"  {lines:5d}  {name}")
print(f"\n## longest functions (of {len(funcs)}); lines, parameters, [njit]")
for lines, params, name, jit in sorted(funcs, reverse=True)[:n]:
    print(f"  {lines:4d} {params:3d}  {name}{'  [njit]' if jit else ''}")
print(f"\n## most parameters")
for lines, params, name, jit in sorted(funcs, key=lambda f: (-f[1], -f[0]))[:n]:
    print(f"  {params:3d} {lines:4d}  {name}{'  [njit]' if jit else ''}")
over = [f for f in funcs if f[0] > 80]
many = [f for f in funcs if f[1] > 10]
big = [m for m in mods if m[0] > 600]
print(f"\n## over the issue's limits: {len(big)} modules > 600 lines, {len(over)} functions > 80 "
      f"lines, {len(many)} functions > 10 parameters ({sum(1 for f in many if f[3])} of them njit)")
