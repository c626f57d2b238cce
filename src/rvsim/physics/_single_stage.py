"""Force elements of the single-stage cycloid drive only (numba; docs/model.md section 13):
the input coupling on the eccentric shaft, the output pins in the discs' holes, and the change
of frame that lets the kernel's pin contacts act on a turning pin ring (``layout.ring_output``).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._jit import NO_REFCOUNT, REFCOUNT
from .._cache_guard import invalidate_stale_cache

# compiled in: the layout constants and the contact law (the kernel's guard lists this file)
invalidate_stale_cache(__file__)

from ._contact_law import add_rank_one, contact, damping  # noqa: E402
from ._layout import (CARRIER, CRANK0, DISC0, DISC_STRIDE, J_CRANK, K_INPUT,  # noqa: E402
                      M_DISC, N_DOF, OUT_C, OUT_CB, OUT_CLEAR, OUT_COUNT, OUT_RADIUS,
                      OUT_SLOT0, RING_OUTPUT, ZETA)

__all__ = ["input_shaft", "output_pin", "output_pin_stiffness", "ring_frame", "ring_forces"]


@numba.njit(**NO_REFCOUNT)
def input_shaft(P, q, v, Q, K, want, theta_in, omega_in):
    """Single-stage drive: the input coupling turns the eccentric shaft (crank 0's rotation)
    through a torsional spring K_INPUT with contact-like damping.  Returns (input torque,
    energy, dissipated power); ``K``, ``want`` as in :func:`gear_mesh`."""
    b = CRANK0 + 4
    k = P[K_INPUT]
    twist = theta_in - q[b]
    rate = omega_in - v[b]
    torque = k * twist + damping(k, P[ZETA], P[J_CRANK]) * rate
    Q[b] += torque
    if want:
        K[b, b] += k
    return torque, 0.5 * k * twist * twist, (torque - k * twist) * rate


@numba.njit(**NO_REFCOUNT)
def output_pin_stiffness(K, d, nx, ny, px, py, lx, ly, k, force, dist, free):
    """Stiffness matrix of an output pin contact (pin (px, py) on the flange, hole centre (lx,
    ly) from the disc centre): k g g^T + F/dist h h^T + F n . d2r/dq2; ``free`` = 0 when the
    flange is fixed (ring output), 1 when it is the CARRIER coordinate."""
    index = (CARRIER, d, d + 1, d + 2)
    add_rank_one(K, index, (free * (ny * px - nx * py), -nx, -ny, nx * ly - ny * lx), k)
    add_rank_one(K, index, (free * (nx * px + ny * py), ny, -nx, -nx * lx - ny * ly),
                 force / dist)
    K[CARRIER, CARRIER] -= free * force * (nx * px + ny * py)
    K[d + 2, d + 2] += force * (nx * lx + ny * ly)


@numba.njit(**NO_REFCOUNT)
def output_pin(P, q, v, Q, K, want, disc, m, elastic):
    """Single-stage drive: output pin m of the flange (the CARRIER coordinate) in its hole of
    disc ``disc``: a clearance contact that closes when the pin centre is farther than
    P[OUT_CLEAR] = design a + clearance from the hole centre (docs/model.md section 13).

    With the pin ring as output (P[RING_OUTPUT] = 1) the flange is fixed to the frame at angle 0
    and takes no part in the CARRIER coordinate.

    ``elastic[disc, OUT_SLOT0 + m]`` carries the elastic force (Newton start; the quasi-static
    engine reads the pin forces there).  ``K``, ``want`` as in :func:`arm_bushing`.  Returns (force,
    energy, dissipated power)."""
    alpha = 2.0 * math.pi * m / P[OUT_COUNT]
    x0, y0 = P[OUT_RADIUS] * math.cos(alpha), P[OUT_RADIUS] * math.sin(alpha)
    free = 1.0 - P[RING_OUTPUT]
    cos_c, sin_c = math.cos(free * q[CARRIER]), math.sin(free * q[CARRIER])
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
    wc = free * v[CARRIER]
    rate = (nx * (-wc * py - v[d] + v[d + 2] * ly)
            + ny * (wc * px - v[d + 1] - v[d + 2] * lx))
    fn, energy, power, elastic[disc, slot], k = contact(delta, rate, P[OUT_C], P[OUT_CB],
                                                        P[ZETA], P[M_DISC], elastic[disc, slot])
    if want:
        output_pin_stiffness(K, d, nx, ny, px, py, lx, ly, k, elastic[disc, slot], dist, free)
    # -fn n on the pin (flange), +fn n on the disc at the hole
    Q[CARRIER] += free * fn * (nx * py - ny * px)
    Q[d] += fn * nx
    Q[d + 1] += fn * ny
    Q[d + 2] += fn * (ny * lx - nx * ly)
    return fn, energy, power


@numba.njit(**REFCOUNT)
def ring_frame(q, v, want, disc):
    """Pin ring as output: copies of ``q`` and ``v`` with disc ``disc``'s pose and velocity
    expressed in the axes of the ring (turned by the CARRIER coordinate theta_r), and zeroed
    force and stiffness arrays (0 x 0 unless ``want``), for the kernel's pin contacts, which hold
    the pins fixed (docs/model.md section 13):

        O' = R(-theta_r) O,  theta' = theta - theta_r,  v' = d/dt of those.
    """
    d = DISC0 + DISC_STRIDE * disc
    c, s = math.cos(q[CARRIER]), math.sin(q[CARRIER])
    wr = v[CARRIER]
    qr = q.copy()
    vr = v.copy()
    x, y = q[d], q[d + 1]
    qr[d], qr[d + 1] = c * x + s * y, -s * x + c * y
    qr[d + 2] = q[d + 2] - q[CARRIER]
    vr[d] = c * v[d] + s * v[d + 1] + wr * qr[d + 1]
    vr[d + 1] = -s * v[d] + c * v[d + 1] - wr * qr[d]
    vr[d + 2] = v[d + 2] - wr
    n = N_DOF if want else 0
    return qr, vr, np.zeros(N_DOF), np.zeros((n, n))


@numba.njit(**REFCOUNT)
def ring_forces(q, qr, Qr, Kr, Q, K, want, disc):
    """Add the pin contacts' forces ``Qr`` and stiffness ``Kr``, found in the ring's axes by
    :func:`ring_frame`, to ``Q`` and ``K`` of the fixed-frame coordinates: Q = J^T Q' and
    K = J^T K' J - sum_k Q'_k d2q'_k/dq2, J = dq'/dq over (x, y, theta, theta_r).  The ring
    receives minus the disc's moment of the pin forces about the axis."""
    d = DISC0 + DISC_STRIDE * disc
    c, s = math.cos(q[CARRIER]), math.sin(q[CARRIER])
    xr, yr = qr[d], qr[d + 1]
    fx, fy, ft = Qr[d], Qr[d + 1], Qr[d + 2]
    Q[d] += c * fx - s * fy
    Q[d + 1] += s * fx + c * fy
    Q[d + 2] += ft
    Q[CARRIER] += yr * fx - xr * fy - ft
    if not want:
        return
    # J rows: x' = (c, s, 0, y'), y' = (-s, c, 0, -x'), theta' = (0, 0, 1, -1)
    J = np.zeros((3, 4))
    J[0, 0], J[0, 1], J[0, 3] = c, s, yr
    J[1, 0], J[1, 1], J[1, 3] = -s, c, -xr
    J[2, 2], J[2, 3] = 1.0, -1.0
    index = (d, d + 1, d + 2, CARRIER)
    for a in range(4):
        for b in range(4):
            total = 0.0
            for i in range(3):
                for j in range(3):
                    total += J[i, a] * Kr[d + i, d + j] * J[j, b]
            K[index[a], index[b]] += total
    # curvature of the change of frame (x', y' turn with theta_r)
    K[CARRIER, CARRIER] += fx * xr + fy * yr
    cross_x = fx * s + fy * c
    cross_y = -fx * c + fy * s
    K[d, CARRIER] += cross_x
    K[CARRIER, d] += cross_x
    K[d + 1, CARRIER] += cross_y
    K[CARRIER, d + 1] += cross_y
