"""Compiled time integration of the RV reducer (numba; arrays and scalars only, no raises).

One driver, :func:`integrate`, advances the 17 generalised coordinates with the semi-implicit
(symplectic) Euler scheme at a fixed step (divided into sub-steps where the crank nodes'
stability guard needs it: dynamics._stiff_nodes) and returns a status code.  The force elements are
small functions; docs/model.md maps every symbol to its equation and source.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._cache_guard import invalidate_stale_cache
from .._jit import CACHE, NO_REFCOUNT, REFCOUNT

# numba's on-disk cache is keyed on this file only; the index constants of _layout, the curve
# functions of geometry._curve, the contact law and the single-stage elements are compiled in,
# so clear the cache when those change (_cache_guard.DEPENDENCIES)
invalidate_stale_cache()

from ..geometry._curve import deviated_gap, pin_gap, pin_opening, profile_axes
from ..physics._bearings import conforming_force_carried, conforming_force_from, radial_stiffness, \
    roller_set
from ..physics._contact_law import add_rank_one, damped, spring_force_from, spring_force_power
from ..physics._single_stage import input_shaft, output_pin, ring_forces, ring_frame
from ..physics._fe_contacts import apply_coupled
from ..physics._pin_compliance import pin_series_compliance
from ..physics._fe_modes import advance_modes, clear_modal_force, modal_energy
from ..physics._fe_carrier import bore_centre_at, plate_supports
from ..physics._fe_holes import add_hole_load, begin_arms, end_arms
from ..physics._fe_holes import free_stretch, hole_css, hole_row, hole_shift, holes_on
from ..physics._fe_crank import arm_law, compliance_torque, crank_compliance, pair_forces
from ..physics._friction import (arm_bearing_friction, mesh_friction, seal_friction,
                                 support_bearing_friction)
from ..physics._layout import (BUSH_COLUMNS, BUSH_SLOT0, ECC_ERR0, ECC_PHASE0, ECC_TURN0, FRAME_TURN0)
from ..physics._layout import (NODE_ALERT, NODE_CHECKS, NODE_CHECKS_STEADY, NODE_H, NODE_OMEGA_DT,
                               NODE_SUBSTEPS,
                               NODE_PEAK, NODE_REFRESH)
from ..physics._layout import (IMPLICIT_ALERTS, IMPLICIT_FACTORS, IMPLICIT_FALLBACKS, IMPLICIT_REFRESH,
                               IMPLICIT_SINCE, IMPLICIT_THETA)
from ._stiff_nodes import ALERT, node_kinetic, node_omega_dt, substeps_for
from ._implicit_bearings import (bearing_forces_risen, factor_effective_mass,
                                 record_bearing_forces, solve_factored)
from ..physics._layout import (A_GEN, ARM_A1, ARM_A2, ARM_C, ARM_CAGE_IN, ARM_CB, ARM_CLEAR, ARM_J1,
                               ARM_J2, ARM_KIND, ARM_ROLLERS, ARM_SHIFT, SUP_A1, SUP_A2_L, SUP_A2_U, SUP_CAGE_IN,
                               SUP_COS_ALPHA, SUP_J1, SUP_J2, SUP_KIND, SUP_ROLLERS, SUP_SHIFT_L, SUP_SHIFT_U, BACKLASH, BASE_PITCH, CARRIER,
                               CENTRE_DIST, CH_ARM_F00, CH_MESH_F0, CH_OMEGA_IN, CH_OMEGA_OUT, CH_SUP_FL0,
                               CH_PIN_MAX, CH_THETA_IN, CH_THETA_OUT, CH_TIME, CH_TORQUE_IN, CH_TORQUE_LOAD,
                               CONTACT_RATIO, CRANK0, CRANK_COUNT, CRANK_STRIDE, DISC0, DISC_COUNT,
                               DISC_STRIDE, DT, E_DISSIPATED, FE_CRANK_SLOT0, FE_CRANK_XX1, FRICTION_ON,
                               E_INPUT, E_PIN_PEAK, E_KIN0, E_KIN1, E_OUTPUT, E_PARAMETRIC, E_POT0, E_POT1, ECC,
                               FLUCT_AMP, FLUCT_FREQ, INPUT_SPEED, J_CARRIER, J_CRANK, J_DISC, K_MESH,
                               LOAD, LOAD_T0, LOAD_T1, M_DISC, M_NODE, MESH_MASS, MINV_LL, MINV_LU,
                               MINV_UU, MU, N_DOF, OUT_COUNT, OUT_SLOT0, PEN_LIMIT, PIN_C,
                               PIN_RADIUS, FE_PLATE_XX1, PROFILE_OFFSET,
                               PROFILE_ROT, RAMP_TIME, RB1, RB2, RG, RING_OUTPUT, RUNOUT_X0, RUNOUT_X1,
                               RUNOUT_Y0, RUNOUT_Y1, SEAL_IN, SEAL_OUT, SIN_AW, STAGES, STATUS_NONFINITE, STATUS_OK,
                               STATUS_PENETRATION, STEADY_START, SUP_C, SUP_CLEAR_L, SUP_CLEAR_U,
                               SUP_SLOT0, V_FRIC, W_D1_L, W_D1_U, W_D2_L, W_D2_U, W_G_L, W_G_U, ZC, ZETA,
                               ZP)

MAX_SKIP = 64          # longest skip of an open pin contact [force evaluations]
#: a pin's carried values (:func:`pin_loop`) are computed afresh at every CARRY_REFRESH-th
#: tick of the pin clock (pins staggered by their index), so their round-off cannot grow
CARRY_REFRESH = 64


@numba.njit(**NO_REFCOUNT)
def step_function(t, t0, t1):
    """ADAMS STEP from 0 to 1 between t0 and t1 (cubic), and its integral from t0."""
    if t <= t0:
        return 0.0, 0.0
    if t >= t1:
        return 1.0, 0.5 * (t1 - t0) + (t - t1)
    d = (t - t0) / (t1 - t0)
    return d * d * (3.0 - 2.0 * d), (t1 - t0) * (d ** 3 - 0.5 * d ** 4)


@numba.njit(**NO_REFCOUNT)
def input_motion(P, t):
    """Input angle and speed of Eq. (19): speed = STEP(t, 0, 0, T, omega)."""
    s, integral = step_function(t, 0.0, P[RAMP_TIME])
    return P[INPUT_SPEED] * integral, P[INPUT_SPEED] * s


@numba.njit(**NO_REFCOUNT)
def load_torque(P, t):
    """Output load of Eqs. (20)/(21)."""
    s, _ = step_function(t, P[LOAD_T0], P[LOAD_T1])
    return P[LOAD] * s + P[FLUCT_AMP] * math.sin(2.0 * math.pi * P[FLUCT_FREQ] * t)


@numba.njit(**NO_REFCOUNT)
def crank_point(q, v, j, wl, wu):
    """Position and velocity of crank j's axis at the axial station with weights (wl, wu)."""
    b = CRANK0 + CRANK_STRIDE * j
    return (wl * q[b] + wu * q[b + 2], wl * q[b + 1] + wu * q[b + 3],
            wl * v[b] + wu * v[b + 2], wl * v[b + 1] + wu * v[b + 3])


@numba.njit(**NO_REFCOUNT)
def add_crank_force(Q, j, wl, wu, fx, fy):
    b = CRANK0 + CRANK_STRIDE * j
    Q[b] += wl * fx
    Q[b + 1] += wl * fy
    Q[b + 2] += wu * fx
    Q[b + 3] += wu * fy


