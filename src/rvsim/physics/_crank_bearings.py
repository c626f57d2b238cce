"""The crank bearings (numba; docs/model.md sections 6, 7 and 17): the arm bushings or needle
bearings of the eccentrics in the discs' holes (or the finite-element crank's pair), the
support bushings or tapered roller bearings in the carrier and flange, their stiffness
matrices, and :func:`crank_bearings`, the one call of them per force evaluation (moved out of
``dynamics/_kernel.py``, issue 31 step 9)."""

from __future__ import annotations

import math

import numba
import numpy as np

from .._cache_guard import invalidate_stale_cache
from .._jit import CACHE, NO_REFCOUNT, REFCOUNT

invalidate_stale_cache(__file__)

from ._bearings import (conforming_force_carried, conforming_force_from,  # noqa: E402
                        radial_stiffness, roller_set)
from ._contact_law import damped  # noqa: E402
from ._fe_carrier import bore_centre_at, plate_supports  # noqa: E402
from ._fe_crank import arm_law, compliance_torque, crank_compliance, pair_forces  # noqa: E402
from ._fe_holes import add_hole_load, begin_arms, end_arms  # noqa: E402
from ._frames import (add_crank_force, angle_trig, crank_point, disc_trig,  # noqa: E402
                      eccentric_angle, eccentric_trig, hole_station)
from ._friction import arm_bearing_friction, support_bearing_friction  # noqa: E402
from ._layout import (ARM_A1, ARM_A2, ARM_C, ARM_CAGE_IN, ARM_CB, ARM_CLEAR, ARM_J1,  # noqa: E402
                      ARM_J2, ARM_KIND, ARM_ROLLERS, ARM_SHIFT, BUSH_COLUMNS,
                      BUSH_SLOT0, CARRIER, CH_ARM_F00, CH_SUP_FL0, CRANK0,
                      CRANK_COUNT, CRANK_STRIDE, DISC0, DISC_COUNT, DISC_STRIDE, ECC,
                      ECC_ERR0, FE_CRANK_SLOT0, FE_CRANK_XX1, FE_PLATE_XX1,
                      FRICTION_ON, M_NODE, SUP_A1, SUP_A2_L, SUP_A2_U, SUP_C,
                      SUP_CAGE_IN, SUP_CLEAR_L, SUP_CLEAR_U, SUP_COS_ALPHA, SUP_J1,
                      SUP_J2, SUP_KIND, SUP_ROLLERS, SUP_SHIFT_L, SUP_SHIFT_U,
                      SUP_SLOT0, ZETA)
from ._pins import CARRY_REFRESH  # noqa: E402


@numba.njit(cache=CACHE, inline="always")
def _material_stiffness(K, index, gx, gy, kxx, kxy, kyy, cx, cy, w_in, inner, outer):
    """K += J^T dS/dr J + J^T dS/dcage dcage/dq of a radial element of the crank bearings, J
    = (gx, gy) the rows d r / d q[index], dS/dr = [[kxx, kxy], [kxy, kyy]], dS/dcage = (cx,
    cy) and the cage angle w_in q[inner] + (1 - w_in) q[outer] (the arm and the support
    elements' common part: :func:`arm_stiffness`, :func:`support_stiffness`)."""
    for a in range(len(index)):
        ax = kxx * gx[a] + kxy * gy[a]
        ay = kxy * gx[a] + kyy * gy[a]
        for c in range(len(index)):
            K[index[c], index[a]] += gx[c] * ax + gy[c] * ay
        cage = gx[a] * cx + gy[a] * cy
        K[index[a], inner] += w_in * cage
        K[index[a], outer] += (1.0 - w_in) * cage


