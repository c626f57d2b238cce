"""Friction constants of a reducer and the recommended values for a greased RV reducer.

The laws and their sources are in docs/model.md section 15; this module derives the constants
the kernel needs (``fill_constants``) and holds :data:`TYPICAL_FRICTION`, the one place that
lists friction values for a greased RV reducer (docs/parameters.md, "Friction").
"""

from __future__ import annotations

import math

from .parameters import Reducer

__all__ = ["TYPICAL_FRICTION", "TYPICAL_FRICTION_SOURCES", "gear_loss_factor",
           "bearing_diameters", "pin_friction_coefficient", "has_friction", "fill_constants",
           "lubricant_viscosity", "seal_torques", "seal_limits", "check_losses"]

from .parameters.friction_values import TYPICAL_FRICTION, TYPICAL_FRICTION_SOURCES  # noqa: E402,F401


def gear_loss_factor(reducer: Reducer) -> float:
    """Ohlendorf's gear loss factor H_V of the sun-planet mesh (spur gears):
    H_V = pi (u + 1) / (z1 u) (1 - eps_a + eps_1^2 + eps_2^2), eps_1, eps_2 the addendum
    contact ratios of sun and planet (ISO/TR 14179-2:2001; Niemann & Winter).  The mesh loses
    mu_m H_V of the power it carries.  0 for the single-stage drive (no gear stage)."""
    if reducer.layout.single_stage:
        return 0.0
    from .geometry.involute import gear_geometry

    g = reducer.gears
    geo = gear_geometry(reducer)
    tan_w = math.tan(geo.operating_pressure_angle)
    eps_1 = (math.sqrt(geo.sun_tip_radius ** 2 - geo.sun_base_radius ** 2)
             - geo.sun_base_radius * tan_w) / geo.base_pitch
    eps_2 = (math.sqrt(geo.planet_tip_radius ** 2 - geo.planet_base_radius ** 2)
             - geo.planet_base_radius * tan_w) / geo.base_pitch
    u = g.planet_teeth / g.sun_teeth
    return math.pi * (u + 1.0) / (g.sun_teeth * u) * (1.0 - geo.contact_ratio + eps_1 ** 2
                                                       + eps_2 ** 2)


def bearing_diameters(reducer: Reducer) -> tuple[float, float]:
    """Mean (pitch) diameters dm [m] of a turning-arm and of a support bearing: the parameter,
    or (0) bore diameter + ring wall, the wall being ``crank.arm_bushing_thickness`` (the
    rolling elements' space in the paper's bushing geometry; docs/model.md section 15)."""
    f, k = reducer.friction, reducer.crank
    wall = k.arm_bushing_thickness
    arm = f.arm_bearing_diameter or 2.0 * k.eccentric_radius + wall
    support = f.support_bearing_diameter or 2.0 * k.journal_radius + wall
    return arm, support


def pin_friction_coefficient(reducer: Reducer) -> float:
    """Tangential force / normal force at a pin contact: the pin-disc coefficient for fixed
    pins; for pins free to turn, the pin rolls on the disc and turns in its groove (friction
    mu_g at the groove, of about the pin's radius, plus the rolling resistance f_r), unless
    that exceeds the pin-disc coefficient, when the pin sticks in its groove and slides on the
    disc: min(mu, mu_g + f_r)."""
    mu = reducer.contact.friction_coefficient
    f = reducer.friction
    if not f.pins_turn:
        return mu
    return min(mu, f.pin_groove_coefficient + f.pin_rolling_coefficient)


