"""The pin contacts of the cycloid discs (numba; docs/model.md sections 4, 5 and 15): the
pin loop (no allocation, no reference counting), the touching pins of a finite-element disc
solved together, pin friction, the pins with the ring as output and the values each pin's
evaluation carries to its next (moved out of ``dynamics/_kernel.py``, issue 31 step 9)."""

from __future__ import annotations

import math

import numba
import numpy as np

from .._cache_guard import invalidate_stale_cache
from .._jit import CACHE, NO_REFCOUNT, REFCOUNT

invalidate_stale_cache(__file__)

from ..geometry._curve import deviated_gap, pin_gap, pin_opening, profile_axes  # noqa: E402
from ._contact_law import add_rank_one, damped, spring_force_from, spring_force_power  # noqa: E402
from ._fe_contacts import apply_coupled  # noqa: E402
from ._fe_holes import free_stretch, hole_css, hole_row, holes_on  # noqa: E402
from ._fe_modes import clear_modal_force  # noqa: E402
from ._frames import _disc_frame, _disc_frame_at, disc_trig  # noqa: E402
from ._layout import (A_GEN, DISC0, DISC_STRIDE, DT, MU, M_DISC, NODE_H, PIN_C,  # noqa: E402
                      PIN_RADIUS, PROFILE_OFFSET, RG, RUNOUT_X0, RUNOUT_X1,
                      RUNOUT_Y0, RUNOUT_Y1, V_FRIC, ZETA, ZP)
from ._pin_compliance import pin_series_compliance  # noqa: E402
from ._single_stage import ring_forces, ring_frame  # noqa: E402


MAX_SKIP = 64          # longest skip of an open pin contact [force evaluations]


#: a pin's carried values (:func:`pin_loop`) are computed afresh at every CARRY_REFRESH-th
#: tick of the pin clock (pins staggered by their index), so their round-off cannot grow
CARRY_REFRESH = 64


@numba.njit(**REFCOUNT)
def pin_contacts(P, q, v, Q, K, want, disc, pins, pin_angle, u, next_eval, clock, forces,
                 elastic, fe, modal, arm_elastic=None, carried=None):
    """All pin contacts of disc ``disc``: returns (energy, dissipated power, max penetration,
    largest pin force): :func:`disc_pins` (which ``forces_with`` calls itself for the pins in
    the housing) with its work arrays allocated.

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
    :func:`coupled_pins`, does.  ``carried``: what
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
    if arm_elastic is None:
        arm = np.empty((0, 0))
    else:
        arm = arm_elastic
    cos_d, sin_d = disc_trig(q, disc)
    return disc_pins(P, q, v, Q, K, want, disc, pins, pin_angle, u, next_eval, clock, forces,
                     elastic, fe, modal, pin_slots, pin_work, carry, cos_d, sin_d, arm,
                     arm_elastic is not None)


@numba.njit(cache=CACHE, inline="always")
def disc_pins(P, q, v, Q, K, want, disc, pins, pin_angle, u, next_eval, clock, forces, elastic,
              fe, modal, slots, work, carried, cos_d, sin_d, arm_elastic, with_holes):
    """The parts of :func:`pin_contacts` in their order, with its work arrays given (inlined
    into :func:`~rvsim.physics._forces.forces_with`, which calls it with no allocation and
    no reference counting in :func:`pin_loop`): the pin loop, then the touching pins of a
    finite-element disc solved together (:func:`coupled_pins`), or with none touching the
    holes' free stretch.  ``with_holes``: the crank holes' columns of ``arm_elastic`` are
    used (:mod:`rvsim.physics._fe_holes`).  Returns (energy, dissipated power, max
    penetration, largest pin force)."""
    coupled = fe.shape[1] > 0
    if coupled:
        clear_modal_force(modal[disc])
    energy, power, worst, count, peak = pin_loop(P, q, v, Q, K, want, disc, pins, pin_angle, u,
                                                 next_eval, clock, forces, elastic, coupled,
                                                 slots, work, carried, cos_d, sin_d)
    if count > 0:
        if with_holes:
            hole = hole_row(P, arm_elastic, disc)
            css = hole_css(P, disc)
        else:
            hole = Q[0:0]
            css = 0.0
        e, pw, peak_fe = coupled_pins(P, q, v, Q, K, want, disc, fe[disc], modal[disc], slots,
                                      work, count, forces, elastic, hole, css)
        energy += e
        power += pw
        peak = max(peak, peak_fe)
    elif with_holes and holes_on(P):     # no pin touches: s = c_ss Q (_fe_holes.free_stretch)
        energy += free_stretch(hole_row(P, arm_elastic, disc), hole_css(P, disc))
    return energy, power, worst, peak


@numba.njit(**NO_REFCOUNT)
def pin_loop(P, q, v, Q, K, want, disc, pins, pin_angle, u, next_eval, clock, forces, elastic,
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
def coupled_pins(P, q, v, Q, K, want, disc, table, modal, slots, work, count, forces, elastic,
                 hole, css):
    """The touching pins of disc ``disc`` that :func:`pin_loop` collected, solved together with
    the disc's finite-element ``table`` (:func:`rvsim.physics._fe_contacts.apply_coupled`),
    and their friction; ``hole``, ``css``: the disc's crank-hole state (0-length, 0: none;
    :mod:`rvsim.physics._fe_holes`).  Returns (energy, dissipated power, largest force)."""
    d = DISC0 + DISC_STRIDE * disc
    _, cos_t, sin_t, lvx, lvy, w = _disc_frame(P, q, v, disc)
    energy, power, _ = apply_coupled(table, slots, work, count, P[PIN_C], P[ZETA],
                                     P[M_DISC], forces[disc], elastic[disc], Q, K, want, d, modal,
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


@numba.njit(**REFCOUNT)
def ring_pins(P, q, v, Q, K, want, disc, pins, pin_angle, u, next_eval, clock, pin_force,
              pin_elastic, fe, modes, carried):
    """Disc ``disc``'s pin contacts with the pin ring as output (single-stage drive): found
    in the ring's axes (:func:`~rvsim.physics._single_stage.ring_frame`), their forces and
    stiffness added to ``Q`` and ``K``.  Returns (energy, dissipated power, max
    penetration, largest pin force).  (A function of its own: it allocates, the step loop does
    not.)"""
    qr, vr, Qr, Kr = ring_frame(q, v, want, disc)
    e, pw, pen, peak = pin_contacts(P, qr, vr, Qr, Kr, want, disc, pins, pin_angle, u, next_eval,
                                    clock, pin_force, pin_elastic, fe, modes, None, carried)
    ring_forces(q, qr, Qr, Kr, Q, K, want, disc)
    return e, pw, pen, peak


#: values each pin's evaluation carries to its next (:func:`pin_loop`): the foot's u, cos u,
#: sin u, cos zp u, sin zp u, the elastic force, its power 0.9, the approach and the tangent
#: stiffness it was found at (_contact_law.spring_force_from)
CARRIED = 9


@numba.njit(**REFCOUNT)
def nothing_carried(n_pins):
    """What the pins carry before their first evaluation (NaN: nothing; :func:`pin_loop`)."""
    return np.full((2, n_pins, CARRIED), np.nan)