@numba.njit(**NO_REFCOUNT)
def arm_stiffness(K, b, d, wl, wu, ecc, cos_p, sin_p, lx, ly, kxx, kxy, kyy, sx, sy, cx, cy,
                  w_in):
    """Stiffness matrix -dQ/dq of an arm element whose elastic force S (on the disc hole;
    -S on the eccentric) depends on r = eccentric centre - hole centre with dS/dr = [[kxx,
    kxy], [kxy, kyy]] and on the cage angle w_in phi + (1 - w_in) theta_disc with dS/dcage
    = (cx, cy) (crank coordinates from b, disc from d; (lx, ly) the hole centre from the disc
    centre): J^T dS/dr J + J^T dS/dcage dcage/dq + S . d2r/dq2."""
    index = (b, b + 1, b + 2, b + 3, b + 4, d, d + 1, d + 2)
    gx = (wl, 0.0, wu, 0.0, -ecc * sin_p, -1.0, 0.0, ly)
    gy = (0.0, wl, 0.0, wu, ecc * cos_p, 0.0, -1.0, -lx)
    _material_stiffness(K, index, gx, gy, kxx, kxy, kyy, cx, cy, w_in, b + 4, d + 2)
    K[b + 4, b + 4] -= ecc * (sx * cos_p + sy * sin_p)
    K[d + 2, d + 2] += sx * lx + sy * ly


@numba.njit(**NO_REFCOUNT)
def support_stiffness(K, b, phi, bx, by, kxx, kxy, kyy, sx, sy, cx, cy, w_in):
    """Stiffness matrix of a support element (node coordinates from b, crank rotation at
    ``phi``, bore centre (bx, by) on the carrier), as :func:`arm_stiffness`."""
    index = (b, b + 1, CARRIER)
    gx = (1.0, 0.0, by)
    gy = (0.0, 1.0, -bx)
    _material_stiffness(K, index, gx, gy, kxx, kxy, kyy, cx, cy, w_in, phi, CARRIER)
    K[CARRIER, CARRIER] += sx * bx + sy * by


@numba.njit(**NO_REFCOUNT)
def _bushing(rx, ry, vx, vy, clearance, j1, a1, j2, a2, cb, zeta, mass, elastic, row, slot,
             carry, shift, want):
    """Conforming bushing on the relative position r of journal and bore (``shift``: ln(a2 /
    a1)): returns (Sx, Sy, energy, power, force, elastic force vector (x, y), kxx, kxy, kyy),
    the stiffness dS/dr of the elastic force only with ``want`` (zero otherwise).

    ``elastic[row, slot]`` holds the bushing's elastic force from step to step and
    ``elastic[row, carry .. carry + 4]`` what its Newton start needs besides (the force they
    belong to, the approach, the stiffness, ln(a1 / F), and the calls since the logarithm was
    last computed afresh: _layout.BUSH_SLOT0): the start is the Taylor predictor of
    :func:`~rvsim.physics._bearings.conforming_force_from` where they belong to the force
    held, the force held otherwise (something else set it) and at every CARRY_REFRESH-th
    call (a reviewer measured the carried logarithm's round-off growing by 4e-17 per call
    without it)."""
    dist = math.sqrt(rx * rx + ry * ry)
    delta = dist - clearance
    if delta <= 0.0 or dist < 1e-15:
        elastic[row, slot] = 0.0
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    inv_dist = 1.0 / dist
    nx, ny = rx * inv_dist, ry * inv_dist
    guess = elastic[row, slot]
    calls = elastic[row, carry + 4]       # since the last start afresh: ln(a1 / F) is carried
    if guess > 0.0 and elastic[row, carry] == guess and calls < CARRY_REFRESH:
        elastic[row, carry + 4] = calls + 1.0
        f, k, energy, log = conforming_force_from(
            delta, j1, a1, j2, a2, cb, shift, guess, elastic[row, carry + 1],
            elastic[row, carry + 2], elastic[row, carry + 3])
    else:       # a new logarithm every CARRY_REFRESH calls: its series' round-off cannot grow
        elastic[row, carry + 4] = 0.0
        f, k, energy, log = conforming_force_carried(delta, j1, a1, j2, a2, cb, guess, shift)
    elastic[row, slot] = f
    elastic[row, carry] = f
    elastic[row, carry + 1] = delta
    elastic[row, carry + 2] = k
    elastic[row, carry + 3] = log
    fn, power = damped(f, k, nx * vx + ny * vy, zeta, mass)
    kxx = kxy = kyy = 0.0
    if want:
        kxx, kxy, kyy = radial_stiffness(nx, ny, k, f, dist)
    return fn * nx, fn * ny, energy, power, fn, f * nx, f * ny, kxx, kxy, kyy


