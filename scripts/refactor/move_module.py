"""Move (and rename) modules of rvsim and rewrite every import of them (issue 31).

    python scripts/refactor/move_module.py [--root TREE] [--dry-run] [--no-git] [--docs] \
        rvsim.dynamics._layout=rvsim.physics._layout rvsim.dynamics._jit=rvsim._jit ...

All moves of one call are applied together (a mapping old -> new dotted name), so modules that
import each other move in one step.  For every ``*.py`` under src/, tests/, benchmarks/,
scripts/ and examples/:

* ``from OLD import a, b``  /  ``from ..x.old import a``  (absolute or relative) -> the new
  module, written in the file's own style (relative inside src/rvsim, absolute elsewhere), with
  continuation lines re-aligned to the moved parenthesis; comments (``# noqa``) stay;
* ``from PKG import old [as x], other`` -> ``from NEWPKG import new as old`` (the name the
  file uses is kept), split off when the other names stay;
* ``import OLD [as x]`` -> ``import NEW [as x]``;
* a moved module's own relative imports are re-resolved from its new package;
* the dotted text ``rvsim.<old>`` (monkeypatch strings, docstrings) -> ``rvsim.<new>``, and
  with ``--docs`` also in docs/*.md and README.md.

Files are moved with ``git mv`` (``--no-git``: plain rename); a new package gets an
``__init__.py`` with a one-line docstring.  What it cannot rewrite it lists at the end
(short dotted mentions such as ``dynamics._layout`` in prose, lazy_loader tables, paths
built from ``Path(__file__)``): review those by hand.
Returns non-zero if a rewritten file no longer parses.
"""
from __future__ import annotations

import argparse
import ast
import re
import subprocess
import sys
from pathlib import Path

PY_DIRS = ("src", "tests", "benchmarks", "scripts", "examples")


def module_of(path: Path, src: Path) -> tuple[str, bool]:
    rel = path.relative_to(src).with_suffix("")
    parts = list(rel.parts)
    is_pkg = parts[-1] == "__init__"
    if is_pkg:
        parts.pop()
    return ".".join(parts), is_pkg


def path_of(module: str, src: Path) -> Path:
    return src.joinpath(*module.split(".")).with_suffix(".py")


