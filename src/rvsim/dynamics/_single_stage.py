"""Force elements of the single-stage cycloid drive only (numba; docs/model.md section 13):
the input coupling on the eccentric shaft and the output pins in the discs' holes."""

from __future__ import annotations

import math

import numba

from ._cache_guard import invalidate_stale_cache

# compiled in: the layout constants and the contact law (the kernel's guard lists this file)
invalidate_stale_cache(__file__)

from ._contact_law import add_rank_one, contact  # noqa: E402
from ._layout import (CARRIER, CRANK0, DISC0, DISC_STRIDE, J_CRANK, K_INPUT,  # noqa: E402
                      M_DISC, OUT_C, OUT_CB, OUT_CLEAR, OUT_COUNT, OUT_RADIUS, OUT_SLOT0, ZETA)

__all__ = ["input_shaft", "output_pin", "output_pin_stiffness"]


@numba.njit(cache=True)
def input_shaft(P, q, v, Q, K, theta_in, omega_in):
    """Single-stage drive: the input coupling turns the eccentric shaft (crank 0's rotation)
    through a torsional spring K_INPUT with contact-like damping.  Returns (input torque,
    energy, dissipated power); ``K`` as in :func:`gear_mesh`."""
    b = CRANK0 + 4
    k = P[K_INPUT]
    twist = theta_in - q[b]
    rate = omega_in - v[b]
    torque = k * twist + 2.0 * P[ZETA] * math.sqrt(k * P[J_CRANK]) * rate
    Q[b] += torque
    if K.shape[0] > 0:
        K[b, b] += k
    return torque, 0.5 * k * twist * twist, (torque - k * twist) * rate


@numba.njit(cache=True)
def output_pin_stiffness(K, d, nx, ny, px, py, lx, ly, k, force, dist):
    """Stiffness matrix of an output pin contact (pin (px, py) on the flange, hole centre (lx,
    ly) from the disc centre): k g g^T + F/dist h h^T + F n . d2r/dq2."""
    index = (CARRIER, d, d + 1, d + 2)
    add_rank_one(K, index, (ny * px - nx * py, -nx, -ny, nx * ly - ny * lx), k)
    add_rank_one(K, index, (nx * px + ny * py, ny, -nx, -nx * lx - ny * ly), force / dist)
    K[CARRIER, CARRIER] -= force * (nx * px + ny * py)
    K[d + 2, d + 2] += force * (nx * lx + ny * ly)


@numba.njit(cache=True)
def output_pin(P, q, v, Q, K, disc, m, elastic):
    """Single-stage drive: output pin m of the flange (the CARRIER coordinate) in its hole of
    disc ``disc``: a clearance contact that closes when the pin centre is farther than
    P[OUT_CLEAR] = design a + clearance from the hole centre (docs/model.md section 13).

    ``elastic[disc, OUT_SLOT0 + m]`` carries the elastic force (Newton start; the quasi-static
    engine reads the pin forces there).  ``K`` as in :func:`arm_bushing`.  Returns (force,
    energy, dissipated power)."""
    alpha = 2.0 * math.pi * m / P[OUT_COUNT]
    x0, y0 = P[OUT_RADIUS] * math.cos(alpha), P[OUT_RADIUS] * math.sin(alpha)
    cos_c, sin_c = math.cos(q[CARRIER]), math.sin(q[CARRIER])
    px, py = cos_c * x0 - sin_c * y0, sin_c * x0 + cos_c * y0
    d = DISC0 + DISC_STRIDE * disc
    cos_t, sin_t = math.cos(q[d + 2]), math.sin(q[d + 2])
    lx, ly = cos_t * x0 - sin_t * y0, sin_t * x0 + cos_t * y0
    rx, ry = px - q[d] - lx, py - q[d + 1] - ly
    dist = math.sqrt(rx * rx + ry * ry)
    delta = dist - P[OUT_CLEAR]
    slot = OUT_SLOT0 + m
    if delta <= 0.0 or dist < 1e-15:
        elastic[disc, slot] = 0.0
        return 0.0, 0.0, 0.0
    nx, ny = rx / dist, ry / dist
    wc = v[CARRIER]
    rate = (nx * (-wc * py - v[d] + v[d + 2] * ly)
            + ny * (wc * px - v[d + 1] - v[d + 2] * lx))
    fn, energy, power, elastic[disc, slot], k = contact(delta, rate, P[OUT_C], P[OUT_CB],
                                                        P[ZETA], P[M_DISC], elastic[disc, slot])
    if K.shape[0] > 0:
        output_pin_stiffness(K, d, nx, ny, px, py, lx, ly, k, elastic[disc, slot], dist)
    # -fn n on the pin (flange), +fn n on the disc at the hole
    Q[CARRIER] += fn * (nx * py - ny * px)
    Q[d] += fn * nx
    Q[d + 1] += fn * ny
    Q[d + 2] += fn * (ny * lx - nx * ly)
    return fn, energy, power
