"""Keep numba's on-disk cache of the kernel consistent with the modules compiled into it.

numba invalidates a cached function when its own source file changes, not when a module it
imports does.  The kernel compiles in the index constants of ``_layout`` and the curve
functions of ``geometry._curve``; this guard stores a fingerprint of those files beside the
cache and deletes the kernel's cache files when the fingerprint changes.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

__all__ = ["invalidate_stale_cache"]

_HERE = Path(__file__).parent
_DEPENDENCIES = (_HERE / "_layout.py", _HERE.parent / "geometry" / "_curve.py",
                 _HERE / "_kernel.py")


def _fingerprint() -> str:
    digest = hashlib.sha256()
    for path in _DEPENDENCIES:
        digest.update(path.read_bytes())
    return digest.hexdigest()


def invalidate_stale_cache() -> None:
    """Delete cached kernel code compiled against other versions of its dependencies."""
    cache = _HERE / "__pycache__"
    stamp = cache / "rvsim_kernel_dependencies.sha256"
    try:
        current = _fingerprint()
        if stamp.exists() and stamp.read_text() == current:
            return
        if cache.exists():
            for pattern in ("_kernel.*.nbi", "_kernel.*.nbc"):
                for stale in cache.glob(pattern):
                    stale.unlink(missing_ok=True)
        cache.mkdir(exist_ok=True)
        stamp.write_text(current)
    except OSError:
        pass  # read-only install: numba then compiles in memory, nothing stale can be loaded