@numba.njit(cache=CACHE, inline="always")
def line_trig(q, crank_angle):
    """Cosine and sine of a crank's nominal angle about the centre, q[carrier] + its assembly
    angle: the line of centres of its mesh and the direction of its bores."""
    line = q[CARRIER] + crank_angle
    return math.cos(line), math.sin(line)


@numba.njit(cache=CACHE, inline="always")
def angle_trig(q, crank_angles):
    """The cosines and sines one force evaluation shares between its elements (one call per
    angle, docs/decisions.md): cranks 0 and 1's nominal angles (:func:`line_trig`), discs 0
    and 1's rotations (:func:`disc_trig`), as (cos, sin, cos, sin, cos, sin, cos, sin)."""
    c0, s0 = line_trig(q, crank_angles[0])
    c1, s1 = line_trig(q, crank_angles[1])
    d0, e0 = disc_trig(q, 0)
    d1, e1 = disc_trig(q, 1)
    return c0, s0, c1, s1, d0, e0, d1, e1


@numba.njit(**NO_REFCOUNT)
def gear_mesh(P, q, v, Q, K, j, crank_angle, phase, theta_in, omega_in, pairs, flank, cos_l,
              sin_l):
    """Sun-planet mesh j: returns (normal force, input torque, energy, dissipated power,
    stiffness, deflection, number of tooth pairs at the roll position, loaded flank).

    Both flanks are contacts of their own (docs/model.md section 3): the positive flank closes
    when rot - radial > backlash / 2, the negative one when -rot - radial > backlash / 2, rot
    the rotational approach along the line of action and radial the centre-distance change
    times sin(alpha_w).  A crank pressed towards the sun by more than half the backlash touches
    both (the tooth wedges into the gap): each carries its own force, the difference turns the
    gears, the sum pushes the planet out.  The returned force is the sum of the two normal
    forces, the torque on the input the difference times rb1, the deflection
    sqrt(delta_+^2 + delta_-^2) (so that 0.5 k deflection^2 is the mesh energy, zero when
    open), the flank +1 / -1 the one with the larger force (0: open).

    ``pairs`` > 0 holds the number of tooth pairs in contact (the quasi-static solver keeps it
    during one equilibrium search: the rectangular-wave stiffness is discontinuous in q); 0
    takes it from the roll position.  ``flank`` is no longer used (both flanks act; kept so
    that the callers' arrays stay as they are).

    ``K`` (17 x 17, or 0 x 0: not wanted) accumulates the stiffness matrix -dQ/dq of the
    elastic force (material term k g g^T per flank; the curvature of the line-of-centres angle
    is left out: docs/model.md, "Quasi-static analysis").  (cos_l, sin_l): of the line of
    centres' nominal angle q[carrier] + crank_angle (:func:`line_trig`)."""
    px, py, pvx, pvy = crank_point(q, v, j, P[W_G_L], P[W_G_U])
    r2 = px * px + py * py
    r = math.sqrt(r2)
    # angle of the line of centres, kept continuous: carrier angle + assembly angle + deviation
    line = q[CARRIER] + crank_angle
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
    damping = 2.0 * P[ZETA] * math.sqrt(stiffness * P[MESH_MASS])
    half = 0.5 * P[BACKLASH]
    total = 0.0
    net = 0.0
    energy = 0.0
    power = 0.0
    squares = 0.0
    largest = 0.0
    loaded = 0.0
    wl, wu = P[W_G_L], P[W_G_U]
    for side in range(2):
        sign = 1.0 if side == 0 else -1.0
        delta = sign * rot - radial - half
        if delta <= 0.0:
            continue
        rate = sign * rot_rate - radial_rate
        force = stiffness * delta + damping * rate
        if force < 0.0:
            force = 0.0
        energy += 0.5 * stiffness * delta * delta
        power += (force - stiffness * delta) * rate
        squares += delta * delta
        total += force
        net += sign * force
        if force > largest or loaded == 0.0:
            largest = force
            loaded = sign
        # generalised forces: Q = -F d(delta)/dq
        gx = sign * (-(rb1 + rb2) * dbeta_x) - P[SIN_AW] * dr_x
        gy = sign * (-(rb1 + rb2) * dbeta_y) - P[SIN_AW] * dr_y
        add_crank_force(Q, j, wl, wu, -force * gx, -force * gy)
        Q[b + 4] -= force * sign * rb2
        if K.shape[0] > 0:
            add_rank_one(K, (b, b + 1, b + 2, b + 3, b + 4),
                         (wl * gx, wl * gy, wu * gx, wu * gy, sign * rb2), stiffness)
    return (total, net * rb1, energy, power, stiffness, math.sqrt(squares), natural,
            loaded)


@numba.njit(**REFCOUNT)
def pin_contacts(P, q, v, Q, K, disc, pins, pin_angle, u, next_eval, clock, forces, elastic,
                 fe, modal, arm_elastic=None, carried=None):
    """All pin contacts of disc ``disc``: returns (energy, dissipated power, max penetration,
    largest pin force).  (``forces_at`` calls the same parts, :func:`pin_loop` and :func:`coupled_pins`, itself for
    the pins in the housing; a change here belongs there too.)

    ``u[disc, i]`` holds the foot-point parameter as an offset from the pin's nominal parameter
    gamma_i - theta (exact in the kinematic pose).  Near contact one Newton step from the
    previous foot point converges; when it does not (first step, after a skip, a pin far from
    contact near the medial axis of a concave stretch of the curve, where the foot point is not
    unique) the nearest point is found robustly over one lobe period (geometry._curve.pin_gap).

    A pin whose gap cannot close before force evaluation ``next_eval[disc, i]`` is not
    evaluated (``clock`` counts the force evaluations: the integrator's steps, or its sub-steps
    where the stability guard takes them): the gap is a 1-Lipschitz function of the pin centre
    in disc axes, whose speed is at most |dO/dt| + |dtheta/dt| * (pin circle + a), so a gap g
    stays open for g / (2 v h) evaluations, h the current (sub-)step P[NODE_H] (P[DT] when
    0; factor 2 for speed changes within at most 64 evaluations).

    ``K`` (17 x 17, or 0 x 0) accumulates the material stiffness k g g^T of each contact, g the
    gradient of its gap (the profile-curvature term F d2gap/dq2 is left out).

    ``fe`` (2, m, m): the discs' finite-element compliance tables; the touching pins of a disc
    are then solved together (:func:`rvsim.physics._fe_contacts.apply_coupled`).  (2, 0, 0):
    independent contacts.  ``modal`` (2, m + HEADER, modes): the discs' modes
    (:mod:`rvsim.physics._fe_modes`; ``fe`` then holds their residual tables), whose modal
    force this evaluation fills.  ``arm_elastic``: the kernel's arm state, whose crank-hole
    columns carry the holes' load Q and stretch (:mod:`rvsim.physics._fe_holes`); passed
    only with the holes as load points (an array argument costs the step its reference
    counting: measured 4-6 % of the closed-form run).  The loop over the pins,
    :func:`pin_loop`, allocates nothing and counts no references; the coupled solve,
    :func:`coupled_pins`, does.  (:func:`forces_at` calls the two itself.)  ``carried``: what
    each pin's evaluation carries to the next (:func:`pin_loop`; omitted: nothing).
    """
    coupled = fe.shape[1] > 0
    n = pins.shape[0]
    if carried is None:
        carry = nothing_carried(n)
    else:
        carry = carried
    pin_slots = np.empty(n if coupled else 0, dtype=np.int64)
    pin_work = np.empty((n if coupled else 0, 12))
    if coupled:
        clear_modal_force(modal[disc])
    cos_d, sin_d = disc_trig(q, disc)
    energy, power, worst, count, peak = pin_loop(P, q, v, Q, K, disc, pins, pin_angle, u,
                                                 next_eval, clock, forces, elastic, coupled,
                                                 pin_slots, pin_work, carry, cos_d, sin_d)
    if count > 0:
        if arm_elastic is None:
            hole = Q[0:0]
            css = 0.0
        else:
            hole = hole_row(P, arm_elastic, disc)
            css = hole_css(P, disc)
        e, pw, peak_fe = coupled_pins(P, q, v, Q, K, disc, fe[disc], modal[disc], pin_slots,
                                      pin_work, count, forces, elastic, hole, css)
        energy += e
        power += pw
        peak = max(peak, peak_fe)
    elif arm_elastic is not None and holes_on(P):     # no pin touches: s = c_ss Q
        energy += free_stretch(hole_row(P, arm_elastic, disc), hole_css(P, disc))
    return energy, power, worst, peak


