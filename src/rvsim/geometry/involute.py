"""Involute sun-planet stage: operating geometry, contact ratio and mesh stiffness.

Sources (docs/model.md, "Sun-planet meshes"):

* operating pressure angle and centre distance of profile-shifted gears, and the transverse
  contact ratio: ISO 21771 / any gear text (e.g. Linke, *Stirnradverzahnung*);
* single-pair tooth stiffness c' from ISO 6336-1:2019 Method B (Eq. for q' with constants
  C1..C9, solid gear blanks C_R = 1, standard basic rack C_B = 1, C_M = 0.8).

The dynamic model uses a rectangular-wave mesh stiffness: c' * b times the number of tooth
pairs in contact, which alternates between 1 and 2 with the contact ratio.
"""

from __future__ import annotations

import dataclasses
import math

from ..errors import ParameterError
from ..parameters import Reducer

__all__ = ["GearGeometry", "gear_geometry", "check_gear_stage", "involute", "MAX_GEAR_TEETH",
           "sun_mesh_force", "check_gear_strength", "LEWIS_Y_RACK", "STATIC_ROOT_STRENGTH"]

#: most teeth a sun or planet gear may have: RV reducers use 10-100; above a few hundred the
#: stage no longer fits any RV housing and the involute formulas lose precision (1e20 teeth
#: gave a contact ratio of -1084).  docs/decisions.md
MAX_GEAR_TEETH = 500

#: Lewis form factor of the basic rack (20 deg, full depth), the largest of the table: the
#: most favourable tooth shape (Budynas & Nisbett, *Shigley's Mechanical Engineering Design*,
#: 10th ed., Table 14-2)
LEWIS_Y_RACK = 0.485
#: static (single-load) tooth-root bending strength of the strongest gear steel in ISO 6336:
#: case-carburised, quality ME, sigma_Flim = 525 MPa (ISO 6336-5) x Y_ST = 2 x the static life
#: factor Y_NT = 2.5 (ISO 6336-3) [Pa].  docs/parameters.md
STATIC_ROOT_STRENGTH = 525e6 * 2.0 * 2.5

_ISO6336_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529,
              0.00182)


def involute(angle: float) -> float:
    """inv(alpha) = tan(alpha) - alpha."""
    return math.tan(angle) - angle


def _inverse_involute(value: float) -> float:
    angle = (3.0 * value) ** (1.0 / 3.0)
    for _ in range(30):
        f = involute(angle) - value
        angle -= f / math.tan(angle) ** 2
    return angle


@dataclasses.dataclass(frozen=True)
class GearGeometry:
    """Derived geometry of one sun-planet mesh (SI)."""

    operating_pressure_angle: float
    """transverse operating pressure angle [rad]"""
    centre_distance: float
    """operating centre distance = crank circle radius [m]"""
    sun_base_radius: float
    planet_base_radius: float
    sun_tip_radius: float
    planet_tip_radius: float
    contact_ratio: float
    """transverse contact ratio epsilon_alpha [-]"""
    base_pitch: float
    """base pitch p_b = pi m cos(alpha) [m]"""
    single_pair_stiffness: float
    """ISO 6336 single-pair stiffness c' times face width [N/m]"""


