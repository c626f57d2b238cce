"""The finite-element disc's crank holes as load points (numba; docs/model.md section 17, "Crank
holes as load points"; tables from :mod:`rvsim.fe.disc_holes`).

Relative to the rigid motion of its two holes (the kernel's disc coordinates), the disc's holes
can only move apart along the line through them, by the *stretch* s (hole 0 by -s/2 e, hole 1
by +s/2 e; e the unit vector from hole 0 to hole 1, fixed in the disc).  Its conjugate force is
Q = e . (S_1 - S_0) / 2, S_k the arm bushing's elastic force on hole k, and

    s = sum_j c_sp(u_j) F_j + c_ss Q,      the pins' normal displacement  += c_sp(u_i) Q,

F_j the pins' elastic forces at feet u_j, c_sp the last column of each disc's table (read
linearly between segment centres like the table's diagonal,
:func:`rvsim.physics._fe_contacts.stretch_column`), c_ss in P; the coupled pins' solve
(:func:`rvsim.physics._fe_contacts.apply_coupled`) takes Q and gives s.  The body's strain
energy gains Q sum_j c_sp F_j + c_ss Q^2 / 2 = Q s - c_ss Q^2 / 2.

One Gauss-Seidel sweep per force evaluation: the pins of a disc are solved with the Q of the
previous evaluation (:data:`Q_PINS`) and give s; the arm bushings then see their holes shifted
by +-s/2 e and sum the new Q (:data:`Q_SUM`); :func:`end_arms` hands it to the next
evaluation.  The dynamic engine takes one sweep per step (Q lags one step); the quasi-static
engine solves the coupling at fixed coordinates by Newton with its exact derivatives and adds
it to its stiffness (:mod:`rvsim.quasistatic._solver`), so its forces and energy are those
of the coupled solution.

State: per disc (row ``disc`` of the kernel's ``arm_elastic``) :data:`COLUMNS` columns from
``_layout.HOLE_SLOT0``.
"""

from __future__ import annotations

import math

import numba

from .._cache_guard import invalidate_stale_cache
from .._jit import CACHE

invalidate_stale_cache(__file__)

from ._layout import (DISC0, DISC_STRIDE, FE_HOLE_CSS0, FE_HOLE_CSS1, FE_HOLE_EX,  # noqa: E402
                      FE_HOLE_EY, FE_HOLES, HOLE_COLUMNS, HOLE_SLOT0)

__all__ = ["COLUMNS", "Q_PINS", "Q_SUM", "STRETCH", "DS_DQ", "DF_DQ", "SETTLED", "PREDICT",
           "free_stretch", "hole_row", "hole_css", "hole_shift", "add_hole_load", "begin_arms",
           "end_arms", "holes_on"]

#: columns per disc row: Q read by the pins, Q summed by the arm bushings, the stretch s; for
#: the quasi-static engine (:mod:`rvsim.quasistatic._solver`) also ds/dQ of the pins' solve
#: and d(generalised forces of the pins on the disc x, y, theta)/dQ (written at these offsets
#: by :func:`rvsim.physics._fe_contacts.apply_coupled`), whether the last evaluation solved
#: the coupling tight (1.0) or loosely (0.0), then the predictor of the next evaluation's Q:
#: Q + PREDICT + sum_i dQ/dq_i q_i (PREDICT = -dQ/dq . q at the last solution; the N_DOF
#: columns of dQ/dq from PREDICT + 1)
COLUMNS = HOLE_COLUMNS      # 9 + N_DOF (_layout)
Q_PINS, Q_SUM, STRETCH, DS_DQ, DF_DQ, SETTLED, PREDICT = 0, 1, 2, 3, 4, 7, 8


@numba.njit(cache=CACHE, inline="always")
def holes_on(P):
    """Whether the discs' crank holes are load points (flexibility.fe_disc_holes)."""
    return P[FE_HOLES] != 0.0


@numba.njit(cache=CACHE, inline="always")
def _col(elastic, k):
    """Column of state ``k`` in the kernel's ``arm_elastic``."""
    return HOLE_SLOT0 + k


@numba.njit(cache=CACHE, inline="always")
def hole_row(P, elastic, disc):
    """The crank-hole state of disc ``disc`` (Q read, Q summed, stretch) as a view for the
    coupled pins (:func:`rvsim.physics._fe_contacts.apply_coupled`); empty with the holes
    held."""
    if not holes_on(P):
        return elastic[disc, 0:0]
    c = _col(elastic, Q_PINS)
    return elastic[disc, c:c + COLUMNS]


@numba.njit(cache=CACHE, inline="always")
def hole_css(P, disc):
    """c_ss of disc ``disc`` [m/N]."""
    return P[FE_HOLE_CSS0] if disc == 0 else P[FE_HOLE_CSS1]


@numba.njit(cache=CACHE, inline="always")
def hole_shift(P, elastic, crank, disc):
    """Elastic displacement (disc axes) of crank ``crank``'s hole in disc ``disc``: -+s/2 e."""
    if not holes_on(P):
        return 0.0, 0.0
    half = 0.5 * elastic[disc, _col(elastic, STRETCH)] * (1.0 if crank == 1 else -1.0)
    return half * P[FE_HOLE_EX], half * P[FE_HOLE_EY]


@numba.njit(cache=CACHE, inline="always")
def add_hole_load(P, q, elastic, crank, disc, sx, sy):
    """Add the arm bushing's elastic force (sx, sy) on its hole (housing axes) to Q."""
    if not holes_on(P):
        return
    th = q[DISC0 + DISC_STRIDE * disc + 2]
    c, s = math.cos(th), math.sin(th)
    ex = c * P[FE_HOLE_EX] - s * P[FE_HOLE_EY]
    ey = s * P[FE_HOLE_EX] + c * P[FE_HOLE_EY]
    sign = 1.0 if crank == 1 else -1.0
    elastic[disc, _col(elastic, Q_SUM)] += 0.5 * sign * (ex * sx + ey * sy)


@numba.njit(cache=CACHE, inline="always")
def free_stretch(hole, css):
    """A disc no pin touches: its holes' stretch from their own load alone, s = c_ss Q, and the
    strain energy Q s - c_ss Q^2 / 2 = c_ss Q^2 / 2 (what the coupled pins' solve gives with
    no pin force; without it s would keep a stale value).  ``hole``: the disc's state row
    (:func:`hole_row`); returns the energy."""
    s = css * hole[Q_PINS]
    hole[STRETCH] = s
    return 0.5 * s * hole[Q_PINS]


@numba.njit(cache=CACHE, inline="always")
def begin_arms(P, elastic):
    """Before the arm bushings: Q summed afresh."""
    if holes_on(P):
        for disc in range(2):
            elastic[disc, _col(elastic, Q_SUM)] = 0.0


@numba.njit(cache=CACHE, inline="always")
def end_arms(P, elastic):
    """After the arm bushings: their Q becomes the pins' for the next evaluation; returns the
    largest change of Q [N] (0 with the holes held)."""
    change = 0.0
    if holes_on(P):
        for disc in range(2):
            new = elastic[disc, _col(elastic, Q_SUM)]
            change = max(change, abs(new - elastic[disc, _col(elastic, Q_PINS)]))
            elastic[disc, _col(elastic, Q_PINS)] = new
    return change