@numba.njit(cache=CACHE, inline="always")
def _rolling(P, rx, ry, vx, vy, rollers, cage, c, clearance, cos_alpha):
    """A rolling bearing in place of a bushing (arm needles or support tapered rollers):
    :func:`~rvsim.physics._bearings.roller_set` with the contacts' damping, and its resultant
    force: (Sx, Sy, energy, power, |S|, kxx, kxy, kyy, dS/dcage x, y)."""
    sx, sy, energy, power, _, kxx, kxy, kyy, cx, cy = roller_set(
        rx, ry, vx, vy, rollers, cage, c, clearance, cos_alpha, P[ZETA], P[M_NODE])
    return sx, sy, energy, power, math.sqrt(sx * sx + sy * sy), kxx, kxy, kyy, cx, cy


@numba.njit(**NO_REFCOUNT)
def arm_geometry(P, q, v, crank, disc, hole_x, hole_y, wl, wu, cos_t, sin_t, cos_p, sin_p):
    """Crank ``crank``'s eccentric for disc ``disc`` and that disc's hole: (rx, ry, vx, vy,
    phi, ecc, cos phi, sin phi, hx, hy), r = eccentric centre - hole centre and v its rate,
    phi the eccentric's direction, (hx, hy) the hole centre.  (cos_t, sin_t) of the disc's
    rotation, (cos_p, sin_p) of phi: :func:`arm_trig`."""
    ax, ay, avx, avy = crank_point(q, v, crank, wl, wu)
    b = CRANK0 + CRANK_STRIDE * crank
    phi = eccentric_angle(P, q, crank, disc)
    ecc = P[ECC] + P[ECC_ERR0 + 2 * crank + disc]
    ex = ax + ecc * cos_p
    ey = ay + ecc * sin_p
    evx = avx - ecc * sin_p * v[b + 4]
    evy = avy + ecc * cos_p * v[b + 4]
    d = DISC0 + DISC_STRIDE * disc
    hx = q[d] + cos_t * hole_x - sin_t * hole_y
    hy = q[d + 1] + sin_t * hole_x + cos_t * hole_y
    hvx = v[d] - v[d + 2] * (hy - q[d + 1])
    hvy = v[d + 1] + v[d + 2] * (hx - q[d])
    return ex - hx, ey - hy, evx - hvx, evy - hvy, phi, ecc, cos_p, sin_p, hx, hy


@numba.njit(**NO_REFCOUNT)
def apply_arm_force(Q, q, crank, disc, wl, wu, ecc, cos_p, sin_p, hx, hy, sx, sy):
    """Generalised forces of an arm element's force (sx, sy) on the disc hole (-S on the
    eccentric)."""
    b = CRANK0 + CRANK_STRIDE * crank
    d = DISC0 + DISC_STRIDE * disc
    fx, fy = -sx, -sy                                # on the crank
    add_crank_force(Q, crank, wl, wu, fx, fy)
    Q[b + 4] += fx * (-ecc * sin_p) + fy * (ecc * cos_p)
    Q[d] -= fx
    Q[d + 1] -= fy
    Q[d + 2] -= -fx * (hy - q[d + 1]) + fy * (hx - q[d])


