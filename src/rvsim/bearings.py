"""Crank bearings and main bearings: constants of the kernel's laws and reported stiffness.

* Bushings (the paper's model): two conforming interfaces in series per bushing, Johnson's
  law (docs/model.md "Bearings"; :mod:`rvsim.physics._bearings`).
* Needle roller bearings at the eccentrics and tapered roller bearings at the supports: every
  roller a Palmgren line contact on both raceways (Harris & Kotzalas, *Rolling Bearing
  Analysis*, 5th ed., Eq. 7.9 and Ch. 7 load distribution).
* Preload of an interference (issue 32): a rolling bearing whose rollers do not fit at the
  assembled pose (a crank-hole position error against needles without clearance) is
  assembled with elastic preload; :func:`roller_preloads` gives the most loaded roller's
  force from the rollers' own law at that approach and its Hertz stress, and
  :func:`check_preload` refuses the reducer only where that stress exceeds
  ``rating.static_contact_stress`` (ISO 76; docs/model.md section 11).
* Main bearings (two angular-contact ball bearings, back to back, carrier in the housing):
  not in the planar kernel (docs/decisions.md); :func:`main_bearing_stiffness` reports their
  radial, axial and tilting stiffness at the preload from Hertz point contact (Hamrock &
  Brewe's closed-form approximation of the elliptic integrals, Harris & Kotzalas Ch. 6).
"""

from __future__ import annotations

import dataclasses
import math

from .geometry.layout import (arm_bushing_play, roller_pitch_diameter,  # public here too
                              support_bushing_play)
from .physics.compliance import effective_modulus, palmgren_coefficient
from .parameters import Reducer

__all__ = ["arm_play", "support_play", "roller_pitch_diameter", "conforming_constants",
           "roller_coefficient", "RollerSet", "roller_set", "RollerPreload", "roller_preloads", "preload_refusal",
           "check_preload",
           "MainBearingStiffness", "main_bearing_stiffness", "ball_contact_coefficient",
           "RAD_PER_ARCMIN"]

RAD_PER_ARCMIN = math.pi / (180.0 * 60.0)


def arm_play(r: Reducer) -> float:
    """Radial play of the eccentric in its disc hole [m]: K + M, plus half the needle
    bearing's radial internal clearance when needles are fitted (negative: preload), less
    the needles' excess over their radial space (``crank.arm_bushing_thickness``): needles
    larger than it are pressed in, a preload as the assembly check counts it (issue 32; a
    smaller needle's room is not added, as before)."""
    play = arm_bushing_play(r)
    if r.bearings.arm_needles:
        play += 0.5 * r.bearings.needle_clearance
        play -= max(r.bearings.needle_diameter - r.crank.arm_bushing_thickness, 0.0)
    return play


def support_play(r: Reducer, upper: bool) -> float:
    """Radial play of a crank journal in its lower (flange, O + L) or upper (carrier, O + N)
    bore [m], plus half the tapered bearing's radial internal clearance when fitted."""
    play = support_bushing_play(r, upper)
    if r.bearings.support_rollers:
        play += 0.5 * r.bearings.support_clearance
    return play


def conforming_constants(length: float, m1, m2, radial_difference: float,
                         stiffness_factor: float = 1.0) -> tuple[float, float]:
    """(j, a) of Johnson's law delta = j F (ln(a / F) - 1) for one conforming interface of
    ``length`` between materials m1 and m2 with the radial difference ``radial_difference``.

    ``stiffness_factor`` s multiplies the force at every approach: j / s and a s."""
    e_star = effective_modulus(m1, m2)
    j = 1.0 / (math.pi * length * e_star)
    a = 4.0 * math.pi * length * e_star * radial_difference
    return j / stiffness_factor, a * stiffness_factor


def roller_coefficient(length: float, inner, roller, outer) -> float:
    """Palmgren coefficient C [m/N^0.9] of one roller on both raceways in series."""
    return palmgren_coefficient(length, inner, roller) + palmgren_coefficient(length, roller,
                                                                              outer)


@dataclasses.dataclass(frozen=True)
class RollerPreload:
    """The most loaded roller of a rolling bearing at the assembled pose (SI)."""

    parts: str          # the bearing, as the assembly check names it
    interference: float  # radial overlap of the most loaded roller, own preload included [m]
    approach: float     # the roller's normal approach, own preload included [m]
    force: float        # the roller's force from its law at that approach [N]
    stress: float       # the larger Hertz pressure of its two raceway contacts [Pa]


