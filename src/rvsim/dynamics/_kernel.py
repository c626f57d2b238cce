"""Compiled time integration of the RV reducer (numba; arrays and scalars only, no raises).

One driver, :func:`integrate`, advances the 17 generalised coordinates with the semi-implicit
(symplectic) Euler scheme at a fixed step and returns a status code.  The force elements are
small functions; docs/model.md maps every symbol to its equation and source.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ._cache_guard import invalidate_stale_cache

# numba's on-disk cache is keyed on this file only; the index constants of _layout, the curve
# functions of geometry._curve, the contact law and the single-stage elements are compiled in,
# so clear the cache when those change (_cache_guard.DEPENDENCIES)
invalidate_stale_cache()

from ..geometry._curve import deviated_gap, pin_gap, pin_opening, profile_axes
from ._contact_law import EXPONENT, add_rank_one, contact, spring_force  # noqa: F401
from ._single_stage import input_shaft, output_pin
from ._layout import (BORE_DR0, BORE_DT0, ECC_ERR0, ECC_PHASE0)
from ._layout import (A_GEN, ARM_C, ARM_CB, ARM_CLEAR, BACKLASH, BASE_PITCH, CARRIER,
                      CENTRE_DIST, CH_ARM_F00, CH_MESH_F0, CH_OMEGA_IN, CH_OMEGA_OUT, CH_SUP_FL0,
                      CH_THETA_IN, CH_THETA_OUT, CH_TIME, CH_TORQUE_IN, CH_TORQUE_LOAD,
                      CONTACT_RATIO, CRANK0, CRANK_COUNT, CRANK_STRIDE, DISC0, DISC_COUNT,
                      DISC_STRIDE, DT, E_DISSIPATED,
                      E_INPUT, E_KIN0, E_KIN1, E_OUTPUT, E_PARAMETRIC, E_POT0, E_POT1, ECC,
                      FLUCT_AMP, FLUCT_FREQ, INPUT_SPEED, J_CARRIER, J_CRANK, J_DISC, K_MESH,
                      LOAD, LOAD_T0, LOAD_T1, M_DISC, M_NODE, MESH_MASS, MINV_LL, MINV_LU,
                      MINV_UU, MU, N_DOF, OUT_COUNT, OUT_SLOT0, PEN_LIMIT, PIN_C, PIN_CB,
                      PIN_RADIUS, PROFILE_OFFSET,
                      PROFILE_ROT, RAMP_TIME, RB1, RB2, RG, RUNOUT_X0, RUNOUT_X1, RUNOUT_Y0,
                      RUNOUT_Y1, SIN_AW, STAGES, STATUS_NONFINITE, STATUS_OK,
                      STATUS_PENETRATION, STEADY_START, SUP_C, SUP_CB, SUP_CLEAR_L, SUP_CLEAR_U,
                      V_FRIC, W_D1_L, W_D1_U, W_D2_L, W_D2_U, W_G_L, W_G_U, ZC, ZETA, ZP)

MAX_SKIP = 64          # longest skip of an open pin contact [steps]


@numba.njit(cache=True)
def step_function(t, t0, t1):
    """ADAMS STEP from 0 to 1 between t0 and t1 (cubic), and its integral from t0."""
    if t <= t0:
        return 0.0, 0.0
    if t >= t1:
        return 1.0, 0.5 * (t1 - t0) + (t - t1)
    d = (t - t0) / (t1 - t0)
    return d * d * (3.0 - 2.0 * d), (t1 - t0) * (d ** 3 - 0.5 * d ** 4)


@numba.njit(cache=True)
def input_motion(P, t):
    """Input angle and speed of Eq. (19): speed = STEP(t, 0, 0, T, omega)."""
    s, integral = step_function(t, 0.0, P[RAMP_TIME])
    return P[INPUT_SPEED] * integral, P[INPUT_SPEED] * s


@numba.njit(cache=True)
def load_torque(P, t):
    """Output load of Eqs. (20)/(21)."""
    s, _ = step_function(t, P[LOAD_T0], P[LOAD_T1])
    return P[LOAD] * s + P[FLUCT_AMP] * math.sin(2.0 * math.pi * P[FLUCT_FREQ] * t)


@numba.njit(cache=True)
def crank_point(q, v, j, wl, wu):
    """Position and velocity of crank j's axis at the axial station with weights (wl, wu)."""
    b = CRANK0 + CRANK_STRIDE * j
    return (wl * q[b] + wu * q[b + 2], wl * q[b + 1] + wu * q[b + 3],
            wl * v[b] + wu * v[b + 2], wl * v[b + 1] + wu * v[b + 3])


