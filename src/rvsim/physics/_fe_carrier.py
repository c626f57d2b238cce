"""Crank support bushings on the finite-element carrier and flange (numba; docs/model.md
section 17, "Carrier / flange").

With ``flexibility.model = fe`` and ``flexibility.fe_carrier`` the crank bores of each plate
(the upper supports' carrier, the lower supports' flange) move under the bushing loads:
u = C S, S = (S_0, S_1) the two cranks' bushing forces on the plate's bores and C the plate's
4 x 4 table (:func:`rvsim.fe.carrier.carrier_table`, carrier frame, bore 1 = crank 0's on +x)
turned with the carrier into the housing frame.  A bushing's own approach is that of its
journal relative to the displaced bore:

    S_j = Phi(r_j - sum_k C_jk S_k),    Phi(r) = f(|r| - clearance) r / |r|,

r_j the journal centre minus the rigid bore centre, f the conforming bushing law.  These are
the FE crank's equations with a plate's two bores in place of a crank's two eccentrics, so the
solvers are the crank's (:mod:`rvsim.physics._fe_crank`): semi-smooth Newton on the 4-vector
with the stiffness dS/dr = (I + D C)^-1 D in the quasi-static engine, one Gauss-Seidel sweep per
step in the dynamic one (each bushing's law in series with its own bore's compliance along its
force, the rest lagged).  Potential energy sum of the bushings' energies + S^T C S / 2; the
moment on the carrier (b_j + u_j) x S_j: the force acts on the displaced bore, which makes the
turning anisotropic table conservative (u x S is the crank's ``compliance_torque``).  The
quasi-static stiffness here also holds the carrier-angle terms (the bores and the table turn
with the carrier).

The force vectors are carried from step to step in the :data:`COLUMNS` columns of the
kernel's ``arm_elastic`` array from ``_layout.PLATE_SLOT0`` (row = crank); the table is in P from FE_PLATE_XX1
(model.build_model fills it, packed as the crank's: ``_fe_crank.pack_table``).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._jit import CACHE, NO_REFCOUNT, REFCOUNT
from .._cache_guard import invalidate_stale_cache

invalidate_stale_cache(__file__)

from ..geometry._pose import bore_centre as bore_centre_of  # noqa: E402
from ._contact_law import damped  # noqa: E402
from ._fe_crank import compliance_torque, pair_forces, rotated_table  # noqa: E402
from ._layout import (BORE_DR0, BORE_DT0, CARRIER, CENTRE_DIST, CH_SUP_FL0,  # noqa: E402
                      CRANK0, CRANK_STRIDE, FE_PLATE_XX1, M_NODE, PLATE_SLOT0, SUP_A1, SUP_A2_L, SUP_A2_U, SUP_SHIFT_L, SUP_SHIFT_U,
                      SUP_CLEAR_L, SUP_CLEAR_U, SUP_J1, SUP_J2, SUP_SLOT0, ZETA)

__all__ = ["COLUMNS", "bore_centre", "support_law", "plate_supports"]

#: columns of ``arm_elastic`` (from _layout.PLATE_SLOT0) holding the support forces (upper,
#: x / y)
COLUMNS = 4


@numba.njit(**NO_REFCOUNT)
def bore_centre(P, q, crank, crank_angle):
    """Centre of crank ``crank``'s carrier / flange bore in the housing frame (with its
    per-part offsets)."""
    angle = q[CARRIER] + crank_angle
    return bore_centre_at(P, crank, math.cos(angle), math.sin(angle))


@numba.njit(cache=CACHE, inline="always")
def bore_centre_at(P, crank, c, s):
    """:func:`bore_centre` from the cosine and sine of q[carrier] + the crank's angle."""
    return bore_centre_of(P[CENTRE_DIST] + P[BORE_DR0 + crank], P[BORE_DT0 + crank], c, s)


@numba.njit(**NO_REFCOUNT)
def support_law(P, upper):
    """The upper (carrier) or lower (flange) support bushing's law as (clearance, j1, a1, j2,
    a2, series compliance, ln(a2 / a1)) (:func:`rvsim.physics._fe_crank.arm_law`'s form)."""
    if upper:
        return P[SUP_CLEAR_U], P[SUP_J1], P[SUP_A1], P[SUP_J2], P[SUP_A2_U], 0.0, P[SUP_SHIFT_U]
    return P[SUP_CLEAR_L], P[SUP_J1], P[SUP_A1], P[SUP_J2], P[SUP_A2_L], 0.0, P[SUP_SHIFT_L]


