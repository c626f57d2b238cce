"""One machine element made stiffer by a factor, for the compliance budget (issue 32 item 3;
docs/model.md section 12, "Compliance budget").

:func:`stiffen` returns copies of the model's constants P and of its finite-element disc tables
in which every force law of the chosen elements gives ``factor`` times its force at every
approach: F'(delta) = s F(delta), i.e. delta'(F) = delta(F / s).  Nothing else changes (no
clearance, no geometry, no other element), so the elements' own laws set exactly how:

* Palmgren line contact delta = C F^0.9 + cb F (pins, rollers, output pins;
  :mod:`rvsim.physics._contact_law`): C -> C s^-0.9, cb -> cb / s;
* Johnson's conforming interface delta = j F (ln(a / F) - 1), continued linearly beyond
  F = a / 16 (bushings; :mod:`rvsim.physics._bearings`): j -> j / s, a -> a s (the wrap force
  moves with the force, ln(a2 / a1) is unchanged);
* linear springs and condensed compliance tables (gear mesh, input coupling, finite-element
  disc, pins in their grooves, crank, carrier plates): stiffness x s, compliance / s.

With the factor 1 the constants are returned unchanged (the caller passes no element at all
for the model's own numbers: P is then not even copied).
"""

from __future__ import annotations

import math

import numpy as np

from . import _layout as L

__all__ = ["ELEMENTS", "elements_in", "element_label", "stiffen"]

#: the elements a budget can stiffen, in the order of the force path from input to output
ELEMENTS = ("gear_mesh", "input_coupling", "arm_bearings", "pins", "fe_disc", "fe_crank",
            "support_bearings", "fe_carrier", "output_pins")


def elements_in(P: np.ndarray) -> tuple[str, ...]:
    """The elements the model of ``P`` has (an element absent from it has nothing to stiffen:
    an RV reducer has no input coupling nor output pins, a single-stage drive no gear mesh;
    the finite-element bodies only where ``flexibility.model = fe`` switches them on)."""
    rv = P[L.STAGES] == 2.0
    present = {
        "gear_mesh": rv,
        "input_coupling": not rv,
        "arm_bearings": True,        # the single-stage drive's discs on its eccentric
        "pins": True,
        "fe_disc": P[L.FE_DISC] == 1.0,
        "fe_crank": P[L.FE_CRANK_XX1] > 0.0,
        "support_bearings": True,
        "fe_carrier": P[L.FE_PLATE_XX1] > 0.0,
        "output_pins": P[L.OUT_COUNT] > 0.0,
    }
    return tuple(name for name in ELEMENTS if present[name])


def element_label(P: np.ndarray, name: str) -> str:
    """A reader's name of element ``name`` in the model of ``P`` (its kind of bearing)."""
    rv = P[L.STAGES] == 2.0
    if name == "arm_bearings":
        what = "arm bearings" if rv else "disc bearings on the eccentric"
        return what + (" (needle rollers)" if P[L.ARM_KIND] == 1.0 else " (bushings)")
    if name == "support_bearings":
        what = "crank support bearings" if rv else "eccentric shaft bearings"
        return what + (" (tapered rollers)" if P[L.SUP_KIND] == 1.0 and rv else
                       " (rollers)" if P[L.SUP_KIND] == 1.0 else " (bushings)")
    return {"gear_mesh": "gear mesh (first stage)",
            "input_coupling": "input coupling (input shaft - eccentric shaft)",
            "pins": "pins (pin - disc contacts, pin and tooth bodies)",
            "fe_disc": "finite-element discs",
            "fe_crank": "finite-element crankshafts",
            "fe_carrier": "finite-element carrier and flange",
            "output_pins": "output pins (in the discs' holes)"}[name]


def stiffen(P: np.ndarray, fe_tables: np.ndarray, factors: dict[str, float]
            ) -> tuple[np.ndarray, np.ndarray]:
    """Copies of ``P`` and ``fe_tables`` with each element of ``factors`` (name -> factor s > 0)
    giving s times its force at every approach (module docstring).  An element the model does
    not have is a ValueError (the caller checks names against :func:`elements_in`)."""
    from ._contact_law import EXPONENT

    P = P.copy()
    tables = fe_tables
    present = elements_in(P)
    for name, s in factors.items():
        if name not in present:
            raise ValueError(f"the model has no element {name!r} (it has {', '.join(present)})")
        if not (math.isfinite(s) and s > 0.0):
            raise ValueError(f"factor of {name}: must be a finite number > 0 (got {s})")
        palmgren = s ** -EXPONENT          # C of delta = C F^0.9 at s times the force
        if name == "gear_mesh":
            P[L.K_MESH] *= s
        elif name == "input_coupling":
            P[L.K_INPUT] *= s
        elif name == "pins":
            P[L.PIN_C] *= palmgren
            P[L.PIN_CB] /= s
            P[L.PIN_FE0:L.PIN_FE0 + L.PIN_FE_N] /= s
        elif name == "output_pins":
            P[L.OUT_C] *= palmgren
            P[L.OUT_CB] /= s
        elif name == "arm_bearings":
            P[L.ARM_C] *= palmgren
            P[[L.ARM_J1, L.ARM_J2, L.ARM_CB]] /= s
            P[[L.ARM_A1, L.ARM_A2]] *= s
        elif name == "support_bearings":
            P[L.SUP_C] *= palmgren
            P[[L.SUP_J1, L.SUP_J2, L.SUP_CB]] /= s
            P[[L.SUP_A1, L.SUP_A2_L, L.SUP_A2_U]] *= s
        elif name == "fe_disc":
            tables = tables / s           # a new array: the cached tables are shared
            P[[L.FE_HOLE_CSS0, L.FE_HOLE_CSS1]] /= s
        elif name == "fe_crank":
            P[L.FE_CRANK_XX1:L.FE_CRANK_XX1 + 10] /= s
        elif name == "fe_carrier":
            P[L.FE_PLATE_XX1:L.FE_PLATE_XX1 + 10] /= s
    return P, tables
