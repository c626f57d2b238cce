"""Unit conversion at the edges of rvsim.

Everything inside rvsim is SI (m, rad, s, N, Pa, kg).  Users read and write the units an
RV-reducer engineer uses (mm, deg, arcmin, deg/s, GPa); this module is the only place that knows
the factors.
"""

from __future__ import annotations

import math

__all__ = ["TO_SI", "to_si", "from_si", "ARCMIN", "MM", "DEG"]

MM = 1e-3
DEG = math.pi / 180.0
ARCMIN = math.pi / (180.0 * 60.0)

#: factor that turns a value in the named unit into SI
TO_SI: dict[str, float] = {
    "m": 1.0,
    "mm": MM,
    "um": 1e-6,
    "rad": 1.0,
    "deg": DEG,
    "arcmin": ARCMIN,
    "rad/s": 1.0,
    "mm/s": MM,
    "mm^2/s": MM * MM,
    "deg/s": DEG,
    "rpm": 2.0 * math.pi / 60.0,
    "s": 1.0,
    "h": 3600.0,
    "Hz": 1.0,
    "N": 1.0,
    "N*m": 1.0,
    "Pa": 1.0,
    "GPa": 1e9,
    "degC": 1.0,     # temperatures stay in degC (an SI derived unit; an offset, not a factor)
    "kg": 1.0,
    "kg/m^3": 1.0,
    "kg*m^2": 1.0,
    "N/m": 1.0,
    "-": 1.0,
    "count": 1.0,
    "flag": 1.0,
    "choice": 1.0,
}


def to_si(value: float, unit: str) -> float:
    """Convert ``value`` given in ``unit`` to SI."""
    return value * TO_SI[unit]


def from_si(value: float, unit: str) -> float:
    """Convert an SI ``value`` to ``unit``."""
    return value / TO_SI[unit]
