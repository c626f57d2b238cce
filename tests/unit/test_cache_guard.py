"""The numba cache guard works on the folder numba really uses (issue 8, item 7).

Each case runs in a fresh interpreter (numba reads NUMBA_CACHE_DIR at import), with the cache
redirected into a temporary folder: never the project's own cache.
"""

import json
import os
import subprocess
import sys
import textwrap


PROBE = textwrap.dedent("""
    import json, sys
    from numba.core import caching
    if sys.argv[1] == "no-in-tree":
        # an unwritable __pycache__ (as a read-only install has): numba falls back to its
        # user-wide folder
        def unwritable(self):
            raise OSError("read-only")
        caching.InTreeCacheLocator.ensure_cache_path = unwritable
    from rvsim._cache_guard import kernel_cache_folder
    from rvsim.dynamics._kernel import step_function
    step_function(0.5, 0.0, 1.0)          # compiles, or loads from the cache
    print(json.dumps({"numba": step_function._cache._cache_path,
                      "guard": str(kernel_cache_folder()),
                      "hits": sum(step_function.stats.cache_hits.values())}))
""")


def _run(tmp_path, mode="env"):
    env = dict(os.environ)
    env.pop("NUMBA_CACHE_DIR", None)
    if mode == "env":
        env["NUMBA_CACHE_DIR"] = str(tmp_path / "numba-cache")
    env["XDG_CACHE_HOME"] = str(tmp_path / "user-cache")
    out = subprocess.run([sys.executable, "-c", PROBE, mode], env=env, capture_output=True,
                         text=True, timeout=300, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_guard_checks_the_folder_numba_caches_in(tmp_path):
    # with NUMBA_CACHE_DIR: the first run of the test below
    seen = _run(tmp_path, "no-in-tree")
    assert seen["guard"] == seen["numba"]
    assert seen["numba"].startswith(str(tmp_path / "user-cache"))


def test_stale_kernel_is_removed_and_not_loaded(tmp_path):
    first = _run(tmp_path)
    # the guard checks the folder numba caches in, NUMBA_CACHE_DIR here
    assert first["guard"] == first["numba"]
    assert first["numba"].startswith(str(tmp_path / "numba-cache"))
    assert first["hits"] == 0                              # compiled and written
    assert _run(tmp_path)["hits"] == 1                     # same sources: loaded
    from pathlib import Path

    from rvsim._cache_guard import STAMP_NAME

    folder = Path(first["numba"])
    cached = sorted(p.name for p in folder.glob("_kernel.*"))
    assert cached                                          # index and data files
    # a dependency changed since the cache was written: the stamp no longer matches
    (folder / STAMP_NAME).write_text("fingerprint of older sources")
    again = _run(tmp_path)
    assert again["hits"] == 0                              # recompiled, not loaded
    assert (folder / STAMP_NAME).read_text() != "fingerprint of older sources"


def _compiled_in(module_file):
    """The module and the project modules it imports, recursively (the cache guard aside)."""
    import ast
    from pathlib import Path

    def local_imports(path):
        found = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.level > 0:
                base = path.parent
                for _ in range(node.level - 1):
                    base = base.parent
                target = base.joinpath(*node.module.split(".")).with_suffix(".py")
                if target.name != "_cache_guard.py":
                    found.add(target.resolve())
        return found

    seen, todo = set(), [Path(module_file).resolve()]
    while todo:                      # the module's imports, and theirs, recursively
        path = todo.pop()
        if path not in seen:
            seen.add(path)
            todo.extend(local_imports(path))
    return seen


def test_every_module_compiled_into_the_kernel_is_a_dependency():
    from pathlib import Path

    from rvsim.dynamics import _kernel
    from rvsim._cache_guard import DEPENDENCIES

    assert _compiled_in(_kernel.__file__) == {Path(p).resolve() for p in DEPENDENCIES}


def test_the_quasi_static_solver_is_guarded_with_all_it_compiles_in():
    from pathlib import Path

    from rvsim._cache_guard import DEPENDENCIES
    from rvsim.quasistatic import _solver

    solver = Path(_solver.__file__).resolve()
    assert "invalidate_stale_cache(__file__)" in solver.read_text()
    # the solver compiles in the physics layer only (issue 31 step 9: no longer the dynamic
    # engine's kernel); its guard covers the kernel's dependencies, a superset
    compiled = _compiled_in(solver)
    assert compiled <= {Path(p).resolve() for p in DEPENDENCIES} | {solver}
    physics = {Path(p).resolve() for p in DEPENDENCIES if Path(p).parent.name == "physics"}
    assert physics <= compiled
    assert not any(Path(p).parent.name == "dynamics" for p in compiled)
