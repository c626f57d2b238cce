"""On-disk cache of condensed finite-element matrices, keyed by a hash of the geometry.

Location: ``$RVSIM_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/rvsim``, else ``~/.cache/rvsim``;
the finite-element matrices go to its ``fe/`` folder, one ``.npz`` file per geometry.  Deleting
the folder only costs the recomputation.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import os
import sys
import time
import zipfile
from pathlib import Path
from typing import Callable

import numpy as np

__all__ = ["CondensedTable", "cache_dir", "cached", "condensed_table", "geometry_key", "load",
           "store"]


def cache_dir() -> Path:
    """The folder of the finite-element cache (not created)."""
    root = os.environ.get("RVSIM_CACHE_DIR")
    if root:
        return Path(root) / "fe"
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg) if xdg else Path.home() / ".cache"
    return base / "rvsim" / "fe"


def geometry_key(kind: str, values: dict) -> str:
    """SHA-256 (first 24 hex digits) of ``kind`` and the geometry ``values`` (floats rounded to
    1e-12 relative so that round-off does not split the cache)."""
    def norm(v):
        if isinstance(v, float):
            return float(f"{v:.12g}")
        if isinstance(v, (list, tuple)):
            return [norm(x) for x in v]
        return v
    text = json.dumps({"kind": kind, **{k: norm(v) for k, v in sorted(values.items())}},
                      sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


#: files already read by this process: path -> (modification time, size, inode, arrays).  A
#: 360-position curve with the FE bodies spent 1.5 ms reading its three tables (a tenth of
#: the rigid-body curve); the file's state is checked at each load, so a file removed or
#: rewritten is read again.  The arrays are shared between the loads, hence read-only
_LOADED: dict = {}
#: files kept in memory (the oldest is dropped beyond)
LOADED_MAX = 16


#: the notes this process has given (each once: a run stores several bodies)
_NOTED: set = set()


def note(text: str) -> None:
    """One line on standard error about the cache (a damaged entry, an unwritable folder),
    once per process."""
    if text in _NOTED:
        return
    _NOTED.add(text)
    print(f"rvsim: note: finite-element cache: {text}", file=sys.stderr)


def load(key: str) -> dict | None:
    """Arrays stored under ``key``, or None (missing or unreadable: recomputed).  Read-only:
    repeated loads of an unchanged file share them.  A damaged file (cut short by a full disk
    or a killed writer of another tool: zipfile's BadZipFile, a short member) is removed with
    a note, so that it is rebuilt once instead of failing every later run."""
    path = cache_dir() / f"{key}.npz"
    try:
        st = os.stat(path)
    except OSError:
        return None                                  # not cached
    stamp = (st.st_mtime_ns, st.st_size, st.st_ino)
    kept = _LOADED.get(path)
    if kept is not None and kept[0] == stamp:
        return dict(kept[1])
    try:
        with np.load(path) as data:
            arrays = {name: data[name] for name in data.files}
    except PermissionError:
        return None                                  # not ours to read or remove
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError) as exc:
        try:
            path.unlink()
            what = "removed, rebuilt now"
        except OSError:
            what = "cannot be removed, computed without it"
        note(f"damaged entry {path} ({type(exc).__name__}) {what}")
        return None
    for value in arrays.values():
        value.flags.writeable = False
    _LOADED.pop(path, None)
    _LOADED[path] = (stamp, arrays)
    while len(_LOADED) > LOADED_MAX:
        del _LOADED[next(iter(_LOADED))]
    return dict(arrays)


def store(key: str, arrays: dict) -> Path | None:
    """Write ``arrays`` under ``key`` atomically; None, with a note, if the cache folder is not
    writable (the run goes on uncached)."""
    folder = cache_dir()
    tmp = folder / f".{key}.{os.getpid()}.npz"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        np.savez(tmp, **arrays)
        path = folder / f"{key}.npz"
        os.replace(tmp, path)
        return path
    except OSError as exc:
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)
        note(f"cannot write {folder} ({exc.strerror or exc}): running uncached "
             "(set RVSIM_CACHE_DIR to a writable folder)")
        return None


def cached(kind: str, values: dict, compute: Callable[[], dict]) -> tuple[dict, float, bool]:
    """The arrays of ``kind`` for geometry ``values``: from the cache, or ``compute()``d and
    stored.  Returns (arrays, seconds spent computing (0 from the cache), from the cache)."""
    key = geometry_key(kind, values)
    stored = load(key)
    if stored is not None:
        return stored, 0.0, True
    from ._extra import require

    require()           # before anything is meshed: one line without the extra
    start = time.perf_counter()
    arrays = compute()
    seconds = time.perf_counter() - start
    store(key, arrays)
    return arrays, seconds, False


@dataclasses.dataclass(frozen=True)
class CondensedTable:
    """A body's condensed compliance with the size of its mesh."""

    compliance: np.ndarray
    n_dofs: int
    n_elements: int
    seconds: float              # meshing + condensation time (0 when loaded from the cache)
    cached: bool


def condensed_table(kind: str, values: dict,
                    compute: Callable[[], tuple[np.ndarray, int, int]]) -> CondensedTable:
    """:func:`cached` for a ``compute()`` returning (compliance, dofs, elements)."""
    def arrays():
        c, n_dofs, n_elements = compute()
        return {"compliance": c, "n_dofs": np.array(n_dofs),
                "n_elements": np.array(n_elements)}

    a, seconds, from_cache = cached(kind, values, arrays)
    return CondensedTable(a["compliance"], int(a["n_dofs"]), int(a["n_elements"]), seconds,
                          from_cache)
