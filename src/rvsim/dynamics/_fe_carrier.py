"""Crank support bushings on the finite-element carrier and flange (numba; docs/model.md
section 17, "Carrier / flange").

With ``flexibility.model = fe`` and ``flexibility.fe_carrier`` the crank bores of each plate
(the upper supports' carrier, the lower supports' flange) move under the bushing loads:
u = C S, S = (S_0, S_1) the two cranks' bushing forces on the plate's bores and C the plate's
4 x 4 table (:func:`rvsim.fe.carrier.carrier_table`, carrier frame, bore 1 = crank 0 on +x)
turned with the carrier into the housing frame (:func:`plate_block`).  A bushing's own
approach is that of its journal relative to the displaced bore:

    S_j = Phi(r_j - sum_k C_jk S_k),    Phi(r) = f(|r| - clearance) r / |r|,

r_j the journal centre minus the rigid bore centre, f the conforming bushing law
(:func:`rvsim.dynamics._bearings.conforming_force`).  Potential energy sum of the bushings'
energies + S^T C S / 2; the moment on the carrier (b_j + u_j) x S_j (the force acts on the
displaced bore, which makes the rotating anisotropic table conservative).

* Quasi-static engine (stiffness wanted): the plate's two bushings are solved together by
  semi-smooth Newton on G(S) = S - Phi(r - C S) (Jacobian I + D C, D the bushings' 2 x 2
  tangents k n n^T + F/|r| t t^T); stiffness dS/dr = (I + D C)^-1 D (symmetric).
* Dynamic engine: one Gauss-Seidel sweep per step: each bushing's own law in series with its
  own bore's compliance projected on its direction, n^T C_jj n, solved exactly; the other
  crank's force (this sweep's, or the previous step's) and the rest of its own bore's
  anisotropic compliance taken as they are.  Damping 2 zeta sqrt(k m) at the series stiffness.

The force vectors are carried from step to step in the last :data:`COLUMNS` columns of the
kernel's ``arm_elastic`` array (row = crank); the table is in P (model.build_model fills it).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ._cache_guard import invalidate_stale_cache

invalidate_stale_cache(__file__)

from ._bearings import conforming_force  # noqa: E402
from ._contact_law import damped  # noqa: E402
from ._fe_contacts import _eliminate  # noqa: E402
from ._layout import (BORE_DR0, BORE_DT0, CARRIER, CENTRE_DIST, CH_SUP_FL0,  # noqa: E402
                      CRANK0, CRANK_STRIDE, M_NODE, PLATE_11XX, PLATE_11XY, PLATE_11YY, PLATE_12XX,
                      PLATE_12XY, PLATE_12YX, PLATE_12YY, PLATE_22XX, PLATE_22XY, PLATE_22YY,
                      SUP_A1, SUP_A2_L, SUP_A2_U, SUP_CLEAR_L, SUP_CLEAR_U, SUP_J1, SUP_J2,
                      SUP_SLOT0, ZETA)

__all__ = ["COLUMNS", "bore_centre", "plate_block", "plate_supports", "plate_forces",
           "plate_sweep"]

#: columns of ``arm_elastic`` (at its end) holding the support forces (upper, x / y)
COLUMNS = 4
#: Newton iterations of a plate's coupled bushings (2-4 from the previous forces), then
#: fixed-point sweeps (a contraction: the coupling's spectral radius is about 0.02)
MAX_NEWTON = 30
MAX_SWEEPS = 200


@numba.njit(cache=True)
def bore_centre(P, q, crank, crank_angle):
    """Centre of crank ``crank``'s carrier / flange bore in the housing frame (with its
    per-part offsets)."""
    angle = q[CARRIER] + crank_angle
    radius = P[CENTRE_DIST] + P[BORE_DR0 + crank]
    c, s = math.cos(angle), math.sin(angle)
    return radius * c - P[BORE_DT0 + crank] * s, radius * s + P[BORE_DT0 + crank] * c


@numba.njit(cache=True)
def plate_block(P, angle, j, k):
    """Block (j, k) of the plate table turned by ``angle`` (carrier frame -> housing frame):
    R C_jk R^T as (xx, xy, yx, yy) [m/N]."""
    if j == k:
        a = P[PLATE_11XX] if j == 0 else P[PLATE_22XX]
        b = P[PLATE_11XY] if j == 0 else P[PLATE_22XY]
        c, d = b, P[PLATE_11YY] if j == 0 else P[PLATE_22YY]
    elif j == 0:
        a, b, c, d = P[PLATE_12XX], P[PLATE_12XY], P[PLATE_12YX], P[PLATE_12YY]
    else:
        a, b, c, d = P[PLATE_12XX], P[PLATE_12YX], P[PLATE_12XY], P[PLATE_12YY]
    co, si = math.cos(angle), math.sin(angle)
    # t = C R^T, then R t
    t00, t01 = a * co - b * si, a * si + b * co
    t10, t11 = c * co - d * si, c * si + d * co
    return (co * t00 - si * t10, co * t01 - si * t11, si * t00 + co * t10,
            si * t01 + co * t11)


@numba.njit(cache=True)
def _table(P, angle, cm):
    """The whole 4 x 4 table in the housing frame into ``cm``."""
    for j in range(2):
        for k in range(2):
            xx, xy, yx, yy = plate_block(P, angle, j, k)
            cm[2 * j, 2 * k], cm[2 * j, 2 * k + 1] = xx, xy
            cm[2 * j + 1, 2 * k], cm[2 * j + 1, 2 * k + 1] = yx, yy


@numba.njit(cache=True)
def _law(P, upper, delta, cb, guess):
    """The support bushing's conforming law with ``cb`` in series: (F, dF/ddelta, energy)."""
    return conforming_force(delta, P[SUP_J1], P[SUP_A1], P[SUP_J2],
                            P[SUP_A2_U] if upper else P[SUP_A2_L], cb, guess)