@dataclasses.dataclass(frozen=True)
class RollerSet:
    """The constants of a crank's needle or tapered roller set (SI): one definition for the
    engines' roller sets (:func:`rvsim.dynamics.model.build_model`) and the preload check."""

    count: int
    diameter: float        # roller diameter [m]
    length: float          # roller length [m]
    inner_radius: float    # the inner raceway: the eccentric's or the journal's radius [m]
    cos_alpha: float       # cosine of the contact angle (needles: 1)
    coefficient: float     # the rollers' Palmgren law coefficient C (roller_coefficient)
    outer_material: object  # the outer raceway's part: the disc (needles), the carrier


def roller_set(r: Reducer, element: str) -> RollerSet:
    """The needle (``"arm_needles"``) or tapered roller (``"support_rollers"``) set of ``r``:
    the inner raceway the eccentric or the journal, the outer one the disc's hole or the
    carrier's bore a roller diameter further out."""
    b, k, m = r.bearings, r.crank, r.materials
    if element == "arm_needles":
        count, d, length = b.needle_count, b.needle_diameter, b.needle_length
        inner, cos_a, outer = k.eccentric_radius, 1.0, m.cycloid_disc
    else:
        count, d, length = b.support_roller_count, b.support_roller_diameter, \
            b.support_roller_length
        inner, cos_a, outer = k.journal_radius, math.cos(b.support_contact_angle), m.carrier
    return RollerSet(count, d, length, inner, cos_a,
                     roller_coefficient(length, m.crankshaft, m.bushing, outer), outer)


def _roller_sizes(r: Reducer, element: str) -> tuple:
    """(roller length, cos alpha, law coefficient C, ((E*, curvature sum) of the inner and of
    the outer raceway contact)) of the needle or the tapered roller set (:func:`roller_set`,
    the engines' constants)."""
    s, m = roller_set(r, element), r.materials
    d, inner = s.diameter, s.inner_radius
    contacts = ((effective_modulus(m.bushing, m.crankshaft), 2.0 / d + 1.0 / inner),
                (effective_modulus(m.bushing, s.outer_material), 2.0 / d - 1.0 / (inner + d)))
    return s.length, s.cos_alpha, s.coefficient, contacts


def roller_preloads(r: Reducer) -> list[RollerPreload]:
    """Every rolling bearing of ``r`` that its rollers preload at the assembled pose (the
    most loaded roller's approach positive): the approach of the roller on the line of the
    eccentric's (or journal's) offset, its force from the rollers' Palmgren law in series on
    both raceways (:func:`~rvsim.physics._contact_law.spring_force`, the law of the engines'
    roller sets) and the larger of its two raceway contacts' Hertz pressures
    (:func:`~rvsim.physics._contact_law.hertz_pressure`).  The parts are held at the
    assembled pose (the discs do not move to share the interference): an upper bound of the
    preload the engines find in equilibrium (docs/model.md section 11)."""
    if not (r.bearings.arm_needles or r.bearings.support_rollers):
        return []                       # bushings: nothing to preload (0.8 ms of gaps saved)
    from .geometry.assembly import ROLLING, assembly_overlaps
    from .physics._contact_law import hertz_pressure, spring_force

    out = []
    for o in assembly_overlaps(r):
        if o.element not in ROLLING or o.approach + o.preload <= 0.0:
            continue
        length, cos_a, c, contacts = _roller_sizes(r, o.element)
        approach = (o.approach + o.preload) * cos_a
        force = spring_force(approach, c, 0.0, 0.0)[0]
        stress = max(hertz_pressure(force, e_star, curvature, length)
                     for e_star, curvature in contacts)
        out.append(RollerPreload(o.parts, o.approach + o.preload, approach, force, stress))
    return out


def preload_refusal(r: Reducer) -> str | None:
    """Why ``r``'s rolling bearings cannot carry their preload at the assembled pose (the
    largest Hertz stress of :func:`roller_preloads` above ``rating.static_contact_stress``),
    or None."""
    preloads = roller_preloads(r)
    if not preloads:
        return None
    worst = max(preloads, key=lambda p: p.stress)
    limit = r.rating.static_contact_stress
    if worst.stress <= limit:
        return None
    return (f"{worst.parts} by {worst.interference * 1e6:.2f} um at the assembled pose: "
            f"the elastic preload ({worst.force / 1e3:.3g} kN on the most loaded roller) "
            f"gives a Hertz stress of {worst.stress / 1e6:.0f} MPa, above the static limit "
            f"{limit / 1e6:g} MPa (rating.static_contact_stress)")


