"""How many positions an output revolution needs: :func:`minimum_positions`.

A TE curve sampled at N equally spaced positions per output revolution cannot hold an order
k >= N / 2: it folds onto order |k - m N| (aliasing), and at N = k / j it is sampled at the
same phase every time, so a whole order vanishes (the RV-40E's paper run 2 reported a
peak-to-peak TE of 5e-9 arcmin at 8, 40 and 80 positions against 0.247 at 360).  The highest
order an analysis needs is the pin count zp (the mesh: the load passes every pin once per
crank turn relative to the carrier, zp = zc + 1 times per output revolution), or a profile
form harmonic's order (a disc's profile wave of order k meets the pins k times per output
revolution) or any order a tolerance study draws.  docs/decisions.md (issue 30) gives the
measurement behind :data:`POSITIONS_PER_ORDER`.
"""

from __future__ import annotations

import math
import numbers

from ..errors import ParameterError

__all__ = ["POSITIONS_PER_ORDER", "MAX_POSITIONS", "highest_order", "minimum_positions",
           "check_positions"]

#: positions per period of the highest order, Nyquist's bound: more than 2 are needed (paper
#: run 2's peak-to-peak TE: 0.0039 arcmin at 80 positions, 0.258 at 81, 0.261 at 1440; between
#: the bound and 360 it is 0.206-0.261 as the samples fall on the peaks or not, a resolution
#: of the peak, not an alias: docs/decisions.md, issue 30)
POSITIONS_PER_ORDER = 2
#: most positions per output revolution the quasi-static commands take
MAX_POSITIONS = 100_000


def _ordinal(k: int) -> str:
    suffix = "th" if 10 <= k % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(k % 10, "th")
    return f"{k}{suffix}"


def highest_order(reducer, orders=()) -> tuple[int, str]:
    """(order, what it is) of the highest order of the output revolution the TE of
    ``reducer`` holds: its pin count, its parts' profile harmonics, the ``orders`` given."""
    best = (int(reducer.cycloid.pin_count), "pin")
    for row in reducer.parts.profile_harmonics:
        best = max(best, (int(row[1]), "profile form"))
    for order in orders:
        best = max(best, (int(order), "profile form"))
    return best


def minimum_positions(reducer, orders=()) -> int:
    """Fewest positions per output revolution that resolve the highest order of
    :func:`highest_order`: more than POSITIONS_PER_ORDER per period."""
    return POSITIONS_PER_ORDER * highest_order(reducer, orders)[0] + 1


def check_positions(reducer, positions, field: str, orders=(), *, order_field=None,
                    given: str = "") -> int:
    """``positions`` (per output revolution) if it resolves the reducer's highest order (and
    ``orders``); else a ParameterError naming ``field`` with the minimum and the reason, or
    ``order_field`` when no count up to MAX_POSITIONS could resolve ``orders``.  ``given``
    ends each reason: what the user typed, where ``positions`` was derived from it."""
    if isinstance(positions, bool) or not isinstance(positions, numbers.Real) \
            or not math.isfinite(positions):
        raise ParameterError(field, f"must be a whole number (got {positions!r}){given}")
    order, what = highest_order(reducer, orders)
    needed = minimum_positions(reducer, orders)
    if needed > MAX_POSITIONS:
        raise ParameterError(order_field or field, f"the {_ordinal(order)} ({what}) order "
                             f"needs at least {needed} positions per output revolution, more "
                             f"than the {MAX_POSITIONS} the analysis takes{given}")
    if positions < needed:
        raise ParameterError(field, f"must be at least {needed} for {reducer.name} (got "
                             f"{positions}): fewer than {needed} positions alias the "
                             f"{_ordinal(order)} ({what}) order of the output revolution{given}")
    return positions