@numba.njit(cache=CACHE, inline="always")
def _disc_frame(P, q, v, disc):
    """Disc ``disc``'s profile angle: (cos, sin) and the housing velocity seen from the disc
    centre in disc axes (rotation part excluded), and its angular velocity."""
    cos_d, sin_d = disc_trig(q, disc)
    return _disc_frame_at(P, q, v, disc, cos_d, sin_d)


@numba.njit(cache=CACHE, inline="always")
def profile_turn(P, disc):
    """Disc ``disc``'s profile angle less its rotation q[theta]: the half-tooth offset of
    disc 1 and the rotation modification (model.build_model turns it into P[FRAME_TURN0 ..])."""
    return -disc * math.pi / P[ZC] + P[PROFILE_ROT]


@numba.njit(cache=CACHE, inline="always")
def _disc_frame_at(P, q, v, disc, cos_d, sin_d):
    """:func:`_disc_frame` from the cosine and sine of the disc's rotation q[theta] (turned
    by the constant P[FRAME_TURN0 + 2 disc ..]: no trigonometric call)."""
    d = DISC0 + DISC_STRIDE * disc
    vx, vy, w = v[d], v[d + 1], v[d + 2]
    angle = q[d + 2] + profile_turn(P, disc)
    cos_f, sin_f = P[FRAME_TURN0 + 2 * disc], P[FRAME_TURN0 + 2 * disc + 1]
    cos_t, sin_t = cos_d * cos_f - sin_d * sin_f, sin_d * cos_f + cos_d * sin_f
    return angle, cos_t, sin_t, cos_t * vx + sin_t * vy, -sin_t * vx + cos_t * vy, w


@numba.njit(**NO_REFCOUNT)
def pin_loop(P, q, v, Q, K, disc, pins, pin_angle, u, next_eval, clock, forces, elastic,
             coupled, slots, work, carried, cos_d, sin_d):
    """The pin loop of :func:`pin_contacts` (compiled without reference counting: it
    allocates nothing): the independent contacts' forces added to ``Q``; with ``coupled``, the
    touching pins written to ``slots`` / ``work`` for :func:`coupled_pins`.  Returns (energy,
    dissipated power, max penetration, number of coupled contacts, largest force of the
    independent contacts).  ``carried[disc, i]``:
    what pin i's evaluation carries to its next one, the foot's cosines and sines
    (geometry._curve.pin_gap) and the elastic force with its power 0.9
    (_contact_law.spring_force_power); NaN: nothing carried.  (cos_d, sin_d): of the disc's
    rotation q[theta] (:func:`disc_trig`)."""
    d = DISC0 + DISC_STRIDE * disc
    ox, oy = q[d], q[d + 1]
    vx, vy = v[d], v[d + 1]
    zp = P[ZP]
    # housing velocity seen from the disc centre, in disc axes (rotation part added per pin)
    angle, cos_t, sin_t, lvx, lvy, w = _disc_frame_at(P, q, v, disc, cos_d, sin_d)
    rg, a = P[RG], P[A_GEN]
    clearance = P[PROFILE_OFFSET] - P[PIN_RADIUS]
    runout_x = P[RUNOUT_X0] if disc == 0 else P[RUNOUT_X1]
    runout_y = P[RUNOUT_Y0] if disc == 0 else P[RUNOUT_Y1]
    speed_bound = 2.0 * (math.sqrt(vx * vx + vy * vy) + abs(w) * (P[RG] + 2.0 * a + 1e-3)) \
        * (P[NODE_H] if P[NODE_H] > 0.0 else P[DT]) + 1e-15
    energy = 0.0
    power = 0.0
    worst = 0.0
    want = K.shape[0] > 0
    n = pins.shape[0]
    count = 0
    peak = 0.0
    for i in range(n):
        if clock < next_eval[disc, i]:
            continue        # open: its force and elastic force were zeroed when it was skipped
        qx, qy = profile_axes(pins[i, 0], pins[i, 1], ox, oy, cos_t, sin_t, runout_x, runout_y)
        nominal = pin_angle[i] - angle
        if (clock + i) % CARRY_REFRESH == 0:     # afresh now and then: no round-off grows
            carried[disc, i, 0] = math.nan
            carried[disc, i, 5] = math.nan
        gap, ui, nx, ny = pin_gap(qx, qy, nominal, nominal + u[disc, i], rg, a, zp,
                                  clearance + pin_opening(pins, i), clock > 0,
                                  carried[disc, i, 0:5])
        gap, nx, ny = deviated_gap(pins, disc, ui, gap, nx, ny, rg, a, zp)  # per-part errors
        u[disc, i] = ui - nominal
        if gap >= 0.0:
            forces[disc, i] = 0.0
            elastic[disc, i] = 0.0
            skip = int(gap / speed_bound)
            next_eval[disc, i] = clock + (skip if skip < MAX_SKIP else MAX_SKIP)
            continue
        next_eval[disc, i] = clock + 1
        delta = -gap
        if delta > worst:
            worst = delta
        # pin centre from the disc centre (the profile centre is off it by the runout)
        px, py = qx + runout_x, qy + runout_y
        lever = nx * py - ny * px                    # d(gap)/d(theta)
        gap_rate = -(nx * lvx + ny * lvy) + w * lever
        # generalised forces Q = F d(gap)/dq on the disc
        gx = -(cos_t * nx - sin_t * ny)                 # d(gap)/d(x, y) of the disc
        gy = -(sin_t * nx + cos_t * ny)
        cb = pin_series_compliance(P, nx, ny, nominal)   # the pin's (and tooth's) own
        if coupled:
            slots[count] = i
            work[count, 0], work[count, 1], work[count, 2] = delta, -gap_rate, ui
            work[count, 3], work[count, 4], work[count, 5] = gx, gy, lever
            work[count, 6] = cb
            # for the friction after the coupled solve: pin centre, gap, normal
            work[count, 7], work[count, 8], work[count, 9] = px, py, gap
            work[count, 10], work[count, 11] = nx, ny
            count += 1
            continue
        guess = elastic[disc, i]
        if guess > 0.0 and carried[disc, i, 5] == guess:     # what it carried is its own
            fel, k, e, power_09 = spring_force_from(
                delta, P[PIN_C], cb, guess, carried[disc, i, 6], carried[disc, i, 7],
                carried[disc, i, 8])
        else:
            fel, k, e, power_09 = spring_force_power(delta, P[PIN_C], cb, guess, 0.0)
        carried[disc, i, 5] = fel
        carried[disc, i, 6] = power_09
        carried[disc, i, 7] = delta
        carried[disc, i, 8] = k
        fn, pw = damped(fel, k, -gap_rate, P[ZETA], P[M_DISC])
        forces[disc, i] = fn
        elastic[disc, i] = fel
        if fn > peak:
            peak = fn
        energy += e
        power += pw
        fx = fn * gx
        fy = fn * gy
        torque = fn * lever
        if want:
            add_rank_one(K, (d, d + 1, d + 2), (gx, gy, lever), k)
        if P[MU] > 0.0:
            fx_t, fy_t, torque_t, loss = pin_friction(P, fn, px, py, gap, nx, ny, lvx, lvy, w,
                                                      cos_t, sin_t)
            fx += fx_t
            fy += fy_t
            torque += torque_t
            power += loss
        Q[d] += fx
        Q[d + 1] += fy
        Q[d + 2] += torque
    return energy, power, worst, count, peak


