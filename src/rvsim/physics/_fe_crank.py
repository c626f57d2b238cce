"""Arm bushings of a finite-element crank, solved together (numba; docs/model.md section 17,
"Crankshaft"); the same solvers serve the support bushings of the finite-element carrier and
flange (:mod:`rvsim.physics._fe_carrier`: a plate's two bores in place of the two eccentrics).

With ``flexibility.model = fe`` and ``flexibility.fe_crank`` a crank's eccentrics deflect
relative to the straight line through its support nodes under the arm-bushing forces of both
discs: the in-plane block of the crank's condensed table (:mod:`rvsim.fe.crank`; forces x, y of
eccentric 1 and 2, crank frame with eccentric 1 towards +x), turned with the crank angle phi
into the housing frame,

    A(phi) = R(phi) C R(phi)^T  (4 x 4, both eccentrics),

is in series with the two bushings.  S_k, the elastic force of bushing k on its disc hole (the
crank carries -S_k), follows the bushing's own law at the relative position of eccentric centre
and hole *with* the deflection:

    S = f(r - A S),     f_k(r') = F(|r'| - clearance) r' / |r'|,

r the rigid relative positions (eccentric centre - hole centre), F the conforming bushing law
(:func:`rvsim.physics._bearings.conforming_force`).  Potential energy
U = sum_k E_k(|r'_k| - clearance) + S^T A S / 2: dU/dr = S (the forces act on the rigid
coordinates as the rigid crank's), and because A turns with phi, -dU/dphi = S^T (dA/dphi) S / 2
= -(J S)^T A S (J the quarter turn of each eccentric's force): a small torque on the crank
where the table is anisotropic (the crank's torsion adds to the compliance across the
eccentric), kept so that the energy closes.

Two solvers of the same equations:

* :func:`coupled_arm_forces` (quasi-static engine): semi-smooth Newton on the 4-vector,
  g(S) = S - f(r - A S), Jacobian I + D A (D the bushings' 2 x 2 tangent stiffnesses), and the
  stiffness with respect to r, (I + D A)^-1 D, symmetric;
* :func:`lagged_arm_forces` (dynamic engine, one Gauss-Seidel sweep per step): each bushing's
  law in series with its own crank compliance projected on its force direction,
  c_k = n^T A_kk n, solved exactly (a scalar Newton of the conforming law with cb + c_k), the
  other eccentric's force (already swept, or the previous step's) and the anisotropic rest
  (A_kk - c_k I) S_k taken from the previous step.  The sweep is a contraction (docs/model.md
  section 17 gives the factor measured on the RV-40E), so the lag is a few steps' worth.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._jit import CACHE, NO_REFCOUNT, REFCOUNT
from .._cache_guard import invalidate_stale_cache

invalidate_stale_cache(__file__)

from ._bearings import conforming_force, radial_stiffness  # noqa: E402
from ._fe_contacts import _eliminate  # noqa: E402
from ._layout import (ARM_A1, ARM_A2, ARM_CB, ARM_CLEAR, ARM_SHIFT, ARM_J1, ARM_J2,  # noqa: E402
                      FE_CRANK_XX1)

__all__ = ["TABLE_ORDER", "pack_table", "rotated_table", "crank_compliance",
           "compliance_torque", "arm_law", "lagged_pair_forces", "coupled_pair_forces",
           "pair_forces",
           "lagged_arm_forces", "coupled_arm_forces", "MAX_NEWTON"]

#: (row, column) of the 4 x 4 table held in P[FE_CRANK_XX1 + i] (its upper triangle)
TABLE_ORDER = ((0, 0), (0, 1), (0, 2), (0, 3), (1, 1), (1, 2), (1, 3), (2, 2), (2, 3), (3, 3))
#: Newton iterations of the coupled bushings (2-4 needed from the previous forces)
MAX_NEWTON = 30
#: Gauss-Seidel sweeps after a Newton solve that did not converge
MAX_SWEEPS = 500


def pack_table(force_block: np.ndarray) -> np.ndarray:
    """The 10 constants of P (from FE_CRANK_XX1) of a symmetric 4 x 4 force block."""
    c = 0.5 * (force_block + force_block.T)
    return np.array([c[i, j] for i, j in TABLE_ORDER])


@numba.njit(cache=CACHE, inline="always")
def _table(P, base, i, j):
    """C[i, j] of a body-frame table held in P from ``base`` (upper triangle,
    :data:`TABLE_ORDER`)."""
    if i > j:
        i, j = j, i
    return P[base + 4 * i - i * (i - 1) // 2 + j - i]


@numba.njit(**NO_REFCOUNT)
def rotated_table(P, base, phi, A):
    """Fill ``A`` (4 x 4, housing frame, (x1, y1, x2, y2)) with R(phi) C R(phi)^T, C the
    body-frame table held in P from ``base`` (the crank's, or the carrier's:
    :mod:`rvsim.physics._fe_carrier`); phi the direction of the body frame's x axis."""
    cp, sp = math.cos(phi), math.sin(phi)
    for k in range(2):
        for m in range(2):
            a, b = 2 * k, 2 * m
            # R C_km R^T with R = [[cp, -sp], [sp, cp]]
            xx, xy = _table(P, base, a, b), _table(P, base, a, b + 1)
            yx, yy = _table(P, base, a + 1, b), _table(P, base, a + 1, b + 1)
            t00, t01 = cp * xx - sp * yx, cp * xy - sp * yy
            t10, t11 = sp * xx + cp * yx, sp * xy + cp * yy
            A[a, b] = t00 * cp - t01 * sp
            A[a, b + 1] = t00 * sp + t01 * cp
            A[a + 1, b] = t10 * cp - t11 * sp
            A[a + 1, b + 1] = t10 * sp + t11 * cp


