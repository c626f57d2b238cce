"""Compiled static equilibrium of the 17 generalised coordinates (numba; no objects, no raises).

The residual is the force evaluation both engines share, :func:`rvsim.physics._forces.
forces_at`, at zero velocity (so every damping and friction term vanishes) with the input
angle held and the output torque given; its stiffness matrix comes from the same force
elements.  The equilibrium minimises the potential energy Pi(q) = U(q) + T_load theta_c, so
the solver is a damped Newton method with the energy as merit function:

* step (K + mu I) dx = r in scaled coordinates (rotations times a length, so that every
  coordinate is in metres and every residual in newtons), mu a Levenberg-Marquardt term that
  starts at :data:`MU_MIN` (several decades below any contact stiffness) and grows when a step
  is rejected or is not a descent direction (K is indefinite where a body rocks on a convex
  contact: the curvature terms of the bushings);
* a trust region on the largest component of dx (grows after good steps, shrinks after
  rejected ones) carries the bodies across their clearances, where nothing resists them;
* a step is accepted when Pi drops by at least a tenth of the quadratic model's prediction
  (or, once Pi is flat to round-off, when the residual drops);
* converged when every scaled residual is below ``tol`` [N].

A body that no contact touches carries no force, so its residual is zero and the Levenberg-
Marquardt step leaves it where it was: the position of an unloaded body inside its clearance
is the one the continuation brought it to (docs/model.md, "Quasi-static analysis").
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._cache_guard import invalidate_stale_cache
from .._jit import CACHE

# numba caches this module's functions keyed on this file only; the kernel's force elements,
# its layout and the curve functions are compiled in (same guard as the kernel's)
invalidate_stale_cache(__file__)

from ..physics._fe_holes import (DF_DQ, DS_DQ, PREDICT, Q_PINS, Q_SUM, SETTLED,  # noqa: E402
                                 STRETCH, hole_css, hole_row, holes_on)
from ..physics._contact_law import hertz_pressure  # noqa: E402
from ..physics._crank_bearings import arm_bushing, arm_pair  # noqa: E402
from ..physics._forces import forces_at  # noqa: E402
from ..physics._frames import arm_trig, hole_station, profile_turn  # noqa: E402
from ..physics._layout import (A_GEN, CARRIER, CRANK0, CRANK_STRIDE, DISC0,  # noqa: E402
                               DISC_STRIDE, ECC, N_CHANNELS, N_DOF, OUT_COUNT, OUT_SLOT0,
                               FE_DISC, FE_HOLES, PEN_LIMIT, PIN_RADIUS, RING_OUTPUT, STAGES,
                               PROFILE_OFFSET, RB1, RB2, RG, ZC, ZP)
from ..physics._layout import (CRANK_COUNT, DISC_COUNT, FE_CRANK_XX1, FE_HOLE_EX,  # noqa: E402
                               FE_HOLE_EY)
from ..physics._status import (STATUS_NONFINITE, STATUS_NOT_CONVERGED, STATUS_OK,  # noqa: E402
                               STATUS_PENETRATION)
from ..geometry._curve import curvature  # noqa: E402
from ..geometry._pose import disc_centre  # noqa: E402


#: smallest Levenberg-Marquardt term [N/m] (contact stiffnesses are 1e7 .. 1e10 N/m)
MU_MIN = 1.0
#: first trust radius [m of scaled coordinate] (also the largest tangent-predictor step): above
#: the 2-3 um a continued position moves, below the 10-30 um Newton steps that overshoot where
#: a contact barely touches (2e-5 took 8 % more CPU per tolerance-study reducer)
TRUST_START = 5e-6
#: largest trust radius [m]
TRUST_MAX = 1e-3
#: a point where no step above the positions' round-off lowers the energy counts as converged
#: if its residual is below this multiple of the tolerance
ROUNDOFF_FACTOR = 1e3


# ---- the FE disc's crank holes as load points: their coupling at fixed coordinates -------
#
# The quasi-static engine's solve of the FE disc's crank-hole coupling (numba; docs/model.md
# section 17, "Crank holes as load points"; the state and the one-sweep coupling of the dynamic
# engine are :mod:`rvsim.physics._fe_holes`).
#
# At fixed coordinates q each disc d has one scalar unknown, its holes' load Q_d: the pins solved
# with Q give the stretch s_d(Q_d) and its derivative B_d = ds_d/dQ_d
# (:func:`rvsim.physics._fe_contacts.apply_coupled`, from the Cholesky factor of the pins'
# solve), the arm bushings at the stretches give Q_sum(s) and D = dQ_sum/ds (2 x 2, from the
# elements' tangent stiffness, :func:`arm_response`).  :func:`_evaluate` runs Newton on
# R(Q) = Q_sum(s(Q)) - Q, whose Jacobian is D B - I: each pass is the kernel's whole force
# evaluation (:func:`rvsim.physics._forces.forces_at`) with the current Q, repeated with the
# Newton update until R passes :func:`settled` (tight, or loosely away from the equilibrium
# with the forces corrected, :func:`correct_forces`); the evaluation that passes is the one
# whose forces, energy and stiffness the solver takes.
# :func:`add_coupling_stiffness` then adds what the coupling changes in the stiffness, by the
# implicit-function theorem (no differences).

#: solved tight when the holes' load mismatch Q_sum - Q is below this fraction of the largest
#: arm-bushing force (the pins' and bushings' own solves are converged to 1e-10 relative, so a
#: tighter test would chase their round-off) ...
HOLE_RTOL = 1e-9
#: ... and loosely when below this fraction of the largest residual force on the bodies'
#: translations: away from the equilibrium the coupling need not be solved tighter than the
#: forces it changes, which :func:`correct_forces` corrects to first order; the equilibrium's
#: solver takes its converged point only with the coupling solved tight (:func:`hole_settled`)
HOLE_LOOSE = 0.5
#: most force evaluations per coupled solve (Newton: 1-2 from the predicted Q)
HOLE_PASSES = 50


@numba.njit(cache=CACHE)
def prepare(P, q, arm_elastic, given, first):
    """Before a pass: on the ``first`` of an evaluation each disc's Q is predicted from the last
    solution's, Q + dQ/dq (q - q_last) (:func:`add_coupling_stiffness` stored the linear
    function); ``given`` (2) receives the Q the pins will read, and the pins' response columns
    are set to those of a disc no pin touches (the pins' solve overwrites them): s = c_ss Q,
    ds/dQ = c_ss, no force."""
    for disc in range(2):
        row = hole_row(P, arm_elastic, disc)
        if first:
            ahead = row[PREDICT]
            for i in range(N_DOF):
                ahead += row[PREDICT + 1 + i] * q[i]
            row[Q_PINS] += ahead
        given[disc] = row[Q_PINS]
        css = hole_css(P, disc)
        row[STRETCH] = css * row[Q_PINS]
        row[DS_DQ] = css
        for p in range(3):
            row[DF_DQ + p] = 0.0


@numba.njit(cache=CACHE)
def forget_prediction(P, arm_elastic):
    """No prediction for the next evaluation (a new point of a path: the linear predictor does
    not carry across the bodies' large rigid rotations); its Q starts from the last one."""
    if not holes_on(P):
        return
    for disc in range(2):
        row = hole_row(P, arm_elastic, disc)
        for i in range(N_DOF + 1):
            row[PREDICT + i] = 0.0


@numba.njit(cache=CACHE)
def settled(P, arm_elastic, given, r, Q, f_ext):
    """After a pass (the arm bushings have summed Q_sum, and the kernel's ``end_arms`` copied it
    to the pins' Q): r = Q_sum - Q given; returns (solved tight, solved loosely) by
    :data:`HOLE_RTOL` and :data:`HOLE_LOOSE` (``Q`` the pass's generalised forces, ``f_ext``
    the friction forces held, which the residual includes) and records the first
    (:func:`hole_settled`)."""
    largest = 0.0
    for j in range(2):
        largest = max(largest, abs(arm_elastic[j, 0]), abs(arm_elastic[j, 1]))
    outer = 0.0
    for j in range(int(P[CRANK_COUNT])):
        for i in range(4):
            k = CRANK0 + CRANK_STRIDE * j + i
            outer = max(outer, abs(Q[k] + f_ext[k]))
    for disc in range(int(P[DISC_COUNT])):
        dd = DISC0 + DISC_STRIDE * disc
        outer = max(outer, abs(Q[dd] + f_ext[dd]), abs(Q[dd + 1] + f_ext[dd + 1]))
    worst = 0.0
    for disc in range(2):
        r[disc] = hole_row(P, arm_elastic, disc)[Q_SUM] - given[disc]
        worst = max(worst, abs(r[disc]))
    tight = worst <= HOLE_RTOL * largest + 1e-12
    for disc in range(2):
        hole_row(P, arm_elastic, disc)[SETTLED] = 1.0 if tight else 0.0
    return tight, worst <= HOLE_LOOSE * outer


@numba.njit(cache=CACHE)
def hole_settled(P, arm_elastic):
    """Whether the last evaluation solved the holes' coupling tight (true with the holes held)."""
    return not holes_on(P) or hole_row(P, arm_elastic, 0)[SETTLED] == 1.0


@numba.njit(cache=CACHE)
def _rotated_axis(P, q, disc):
    """The unit vector e from hole 0 to hole 1 of disc ``disc``, housing axes."""
    th = q[DISC0 + DISC_STRIDE * disc + 2]
    c, s = math.cos(th), math.sin(th)
    return c * P[FE_HOLE_EX] - s * P[FE_HOLE_EY], s * P[FE_HOLE_EX] + c * P[FE_HOLE_EY]


@numba.njit(cache=CACHE)
def arm_response(P, q, holes, arm_elastic, c, d):
    """The arm bushings' response to the stretches at q (holes shifted by the stored s):
    ``c`` (N_DOF x 2) = d(their generalised forces)/ds_disc and ``d`` (2 x 2) = dQ_sum/ds.

    Hole k of disc d moves by -+s_d/2 e_d (k = 0, 1), which changes the bushing's relative
    position r as a translation of the disc by the same vector does; so the response is the
    element's stiffness column for the disc's translation (the elements' exact tangent,
    accumulated per crank into a scratch matrix: the FE crank couples its two bushings), plus
    the moment of the bushing's force S about the moved hole centre (S_y dx - S_x dy).  The
    elements are evaluated again at the same state (their forces, Newton guesses and the holes'
    Q_sum are left as they were)."""
    v = np.zeros(N_DOF)
    Qs = np.zeros(N_DOF)
    Ks = np.zeros((N_DOF, N_DOF))
    kept = np.empty(2)
    for disc in range(2):
        kept[disc] = hole_row(P, arm_elastic, disc)[Q_SUM]
    c[:, :] = 0.0
    d[:, :] = 0.0
    coupled = P[FE_CRANK_XX1] > 0.0
    n_discs = int(P[DISC_COUNT])
    for j in range(int(P[CRANK_COUNT])):
        Qs[:] = 0.0
        Ks[:, :] = 0.0
        if coupled:
            arm_pair(P, q, v, Qs, Ks, bool(True), j, holes, arm_elastic)
        else:
            for disc in range(n_discs):
                wl, wu, hole_x, hole_y = hole_station(P, holes, j, disc, arm_elastic)
                cos_t, sin_t, cos_p, sin_p = arm_trig(P, q, j, disc)
                arm_bushing(P, q, v, Qs, Ks, bool(True), j, disc, hole_x, hole_y, wl, wu,
                            arm_elastic, cos_t, sin_t, cos_p, sin_p)
        half = 0.5 if j == 1 else -0.5
        for disc in range(n_discs):
            dd = DISC0 + DISC_STRIDE * disc
            ex, ey = _rotated_axis(P, q, disc)
            mx, my = half * ex, half * ey              # the hole's move per unit s_disc
            for i in range(N_DOF):
                c[i, disc] -= Ks[i, dd] * mx + Ks[i, dd + 1] * my
            c[dd + 2, disc] += Qs[dd + 1] * mx - Qs[dd] * my
            for other in range(n_discs):
                od = DISC0 + DISC_STRIDE * other
                ox, oy = _rotated_axis(P, q, other)
                dsx = -(Ks[od, dd] * mx + Ks[od, dd + 1] * my)
                dsy = -(Ks[od + 1, dd] * mx + Ks[od + 1, dd + 1] * my)
                d[other, disc] += half * (ox * dsx + oy * dsy)
    for disc in range(2):
        hole_row(P, arm_elastic, disc)[Q_SUM] = kept[disc]


@numba.njit(cache=CACHE)
def _inverse(P, arm_elastic, d):
    """(I - D B)^-1 (2 x 2, row by row), B = diag ds_d/dQ_d of the pins' pass, D = dQ_sum/ds:
    the inverse Jacobian of Q - Q_sum(s(Q))."""
    b0 = hole_row(P, arm_elastic, 0)[DS_DQ]
    b1 = hole_row(P, arm_elastic, 1)[DS_DQ]
    m00, m01 = 1.0 - d[0, 0] * b0, -d[0, 1] * b1
    m10, m11 = -d[1, 0] * b0, 1.0 - d[1, 1] * b1
    det = m00 * m11 - m01 * m10
    return m11 / det, -m01 / det, -m10 / det, m00 / det


@numba.njit(cache=CACHE)
def newton_step(P, arm_elastic, r, d, step):
    """The Newton step of the holes' loads into ``step`` (2): (I - D B)^-1 r (B = diag
    ds_d/dQ_d of the pins' pass, D = dQ_sum/ds, r = Q_sum - Q)."""
    w00, w01, w10, w11 = _inverse(P, arm_elastic, d)
    step[0] = w00 * r[0] + w01 * r[1]
    step[1] = w10 * r[0] + w11 * r[1]


@numba.njit(cache=CACHE)
def newton_update(P, arm_elastic, given, step):
    """The pins' Q of the next pass: the given one plus the Newton ``step``."""
    for disc in range(2):
        hole_row(P, arm_elastic, disc)[Q_PINS] = given[disc] + step[disc]


@numba.njit(cache=CACHE)
def correct_forces(P, arm_elastic, c, step, Q):
    """The generalised forces ``Q`` of a pass whose holes' loads are off the solution by
    -``step``, corrected to first order: + (a + c B) step (a the pins' d(forces)/dQ, B their
    ds/dQ, c the bushings' d(forces)/ds)."""
    for disc in range(2):
        row = hole_row(P, arm_elastic, disc)
        dd = DISC0 + DISC_STRIDE * disc
        for p in range(3):
            Q[dd + p] += row[DF_DQ + p] * step[disc]
        moved = row[DS_DQ] * step[disc]
        for i in range(N_DOF):
            Q[i] += c[i, disc] * moved


@numba.njit(cache=CACHE)
def add_coupling_stiffness(P, q, arm_elastic, c, d, K):
    """Add to ``K`` (assembled with each disc's Q held for its pins and each stretch s held for
    the arm bushings) what the holes' coupling changes, by the implicit-function theorem:

        K += -a dQ/dq - c ds/dq,   dQ/dq = (I - D B)^-1 (C + D A),   ds/dq = A + B dQ/dq,

    a = d(pins' generalised forces)/dQ (N_DOF x 2; the pins' pass), A = ds/dq at Q held = a^T
    and C = dQ_sum/dq at s held = c^T (each pair a mixed second derivative of the potential
    energy), B = diag ds_d/dQ_d, c and D from :func:`arm_response`.  Symmetrised.  dQ/dq is
    stored as the next evaluation's predictor (:func:`prepare`)."""
    w00, w01, w10, w11 = _inverse(P, arm_elastic, d)
    b0 = hole_row(P, arm_elastic, 0)[DS_DQ]
    b1 = hole_row(P, arm_elastic, 1)[DS_DQ]
    # a (N_DOF x 2) nonzero on each disc's own rows only: its three columns in the rows
    row0, row1 = hole_row(P, arm_elastic, 0), hole_row(P, arm_elastic, 1)
    a = np.zeros((N_DOF, 2))
    for p in range(3):
        a[DISC0 + p, 0] = row0[DF_DQ + p]
        a[DISC0 + DISC_STRIDE + p, 1] = row1[DF_DQ + p]
    dq = np.empty((2, N_DOF))      # dQ/dq = W (C + D A)
    ds = np.empty((2, N_DOF))      # ds/dq = A + B dQ/dq
    for j in range(N_DOF):
        g0 = c[j, 0] + d[0, 0] * a[j, 0] + d[0, 1] * a[j, 1]
        g1 = c[j, 1] + d[1, 0] * a[j, 0] + d[1, 1] * a[j, 1]
        dq[0, j] = w00 * g0 + w01 * g1
        dq[1, j] = w10 * g0 + w11 * g1
        ds[0, j] = a[j, 0] + b0 * dq[0, j]
        ds[1, j] = a[j, 1] + b1 * dq[1, j]
    # K += -(a dQ/dq + c ds/dq), symmetrised
    for i in range(N_DOF):
        for j in range(i, N_DOF):
            total = (a[i, 0] * dq[0, j] + a[i, 1] * dq[1, j] + c[i, 0] * ds[0, j]
                     + c[i, 1] * ds[1, j] + a[j, 0] * dq[0, i] + a[j, 1] * dq[1, i]
                     + c[j, 0] * ds[0, i] + c[j, 1] * ds[1, i])
            K[i, j] -= 0.5 * total
            if j != i:
                K[j, i] -= 0.5 * total
    for disc in range(2):
        row = hole_row(P, arm_elastic, disc)
        ahead = 0.0
        for i in range(N_DOF):
            row[PREDICT + 1 + i] = dq[disc, i]
            ahead -= dq[disc, i] * q[i]
        row[PREDICT] = ahead


@numba.njit(cache=CACHE)
def every_force(P, q, v, theta_in, omega, torque, work, Q, K, want):
    """The elements' forces (:func:`rvsim.physics._forces.forces_at`) with every pin evaluated:
    Q (and K if ``want``, a boolean) at (q, v).  ``work``: the tuple (pins, pin_angle, holes,
    crank_angles, mesh_phase, u, next_eval, pin_force, pin_elastic, arm_elastic, channel,
    mesh_state, mesh_hold, fe).  One compiled function for this engine's two callers
    (:func:`_evaluate`, :func:`friction_forces`), where ``forces_at`` was inlined into each,
    and the step count given as a non-literal int64, the dynamic engine's type, so that both
    engines share the pin elements' compiled code instead of one specialisation each for a
    literal 1 (with the kernel's non-literal crank: both chains' cold compile 182.7 -> 170.4 s
    of CPU, docs/decisions.md, issue 30)."""
    (pins, pin_angle, holes, crank_angles, mesh_phase, u, next_eval, pin_force, pin_elastic,
     arm_elastic, channel, mesh_state, mesh_hold, fe) = work
    return forces_at(P, q, v, theta_in, omega, torque, pins, pin_angle, holes, crank_angles,
                     mesh_phase, u, next_eval, np.int64(1), pin_force, pin_elastic,
                     arm_elastic, Q, K, want, channel, mesh_state, mesh_hold, fe)


@numba.njit(cache=CACHE)
def _evaluate(P, q, theta_in, torque, pins, pin_angle, holes, crank_angles, mesh_phase, u,
              next_eval, pin_force, pin_elastic, arm_elastic, Q, K, channel, mesh_state, v,
              mesh_hold, f_ext, fe):
    """Residual Q, stiffness K and potential energy Pi at q (every pin evaluated); returns
    (Pi, the size of its terms, input torque, max pin penetration).  ``f_ext`` is a constant
    generalised force added to Q (the friction forces held during one search), its potential
    -f_ext . q added to Pi."""
    coupled = P[FE_HOLES] != 0.0    # the FE disc's crank holes as load points
    two = 2 if coupled else 0
    given, r, step = np.empty(two), np.empty(two), np.zeros(two)
    c, d = np.empty((N_DOF if coupled else 0, 2)), np.empty((two, 2))
    newton = coupled
    before = np.inf
    # one force evaluation; with the holes, Newton passes on their load Q (the holes'
    # section above) until it is solved tight, or loosely with the forces corrected
    for attempt in range(HOLE_PASSES if coupled else 1):
        K[:, :] = 0.0
        next_eval[:, :] = 0
        if coupled:
            prepare(P, q, arm_elastic, given, attempt == 0)
        energy, _, torque_in, worst = every_force(
            P, q, v, theta_in, 0.0, torque, (pins, pin_angle, holes, crank_angles, mesh_phase,
                                             u, next_eval, pin_force, pin_elastic, arm_elastic,
                                             channel, mesh_state, mesh_hold, fe), Q, K,
            bool(True))     # bool(): a boolean, not Literal[bool] (one compiled every_force)
        if not coupled:
            break
        tight, loose = settled(P, arm_elastic, given, r, Q, f_ext)
        arm_response(P, q, holes, arm_elastic, c, d)
        # a Newton step that did not halve |r| (contacts switching): plain sweeps from here
        # (Q = Q_sum, a contraction)
        size = max(abs(r[0]), abs(r[1]))
        newton = newton and size <= 0.5 * before
        before = size
        if newton:
            newton_step(P, arm_elastic, r, d, step)
            newton_update(P, arm_elastic, given, step)
        if tight or (loose and newton):
            break
    if coupled:
        add_coupling_stiffness(P, q, arm_elastic, c, d, K)
        if newton:
            correct_forces(P, arm_elastic, c, step, Q)
    work = torque * q[CARRIER]
    held = 0.0
    for i in range(N_DOF):
        Q[i] += f_ext[i]
        held -= f_ext[i] * q[i]
    return energy + work + held, abs(energy) + abs(work) + abs(held), torque_in, worst


@numba.njit(cache=CACHE)
def _copy_state(Q, K, u, pin_force, pin_elastic, arm_elastic, channel, mesh_state,
                Q_to, K_to, u_to, force_to, elastic_to, arm_to, channel_to, mesh_to):
    """Copy the state an evaluation leaves (forces, stiffness, contact arrays) into the
    ``_to`` arrays."""
    Q_to[:] = Q
    K_to[:, :] = K
    u_to[:, :] = u
    force_to[:, :] = pin_force
    elastic_to[:, :] = pin_elastic
    arm_to[:, :] = arm_elastic
    channel_to[:] = channel
    mesh_to[:, :] = mesh_state


@numba.njit(cache=CACHE)
def equilibrium(P, q, theta_in, torque, scale, tol, max_iter, pins, pin_angle, holes,
                crank_angles, mesh_phase, u, next_eval, pin_force, pin_elastic, arm_elastic,
                Q, K, channel, mesh_state, mesh_hold, f_ext, fe):
    """Move ``q`` to the static equilibrium at input angle ``theta_in`` under ``torque``, each
    mesh j with its number of tooth pairs ``mesh_hold[j, 0]`` held (zero: that of the starting
    pose, stored into ``mesh_hold``).  ``mesh_state`` has four columns (stiffness, deflection,
    pairs at the roll position, loaded flank).

    ``scale[i]`` is the length that turns coordinate i into metres (1 for translations, a
    radius for rotations).  ``f_ext``: a constant generalised force (held friction, see
    :func:`_evaluate`).  Returns (status, iterations, input torque); on return Q, K and the
    work arrays hold the state at q.
    """
    n = N_DOF
    v = np.zeros(n)
    q_trial = np.empty(n)
    A = np.empty((n, n))
    r = np.empty(n)
    pi, size, torque_in, worst = _evaluate(P, q, theta_in, torque, pins, pin_angle, holes,
                                           crank_angles, mesh_phase, u, next_eval, pin_force,
                                           pin_elastic, arm_elastic, Q, K, channel,
                                           mesh_state, v, mesh_hold, f_ext, fe)
    for j in range(2):
        if mesh_hold[j, 0] == 0.0:
            mesh_hold[j, 0] = mesh_state[j, 2]
    mu = MU_MIN
    trust = TRUST_START
    # the state at q, put back when a trial step is rejected (cheaper than evaluating q again)
    Q_keep, K_keep = np.empty(n), np.empty((n, n))
    u_keep, force_keep, elastic_keep = np.empty_like(u), np.empty_like(u), np.empty_like(u)
    arm_keep, channel_keep = np.empty_like(arm_elastic), np.empty_like(channel)
    mesh_keep = np.empty_like(mesh_state)
    polish = 0
    for iteration in range(max_iter + 1):
        norm = 0.0
        for i in range(n):
            r[i] = Q[i] / scale[i]
            if abs(r[i]) > norm:
                norm = abs(r[i])
        if not (math.isfinite(norm) and math.isfinite(pi)):
            return STATUS_NONFINITE, iteration, torque_in
        if norm <= tol and not hole_settled(P, arm_elastic) and polish < 5:
            # the FE disc's crank holes solved loosely so far: again at q, from the Newton
            # update of their loads (the holes' section above)
            polish += 1
            pi, size, torque_in, worst = _evaluate(
                P, q, theta_in, torque, pins, pin_angle, holes, crank_angles, mesh_phase, u,
                next_eval, pin_force, pin_elastic, arm_elastic, Q, K, channel, mesh_state, v,
                mesh_hold, f_ext, fe)
            continue
        if norm <= tol:
            if not hole_settled(P, arm_elastic):
                # polishing used up with the holes still solved loosely: not an equilibrium
                return STATUS_NOT_CONVERGED, iteration, torque_in
            if worst > P[PEN_LIMIT]:
                return STATUS_PENETRATION, iteration, torque_in
            return STATUS_OK, iteration, torque_in
        if iteration == max_iter:
            break
        accepted = False
        while not accepted:
            for i in range(n):
                for j in range(n):
                    A[i, j] = K[i, j] / (scale[i] * scale[j])
                A[i, i] += mu
            dx = np.linalg.solve(A, r)
            descent = 0.0
            for i in range(n):
                descent += r[i] * dx[i]
            if not descent > 0.0:
                # K has a negative eigenvalue (a body rocking on a convex contact) that mu
                # does not yet cover: raise mu, keep the trust radius
                mu *= 10.0
                if mu > 1e16:
                    return STATUS_NOT_CONVERGED, iteration, torque_in
                continue
            largest = 0.0
            for i in range(n):
                if abs(dx[i]) > largest:
                    largest = abs(dx[i])
            clipped = largest > trust
            if clipped:
                for i in range(n):
                    dx[i] *= trust / largest
                largest = trust
            # decrease of Pi predicted by the quadratic model
            predicted = 0.0
            for i in range(n):
                predicted += r[i] * dx[i]
                for j in range(n):
                    predicted -= 0.5 * dx[i] * (A[i, j] - (mu if i == j else 0.0)) * dx[j]
            for i in range(n):
                q_trial[i] = q[i] + dx[i] / scale[i]
            norm_old = norm
            _copy_state(Q, K, u, pin_force, pin_elastic, arm_elastic, channel, mesh_state,
                        Q_keep, K_keep, u_keep, force_keep, elastic_keep, arm_keep,
                        channel_keep, mesh_keep)
            size_keep, torque_keep, worst_keep = size, torque_in, worst
            pi_trial, size, torque_in, worst = _evaluate(
                P, q_trial, theta_in, torque, pins, pin_angle, holes, crank_angles, mesh_phase,
                u, next_eval, pin_force, pin_elastic, arm_elastic, Q, K, channel, mesh_state, v,
                mesh_hold, f_ext, fe)
            drop = pi - pi_trial
            # below round-off of Pi's terms the energy cannot rank the points: the residual does
            flat = abs(drop) <= 1e-12 * size + 1e-18
            norm_trial = 0.0
            for i in range(n):
                if abs(Q[i] / scale[i]) > norm_trial:
                    norm_trial = abs(Q[i] / scale[i])
            # with finite-element discs the forces are the energy's gradient only at fixed
            # contact points (the table's dependence on where a pin touches is left out of
            # the forces), so a step that lowers the residual is accepted as well
            if math.isfinite(pi_trial) and (drop >= 0.1 * predicted
                                            or ((flat or P[FE_DISC] != 0.0)
                                                and norm_trial < norm_old)):
                accepted = True
                for i in range(n):
                    q[i] = q_trial[i]
                pi = pi_trial
                if drop >= 0.75 * predicted and clipped:
                    trust = min(2.0 * trust, TRUST_MAX)
                mu = max(0.1 * mu, MU_MIN)
            else:
                trust = 0.25 * largest
                mu *= 10.0
                # back to the last accepted state (pi unchanged)
                _copy_state(Q_keep, K_keep, u_keep, force_keep, elastic_keep, arm_keep,
                            channel_keep, mesh_keep, Q, K, u, pin_force, pin_elastic,
                            arm_elastic, channel, mesh_state)
                size, torque_in, worst = size_keep, torque_keep, worst_keep
                if trust < 1e-16 or mu > 1e16:
                    # no step left above the round-off of the positions (1e-16 m): converged
                    # as far as double precision goes if the residual is near tol (very stiff
                    # contacts turn the positions' round-off into ~ tol of force)
                    if (norm <= ROUNDOFF_FACTOR * tol and worst <= P[PEN_LIMIT]
                            and hole_settled(P, arm_elastic)):
                        return STATUS_OK, iteration, torque_in
                    return STATUS_NOT_CONVERGED, iteration, torque_in
    return STATUS_NOT_CONVERGED, max_iter, torque_in


@numba.njit(cache=CACHE)
def _solve_point(P, q, theta_in, torque, scale, tol, max_iter, pins, pin_angle, holes,
                 crank_angles, mesh_phase, u, next_eval, pin_force, pin_elastic, arm_elastic,
                 Q, K, channel, mesh_state, f_ext, fe):
    """:func:`equilibrium` with each mesh's number of tooth pairs held at that of the starting
    pose (the rectangular-wave stiffness is discontinuous in q); where the equilibrium lies
    across a switch, solved again with the count found there.  Where it would flip back (the
    equilibrium sits on the switch, where none exists for either count), the second count is
    kept.  Both flanks of a mesh are contacts of their own (:func:`rvsim.physics._gear_mesh.
    gear_mesh`), continuous in q: no flank is held.  Returns (status, total iterations, input
    torque)."""
    hold = np.zeros((2, 2))          # zeros: taken from the starting pose by equilibrium()
    total = 0
    status, torque_in = STATUS_OK, 0.0
    for attempt in range(2):
        status, iterations, torque_in = equilibrium(
            P, q, theta_in, torque, scale, tol, max_iter, pins, pin_angle, holes, crank_angles,
            mesh_phase, u, next_eval, pin_force, pin_elastic, arm_elastic, Q, K, channel,
            mesh_state, hold, f_ext, fe)
        total += iterations
        same = True
        for j in range(2):
            if mesh_state[j, 2] != hold[j, 0]:
                same = False
        if status != STATUS_OK or same:
            break
        for j in range(2):
            hold[j, 0] = mesh_state[j, 2]
    return status, total, torque_in


@numba.njit(cache=CACHE)
def kinematic_pose(P, theta_in, holes, q):
    """The ideal (rigid, error-free) pose at input angle ``theta_in`` into ``q``; returns the
    eccentric angle beta (docs/model.md sections 1 and 13)."""
    disc_angle = -1.0        # the discs turn with the output (RV, single-stage output pins)
    if P[STAGES] == 1.0 and P[RING_OUTPUT] == 1.0:
        # single-stage, pin ring output: the discs are held, the ring turns by beta (zp-zc)/zp
        beta = theta_in
        theta_c = theta_in * (P[ZP] - P[ZC]) / P[ZP]
        disc_angle = 0.0
    elif P[STAGES] == 1.0:
        # single-stage: the input turns the eccentric; the disc and output turn by -beta / zc
        beta = theta_in
        theta_c = -theta_in * (P[ZP] - P[ZC]) / P[ZC]
    else:
        ratio = 1.0 + P[RB2] / P[RB1] * P[ZP]
        theta_c = theta_in / ratio
        beta = theta_c - P[RB1] / P[RB2] * (theta_in - theta_c)
    q[CARRIER] = theta_c
    cos_c, sin_c = math.cos(theta_c), math.sin(theta_c)
    for j in range(2):
        b = CRANK0 + CRANK_STRIDE * j
        x = cos_c * holes[j, 0] - sin_c * holes[j, 1]
        y = sin_c * holes[j, 0] + cos_c * holes[j, 1]
        q[b], q[b + 1], q[b + 2], q[b + 3] = x, y, x, y
        q[b + 4] = beta
    for disc in range(2):
        d = DISC0 + DISC_STRIDE * disc
        q[d], q[d + 1] = disc_centre(P[ECC], beta, disc)
        q[d + 2] = theta_c if disc_angle < 0.0 else disc_angle
    return beta


@numba.njit(cache=CACHE)
def _carry_feet(u, shift):
    """Carry the pins' foot-point offsets (``u[disc, i]``, from the pin's nominal parameter,
    :func:`rvsim.physics._pins.pin_contacts`) to the next point of a path in input angle:
    the offsets follow the load pattern, which turns with the eccentric (and the discs) by
    ``shift`` [rad]; linear interpolation between the pins.  Only a start for the kernel's
    foot-point tracking (one Newton step from it, a robust search where that step is too large):
    the offsets left by the previous point are those of pins a whole load pattern away, which
    sends most pins to the robust search (about a quarter of a position's time for the RV-40E)."""
    zp = u.shape[1]
    pitch = 2.0 * math.pi / zp
    s = (shift / pitch) % zp             # in pins, within [0, zp)
    whole = int(math.floor(s))
    frac = s - whole
    old = u.copy()
    for disc in range(u.shape[0]):
        for i in range(zp):
            # the offset at pin i is that of the point shift behind it: between pins
            # i - whole - 1 and i - whole
            a = old[disc, (i - whole) % zp]
            b = old[disc, (i - whole - 1) % zp]
            u[disc, i] = (1.0 - frac) * a + frac * b


@numba.njit(cache=CACHE)
def _predict(P, q, theta_old, theta_new, holes):
    """Carry the elastic and clearance deviation from the ideal pose from one input angle to
    the next, the discs' translations turned with the eccentric (the pin resultant turns with
    it); the cranks' kept (fewest Newton iterations of the variants tried: 3.0 per position
    for the RV-40E at rated torque against 3.8 with the cranks' turned too and 5.0 with
    nothing turned)."""
    ideal_old = np.empty(N_DOF)
    ideal_new = np.empty(N_DOF)
    beta_old = kinematic_pose(P, theta_old, holes, ideal_old)
    beta_new = kinematic_pose(P, theta_new, holes, ideal_new)
    c, s = math.cos(beta_new - beta_old), math.sin(beta_new - beta_old)
    dev = q - ideal_old
    for base in (DISC0, DISC0 + DISC_STRIDE):
        x, y = dev[base], dev[base + 1]
        dev[base], dev[base + 1] = c * x - s * y, s * x + c * y
    for i in range(N_DOF):
        q[i] = ideal_new[i] + dev[i]
    return beta_new - beta_old + ideal_new[CARRIER] - ideal_old[CARRIER]


@numba.njit(cache=CACHE)
def condensed_stiffness(K, scale):
    """Torsional stiffness of the output with the input held: 1 / (K^-1)_cc [N*m/rad].

    The Levenberg-Marquardt floor (:data:`MU_MIN`) keeps a body that no contact holds from
    making K singular (it adds a compliance in series with that body only).
    """
    n = N_DOF
    A = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            A[i, j] = K[i, j] / (scale[i] * scale[j])
        A[i, i] += MU_MIN
    e = np.zeros(n)
    e[CARRIER] = 1.0
    x = np.linalg.solve(A, e)
    return scale[CARRIER] ** 2 / x[CARRIER]


@numba.njit(cache=CACHE)
def virtual_velocity(P, q, theta_in, omega, carrier_rate, K, scale, holes, out):
    """The direction of travel as a velocity field: ``omega`` [rad/s] times the kinematic
    motion per input radian (the ideal pose's derivative) plus ``carrier_rate`` [rad/s] times
    the elastic motion per output radian with the input held (the tangent K^-1 e_c, scaled to
    a unit carrier rotation; K from the last search)."""
    for i in range(N_DOF):
        out[i] = 0.0
    if omega != 0.0:
        h = 1e-6
        ahead = np.empty(N_DOF)
        behind = np.empty(N_DOF)
        kinematic_pose(P, theta_in + h, holes, ahead)
        kinematic_pose(P, theta_in - h, holes, behind)
        for i in range(N_DOF):
            out[i] += omega * (ahead[i] - behind[i]) / (2.0 * h)
    if carrier_rate != 0.0:
        A = np.empty((N_DOF, N_DOF))
        for i in range(N_DOF):
            for j in range(N_DOF):
                A[i, j] = K[i, j] / (scale[i] * scale[j])
            A[i, i] += MU_MIN
        e = np.zeros(N_DOF)
        e[CARRIER] = 1.0
        x = np.linalg.solve(A, e)
        for i in range(N_DOF):
            out[i] += carrier_rate * (x[i] / scale[i]) / (x[CARRIER] / scale[CARRIER])


@numba.njit(cache=CACHE)
def friction_forces(P_fric, q, v, Q0, theta_in, omega, torque, pins, pin_angle, holes,
                    crank_angles, mesh_phase, u, next_eval, pin_force, pin_elastic,
                    arm_elastic, channel, mesh_state, mesh_hold, out, fe):
    """Generalised friction forces at q for the virtual velocity ``v`` (input speed ``omega``)
    into ``out``: the kernel's forces at (q, v) minus ``Q0``, those at (q, 0), with ``P_fric``
    (damping off, friction velocity of the quasi-static engine).  Returns the input torque at
    (q, v) (the elastic mesh torque plus the mesh friction's)."""
    K0 = np.zeros((0, 0))
    next_eval[:, :] = 0
    _, _, torque_in, _ = every_force(P_fric, q, v, theta_in, omega, torque,
                                     (pins, pin_angle, holes, crank_angles, mesh_phase, u,
                                      next_eval, pin_force, pin_elastic, arm_elastic, channel,
                                      mesh_state, mesh_hold, fe), out, K0, bool(False))
    for i in range(N_DOF):
        out[i] -= Q0[i]
    return torque_in


#: most friction updates per position (each a search with the friction forces held)
FRICTION_ITERATIONS = 30


@numba.njit(cache=CACHE)
def _solve_with_friction(P, P_fric, q, theta_in, torque, omega, carrier_rate, scale, tol,
                         max_iter, pins, pin_angle, holes, crank_angles, mesh_phase, u,
                         next_eval, pin_force, pin_elastic, arm_elastic, Q, K, channel,
                         mesh_state, f_ext, fe):
    """Equilibrium with friction that follows the direction of travel: searches with the
    friction forces ``f_ext`` held (from the previous position first), each followed by the
    friction at the new pose, until they change by less than ``tol`` (fixed point; friction
    coefficients well below 1 make it contract).  The direction of travel (the virtual
    velocity) is taken once, at the pose of the first search.  Returns (status, iterations, input torque
    with the mesh friction); ``f_ext`` holds the friction forces of the equilibrium."""
    v = np.empty(N_DOF)
    f_new = np.empty(N_DOF)
    Q0 = np.empty(N_DOF)
    hold = np.zeros((2, 2))
    q_entry = q.copy()
    total = 0
    torque_in = 0.0
    if omega == 0.0 and abs(torque) <= tol * scale[CARRIER]:
        # input held and no output torque (the torque-reversal test's zero crossings): the
        # reducer sticks; with the input turning (no-load running torque) the input drives.
        # Unloaded contacts carry no friction (Coulomb's is bounded by their normal forces),
        # and the bearings' viscous drag needs a motion that nothing drives; held as a
        # constant force it would push the bodies across their play.  The frictionless
        # equilibrium from where the point begins is a static one (zero friction is within
        # every friction law's bound): an unloaded body stays where it was
        for i in range(N_DOF):
            f_ext[i] = 0.0
        return _solve_point(P, q, theta_in, torque, scale, tol, max_iter, pins, pin_angle,
                            holes, crank_angles, mesh_phase, u, next_eval, pin_force,
                            pin_elastic, arm_elastic, Q, K, channel, mesh_state, f_ext, fe)
    restarted = False
    first = 0
    status = STATUS_OK
    for update in range(2 * FRICTION_ITERATIONS):
        if update - first >= FRICTION_ITERATIONS:
            status = STATUS_NOT_CONVERGED
            break
        status, iterations, torque_in = _solve_point(
            P, q, theta_in, torque, scale, tol, max_iter, pins, pin_angle, holes, crank_angles,
            mesh_phase, u, next_eval, pin_force, pin_elastic, arm_elastic, Q, K, channel,
            mesh_state, f_ext, fe)
        total += iterations
        if status == STATUS_NOT_CONVERGED and not restarted:
            # the held friction is a constant force: where contacts unload it can push the
            # bodies across their play, in many small steps along curved contacts, which
            # friction cannot do.  The point starts again from where it began with no
            # friction held (an unloaded body stays where it was) and the friction grows
            # from that of that pose
            restarted = True
            first = update + 1
            for i in range(N_DOF):
                q[i] = q_entry[i]
                f_ext[i] = 0.0
            continue
        if status != STATUS_OK:
            break
        if update == first:
            # the direction of travel of this point, held while the friction settles (a
            # direction taken afresh at each update can turn a tiny relative motion over
            # and back, and the Coulomb forces with it: no fixed point)
            virtual_velocity(P, q, theta_in, omega, carrier_rate, K, scale, holes, v)
        for j in range(2):
            hold[j, 0] = mesh_state[j, 2]
            hold[j, 1] = mesh_state[j, 3] if mesh_state[j, 1] > 0.0 else 0.0
        for i in range(N_DOF):
            Q0[i] = Q[i] - f_ext[i]         # the search's residual holds f_ext
        torque_in = friction_forces(P_fric, q, v, Q0, theta_in, omega, torque, pins,
                                    pin_angle, holes, crank_angles, mesh_phase, u, next_eval,
                                    pin_force, pin_elastic, arm_elastic, channel, mesh_state,
                                    hold, f_new, fe)
        change = 0.0
        for i in range(N_DOF):
            change = max(change, abs(f_new[i] - f_ext[i]) / scale[i])
            f_ext[i] = f_new[i]
        if change <= tol:
            # q is the equilibrium to the tolerance; K, the forces and the channels are those
            # of q (friction changes no normal force); Q is its residual with the new friction
            for i in range(N_DOF):
                Q[i] = Q0[i] + f_ext[i]
            return STATUS_OK, total, torque_in
    return status if status != STATUS_OK else STATUS_NOT_CONVERGED, total, torque_in


@numba.njit(cache=CACHE)
def sweep(P, hertz, q_start, theta_in, torque, scale, tol, max_iter, pins, holes, crank_angles,
          mesh_phase, q_out, pin_out, stress_out, channel_out, mesh_out, stiffness_out,
          status_out, iterations_out, torque_in_out, output_pin_out, P_fric, omega,
          carrier_rate, friction_out, fe):
    """Equilibria along a path of (input angle, output torque) pairs, each started from the
    previous one (continuation); the first from ``q_start``.

    ``hertz`` = (E* of the pin-disc pair [Pa], disc width [m]).  Fills, per point: q, pin
    forces, maximum Hertz pressure per pin, the force channels, mesh (stiffness, deflection),
    local torsional stiffness, status, iterations and input torque.  Stops at the first point
    that fails (its status stored; the later ones keep status -1).  Returns the number of points
    solved.  ``output_pin_out`` (points x 2 discs x output pins) receives the output pins'
    forces of the single-stage drive.

    ``P_fric`` (an empty vector: frictionless; one ``sweep`` compiled for both, issue 30)
    evaluates the friction at each point's virtual velocity
    (:func:`virtual_velocity` with ``omega[k]``, ``carrier_rate[k]``); the friction forces of
    each equilibrium go to ``friction_out`` (points x 17) and the input torque includes the
    mesh friction.
    """
    n_points = theta_in.shape[0]
    zp = pins.shape[0]
    pin_angle = 2.0 * np.pi * np.arange(zp) / zp
    u = np.zeros((2, zp))
    next_eval = np.zeros((2, zp), dtype=np.int64)
    pin_force = np.zeros((2, zp))
    pin_elastic = np.zeros((2, zp))
    n_out = int(P[OUT_COUNT])
    arm_elastic = np.zeros((2, OUT_SLOT0 + n_out))
    mesh_state = np.zeros((2, 4))
    channel = np.zeros(N_CHANNELS)
    Q = np.zeros(N_DOF)
    K = np.zeros((N_DOF, N_DOF))
    A = np.empty((N_DOF, N_DOF))
    q = q_start.copy()
    f_ext = np.zeros(N_DOF)
    f_last = np.zeros(N_DOF)
    for k in range(n_points):
        status_out[k] = -1
    for k in range(n_points):
        if k > 0:
            if theta_in[k] != theta_in[k - 1]:
                shift = _predict(P, q, theta_in[k - 1], theta_in[k], holes)
                forget_prediction(P, arm_elastic)
                if P[STAGES] != 1.0:
                    _carry_feet(u, shift)
            elif torque[k] != torque[k - 1]:
                # tangent predictor: K dq = -dT e_c, limited to the first trust radius
                for i in range(N_DOF):
                    for j in range(N_DOF):
                        A[i, j] = K[i, j] / (scale[i] * scale[j])
                    A[i, i] += MU_MIN
                e = np.zeros(N_DOF)
                e[CARRIER] = -(torque[k] - torque[k - 1]) / scale[CARRIER]
                dx = np.linalg.solve(A, e)
                largest = np.max(np.abs(dx))
                factor = 1.0 if largest <= TRUST_START else TRUST_START / largest
                for i in range(N_DOF):
                    q[i] += factor * dx[i] / scale[i]
        if P_fric.shape[0] == 0:
            status, iterations, torque_in = _solve_point(
                P, q, theta_in[k], torque[k], scale, tol, max_iter, pins, pin_angle, holes,
                crank_angles, mesh_phase, u, next_eval, pin_force, pin_elastic, arm_elastic, Q,
                K, channel, mesh_state, f_ext, fe)
        else:
            if k > 1:
                # friction of the previous point extrapolated along the path; turned over
                # where the direction of travel turns
                same = omega[k] * omega[k - 1] + carrier_rate[k] * carrier_rate[k - 1]
                for i in range(N_DOF):
                    held = f_ext[i]
                    f_ext[i] = 2.0 * held - f_last[i] if same > 0.0 else -held
                    f_last[i] = held
            else:
                f_last[:] = f_ext
            status, iterations, torque_in = _solve_with_friction(
                P, P_fric, q, theta_in[k], torque[k], omega[k], carrier_rate[k], scale, tol,
                max_iter, pins, pin_angle, holes, crank_angles, mesh_phase, u, next_eval,
                pin_force, pin_elastic, arm_elastic, Q, K, channel, mesh_state, f_ext, fe)
            friction_out[k, :] = f_ext
        status_out[k] = status
        iterations_out[k] = iterations
        torque_in_out[k] = torque_in
        q_out[k, :] = q
        pin_out[k, :, :] = pin_force
        for m in range(n_out):
            output_pin_out[k, 0, m] = arm_elastic[0, OUT_SLOT0 + m]
            output_pin_out[k, 1, m] = arm_elastic[1, OUT_SLOT0 + m]
        channel_out[k, :] = channel
        mesh_out[k, :, :] = mesh_state[:, :2]
        stiffness_out[k] = condensed_stiffness(K, scale)
        _hertz(P, hertz, q, u, pin_angle, pin_force, stress_out[k])
        if status != STATUS_OK:
            return k + 1
    return n_points


@numba.njit(cache=CACHE)
def _hertz(P, hertz, q, u, pin_angle, pin_force, out):
    """Maximum Hertz pressure of each loaded pin (line contact, the profile's curvature at the
    contact point): p = sqrt(F E* (1/r_pin + kappa_profile) / (pi L)),
    :func:`~rvsim.physics._contact_law.hertz_pressure`."""
    e_star, width = hertz[0], hertz[1]
    offset = P[PROFILE_OFFSET]
    for disc in range(2):
        angle = q[DISC0 + DISC_STRIDE * disc + 2] + profile_turn(P, disc)
        if P[STAGES] == 1.0 and P[RING_OUTPUT] == 1.0:
            angle -= q[CARRIER]          # the disc's angle relative to the turning pin ring
        for i in range(pin_force.shape[1]):
            f = pin_force[disc, i]
            if f <= 0.0:
                out[disc, i] = 0.0
                continue
            foot = pin_angle[i] - angle + u[disc, i]
            kappa = curvature(foot, P[RG], P[A_GEN], P[ZP])     # of the pin-centre curve
            kappa_profile = kappa / (1.0 - offset * kappa)      # of the offset profile
            relative = 1.0 / P[PIN_RADIUS] + kappa_profile
            out[disc, i] = hertz_pressure(f, e_star, relative, width)