@numba.njit(**REFCOUNT)
def coupled_pins(P, q, v, Q, K, disc, table, modal, slots, work, count, forces, elastic,
                 hole, css):
    """The touching pins of disc ``disc`` that :func:`pin_loop` collected, solved together with
    the disc's finite-element ``table`` (:func:`rvsim.physics._fe_contacts.apply_coupled`),
    and their friction; ``hole``, ``css``: the disc's crank-hole state (0-length, 0: none;
    :mod:`rvsim.physics._fe_holes`).  Returns (energy, dissipated power, largest force)."""
    d = DISC0 + DISC_STRIDE * disc
    _, cos_t, sin_t, lvx, lvy, w = _disc_frame(P, q, v, disc)
    energy, power, _ = apply_coupled(table, slots, work, count, P[PIN_C], P[ZETA],
                                     P[M_DISC], forces[disc], elastic[disc], Q, K, d, modal,
                                     hole, css)
    if P[MU] > 0.0:
        # friction at the coupled solve's normal forces (the table is normal-normal: the
        # tangential forces do not deflect the neighbours' approaches)
        for a in range(count):
            fx_t, fy_t, torque_t, loss = pin_friction(
                P, forces[disc, slots[a]], work[a, 7], work[a, 8], work[a, 9],
                work[a, 10], work[a, 11], lvx, lvy, w, cos_t, sin_t)
            Q[d] += fx_t
            Q[d + 1] += fy_t
            Q[d + 2] += torque_t
            power += loss
    peak = 0.0
    for a in range(count):
        if forces[disc, slots[a]] > peak:
            peak = forces[disc, slots[a]]
    return energy, power, peak


@numba.njit(cache=CACHE, inline="always")
def pin_friction(P, fn, px, py, gap, nx, ny, lvx, lvy, w, cos_t, sin_t):
    """Coulomb friction of a pin contact with normal force ``fn``, P[MU] the effective
    coefficient (fixed pins sliding on the disc, or pins turning in their grooves:
    rvsim.friction, docs/model.md section 15), regularised over P[V_FRIC]: the force (x, y)
    and torque on the disc and the dissipated power.  (px, py) the pin centre from the disc
    centre and (nx, ny) the contact normal, in disc axes; (lvx, lvy) the housing's velocity
    seen from the disc centre and w the disc's angular velocity."""
    # contact point on the disc (disc axes, from its centre) and sliding speed there
    cx = px - (P[PIN_RADIUS] - gap) * nx
    cy = py - (P[PIN_RADIUS] - gap) * ny
    tix, tiy = -ny, nx
    slide = (lvx - w * cy) * tix + (lvy + w * cx) * tiy
    ft = -P[MU] * fn * math.tanh(slide / P[V_FRIC])
    return (ft * (cos_t * tix - sin_t * tiy), ft * (sin_t * tix + cos_t * tiy),
            ft * (cx * tiy - cy * tix), -ft * slide)


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
    for a in range(8):
        ax = kxx * gx[a] + kxy * gy[a]
        ay = kxy * gx[a] + kyy * gy[a]
        for c in range(8):
            K[index[c], index[a]] += gx[c] * ax + gy[c] * ay
        cage = gx[a] * cx + gy[a] * cy
        K[index[a], b + 4] += w_in * cage
        K[index[a], d + 2] += (1.0 - w_in) * cage
    K[b + 4, b + 4] -= ecc * (sx * cos_p + sy * sin_p)
    K[d + 2, d + 2] += sx * lx + sy * ly


@numba.njit(**NO_REFCOUNT)
def support_stiffness(K, b, phi, bx, by, kxx, kxy, kyy, sx, sy, cx, cy, w_in):
    """Stiffness matrix of a support element (node coordinates from b, crank rotation at
    ``phi``, bore centre (bx, by) on the carrier), as :func:`arm_stiffness`."""
    index = (b, b + 1, CARRIER)
    gx = (1.0, 0.0, by)
    gy = (0.0, 1.0, -bx)
    for a in range(3):
        ax = kxx * gx[a] + kxy * gy[a]
        ay = kxy * gx[a] + kyy * gy[a]
        for c in range(3):
            K[index[c], index[a]] += gx[c] * ax + gy[c] * ay
        cage = gx[a] * cx + gy[a] * cy
        K[index[a], phi] += w_in * cage
        K[index[a], CARRIER] += (1.0 - w_in) * cage
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


@numba.njit(**NO_REFCOUNT)
def arm_station(P, holes, crank, disc):
    """Station weights (wl, wu) of disc ``disc``'s eccentric on crank ``crank`` and the centre
    of its hole in the disc's axes (with the per-disc hole offsets of per-part errors, and the
    hole's elastic displacement when the FE disc's holes are load points: added by the
    callers, :func:`rvsim.physics._fe_holes.hole_shift`)."""
    wl = P[W_D1_L] if disc == 0 else P[W_D2_L]
    wu = P[W_D1_U] if disc == 0 else P[W_D2_U]
    hole_x, hole_y = holes[crank, 0], holes[crank, 1]
    if holes.shape[1] > 2:
        hole_x += holes[crank, 2 + 2 * disc]
        hole_y += holes[crank, 3 + 2 * disc]
    return wl, wu, hole_x, hole_y


@numba.njit(cache=CACHE, inline="always")
def hole_station(P, holes, crank, disc, elastic):
    """:func:`arm_station` with the hole's elastic displacement when the FE disc's holes are
    load points (``elastic`` the kernel's arm state; physics._fe_holes)."""
    wl, wu, hole_x, hole_y = arm_station(P, holes, crank, disc)
    if holes_on(P):
        dx, dy = hole_shift(P, elastic, crank, disc)
        hole_x += dx
        hole_y += dy
    return wl, wu, hole_x, hole_y


@numba.njit(cache=CACHE, inline="always")
def eccentric_angle(P, q, crank, disc):
    """Direction of crank ``crank``'s eccentric for disc ``disc``."""
    return q[CRANK0 + CRANK_STRIDE * crank + 4] + disc * math.pi + P[ECC_PHASE0 + 2 * crank + disc]


@numba.njit(cache=CACHE, inline="always")
def disc_trig(q, disc):
    """Cosine and sine of disc ``disc``'s rotation q[theta]."""
    angle = q[DISC0 + DISC_STRIDE * disc + 2]
    return math.cos(angle), math.sin(angle)