@numba.njit(cache=True)
def _evaluate(P, upper, clearance, r, cm, s, guess, phi, dm, own, energies):
    """Phi(r - C s) of both bushings into ``phi``, their 2 x 2 tangents into the diagonal
    blocks of ``dm``, (law stiffness along n, n^T C_jj n) into ``own`` and their energies;
    returns the largest force."""
    largest = 0.0
    for j in range(2):
        ex, ey = r[2 * j], r[2 * j + 1]
        for m in range(4):
            ex -= cm[2 * j, m] * s[m]
            ey -= cm[2 * j + 1, m] * s[m]
        dist = math.sqrt(ex * ex + ey * ey)
        for a in range(2):
            for b in range(2):
                dm[2 * j + a, 2 * j + b] = 0.0
        if dist <= clearance or dist < 1e-15:
            phi[2 * j] = phi[2 * j + 1] = energies[j] = own[j, 0] = own[j, 1] = 0.0
            continue
        nx, ny = ex / dist, ey / dist
        f, k, e = _law(P, upper, dist - clearance, 0.0, guess[j])
        guess[j] = f
        phi[2 * j], phi[2 * j + 1], energies[j] = f * nx, f * ny, e
        own[j, 0], own[j, 1] = k, _projected(cm, j, nx, ny)
        turn = f / dist                         # the normal turns with the approach vector
        dm[2 * j, 2 * j] = k * nx * nx + turn * ny * ny
        dm[2 * j, 2 * j + 1] = dm[2 * j + 1, 2 * j] = (k - turn) * nx * ny
        dm[2 * j + 1, 2 * j + 1] = k * ny * ny + turn * nx * nx
        largest = max(largest, f)
    return largest


@numba.njit(cache=True)
def _projected(cm, j, nx, ny):
    """n^T C_jj n: bore j's compliance along n."""
    return (cm[2 * j, 2 * j] * nx * nx + (cm[2 * j, 2 * j + 1] + cm[2 * j + 1, 2 * j]) * nx * ny
            + cm[2 * j + 1, 2 * j + 1] * ny * ny)


@numba.njit(cache=True)
def _jacobian(dm, cm, jac):
    """jac = I + D C."""
    for i in range(4):
        for j in range(4):
            total = 0.0
            for m in range(4):
                total += dm[i, m] * cm[m, j]
            jac[i, j] = total + (1.0 if i == j else 0.0)


