"""The one evaluation of the force elements that both engines use (numba): :func:`forces_at`
at an input angle and speed under an output load, :func:`forces_with` with every work array
given.  The elements are called in a fixed order (input shaft or gear meshes, pins, crank
bearings, output pins, seals) and summed in that order: the numbers depend on it (moved out
of ``dynamics/_kernel.py``, issue 31 step 9)."""

from __future__ import annotations

import numba
import numpy as np

from .._cache_guard import invalidate_stale_cache
from .._jit import CACHE

invalidate_stale_cache(__file__)

from ._crank_bearings import crank_bearings  # noqa: E402
from ._fe_holes import holes_on  # noqa: E402
from ._frames import add_crank_force, angle_trig, crank_point  # noqa: E402
from ._friction import mesh_friction, seal_friction  # noqa: E402
from ._gear_mesh import gear_mesh  # noqa: E402
from ._layout import (CARRIER, CH_MESH_F0, CH_PIN_MAX, DISC_COUNT, FRICTION_ON,  # noqa: E402
                      N_DOF, OUT_COUNT, RING_OUTPUT, SEAL_IN, SEAL_OUT, STAGES,
                      W_G_L, W_G_U)
from ._pins import disc_pins, nothing_carried, ring_pins  # noqa: E402
from ._single_stage import input_shaft, output_pin  # noqa: E402


@numba.njit(cache=CACHE, inline="always")
def forces_at(P, q, v, theta_in, omega_in, torque_load, pins, pin_angle, holes, crank_angles,
              mesh_phase, u, next_eval, step, pin_force, pin_elastic, arm_elastic, Q, K, want,
              channel, mesh_state, mesh_hold, fe, modal=None, pin_slots=None, pin_work=None,
              pin_carried=None, K_bearings=None):
    """Generalised forces Q at input angle and speed (theta_in, omega_in) under the output load
    ``torque_load``: the one evaluation of the force elements that both engines use.

    Fills the force channels and ``mesh_state`` (stiffness, deflection of each mesh); with
    ``want`` (the stiffness wanted: a flag, not the shape of ``K``) it also accumulates the
    stiffness matrix -dQ/dq of the elastic forces into ``K`` (17 x 17, zeroed by the caller;
    else 0 x 0).  ``mesh_hold[j]`` = (pairs, unused) held for mesh j (zero: from the roll
    position, see :func:`gear_mesh`); with four columns, ``mesh_state`` also receives the
    pairs at the roll position and the loaded flank.
    With P[FRICTION_ON], the mesh and bearing friction (physics._friction) act after their
    elements with the normal forces those return.  Returns (potential energy, dissipated
    power, input torque, max pin penetration).  ``modal``: the discs' modes (dynamic engine,
    :mod:`rvsim.physics._fe_modes`; omitted: none).  ``pin_slots``, ``pin_work``: the pin
    contacts' work arrays (:func:`pin_contacts`; omitted: allocated per call).
    ``pin_carried``: what each pin's evaluation carries to the next (:func:`pin_loop`; omitted:
    nothing).  ``K_bearings``: a 17 x 17 matrix (zeroed by the caller) that takes the crank
    bearings' stiffness, always wanted, instead of ``K`` (the scheme ``implicit-bearings``,
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
        apart = bool(False)      # typed boolean, not Literal[bool]: one compile of the elements
    else:
        bearings = K_bearings
        apart = bool(True)
    return forces_with(P, q, v, theta_in, omega_in, torque_load, pins, pin_angle, holes,
                       crank_angles, mesh_phase, u, next_eval, step, pin_force, pin_elastic,
                       arm_elastic, Q, K, want, channel, mesh_state, mesh_hold, fe, modes, slots,
                       work, carried, bearings, apart)


@numba.njit(cache=CACHE, inline="always")
def forces_with(P, q, v, theta_in, omega_in, torque_load, pins, pin_angle, holes, crank_angles,
                mesh_phase, u, next_eval, step, pin_force, pin_elastic, arm_elastic, Q, K, want,
                channel, mesh_state, mesh_hold, fe, modes, slots, work, carried, K_bearings,
                bearings_apart):
    """:func:`forces_at` with every work array given (``modes``, the pin contacts' ``slots``
    and ``work``; with ``bearings_apart`` the crank bearings' stiffness goes to
    ``K_bearings``, wanted whatever ``want`` says; else ``K_bearings`` is 0 x 0 and they
    follow ``want``): allocates nothing, so that the step loop compiles without reference
    counting."""
    for i in range(N_DOF):
        Q[i] = 0.0
    # one cosine and sine per angle, shared by the elements
    trig = angle_trig(q, crank_angles)
    energy = 0.0
    power = 0.0
    torque_in = 0.0
    single = P[STAGES] == 1.0
    if single:
        torque_in, energy, power = input_shaft(P, q, v, Q, K, want, theta_in, omega_in)
    else:
        for j in range(2):
            force, torque, e, pw, stiffness, deflection, natural, rule = gear_mesh(
                P, q, v, Q, K, want, j, crank_angles[j], mesh_phase[j], theta_in, omega_in,
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
            e, pw, pen, peak = ring_pins(P, q, v, Q, K, want, disc, pins, pin_angle, u, next_eval,
                                         step, pin_force, pin_elastic, fe, modes, carried)
        else:   # pin_contacts' parts with the work arrays given (no allocation, no
                # reference counting in the pin loop; docs/decisions.md); the FE disc's
                # crank holes as load points where they are on (_fe_holes)
            e, pw, pen, peak = disc_pins(P, q, v, Q, K, want, disc, pins, pin_angle, u, next_eval,
                                         step, pin_force, pin_elastic, fe, modes, slots, work,
                                         carried, trig[4 + 2 * disc], trig[5 + 2 * disc],
                                         arm_elastic, holes_on(P))
        energy += e
        power += pw
        if pen > worst:
            worst = pen
        if peak > pin_peak:
            pin_peak = peak
    channel[CH_PIN_MAX] = pin_peak
    e, pw = crank_bearings(P, q, v, Q, K_bearings if bearings_apart else K,
                           bearings_apart or want, holes, crank_angles, arm_elastic, channel,
                           n_discs, trig)
    energy += e
    power += pw
    if single:
        for disc in range(n_discs):
            for m in range(int(P[OUT_COUNT])):
                force, e, pw = output_pin(P, q, v, Q, K, want, disc, m, arm_elastic)
                energy += e
                power += pw
    if P[FRICTION_ON] == 1.0 and (P[SEAL_IN] > 0.0 or P[SEAL_OUT] > 0.0):
        torque, pw = seal_friction(P, v, Q, omega_in)
        torque_in += torque
        power += pw
    Q[CARRIER] -= torque_load
    return energy, power, torque_in, worst