@numba.njit(cache=True)
def add_crank_force(Q, j, wl, wu, fx, fy):
    b = CRANK0 + CRANK_STRIDE * j
    Q[b] += wl * fx
    Q[b + 1] += wl * fy
    Q[b + 2] += wu * fx
    Q[b + 3] += wu * fy


@numba.njit(cache=True)
def gear_mesh(P, q, v, Q, K, j, crank_angle, phase, theta_in, omega_in, pairs, flank):
    """Sun-planet mesh j: returns (force, input torque, energy, dissipated power, stiffness,
    deflection, number of tooth pairs at the roll position, flank the rule picks).

    The mesh acts on one flank: the positive one if it is engaged, else the negative one (the
    rule; 0 returned for "none").  ``pairs`` > 0 holds the number of tooth pairs in contact and
    ``flank`` = +-1 the flank (the quasi-static solver keeps both during one equilibrium search:
    the rectangular-wave stiffness and the rule are discontinuous in q, the rule where the crank
    is pressed towards the sun so far that both flanks would touch); 0 takes them from the roll
    position and the rule.

    ``K`` (17 x 17, or 0 x 0: not wanted) accumulates the stiffness matrix -dQ/dq of the
    elastic force (material term k g g^T; the curvature of the line-of-centres angle is left
    out: docs/model.md, "Quasi-static analysis")."""
    px, py, pvx, pvy = crank_point(q, v, j, P[W_G_L], P[W_G_U])
    r2 = px * px + py * py
    r = math.sqrt(r2)
    # angle of the line of centres, kept continuous: carrier angle + assembly angle + deviation
    line = q[CARRIER] + crank_angle
    cos_l, sin_l = math.cos(line), math.sin(line)
    beta = line + math.atan2(-sin_l * px + cos_l * py, cos_l * px + sin_l * py)
    dbeta_x, dbeta_y = -py / r2, px / r2
    dr_x, dr_y = px / r, py / r
    rb1, rb2 = P[RB1], P[RB2]
    b = CRANK0 + CRANK_STRIDE * j
    rot = rb1 * (theta_in - beta) + rb2 * (q[b + 4] - beta) + (rb1 + rb2) * crank_angle
    radial = (r - P[CENTRE_DIST]) * P[SIN_AW]
    beta_rate = dbeta_x * pvx + dbeta_y * pvy
    rot_rate = rb1 * (omega_in - beta_rate) + rb2 * (v[b + 4] - beta_rate)
    radial_rate = (dr_x * pvx + dr_y * pvy) * P[SIN_AW]
    # number of tooth pairs in contact from the roll position (rectangular-wave stiffness)
    roll = (rb1 * (theta_in - beta)) / P[BASE_PITCH] + phase
    frac = roll - math.floor(roll)
    natural = 2.0 if frac < P[CONTACT_RATIO] - 1.0 else 1.0
    stiffness = P[K_MESH] * (pairs if pairs > 0.0 else natural)
    half = 0.5 * P[BACKLASH]
    force = 0.0
    sign = 0.0
    delta = 0.0
    rate = 0.0
    rule = 0.0
    if rot - radial - half > 0.0:
        rule = 1.0
    elif -rot - radial - half > 0.0:
        rule = -1.0
    chosen = rule if flank == 0.0 else flank
    if chosen > 0.0 and rot - radial - half > 0.0:
        sign, delta, rate = 1.0, rot - radial - half, rot_rate - radial_rate
    elif chosen < 0.0 and -rot - radial - half > 0.0:
        sign, delta, rate = -1.0, -rot - radial - half, -rot_rate - radial_rate
    energy = 0.0
    power = 0.0
    if sign != 0.0:
        damping = 2.0 * P[ZETA] * math.sqrt(stiffness * P[MESH_MASS])
        force = stiffness * delta + damping * rate
        if force < 0.0:
            force = 0.0
        energy = 0.5 * stiffness * delta * delta
        power = (force - stiffness * delta) * rate
        # generalised forces: Q = -F d(delta)/dq
        gx = sign * (-(rb1 + rb2) * dbeta_x) - P[SIN_AW] * dr_x
        gy = sign * (-(rb1 + rb2) * dbeta_y) - P[SIN_AW] * dr_y
        add_crank_force(Q, j, P[W_G_L], P[W_G_U], -force * gx, -force * gy)
        Q[b + 4] -= force * sign * rb2
        if K.shape[0] > 0:
            wl, wu = P[W_G_L], P[W_G_U]
            add_rank_one(K, (b, b + 1, b + 2, b + 3, b + 4),
                         (wl * gx, wl * gy, wu * gx, wu * gy, sign * rb2), stiffness)
    return force, force * sign * rb1, energy, power, stiffness, delta, natural, rule


