"""Stability guard of the crank nodes for the explicit integrator (issue 14; docs/model.md 9).

The step of the semi-implicit Euler scheme is limited by the crank nodes on their bushings:
the largest eigenvalue omega^2 of M_n^-1 K_n, M_n the 4 x 4 mass matrix of one crank's two
support nodes (x_l, y_l, x_u, y_u) and K_n the tangent stiffness of the elements on them (the
two supports, the two arm bushings, the mesh), rises with the conforming bushings' load, and
the scheme is unstable once omega h exceeds 2 (less with damping).  In a run the largest
values come in the unloaded start and the load step, where the play is thrown through
(docs/benchmarks.md, issue 14), and in the steady window of the runs with stiff bushings.

The guard: every P[NODE_REFRESH] steps the kernel assembles the stiffness matrix (the one the
quasi-static engine uses, ``forces_at`` with a 17 x 17 K) and finds omega dt of both cranks'
node modes.  Where the larger exceeds P[NODE_OMEGA_DT], the whole system takes that step and
the following ones up to the next check in n equal sub-steps (:func:`substeps_for`: omega h
at most ALERT x the limit), each a full step of the same scheme: the physics is unchanged,
only the step is smaller where the nodes need it (the stiff phases run as they would at
dt / n).  While omega h stays above ALERT x the limit the check comes every step; since the
sub-steps leave omega h at most ALERT x the limit, that happens only at n = 1 (omega dt
between ALERT x the limit and the limit) or at the most sub-steps: while sub-stepped, the
checks come every P[NODE_REFRESH] steps, and a stiffness that more than doubles within
those steps would reach the scheme's limit before the next check (not seen in the 36 L36
runs at 1e-5 s; such a run would end with its status, docs/model.md section 9).  Where the
limit is not exceeded (n = 1) nothing changes, bit for bit.  With a coupled finite-element
disc, crank or plate the guard is off (``model.build_model``): passing a K switches their
solves to the converged quasi-static path.

P[NODE_SUBSTEPS] carries n from one call of ``integrate`` to the next.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._jit import NO_REFCOUNT, REFCOUNT
from .._cache_guard import invalidate_stale_cache

invalidate_stale_cache(__file__)

from ..physics._layout import CRANK0, CRANK_STRIDE, MINV_LL, MINV_LU, MINV_UU  # noqa: E402

#: above ALERT x the limit the next check comes at the next step, not P[NODE_REFRESH] steps
#: later: a bushing's stiffness can double within a few steps when the play is thrown
#: through (paper run 29 diverged at 1e-5 s with checks every 8 steps only)
ALERT = 0.9
#: most sub-steps per step (a step so large that even this is not enough may diverge: the
#: run then ends with its status)
MAX_SUBSTEPS = 64
#: Jacobi sweeps for the 4 x 4 symmetric eigenproblem (converged to rounding in 4-6)
_SWEEPS = 8


@numba.njit(**NO_REFCOUNT)
def node_mass(P):
    """(m_ll, m_lu, m_uu): one axis of a crank's node mass matrix (the inverse of P's
    MINV block)."""
    det = P[MINV_LL] * P[MINV_UU] - P[MINV_LU] ** 2
    return P[MINV_UU] / det, -P[MINV_LU] / det, P[MINV_LL] / det


@numba.njit(**NO_REFCOUNT)
def largest_eigenvalue(C):
    """Largest eigenvalue of the symmetric 4 x 4 matrix C (cyclic Jacobi; C is overwritten)."""
    n = 4
    for _ in range(_SWEEPS):
        off = 0.0
        for p in range(n):
            for r in range(p + 1, n):
                off += C[p, r] * C[p, r]
        scale = 0.0
        for p in range(n):
            scale += C[p, p] * C[p, p]
        if off <= 1e-30 * scale:
            break
        for p in range(n - 1):
            for r in range(p + 1, n):
                if C[p, r] == 0.0:
                    continue
                theta = (C[r, r] - C[p, p]) / (2.0 * C[p, r])
                t = (1.0 if theta >= 0.0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(n):          # columns p, r
                    ckp, ckr = C[k, p], C[k, r]
                    C[k, p] = c * ckp - s * ckr
                    C[k, r] = s * ckp + c * ckr
                for k in range(n):          # rows p, r
                    cpk, crk = C[p, k], C[r, k]
                    C[p, k] = c * cpk - s * crk
                    C[r, k] = s * cpk + c * crk
    best = C[0, 0]
    for p in range(1, n):
        if C[p, p] > best:
            best = C[p, p]
    return best


@numba.njit(**REFCOUNT)
def node_omega_dt(P, K, crank, dt):
    """omega dt of crank ``crank``'s stiffest node mode: sqrt(lambda_max(M_n^-1 K_n)) dt, K_n
    the symmetric part of K's node block."""
    m_ll, m_lu, m_uu = node_mass(P)
    # M_n = L L^T per axis (lower, upper), L = [[a, 0], [b, c]]; C = L^-1 K_n L^-T
    a = math.sqrt(m_ll)
    b = m_lu / a
    c = math.sqrt(m_uu - b * b)
    # L^-1 = [[1 / a, 0], [-b / (a c), 1 / c]] for both axes; coordinates (x_l, y_l, x_u, y_u)
    Li = np.zeros((4, 4))
    for axis in range(2):
        Li[axis, axis] = 1.0 / a
        Li[2 + axis, axis] = -b / (a * c)
        Li[2 + axis, 2 + axis] = 1.0 / c
    base = CRANK0 + CRANK_STRIDE * crank
    Ks = np.empty((4, 4))
    for r in range(4):
        for s in range(4):
            Ks[r, s] = 0.5 * (K[base + r, base + s] + K[base + s, base + r])
    C = Li @ Ks @ Li.T
    lam = largest_eigenvalue(C)
    return math.sqrt(lam) * dt if lam > 0.0 else 0.0


@numba.njit(**NO_REFCOUNT)
def node_kinetic(P, v, crank):
    """1/2 v_n^T M_n v_n of crank ``crank``'s nodes."""
    m_ll, m_lu, m_uu = node_mass(P)
    base = CRANK0 + CRANK_STRIDE * crank
    energy = 0.0
    for axis in range(2):
        v_low, v_up = v[base + axis], v[base + 2 + axis]
        energy += 0.5 * (m_ll * v_low * v_low + 2.0 * m_lu * v_low * v_up
                         + m_uu * v_up * v_up)
    return energy


@numba.njit(**NO_REFCOUNT)
def substeps_for(omega_dt, limit):
    """Sub-steps per step for the node modes' omega dt: 1 up to ``limit``, above it the
    fewest that bring omega h to ALERT x ``limit`` or below (so that the next check need not
    come at the next step), at most MAX_SUBSTEPS."""
    if limit <= 0.0 or omega_dt <= limit:
        return 1
    n = int(math.ceil(omega_dt / (ALERT * limit)))
    return n if n < MAX_SUBSTEPS else MAX_SUBSTEPS
