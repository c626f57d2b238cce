"""The paper's analytical error model of the cycloid stage, Eqs. (2)-(17).

Every term of Eq. (11) has the form ``coefficient * 2 / (a * zc) * error`` (reference README;
Table 1).  The missing Eqs. (2), (4) and (8) follow from Table 1's coefficients:

==========  ===================================  ============================  ==========
row/symbol  error                                coefficient                   equation
==========  ===================================  ============================  ==========
delta_r_p   pin circle radius error              sqrt(1 - K1^2)                (2)
delta_r_rp  pin radius error                     -1                            (3)
delta_t_sigma  circular position error of holes  K1                            (4)
delta_j     pin / pin-hole clearance             1/2                           (5)
Delta_r_rp  equidistant modification             1                             (6)
Delta_r_p   radial-moving modification           -sqrt(1 - K1^2)               (6)
Delta_F_t1  radial runout of the disc            1/4                           (7)
Delta_F_P   cumulative pitch error of the disc   -K1/2                         (8)
delta_a     eccentricity error                   -k_n * a * zc                 (9), (10)
==========  ===================================  ============================  ==========

The sensitivity index of Eq. (15) is each coefficient divided by the reference coefficient
(row 1, the pin-circle radius error).  Row 9 is computed from k_n as Eq. (10) defines it, with
the modification amounts of rows 5 and 6 entered as Eq. (6) writes them; it does not reproduce
the printed 0.00005 (docs/analytical.md explains).
"""

from __future__ import annotations

import dataclasses
import math

from .parameters import Reducer
from .units import ARCMIN, MM

__all__ = ["ErrorTerm", "SensitivityTable", "PAPER_TABLE1_ERRORS", "TABLE1_PARAMETERS",
           "reducer_errors", "sensitivity_table", "k_n"]

#: error values of the paper's Table 1 [m], by symbol
PAPER_TABLE1_ERRORS: dict[str, float] = {
    "delta_r_p": 0.025 * MM,
    "delta_r_rp": 0.015 * MM,
    "delta_t_sigma": 0.01 * MM,
    "delta_j": 0.002 * MM,
    "Delta_r_rp": 0.016 * MM,
    "Delta_r_p": 0.026 * MM,
    "Delta_F_t1": 0.014 * MM,
    "Delta_F_P": 0.015 * MM,
    "delta_a": 0.005 * MM,
}

#: the reducer parameter behind a Table 1 symbol (the other three rows have none)
TABLE1_PARAMETERS: dict[str, str] = {
    "delta_r_p": "errors.pin_circle_radius",
    "delta_r_rp": "errors.pin_radius",
    "Delta_r_rp": "errors.equidistant_modification",
    "Delta_r_p": "errors.radial_modification",
    "Delta_F_t1": "errors.disc_runout",
    "delta_a": "errors.eccentricity",
}


def reducer_errors(reducer: Reducer) -> dict[str, float]:
    """The reducer's own error values [m] for the Table 1 symbols that have a parameter, where
    that parameter is non-zero (a zero, as in the built-in sets, keeps Table 1's value:
    docs/analytical.md)."""
    from .parameters import get_value

    values = {}
    for symbol, name in TABLE1_PARAMETERS.items():
        value = get_value(reducer, name, user_units=False)
        if value != 0.0:
            values[symbol] = float(value)
    return values


_NAMES = {
    "delta_r_p": "circle center radius error of pin gear",
    "delta_r_rp": "pin gear radius error",
    "delta_t_sigma": "circular position error of pin gear hole",
    "delta_j": "matching clearance between pin gear and pin gear hole",
    "Delta_r_rp": "amount of equidistant modification of cycloid gear",
    "Delta_r_p": "amount of radial-moving modification of cycloid gear",
    "Delta_F_t1": "radial ring runout of cycloid gear",
    "Delta_F_P": "tooth pitch cumulative error of cycloid gear",
    "delta_a": "eccentricity error",
}