@numba.njit(cache=True)
def pin_contacts(P, q, v, Q, K, disc, pins, pin_angle, u, next_eval, step, forces, elastic):
    """All pin contacts of disc ``disc``: returns (energy, dissipated power, max penetration).

    ``u[disc, i]`` holds the foot-point parameter as an offset from the pin's nominal parameter
    gamma_i - theta (exact in the kinematic pose).  Near contact one Newton step from the
    previous foot point converges; when it does not (first step, after a skip, a pin far from
    contact near the medial axis of a concave stretch of the curve, where the foot point is not
    unique) the nearest point is found robustly over one lobe period (geometry._curve.pin_gap).

    A pin whose gap cannot close before step ``next_eval[disc, i]`` is not evaluated: the gap
    is a 1-Lipschitz function of the pin centre in disc axes, whose speed is at most
    |dO/dt| + |dtheta/dt| * (pin circle + a), so a gap g stays open for g / (2 v dt) steps
    (factor 2 for speed changes within at most 64 steps).

    ``K`` (17 x 17, or 0 x 0) accumulates the material stiffness k g g^T of each contact, g the
    gradient of its gap (the profile-curvature term F d2gap/dq2 is left out).
    """
    d = DISC0 + DISC_STRIDE * disc
    ox, oy, th = q[d], q[d + 1], q[d + 2]
    vx, vy, w = v[d], v[d + 1], v[d + 2]
    zp = P[ZP]
    angle = th - disc * math.pi / P[ZC] + P[PROFILE_ROT]
    cos_t, sin_t = math.cos(angle), math.sin(angle)
    # housing velocity seen from the disc centre, in disc axes (rotation part added per pin)
    lvx, lvy = cos_t * vx + sin_t * vy, -sin_t * vx + cos_t * vy
    rg, a = P[RG], P[A_GEN]
    clearance = P[PROFILE_OFFSET] - P[PIN_RADIUS]
    runout_x = P[RUNOUT_X0] if disc == 0 else P[RUNOUT_X1]
    runout_y = P[RUNOUT_Y0] if disc == 0 else P[RUNOUT_Y1]
    speed_bound = 2.0 * (math.sqrt(vx * vx + vy * vy) + abs(w) * (P[RG] + 2.0 * a + 1e-3)) \
        * P[DT] + 1e-15
    energy = 0.0
    power = 0.0
    worst = 0.0
    want = K.shape[0] > 0
    n = pins.shape[0]
    for i in range(n):
        if step < next_eval[disc, i]:
            forces[disc, i] = 0.0
            elastic[disc, i] = 0.0
            continue
        qx, qy = profile_axes(pins[i, 0], pins[i, 1], ox, oy, cos_t, sin_t, runout_x, runout_y)
        nominal = pin_angle[i] - angle
        gap, ui, nx, ny = pin_gap(qx, qy, nominal, nominal + u[disc, i], rg, a, zp,
                                  clearance + pin_opening(pins, i), step > 0)
        gap, nx, ny = deviated_gap(pins, disc, ui, gap, nx, ny, rg, a, zp)  # per-part errors
        u[disc, i] = ui - nominal
        if gap >= 0.0:
            forces[disc, i] = 0.0
            elastic[disc, i] = 0.0
            skip = int(gap / speed_bound)
            next_eval[disc, i] = step + (skip if skip < MAX_SKIP else MAX_SKIP)
            continue
        next_eval[disc, i] = step + 1
        delta = -gap
        if delta > worst:
            worst = delta
        # pin centre from the disc centre (the profile centre is off it by the runout)
        px, py = qx + runout_x, qy + runout_y
        lever = nx * py - ny * px                    # d(gap)/d(theta)
        gap_rate = -(nx * lvx + ny * lvy) + w * lever
        fn, e, pw, fel, k = contact(delta, -gap_rate, P[PIN_C], P[PIN_CB], P[ZETA],
                                    P[M_DISC], elastic[disc, i])
        forces[disc, i] = fn
        elastic[disc, i] = fel
        energy += e
        power += pw
        # generalised forces Q = F d(gap)/dq on the disc
        gx = -(cos_t * nx - sin_t * ny)                 # d(gap)/d(x, y) of the disc
        gy = -(sin_t * nx + cos_t * ny)
        fx = fn * gx
        fy = fn * gy
        torque = fn * lever
        if want:
            add_rank_one(K, (d, d + 1, d + 2), (gx, gy, lever), k)
        if P[MU] > 0.0:
            # contact point on the disc (disc axes, from its centre) and sliding speed there
            cx = px - (P[PIN_RADIUS] - gap) * nx
            cy = py - (P[PIN_RADIUS] - gap) * ny
            tix, tiy = -ny, nx
            slide = (lvx - w * cy) * tix + (lvy + w * cx) * tiy
            ft = -P[MU] * fn * math.tanh(slide / P[V_FRIC])
            fx += ft * (cos_t * tix - sin_t * tiy)
            fy += ft * (sin_t * tix + cos_t * tiy)
            torque += ft * (cx * tiy - cy * tix)
            power -= ft * slide
        Q[d] += fx
        Q[d + 1] += fy
        Q[d + 2] += torque
    return energy, power, worst