@numba.njit(cache=True)
def plate_forces(P, upper, clearance, r, cm, s, guess, own, stiffness):
    """Elastic forces ``s`` (4: S_0, S_1 on the bores) of a plate's two bushings at the rigid
    approach vectors ``r`` with the housing-frame table ``cm``, semi-smooth Newton from
    ``s`` (``guess``: the bushings' force magnitudes, Newton starts of their law).  Fills
    ``own[j]`` = (law stiffness along n, n^T C_jj n); with a 4 x 4 ``stiffness`` also the
    tangent dS/dr = (I + D C)^-1 D.  Returns (potential energy, iterations, converged)."""
    work = np.zeros(42)                         # one scratch array
    phi, g, energies = work[:4], work[4:8], work[8:10]
    dm, jac = work[10:26].reshape((4, 4)), work[26:42].reshape((4, 4))
    converged = False
    iterations = 0
    for iterations in range(1, MAX_NEWTON + MAX_SWEEPS + 1):
        largest = _evaluate(P, upper, clearance, r, cm, s, guess, phi, dm, own, energies)
        worst = 0.0
        for i in range(4):
            g[i] = s[i] - phi[i]
            worst = max(worst, abs(g[i]))
        if worst <= 1e-10 * largest + 1e-12:
            converged = True
            break
        if iterations > MAX_NEWTON:    # Newton cycling where a bushing opens: sweeps
            s[:] = phi
            continue
        _jacobian(dm, cm, jac)
        _eliminate(jac, g.reshape((4, 1)), 4)        # I + D C: diagonally dominant
        for i in range(4):
            s[i] -= g[i]
    s[:] = phi
    energy = energies[0] + energies[1]
    for i in range(4):
        for j in range(4):
            energy += 0.5 * s[i] * cm[i, j] * s[j]
    if stiffness.shape[0] == 4:
        _jacobian(dm, cm, jac)
        stiffness[:, :] = dm
        _eliminate(jac, stiffness, 4)
        for i in range(4):
            for j in range(i + 1, 4):
                mean = 0.5 * (stiffness[i, j] + stiffness[j, i])
                stiffness[i, j] = stiffness[j, i] = mean
    return energy, iterations, converged


@numba.njit(cache=True)
def plate_sweep(P, upper, clearance, r, cm, s, guess, own):
    """One Gauss-Seidel sweep (dynamic engine): bushing j's law in series with n^T C_jj n
    along its direction n, solved exactly; the other bushing's force ``s`` as it stands (this
    sweep's for the second) and the rest of its own bore's compliance at its previous force
    taken as they are.  Updates ``s``, ``guess`` and ``own[j]`` = (series stiffness along n,
    n^T C_jj n).  Returns the potential energy."""
    energy = 0.0
    for j in range(2):
        o = 2 * (1 - j)
        sx, sy = s[2 * j], s[2 * j + 1]
        # the other bore's load ...
        wx = cm[2 * j, o] * s[o] + cm[2 * j, o + 1] * s[o + 1]
        wy = cm[2 * j + 1, o] * s[o] + cm[2 * j + 1, o + 1] * s[o + 1]
        # ... and the own bore's displacement off the direction of its previous force
        rx, ry = r[2 * j] - wx, r[2 * j + 1] - wy
        f_prev = math.sqrt(sx * sx + sy * sy)
        if f_prev > 0.0:
            ux = cm[2 * j, 2 * j] * sx + cm[2 * j, 2 * j + 1] * sy
            uy = cm[2 * j + 1, 2 * j] * sx + cm[2 * j + 1, 2 * j + 1] * sy
            along = (ux * sx + uy * sy) / (f_prev * f_prev)
            rx -= ux - along * sx
            ry -= uy - along * sy
        dist = math.sqrt(rx * rx + ry * ry)
        if dist <= clearance or dist < 1e-15:
            s[2 * j] = s[2 * j + 1] = guess[j] = own[j, 0] = own[j, 1] = 0.0
            continue
        nx, ny = rx / dist, ry / dist
        cn = _projected(cm, j, nx, ny)
        f, k, e = _law(P, upper, dist - clearance, cn, guess[j])
        guess[j] = f
        s[2 * j], s[2 * j + 1] = f * nx, f * ny
        own[j, 0], own[j, 1] = k, cn
        # the series law holds f^2 n^T C_jj n / 2; the pair term comes half from each side
        energy += e + 0.5 * f * (wx * nx + wy * ny)
    return energy


@numba.njit(cache=True)
def _stiffness(K, shift, cm, s, bore, sm):
    """K += the plate's stiffness -dQ/dq in its nodes and the carrier angle: dS/dx = Sm,
    dS/dtheta = -Sm a with a = J (b + u) - C J S (the bores turn with the carrier, the table
    with them), and the moment's own terms a^T J S (J: a quarter turn)."""
    work = np.empty(12)
    a, js, sa = work[:4], work[4:8], work[8:12]
    for j in range(2):
        js[2 * j], js[2 * j + 1] = -s[2 * j + 1], s[2 * j]
    for j in range(2):
        ux = uy = cjx = cjy = 0.0
        for m in range(4):
            ux += cm[2 * j, m] * s[m]
            uy += cm[2 * j + 1, m] * s[m]
            cjx += cm[2 * j, m] * js[m]
            cjy += cm[2 * j + 1, m] * js[m]
        a[2 * j] = -(bore[2 * j + 1] + uy) - cjx
        a[2 * j + 1] = bore[2 * j] + ux - cjy
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