@numba.njit(**NO_REFCOUNT)
def arm_bushing(P, q, v, Q, K, want, crank, disc, hole_x, hole_y, wl, wu, elastic, cos_t, sin_t,
                cos_p, sin_p):
    """Crank ``crank``'s eccentric in disc ``disc``'s hole: the paper's bushing (a conforming
    contact, :func:`~rvsim.physics._bearings.conforming_force`) or a needle roller bearing
    (:func:`~rvsim.physics._bearings.roller_set`; P[ARM_KIND]).

    ``elastic[crank, disc]`` carries the bushing's elastic force from step to step (Newton
    start).  ``K`` (17 x 17, or 0 x 0) accumulates the exact stiffness matrix of the elastic
    force (:func:`arm_stiffness`).  (cos_t, sin_t, cos_p, sin_p): :func:`arm_trig`.  Returns
    (resultant force, energy, dissipated power)."""
    rx, ry, rvx, rvy, phi, ecc, cos_p, sin_p, hx, hy = arm_geometry(
        P, q, v, crank, disc, hole_x, hole_y, wl, wu, cos_t, sin_t, cos_p, sin_p)
    b = CRANK0 + CRANK_STRIDE * crank
    d = DISC0 + DISC_STRIDE * disc
    cx = cy = 0.0
    w_in = P[ARM_CAGE_IN]
    if P[ARM_KIND] == 1.0:
        cage = w_in * phi + (1.0 - w_in) * q[d + 2]
        sx, sy, energy, power, fn, kxx, kxy, kyy, cx, cy = _rolling(
            P, rx, ry, rvx, rvy, P[ARM_ROLLERS], cage, P[ARM_C], P[ARM_CLEAR], 1.0)
        ex_el, ey_el = sx, sy
        if fn == 0.0:
            return 0.0, 0.0, 0.0
    else:
        sx, sy, energy, power, fn, ex_el, ey_el, kxx, kxy, kyy = _bushing(
            rx, ry, rvx, rvy, P[ARM_CLEAR], P[ARM_J1], P[ARM_A1], P[ARM_J2],
            P[ARM_A2], P[ARM_CB], P[ZETA], P[M_NODE], elastic, crank, disc,
            BUSH_SLOT0 + BUSH_COLUMNS * disc, P[ARM_SHIFT], want)
        if fn == 0.0 and elastic[crank, disc] == 0.0:
            return 0.0, 0.0, 0.0
    add_hole_load(P, q, elastic, crank, disc, ex_el, ey_el)     # the holes' Q (_fe_holes)
    if want:
        arm_stiffness(K, b, d, wl, wu, ecc, cos_p, sin_p, hx - q[d], hy - q[d + 1], kxx, kxy,
                      kyy, ex_el, ey_el, cx, cy, w_in)
    apply_arm_force(Q, q, crank, disc, wl, wu, ecc, cos_p, sin_p, hx, hy, sx, sy)
    return fn, energy, power