@numba.njit(cache=True)
def arm_stiffness(K, b, d, wl, wu, nx, ny, ecc, cos_p, sin_p, lx, ly, k, force, dist):
    """Stiffness matrix of an arm bushing contact (crank coordinates from b, disc from d; (lx,
    ly) the hole centre from the disc centre): k g g^T + F/dist h h^T + F n . d2r/dq2."""
    index = (b, b + 1, b + 2, b + 3, b + 4, d, d + 1, d + 2)
    add_rank_one(K, index, (wl * nx, wl * ny, wu * nx, wu * ny,
                            ecc * (-nx * sin_p + ny * cos_p), -nx, -ny, nx * ly - ny * lx), k)
    tx, ty = -ny, nx
    add_rank_one(K, index, (wl * tx, wl * ty, wu * tx, wu * ty,
                            ecc * (-tx * sin_p + ty * cos_p), -tx, -ty, tx * ly - ty * lx),
                 force / dist)
    K[b + 4, b + 4] -= force * ecc * (nx * cos_p + ny * sin_p)
    K[d + 2, d + 2] += force * (nx * lx + ny * ly)


@numba.njit(cache=True)
def support_stiffness(K, b, nx, ny, bx, by, k, force, dist):
    """Stiffness matrix of a support bushing contact (node coordinates from b, bore centre
    (bx, by) on the carrier): k g g^T + F/dist h h^T + F n . d2r/dtheta_c^2."""
    add_rank_one(K, (b, b + 1, CARRIER), (nx, ny, nx * by - ny * bx), k)
    add_rank_one(K, (b, b + 1, CARRIER), (-ny, nx, -ny * by - nx * bx), force / dist)
    K[CARRIER, CARRIER] += force * (nx * bx + ny * by)