@numba.njit(cache=True)
def plate_supports(P, q, v, Q, K, upper, crank_angles, elastic, channel):
    """Both cranks' support bushings on one plate (``upper``: the carrier; else the flange),
    with the plate's table: adds their forces to ``Q`` (and their stiffness to a 17 x 17
    ``K``: then solved together, :func:`plate_forces`; else one sweep, :func:`plate_sweep`),
    the resultant force on crank j to its channel.  Returns (energy, dissipated power)."""
    clearance = P[SUP_CLEAR_U] if upper else P[SUP_CLEAR_L]
    # one scratch array (this runs twice per time step): the housing-frame table, the
    # approach vectors and rates, the bore centres, the forces, their magnitudes, the
    # bushings' (stiffness, n^T C n) and the quasi-static tangent
    work = np.empty(58)
    cm = work[:16].reshape((4, 4))
    r, rate, bore, s = work[16:20], work[20:24], work[24:28], work[28:32]
    guess, own, sm = work[32:34], work[34:38].reshape((2, 2)), work[38:54].reshape((4, 4))
    _table(P, q[CARRIER] + crank_angles[0], cm)   # the table's x axis: through crank 0's bore
    col = elastic.shape[1] - COLUMNS + (2 if upper else 0)
    slot = SUP_SLOT0 + (1 if upper else 0)
    shift = 2 if upper else 0
    wc = v[CARRIER]
    for j in range(2):
        b = CRANK0 + CRANK_STRIDE * j + shift
        bx, by = bore_centre(P, q, j, crank_angles[j])
        bore[2 * j], bore[2 * j + 1] = bx, by
        r[2 * j], r[2 * j + 1] = q[b] - bx, q[b + 1] - by
        rate[2 * j], rate[2 * j + 1] = v[b] + wc * by, v[b + 1] - wc * bx
        s[2 * j], s[2 * j + 1] = elastic[j, col], elastic[j, col + 1]
        guess[j] = elastic[j, slot]
        own[j, 0] = own[j, 1] = 0.0
    want = K.shape[0] > 0
    if want:
        # start from the stored forces where they point along the rigid approach (the same
        # equilibrium search); else (another pose) along it with the stored magnitude
        for j in range(2):
            dist = math.sqrt(r[2 * j] ** 2 + r[2 * j + 1] ** 2)
            f = guess[j] if dist > clearance else 0.0
            if f > 0.0 and s[2 * j] * r[2 * j] + s[2 * j + 1] * r[2 * j + 1] > 0.999 * f * dist:
                continue
            s[2 * j] = f * r[2 * j] / dist if f > 0.0 else 0.0
            s[2 * j + 1] = f * r[2 * j + 1] / dist if f > 0.0 else 0.0
        energy, _, _ = plate_forces(P, upper, clearance, r, cm, s, guess, own, sm)
        for j in range(2):
            if own[j, 0] > 0.0:
                own[j, 0] = 1.0 / (1.0 / own[j, 0] + own[j, 1])
    else:
        energy = plate_sweep(P, upper, clearance, r, cm, s, guess, own)
    power = 0.0
    for j in range(2):
        b = CRANK0 + CRANK_STRIDE * j + shift
        sx, sy = s[2 * j], s[2 * j + 1]
        f = math.sqrt(sx * sx + sy * sy)
        elastic[j, col], elastic[j, col + 1] = sx, sy
        elastic[j, slot] = f
        channel[CH_SUP_FL0 + 2 * j + (1 if upper else 0)] = 0.0
        if f == 0.0:
            continue
        nx, ny = sx / f, sy / f
        # damping 2 zeta sqrt(k m) at the series stiffness, on the rigid bore's approach rate
        total, pw = damped(f, own[j, 0], nx * rate[2 * j] + ny * rate[2 * j + 1], P[ZETA],
                           P[M_NODE])
        power += pw
        channel[CH_SUP_FL0 + 2 * j + (1 if upper else 0)] = total
        # the force acts on the displaced bore b + u, u = C S
        ux = uy = 0.0
        for m in range(4):
            ux += cm[2 * j, m] * s[m]
            uy += cm[2 * j + 1, m] * s[m]
        Q[b] -= total * nx
        Q[b + 1] -= total * ny
        Q[CARRIER] += total * ((bore[2 * j] + ux) * ny - (bore[2 * j + 1] + uy) * nx)
    if want:
        _stiffness(K, shift, cm, s, bore, sm)
    return energy, power