@numba.njit(**REFCOUNT)
def arm_pair(P, q, v, Q, K, want, crank, holes, elastic):
    """Crank ``crank``'s two eccentrics in their discs' holes with the finite-element crank
    between them (docs/model.md section 17; :mod:`rvsim.physics._fe_crank`): the two arm
    bushings solved together, to convergence with ``K`` wanted (the quasi-static engine), one
    Gauss-Seidel sweep per step otherwise (the dynamic engine).  Each bushing is damped at its
    tangent stiffness in series with the crank (the diagonal of dS/dr along its force).
    Returns (energy, dissipated power, resultant force on disc 0, on disc 1)."""
    b = CRANK0 + CRANK_STRIDE * crank
    # one work array per call (views of it: no allocation per quantity, this runs every step)
    work = np.empty((2, 17))
    r, rate, guess, force = work[:, 0:2], work[:, 2:4], work[:, 4:6], work[:, 6:8]
    geo = work[:, 8:16]              # wl, wu, ecc, cos phi, sin phi, hx, hy, series stiffness
    c0, s0, c1, s1 = eccentric_trig(P, q, crank)      # both eccentrics: one cosine and sine
    for disc in range(2):
        wl, wu, hole_x, hole_y = hole_station(P, holes, crank, disc, elastic)
        cos_t, sin_t = disc_trig(q, disc)
        cos_p, sin_p = (c0, s0) if disc == 0 else (c1, s1)
        rx, ry, rvx, rvy, _, ecc, cos_p, sin_p, hx, hy = arm_geometry(
            P, q, v, crank, disc, hole_x, hole_y, wl, wu, cos_t, sin_t, cos_p, sin_p)
        r[disc, 0], r[disc, 1], rate[disc, 0], rate[disc, 1] = rx, ry, rvx, rvy
        geo[disc, 0], geo[disc, 1], geo[disc, 2] = wl, wu, ecc
        geo[disc, 3], geo[disc, 4], geo[disc, 5], geo[disc, 6] = cos_p, sin_p, hx, hy
    mats = np.empty((4, 8))
    A = mats[:, 0:4]
    crank_compliance(P, q[b + 4], A)
    for disc in range(2):
        guess[disc, 0] = elastic[crank, FE_CRANK_SLOT0 + 2 * disc]
        guess[disc, 1] = elastic[crank, FE_CRANK_SLOT0 + 2 * disc + 1]
    series = work[:, 15]
    dsdr = mats[:, 4:8]
    energy = pair_forces(arm_law(P), A, r, guess, force, dsdr, series, want)
    power = 0.0
    resultant = work[:, 16]                  # force on each disc, damping included
    for disc in range(2):
        sx, sy = force[disc, 0], force[disc, 1]
        elastic[crank, FE_CRANK_SLOT0 + 2 * disc] = sx
        elastic[crank, FE_CRANK_SLOT0 + 2 * disc + 1] = sy
        add_hole_load(P, q, elastic, crank, disc, sx, sy)     # the holes' Q (_fe_holes)
        f = math.sqrt(sx * sx + sy * sy)
        elastic[crank, disc] = f
        resultant[disc] = f
        if f == 0.0:
            continue
        nx, ny = sx / f, sy / f
        fn, pw = damped(f, series[disc], nx * rate[disc, 0] + ny * rate[disc, 1], P[ZETA],
                        P[M_NODE])
        power += pw
        resultant[disc] = fn
        apply_arm_force(Q, q, crank, disc, geo[disc, 0], geo[disc, 1], geo[disc, 2],
                        geo[disc, 3], geo[disc, 4], geo[disc, 5], geo[disc, 6], fn * nx,
                        fn * ny)
    # the table turns with the crank: -dU/dphi at fixed relative positions
    Q[b + 4] += compliance_torque(A, force)
    if want:
        arm_pair_stiffness(K, q, crank, geo, dsdr, force, P[ARM_CAGE_IN])
    return energy, power, resultant[0], resultant[1]


@numba.njit(cache=CACHE, inline="always")
def _arm_rows(q, geo, disc):
    """d r / d(crank b..b+4, disc d..d+2) of eccentric ``disc``'s relative position (x and y
    rows; :func:`arm_stiffness`)."""
    d = DISC0 + DISC_STRIDE * disc
    wl, wu, ecc, cos_p, sin_p = geo[disc, 0], geo[disc, 1], geo[disc, 2], geo[disc, 3], \
        geo[disc, 4]
    lx, ly = geo[disc, 5] - q[d], geo[disc, 6] - q[d + 1]
    return ((wl, 0.0, wu, 0.0, -ecc * sin_p, -1.0, 0.0, ly),
            (0.0, wl, 0.0, wu, ecc * cos_p, 0.0, -1.0, -lx), lx, ly)


@numba.njit(**NO_REFCOUNT)
def arm_pair_stiffness(K, q, crank, geo, dsdr, force, w_in):
    """Stiffness matrix of :func:`arm_pair`: J^T (dS/dr) J over both eccentrics (the crank
    couples them) and each element's S . d2r/dq2 (:func:`arm_stiffness` with no material
    term).  The turning of the table with phi is left out (its torque is second order in the
    crank's anisotropy)."""
    b = CRANK0 + CRANK_STRIDE * crank
    for k in range(2):
        gx, gy, lx, ly = _arm_rows(q, geo, k)
        dk = DISC0 + DISC_STRIDE * k
        arm_stiffness(K, b, dk, geo[k, 0], geo[k, 1], geo[k, 2], geo[k, 3], geo[k, 4], lx,
                      ly, 0.0, 0.0, 0.0, force[k, 0], force[k, 1], 0.0, 0.0, w_in)
        for m in range(2):
            hx, hy, _, _ = _arm_rows(q, geo, m)
            dm = DISC0 + DISC_STRIDE * m
            sxx, sxy = dsdr[2 * k, 2 * m], dsdr[2 * k, 2 * m + 1]
            syx, syy = dsdr[2 * k + 1, 2 * m], dsdr[2 * k + 1, 2 * m + 1]
            for c in range(8):
                ax = sxx * hx[c] + sxy * hy[c]
                ay = syx * hx[c] + syy * hy[c]
                col = b + c if c < 5 else dm + c - 5
                for a in range(8):
                    row = b + a if a < 5 else dk + a - 5
                    K[row, col] += gx[a] * ax + gy[a] * ay