@numba.njit(cache=True)
def arm_bushing(P, q, v, Q, K, crank, disc, hole_x, hole_y, wl, wu, elastic):
    """Crank ``crank``'s eccentric in disc ``disc``'s hole through the arm bushing (K + M).

    ``elastic[crank, disc]`` carries the contact's elastic force from step to step (Newton
    start).  ``K`` (17 x 17, or 0 x 0) accumulates the exact stiffness matrix of the elastic
    force: k g g^T + F/dist h h^T (turning of the normal, h the gradient along the tangent)
    + F n . d2r/dq2 (the eccentric's and the hole's rotation)."""
    ax, ay, avx, avy = crank_point(q, v, crank, wl, wu)
    b = CRANK0 + CRANK_STRIDE * crank
    phi = q[b + 4] + disc * math.pi + P[ECC_PHASE0 + 2 * crank + disc]
    ecc = P[ECC] + P[ECC_ERR0 + 2 * crank + disc]
    cos_p, sin_p = math.cos(phi), math.sin(phi)
    ex = ax + ecc * cos_p
    ey = ay + ecc * sin_p
    evx = avx - ecc * sin_p * v[b + 4]
    evy = avy + ecc * cos_p * v[b + 4]
    d = DISC0 + DISC_STRIDE * disc
    cos_t, sin_t = math.cos(q[d + 2]), math.sin(q[d + 2])
    hx = q[d] + cos_t * hole_x - sin_t * hole_y
    hy = q[d + 1] + sin_t * hole_x + cos_t * hole_y
    hvx = v[d] - v[d + 2] * (hy - q[d + 1])
    hvy = v[d + 1] + v[d + 2] * (hx - q[d])
    rx, ry = ex - hx, ey - hy
    dist = math.sqrt(rx * rx + ry * ry)
    delta = dist - P[ARM_CLEAR]
    if delta <= 0.0 or dist < 1e-15:
        elastic[crank, disc] = 0.0
        return 0.0, 0.0, 0.0
    nx, ny = rx / dist, ry / dist
    rate = nx * (evx - hvx) + ny * (evy - hvy)
    fn, energy, power, elastic[crank, disc], k = contact(delta, rate, P[ARM_C], P[ARM_CB],
                                                         P[ZETA], P[M_NODE],
                                                         elastic[crank, disc])
    if K.shape[0] > 0:
        arm_stiffness(K, b, d, wl, wu, nx, ny, ecc, cos_p, sin_p, hx - q[d], hy - q[d + 1], k,
                      elastic[crank, disc], dist)
    fx, fy = -fn * nx, -fn * ny                      # on the crank
    add_crank_force(Q, crank, wl, wu, fx, fy)
    Q[b + 4] += fx * (-ecc * sin_p) + fy * (ecc * cos_p)
    Q[d] -= fx
    Q[d + 1] -= fy
    Q[d + 2] -= -fx * (hy - q[d + 1]) + fy * (hx - q[d])
    return fn, energy, power