def resolve(node: ast.ImportFrom, package: str) -> str:
    if not node.level:
        return node.module or ""
    base = package.split(".")
    base = base[:len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def relative(target: str, package: str) -> str:
    """``target`` written relative to ``package`` (both dotted, in the same top package)."""
    t, p = target.split("."), package.split(".")
    common = 0
    while common < min(len(t), len(p)) and t[common] == p[common]:
        common += 1
    if common == 0:
        return target
    level = len(p) - common + 1
    return "." * level + ".".join(t[common:])


class Rewriter:
    def __init__(self, root: Path, mapping: dict[str, str]):
        self.root = root
        self.src = root / "src"
        self.mapping = mapping
        self.modules = {module_of(p, self.src)[0] for p in self.src.rglob("*.py")}
        self.modules |= set(mapping.values())
        self.review: list[str] = []

    def new_name(self, module: str) -> str | None:
        return self.mapping.get(module)

    # -- one file ------------------------------------------------------------------------
    def rewrite(self, path: Path, old_module: str | None, new_module: str | None) -> str | None:
        """New text of ``path`` (None: unchanged).  ``old_module``/``new_module``: the file's
        dotted name before and after the move (None outside src/)."""
        text = path.read_text(encoding="utf-8")
        tree = ast.parse(text, str(path))
        lines = text.splitlines(keepends=True)
        in_src = old_module is not None
        is_pkg = path.name == "__init__.py"
        old_pkg = (old_module if is_pkg else old_module.rpartition(".")[0]) if in_src else None
        new_pkg = (new_module if is_pkg else new_module.rpartition(".")[0]) if in_src else None
        moved_self = in_src and old_module != new_module
        edits: list[tuple[int, int, list[str]]] = []     # (first line, last line, new lines)

        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                rep = self._from(node, lines, old_pkg, new_pkg, moved_self)
            elif isinstance(node, ast.Import):
                rep = self._import(node, lines)
            else:
                continue
            if rep is not None:
                edits.append((node.lineno, node.end_lineno, rep))
        for first, last, rep in sorted(edits, reverse=True):
            lines[first - 1:last] = rep
        new_text = "".join(lines)
        # dotted text: rvsim.old.mod -> rvsim.new.mod (strings, docstrings, comments)
        for old, new in sorted(self.mapping.items(), key=lambda kv: -len(kv[0])):
            new_text = re.sub(rf"(?<![\w.]){re.escape(old)}(?![\w])", new, new_text)
        for old in self.mapping:
            short = ".".join(old.split(".")[1:])       # e.g. dynamics._layout
            for m in re.finditer(rf"(?<![\w.]){re.escape(short)}(?![\w])", new_text):
                line = new_text.count("\n", 0, m.start()) + 1
                self.review.append(f"{path.relative_to(self.root)}:{line}: mentions {short}")
        return new_text if new_text != text else None

    def _segment(self, node, lines) -> tuple[str, str]:
        """The statement's text and the indentation of its first line."""
        first = lines[node.lineno - 1]
        indent = first[:len(first) - len(first.lstrip())]
        return "".join(lines[node.lineno - 1:node.end_lineno]), indent

    def _from(self, node: ast.ImportFrom, lines, old_pkg, new_pkg, moved_self):
        in_src = old_pkg is not None
        target = resolve(node, old_pkg) if (node.level and in_src) else (node.module or "")
        if not (target == "rvsim" or target.startswith("rvsim.")):
            return None
        use_relative = node.level > 0

        def spell(module: str) -> str:
            if use_relative and in_src:
                return relative(module, new_pkg)
            return module

        names = [(a.name, a.asname) for a in node.names]
        moved_names = [(n, a) for n, a in names if f"{target}.{n}" in self.mapping]
        new_target = self.mapping.get(target, target)
        text, indent = self._segment(node, lines)
        if not moved_names:
            if new_target == target and not moved_self:
                return None
            new_spelled = spell(new_target)
            if new_spelled == (("." * node.level) + (node.module or "")) and node.level:
                return None
            if not node.level and new_target == target:
                return None
            return self._respell(text, node, new_spelled)
        # ``from PKG import mod as x``: modules moved out of PKG
        out, rest = [], [(n, a) for n, a in names if (n, a) not in moved_names]
        groups: dict[str, list[str]] = {}
        for n, a in moved_names:
            new_full = self.mapping[f"{target}.{n}"]
            pkg, _, leaf = new_full.rpartition(".")
            local = a or n
            groups.setdefault(pkg, []).append(leaf if leaf == local else f"{leaf} as {local}")
        comment = self._comment(text)
        if rest:
            kept = ", ".join(n if a is None else f"{n} as {a}" for n, a in rest)
            out.append(f"{indent}from {spell(new_target)} import {kept}{comment}\n")
            comment = ""
        for pkg, items in groups.items():
            out.append(f"{indent}from {spell(pkg)} import {', '.join(items)}{comment}\n")
        return out

    @staticmethod
    def _comment(text: str) -> str:
        first = text.splitlines()[0]
        m = re.search(r"\s+#.*$", first)
        return m.group(0) if m else ""

    @staticmethod
    def _respell(text: str, node, new_module: str) -> list[str]:
        m = re.match(r"(\s*from\s+)(\S+)(\s+import\s+)", text)
        assert m, text
        old_col = len(m.group(1)) + len(m.group(2))
        new_text = m.group(1) + new_module + text[m.end(2):]
        delta = len(new_module) - len(m.group(2))
        out = new_text.splitlines(keepends=True)
        paren = new_text.find("(")
        if delta and paren >= 0 and len(out) > 1:
            old_paren = paren - delta            # column of "(" before, within the first line
            for i in range(1, len(out)):
                line = out[i]
                lead = len(line) - len(line.lstrip(" "))
                if lead == old_paren + 1:        # aligned with the opening parenthesis
                    out[i] = " " * max(0, lead + delta) + line.lstrip(" ")
        del old_col
        return out

    def _import(self, node: ast.Import, lines):
        changed = False
        parts = []
        for a in node.names:
            name = a.name
            for old, new in self.mapping.items():
                if name == old or name.startswith(old + "."):
                    name = new + name[len(old):]
                    changed = True
            parts.append(name if a.asname is None else f"{name} as {a.asname}")
        if not changed:
            return None
        text, indent = self._segment(node, lines)
        return [f"{indent}import {', '.join(parts)}{self._comment(text)}\n"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("moves", nargs="+", help="old.dotted=new.dotted")
    ap.add_argument("--root", default=".")
    ap.add_argument("--dry-run", action="store_true")
    ap.add_argument("--no-git", action="store_true")
    ap.add_argument("--docs", action="store_true", help="also rewrite rvsim.<old> in docs/*.md")
    args = ap.parse_args(argv)
    root = Path(args.root).resolve()
    src = root / "src"
    mapping = dict(m.split("=", 1) for m in args.moves)
    for old, new in mapping.items():
        if not path_of(old, src).exists():
            sys.exit(f"no module {old} ({path_of(old, src)})")
        if path_of(new, src).exists():
            sys.exit(f"{new} exists already")
    rw = Rewriter(root, mapping)
    changed: dict[Path, str] = {}
    renames: dict[Path, Path] = {}
    for d in PY_DIRS:
        for path in sorted((root / d).rglob("*.py")) if (root / d).exists() else []:
            if "__pycache__" in path.parts:
                continue
            if d == "src":
                old_mod, _ = module_of(path, src)
                new_mod = mapping.get(old_mod, old_mod)
            else:
                old_mod = new_mod = None
            text = rw.rewrite(path, old_mod, new_mod)
            if text is not None:
                changed[path] = text
            if d == "src" and old_mod in mapping:
                renames[path] = path_of(mapping[old_mod], src)
    if args.docs:
        for path in sorted((root / "docs").rglob("*.md")) + [root / "README.md"]:
            text = path.read_text(encoding="utf-8")
            new = text
            for old, nw in sorted(mapping.items(), key=lambda kv: -len(kv[0])):
                new = re.sub(rf"(?<![\w.]){re.escape(old)}(?![\w])", nw, new)
            if new != text:
                changed[path] = new
    # lazy_loader tables and file paths that name the moved modules
    for old in mapping:
        pkg_init = path_of(old.rpartition(".")[0], src).with_suffix("") / "__init__.py"
        leaf = old.rpartition(".")[2]
        if pkg_init.exists() and re.search(rf"[\"']{re.escape(leaf)}[\"']", pkg_init.read_text()):
            rw.review.append(f"{pkg_init.relative_to(root)}: names '{leaf}' (lazy_loader?)")
        for path in src.rglob("*.py"):
            t = path.read_text()
            if re.search(rf"[\"']{re.escape(leaf)}\.py[\"']", t):
                rw.review.append(f"{path.relative_to(root)}: builds the path '{leaf}.py'")
    for old in mapping:
        t = path_of(old, src).read_text()
        for i, line in enumerate(t.splitlines(), 1):
            if "__file__" in line and "invalidate_stale_cache(__file__)" not in line:
                rw.review.append(f"{path_of(old, src).relative_to(root)}:{i}: uses __file__ "
                                 f"(paths relative to the old folder?): {line.strip()}")
    print(f"{len(renames)} module(s) moved, {len(changed)} file(s) rewritten")
    for p in sorted(changed):
        print(f"  rewrite {p.relative_to(root)}")
    if args.dry_run:
        for r in sorted(set(rw.review)):
            print("  review", r)
        return 0
    for path, text in changed.items():
        path.write_text(text, encoding="utf-8")
    for old, new in renames.items():
        new.parent.mkdir(parents=True, exist_ok=True)
        init = new.parent / "__init__.py"
        if not init.exists():
            init.write_text(f'"""{new.parent.name}: see docs/architecture.md."""\n')
            if not args.no_git:
                subprocess.run(["git", "add", str(init)], cwd=root, check=True)
        if args.no_git:
            old.rename(new)
        else:
            subprocess.run(["git", "mv", str(old), str(new)], cwd=root, check=True)
        print(f"  moved {old.relative_to(root)} -> {new.relative_to(root)}")
    bad = []
    for path in [renames.get(p, p) for p in changed]:
        if path.suffix == ".py":
            try:
                ast.parse(path.read_text(encoding="utf-8"))
            except SyntaxError as exc:
                bad.append(f"{path}: {exc}")
    for r in sorted(set(rw.review)):
        print("  review", r)
    for b in bad:
        print("  SYNTAX ERROR", b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
