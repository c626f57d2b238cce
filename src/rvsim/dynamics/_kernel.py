"""Compiled time integration of the RV reducer (numba; arrays and scalars only, no raises).

One driver, :func:`integrate`, advances the 17 generalised coordinates with the semi-implicit
(symplectic) Euler scheme at a fixed step (divided into sub-steps where the crank nodes'
stability guard needs it: dynamics._stiff_nodes) and returns a status code.  The force elements and
their one evaluation, :func:`rvsim.physics._forces.forces_with`, are in the physics layer
(issue 31 step 9); this module keeps the run's schedule (input motion, load) and the step loop.
docs/model.md maps every symbol to its equation and source.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._cache_guard import invalidate_stale_cache
from .._jit import CACHE, NO_REFCOUNT, REFCOUNT

# numba's on-disk cache is keyed on this file only; the index constants of _layout, the curve
# functions of geometry._curve and the force elements of physics are compiled in, so clear the
# cache when those change (_cache_guard.DEPENDENCIES)
invalidate_stale_cache()

from ..physics._crank_bearings import bearing_stiffness
from ..physics._fe_modes import advance_modes, modal_energy
from ..physics._forces import forces_with
from ..physics._layout import (CARRIER, CH_OMEGA_IN, CH_OMEGA_OUT, CH_PIN_MAX, CH_THETA_IN,
                               CH_THETA_OUT, CH_TIME, CH_TORQUE_IN, CH_TORQUE_LOAD, CRANK0,
                               CRANK_STRIDE, DISC0, DISC_STRIDE, DT, E_DISSIPATED, E_INPUT, E_KIN0,
                               E_KIN1, E_OUTPUT, E_PARAMETRIC, E_PIN_PEAK, E_POT0, E_POT1,
                               FLUCT_AMP, FLUCT_FREQ, IMPLICIT_ALERTS, IMPLICIT_FACTORS,
                               IMPLICIT_FALLBACKS, IMPLICIT_REFRESH, IMPLICIT_SINCE,
                               IMPLICIT_THETA, INPUT_SPEED, J_CARRIER, J_CRANK, J_DISC, LOAD,
                               LOAD_T0, LOAD_T1, MINV_LL, MINV_LU, MINV_UU, M_DISC, NODE_ALERT,
                               NODE_CHECKS, NODE_CHECKS_STEADY, NODE_H, NODE_OMEGA_DT, NODE_PEAK,
                               NODE_REFRESH, NODE_SUBSTEPS, N_DOF, OUT_SLOT0, PEN_LIMIT, RAMP_TIME,
                               STEADY_START, ZETA)
from ..physics._status import STATUS_NONFINITE, STATUS_OK, STATUS_PENETRATION
from ._implicit_bearings import (bearing_forces_risen, factor_effective_mass,
                                 record_bearing_forces, solve_factored)
from ._stiff_nodes import ALERT, node_kinetic, node_omega_dt, substeps_for


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


@numba.njit(cache=CACHE, inline="always")
def forces(P, q, v, t, pins, pin_angle, holes, crank_angles, mesh_phase, u, next_eval, step,
           pin_force, pin_elastic, arm_elastic, Q, channel, mesh_state, K, want, mesh_hold, fe,
           modal, pin_slots, pin_work, pin_carried, K_bearings, bearings_apart):
    """Generalised forces Q at time t (:func:`forces_at` with the input motion and the load of
    the run's schedule; ``want``, ``K_bearings``, ``bearings_apart`` as :func:`forces_with`
    takes them). Returns (potential energy, dissipated power, input torque,
    load torque, max pin penetration, input angle, input speed)."""
    theta_in, omega_in = input_motion(P, t)
    torque_load = load_torque(P, t)
    energy, power, torque_in, worst = forces_with(
        P, q, v, theta_in, omega_in, torque_load, pins, pin_angle, holes, crank_angles,
        mesh_phase, u, next_eval, step, pin_force, pin_elastic, arm_elastic, Q, K, want, channel,
        mesh_state, mesh_hold, fe, modal, pin_slots, pin_work, pin_carried, K_bearings,
        bearings_apart)
    return energy, power, torque_in, torque_load, worst, theta_in, omega_in


@numba.njit(cache=CACHE, inline="always")
def impulse_factors(P, h):
    """The (sub-)step ``h``'s velocity change per unit generalised force of each coordinate:
    carrier, crank rotation, disc translation, disc rotation, and the crank nodes' inverse
    mass blocks (lower-lower, lower-upper, upper-upper)."""
    return (h / P[J_CARRIER], h / P[J_CRANK], h / P[M_DISC], h / P[J_DISC], h * P[MINV_LL],
            h * P[MINV_LU], h * P[MINV_UU])


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
            K_node if check else K, check, mesh_hold, fe, modal, pin_slots, pin_work,
            pin_carried, K_bear if refactor else K, refactor)
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
            # (the crank as a non-literal int64: one compiled node_omega_dt, not one per crank)
            stiffest = node_omega_dt(P, K_node, np.int64(0), dt)
            stiffest = max(stiffest, node_omega_dt(P, K_node, np.int64(1), dt))
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
