"""Friction elements of the kernel that act on top of the normal forces of the other elements
(numba; docs/model.md section 15): rolling-bearing friction torque after Palmgren and the
sun-planet mesh friction after Ohlendorf.  The pin-disc friction is part of
:func:`rvsim.physics._pins.pin_contacts` (the tangential force needs its contact point).

Every law is regularised with tanh(v / v_s) (v_s = P[V_FRIC], ``contact.friction_velocity``),
so the dynamic kernel integrates it with the explicit step and the dissipated power
F v tanh(v / v_s) >= 0 enters the energy balance; the quasi-static engine evaluates the same
functions at a virtual velocity (the direction of travel) with a very small v_s (Coulomb).
"""

from __future__ import annotations

import math

import numba

from .._cache_guard import invalidate_stale_cache
from .._jit import NO_REFCOUNT

invalidate_stale_cache(__file__)

from ._layout import (ARM_DM, ARM_F0, ARM_F1, CARRIER, CRANK0, CRANK_STRIDE,  # noqa: E402
                      DISC0, DISC_STRIDE, MESH_LOSS, NU_OIL, RB1, SEAL_IN, SEAL_IN_R,
                      SEAL_OUT, SEAL_OUT_R, SUP_DM, SUP_F0, SUP_F1, V_FRIC)

__all__ = ["bearing_torque", "bearing_friction", "arm_bearing_friction",
           "support_bearing_friction", "mesh_friction", "seal_friction", "PALMGREN_LOW_SPEED"]

#: below nu * n = 2000 mm^2/s * rpm the Palmgren viscous torque is constant (Harris & Kotzalas,
#: Rolling Bearing Analysis, 5th ed., Ch. 13; SKF General Catalogue 4000, 1989)
PALMGREN_LOW_SPEED = 2000.0
_RAD_S_TO_RPM = 30.0 / math.pi


@numba.njit(**NO_REFCOUNT)
def bearing_torque(f0, f1, dm, nu, omega, load):
    """Palmgren friction torque of a rolling bearing [N*m] at relative speed ``omega`` [rad/s]
    under the radial ``load`` [N]: M = M0 + M1 with

    * M0 = 1e-7 f0 (nu n)^(2/3) dm^3 for nu n >= 2000, 160e-7 f0 dm^3 below (nu in mm^2/s,
      n in rpm, dm in mm, M0 in N*mm): the load-independent, viscous part;
    * M1 = f1 P1 dm: the load-dependent part (P1 = radial load for radial roller bearings).

    ``dm`` [m], ``nu`` [m^2/s].  Returns the magnitude (the caller gives the sign)."""
    if f0 == 0.0 and f1 == 0.0:
        return 0.0
    dm_mm = dm * 1e3
    nu_n = nu * 1e6 * abs(omega) * _RAD_S_TO_RPM
    if nu_n >= PALMGREN_LOW_SPEED:
        m0 = 1e-7 * f0 * nu_n ** (2.0 / 3.0) * dm_mm ** 3
    else:
        m0 = 160e-7 * f0 * dm_mm ** 3
    return 1e-3 * m0 + f1 * load * dm


@numba.njit(**NO_REFCOUNT)
def bearing_friction(P, v, Q, inner, outer, f0, f1, dm, load):
    """Friction torque of a bearing between the rotations ``inner`` and ``outer`` (indices of
    q) under the radial ``load``: -M tanh(w / w_s) on ``inner``, the reaction on ``outer``,
    w the relative speed, w_s = v_s / (dm / 2).  Returns the dissipated power."""
    omega = v[inner] - v[outer]
    torque = bearing_torque(f0, f1, dm, P[NU_OIL], omega, load)
    if torque == 0.0:
        return 0.0
    torque *= math.tanh(omega * 0.5 * dm / P[V_FRIC])
    Q[inner] -= torque
    Q[outer] += torque
    return torque * omega


@numba.njit(**NO_REFCOUNT)
def arm_bearing_friction(P, v, Q, crank, disc, load):
    """Turning-arm bearing of crank ``crank`` in disc ``disc``: the eccentric (the crank's
    rotation) turns in the disc's hole."""
    return bearing_friction(P, v, Q, CRANK0 + CRANK_STRIDE * crank + 4,
                            DISC0 + DISC_STRIDE * disc + 2, P[ARM_F0], P[ARM_F1], P[ARM_DM],
                            load)


@numba.njit(**NO_REFCOUNT)
def support_bearing_friction(P, v, Q, crank, load):
    """Support bearing of crank ``crank`` (lower or upper): the journal turns in the carrier."""
    return bearing_friction(P, v, Q, CRANK0 + CRANK_STRIDE * crank + 4, CARRIER, P[SUP_F0],
                            P[SUP_F1], P[SUP_DM], load)


@numba.njit(**NO_REFCOUNT)
def mesh_friction(P, force, omega_in, px, py, pvx, pvy):
    """Sliding friction of a sun-planet mesh of normal force ``force``, the planet's centre at
    (px, py) moving at (pvx, pvy): the mean loss of Ohlendorf's gear loss factor H_V
    (ISO/TR 14179-2; P[MESH_LOSS] = mu_m H_V), the power mu_m H_V F v_b with v_b = rb1 (omega_in
    - beta') the base-circle speed of the sun relative to the line of centres.

    It acts as a torque T on the sun (the input supplies it) and the opposite moment about the
    sun's axis on the planet, a tangential force T / r at its centre.  Returns (T, fx, fy on
    the planet's centre, dissipated power)."""
    if P[MESH_LOSS] == 0.0 or force <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    r2 = px * px + py * py
    beta_rate = (px * pvy - py * pvx) / r2
    rolling = P[RB1] * (omega_in - beta_rate)
    torque = P[MESH_LOSS] * force * P[RB1] * math.tanh(rolling / P[V_FRIC])
    # moment +torque about the sun axis on the planet: force torque / r along (-py, px) / r
    return torque, -torque * py / r2, torque * px / r2, torque * (omega_in - beta_rate)


@numba.njit(**NO_REFCOUNT)
def seal_friction(P, v, Q, omega_in):
    """Lip seals (ISO/TR 14179-2; the constant drag torques rvsim.friction.seal_torques puts
    in P): those of the output act on the output rotation against the housing, -T tanh(w /
    w_s) with w_s = v_s / r_lip; those of the input shaft add their drag to the input torque
    (the input's motion is given).  Returns (input torque, dissipated power)."""
    torque_in = 0.0
    power = 0.0
    if P[SEAL_OUT] > 0.0:
        omega = v[CARRIER]
        torque = P[SEAL_OUT] * math.tanh(omega * P[SEAL_OUT_R] / P[V_FRIC])
        Q[CARRIER] -= torque
        power += torque * omega
    if P[SEAL_IN] > 0.0:
        torque_in = P[SEAL_IN] * math.tanh(omega_in * P[SEAL_IN_R] / P[V_FRIC])
        power += torque_in * omega_in
    return torque_in, power