def gear_geometry(reducer: Reducer) -> GearGeometry:
    """Operating geometry of the sun-planet mesh of ``reducer``."""
    g = reducer.gears
    m, z1, z2, alpha = g.module, g.sun_teeth, g.planet_teeth, g.pressure_angle
    x1, x2 = g.sun_profile_shift, g.planet_profile_shift
    inv_w = involute(alpha) + 2.0 * math.tan(alpha) * (x1 + x2) / (z1 + z2)
    alpha_w = _inverse_involute(inv_w)
    centre = 0.5 * m * (z1 + z2) * math.cos(alpha) / math.cos(alpha_w)
    rb1 = 0.5 * m * z1 * math.cos(alpha)
    rb2 = 0.5 * m * z2 * math.cos(alpha)
    ra1 = 0.5 * m * (z1 + 2.0 + 2.0 * x1)
    ra2 = 0.5 * m * (z2 + 2.0 + 2.0 * x2)
    pb = math.pi * m * math.cos(alpha)
    eps = (math.sqrt(max(ra1 ** 2 - rb1 ** 2, 0.0)) + math.sqrt(max(ra2 ** 2 - rb2 ** 2, 0.0))
           - centre * math.sin(alpha_w)) / pb
    c = _ISO6336_C
    q = (c[0] + c[1] / z1 + c[2] / z2 + c[3] * x1 + c[4] * x1 / z1 + c[5] * x2 + c[6] * x2 / z2
         + c[7] * x1 ** 2 + c[8] * x2 ** 2)          # mm*um/N
    c_single = 0.8 / q                               # N/(mm*um), C_M = 0.8, C_R = C_B = 1
    stiffness = c_single * (g.face_width * 1e3) * 1e6  # N/um * 1e6 -> N/m
    return GearGeometry(alpha_w, centre, rb1, rb2, ra1, ra2, eps, pb, stiffness)


def check_gear_stage(reducer: Reducer) -> None:
    """Raise :class:`ParameterError` when the sun-planet stage cannot mesh."""
    g = reducer.gears
    for name, z in (("sun", g.sun_teeth), ("planet", g.planet_teeth)):
        if z > MAX_GEAR_TEETH:
            raise ParameterError(f"gears.{name}_teeth", f"must not exceed {MAX_GEAR_TEETH} "
                                 f"teeth (got {z:.6g})")
    for name, z, x in (("sun", g.sun_teeth, g.sun_profile_shift),
                       ("planet", g.planet_teeth, g.planet_profile_shift)):
        if 0.5 * z * math.sin(g.pressure_angle) ** 2 < 1.0 - x - 1e-12:
            raise ParameterError(f"gears.{name}_profile_shift",
                                 f"{name} teeth undercut (z sin^2(alpha)/2 < 1 - x)")
    geo = gear_geometry(reducer)
    if not geo.contact_ratio > 1.0:
        # the module scales the gears and leaves the contact ratio unchanged: name the stage
        raise ParameterError("gears", f"contact ratio {geo.contact_ratio:.3f} is not above 1 "
                             "(set by the tooth counts, profile shifts and pressure angle)")


def sun_mesh_force(reducer: Reducer, output_torque: float) -> float:
    """Tangential force of one sun-planet mesh at the sun's operating pitch circle when the
    carrier delivers ``output_torque`` (no losses: the sun's torque is output / ratio, shared
    by the planets) [N]."""
    g = reducer.gears
    sun_pitch_radius = gear_geometry(reducer).centre_distance * g.sun_teeth \
        / (g.sun_teeth + g.planet_teeth)
    return output_torque / reducer.ratio / g.planet_count / sun_pitch_radius


def check_gear_strength(reducer: Reducer) -> None:
    """Raise :class:`ParameterError` when the teeth cannot carry the rated torque even once:
    the Lewis root stress F_t / (b m Y) with the most favourable form factor (the rack's)
    above the static bending strength of the strongest gear steel (docs/parameters.md)."""
    g = reducer.gears
    force = sun_mesh_force(reducer, reducer.rating.rated_torque)
    stress = force / (g.face_width * g.module * LEWIS_Y_RACK)
    if stress > STATIC_ROOT_STRENGTH:
        least = force / (STATIC_ROOT_STRENGTH * g.module * LEWIS_Y_RACK)
        raise ParameterError("gears.face_width", f"{g.face_width * 1e3:g} mm cannot carry the "
                             f"rated torque {reducer.rating.rated_torque:g} N*m: the Lewis "
                             f"tooth-root stress would be {stress / 1e6:.3g} MPa, above the "
                             f"static strength of any gear steel, "
                             f"{STATIC_ROOT_STRENGTH / 1e6:g} MPa (ISO 6336; at least "
                             f"{least * 1e3:.2g} mm)")
