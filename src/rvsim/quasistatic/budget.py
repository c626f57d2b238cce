"""Where the torsional compliance goes: :func:`compliance_budget` (issue 32 item 3;
docs/model.md section 12, "Compliance budget").

The torque-reversal test (:func:`~rvsim.quasistatic.hysteresis`) is run once on the model as
it is and once more per machine element with that element ``factor`` times stiffer
(:mod:`rvsim.physics.stiffening`), everything else unchanged.  With C = 1 / K the compliance of
the catalogue's rigidity K (secant 50-100 % of rated) and C_i that with element i stiffened,

    share_i = (C - C_i) / C,

the part of the reducer's compliance that element i takes away when it is made (nearly) rigid;
the element's own secant stiffness at the output is 1 / (C - C_i).  For springs in series the
shares add up to 1 as s grows (a stiffened element keeps 1/s of a linear spring's
compliance, s^-0.9 of a Palmgren contact's, more of a bushing's: hence the default 1e4, where
the built-in sets' shares have converged); what else is missing from 100 % (``residual``)
is the interaction of elements loaded in parallel (load sharing between pins, cranks and
discs that shifts when one element stiffens).
"""

from __future__ import annotations

import dataclasses
import math
import time as _time

import numpy as np

from ..errors import ParameterError
from ..parameters import Reducer, check_reducer
from ..physics._status import STATUS_SINGULAR, STATUS_TEXT
from ..units import ARCMIN

__all__ = ["compliance_budget", "ComplianceBudget", "DEFAULT_FACTOR", "rigidity_of"]

#: stiffening factor of one element: the shares of the built-in sets have converged to the
#: rigid element's within 0.05 % points (docs/model.md section 12: 10 x leaves 12-22 %
#: residual, 100 x, issue 32's first budget, 1-3 %, mostly the compliance a bushing keeps)
DEFAULT_FACTOR = 1e4

#: the smallest stiffening factor: the share (C - C_i)/C is the element's own compliance only
#: where the stiffened element keeps little of it (100 x: a Palmgren contact keeps 100^-0.9 =
#: 1.6 %, a conforming bushing about 4 %, docs/model.md section 12); a smaller factor gives
#: shares that say nothing (1.0000001 x: every share 0.0 %, hostile test 2026-11-28)
MIN_FACTOR = 100.0

#: a share below this is a contradiction (stiffening one element made the reducer softer by
#: more than the solver's tolerance can explain): the budget's status says so, not "ok"
NEGATIVE_SHARE = -0.01


@dataclasses.dataclass
class ComplianceBudget:
    """Each element's share of the torsional compliance at the rated torque (SI)."""

    rated_torque: float            # [N*m]
    factor: float                  # stiffening factor of one element
    rigidity: float                # [N*m/rad] the model's (catalogue secant 50-100 %)
    elements: tuple                # element names (rvsim.physics.stiffening.ELEMENTS)
    labels: tuple                  # their readers' names
    stiffened_rigidity: np.ndarray  # (n,) [N*m/rad] the rigidity with element i stiffened
    status: str                    # "ok", or "<status> (<element> stiffened)"
    wall_s: float
    base: dict = dataclasses.field(default_factory=dict)  # elements stiffened in every run

    @property
    def shares(self) -> np.ndarray:
        """(n,) (C - C_i) / C = 1 - K / K_i (NaN where the stiffened test failed)."""
        return 1.0 - self.rigidity / self.stiffened_rigidity

    @property
    def element_stiffness(self) -> np.ndarray:
        """(n,) [N*m/rad] 1 / (C - C_i): the element's own secant stiffness at the output
        (infinite where stiffening it changed nothing)."""
        with np.errstate(divide="ignore"):
            return 1.0 / (1.0 / self.rigidity - 1.0 / self.stiffened_rigidity)

    @property
    def residual(self) -> float:
        """1 - sum of the shares (a NaN share makes it NaN)."""
        return float(1.0 - np.sum(self.shares))

    def order(self) -> np.ndarray:
        """Indices of the elements, the largest share (the softest element) first."""
        shares = np.nan_to_num(self.shares, nan=-np.inf)
        return np.argsort(-shares, kind="stable")

    def summary(self) -> dict:
        """The ``budget`` object of ``rvsim hysteresis --budget --json`` (N*m/arcmin)."""
        shares, stiffness = self.shares, self.element_stiffness

        def number(x):
            return float(x) if math.isfinite(x) else None

        rows = [{"element": self.elements[i], "label": self.labels[i],
                 "share": number(shares[i]),
                 "stiffness_nm_per_arcmin": number(stiffness[i] * ARCMIN)
                 if stiffness[i] > 0 else None,
                 "stiffened_rigidity_nm_per_arcmin": number(self.stiffened_rigidity[i]
                                                            * ARCMIN)}
                for i in self.order()]
        return {"method": "stiffen_one_at_a_time", "factor": self.factor,
                "secant": "50-100 % of rated torque, both directions (catalogue rigidity)",
                "rated_torque_nm": self.rated_torque,
                "rigidity_nm_per_arcmin": self.rigidity * ARCMIN,
                "elements": rows, "sum": number(float(np.sum(shares))),
                "residual": number(self.residual),
                "stiffened_in_every_run": dict(self.base),
                "status": self.status, "wall_s": self.wall_s}