@numba.njit(**NO_REFCOUNT)
def crank_compliance(P, phi, A):
    """:func:`rotated_table` of the crank's table; phi the direction of eccentric 1."""
    rotated_table(P, FE_CRANK_XX1, phi, A)


@numba.njit(**NO_REFCOUNT)
def compliance_torque(A, S):
    """-dU/dphi at fixed relative positions: -(J S)^T A S, S (2, 2) the elastic forces on the
    holes, J S = (-S_y, S_x) per eccentric."""
    total = 0.0
    for i in range(4):
        k, axis = i // 2, i % 2
        js = -S[k, 1] if axis == 0 else S[k, 0]
        w = 0.0
        for j in range(4):
            w += A[i, j] * S[j // 2, j % 2]
        total -= js * w
    return total


@numba.njit(**NO_REFCOUNT)
def arm_law(P):
    """The arm bushing's law as (clearance, j1, a1, j2, a2, series compliance, ln(a2 / a1))."""
    return P[ARM_CLEAR], P[ARM_J1], P[ARM_A1], P[ARM_J2], P[ARM_A2], P[ARM_CB], P[ARM_SHIFT]


@numba.njit(**NO_REFCOUNT)
def _law(law, rx, ry, cb, guess):
    """A conforming bushing's law ``law`` (:func:`arm_law`; compliance ``cb`` added in series)
    at the relative position (rx, ry): (Sx, Sy, force, tangent stiffness, energy, distance)."""
    dist = math.sqrt(rx * rx + ry * ry)
    delta = dist - law[0]
    if delta <= 0.0 or dist < 1e-15:
        return 0.0, 0.0, 0.0, 0.0, 0.0, dist
    f, k, e = conforming_force(delta, law[1], law[2], law[3], law[4], law[5] + cb, guess,
                               law[6])
    return f * rx / dist, f * ry / dist, f, k, e, dist


@numba.njit(**NO_REFCOUNT)
def _pair_energy(A, S):
    """S^T A S / 2."""
    total = 0.0
    for i in range(4):
        for j in range(4):
            total += 0.5 * S[i // 2, i % 2] * A[i, j] * S[j // 2, j % 2]
    return total


@numba.njit(**NO_REFCOUNT)
def lagged_arm_forces(P, A, r, guess, force, stiffness):
    """:func:`lagged_pair_forces` of a crank's arm bushings."""
    return lagged_pair_forces(arm_law(P), A, r, guess, force, stiffness)


@numba.njit(**NO_REFCOUNT)
def lagged_pair_forces(law, A, r, guess, force, stiffness):
    """One Gauss-Seidel sweep (dynamic engine) of two bushings of law ``law`` coupled by
    ``A``: ``r`` (2, 2) the rigid relative positions,
    ``guess`` (2, 2) the previous step's elastic forces.  Fills ``force`` (2, 2) and
    ``stiffness`` (2: each bushing's tangent stiffness in series with its projected crank
    compliance, for its damping); returns the potential energy."""
    energy = 0.0
    for k in range(2):
        force[k, 0], force[k, 1] = guess[k, 0], guess[k, 1]
    for k in range(2):
        a = 2 * k
        m = 2 * (1 - k)
        # the other eccentric's force, as swept
        wx = A[a, m] * force[1 - k, 0] + A[a, m + 1] * force[1 - k, 1]
        wy = A[a + 1, m] * force[1 - k, 0] + A[a + 1, m + 1] * force[1 - k, 1]
        gx, gy = guess[k, 0], guess[k, 1]
        g = math.sqrt(gx * gx + gy * gy)
        if g > 0.0:
            nx, ny = gx / g, gy / g
        else:
            nx, ny = r[k, 0] - wx, r[k, 1] - wy
            norm = math.sqrt(nx * nx + ny * ny)
            nx, ny = (nx / norm, ny / norm) if norm > 0.0 else (1.0, 0.0)
        own = nx * (A[a, a] * nx + A[a, a + 1] * ny) + ny * (A[a + 1, a] * nx
                                                            + A[a + 1, a + 1] * ny)
        # the anisotropic rest (A_kk - own I) S_k of the previous step
        wx += A[a, a] * gx + A[a, a + 1] * gy - own * gx
        wy += A[a + 1, a] * gx + A[a + 1, a + 1] * gy - own * gy
        sx, sy, f, kt, e, _ = _law(law, r[k, 0] - wx, r[k, 1] - wy, own, g)
        force[k, 0], force[k, 1] = sx, sy
        stiffness[k] = kt
        # the series law's energy holds own f^2 / 2; the crank's comes below
        energy += e - 0.5 * own * f * f
    return energy + _pair_energy(A, force)


@numba.njit(**NO_REFCOUNT)
def _evaluate(law, A, r, S, f, D, e):
    """The bushings' laws at r - A S: forces f (2, 2), tangent matrices D (4 x 4, block
    diagonal), energies e (2); returns (largest force, largest |S - f|)."""
    largest = 0.0
    worst = 0.0
    for i in range(4):
        for j in range(4):
            D[i, j] = 0.0
    for k in range(2):
        a = 2 * k
        rx, ry = r[k, 0], r[k, 1]
        for j in range(4):
            rx -= A[a, j] * S[j // 2, j % 2]
            ry -= A[a + 1, j] * S[j // 2, j % 2]
        guess = math.sqrt(S[k, 0] ** 2 + S[k, 1] ** 2)
        sx, sy, fk, kt, ek, dist = _law(law, rx, ry, 0.0, guess)
        e[k] = ek
        f[k, 0], f[k, 1] = sx, sy
        if fk > 0.0:
            kxx, kxy, kyy = radial_stiffness(rx / dist, ry / dist, kt, fk, dist)
            D[a, a], D[a, a + 1], D[a + 1, a], D[a + 1, a + 1] = kxx, kxy, kxy, kyy
        largest = max(largest, fk)
        worst = max(worst, abs(S[k, 0] - sx), abs(S[k, 1] - sy))
    return largest, worst


@numba.njit(**NO_REFCOUNT)
def _jacobian(D, A, jac):
    """jac = I + D A."""
    for i in range(4):
        for j in range(4):
            total = 1.0 if i == j else 0.0
            for m in range(4):
                total += D[i, m] * A[m, j]
            jac[i, j] = total


@numba.njit(**NO_REFCOUNT)
def coupled_arm_forces(P, A, r, guess, force, stiffness):
    """:func:`coupled_pair_forces` of a crank's arm bushings."""
    return coupled_pair_forces(arm_law(P), A, r, guess, force, stiffness)


@numba.njit(**REFCOUNT)
def coupled_pair_forces(law, A, r, guess, force, stiffness):
    """Two bushings of law ``law`` coupled by ``A``, solved to convergence (quasi-static
    engine), semi-smooth Newton
    from ``guess`` (2, 2).  Fills ``force`` (2, 2) and ``stiffness`` (4 x 4, dS/dr =
    (I + D A)^-1 D); returns (potential energy, iterations, converged).  The 4 x 4 systems are
    solved by elimination without pivoting (I + D A is diagonally dominant: k C summed over a
    row is below 1, as for the disc's pins)."""
    # one work array (this runs at every evaluation of the quasi-static solver)
    work = np.empty((4, 14))
    D, jac, step = work[:, 0:4], work[:, 4:8], work[:, 8:9]
    S, f, e = work[0:2, 9:11], work[2:4, 9:11], work[0:2, 11]
    for k in range(2):
        S[k, 0], S[k, 1] = guess[k, 0], guess[k, 1]
    converged = False
    iterations = 0
    for iterations in range(1, MAX_NEWTON + 1):
        largest, worst = _evaluate(law, A, r, S, f, D, e)
        if worst <= 1e-10 * largest + 1e-12:
            converged = True
            break
        for i in range(4):
            step[i, 0] = S[i // 2, i % 2] - f[i // 2, i % 2]
        _jacobian(D, A, jac)
        _eliminate(jac, step, 4)
        for i in range(4):
            S[i // 2, i % 2] -= step[i, 0]
    if not converged:
        # Newton can cycle where a bushing opens and closes: Gauss-Seidel sweeps finish
        k2 = np.empty(2)
        for sweep in range(MAX_SWEEPS):
            lagged_pair_forces(law, A, r, S.copy(), S, k2)
            largest, worst = _evaluate(law, A, r, S, f, D, e)
            iterations += 1
            if worst <= 1e-10 * largest + 1e-12:
                converged = True
                break
    for k in range(2):
        force[k, 0], force[k, 1] = f[k, 0], f[k, 1]
    _jacobian(D, A, jac)
    for i in range(4):
        for j in range(4):
            stiffness[i, j] = D[i, j]
    _eliminate(jac, stiffness, 4)
    for i in range(4):
        for j in range(i + 1, 4):
            mean = 0.5 * (stiffness[i, j] + stiffness[j, i])
            stiffness[i, j] = mean
            stiffness[j, i] = mean
    return e[0] + e[1] + _pair_energy(A, force), iterations, converged


@numba.njit(**NO_REFCOUNT)
def pair_forces(law, A, r, guess, force, dsdr, series, want):
    """The two coupled bushings for either engine: solved together with the tangent ``dsdr``
    when the stiffness is ``want``ed (quasi-static), else one sweep (dynamic).  Fills
    ``force`` (2, 2) and ``series`` (2: each bushing's stiffness along its force, for its
    damping: the sweep's law in series with its projected compliance, or n^T (dS/dr)_kk n);
    returns the potential energy."""
    if not want:
        return lagged_pair_forces(law, A, r, guess, force, series)
    energy, _, _ = coupled_pair_forces(law, A, r, guess, force, dsdr)
    for k in range(2):
        a = 2 * k
        f = math.sqrt(force[k, 0] ** 2 + force[k, 1] ** 2)
        nx, ny = (force[k, 0] / f, force[k, 1] / f) if f > 0.0 else (0.0, 0.0)
        series[k] = (nx * (dsdr[a, a] * nx + dsdr[a, a + 1] * ny)
                     + ny * (dsdr[a + 1, a] * nx + dsdr[a + 1, a + 1] * ny))
    return energy
