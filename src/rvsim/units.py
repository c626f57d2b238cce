"""Unit conversion at the edges of rvsim.

Everything inside rvsim is SI (m, rad, s, N, Pa, kg).  Users read and write the units an
RV-reducer engineer uses (mm, deg, arcmin, deg/s, GPa); this module is the only place that knows
the factors.
"""

from __future__ import annotations

import math
import re
from decimal import Decimal

__all__ = ["TO_SI", "to_si", "from_si", "ARCMIN", "MM", "DEG", "DIMENSION", "ALIASES",
           "si_from_text"]

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
    # units a user may type with a value (--set NAME=VALUE), besides the listed ones
    "cm": 1e-2,
    "nm": 1e-9,
    "arcsec": ARCMIN / 60.0,
    "ms": 1e-3,
    "min": 60.0,
    "MPa": 1e6,
    "m/s": 1.0,
    "m^2/s": 1.0,
    "g/cm^3": 1e3,
}

#: what each unit measures: a value typed with a unit must measure what its parameter does
DIMENSION: dict[str, str] = {
    "m": "length", "cm": "length", "mm": "length", "um": "length", "nm": "length",
    "rad": "angle", "deg": "angle", "arcmin": "angle", "arcsec": "angle",
    "rad/s": "angular speed", "deg/s": "angular speed", "rpm": "angular speed",
    "m/s": "speed", "mm/s": "speed",
    "m^2/s": "kinematic viscosity", "mm^2/s": "kinematic viscosity",
    "s": "time", "ms": "time", "min": "time", "h": "time",
    "Hz": "frequency",
    "N": "force",
    "N*m": "torque",
    "Pa": "pressure", "MPa": "pressure", "GPa": "pressure",
    "degC": "temperature",
    "kg": "mass",
    "kg/m^3": "density", "g/cm^3": "density",
    "kg*m^2": "moment of inertia",
    "N/m": "stiffness",
    # plain numbers: no unit is typed with them
    "-": "", "count": "", "flag": "", "choice": "",
}

#: other spellings of the units above
ALIASES: dict[str, str] = {
    "\u00b5m": "um", "\u03bcm": "um", "micron": "um",
    "\u00b0": "deg", "\u00b0C": "degC",
    "rev/min": "rpm", "r/min": "rpm", "min^-1": "rpm",
    "Nm": "N*m", "N.m": "N*m", "N m": "N*m",
    "N/mm^2": "MPa", "cSt": "mm^2/s", "sec": "s",
}

# a number (as Python's float reads it, without digit groups) and the text after it
# (the unit starts with a letter, micro or degree sign: "1_0mm" is no number with a unit)
_QUANTITY = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*"
                       r"((?:[^\W\d_]|\u00b0).*?)\s*")


def to_si(value: float, unit: str) -> float:
    """Convert ``value`` given in ``unit`` to SI."""
    return value * TO_SI[unit]


def from_si(value: float, unit: str) -> float:
    """Convert an SI ``value`` to ``unit``."""
    return value / TO_SI[unit]


def si_from_text(text: str, unit: str) -> float | None:
    """The SI value of ``text``, a number followed by a unit that measures what ``unit``
    does ("1000rpm" or "1000 rpm" for a deg/s parameter, "5um" for mm); None when ``text``
    is no number with a unit.  A unit that is unknown or measures something else raises
    ValueError with the reason (naming ``unit`` and the others the parameter takes)."""
    match = _QUANTITY.fullmatch(text)
    if match is None:
        return None
    number, typed = match.groups()
    given = ALIASES.get(typed, typed)
    wanted = DIMENSION[unit]
    if not wanted:
        raise ValueError(f"'{text}': takes a plain number, without a unit")
    takes = sorted((u for u, d in DIMENSION.items() if d == wanted and u != unit),
                   key=TO_SI.get)
    expected = f"in {unit}" + (f" (or {', '.join(takes)})" if takes else "")
    if given not in DIMENSION:
        raise ValueError(f"'{text}': unknown unit '{typed}'; give {_a(wanted)} {expected}")
    if DIMENSION[given] != wanted:
        raise ValueError(f"'{text}' is {_a(DIMENSION[given] or 'plain number')}, not "
                         f"{_a(wanted)}: give it {expected}")
    if given == unit:                  # as the plain number: "5mm" is "5" to the last bit
        return float(number) * TO_SI[unit]
    # another unit: the decimal product, correctly rounded ("5um" is 5e-6 m, where
    # 5 * 1e-6 is one unit in the last place below and lists as 0.004999999999999999 mm)
    try:
        return float(Decimal(number) * Decimal(repr(TO_SI[given])))
    except ArithmeticError:            # "1e9999999um": beyond the decimal context's exponents
        return math.inf                # (the caller refuses it as no finite number)


def _a(noun: str) -> str:
    return f"{'an' if noun[0] in 'aeiou' else 'a'} {noun}"
