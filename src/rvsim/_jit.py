"""Compile options shared by the kernel's force elements (docs/decisions.md, "reference
counting")."""

from __future__ import annotations

import sys
from pathlib import Path

from ._cache_guard import kernel_cache_folder

try:        # Numba's private option that compiles a function without reference counting
    from numba.core.cpu import CPUTargetOptions

    _NRT_OPTION = hasattr(CPUTargetOptions, "_nrt")
except ImportError:        # pragma: no cover - a Numba without that module
    _NRT_OPTION = False

__all__ = ["CACHE", "NO_REFCOUNT", "REFCOUNT", "cache_usable"]

_PACKAGE = Path(__file__).resolve().parent
#: one module of each folder whose functions are compiled with ``cache``: numba's locators pick
#: a folder per source folder (its ``__pycache__`` when writable)
_COMPILED = (_PACKAGE / "dynamics" / "_kernel.py", _PACKAGE / "physics" / "_contact_law.py",
             _PACKAGE / "geometry" / "_curve.py", _PACKAGE / "quasistatic" / "_solver.py")


def cache_usable() -> bool:
    """Whether numba can write its cache for every compiled module: a locator of numba's finds
    a writable folder (``NUMBA_CACHE_DIR``, the module's ``__pycache__``, the user-wide cache).
    Where none does, a function decorated with ``cache=True`` raises RuntimeError ("no locator
    available") at import: an unwritable NUMBA_CACHE_DIR with the package installed read-only,
    or no home folder."""
    try:
        return all(kernel_cache_folder(module) is not None for module in _COMPILED)
    except Exception:        # a locator failing otherwise (a numba without CacheImpl's list)
        return False


#: whether the compiled functions are cached on disk (``cache`` of every ``numba.njit`` of the
#: package); without a writable cache folder they are compiled in memory, each process again
#: (docs/decisions.md, issue 30)
CACHE = cache_usable()
if not CACHE:
    print("rvsim: note: numba's cache folder cannot be written (NUMBA_CACHE_DIR, the package's "
          "__pycache__ and the home folder's cache are read-only or missing): compiling in "
          "memory, 30-45 s in each process; set NUMBA_CACHE_DIR to a writable folder",
          file=sys.stderr)

#: ``numba.njit`` options of an element that allocates nothing: cached, with numpy's error model
#: (a division by zero gives inf or nan instead of a check and an exception: the kernel raises
#: nothing and reports non-finite states by its status), and compiled without reference
#: counting where this Numba offers the option (issue 14: 6 % of a run on AMD EPYC, 21 % on
#: Intel Xeon, where the atomic counts cost more); a Numba that drops the option compiles the
#: same code with reference counting instead of failing.  Numba keys compiled code by argument
#: types only, so a function that set no options would keep those of whichever function
#: compiled it first: every compiled kernel function that is not inlined states NO_REFCOUNT
#: or REFCOUNT (tests/unit/test_jit_options.py)
NO_REFCOUNT = {"cache": CACHE, "error_model": "numpy",
               **({"_nrt": False} if _NRT_OPTION else {})}

#: ``numba.njit`` options of a kernel function that allocates (it may be called from a
#: NO_REFCOUNT one: it counts its own references)
REFCOUNT = {"cache": CACHE, "error_model": "numpy", **({"_nrt": True} if _NRT_OPTION else {})}
