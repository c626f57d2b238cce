"""The bearings taken linearly implicitly: the integration scheme ``implicit-bearings``
(issue 14; docs/model.md section 9, docs/decisions.md).

The explicit scheme's step is set by the crank nodes on their bearings (omega up to about
2.2e5 rad/s: the guard measured omega dt up to 1.07 at the default 5e-6 s in the tests'
shortened paper run 2 and 4.5 at 2e-5 s in paper run 3's load step), not by the contact
physics that matters for the TE.  This scheme takes the
bearings' stiffness implicitly to first order.  Each step

    (M + theta h^2 K_b) dv = h Q(q_n, v_n),    v_n+1 = v_n + dv,    q_n+1 = q_n + h v_n+1,

with K_b = -dQ/dq of the bearings alone (the arm and support bushings or rolling bearings:
the tangent stiffness that the same element functions assemble for the quasi-static
engine), symmetrised.  It is the semi-implicit Euler step with the bearings' forces taken
at the position the step's velocity change moves to, q_n + theta h dv, linearised.  Every
other element (meshes, pins, input shaft, output pins) and the contacts' damping stay
explicit.

* Stability, theta = 1/2: for one linear mode of stiffness k (x = (omega h)^2) integrated
  against the mass m + theta h^2 k0 of the factorisation, with its damping 2 zeta sqrt(k m)
  explicit, the step is stable where r x + 4 zeta sqrt(r x) < 4 (1 + theta x), r = k / k0.
  With theta = 1/2 that holds at every step for r = 1 and zeta < 1, and for r = 1.5 and zeta
  < 1/sqrt(3) = 0.577: the factor may lag a stiffening bearing by half its stiffness.  This
  is the bearing modes' bound only: the explicit meshes and pins, damped explicitly too, set
  a lower one for whole runs (paper run 3 at 2e-5 s: `ok` up to a damping ratio of 0.25,
  `energy_imbalance` from 0.28; the explicit scheme runs 0.5; docs/benchmarks.md).  (theta = 1/4, the
  least that is stable undamped, holds only for omega h < 1 / zeta at r = 1 and fails at
  omega h > 2.8 for r = 1.5: a reviewer's case, contact.damping_ratio 0.2, diverged.)
* What it changes: the inertia of a motion that deforms the bearings rises by theta (omega
  h)^2 of its stiffness; a rigid motion of both sides of a bearing (K_b v = 0) none at all,
  so momentum is kept and the slow modes (the drive's torsional mode near 250 Hz, omega h =
  0.03 at 2e-5 s) see a relative change of 5e-4.
* Why only the bearings: the meshes' stiffness jumps as tooth pairs enter and leave, and an
  effective mass that jumps with it pumps energy (-1.8e-3 of the input work in paper run 1
  at 2e-5 s with the meshes in K, -2.8e-5 without; docs/benchmarks.md).
* The factorisation (Cholesky, 17 x 17, in place) is renewed every P[IMPLICIT_REFRESH]
  steps and, at the same step, wherever a bearing's force has risen above ALERT_RATIO
  times its force at the last factorisation plus FORCE_FLOOR (a bushing's stiffness grows
  with its load, more slowly than the force; the play is thrown through within a few
  steps).
"""

from __future__ import annotations

import numba
import numpy as np

from .._jit import NO_REFCOUNT
from .._cache_guard import invalidate_stale_cache

invalidate_stale_cache(__file__)

from ..physics._layout import (CARRIER, CH_ARM_F00, CH_SUP_FU1, CRANK0, CRANK_STRIDE,  # noqa: E402
                               DISC0, DISC_STRIDE, IMPLICIT_THETA, J_CARRIER, J_CRANK, J_DISC, M_DISC,
                               N_DOF)
from ..physics._fe_contacts import _cholesky  # noqa: E402
from ._stiff_nodes import node_mass  # noqa: E402

__all__ = ["THETA", "REFRESH_STEPS", "ALERT_RATIO", "FORCE_FLOOR", "new_work",
           "fill_mass_matrix",
           "factor_effective_mass", "solve_factored", "record_bearing_forces",
           "bearing_forces_risen"]

