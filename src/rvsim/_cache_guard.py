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

The same modules say when numba really compiles (issue 34 item 3, issue 35 item 3): every
compiled module calls :func:`invalidate_stale_cache` at import, which also registers, once per
process, a listener of numba's ``"numba:compile"`` event (``numba.core.event``).  numba
broadcasts that event around a dispatcher's compilation only, never when it loads the function
from its disk cache (``Dispatcher.compile``), so a warm cache says nothing.  The first time an
rvsim function compiles, the listener logs :data:`COMPILING` on the ``rvsim.compile`` logger;
it adds up the seconds of the outermost compilations (:func:`compile_seconds`), which
:class:`RunClock` keeps out of a run's wall time (docs/decisions.md, issue 34/35).
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

from ._files import atomic_write_text
from ._fingerprint import fingerprint_files

__all__ = ["invalidate_stale_cache", "kernel_cache_folder", "DEPENDENCIES", "STAMP_NAME",
           "COMPILING", "LOGGER", "compile_seconds", "watch_compiles", "RunClock",
           "compiled_or_cached"]

_ROOT = Path(__file__).parent
_KERNEL = _ROOT / "dynamics" / "_kernel.py"
#: the packages whose private modules (``_*.py``) are compiled into the kernel
COMPILED_PACKAGES = ("physics", "dynamics")
#: every source file compiled into the kernel's cached machine code: the compile options, the
#: compiled curve and pose functions of geometry and every private module of the compiled
#: packages (the force elements, the layout; a new element module is covered without being
#: listed)
DEPENDENCIES = (_ROOT / "_jit.py", _ROOT / "geometry" / "_curve.py",
                _ROOT / "geometry" / "_pose.py") + tuple(
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
    watch_compiles()        # every compiled module comes here at import, before compiling
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


#: the line said once per process when an rvsim function starts compiling (first run after an
#: install or an update; measured cold on 2 cores: simulate 44 s quiet (issue 35), about 100 s
#: of CPU for the dynamic kernel and 150 s for the quasi-static solver on a shared machine,
#: 3-5 minutes of wall there; docs/benchmarks.md)
COMPILING = ("rvsim: compiling the model's kernels with numba (first run after an install or "
             "an update: one to a few minutes, cached afterwards)")
#: the logger of the compile notice: a WARNING, so that without any logging set up Python's
#: last-resort handler prints it on stderr; silence it with
#: ``logging.getLogger("rvsim.compile").setLevel(logging.ERROR)``
LOGGER = logging.getLogger("rvsim.compile")


class _CompileWatch:
    """State of the process's "numba:compile" listener: the compilations' nesting depth (a
    kernel compiles its callees inside its own event), whether the notice was said, and the
    seconds spent in outermost compilations of rvsim functions."""

    def __init__(self) -> None:
        self.depth = 0
        self.ours = False       # the outermost compilation under way is an rvsim function's
        self.started = 0.0
        self.seconds = 0.0
        self.said = False
        self.listener = None
        self.packages = ("rvsim.",)     # whose functions' compilations are ours

    def start(self, dispatcher) -> None:
        self.depth += 1
        if self.depth > 1:
            return
        module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
        self.ours = module.startswith(self.packages)
        if not self.ours:
            return
        if not self.said:
            self.said = True
            LOGGER.warning(COMPILING)
        self.started = time.perf_counter()

    def end(self) -> None:
        self.depth = max(self.depth - 1, 0)
        if self.depth == 0 and self.ours:
            self.seconds += time.perf_counter() - self.started
            self.ours = False


_WATCH = _CompileWatch()


def watch_compiles() -> None:
    """Register the process's compile listener with numba (once; numba's global listener
    registry, ``numba.core.event.register``)."""
    if _WATCH.listener is not None:
        return
    from numba.core import event

    class _Listener(event.Listener):
        def on_start(self, ev):
            _WATCH.start(ev.data.get("dispatcher") if isinstance(ev.data, dict) else None)

        def on_end(self, ev):
            _WATCH.end()

    _WATCH.listener = _Listener()
    event.register("numba:compile", _WATCH.listener)


def compile_seconds() -> float:
    """Seconds this process has spent compiling rvsim functions so far (0 with a warm cache)."""
    return _WATCH.seconds


class RunClock:
    """Wall time of a run without the compilations inside it: ``split()`` gives (run seconds,
    compile seconds) since the clock was made."""

    def __init__(self) -> None:
        self._start = time.perf_counter()
        self._compiled = _WATCH.seconds

    def split(self) -> tuple[float, float]:
        compiled = _WATCH.seconds - self._compiled
        return max(time.perf_counter() - self._start - compiled, 0.0), compiled


def compiled_or_cached(dispatcher) -> bool:
    """Whether calling ``dispatcher`` (a ``numba.njit`` function) needs no compilation: it is
    compiled in this process, or numba's cache index for its current source holds an entry
    (numba's ``IndexDataCacheFile._load_index`` gives {} for a missing or stale index).  A
    function without a disk cache counts as cached: every process compiles it anyway, so
    nothing is gained by waiting for another.  A numba whose private cache classes differ
    counts as cached too (the caller then behaves as before)."""
    try:
        if dispatcher.overloads:
            return True
        cache_file = getattr(dispatcher._cache, "_cache_file", None)
        if cache_file is None:      # NullCache: cache=False
            return True
        return bool(cache_file._load_index())
    except Exception:  # noqa: BLE001 - a private API that moved: no worse than before
        return True
