"""Cycloid disc profile, pin positions and tooth gaps, derived from the generating geometry.

Conventions (docs/model.md, "Cycloid stage geometry"):

* Fixed pin housing; pin j sits at angle gamma_j = 2 pi j / zp on radius r_p + H.
* ``crank_angle`` beta is the absolute angle of disc 1's eccentric; disc k's eccentric is at
  beta + k*pi.  In the nominal (kinematic) pose the disc centre is a*(cos, sin)(beta + k pi) and
  the disc turns by -beta/zc, i.e. with the carrier.
* Disc k's teeth are cut with phase -k*pi/zc so that both identical discs mesh (zc odd: a disc
  turned half a revolution is half a pitch out).
* Errors and modifications: pin radius r_rp - F, pin circle r_p + H, profile offset r_rp + I
  and generating circle r_p - J open clearance at every pin (paper Sec. 3.2); the crank
  eccentricity a - G (crank only), a rotation modification, disc runout and pin position errors
  close it at some pins (:mod:`rvsim.geometry.assembly` rejects an assembly that overlaps).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import ParameterError
from ..parameters import Reducer
from ._curve import curvatures, pin_gaps_at, profile_points
from ._pose import disc_centre_py
from .deviations import pin_centres, pin_table   # pin_centres public here too

__all__ = [
    "CycloidProfile", "profile_of", "pin_centres", "profile_offset", "nominal_disc_pose",
    "pin_gaps",
    "geometric_backlash", "undercut_ratio", "pin_contact_geometry",
]


@dataclasses.dataclass(frozen=True)
class CycloidProfile:
    """The tooth profile of a cycloid disc, in disc axes, SI units."""

    generating_radius: float
    """radius of the generating pin circle r_p - J [m]"""
    eccentricity: float
    """design eccentricity used to cut the disc [m]"""
    pin_count: int
    """number of pins zp (disc has zp - 1 teeth)"""
    offset: float
    """equidistant offset r_rp + I from the pin-centre curve to the profile [m]"""
    rotation: float = 0.0
    """rotation modification [rad]"""

    @property
    def teeth(self) -> int:
        return self.pin_count - 1

    def points(self, n: int = 3600, phase: float = 0.0) -> np.ndarray:
        """``n`` points of the closed profile (first point not repeated), shape (n, 2) [m]."""
        u = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
        p = profile_points(u, self.generating_radius, self.eccentricity,
                           float(self.pin_count), self.offset)
        cos_t, sin_t = math.cos(self.rotation + phase), math.sin(self.rotation + phase)
        return p @ np.array([[cos_t, sin_t], [-sin_t, cos_t]])


def profile_of(reducer: Reducer) -> CycloidProfile:
    """The (possibly modified) profile the reducer's discs are cut to."""
    c, e = reducer.cycloid, reducer.errors
    return CycloidProfile(
        generating_radius=c.pin_circle_radius - e.radial_modification,
        eccentricity=c.eccentricity,
        pin_count=c.pin_count,
        offset=c.pin_radius + e.equidistant_modification,
        rotation=e.rotation_modification,
    )


def profile_offset(reducer: Reducer, disc: int) -> tuple[float, float]:
    """Centre of disc ``disc``'s profile relative to its crank-hole pattern, in profile axes.

    Radial runout Delta F_t1 puts the profile centre Delta F_t1 / 2 off the hole pattern, along
    the part's x axis turned by ``errors.disc_runout_phase``; disc 2 is the same part turned
    half a turn.  [m]
    """
    half = 0.5 * reducer.errors.disc_runout
    if half == 0.0:
        return 0.0, 0.0
    # body axes -> profile axes: the profile frame is the body frame turned by the tooth
    # phase -disc*pi/zc and the rotation modification
    angle = disc * math.pi + disc * math.pi / reducer.cycloid.disc_teeth \
        - reducer.errors.rotation_modification + reducer.errors.disc_runout_phase
    return half * math.cos(angle), half * math.sin(angle)


def check_disc(disc) -> int:
    """A disc index, 0 or 1 (ParameterError): a reducer has at most two discs, and another
    index would place a disc where none is (a reviewer's disc=2 gave a 40 mm overlap)."""
    if isinstance(disc, bool) or disc not in (0, 1):
        raise ParameterError("disc", f"must be 0 or 1 (got {disc!r})")
    return int(disc)


def nominal_disc_pose(reducer: Reducer, crank_angle: float, disc: int = 0):
    """Kinematic pose (x, y, rotation) of disc ``disc`` at eccentric angle ``crank_angle``."""
    disc = check_disc(disc)
    x, y = disc_centre_py(reducer.cycloid.eccentricity - reducer.errors.eccentricity,
                          crank_angle, disc)
    return x, y, -crank_angle / reducer.cycloid.disc_teeth