@numba.njit(**NO_REFCOUNT)
def support_bushing(P, q, v, Q, K, want, crank, upper, bx, by, elastic):
    """Crank ``crank``'s lower or upper support node in its carrier / flange bore: the paper's
    bushing (conforming contact) or a tapered roller bearing (P[SUP_KIND]).

    (bx, by): the centre of the crank's bores (:func:`~rvsim.physics._fe_carrier.bore_centre`,
    the same for both supports).  ``elastic[crank, SUP_SLOT0 + upper]`` carries the bushing's
    elastic force from step to step (Newton start, as in :func:`arm_bushing`).
    ``K`` (17 x 17, or 0 x 0) accumulates the exact stiffness matrix of the elastic force (as in
    :func:`arm_bushing`).  Returns (resultant force, energy, dissipated power)."""
    b = CRANK0 + CRANK_STRIDE * crank + (2 if upper else 0)
    phi = CRANK0 + CRANK_STRIDE * crank + 4
    rx, ry = q[b] - bx, q[b + 1] - by
    wc = v[CARRIER]
    vx, vy = v[b] + wc * by, v[b + 1] - wc * bx
    clearance = P[SUP_CLEAR_U] if upper else P[SUP_CLEAR_L]
    cx = cy = 0.0
    w_in = P[SUP_CAGE_IN]
    if P[SUP_KIND] == 1.0:
        cage = w_in * q[phi] + (1.0 - w_in) * q[CARRIER]
        sx, sy, energy, power, fn, kxx, kxy, kyy, cx, cy = _rolling(
            P, rx, ry, vx, vy, P[SUP_ROLLERS], cage, P[SUP_C], clearance, P[SUP_COS_ALPHA])
        ex_el, ey_el = sx, sy
        if fn == 0.0:
            return 0.0, 0.0, 0.0
    else:
        a2 = P[SUP_A2_U] if upper else P[SUP_A2_L]
        slot = SUP_SLOT0 + (1 if upper else 0)
        sx, sy, energy, power, fn, ex_el, ey_el, kxx, kxy, kyy = _bushing(
            rx, ry, vx, vy, clearance, P[SUP_J1], P[SUP_A1], P[SUP_J2], a2, 0.0, P[ZETA],
            P[M_NODE], elastic, crank, slot, BUSH_SLOT0 + BUSH_COLUMNS * slot,
            P[SUP_SHIFT_U] if upper else P[SUP_SHIFT_L], want)
        if fn == 0.0 and elastic[crank, slot] == 0.0:
            return 0.0, 0.0, 0.0
    if want:
        support_stiffness(K, b, phi, bx, by, kxx, kxy, kyy, ex_el, ey_el, cx, cy, w_in)
    Q[b] -= sx
    Q[b + 1] -= sy
    Q[CARRIER] += -sx * by + sy * bx
    return fn, energy, power