def lubricant_viscosity(reducer: Reducer) -> float:
    """Kinematic viscosity [m^2/s] of the lubricant at ``operating.temperature``: with
    ``friction.oil_viscosity_100`` the ASTM D341 law through it and ``friction.oil_viscosity``
    (40 degC), else ``friction.oil_viscosity`` itself, which then only holds at 40 degC (another
    temperature without a law is refused).  Outside the law's range (below the cloud point,
    above ``friction.oil_max_temperature``, or hotter than where it gives 2 mm^2/s) raises
    :class:`ParameterError`."""
    from .errors import ParameterError
    from .parameters._io import SI_CEILING
    from .physics.losses import (REFERENCE_TEMPERATURES, WALTHER_MIN_VISCOSITY,
                                 walther_viscosity)

    f, temperature = reducer.friction, reducer.operating.temperature
    t_40, t_100 = REFERENCE_TEMPERATURES
    if f.oil_viscosity_100 == 0.0:
        if temperature != t_40:
            raise ParameterError("operating.temperature", f"{temperature:g} degC needs a "
                                 "viscosity-temperature law: set friction.oil_viscosity_100 "
                                 f"(friction.oil_viscosity is the viscosity at {t_40:g} degC)")
        return f.oil_viscosity
    if f.oil_viscosity_100 >= f.oil_viscosity:
        raise ParameterError("friction.oil_viscosity_100", f"{f.oil_viscosity_100 * 1e6:g} "
                             f"mm^2/s must be below the {t_40:g} degC viscosity "
                             f"friction.oil_viscosity ({f.oil_viscosity * 1e6:g} mm^2/s)")
    if f.oil_viscosity_100 < WALTHER_MIN_VISCOSITY:
        raise ParameterError("friction.oil_viscosity_100", f"{f.oil_viscosity_100 * 1e6:g} "
                             f"mm^2/s: the law (ASTM D341) holds from "
                             f"{WALTHER_MIN_VISCOSITY * 1e6:g} mm^2/s")
    if temperature < f.oil_cloud_point:
        raise ParameterError("operating.temperature", f"{temperature:g} degC is below the "
                             f"lubricant's cloud point friction.oil_cloud_point = "
                             f"{f.oil_cloud_point:g} degC (ASTM D341 holds from it up)")
    if f.oil_max_temperature <= f.oil_cloud_point:
        raise ParameterError("friction.oil_max_temperature", f"{f.oil_max_temperature:g} degC "
                             f"must be above the cloud point friction.oil_cloud_point = "
                             f"{f.oil_cloud_point:g} degC")
    if temperature > f.oil_max_temperature:
        raise ParameterError("operating.temperature", f"{temperature:g} degC is above the "
                             f"lubricant's highest temperature friction.oil_max_temperature = "
                             f"{f.oil_max_temperature:g} degC (mineral base oils degrade from "
                             "110-150 degC)")
    try:
        nu = walther_viscosity(temperature, f.oil_viscosity, f.oil_viscosity_100)
    except OverflowError:      # 10^(10^z) beyond a double: the law far below 40 degC
        nu = math.inf
    if not nu <= SI_CEILING:   # the ceiling of every parameter, friction.oil_viscosity's too
        raise ParameterError("operating.temperature", f"{temperature:g} degC: the viscosity "
                             f"law gives more than {SI_CEILING * 1e6:g} mm^2/s, beyond any "
                             "lubricant (check friction.oil_viscosity and oil_viscosity_100)")
    if not nu >= WALTHER_MIN_VISCOSITY:
        raise ParameterError("operating.temperature", f"{temperature:g} degC: the viscosity "
                             f"law gives {nu * 1e6:.3g} mm^2/s, below the "
                             f"{WALTHER_MIN_VISCOSITY * 1e6:g} mm^2/s it holds for")
    return nu


def seal_limits(reducer: Reducer) -> tuple[tuple[float, str], tuple[float, str]]:
    """The largest lip diameter [m] of the input and of the output seals, each with the part
    that bounds it: the input shaft passes through the discs' central bore (RV: to the sun
    gear; single stage: the eccentric shaft in the discs' bearing bore), so its seal is at
    most the bore's diameter; the output seal closes the flange in the housing, which holds
    the pin ring, so it is at most the pin ring's outer diameter 2 (r_p + r_rp), the largest
    diameter of the reducer's own geometry (docs/parameters.md, "friction")."""
    c = reducer.cycloid
    return ((2.0 * c.disc_bore_radius, "the discs' central bore the input shaft passes "
                                       "through, 2 cycloid.disc_bore_radius"),
            (2.0 * (c.pin_circle_radius + c.pin_radius), "the pin ring's outer diameter, "
             "2 (cycloid.pin_circle_radius + cycloid.pin_radius)"))


