"""One fingerprint of the source code that determines a run's numbers.

The study store keys every run by its parameters and this fingerprint, so results stored by an
older model are never mistaken for current ones; no version string has to be bumped by hand.
The numba cache guard can use :func:`fingerprint_files` for the files compiled into the kernel.
"""

from __future__ import annotations

import functools
import hashlib
from pathlib import Path

__all__ = ["MODEL_PACKAGES", "model_source_files", "fingerprint_files", "model_fingerprint"]

_ROOT = Path(__file__).parent

#: sub-packages and modules of rvsim whose source determines a stored run's numbers: the
#: dynamic and quasi-static engines and what they call, the catalogue quantities of a
#: quasi-static run, a study's and a tolerance sample's evaluation
MODEL_PACKAGES = ("_jit.py", "physics", "dynamics", "fe", "geometry", "parameters", "quasistatic",
                  "units.py", "bearings.py", "friction.py", "analysis/catalogue.py", "doe/engines.py",
                  "tolerance/engine.py")


def model_source_files(root: Path = _ROOT) -> list[Path]:
    """The .py files of :data:`MODEL_PACKAGES` under ``root``, in a fixed order."""
    files: list[Path] = []
    for name in MODEL_PACKAGES:
        path = root / name
        files += sorted(path.rglob("*.py")) if path.is_dir() else [path] if path.exists() else []
    return [f for f in files if "__pycache__" not in f.parts]


def fingerprint_files(files: list[Path], root: Path = _ROOT) -> str:
    """SHA-256 over the relative names and contents of ``files``."""
    digest = hashlib.sha256()
    for path in files:
        name = path.relative_to(root).as_posix() if path.is_relative_to(root) else path.name
        content = path.read_bytes()
        digest.update(f"{name}\0{len(content)}\0".encode())
        digest.update(content)
    return digest.hexdigest()


@functools.lru_cache(maxsize=1)
def model_fingerprint() -> str:
    """Fingerprint of the installed model sources (computed once per process)."""
    return fingerprint_files(model_source_files())