def _check(reducer: Reducer, factor, base, elements) -> tuple[float, dict, tuple, tuple]:
    """The factor, the base map, the elements to stiffen and their labels (ParameterError on
    a factor that is not a number > 1 or an element the model lacks)."""
    from ..dynamics.model import build_model
    from ..physics.stiffening import element_label, elements_in

    if isinstance(factor, bool) or not isinstance(factor, (int, float, np.number)) \
            or not math.isfinite(factor) or factor < MIN_FACTOR:
        raise ParameterError("factor", f"must be a finite number >= {MIN_FACTOR:g} (got "
                             f"{factor!r}): a less stiffened element keeps part of its "
                             "compliance and its share says nothing")
    P = build_model(reducer, 1e-5).P
    present = elements_in(P)
    base = dict(base or {})
    for name, s in base.items():
        if name not in present:
            raise ParameterError("base", f"the model has no element {name!r} (it has "
                                 f"{', '.join(present)})")
        if isinstance(s, bool) or not isinstance(s, (int, float, np.number)) \
                or not (math.isfinite(s) and s > 0):
            raise ParameterError("base", f"factor of {name} must be a finite number > 0 "
                                 f"(got {s!r})")
    if elements is not None:
        unknown = [e for e in elements if e not in present]
        if unknown or not elements:
            raise ParameterError("elements", f"must be some of {', '.join(present)} (got "
                                 f"{', '.join(map(str, elements)) or 'none'})")
        present = tuple(e for e in present if e in elements)
    return float(factor), base, present, tuple(element_label(P, e) for e in present)


def _rigidity(reducer, rated, points, stiffen) -> tuple[float, str]:
    """(catalogue rigidity [N*m/rad], status) of one torque-reversal test; NaN and the status
    where the test or its curve fails."""
    from .torque_reversal import hysteresis

    try:
        run = hysteresis(reducer, rated_torque=rated, points_per_branch=points,
                         raise_on_failure=False, stiffen=stiffen)
    except np.linalg.LinAlgError:
        # the condensed stiffness of a model whose stiffnesses span too many decades (a
        # factor far beyond what a budget needs) cannot be inverted in double precision
        return math.nan, STATUS_TEXT[STATUS_SINGULAR]
    return rigidity_of(run)


def rigidity_of(run) -> tuple[float, str]:
    """(catalogue rigidity [N*m/rad], status) of a torque-reversal result: the secant of its
    summary, in SI; NaN and the status where the test or its curve failed."""
    from ..analysis.catalogue import CurveError, torsional_rigidity

    if run.status != "ok":
        return math.nan, run.status
    ok = run.converged
    try:
        return torsional_rigidity(run.torque[ok], run.angle[ok], run.rated_torque), "ok"
    except CurveError:
        return math.nan, "invalid_curve"


def compliance_budget(reducer: Reducer, *, rated_torque: float | None = None,
                      points_per_branch: int = 50, factor: float = DEFAULT_FACTOR,
                      base: dict | None = None, rigidity: float | None = None,
                      elements=None) -> ComplianceBudget:
    """Each element's share of the torsional compliance at ``rated_torque`` (default:
    reducer.rating.rated_torque), by stiffening one element at a time ``factor`` times (module
    docstring).  ``base`` (element -> factor) stiffens elements in every run, the reference
    included (a what-if: the budget of the reducer with those elements stiffer).
    ``rigidity``: the reference test's rigidity [N*m/rad] where the caller has run it with the
    same arguments (``rvsim hysteresis``), else it is run here.  ``elements``: the names to
    stiffen (default: every element the model has, :func:`rvsim.physics.stiffening.elements_in`).

    Never raises on a failed test: the budget's ``status`` names the first element whose
    stiffened test failed (its share NaN); a failed reference test fails the whole budget."""
    check_reducer(reducer)
    factor, base, present, labels = _check(reducer, factor, base, elements)
    rated = reducer.rating.rated_torque if rated_torque is None else rated_torque
    start = _time.perf_counter()
    status = "ok"
    if rigidity is None:
        rigidity, status = _rigidity(reducer, rated, points_per_branch, base)
        if status != "ok":
            status = f"{status} (reference test)"
    stiffened = np.full(len(present), math.nan)
    if status == "ok":
        for i, name in enumerate(present):
            factors = dict(base)
            factors[name] = factors.get(name, 1.0) * factor
            stiffened[i], run_status = _rigidity(reducer, rated, points_per_branch, factors)
            if run_status != "ok" and status == "ok":
                status = f"{run_status} ({name} stiffened)"
    if status == "ok":
        shares = 1.0 - rigidity / stiffened
        worst = int(np.argmin(shares))
        if shares[worst] < NEGATIVE_SHARE:
            status = (f"inconsistent ({present[worst]} stiffened: the reducer came out softer, "
                      f"share {100 * shares[worst]:.1f} %)")
    return ComplianceBudget(rated_torque=float(rated), factor=factor, rigidity=float(rigidity),
                            elements=present, labels=labels, stiffened_rigidity=stiffened,
                            status=status, wall_s=_time.perf_counter() - start, base=base)
