"""The pin's own compliance in series with its contact, shared by the dynamic kernel and the
quasi-static engine (docs/model.md sections 6 and 17).

``P[PIN_CB]`` holds the closed-form series compliances (switch A's tooth, switch B's Roark
pin).  With ``flexibility.model = fe`` and switch B, switch B's part is the finite-element pin
in its groove (:mod:`rvsim.fe.pin`) instead, read at the contact's own direction: the table
c_pin(psi), psi = 0, step, .. (``P[PIN_FE0 + k]``, step ``P[PIN_FE_STEP]``; 0: no table), psi
the angle between the contact normal and the pin's groove axis (the outward radial of the
pin circle).  Cubic (Catmull-Rom) interpolation, the table mirrored at psi = 0 (the groove is
symmetric) and held at its last value beyond its end.
"""

from __future__ import annotations

import math

import numba

from .._jit import NO_REFCOUNT
from .._cache_guard import invalidate_stale_cache

invalidate_stale_cache(__file__)

from ._layout import PIN_CB, PIN_FE0, PIN_FE_N, PIN_FE_STEP  # noqa: E402

__all__ = ["table_value", "pin_series_compliance"]


@numba.njit(**NO_REFCOUNT)
def table_value(table, step, cos_psi):
    """c(psi) from ``table`` at psi = 0, step, .. (Catmull-Rom, even in psi, held beyond the
    end) for the cosine ``cos_psi`` of the angle."""
    last = table.shape[0] - 1
    psi = math.acos(min(1.0, max(-1.0, cos_psi)))
    s = psi / step
    if s >= last:
        return table[last]
    i = int(s)
    t = s - i
    p0 = table[abs(i - 1)]
    p1 = table[i]
    p2 = table[i + 1]
    p3 = table[i + 2] if i + 2 <= last else 2.0 * table[last] - table[last - 1]
    return p1 + 0.5 * t * (p2 - p0 + t * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3
                                          + t * (3.0 * (p1 - p2) + p3 - p0)))


@numba.njit(**NO_REFCOUNT)
def pin_series_compliance(P, nx, ny, radial):
    """Series compliance [m/N] of a pin contact with normal (nx, ny) (disc axes, towards the
    pin) for a pin whose groove axis is at angle ``radial`` in the same axes."""
    step = P[PIN_FE_STEP]
    if step == 0.0:
        return P[PIN_CB]
    cos_psi = nx * math.cos(radial) + ny * math.sin(radial)
    return P[PIN_CB] + table_value(P[PIN_FE0:PIN_FE0 + PIN_FE_N], step, cos_psi)
