"""The rigid parts' pose, compiled (numba) and callable from Python: one definition of a
crank's bore centre and of a disc's centre on its eccentric (issue 31 step 10).

The force elements (:mod:`rvsim.physics._fe_carrier`, the quasi-static solver's kinematic
pose), the dynamic model's starting pose (:func:`rvsim.dynamics.model.build_model`) and the
geometry checks (:func:`rvsim.geometry.cycloid.nominal_disc_pose`, the assembly check) call
these; the geometry layer holds them because the geometry checks sit below the physics layer
(tests/unit/test_import_layers.py).  Inlined into the compiled callers (the same arithmetic,
in the same order, as the copies they replace).
"""

from __future__ import annotations

import math

import numba

from .._cache_guard import invalidate_stale_cache
from .._jit import CACHE

# the compile options come from rvsim._jit: clear this module's cached code when they change
invalidate_stale_cache(__file__)
__all__ = ["bore_centre", "disc_centre", "bore_centre_py", "disc_centre_py"]


@numba.njit(cache=CACHE, inline="always")
def bore_centre(radius, tangential, c, s):
    """Centre (x, y) of a crank's carrier / flange bore: ``radius`` (the centre distance plus
    the bore's radial offset) along the crank's direction (c, s) = (cos, sin) of its angle in
    the frame wanted, ``tangential`` (the bore's tangential offset) across it [m]."""
    return radius * c - tangential * s, radius * s + tangential * c


@numba.njit(cache=CACHE, inline="always")
def disc_centre(a, beta, disc):
    """Centre (x, y) of disc ``disc`` relative to its crank's axis: the eccentricity ``a``
    along the eccentric angle ``beta`` + disc pi (the two discs' eccentrics half a turn
    apart) [m]."""
    angle = beta + disc * math.pi
    return a * math.cos(angle), a * math.sin(angle)


#: the same functions as plain Python, for the Python callers (the model's starting pose, the
#: geometry checks): one source, no compile for a call from Python (the interpreter's
#: arithmetic is the compiled code's: no fused or reordered operations)
bore_centre_py = getattr(bore_centre, "py_func", bore_centre)
disc_centre_py = getattr(disc_centre, "py_func", disc_centre)