@numba.njit(cache=True)
def support_bushing(P, q, v, Q, K, crank, upper, crank_angle):
    """Crank ``crank``'s lower or upper support node in its carrier / flange bore.

    ``K`` (17 x 17, or 0 x 0) accumulates the exact stiffness matrix of the elastic force (as in
    :func:`arm_bushing`)."""
    b = CRANK0 + CRANK_STRIDE * crank + (2 if upper else 0)
    carrier_angle = q[CARRIER] + crank_angle
    radius = P[CENTRE_DIST] + P[BORE_DR0 + crank]
    bx = radius * math.cos(carrier_angle) - P[BORE_DT0 + crank] * math.sin(carrier_angle)
    by = radius * math.sin(carrier_angle) + P[BORE_DT0 + crank] * math.cos(carrier_angle)
    rx, ry = q[b] - bx, q[b + 1] - by
    dist = math.sqrt(rx * rx + ry * ry)
    clearance = P[SUP_CLEAR_U] if upper else P[SUP_CLEAR_L]
    delta = dist - clearance
    if delta <= 0.0 or dist < 1e-15:
        return 0.0, 0.0, 0.0
    nx, ny = rx / dist, ry / dist
    wc = v[CARRIER]
    rate = nx * (v[b] + wc * by) + ny * (v[b + 1] - wc * bx)
    fn, energy, power, f_el, k = contact(delta, rate, P[SUP_C], P[SUP_CB], P[ZETA], P[M_NODE],
                                         0.0)
    if K.shape[0] > 0:
        support_stiffness(K, b, nx, ny, bx, by, k, f_el, dist)
    Q[b] -= fn * nx
    Q[b + 1] -= fn * ny
    Q[CARRIER] += fn * (-nx * by + ny * bx)
    return fn, energy, power


@numba.njit(cache=True)
def kinetic_energy(P, v):
    energy = 0.5 * P[J_CARRIER] * v[CARRIER] ** 2
    # crank node mass matrix: the inverse of [[LL, LU], [LU, UU]]
    det = P[MINV_LL] * P[MINV_UU] - P[MINV_LU] ** 2
    m_ll, m_lu, m_uu = P[MINV_UU] / det, -P[MINV_LU] / det, P[MINV_LL] / det
    for j in range(2):
        b = CRANK0 + CRANK_STRIDE * j
        for axis in range(2):
            v_low, v_up = v[b + axis], v[b + 2 + axis]
            energy += 0.5 * (m_ll * v_low * v_low + 2.0 * m_lu * v_low * v_up
                             + m_uu * v_up * v_up)
        energy += 0.5 * P[J_CRANK] * v[b + 4] ** 2
    for disc in range(2):
        d = DISC0 + DISC_STRIDE * disc
        energy += 0.5 * P[M_DISC] * (v[d] ** 2 + v[d + 1] ** 2) + 0.5 * P[J_DISC] * v[d + 2] ** 2
    return energy


@numba.njit(cache=True, inline="always")
def forces_at(P, q, v, theta_in, omega_in, torque_load, pins, pin_angle, holes, crank_angles,
              mesh_phase, u, next_eval, step, pin_force, pin_elastic, arm_elastic, Q, K,
              channel, mesh_state, mesh_hold):
    """Generalised forces Q at input angle and speed (theta_in, omega_in) under the output load
    ``torque_load``: the one evaluation of the force elements that both engines use.

    Fills the force channels and ``mesh_state`` (stiffness, deflection of each mesh); with a
    17 x 17 ``K`` (zeroed by the caller) it also accumulates the stiffness matrix -dQ/dq of the
    elastic forces (a 0 x 0 ``K``: not wanted).  ``mesh_hold[j]`` = (pairs, flank) held for mesh
    j (zeros: from the roll position and the flank rule, see :func:`gear_mesh`); with four
    columns, ``mesh_state`` also receives the pairs at the roll position and the rule's flank.
    Returns (potential energy, dissipated power,
    input torque, max pin penetration).
    """
    for i in range(N_DOF):
        Q[i] = 0.0
    energy = 0.0
    power = 0.0
    torque_in = 0.0
    single = P[STAGES] == 1.0
    if single:
        torque_in, energy, power = input_shaft(P, q, v, Q, K, theta_in, omega_in)
    else:
        for j in range(2):
            force, torque, e, pw, stiffness, deflection, natural, rule = gear_mesh(
                P, q, v, Q, K, j, crank_angles[j], mesh_phase[j], theta_in, omega_in,
                mesh_hold[j, 0], mesh_hold[j, 1])
            channel[CH_MESH_F0 + j] = force
            mesh_state[j, 0] = stiffness
            mesh_state[j, 1] = deflection
            if mesh_state.shape[1] > 3:
                mesh_state[j, 2] = natural
                mesh_state[j, 3] = rule
            torque_in += torque
            energy += e
            power += pw
    n_discs = int(P[DISC_COUNT])
    worst = 0.0
    for disc in range(n_discs):
        e, pw, pen = pin_contacts(P, q, v, Q, K, disc, pins, pin_angle, u, next_eval, step,
                                  pin_force, pin_elastic)
        energy += e
        power += pw
        if pen > worst:
            worst = pen
    for j in range(int(P[CRANK_COUNT])):
        for disc in range(n_discs):
            wl = P[W_D1_L] if disc == 0 else P[W_D2_L]
            wu = P[W_D1_U] if disc == 0 else P[W_D2_U]
            hole_x, hole_y = holes[j, 0], holes[j, 1]
            if holes.shape[1] > 2:          # per-disc hole offsets (per-part errors)
                hole_x += holes[j, 2 + 2 * disc]
                hole_y += holes[j, 3 + 2 * disc]
            force, e, pw = arm_bushing(P, q, v, Q, K, j, disc, hole_x, hole_y, wl, wu,
                                       arm_elastic)
            channel[CH_ARM_F00 + 2 * j + disc] = force
            energy += e
            power += pw
        for upper in range(2):
            force, e, pw = support_bushing(P, q, v, Q, K, j, upper == 1, crank_angles[j])
            channel[CH_SUP_FL0 + 2 * j + upper] = force
            energy += e
            power += pw
    if single:
        for disc in range(n_discs):
            for m in range(int(P[OUT_COUNT])):
                force, e, pw = output_pin(P, q, v, Q, K, disc, m, arm_elastic)
                energy += e
                power += pw
    Q[CARRIER] -= torque_load
    return energy, power, torque_in, worst


