"""Load-independent losses of a reducer: the lubricant's viscosity at the operating temperature
(Ubbelohde-Walther, ASTM D341) and the drag torque of radial lip seals (ISO/TR 14179-2).

Pure functions, SI inside (viscosity in m^2/s, diameters in m, torques in N*m); the temperature
in degrees Celsius (an SI derived unit; the law converts to kelvin itself).  docs/model.md
section 15 gives the laws and their sources; rvsim.friction turns a parameter set into their
arguments and the kernel applies the seal torques (physics._friction.seal_friction).
"""

from __future__ import annotations

import math

__all__ = ["walther_viscosity", "seal_torque", "KELVIN", "WALTHER_OFFSET",
           "WALTHER_MIN_VISCOSITY", "REFERENCE_TEMPERATURES", "ISO_TR_SEAL_POWER"]

#: 0 degC in kelvin
KELVIN = 273.15
#: the constant added to the viscosity [mm^2/s] in Walther's double logarithm (ASTM D341:
#: log10 log10 (nu + 0.7) = A - B log10 T, nu in mm^2/s, T in K)
WALTHER_OFFSET = 0.7
#: smallest viscosity [m^2/s] the two-constant law is used for: ASTM D341 adds correction
#: terms to the 0.7 below about 2 mm^2/s (docs/decisions.md, issue 32 losses)
WALTHER_MIN_VISCOSITY = 2.0e-6
#: the two reference temperatures [degC] of a lubricant's data sheet: 40 degC (ISO 3448's
#: grade temperature) and 100 degC (ASTM D2270 / ISO 2909's second point)
REFERENCE_TEMPERATURES = (40.0, 100.0)
#: ISO/TR 14179-2 seal loss: P [W] = 7.69e-6 d^2 n, d the shaft diameter at the lip [mm], n
#: [rpm] (as implemented with the clause named in a public gear-loss script; docs/model.md)
ISO_TR_SEAL_POWER = 7.69e-6


def _walther_z(nu: float) -> float:
    """log10 log10 (nu + 0.7), nu in mm^2/s."""
    return math.log10(math.log10(nu + WALTHER_OFFSET))


def walther_viscosity(temperature: float, nu_40: float, nu_100: float) -> float:
    """Kinematic viscosity [m^2/s] at ``temperature`` [degC] of a lubricant of ``nu_40`` and
    ``nu_100`` [m^2/s] at 40 and 100 degC: the straight line of ASTM D341 through the two
    points, log10 log10 (nu + 0.7) linear in log10 T (nu in mm^2/s, T in K).  At 40 degC it
    returns ``nu_40`` itself (the law passes through it; no round trip through the logs)."""
    t_40, t_100 = REFERENCE_TEMPERATURES
    if temperature == t_40:
        return nu_40
    z_40, z_100 = _walther_z(nu_40 * 1e6), _walther_z(nu_100 * 1e6)
    x_40, x_100 = math.log10(t_40 + KELVIN), math.log10(t_100 + KELVIN)
    z = z_40 + (z_100 - z_40) * (math.log10(temperature + KELVIN) - x_40) / (x_100 - x_40)
    return (10.0 ** (10.0 ** z) - WALTHER_OFFSET) * 1e-6


def seal_torque(diameter: float) -> float:
    """Drag torque [N*m] of one radial lip seal on a shaft of ``diameter`` [m] after
    ISO/TR 14179-2: the loss P = 7.69e-6 d^2 n [W] (d in mm, n in rpm) is proportional to the
    speed, so the torque P / omega = 7.69e-6 d^2 60 / (2 pi) [N*m] is independent of it."""
    d_mm = diameter * 1e3
    return ISO_TR_SEAL_POWER * d_mm * d_mm * 60.0 / (2.0 * math.pi)