#: theta of the effective mass (module docstring: stable at any step with the contacts'
#: damping and a factor that lags the stiffness; 1/4 was not)
THETA = 0.5
#: steps between two factorisations (docs/decisions.md: every 2 cost 13-33 % more CPU)
REFRESH_STEPS = 8
#: a bearing force above ALERT_RATIO x its force at the last factorisation (+ FORCE_FLOOR [N])
#: brings the factorisation forward to that step
ALERT_RATIO = 1.5
FORCE_FLOOR = 10.0
#: the force channels of the bearings (arm bushings, then supports): 8 consecutive columns
_FIRST, _LAST = CH_ARM_F00, CH_SUP_FU1


def new_work(P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The scheme's work arrays, which the kernel's ``integrate`` carries between calls:
    (M, K_b, factor) as a (3, 17, 17) array with the mass matrix filled, and (dv, the
    bearings' forces at the last factorisation, a scratch force vector) as (3, 17); empty
    (17 x 0) for the explicit scheme (P[IMPLICIT_THETA] = 0)."""
    n = N_DOF if P[IMPLICIT_THETA] != 0.0 else 0
    matrices = np.zeros((3, n, n))
    if n:
        fill_mass_matrix(P, matrices[0])
    return matrices, np.zeros((3, n))


@numba.njit(**NO_REFCOUNT)
def fill_mass_matrix(P, M):
    """The constant 17 x 17 mass matrix into ``M`` (zeroed here): carrier, each crank's node
    block (x and y of its lower and upper nodes) and rotation, each disc's mass and inertia;
    the kinetic energy 1/2 v^T M v is the kernel's ``kinetic_energy``."""
    for i in range(N_DOF):
        for k in range(N_DOF):
            M[i, k] = 0.0
    M[CARRIER, CARRIER] = P[J_CARRIER]
    m_ll, m_lu, m_uu = node_mass(P)
    for j in range(2):
        b = CRANK0 + CRANK_STRIDE * j
        for axis in range(2):
            M[b + axis, b + axis] = m_ll
            M[b + axis, b + 2 + axis] = m_lu
            M[b + 2 + axis, b + axis] = m_lu
            M[b + 2 + axis, b + 2 + axis] = m_uu
        M[b + 4, b + 4] = P[J_CRANK]
    for disc in range(2):
        d = DISC0 + DISC_STRIDE * disc
        M[d, d] = P[M_DISC]
        M[d + 1, d + 1] = P[M_DISC]
        M[d + 2, d + 2] = P[J_DISC]


@numba.njit(**NO_REFCOUNT)
def factor_effective_mass(M, K, c, A):
    """Cholesky factor L of M + c (K + K^T) / 2 into ``A`` (the finite-element contacts'
    in-place factor, :func:`rvsim.physics._fe_contacts._cholesky`): L below the diagonal,
    1 / L_kk on it (so that :func:`solve_factored` multiplies instead of dividing); returns
    False, leaving ``A`` unusable, where that matrix is not positive definite."""
    n = M.shape[0]
    half = 0.5 * c
    for i in range(n):
        for k in range(i + 1):     # c = 0: M alone, whatever K holds (NaN included)
            A[i, k] = M[i, k] + half * (K[i, k] + K[k, i]) if c != 0.0 else M[i, k]
    if not _cholesky(A, n):
        return False
    for k in range(n):
        A[k, k] = 1.0 / A[k, k]
    return True


@numba.njit(**NO_REFCOUNT)
def solve_factored(A, Q, h, dv):
    """dv = h (L L^T)^-1 Q with L as :func:`factor_effective_mass` leaves it in ``A``."""
    n = A.shape[0]
    for i in range(n):
        s = h * Q[i]
        for m in range(i):
            s -= A[i, m] * dv[m]
        dv[i] = s * A[i, i]
    for i in range(n - 1, -1, -1):
        s = dv[i]
        for m in range(i + 1, n):
            s -= A[m, i] * dv[m]
        dv[i] = s * A[i, i]


@numba.njit(**NO_REFCOUNT)
def record_bearing_forces(channel, reference):
    """The bearings' forces (their channels) at a factorisation, for the alert."""
    for k in range(_LAST - _FIRST + 1):
        reference[k] = channel[_FIRST + k]


@numba.njit(**NO_REFCOUNT)
def bearing_forces_risen(channel, reference):
    """True where a bearing's force has risen above ALERT_RATIO x its force at the last
    factorisation + FORCE_FLOOR: its stiffness has grown beyond what the effective mass holds."""
    for k in range(_LAST - _FIRST + 1):
        if channel[_FIRST + k] > ALERT_RATIO * reference[k] + FORCE_FLOOR:
            return True
    return False
