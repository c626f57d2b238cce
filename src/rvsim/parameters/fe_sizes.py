"""Admissible finite-element sizes, one rule for the parameter checks and the meshers
(docs/decisions.md, "Admissible finite-element sizes").

Imports nothing heavy: :func:`rvsim.parameters.validate` applies :func:`check_element_sizes`
to every reducer (through :func:`rvsim.geometry.checks.check_geometry`), so that a study, a
tolerance run or ``rvsim params`` refuses an inadmissible size before anything is meshed or
run.  A rule on parameter values only (eccentricity, journal radius, the flexibility flags),
so it lives with the parameters, below both the geometry checks and the meshers of
:mod:`rvsim.fe` that use it (moved from ``rvsim.fe.sizes``, issue 31 step 4).
"""

from __future__ import annotations

from ..errors import ParameterError

__all__ = ["DISC_FINEST", "DISC_COARSEST", "CRANK_FINEST", "CRANK_COARSEST",
           "check_element_size", "disc_element_size", "check_crank_element_size",
           "check_element_sizes"]

#: admissible element sizes of the disc and the plates, in eccentricities (RV-40E: 0.375 mm,
#: about 750 000 dofs, to 12 mm, four elements over a tooth pitch)
DISC_FINEST, DISC_COARSEST = 0.25, 8.0
#: admissible crank element sizes, in journal radii (RV-40E: 1.25-10 mm; 1.25 mm is about
#: 400 000 dofs, 10 mm two elements across the journal)
CRANK_FINEST, CRANK_COARSEST = 0.125, 1.0


def check_element_size(field: str, size: float, feature: str, length: float,
                       finest: float, coarsest: float) -> None:
    """Refuse an element ``size`` [m] outside ``finest``..``coarsest`` times the body's
    characteristic ``length`` [m] (named ``feature``): a finer mesh takes hours and gigabytes
    to condense, a coarser one cannot follow the body's curves (docs/decisions.md)."""
    if not finest * length <= size <= coarsest * length:
        raise ParameterError(field, f"must lie between {finest * length * 1e3:.3g} and "
                                    f"{coarsest * length * 1e3:.3g} mm ({finest:g} to "
                                    f"{coarsest:g} times the {feature}, "
                                    f"{length * 1e3:.3g} mm) (got {size * 1e3:.3g} mm)")


def disc_element_size(reducer) -> float:
    """``flexibility.fe_element_size`` [m] of the disc and the plates, checked."""
    size = reducer.flexibility.fe_element_size
    check_element_size("flexibility.fe_element_size", size,
                       "eccentricity (half the tooth height)", reducer.cycloid.eccentricity,
                       DISC_FINEST, DISC_COARSEST)
    return size


def check_crank_element_size(reducer, size: float) -> None:
    """Refuse a crank element ``size`` [m] outside the admissible range."""
    check_element_size("flexibility.fe_crank_element_size", size, "journal radius",
                       reducer.crank.journal_radius, CRANK_FINEST, CRANK_COARSEST)


def check_element_sizes(reducer) -> None:
    """Refuse an inadmissible element size of any finite-element body ``reducer`` meshes
    (``flexibility.model = fe``, RV reducer): the disc's and the plates' where the disc or the
    carrier is a finite-element body, the crank's where ``flexibility.fe_crank`` is on.  A
    size of a body that is not meshed is not checked."""
    f = reducer.flexibility
    if f.model != "fe" or reducer.layout.single_stage:
        return
    if f.cycloid_disc or f.fe_carrier:
        disc_element_size(reducer)
    if f.fe_crank:
        check_crank_element_size(reducer, f.fe_crank_element_size)