def check_preload(r: Reducer) -> None:
    """Raise ParameterError("assembly", ...) where :func:`preload_refusal` gives a reason."""
    from .errors import ParameterError

    reason = preload_refusal(r)
    if reason:
        raise ParameterError("assembly", reason)


@dataclasses.dataclass(frozen=True)
class MainBearingStiffness:
    """Stiffness of the pair of main bearings at their preload (linearised)."""

    ball_stiffness: float        # N/m, one ball's normal contact (both raceways) at preload
    radial: float                # N/m, the pair
    axial: float                 # N/m, the pair (preloaded: both rows work)
    tilting: float               # N*m/rad, the pair
    tilting_per_arcmin: float    # N*m/arcmin
    preload_force: float         # N, axial preload of the pair


def ball_contact_coefficient(ball_diameter: float, pitch_diameter: float, contact_angle: float,
                             conformity: float, inner: bool, e_star: float) -> float:
    """K [N/m^1.5] of Q = K delta^1.5 for a ball on a raceway groove of radius ``conformity``
    x ball diameter (Hertz point contact; Hamrock & Brewe approximations of the ellipticity
    k, the elliptic integral E and the function F)."""
    d = ball_diameter
    gamma = d * math.cos(contact_angle) / pitch_diameter
    if inner:                                                  # rolling direction
        rx = 1.0 / (2.0 / d + 2.0 / d * gamma / (1.0 - gamma))
    else:
        rx = 1.0 / (2.0 / d - 2.0 / d * gamma / (1.0 + gamma))
    ry = 1.0 / (2.0 / d - 1.0 / (conformity * d))              # across the groove
    ratio = ry / rx
    k = 1.0339 * ratio ** 0.636
    ell_e = 1.0003 + 0.5968 / ratio
    ell_f = 1.5277 + 0.6023 * math.log(ratio)
    rr = 1.0 / (1.0 / rx + 1.0 / ry)
    e_prime = 2.0 * e_star
    # delta = F [9 / (2 E R) (Q / (pi k E'))^2]^(1/3)  ->  Q = K delta^1.5
    factor = ell_f * (9.0 / (2.0 * ell_e * rr)) ** (1.0 / 3.0) * (1.0 / (math.pi * k * e_prime)) \
        ** (2.0 / 3.0)
    return factor ** -1.5


def main_bearing_stiffness(r: Reducer, conformity: float = 0.52) -> MainBearingStiffness:
    """Radial, axial and tilting stiffness of the two main bearings (back to back, each with
    ``main_ball_count`` balls, preloaded by ``main_preload`` of contact approach per ball).

    Each ball's normal stiffness at the preload approach d0 is 1.5 K d0^0.5 (K of the inner
    and outer contact in series).  A row of Z balls at contact angle alpha gives radial
    Z/2 k cos^2(alpha) and axial Z k sin^2(alpha); a tilt theta of the carrier moves ball psi
    by theta cos(psi) (sin(alpha) dm / 2 + cos(alpha) s / 2) along its contact line (rows at
    +-s/2, contact lines spreading outwards), so the pair's tilting stiffness is
    Z k (sin(alpha) dm/2 + cos(alpha) s/2)^2.
    """
    b, m = r.bearings, r.materials
    e_star = effective_modulus(m.bushing, m.bushing)
    alpha = b.main_contact_angle
    k_in = ball_contact_coefficient(b.main_ball_diameter, b.main_pitch_diameter, alpha,
                                    conformity, True, e_star)
    k_out = ball_contact_coefficient(b.main_ball_diameter, b.main_pitch_diameter, alpha,
                                     conformity, False, e_star)
    k_ball_coef = (k_in ** (-2.0 / 3.0) + k_out ** (-2.0 / 3.0)) ** -1.5
    d0 = max(b.main_preload, 1e-9)
    k_ball = 1.5 * k_ball_coef * math.sqrt(d0)
    z = b.main_ball_count
    radial = 2.0 * 0.5 * z * k_ball * math.cos(alpha) ** 2
    axial = 2.0 * z * k_ball * math.sin(alpha) ** 2
    arm = math.sin(alpha) * 0.5 * b.main_pitch_diameter + math.cos(alpha) * 0.5 * b.main_span
    tilting = z * k_ball * arm ** 2
    preload = z * k_ball_coef * d0 ** 1.5 * math.sin(alpha)
    return MainBearingStiffness(k_ball, radial, axial, tilting, tilting * RAD_PER_ARCMIN,
                                preload)
