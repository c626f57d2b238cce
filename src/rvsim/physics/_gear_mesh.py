"""The sun-planet gear mesh: both flanks of an involute mesh with the rectangular-wave
stiffness of the contact ratio (numba; docs/model.md section 3; moved out of
``dynamics/_kernel.py``, issue 31 step 9)."""

from __future__ import annotations

import math

import numba

from .._cache_guard import invalidate_stale_cache
from .._jit import NO_REFCOUNT

invalidate_stale_cache(__file__)

from ._contact_law import add_rank_one, damping  # noqa: E402
from ._frames import add_crank_force, crank_point  # noqa: E402
from ._layout import (BACKLASH, BASE_PITCH, CARRIER, CENTRE_DIST, CONTACT_RATIO,  # noqa: E402
                      CRANK0, CRANK_STRIDE, K_MESH, MESH_MASS, RB1, RB2, SIN_AW,
                      W_G_L, W_G_U, ZETA)


@numba.njit(**NO_REFCOUNT)
def gear_mesh(P, q, v, Q, K, want, j, crank_angle, phase, theta_in, omega_in, pairs, flank,
              cos_l, sin_l):
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

    With ``want`` (the stiffness wanted) ``K`` (17 x 17; else 0 x 0) accumulates the stiffness
    matrix -dQ/dq of the elastic force (material term k g g^T per flank; the curvature of the
    line-of-centres angle is left out: docs/model.md, "Quasi-static analysis"). (cos_l, sin_l):
    of the line of centres' nominal angle q[carrier] + crank_angle (:func:`line_trig`)."""
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
    coefficient = damping(stiffness, P[ZETA], P[MESH_MASS])
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
        force = stiffness * delta + coefficient * rate
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
        if want:
            add_rank_one(K, (b, b + 1, b + 2, b + 3, b + 4),
                         (wl * gx, wl * gy, wu * gx, wu * gy, sign * rb2), stiffness)
    return (total, net * rb1, energy, power, stiffness, math.sqrt(squares), natural,
            loaded)