@numba.njit(cache=CACHE, inline="always")
def eccentric_trig(P, q, crank):
    """Cosines and sines of crank ``crank``'s two eccentrics (disc 1's turned from disc 0's by
    the constant P[ECC_TURN0 + 2 crank ..]): (cos, sin disc 0, cos, sin disc 1)."""
    phi = eccentric_angle(P, q, crank, 0)
    c0, s0 = math.cos(phi), math.sin(phi)
    ct, st = P[ECC_TURN0 + 2 * crank], P[ECC_TURN0 + 2 * crank + 1]
    return c0, s0, c0 * ct - s0 * st, s0 * ct + c0 * st


@numba.njit(**NO_REFCOUNT)
def arm_trig(P, q, crank, disc):
    """(cos, sin) of disc ``disc``'s rotation and of crank ``crank``'s eccentric for it, the
    trigonometric arguments of :func:`arm_geometry` and :func:`arm_bushing` for a caller
    that has none at hand (:func:`crank_bearings` shares them between the elements)."""
    cos_t, sin_t = disc_trig(q, disc)
    c0, s0, c1, s1 = eccentric_trig(P, q, crank)
    return (cos_t, sin_t, c0, s0) if disc == 0 else (cos_t, sin_t, c1, s1)


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
def arm_bushing(P, q, v, Q, K, crank, disc, hole_x, hole_y, wl, wu, elastic, cos_t, sin_t,
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
        sx, sy, energy, power, _, kxx, kxy, kyy, cx, cy = roller_set(
            rx, ry, rvx, rvy, P[ARM_ROLLERS], cage, P[ARM_C], P[ARM_CLEAR], 1.0,
            P[ZETA], P[M_NODE])
        fn = math.sqrt(sx * sx + sy * sy)
        ex_el, ey_el = sx, sy
        if fn == 0.0:
            return 0.0, 0.0, 0.0
    else:
        sx, sy, energy, power, fn, ex_el, ey_el, kxx, kxy, kyy = _bushing(
            rx, ry, rvx, rvy, P[ARM_CLEAR], P[ARM_J1], P[ARM_A1], P[ARM_J2],
            P[ARM_A2], P[ARM_CB], P[ZETA], P[M_NODE], elastic, crank, disc,
            BUSH_SLOT0 + BUSH_COLUMNS * disc, P[ARM_SHIFT], K.shape[0] > 0)
        if fn == 0.0 and elastic[crank, disc] == 0.0:
            return 0.0, 0.0, 0.0
    add_hole_load(P, q, elastic, crank, disc, ex_el, ey_el)     # the holes' Q (_fe_holes)
    if K.shape[0] > 0:
        arm_stiffness(K, b, d, wl, wu, ecc, cos_p, sin_p, hx - q[d], hy - q[d + 1], kxx, kxy,
                      kyy, ex_el, ey_el, cx, cy, w_in)
    apply_arm_force(Q, q, crank, disc, wl, wu, ecc, cos_p, sin_p, hx, hy, sx, sy)
    return fn, energy, power


@numba.njit(**REFCOUNT)
def arm_pair(P, q, v, Q, K, crank, holes, elastic):
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
    want = K.shape[0] > 0
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
def support_bushing(P, q, v, Q, K, crank, upper, bx, by, elastic):
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
        sx, sy, energy, power, _, kxx, kxy, kyy, cx, cy = roller_set(
            rx, ry, vx, vy, P[SUP_ROLLERS], cage, P[SUP_C], clearance, P[SUP_COS_ALPHA],
            P[ZETA], P[M_NODE])
        fn = math.sqrt(sx * sx + sy * sy)
        ex_el, ey_el = sx, sy
        if fn == 0.0:
            return 0.0, 0.0, 0.0
    else:
        a2 = P[SUP_A2_U] if upper else P[SUP_A2_L]
        slot = SUP_SLOT0 + (1 if upper else 0)
        sx, sy, energy, power, fn, ex_el, ey_el, kxx, kxy, kyy = _bushing(
            rx, ry, vx, vy, clearance, P[SUP_J1], P[SUP_A1], P[SUP_J2], a2, 0.0, P[ZETA],
            P[M_NODE], elastic, crank, slot, BUSH_SLOT0 + BUSH_COLUMNS * slot,
            P[SUP_SHIFT_U] if upper else P[SUP_SHIFT_L], K.shape[0] > 0)
        if fn == 0.0 and elastic[crank, slot] == 0.0:
            return 0.0, 0.0, 0.0
    if K.shape[0] > 0:
        support_stiffness(K, b, phi, bx, by, kxx, kxy, kyy, ex_el, ey_el, cx, cy, w_in)
    Q[b] -= sx
    Q[b + 1] -= sy
    Q[CARRIER] += -sx * by + sy * bx
    return fn, energy, power


@numba.njit(**NO_REFCOUNT)
def kinetic_energy(P, v):
    energy = 0.5 * P[J_CARRIER] * v[CARRIER] ** 2
    for j in range(2):
        b = CRANK0 + CRANK_STRIDE * j
        energy += node_kinetic(P, v, j)        # the support nodes (dynamics._stiff_nodes)
        energy += 0.5 * P[J_CRANK] * v[b + 4] ** 2
    for disc in range(2):
        d = DISC0 + DISC_STRIDE * disc
        energy += 0.5 * P[M_DISC] * (v[d] ** 2 + v[d + 1] ** 2) + 0.5 * P[J_DISC] * v[d + 2] ** 2
    return energy


@numba.njit(**NO_REFCOUNT)
def crank_bearings(P, q, v, Q, K, holes, crank_angles, arm_elastic, channel, n_discs, trig):
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
            e, pw, pair0, pair1 = arm_pair(P, q, v, Q, K, j, holes, arm_elastic)
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
            force, e, pw = arm_bushing(P, q, v, Q, K, j, disc, hole_x, hole_y, wl, wu,
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
            force, e, pw = support_bushing(P, q, v, Q, K, j, upper == 1, bx, by, arm_elastic)
            channel[CH_SUP_FL0 + 2 * j + upper] = force
            energy += e
            power += pw
            if P[FRICTION_ON] == 1.0:
                power += support_bearing_friction(P, v, Q, j, force)
    end_arms(P, arm_elastic)
    if P[FE_PLATE_XX1] != 0.0:    # finite-element carrier and flange (physics._fe_carrier)
        for upper in range(2):
            e, pw = plate_supports(P, q, v, Q, K, upper == 1, crank_angles, arm_elastic,
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
    crank_bearings(P, q, v, Q_scratch, K, holes, crank_angles, arm_elastic, channel,
                   int(P[DISC_COUNT]), angle_trig(q, crank_angles))


@numba.njit(**REFCOUNT)
def ring_pins(P, q, v, Q, K, disc, pins, pin_angle, u, next_eval, clock, pin_force,
              pin_elastic, fe, modes, carried):
    """Disc ``disc``'s pin contacts with the pin ring as output (single-stage drive): found
    in the ring's axes (:func:`~rvsim.physics._single_stage.ring_frame`), their forces and
    stiffness added to ``Q`` and ``K``.  Returns (energy, dissipated power, max
    penetration, largest pin force).  (A function of its own: it allocates, the step loop does
    not.)"""
    qr, vr, Qr, Kr = ring_frame(q, v, K, disc)
    e, pw, pen, peak = pin_contacts(P, qr, vr, Qr, Kr, disc, pins, pin_angle, u, next_eval,
                                    clock, pin_force, pin_elastic, fe, modes, None, carried)
    ring_forces(q, qr, Qr, Kr, Q, K, disc)
    return e, pw, pen, peak


@numba.njit(cache=CACHE, inline="always")
def forces_at(P, q, v, theta_in, omega_in, torque_load, pins, pin_angle, holes, crank_angles,
              mesh_phase, u, next_eval, step, pin_force, pin_elastic, arm_elastic, Q, K,
              channel, mesh_state, mesh_hold, fe, modal=None, pin_slots=None, pin_work=None,
              pin_carried=None, K_bearings=None):
    """Generalised forces Q at input angle and speed (theta_in, omega_in) under the output load
    ``torque_load``: the one evaluation of the force elements that both engines use.

    Fills the force channels and ``mesh_state`` (stiffness, deflection of each mesh); with a
    17 x 17 ``K`` (zeroed by the caller) it also accumulates the stiffness matrix -dQ/dq of the
    elastic forces (a 0 x 0 ``K``: not wanted).  ``mesh_hold[j]`` = (pairs, unused) held for
    mesh j (zero: from the roll position, see :func:`gear_mesh`); with four columns,
    ``mesh_state`` also receives the pairs at the roll position and the loaded flank.
    With P[FRICTION_ON], the mesh and bearing friction (physics._friction) act after their
    elements with the normal forces those return.  Returns (potential energy, dissipated
    power, input torque, max pin penetration).  ``modal``: the discs' modes (dynamic engine,
    :mod:`rvsim.physics._fe_modes`; omitted: none).  ``pin_slots``, ``pin_work``: the pin
    contacts' work arrays (:func:`pin_contacts`; omitted: allocated per call).
    ``pin_carried``: what each pin's evaluation carries to the next (:func:`pin_loop`; omitted:
    nothing).  ``K_bearings``: a 17 x 17 matrix (zeroed by the caller) that takes the crank
    bearings' stiffness instead of ``K`` (the scheme ``implicit-bearings``,
    :mod:`rvsim.dynamics._implicit_bearings`; omitted: they go to ``K``).
    """
    if modal is None:
        modes = np.zeros((2, 0, 0))
    else:
        modes = modal
    coupled = fe.shape[1] > 0
    if pin_slots is None:
        slots = np.empty(pins.shape[0] if coupled else 0, dtype=np.int64)
        work = np.empty((pins.shape[0] if coupled else 0, 12))
    else:
        slots, work = pin_slots, pin_work
    if pin_carried is None:
        carried = nothing_carried(pins.shape[0])
    else:
        carried = pin_carried
    if K_bearings is None:
        bearings = np.zeros((0, 0))
    else:
        bearings = K_bearings
    return forces_with(P, q, v, theta_in, omega_in, torque_load, pins, pin_angle, holes,
                       crank_angles, mesh_phase, u, next_eval, step, pin_force, pin_elastic,
                       arm_elastic, Q, K, channel, mesh_state, mesh_hold, fe, modes, slots, work,
                       carried, bearings)


@numba.njit(cache=CACHE, inline="always")
def forces_with(P, q, v, theta_in, omega_in, torque_load, pins, pin_angle, holes, crank_angles,
                mesh_phase, u, next_eval, step, pin_force, pin_elastic, arm_elastic, Q, K,
                channel, mesh_state, mesh_hold, fe, modes, slots, work, carried, K_bearings):
    """:func:`forces_at` with every work array given (``modes``, the pin contacts' ``slots``
    and ``work``; ``K_bearings`` 0 x 0 where the bearings' stiffness goes to ``K``): allocates
    nothing, so that the step loop compiles without reference counting."""
    coupled = fe.shape[1] > 0
    for i in range(N_DOF):
        Q[i] = 0.0
    # one cosine and sine per angle, shared by the elements
    trig = angle_trig(q, crank_angles)
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
                mesh_hold[j, 0], mesh_hold[j, 1], trig[2 * j], trig[2 * j + 1])
            channel[CH_MESH_F0 + j] = force
            mesh_state[j, 0] = stiffness
            mesh_state[j, 1] = deflection
            if mesh_state.shape[1] > 3:
                mesh_state[j, 2] = natural
                mesh_state[j, 3] = rule
            torque_in += torque
            energy += e
            power += pw
            if P[FRICTION_ON] == 1.0:
                px, py, pvx, pvy = crank_point(q, v, j, P[W_G_L], P[W_G_U])
                torque, fx, fy, pw = mesh_friction(P, force, omega_in, px, py, pvx, pvy)
                add_crank_force(Q, j, P[W_G_L], P[W_G_U], fx, fy)
                torque_in += torque
                power += pw
    n_discs = int(P[DISC_COUNT])
    worst = 0.0
    pin_peak = 0.0
    ring = single and P[RING_OUTPUT] == 1.0
    for disc in range(n_discs):
        if ring:  # the pins turn with the output: contacts found in the ring's axes
            e, pw, pen, peak = ring_pins(P, q, v, Q, K, disc, pins, pin_angle, u, next_eval,
                                         step, pin_force, pin_elastic, fe, modes, carried)
        else:   # pin_contacts' parts, called here (no reference counting in the pin loop;
                # docs/decisions.md): a change to one sequence belongs in the other too
            if coupled:
                clear_modal_force(modes[disc])
            e, pw, pen, count, peak = pin_loop(
                P, q, v, Q, K, disc, pins, pin_angle, u, next_eval, step, pin_force,
                pin_elastic, coupled, slots, work, carried, trig[4 + 2 * disc],
                trig[5 + 2 * disc])
            if count > 0:
                if holes_on(P):     # the FE disc's crank holes as load points (_fe_holes)
                    hole = hole_row(P, arm_elastic, disc)
                    css = hole_css(P, disc)
                else:
                    hole = Q[0:0]
                    css = 0.0
                e_fe, pw_fe, peak_fe = coupled_pins(P, q, v, Q, K, disc, fe[disc], modes[disc],
                                                    slots, work, count, pin_force,
                                                    pin_elastic, hole, css)
                e += e_fe
                pw += pw_fe
                peak = max(peak, peak_fe)
            elif holes_on(P):       # no pin touches: s = c_ss Q (_fe_holes.free_stretch)
                e += free_stretch(hole_row(P, arm_elastic, disc), hole_css(P, disc))
        energy += e
        power += pw
        if pen > worst:
            worst = pen
        if peak > pin_peak:
            pin_peak = peak
    channel[CH_PIN_MAX] = pin_peak
    e, pw = crank_bearings(P, q, v, Q, K_bearings if K_bearings.shape[0] > 0 else K, holes,
                           crank_angles, arm_elastic, channel, n_discs, trig)
    energy += e
    power += pw
    if single:
        for disc in range(n_discs):
            for m in range(int(P[OUT_COUNT])):
                force, e, pw = output_pin(P, q, v, Q, K, disc, m, arm_elastic)
                energy += e
                power += pw
    if P[FRICTION_ON] == 1.0 and (P[SEAL_IN] > 0.0 or P[SEAL_OUT] > 0.0):
        torque, pw = seal_friction(P, v, Q, omega_in)
        torque_in += torque
        power += pw
    Q[CARRIER] -= torque_load
    return energy, power, torque_in, worst


@numba.njit(cache=CACHE, inline="always")
def forces(P, q, v, t, pins, pin_angle, holes, crank_angles, mesh_phase, u, next_eval, step,
           pin_force, pin_elastic, arm_elastic, Q, channel, mesh_state, K, mesh_hold, fe, modal,
           pin_slots, pin_work, pin_carried, K_bearings):
    """Generalised forces Q at time t (:func:`forces_at` with the input motion and the load of
    the run's schedule; ``K_bearings`` as :func:`forces_with` takes it). Returns (potential energy, dissipated power, input torque,
    load torque, max pin penetration, input angle, input speed)."""
    theta_in, omega_in = input_motion(P, t)
    torque_load = load_torque(P, t)
    energy, power, torque_in, worst = forces_with(
        P, q, v, theta_in, omega_in, torque_load, pins, pin_angle, holes, crank_angles,
        mesh_phase, u, next_eval, step, pin_force, pin_elastic, arm_elastic, Q, K, channel,
        mesh_state, mesh_hold, fe, modal, pin_slots, pin_work, pin_carried, K_bearings)
    return energy, power, torque_in, torque_load, worst, theta_in, omega_in


@numba.njit(cache=CACHE, inline="always")
def impulse_factors(P, h):
    """The (sub-)step ``h``'s velocity change per unit generalised force of each coordinate:
    carrier, crank rotation, disc translation, disc rotation, and the crank nodes' inverse
    mass blocks (lower-lower, lower-upper, upper-upper)."""
    return (h / P[J_CARRIER], h / P[J_CRANK], h / P[M_DISC], h / P[J_DISC], h * P[MINV_LL],
            h * P[MINV_LU], h * P[MINV_UU])


#: values each pin's evaluation carries to its next (:func:`pin_loop`): the foot's u, cos u,
#: sin u, cos zp u, sin zp u, the elastic force, its power 0.9, the approach and the tangent
#: stiffness it was found at (_contact_law.spring_force_from)
CARRIED = 9


@numba.njit(**REFCOUNT)
def nothing_carried(n_pins):
    """What the pins carry before their first evaluation (NaN: nothing; :func:`pin_loop`)."""
    return np.full((2, n_pins, CARRIED), np.nan)


#: slots of the integer ``counters`` array carried between calls of :func:`integrate`
COUNT_ROW, COUNT_IN_WINDOW, COUNT_TICK = 0, 1, 2


def new_state(n_pins, n_channels, n_output_pins=0):
    """Work arrays that :func:`integrate` carries from one call to the next (all zero at t = 0):
    (pin_angle, u, next_eval, pin_force, pin_elastic, arm_elastic, mesh_state, channel,
    counters).  ``arm_elastic`` has the columns of _layout (the arm and support bushings',
    the finite-element crank's and plates' force vectors, the crank holes' state) and a
    column per output pin from _layout.OUT_SLOT0."""
    pin_angle = 2.0 * np.pi * np.arange(n_pins) / n_pins
    return (pin_angle, np.zeros((2, n_pins)), np.zeros((2, n_pins), dtype=np.int64),
            np.zeros((2, n_pins)), np.zeros((2, n_pins)),
            np.zeros((2, OUT_SLOT0 + n_output_pins)), np.zeros((2, 2)),
            np.zeros(n_channels), np.zeros(3, dtype=np.int64))


@numba.njit(**REFCOUNT)
def integrate(P, q, v, first_step, stop_step, n_steps, sample_every, pins, holes, crank_angles,
              mesh_phase, pin_angle, u, next_eval, pin_force, pin_elastic, arm_elastic,
              mesh_state, channel, counters, channels, pin_forces, energy, fe, modal,
              pin_carried, implicit, implicit_rows):
    """Advance from step ``first_step`` to ``stop_step`` (exclusive) of a run of ``n_steps``
    steps of size P[DT] that starts at t = 0; returns (status, next step).

    The caller integrates in chunks (so that it can be interrupted and show progress) and
    carries the state between calls: ``q``, ``v``, the work arrays of :func:`new_state` and
    ``energy``.  The last step, ``n_steps``, only evaluates and samples; after it the next step
    is ``n_steps + 1``.  Samples every ``sample_every`` steps into ``channels`` (rows) and
    ``pin_forces`` (rows x 2 discs x zp pins).  ``energy`` accumulates the steady-window
    balance and the window's largest pin force (E_PIN_PEAK, at every (sub-)step).  ``fe``:
    the discs' finite-element compliance tables, (2, 0, 0) for none; ``modal`` (2, m + HEADER,
    modes): the discs' modes and their state (``fe`` then the residual tables;
    :mod:`rvsim.physics._fe_modes`), (2, m + HEADER, 0) or (2, 0, 0) for none.
    ``pin_carried``: what each pin's evaluation carries to the next (:func:`nothing_carried`
    at t = 0, then carried between calls like the other state).  ``implicit``,
    ``implicit_rows``: the work of the scheme implicit-bearings, carried between calls
    (:func:`rvsim.dynamics._implicit_bearings.new_work`; 17 x 0 arrays: the explicit scheme).
    """
    Q = np.zeros(N_DOF)
    K = np.zeros((0, 0))
    # stability guard of the crank nodes (dynamics._stiff_nodes): the stiffness assembled
    # every P[NODE_REFRESH] steps, the step divided into sub-steps where the nodes need it
    K_node = np.zeros((N_DOF, N_DOF) if P[NODE_OMEGA_DT] > 0.0 else (0, 0))
    mesh_hold = np.zeros((2, 2))
    previous_stiffness = np.zeros(2)
    # the pin contacts' work arrays (coupled finite-element discs only), once per call
    coupled = fe.shape[1] > 0
    pin_slots = np.empty(pins.shape[0] if coupled else 0, dtype=np.int64)
    pin_work = np.empty((pins.shape[0] if coupled else 0, 12))
    return _advance(P, q, v, first_step, stop_step, n_steps, sample_every, pins, holes,
                    crank_angles, mesh_phase, pin_angle, u, next_eval, pin_force, pin_elastic,
                    arm_elastic, mesh_state, channel, counters, channels, pin_forces, energy, fe,
                    modal, pin_carried, Q, K, K_node, mesh_hold, previous_stiffness, pin_slots,
                    pin_work, implicit, implicit_rows)


@numba.njit(**NO_REFCOUNT)
def _advance(P, q, v, first_step, stop_step, n_steps, sample_every, pins, holes, crank_angles,
             mesh_phase, pin_angle, u, next_eval, pin_force, pin_elastic, arm_elastic,
             mesh_state, channel, counters, channels, pin_forces, energy, fe, modal,
             pin_carried, Q, K, K_node, mesh_hold, previous_stiffness, pin_slots, pin_work,
             implicit, implicit_rows):
    """The step loop of :func:`integrate` (compiled without reference counting: the work
    arrays are allocated by the caller)."""
    dt = P[DT]
    guard = P[NODE_OMEGA_DT] > 0.0
    refresh = max(1, int(P[NODE_REFRESH]))
    if first_step == 0:
        for i in (NODE_SUBSTEPS, NODE_CHECKS, NODE_CHECKS_STEADY, NODE_PEAK, NODE_ALERT,
                  IMPLICIT_FACTORS, IMPLICIT_ALERTS, IMPLICIT_FALLBACKS):
            P[i] = 0.0
    # the scheme implicit-bearings: M + theta h^2 K_b factored at the first step of the run,
    # every implicit_refresh steps (counted across calls: P[IMPLICIT_SINCE] and the factor
    # are carried) and at any step where a bearing's force has risen beyond what the last
    # factorisation had (dynamics._implicit_bearings)
    linear_implicit = implicit.shape[1] > 0
    implicit_refresh = max(1, int(P[IMPLICIT_REFRESH]))
    since_factor = int(P[IMPLICIT_SINCE]) if first_step > 0 else implicit_refresh
    M_full, K_bear, factor = implicit[0], implicit[1], implicit[2]
    dv, bearing_reference, scratch = implicit_rows[0], implicit_rows[1], implicit_rows[2]
    row = counters[COUNT_ROW]
    in_window = counters[COUNT_IN_WINDOW] == 1
    # sub-steps of the step where the guard found the node modes too stiff for it
    n_sub = max(1, int(P[NODE_SUBSTEPS])) if first_step > 0 else 1
    sub = 0
    h = dt / n_sub
    P[NODE_H] = h
    tick = counters[COUNT_TICK]       # force evaluations so far (the pin loop's clock)
    # inverse inertias, and the sub-step's impulse per unit force on each coordinate
    h_carrier, h_crank, h_mass, h_disc, h_ll, h_lu, h_uu = impulse_factors(P, h)
    status = STATUS_OK
    step = first_step
    while step < stop_step:
        first = sub == 0
        t = step * dt + sub * h
        modal_kinetic = 0.0
        for j in range(2):
            previous_stiffness[j] = mesh_state[j, 0]
        check = first and guard and (step % refresh == 0 or P[NODE_ALERT] == 1.0)
        if check:
            K_node[:, :] = 0.0
        refactor = linear_implicit and since_factor >= implicit_refresh
        if refactor:
            K_bear[:, :] = 0.0
        pot, diss, t_in, t_load, pen, theta_in, omega_in = forces(
            P, q, v, t, pins, pin_angle, holes, crank_angles, mesh_phase, u, next_eval, tick,
            pin_force, pin_elastic, arm_elastic, Q, channel, mesh_state,
            K_node if check else K, mesh_hold, fe, modal, pin_slots, pin_work, pin_carried,
            K_bear if refactor else K)
        tick += 1
        if linear_implicit and not refactor and bearing_forces_risen(channel,
                                                                     bearing_reference):
            # a bearing stiffer than the factor holds: one explicit step of it could grow
            # its mode manyfold, so its stiffness is assembled now, at this step's state
            K_bear[:, :] = 0.0
            bearing_stiffness(P, q, v, scratch, K_bear, holes, crank_angles, arm_elastic,
                              channel)
            refactor = True
            P[IMPLICIT_ALERTS] += 1.0
        if refactor:
            P[IMPLICIT_FACTORS] += 1.0
            if not factor_effective_mass(M_full, K_bear, P[IMPLICIT_THETA] * h * h, factor):
                P[IMPLICIT_FALLBACKS] += 1.0      # this step explicit: M alone
                factor_effective_mass(M_full, K_bear, 0.0, factor)
                since_factor = implicit_refresh   # and factor again at the next step
            else:
                since_factor = 0
            record_bearing_forces(channel, bearing_reference)
        if check:
            # the stiffest node mode of the two cranks sets the sub-steps of this step and of
            # the steps up to the next check (dynamics._stiff_nodes)
            stiffest = max(node_omega_dt(P, K_node, 0, dt), node_omega_dt(P, K_node, 1, dt))
            if stiffest > P[NODE_PEAK]:
                P[NODE_PEAK] = stiffest
            wanted = substeps_for(stiffest, P[NODE_OMEGA_DT])
            if wanted != n_sub:
                n_sub = wanted
                h = dt / n_sub
                h_carrier, h_crank, h_mass, h_disc, h_ll, h_lu, h_uu = impulse_factors(P, h)
                # the open pins' skips were counted in the old sub-step: evaluate them all
                P[NODE_H] = h
                next_eval[:, :] = 0
            # near the limit (a bushing can stiffen within a few steps): check every step
            P[NODE_ALERT] = 1.0 if stiffest / n_sub > ALERT * P[NODE_OMEGA_DT] else 0.0
            if n_sub > 1:
                P[NODE_CHECKS] += 1.0
                if in_window:
                    P[NODE_CHECKS_STEADY] += 1.0
        # the discs' modes: their energies, where the balance reads them
        if first and modal.shape[2] > 0 and (step == n_steps
                                             or in_window != (t >= P[STEADY_START])):
            for disc in range(2):
                kinetic, strain = modal_energy(modal[disc])
                pot += strain
                modal_kinetic += kinetic
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
        if (in_window or t >= P[STEADY_START]) and channel[CH_PIN_MAX] > energy[E_PIN_PEAK]:
            # the window's largest pin force, at every (sub-)step: samples miss the peaks
            # between them (paper run 2: 1207.4 N sampled at 2 kHz, 1216.2 N)
            energy[E_PIN_PEAK] = channel[CH_PIN_MAX]
        if first:
            if step % sample_every == 0 and row < channels.shape[0]:
                channel[CH_TIME] = t
                channel[CH_THETA_IN] = theta_in
                channel[CH_OMEGA_IN] = omega_in
                channel[CH_THETA_OUT] = q[CARRIER]
                channel[CH_OMEGA_OUT] = v[CARRIER]
                channel[CH_TORQUE_IN] = t_in
                channel[CH_TORQUE_LOAD] = t_load
                for k in range(channel.shape[0]):    # element by element: a slice copy
                    channels[row, k] = channel[k]     # would need reference counting
                for disc in range(pin_force.shape[0]):
                    for i in range(pin_force.shape[1]):
                        pin_forces[row, disc, i] = pin_force[disc, i]
                row += 1
            if step == n_steps:
                if in_window:
                    energy[E_KIN1] = kinetic_energy(P, v) + modal_kinetic
                    energy[E_POT1] = pot
                step += 1
                break
            if not in_window and t >= P[STEADY_START]:
                in_window = True
                energy[E_KIN0] = kinetic_energy(P, v) + modal_kinetic
                energy[E_POT0] = pot
        if in_window:
            # power flows over this (sub-)step, velocities taken at its start
            energy[E_INPUT] += t_in * omega_in * h
            energy[E_OUTPUT] += t_load * v[CARRIER] * h
            energy[E_DISSIPATED] += diss * h
        # semi-implicit Euler: velocities first, then positions with the new velocities
        if linear_implicit:     # (M + theta h^2 K_b) dv = h Q
            solve_factored(factor, Q, h, dv)
            for i in range(N_DOF):
                v[i] += dv[i]
            since_factor += 1
        else:
            v[CARRIER] += h_carrier * Q[CARRIER]
            for j in range(2):
                b = CRANK0 + CRANK_STRIDE * j
                for axis in range(2):
                    f_low, f_up = Q[b + axis], Q[b + 2 + axis]
                    v[b + axis] += h_ll * f_low + h_lu * f_up
                    v[b + 2 + axis] += h_lu * f_low + h_uu * f_up
                v[b + 4] += h_crank * Q[b + 4]
            for disc in range(2):
                d = DISC0 + DISC_STRIDE * disc
                v[d] += h_mass * Q[d]
                v[d + 1] += h_mass * Q[d + 1]
                v[d + 2] += h_disc * Q[d + 2]
        for i in range(N_DOF):
            q[i] += h * v[i]
        if modal.shape[2] > 0:
            for disc in range(2):
                power = advance_modes(modal[disc], h, P[ZETA])   # the contacts' ratio
                if in_window:
                    energy[E_DISSIPATED] += power * h
        sub += 1
        if sub >= n_sub:
            sub = 0
            step += 1
    P[NODE_SUBSTEPS] = n_sub
    P[NODE_H] = 0.0
    P[IMPLICIT_SINCE] = since_factor
    counters[COUNT_TICK] = tick
    counters[COUNT_ROW] = row
    counters[COUNT_IN_WINDOW] = 1 if in_window else 0
    return status, step
