"""Designs of experiments: Taguchi orthogonal arrays (pyDOE3), full factorials, Latin
hypercube and Sobol samples (scipy.stats.qmc).

Level designs return 1-based level numbers, one column per factor; sampling designs return
points of the unit hypercube that :mod:`rvsim.doe.study` maps onto each factor's range.

pyDOE3 names its L36 'L36(3^23)' but it is Taguchi's L36(2^11 x 3^12): 11 two-level and 12
three-level columns.  :func:`assign_columns` picks, for each factor in turn, the next unused
column with that factor's number of levels, which for 4 two-level and 11 three-level factors is
the paper's L36(2^4 x 3^11) assignment.
"""

from __future__ import annotations

import functools
import itertools

import numpy as np

from ..errors import ParameterError

__all__ = ["ORTHOGONAL_ARRAYS", "orthogonal_array", "assign_columns", "is_strength2_balanced",
           "full_factorial", "latin_hypercube", "sobol"]


@functools.cache
def _catalogue() -> dict[str, str]:
    import pyDOE3

    names = pyDOE3.list_orthogonal_arrays()
    short: dict[str, str] = {}
    for name in names:
        key = name.split("(")[0]
        short.setdefault(key, name)  # first listed array of each size, e.g. L16 -> L16(2^15)
    return {**short, **{n: n for n in names}}


def __getattr__(name: str):
    """``ORTHOGONAL_ARRAYS``: the orthogonal arrays by short name (L4, L8, L9, L12, L16, L18,
    L27, L36, ...) and full name, read from pyDOE3 on first use (importing pyDOE3 imports
    scipy.stats, about a second that a study, tolerance or allocation process not using an
    array should not pay)."""
    if name == "ORTHOGONAL_ARRAYS":
        return _catalogue()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def orthogonal_array(name: str) -> np.ndarray:
    """The named orthogonal array with 1-based levels, shape (runs, columns)."""
    import pyDOE3

    arrays = _catalogue()
    if name not in arrays:
        raise ParameterError("design", f"unknown orthogonal array '{name}' (available: "
                             f"{', '.join(sorted(set(k.split('(')[0] for k in arrays)))})")
    array = np.asarray(pyDOE3.get_orthogonal_array(arrays[name]), dtype=int)
    return array - array.min() + 1


def is_strength2_balanced(array: np.ndarray) -> bool:
    """True when every pair of columns shows each level combination equally often."""
    array = np.asarray(array)
    for a, b in itertools.combinations(range(array.shape[1]), 2):
        pairs = array[:, a] * 1000 + array[:, b]
        _, counts = np.unique(pairs, return_counts=True)
        expected = len(np.unique(array[:, a])) * len(np.unique(array[:, b]))
        if len(counts) != expected or counts.min() != counts.max():
            return False
    return True


def assign_columns(array: np.ndarray, level_counts: list[int], name: str = "array"
                   ) -> np.ndarray:
    """Columns of ``array`` for factors with ``level_counts`` levels, in order of appearance."""
    used: set[int] = set()
    chosen = []
    levels_of = [len(np.unique(array[:, j])) for j in range(array.shape[1])]
    for i, n in enumerate(level_counts):
        for j, m in enumerate(levels_of):
            if m == n and j not in used:
                used.add(j)
                chosen.append(j)
                break
        else:
            available = sorted(set(levels_of))
            raise ParameterError("design", f"{name} has no free {n}-level column for factor "
                                 f"{i + 1} (its columns have {available} levels)")
    return array[:, chosen]


def full_factorial(level_counts: list[int]) -> np.ndarray:
    """All combinations of the factor levels, 1-based, shape (prod(levels), factors)."""
    grids = np.meshgrid(*[np.arange(1, n + 1) for n in level_counts], indexing="ij")
    return np.column_stack([g.ravel() for g in grids])


def latin_hypercube(samples: int, dimensions: int, seed: int = 0) -> np.ndarray:
    """Latin hypercube points in [0, 1)^dimensions (scipy.stats.qmc, optimised by random CD)."""
    from scipy.stats import qmc

    return qmc.LatinHypercube(d=dimensions, seed=seed).random(samples)


def sobol(samples: int, dimensions: int, seed: int = 0) -> np.ndarray:
    """Scrambled Sobol points in [0, 1)^dimensions; ``samples`` should be a power of two."""
    from scipy.stats import qmc

    if samples & (samples - 1):
        raise ParameterError("samples", f"Sobol designs need a power of two (got {samples})")
    return qmc.Sobol(d=dimensions, scramble=True, seed=seed).random(samples)