@numba.njit(**NO_REFCOUNT)
def crank_bearings(P, q, v, Q, K, want, holes, crank_angles, arm_elastic, channel, n_discs,
                   trig):
    """The cranks' arm bushings (or the FE crank's pairs) and support bushings (or the FE
    plates), with their friction: adds to ``Q`` (and ``K``) and the force channels; returns
    (potential energy, dissipated power).  One call from :func:`forces_at` (a separate
    function: the calls of the bearing elements from the inlined step loop cost more than
    their arithmetic, measured in docs/benchmarks.md, issue 14).  ``trig``: the cosines and
    sines of :func:`angle_trig`."""
    energy = 0.0
    power = 0.0
    coupled = P[FE_CRANK_XX1] > 0.0     # finite-element crank (RV reducers only)
    begin_arms(P, arm_elastic)          # the FE disc's crank holes (physics._fe_holes)
    for j in range(int(P[CRANK_COUNT])):
        pair0 = pair1 = 0.0
        c0 = s0 = c1 = s1 = 0.0
        if coupled:     # both bushings together
            e, pw, pair0, pair1 = arm_pair(P, q, v, Q, K, want, j, holes, arm_elastic)
            energy += e
            power += pw
        else:
            c0, s0, c1, s1 = eccentric_trig(P, q, j)     # one cosine and sine per crank
        for disc in range(n_discs):
            if coupled:
                force = pair0 if disc == 0 else pair1
                channel[CH_ARM_F00 + 2 * j + disc] = force
                if P[FRICTION_ON] == 1.0:
                    power += arm_bearing_friction(P, v, Q, j, disc, force)
                continue
            wl, wu, hole_x, hole_y = hole_station(P, holes, j, disc, arm_elastic)
            cos_p, sin_p = (c0, s0) if disc == 0 else (c1, s1)
            force, e, pw = arm_bushing(P, q, v, Q, K, want, j, disc, hole_x, hole_y, wl, wu,
                                       arm_elastic, trig[4 + 2 * disc], trig[5 + 2 * disc],
                                       cos_p, sin_p)
            channel[CH_ARM_F00 + 2 * j + disc] = force
            energy += e
            power += pw
            if P[FRICTION_ON] == 1.0:
                power += arm_bearing_friction(P, v, Q, j, disc, force)
        # one bore centre for both supports (the closed-form ones: none with the FE plates)
        bx, by = bore_centre_at(P, j, trig[2 * j], trig[2 * j + 1])
        for upper in range(2 if P[FE_PLATE_XX1] == 0.0 else 0):
            force, e, pw = support_bushing(P, q, v, Q, K, want, j, upper == 1, bx, by,
                                           arm_elastic)
            channel[CH_SUP_FL0 + 2 * j + upper] = force
            energy += e
            power += pw
            if P[FRICTION_ON] == 1.0:
                power += support_bearing_friction(P, v, Q, j, force)
    end_arms(P, arm_elastic)
    if P[FE_PLATE_XX1] != 0.0:    # finite-element carrier and flange (physics._fe_carrier)
        for upper in range(2):
            e, pw = plate_supports(P, q, v, Q, K, want, upper == 1, crank_angles, arm_elastic,
                                   channel)
            energy += e
            power += pw
            for j in range(2):
                if P[FRICTION_ON] == 1.0:
                    power += support_bearing_friction(P, v, Q, j,
                                                      channel[CH_SUP_FL0 + 2 * j + upper])
    return energy, power


@numba.njit(**NO_REFCOUNT)
def bearing_stiffness(P, q, v, Q_scratch, K, holes, crank_angles, arm_elastic, channel):
    """The crank bearings' stiffness into ``K`` (zeroed by the caller) at the state (q, v)
    whose forces were just evaluated (the scheme implicit-bearings, where a bearing's force
    has risen beyond what its factorisation holds): :func:`crank_bearings` again, its forces
    into ``Q_scratch`` (the same as the evaluation's, to round-off: every law starts from its
    carried solution at the same approach)."""
    for i in range(Q_scratch.shape[0]):
        Q_scratch[i] = 0.0
    # bool(): a flag typed boolean, not Literal[bool] (numba would compile the bearings once
    # more for a literal argument)
    crank_bearings(P, q, v, Q_scratch, K, bool(True), holes, crank_angles, arm_elastic, channel,
                   int(P[DISC_COUNT]), angle_trig(q, crank_angles))