@dataclasses.dataclass(frozen=True)
class ErrorTerm:
    """One row of Table 1."""

    symbol: str
    name: str
    error: float
    """error value [m]"""
    coefficient: float
    """Table 1 coefficient: the term is coefficient * 2/(a zc) * error"""
    sensitivity_index: float
    """Eq. (15): coefficient / coefficient of delta_r_p"""
    te: float
    """the term's transmission error [rad]"""
    source: str = "Table 1"
    """where the error value comes from: "Table 1" or the reducer parameter"""

    @property
    def te_arcmin(self) -> float:
        return self.te / ARCMIN


@dataclasses.dataclass(frozen=True)
class SensitivityTable:
    """Table 1 for one reducer, and the mean TE of Eq. (11)."""

    curtate_ratio: float
    terms: tuple[ErrorTerm, ...]

    @property
    def mean_te(self) -> float:
        """Eq. (11): sum of the error terms [rad]."""
        return sum(t.te for t in self.terms)

    @property
    def mean_te_arcmin(self) -> float:
        return self.mean_te / ARCMIN

    def to_dict(self) -> dict:
        """JSON-ready form used by ``rvsim sensitivity --json``."""
        return {"K1": self.curtate_ratio,
                "terms": [{"symbol": t.symbol, "name": t.name, "error_mm": t.error / MM,
                           "coefficient": t.coefficient,
                           "sensitivity_index": t.sensitivity_index,
                           "te_arcmin": t.te_arcmin, "source": t.source}
                          for t in self.terms],
                "mean_te_arcmin": self.mean_te_arcmin}

    def to_df(self):
        import pandas as pd

        return pd.DataFrame(self.to_dict()["terms"])


def k_n(reducer: Reducer, equidistant: float, radial: float) -> float:
    """k_n of Eq. (10) as printed, in the paper's units [1/mm], for amounts given in [m].

    The printed formula is not dimensionally homogeneous (its term z_c / (a r_p^2 sqrt(1-K1^2))
    carries one length too many), so its value depends on the unit system; it is evaluated in
    millimetres, the paper's unit.  docs/analytical.md gives the consistent derivative.
    """
    c = reducer.cycloid
    a, zc, rp = c.eccentricity / MM, c.disc_teeth, c.pin_circle_radius / MM
    d_eq, d_rad = equidistant / MM, radial / MM
    root = math.sqrt(1.0 - reducer.curtate_ratio ** 2)
    return d_eq / (a * a * zc) - (zc / (a * rp * rp * root) + root / (a * a * zc)) * d_rad


def sensitivity_table(reducer: Reducer, errors: dict[str, float] | None = None
                      ) -> SensitivityTable:
    """Table 1 and Eq. (11) for ``reducer`` with error values ``errors`` [m] (default: Table 1).

    K1 is the reducer's curtate ratio a*zp/r_p (0.7317 for the RV-40E; the paper rounds it to
    0.73).
    """
    values = dict(PAPER_TABLE1_ERRORS)
    if errors:
        unknown = set(errors) - set(values)
        if unknown:
            raise KeyError(f"unknown error symbols: {sorted(unknown)}")
        values.update(errors)
    c = reducer.cycloid
    k1 = reducer.curtate_ratio
    root = math.sqrt(1.0 - k1 * k1)
    scale = 2.0 / (c.eccentricity * c.disc_teeth)
    kn = k_n(reducer, values["Delta_r_rp"], values["Delta_r_p"])
    coefficients = {
        "delta_r_p": root, "delta_r_rp": -1.0, "delta_t_sigma": k1, "delta_j": 0.5,
        "Delta_r_rp": 1.0, "Delta_r_p": -root, "Delta_F_t1": 0.25, "Delta_F_P": -0.5 * k1,
        # Eq. (10): -2 k_n delta_a = coefficient * 2/(a zc) * delta_a
        "delta_a": -kn * (c.eccentricity / MM) * c.disc_teeth,
    }
    reference = coefficients["delta_r_p"]
    given = errors or {}
    terms = tuple(ErrorTerm(symbol, _NAMES[symbol], values[symbol], coef, coef / reference,
                            coef * scale * values[symbol],
                            TABLE1_PARAMETERS.get(symbol, "") if symbol in given
                            else "Table 1")
                  for symbol, coef in coefficients.items())
    return SensitivityTable(k1, terms)
