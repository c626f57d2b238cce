"""Keep numba's on-disk cache of the kernel consistent with the modules compiled into it.

numba invalidates a cached function when its own source file changes, not when a module it
imports does.  The kernel (``dynamics/_kernel.py``) compiles in the compile options
(``_jit``), the curve and gap functions of ``geometry._curve``, the laws, elements and index
constants of ``physics`` (``physics/_*.py``) and the dynamic engine's other private modules;
this guard stores a fingerprint of those files beside the
cache and deletes the kernel's cache files when the fingerprint changes.  A module that compiles
the kernel's functions into its own (the quasi-static solver) calls the guard with its own file:
its fingerprint covers the kernel's dependencies and that file.

The cache folder is the one numba itself picks, asked from numba's own cache locators in
numba's order (``numba.core.caching.CacheImpl``): ``NUMBA_CACHE_DIR`` when set, else
``__pycache__`` beside ``dynamics/_kernel.py`` when writable, else numba's user-wide cache folder.
"""

from __future__ import annotations

from pathlib import Path

from ._files import atomic_write_text
from ._fingerprint import fingerprint_files

__all__ = ["invalidate_stale_cache", "kernel_cache_folder", "DEPENDENCIES", "STAMP_NAME"]

_ROOT = Path(__file__).parent
_KERNEL = _ROOT / "dynamics" / "_kernel.py"
#: the packages whose private modules (``_*.py``) are compiled into the kernel
COMPILED_PACKAGES = ("physics", "dynamics")
#: every source file compiled into the kernel's cached machine code: the compile options, the
#: compiled curve functions and every private module of the compiled packages (the force
#: elements, the layout; a new element module is covered without being listed)
DEPENDENCIES = (_ROOT / "_jit.py", _ROOT / "geometry" / "_curve.py") + tuple(
    sorted(p for package in COMPILED_PACKAGES for p in (_ROOT / package).glob("_*.py")
           if p.name != "__init__.py"))
STAMP_NAME = "rvsim_kernel_dependencies.sha256"


def _probe() -> None:  # stands for a kernel function: the locators only read its line number
    pass


def kernel_cache_folder(module: str | Path = _KERNEL) -> Path | None:
    """The folder numba caches the functions of ``module`` (default: the kernel) in (None: no
    usable cache folder)."""
    from numba.core.caching import CacheImpl

    for locator_class in CacheImpl._locator_classes:
        locator = locator_class.from_function(_probe, str(module))
        if locator is not None:
            return Path(locator.get_cache_path())
    return None


def invalidate_stale_cache(module: str | Path = _KERNEL) -> None:
    """Delete cached code of ``module`` (default: the kernel) compiled against other versions
    of its dependencies (the kernel's, and ``module`` itself)."""
    module = Path(module).resolve()
    kernel = module == _KERNEL.resolve()
    paths = DEPENDENCIES if kernel else DEPENDENCIES + (module,)
    try:
        cache = kernel_cache_folder(module)
        if cache is None:
            return  # numba compiles in memory: nothing stale can be loaded
        stamp = cache / (STAMP_NAME if kernel else f"rvsim_{module.stem}_dependencies.sha256")
        current = fingerprint_files(list(paths))
        if stamp.exists() and stamp.read_text() == current:
            return
        for pattern in (f"{module.stem}.*.nbi", f"{module.stem}.*.nbc"):
            for stale in cache.glob(pattern):
                stale.unlink(missing_ok=True)
        cache.mkdir(parents=True, exist_ok=True)
        atomic_write_text(stamp, current)  # a concurrent reader never sees half a stamp
    except OSError:
        pass  # read-only cache folder: numba cannot write there either
