"""Contact laws and part compliances, from geometry and materials (sources in docs/model.md).

* Line contact (pin-disc, bushings): Palmgren's empirical law for a roller of length l,
  delta [mm] = 3.84e-5 Q^0.9 / l^0.8 (Palmgren 1959; Harris & Kotzalas, *Rolling Bearing
  Analysis*, 5th ed., Eq. 7.9), written for bearing steel and scaled here by the effective
  modulus E* of the actual pair.
* Disc tooth (factor A): a Timoshenko cantilever of depth 2a and root width one root pitch,
  loaded at its tip (bending + shear), per Timoshenko & Gere, *Mechanics of Materials*.
* Pin body (factor B): total compression of a cylinder between two line loads (Roark's
  Formulas for Stress and Strain, 7th ed., Table 14.1 case 2c), linearised at the pin load that
  carries the reducer's rated torque (``rating.rated_torque``) at the largest lever arm.
* Bushing ring (factor C): radial compression of the ring wall, t / (E r_m b), load spread over
  +-30 deg (chord = r_m).
"""

from __future__ import annotations

import math

from ..parameters import Material

__all__ = ["effective_modulus", "palmgren_coefficient", "tooth_compliance", "pin_compliance",
           "ring_compliance", "PALMGREN_REFERENCE"]

#: Palmgren's constant holds for bearing steel on bearing steel
PALMGREN_REFERENCE = Material("bearing steel", 2.075e11, 7850.0, 0.3)


def effective_modulus(m1: Material, m2: Material) -> float:
    """E* with 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 [Pa]."""
    return 1.0 / ((1.0 - m1.poisson_ratio ** 2) / m1.elastic_modulus
                  + (1.0 - m2.poisson_ratio ** 2) / m2.elastic_modulus)


def palmgren_coefficient(length: float, m1: Material, m2: Material) -> float:
    """C [m / N^0.9] such that delta = C F^0.9 for a line contact of ``length`` [m]."""
    ref = effective_modulus(PALMGREN_REFERENCE, PALMGREN_REFERENCE)
    steel = 3.84e-5 * 1e-3 / (length * 1e3) ** 0.8
    return steel * ref / effective_modulus(m1, m2)


def tooth_compliance(depth: float, root_width: float, width: float, material: Material) -> float:
    """Tip compliance [m/N] of a cantilever tooth (bending + shear, shear factor 1.2)."""
    e = material.elastic_modulus
    g = e / (2.0 * (1.0 + material.poisson_ratio))
    inertia = width * root_width ** 3 / 12.0
    area = width * root_width
    return depth ** 3 / (3.0 * e * inertia) + 1.2 * depth / (g * area)


def pin_compliance(radius: float, length: float, load: float, material: Material) -> float:
    """Secant compliance [m/N] of a pin squeezed across its diameter at ``load`` [N]."""
    e, nu = material.elastic_modulus, material.poisson_ratio
    q = load / length                          # N/m
    diameter = 2.0 * radius
    c_e = 2.0 * (1.0 - nu * nu) / e
    half_width = 1.6 * math.sqrt(q * diameter * c_e)
    return 4.0 * (1.0 - nu * nu) / (math.pi * e * length) * (1.0 / 3.0
                                                              + math.log(2.0 * diameter
                                                                         / half_width))


def ring_compliance(thickness: float, mean_radius: float, width: float,
                    material: Material) -> float:
    """Radial compliance [m/N] of a bushing wall loaded over a chord equal to its radius."""
    return thickness / (material.elastic_modulus * mean_radius * width)