def seal_torques(reducer: Reducer) -> tuple[float, float]:
    """Drag torques [N*m] of the input shaft's and of the output's lip seals, all seals of
    each together (ISO/TR 14179-2, :func:`rvsim.physics.losses.seal_torque`).  A seal count
    without its diameter, or a diameter larger than the part the seal sits on
    (:func:`seal_limits`), raises :class:`ParameterError`."""
    from .errors import ParameterError
    from .physics.losses import seal_torque

    f = reducer.friction
    torques = []
    for side, seals, diameter, (limit, part) in zip(
            ("input", "output"), (f.input_seal_count, f.output_seal_count),
            (f.input_seal_diameter, f.output_seal_diameter), seal_limits(reducer)):
        if seals > 0 and diameter <= 0.0:
            raise ParameterError(f"friction.{side}_seal_diameter", f"must be given (> 0 mm) "
                                 f"with friction.{side}_seal_count = {seals}")
        if seals > 0 and diameter > limit:
            raise ParameterError(f"friction.{side}_seal_diameter", f"{diameter * 1e3:g} mm is "
                                 f"larger than {part} ({limit * 1e3:g} mm): the seal cannot "
                                 "sit on the reducer")
        torques.append(seals * seal_torque(diameter) if seals > 0 else 0.0)
    return torques[0], torques[1]


def check_losses(reducer: Reducer) -> Reducer:
    """Refuse (:class:`ParameterError`) a temperature outside the viscosity law and a seal
    without its diameter before anything runs; return ``reducer``."""
    lubricant_viscosity(reducer)
    seal_torques(reducer)
    return reducer


def has_friction(reducer: Reducer) -> bool:
    """True when any friction element of the reducer is active."""
    f = reducer.friction
    return (pin_friction_coefficient(reducer) > 0.0 or f.mesh_coefficient > 0.0
            or f.arm_bearing_f0 > 0.0 or f.arm_bearing_f1 > 0.0 or f.support_bearing_f0 > 0.0
            or f.support_bearing_f1 > 0.0 or f.input_seal_count > 0
            or f.output_seal_count > 0)


def fill_constants(reducer: Reducer, P) -> None:
    """Friction constants into the kernel's constant vector ``P`` (physics._layout)."""
    from .physics import _layout as L

    f = reducer.friction
    P[L.MU] = pin_friction_coefficient(reducer)
    P[L.MESH_LOSS] = f.mesh_coefficient * gear_loss_factor(reducer)
    P[L.NU_OIL] = lubricant_viscosity(reducer)
    P[L.ARM_DM], P[L.SUP_DM] = bearing_diameters(reducer)
    P[L.ARM_F0], P[L.ARM_F1] = f.arm_bearing_f0, f.arm_bearing_f1
    P[L.SUP_F0], P[L.SUP_F1] = f.support_bearing_f0, f.support_bearing_f1
    P[L.SEAL_IN], P[L.SEAL_OUT] = seal_torques(reducer)
    P[L.SEAL_IN_R] = 0.5 * f.input_seal_diameter
    P[L.SEAL_OUT_R] = 0.5 * f.output_seal_diameter
    bearings = f.arm_bearing_f0 + f.arm_bearing_f1 + f.support_bearing_f0 + f.support_bearing_f1
    seals = P[L.SEAL_IN] + P[L.SEAL_OUT]
    P[L.FRICTION_ON] = 1.0 if (P[L.MESH_LOSS] > 0.0 or bearings > 0.0 or seals > 0.0) else 0.0