def _disc_gaps(reducer: Reducer, crank_angle: float, disc: int, extra_rotation: float,
               offset: tuple[float, float]):
    """:func:`~rvsim.geometry._curve.pin_gaps_at` of every pin, and the profile angle."""
    prof = profile_of(reducer)
    x, y, rot = nominal_disc_pose(reducer, crank_angle, disc)     # checks the disc index
    angle = rot + extra_rotation - disc * math.pi / reducer.cycloid.disc_teeth + prof.rotation
    shift_x, shift_y = profile_offset(reducer, disc)
    clearance = prof.offset - (reducer.cycloid.pin_radius - reducer.errors.pin_radius)
    return pin_gaps_at(pin_table(reducer), x + offset[0], y + offset[1], angle, shift_x,
                       shift_y, prof.generating_radius, prof.eccentricity,
                       float(prof.pin_count), clearance, disc), angle


def pin_gaps(reducer: Reducer, crank_angle: float, *, disc: int = 0,
             extra_rotation: float = 0.0, offset: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """Normal clearance between each pin and the disc profile, shape (zp,) [m].

    The disc is placed in its nominal pose for ``crank_angle`` (eccentricity error included),
    then turned by ``extra_rotation`` and shifted by ``offset``.  Negative values are overlap.
    """
    (gap, *_), _ = _disc_gaps(reducer, crank_angle, disc, extra_rotation, offset)
    return gap


def geometric_backlash(reducer: Reducer, crank_angle: float = 0.0, disc: int = 0):
    """Disc rotation to first pin contact with the crank held, both ways: (forward, backward).

    Both are positive angles [rad]; their sum is the angular backlash of the cycloid stage.
    Raises :class:`ValueError` when the disc already overlaps a pin.
    """
    from scipy.optimize import brentq

    def min_gap(phi: float) -> float:
        return float(np.min(pin_gaps(reducer, crank_angle, disc=disc, extra_rotation=phi)))

    if min_gap(0.0) < -1e-12:
        raise ValueError("the disc overlaps a pin in its nominal pose")
    limit = 0.05
    result = []
    for sign in (1.0, -1.0):
        if min_gap(0.0) <= 1e-12:
            result.append(0.0)
            continue
        root = brentq(lambda p: min_gap(sign * p), 0.0, limit, xtol=1e-13, rtol=1e-12)
        result.append(root)
    return result[0], result[1]


def undercut_ratio(reducer: Reducer, samples: int = 2000) -> float:
    """max over the profile of offset * curvature of the pin-centre curve.

    The profile is free of undercut (no cusp, no self-intersection) while this is below 1.
    """
    prof = profile_of(reducer)
    u = np.linspace(0.0, 2.0 * np.pi / prof.teeth, samples)
    kappa = curvatures(u, prof.generating_radius, prof.eccentricity, float(prof.pin_count))
    return float(np.max(kappa) * prof.offset)


def check_profile(reducer: Reducer) -> None:
    """Raise :class:`ParameterError` if the profile loops or undercuts."""
    k1 = reducer.curtate_ratio
    if k1 >= 1.0:
        raise ParameterError("cycloid.eccentricity",
                             f"curtate ratio K1 = a*zp/r_p = {k1:.4f} must be below 1 "
                             "(the profile would loop)")
    ratio = undercut_ratio(reducer)
    if ratio >= 1.0:
        # blame the modification when the pin radius alone leaves the teeth whole
        pin_alone = ratio * reducer.cycloid.pin_radius / profile_of(reducer).offset
        field = "cycloid.pin_radius" if pin_alone >= 1.0 else "errors.equidistant_modification"
        raise ParameterError(field,
                             f"teeth undercut: pin radius + equidistant modification exceeds "
                             f"the smallest radius of curvature of the pin-centre curve by a "
                             f"factor {ratio:.4g}")


def pin_contact_geometry(reducer: Reducer, crank_angle: float, *, disc: int = 0):
    """Lever arm and contact normal of every pin in the nominal pose.

    Returns (lever [m], normal) with shapes (zp,) and (zp, 2).  ``lever`` is d(gap)/d(disc
    rotation): the pins with positive lever carry the output torque (forward drive); its
    largest value is a * zc.  ``normal`` is the unit outward normal of the disc profile in
    housing axes; a pin pushes the disc along -normal.
    """
    (_, _, nx, ny, qx, qy), angle = _disc_gaps(reducer, crank_angle, disc, 0.0, (0.0, 0.0))
    cos_t, sin_t = math.cos(angle), math.sin(angle)
    normal = np.column_stack([cos_t * nx - sin_t * ny, sin_t * nx + cos_t * ny])
    shift_x, shift_y = profile_offset(reducer, disc)  # lever about the disc centre
    return nx * (qy + shift_y) - ny * (qx + shift_x), normal