@numba.njit(cache=True, inline="always")
def forces(P, q, v, t, pins, pin_angle, holes, crank_angles, mesh_phase, u, next_eval, step,
           pin_force, pin_elastic, arm_elastic, Q, channel, mesh_state, K, mesh_hold):
    """Generalised forces Q at time t (:func:`forces_at` with the input motion and the load of
    the run's schedule). Returns (potential energy, dissipated power, input torque,
    load torque, max pin penetration, input angle, input speed)."""
    theta_in, omega_in = input_motion(P, t)
    torque_load = load_torque(P, t)
    energy, power, torque_in, worst = forces_at(
        P, q, v, theta_in, omega_in, torque_load, pins, pin_angle, holes, crank_angles,
        mesh_phase, u, next_eval, step, pin_force, pin_elastic, arm_elastic, Q, K, channel,
        mesh_state, mesh_hold)
    return energy, power, torque_in, torque_load, worst, theta_in, omega_in


#: slots of the integer ``counters`` array carried between calls of :func:`integrate`
COUNT_ROW, COUNT_IN_WINDOW = 0, 1


def new_state(n_pins, n_channels, n_output_pins=0):
    """Work arrays that :func:`integrate` carries from one call to the next (all zero at t = 0):
    (pin_angle, u, next_eval, pin_force, pin_elastic, arm_elastic, mesh_state, channel,
    counters).  ``arm_elastic`` has a column per output pin after the two crank columns."""
    pin_angle = 2.0 * np.pi * np.arange(n_pins) / n_pins
    return (pin_angle, np.zeros((2, n_pins)), np.zeros((2, n_pins), dtype=np.int64),
            np.zeros((2, n_pins)), np.zeros((2, n_pins)),
            np.zeros((2, OUT_SLOT0 + n_output_pins)), np.zeros((2, 2)),
            np.zeros(n_channels), np.zeros(2, dtype=np.int64))


