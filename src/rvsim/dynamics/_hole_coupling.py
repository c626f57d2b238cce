"""The quasi-static engine's solve of the FE disc's crank-hole coupling (numba; docs/model.md
section 17, "Crank holes as load points"; the state and the one-sweep coupling of the dynamic
engine are :mod:`rvsim.dynamics._fe_holes`).

At fixed coordinates q each disc d has one scalar unknown, its holes' load Q_d: the pins solved
with Q give the stretch s_d(Q_d) and its derivative B_d = ds_d/dQ_d
(:func:`rvsim.dynamics._fe_contacts.apply_coupled`, from the Cholesky factor of the pins'
solve), the arm bushings at the stretches give Q_sum(s) and D = dQ_sum/ds (2 x 2, from the
elements' tangent stiffness, :func:`arm_response`).  :func:`settle` is Newton on
R(Q) = Q_sum(s(Q)) - Q, whose Jacobian is D B - I: each pass is the kernel's whole force
evaluation (:func:`rvsim.dynamics._kernel.forces_at`) with the current Q, repeated with the
Newton update until R is below :data:`HOLE_RTOL` of the largest arm-bushing force; the
evaluation that passes the test is the one whose forces, energy and stiffness the solver takes.
:func:`add_coupling_stiffness` then adds what the coupling changes in the stiffness, by the
implicit-function theorem (no differences)."""

from __future__ import annotations

import math

import numba
import numpy as np

from ._cache_guard import invalidate_stale_cache

invalidate_stale_cache(__file__)

from ._fe_holes import (DF_DQ, DS_DQ, PREDICT, Q_PINS, Q_SUM, SETTLED,  # noqa: E402
                        STRETCH, hole_css, hole_row, holes_on)
from ._kernel import arm_bushing, arm_pair, hole_station  # noqa: E402
from ._layout import (CRANK0, CRANK_COUNT, CRANK_STRIDE, DISC0, DISC_COUNT,  # noqa: E402
                      DISC_STRIDE, FE_CRANK_XX1, FE_HOLE_EX, FE_HOLE_EY, N_DOF)

__all__ = ["HOLE_RTOL", "HOLE_LOOSE", "HOLE_PASSES", "prepare", "settled", "newton_step",
           "newton_update", "correct_forces", "arm_response", "add_coupling_stiffness",
           "forget_prediction", "hole_settled"]

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


@numba.njit(cache=True)
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


@numba.njit(cache=True)
def forget_prediction(P, arm_elastic):
    """No prediction for the next evaluation (a new point of a path: the linear predictor does
    not carry across the bodies' large rigid rotations); its Q starts from the last one."""
    if not holes_on(P):
        return
    for disc in range(2):
        row = hole_row(P, arm_elastic, disc)
        for i in range(N_DOF + 1):
            row[PREDICT + i] = 0.0


@numba.njit(cache=True)
def settled(P, arm_elastic, given, r, Q):
    """After a pass (the arm bushings have summed Q_sum, and the kernel's ``end_arms`` copied it
    to the pins' Q): r = Q_sum - Q given; returns (solved tight, solved loosely) by
    :data:`HOLE_RTOL` and :data:`HOLE_LOOSE` (``Q`` the pass's generalised forces) and records
    the first (:func:`hole_settled`)."""
    largest = 0.0
    for j in range(2):
        largest = max(largest, abs(arm_elastic[j, 0]), abs(arm_elastic[j, 1]))
    outer = 0.0
    for j in range(int(P[CRANK_COUNT])):
        for i in range(4):
            outer = max(outer, abs(Q[CRANK0 + CRANK_STRIDE * j + i]))
    for disc in range(int(P[DISC_COUNT])):
        dd = DISC0 + DISC_STRIDE * disc
        outer = max(outer, abs(Q[dd]), abs(Q[dd + 1]))
    worst = 0.0
    for disc in range(2):
        r[disc] = hole_row(P, arm_elastic, disc)[Q_SUM] - given[disc]
        worst = max(worst, abs(r[disc]))
    tight = worst <= HOLE_RTOL * largest + 1e-12
    for disc in range(2):
        hole_row(P, arm_elastic, disc)[SETTLED] = 1.0 if tight else 0.0
    return tight, worst <= HOLE_LOOSE * outer


@numba.njit(cache=True)
def hole_settled(P, arm_elastic):
    """Whether the last evaluation solved the holes' coupling tight (true with the holes held)."""
    return not holes_on(P) or hole_row(P, arm_elastic, 0)[SETTLED] == 1.0


@numba.njit(cache=True)
def _rotated_axis(P, q, disc):
    """The unit vector e from hole 0 to hole 1 of disc ``disc``, housing axes."""
    th = q[DISC0 + DISC_STRIDE * disc + 2]
    c, s = math.cos(th), math.sin(th)
    return c * P[FE_HOLE_EX] - s * P[FE_HOLE_EY], s * P[FE_HOLE_EX] + c * P[FE_HOLE_EY]


@numba.njit(cache=True)
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
            arm_pair(P, q, v, Qs, Ks, j, holes, arm_elastic)
        else:
            for disc in range(n_discs):
                wl, wu, hole_x, hole_y = hole_station(P, holes, j, disc, arm_elastic)
                arm_bushing(P, q, v, Qs, Ks, j, disc, hole_x, hole_y, wl, wu, arm_elastic)
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


@numba.njit(cache=True)
def _inverse(P, arm_elastic, d):
    """(I - D B)^-1 (2 x 2, row by row), B = diag ds_d/dQ_d of the pins' pass, D = dQ_sum/ds:
    the inverse Jacobian of Q - Q_sum(s(Q))."""
    b0 = hole_row(P, arm_elastic, 0)[DS_DQ]
    b1 = hole_row(P, arm_elastic, 1)[DS_DQ]
    m00, m01 = 1.0 - d[0, 0] * b0, -d[0, 1] * b1
    m10, m11 = -d[1, 0] * b0, 1.0 - d[1, 1] * b1
    det = m00 * m11 - m01 * m10
    return m11 / det, -m01 / det, -m10 / det, m00 / det


@numba.njit(cache=True)
def newton_step(P, arm_elastic, r, d, step):
    """The Newton step of the holes' loads into ``step`` (2): (I - D B)^-1 r (B = diag
    ds_d/dQ_d of the pins' pass, D = dQ_sum/ds, r = Q_sum - Q)."""
    w00, w01, w10, w11 = _inverse(P, arm_elastic, d)
    step[0] = w00 * r[0] + w01 * r[1]
    step[1] = w10 * r[0] + w11 * r[1]


@numba.njit(cache=True)
def newton_update(P, arm_elastic, given, step):
    """The pins' Q of the next pass: the given one plus the Newton ``step``."""
    for disc in range(2):
        hole_row(P, arm_elastic, disc)[Q_PINS] = given[disc] + step[disc]


@numba.njit(cache=True)
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


@numba.njit(cache=True)
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