@numba.njit(**REFCOUNT)
def _stiffness(K, shift, cm, force, bore, sm):
    """K += the plate's stiffness -dQ/dq in its nodes and the carrier angle: dS/dx = Sm,
    dS/dtheta = -Sm a with a = J (b + u) - C J S (the bores turn with the carrier, the table
    with them), and the moment's own terms a^T J S (J: a quarter turn)."""
    work = np.empty(16)
    s, a, js, sa = work[:4], work[4:8], work[8:12], work[12:16]
    for j in range(2):
        s[2 * j], s[2 * j + 1] = force[j, 0], force[j, 1]
        js[2 * j], js[2 * j + 1] = -force[j, 1], force[j, 0]
    for j in range(2):
        ux = uy = cjx = cjy = 0.0
        for m in range(4):
            ux += cm[2 * j, m] * s[m]
            uy += cm[2 * j + 1, m] * s[m]
            cjx += cm[2 * j, m] * js[m]
            cjy += cm[2 * j + 1, m] * js[m]
        a[2 * j] = -(bore[j, 1] + uy) - cjx
        a[2 * j + 1] = bore[j, 0] + ux - cjy
    for i in range(4):
        sa[i] = sm[i, 0] * a[0] + sm[i, 1] * a[1] + sm[i, 2] * a[2] + sm[i, 3] * a[3]
    theta = 0.0
    for i in range(4):
        theta += a[i] * (sa[i] + js[i])
        row = CRANK0 + CRANK_STRIDE * (i // 2) + shift + i % 2
        K[row, CARRIER] -= sa[i]
        K[CARRIER, row] -= sa[i]
        for m in range(4):
            K[row, CRANK0 + CRANK_STRIDE * (m // 2) + shift + m % 2] += sm[i, m]
    K[CARRIER, CARRIER] += theta


@numba.njit(**REFCOUNT)
def plate_supports(P, q, v, Q, K, want, upper, crank_angles, elastic, channel):
    """Both cranks' support bushings on one plate (``upper``: the carrier; else the flange),
    with the plate's table: adds their forces to ``Q`` (and their stiffness to a 17 x 17
    ``K``: then solved together, else one sweep), the resultant force on crank j to its
    channel.  Returns (energy, dissipated power)."""
    law = support_law(P, upper)
    # one scratch array (this runs twice per time step): the housing-frame table, the tangent
    # dS/dr, the approach vectors and rates, the stored and the new forces, the bore centres
    # and the series stiffnesses
    work = np.empty((4, 15))
    cm, sm = work[:, 0:4], work[:, 4:8]
    r, rate, guess, force = work[0:2, 8:10], work[2:4, 8:10], work[0:2, 10:12], work[2:4, 10:12]
    bore, series = work[0:2, 12:14], work[2:4, 14]
    rotated_table(P, FE_PLATE_XX1, q[CARRIER] + crank_angles[0], cm)   # x axis: crank 0's bore
    col = PLATE_SLOT0 + (2 if upper else 0)
    slot = SUP_SLOT0 + (1 if upper else 0)
    shift = 2 if upper else 0
    wc = v[CARRIER]
    for j in range(2):
        b = CRANK0 + CRANK_STRIDE * j + shift
        bx, by = bore_centre(P, q, j, crank_angles[j])
        bore[j, 0], bore[j, 1] = bx, by
        r[j, 0], r[j, 1] = q[b] - bx, q[b + 1] - by
        rate[j, 0], rate[j, 1] = v[b] + wc * by, v[b + 1] - wc * bx
        guess[j, 0], guess[j, 1] = elastic[j, col], elastic[j, col + 1]
        f, dist = elastic[j, slot], math.sqrt(r[j, 0] ** 2 + r[j, 1] ** 2)
        if want and guess[j, 0] * r[j, 0] + guess[j, 1] * r[j, 1] <= 0.999 * f * dist:
            # stored at another pose: start along the rigid approach with the stored size
            scale = f / dist if dist > law[0] else 0.0
            guess[j, 0], guess[j, 1] = scale * r[j, 0], scale * r[j, 1]
    energy = pair_forces(law, cm, r, guess, force, sm, series, want)
    power = 0.0
    for j in range(2):
        b = CRANK0 + CRANK_STRIDE * j + shift
        sx, sy = force[j, 0], force[j, 1]
        f = math.sqrt(sx * sx + sy * sy)
        elastic[j, col], elastic[j, col + 1] = sx, sy
        elastic[j, slot] = f
        channel[CH_SUP_FL0 + 2 * j + (1 if upper else 0)] = 0.0
        if f == 0.0:
            continue
        nx, ny = sx / f, sy / f
        # damping 2 zeta sqrt(k m) at the series stiffness, on the rigid bore's approach rate
        total, pw = damped(f, series[j], nx * rate[j, 0] + ny * rate[j, 1], P[ZETA], P[M_NODE])
        power += pw
        channel[CH_SUP_FL0 + 2 * j + (1 if upper else 0)] = total
        Q[b] -= total * nx
        Q[b + 1] -= total * ny
        Q[CARRIER] += total * (bore[j, 0] * ny - bore[j, 1] * nx)
    # the elastic forces act on the displaced bores b + u, u = C S: u x S on the carrier
    Q[CARRIER] += compliance_torque(cm, force)
    if want:
        _stiffness(K, shift, cm, force, bore, sm)
    return energy, power