@numba.njit(cache=True)
def integrate(P, q, v, first_step, stop_step, n_steps, sample_every, pins, holes, crank_angles,
              mesh_phase, pin_angle, u, next_eval, pin_force, pin_elastic, arm_elastic,
              mesh_state, channel, counters, channels, pin_forces, energy):
    """Advance from step ``first_step`` to ``stop_step`` (exclusive) of a run of ``n_steps``
    steps of size P[DT] that starts at t = 0; returns (status, next step).

    The caller integrates in chunks (so that it can be interrupted and show progress) and
    carries the state between calls: ``q``, ``v``, the work arrays of :func:`new_state` and
    ``energy``.  The last step, ``n_steps``, only evaluates and samples; after it the next step
    is ``n_steps + 1``.  Samples every ``sample_every`` steps into ``channels`` (rows) and
    ``pin_forces`` (rows x 2 discs x zp pins).  ``energy`` accumulates the steady-window
    balance.
    """
    dt = P[DT]
    Q = np.zeros(N_DOF)
    K = np.zeros((0, 0))
    mesh_hold = np.zeros((2, 2))
    previous_stiffness = np.zeros(2)
    row = counters[COUNT_ROW]
    in_window = counters[COUNT_IN_WINDOW] == 1
    status = STATUS_OK
    step = first_step
    while step < stop_step:
        t = step * dt
        for j in range(2):
            previous_stiffness[j] = mesh_state[j, 0]
        pot, diss, t_in, t_load, pen, theta_in, omega_in = forces(
            P, q, v, t, pins, pin_angle, holes, crank_angles, mesh_phase, u, next_eval, step,
            pin_force, pin_elastic, arm_elastic, Q, channel, mesh_state, K, mesh_hold)
        if in_window:
            # work done on the meshes by the stiffness change between steps (parametric)
            for j in range(2):
                energy[E_PARAMETRIC] += 0.5 * (mesh_state[j, 0] - previous_stiffness[j]) \
                    * mesh_state[j, 1] ** 2
        if not (math.isfinite(pot) and math.isfinite(q[CARRIER]) and math.isfinite(v[CARRIER])):
            status = STATUS_NONFINITE
            break
        if pen > P[PEN_LIMIT]:
            status = STATUS_PENETRATION
            break
        if step % sample_every == 0 and row < channels.shape[0]:
            channel[CH_TIME] = t
            channel[CH_THETA_IN] = theta_in
            channel[CH_OMEGA_IN] = omega_in
            channel[CH_THETA_OUT] = q[CARRIER]
            channel[CH_OMEGA_OUT] = v[CARRIER]
            channel[CH_TORQUE_IN] = t_in
            channel[CH_TORQUE_LOAD] = t_load
            channels[row, :] = channel
            pin_forces[row, :, :] = pin_force
            row += 1
        if step == n_steps:
            if in_window:
                energy[E_KIN1] = kinetic_energy(P, v)
                energy[E_POT1] = pot
            step += 1
            break
        if not in_window and t >= P[STEADY_START]:
            in_window = True
            energy[E_KIN0] = kinetic_energy(P, v)
            energy[E_POT0] = pot
        if in_window:
            # power flows over this step, velocities taken at the start of the step
            energy[E_INPUT] += t_in * omega_in * dt
            energy[E_OUTPUT] += t_load * v[CARRIER] * dt
            energy[E_DISSIPATED] += diss * dt
        # semi-implicit Euler: velocities first, then positions with the new velocities
        v[CARRIER] += dt * Q[CARRIER] / P[J_CARRIER]
        for j in range(2):
            b = CRANK0 + CRANK_STRIDE * j
            for axis in range(2):
                f_low, f_up = Q[b + axis], Q[b + 2 + axis]
                v[b + axis] += dt * (P[MINV_LL] * f_low + P[MINV_LU] * f_up)
                v[b + 2 + axis] += dt * (P[MINV_LU] * f_low + P[MINV_UU] * f_up)
            v[b + 4] += dt * Q[b + 4] / P[J_CRANK]
        for disc in range(2):
            d = DISC0 + DISC_STRIDE * disc
            v[d] += dt * Q[d] / P[M_DISC]
            v[d + 1] += dt * Q[d + 1] / P[M_DISC]
            v[d + 2] += dt * Q[d + 2] / P[J_DISC]
        for i in range(N_DOF):
            q[i] += dt * v[i]
        step += 1
    counters[COUNT_ROW] = row
    counters[COUNT_IN_WINDOW] = 1 if in_window else 0
    return status, step
