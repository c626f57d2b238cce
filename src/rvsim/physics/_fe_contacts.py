"""Pin contacts of a finite-element disc, solved together (numba; docs/model.md
"Finite-element bodies").

With ``flexibility.model = fe`` a disc's pins are not independent springs: the approach
delta_i of pin i (the rigid overlap of its gap) is shared by its own contact (Palmgren line
contact in series with the pin body, h_i(F) = c F^0.9 + cb_i F, cb_i the pin's compliance at
its contact's direction, :mod:`rvsim.physics._pin_compliance`) and the disc's elastic
displacement there, which every loaded pin causes:

    delta_i = h_i(F_i) + sum_j C(u_i, u_j) F_j      for a loaded pin (F_i > 0),

C the disc's condensed compliance table (:mod:`rvsim.fe.disc`) read at the contacts' foot
parameters.  Written as F = f(delta - C F), f the contact's own force law (zero where its
argument is not positive), the system is solved by semi-smooth Newton from the forces of the
previous evaluation.  Its potential energy is sum of the contacts' energies + F^T C F / 2, its
stiffness with respect to the approaches S = (I + D C)^-1 D, D = diag of the contacts' tangent
stiffnesses: symmetric, the material stiffness G^T S G of the disc's coordinates.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._jit import CACHE, NO_REFCOUNT, REFCOUNT
from .._cache_guard import invalidate_stale_cache

invalidate_stale_cache(__file__)

from ._contact_law import EXPONENT, damped, spring_force  # noqa: E402
from ._fe_modes import add_modal_force, foot_modes  # noqa: E402

__all__ = ["table_compliance", "stretch_column", "coupled_forces", "lagged_forces", "apply_coupled",
           "MAX_NEWTON"]

#: Newton iterations of the coupled contacts (2-4 needed from the previous forces)
MAX_NEWTON = 30
#: Gauss-Seidel sweeps after a Newton solve that did not converge
MAX_SWEEPS = 2000


@numba.njit(**NO_REFCOUNT)
def _segment(u, m):
    """Lower neighbouring segment centre and the weight of the upper one, for foot ``u``."""
    s = (u / (2.0 * math.pi)) % 1.0 * m - 0.5
    i0 = int(math.floor(s))
    frac = s - i0
    return i0 % m, (i0 + 1) % m, frac


@numba.njit(**NO_REFCOUNT)
def _eliminate(a, b, n):
    """Solve a x = b in place (b becomes x; a is overwritten) by Gaussian elimination without
    pivoting: a = I + D C is diagonally dominant (k C summed over a row is below 1), and for
    the 10-20 touching pins of a disc this is several times faster than a LAPACK call."""
    m = b.shape[1]
    for p in range(n):
        inv = 1.0 / a[p, p]
        for i in range(p + 1, n):
            factor = a[i, p] * inv
            if factor == 0.0:
                continue
            for j in range(p + 1, n):
                a[i, j] -= factor * a[p, j]
            for j in range(m):
                b[i, j] -= factor * b[p, j]
    for p in range(n - 1, -1, -1):
        inv = 1.0 / a[p, p]
        for j in range(m):
            total = b[p, j]
            for i in range(p + 1, n):
                total -= a[p, i] * b[i, j]
            b[p, j] = total * inv


@numba.njit(**NO_REFCOUNT)
def _cholesky(a, n):
    """Cholesky factor L (L L^T = a) of a symmetric positive definite ``a`` in place: its
    lower triangle is read and overwritten (half the operations of :func:`_eliminate`).
    Returns False at a pivot that is not positive."""
    for j in range(n):
        total = a[j, j]
        for p in range(j):
            total -= a[j, p] * a[j, p]
        if not total > 0.0:
            return False
        pivot = math.sqrt(total)
        a[j, j] = pivot
        inv = 1.0 / pivot
        for i in range(j + 1, n):
            total = a[i, j]
            for p in range(j):
                total -= a[i, p] * a[j, p]
            a[i, j] = total * inv
    return True


@numba.njit(**NO_REFCOUNT)
def _forward(a, b, n):
    """b <- L^-1 b in place (b: n x m), L the factor :func:`_cholesky` left in ``a``."""
    for r in range(b.shape[1]):
        for i in range(n):
            total = b[i, r]
            for p in range(i):
                total -= a[i, p] * b[p, r]
            b[i, r] = total / a[i, i]


@numba.njit(**NO_REFCOUNT)
def _cholesky_solve(a, b, n):
    """Solve L L^T x = b in place (b: n x m), L the factor :func:`_cholesky` left in ``a``."""
    _forward(a, b, n)
    for r in range(b.shape[1]):
        for i in range(n - 1, -1, -1):
            total = b[i, r]
            for p in range(i + 1, n):
                total -= a[p, i] * b[p, r]
            b[i, r] = total / a[i, i]


@numba.njit(**NO_REFCOUNT)
def _factor_tangent(cm, k, n, active, a):
    """The loaded contacts (k > 0) into ``active`` and the Cholesky factor of C_AA + D_A^-1
    into ``a``: the matrix I + D C restricted to them, made symmetric (D = diag k, C = ``cm``;
    a row of I + D C with k = 0 is that of the identity).  Its inverse is the loaded block of
    the tangent S = dF/d(delta) = (I + D C)^-1 D, whose other rows are zero.  Returns their
    number, or -1 where the factorisation fails."""
    na = 0
    for i in range(n):
        if k[i] > 0.0:
            active[na] = i
            na += 1
    for x in range(na):
        i = active[x]
        for y in range(x + 1):
            a[x, y] = cm[i, active[y]]
        a[x, x] += 1.0 / k[i]
    return na if _cholesky(a, na) else -1


@numba.njit(cache=CACHE, inline="always")
def stretch_column(table, u):
    """c_sp at foot ``u`` [m/N]: the last column of a table with the crank holes' stretch
    (:mod:`rvsim.physics._fe_holes`), linear between segment centres."""
    m = table.shape[0]
    i0, i1, frac = _segment(u, m)
    return (1.0 - frac) * table[i0, m] + frac * table[i1, m]


@numba.njit(**NO_REFCOUNT)
def table_compliance(table, ui, uj, same):
    """C(ui, uj) [m/N] from the segment table: linear along the diagonal for a contact with
    itself (``same``), bilinear between segment centres otherwise."""
    m = table.shape[0]
    i0, i1, fi = _segment(ui, m)
    if same:
        return (1.0 - fi) * table[i0, i0] + fi * table[i1, i1]
    j0, j1, fj = _segment(uj, m)
    return ((1.0 - fi) * ((1.0 - fj) * table[i0, j0] + fj * table[i0, j1])
            + fi * ((1.0 - fj) * table[i1, j0] + fj * table[i1, j1]))


@numba.njit(**REFCOUNT)
def lagged_forces(table, delta, foot, guess, n, c, cb, force, self_compliance, extra=None):
    """One Gauss-Seidel sweep of the coupled contacts for the dynamic engine (``cb`` (n) the
    contacts' own series compliances): pin i's own law
    in series with its own disc compliance C_ii is solved exactly, its neighbours' forces
    taken as they are (already swept, or ``guess``, their forces of the previous step: the
    coupling lags at most one time step).  Fills ``force`` and ``self_compliance``; returns
    the potential energy.  ``extra`` (n), if given, adds to each pin's own compliance (the
    modes' interpolation term, :func:`rvsim.physics._fe_modes.foot_modes`)."""
    m = table.shape[0]
    lo = np.empty(n, dtype=np.int64)
    hi = np.empty(n, dtype=np.int64)
    frac = np.empty(n)
    for i in range(n):
        lo[i], hi[i], frac[i] = _segment(foot[i], m)
        force[i] = max(guess[i], 0.0)
    energy = 0.0
    for i in range(n):
        a0, a1, fa = lo[i], hi[i], frac[i]
        w = 0.0
        for j in range(n):
            if j == i or force[j] == 0.0:
                continue
            b0, b1, fb = lo[j], hi[j], frac[j]
            cij = ((1.0 - fa) * ((1.0 - fb) * table[a0, b0] + fb * table[a0, b1])
                   + fa * ((1.0 - fb) * table[a1, b0] + fb * table[a1, b1]))
            w += cij * force[j]
        cii = (1.0 - fa) * table[a0, a0] + fa * table[a1, a1]
        if extra is not None:
            cii += extra[i]
        self_compliance[i] = cii
        own = delta[i] - w
        if own > 0.0:
            force[i], _, e = spring_force(own, c, cb[i] + cii, force[i])
            # the series law's energy holds F^2 C_ii / 2; the pair terms come once each
            energy += e + 0.5 * w * force[i]
        else:
            force[i] = 0.0
    return energy


@numba.njit(**NO_REFCOUNT)
def _contact_forces(cm, delta, force, n, c, cb, f, k, e, g):
    """Each contact's law at its own approach less the deflection the forces ``force`` cause
    there (compliance ``cm``): force f, stiffness k, energy e and residual g = force - f;
    returns (largest f, largest |g|)."""
    largest = 0.0
    worst = 0.0
    for i in range(n):
        w = 0.0
        for j in range(n):
            w += cm[i, j] * force[j]
        own = delta[i] - w
        if own > 0.0:
            f[i], k[i], e[i] = spring_force(own, c, cb[i], force[i])
        else:
            f[i], k[i], e[i] = 0.0, 0.0, 0.0
        g[i] = force[i] - f[i]
        largest = max(largest, f[i])
        worst = max(worst, abs(g[i]))
    return largest, worst


@numba.njit(**REFCOUNT)
def _solve_coupled(table, delta, foot, guess, n, c, cb, force, cm, k, jac, scratch, index):
    """Newton solve of :func:`coupled_forces` (the forces into ``force``), leaving the
    interpolated compliance in ``cm``, the contacts' tangent stiffnesses at the solution in
    ``k`` and the factor of :func:`_factor_tangent` at them in ``jac`` (n x n); ``scratch``
    (>= 5 n floats) and ``index`` (>= 3 n integers) are work space.  Returns (potential
    energy, Newton iterations, converged, number of loaded contacts (listed in
    ``index[2 n:3 n]``) or -1 where the factorisation failed)."""
    m = table.shape[0]
    lo = index[:n]
    hi = index[n:2 * n]
    active = index[2 * n:3 * n]
    frac = scratch[:n]
    f = scratch[n:2 * n]
    e = scratch[2 * n:3 * n]
    gv = scratch[3 * n:4 * n]
    rhs = scratch[4 * n:5 * n].reshape((n, 1))
    for i in range(n):
        lo[i], hi[i], frac[i] = _segment(foot[i], m)
    for i in range(n):
        a0, a1, fa = lo[i], hi[i], frac[i]
        cm[i, i] = (1.0 - fa) * table[a0, a0] + fa * table[a1, a1]
        for j in range(i + 1, n):
            b0, b1, fb = lo[j], hi[j], frac[j]
            cij = ((1.0 - fa) * ((1.0 - fb) * table[a0, b0] + fb * table[a0, b1])
                   + fa * ((1.0 - fb) * table[a1, b0] + fb * table[a1, b1]))
            cm[i, j] = cij
            cm[j, i] = cij
    for i in range(n):
        force[i] = max(guess[i], 0.0)
        e[i] = 0.0
    converged = False
    iterations = 0
    na = -1
    for iterations in range(1, MAX_NEWTON + 1):
        largest, worst = _contact_forces(cm, delta, force, n, c, cb, f, k, e, gv)
        # the factor at the new forces: the Newton step's matrix, or the tangent's at the
        # solution
        na = _factor_tangent(cm, k, n, active, jac)
        if worst <= 1e-10 * largest + 1e-12 or na < 0:
            converged = na >= 0
            break
        # Newton step s: (I + D C) s = g.  Rows with k = 0 give s_i = g_i (the force drops
        # to zero); the others (C_AA + D_A^-1) s_A = D_A^-1 g_A - C_AI g_I
        for x in range(na):
            rhs[x, 0] = gv[active[x]] / k[active[x]]
        if na < n:
            for j in range(n):
                if k[j] == 0.0 and gv[j] != 0.0:
                    for x in range(na):
                        rhs[x, 0] -= cm[active[x], j] * gv[j]
        _cholesky_solve(jac, rhs, na)
        for i in range(n):
            if k[i] == 0.0:
                force[i] = 0.0
        for x in range(na):
            i = active[x]
            force[i] = max(force[i] - rhs[x, 0], 0.0)
    if not converged:
        # Newton can cycle where pins open and close between iterations: Gauss-Seidel sweeps
        # (a contraction, k C summed over the neighbours < 1) then finish the solve
        cii = np.empty(n)
        previous = np.empty(n)
        for sweep in range(MAX_SWEEPS):
            previous[:] = force
            lagged_forces(table, delta, foot, previous, n, c, cb, force, cii)
            change = 0.0
            largest = 0.0
            for i in range(n):
                change = max(change, abs(force[i] - previous[i]))
                largest = max(largest, force[i])
            if change <= 1e-10 * largest + 1e-12:
                converged = True
                break
        iterations += sweep + 1
        _contact_forces(cm, delta, force, n, c, cb, f, k, e, gv)
        na = _factor_tangent(cm, k, n, active, jac)
    energy = 0.0
    for i in range(n):
        force[i] = f[i]
        energy += e[i]
    for i in range(n):
        for j in range(n):
            energy += 0.5 * force[i] * cm[i, j] * force[j]
    return energy, iterations, converged, na


@numba.njit(**REFCOUNT)
def coupled_forces(table, delta, foot, guess, n, c, cb, force, stiffness):
    """Elastic forces of ``n`` coupled contacts with approaches ``delta`` at feet ``foot`` and
    own series compliances ``cb`` (n), Newton from ``guess``.  Fills ``force`` (n) and, if
    ``stiffness`` is n x n, the tangent S = dF/d(delta).  Returns (potential energy, Newton
    iterations, converged)."""
    cm = np.empty((n, n))
    k = np.empty(n)
    jac = np.empty((n, n))
    index = np.empty(3 * n, dtype=np.int64)
    energy, iterations, converged, na = _solve_coupled(
        table, delta, foot, guess, n, c, cb, force, cm, k, jac, np.empty(5 * n), index)
    if stiffness.shape[0] == n:
        # S: (C_AA + D_A^-1)^-1 on the loaded contacts A, zero elsewhere
        stiffness[:, :] = 0.0 if na >= 0 else np.nan
        if na > 0:
            inverse = np.eye(na)
            _cholesky_solve(jac, inverse, na)
            active = index[2 * n:2 * n + na]
            for x in range(na):
                for y in range(na):
                    stiffness[active[x], active[y]] = 0.5 * (inverse[x, y] + inverse[y, x])
    return energy, iterations, converged


@numba.njit(**NO_REFCOUNT)
def _hole_derivatives(table, work, active, jac, y, na, css, scratch, hole):
    """The crank holes' load Q seen from the solved pins (:mod:`rvsim.physics._fe_holes`;
    quasi-static engine): into ``hole[3]`` ds/dQ = c_ss - c_A^T S_AA c_A and the pins'
    generalised forces on the disc (``hole[4:7]``) d(x, y, theta)/dQ = -G_A^T S_AA c_A,
    S_AA = (C_AA + D_A^-1)^-1 = L^-T L^-1 the tangent of the loaded pins A (factor L in ``jac``), c_A their
    stretch column (the approaches fall by c_sp Q), ``y`` = L^-1 G_A (na x 3) already formed:
    one forward substitution for t = L^-1 c_A."""
    t = scratch[:na].reshape((na, 1))
    for x in range(na):
        t[x, 0] = stretch_column(table, work[active[x], 2])
    _forward(jac, t, na)
    ds = css
    for x in range(na):
        ds -= t[x, 0] * t[x, 0]
    hole[3] = ds
    for p in range(3):
        total = 0.0
        for x in range(na):
            total += y[x, p] * t[x, 0]
        hole[4 + p] = -total


@numba.njit(**REFCOUNT)
def apply_coupled(table, slots, work, count, c, zeta, mass, forces, elastic, Q, K, want, d,
                  modal, hole, css):
    """Solve the ``count`` touching pins of a disc together and add their forces to ``Q`` (and
    their stiffness to a 17 x 17 ``K``); ``work`` rows hold each pin's (approach, approach
    rate, foot parameter, d(gap)/dx, d(gap)/dy, d(gap)/dtheta, own series compliance) and
    ``slots`` its index.  The
    damping of a pin is 2 zeta sqrt(k m) at its series stiffness k = 1 / (1/k_contact + C_ii).
    ``forces``/``elastic`` are the disc's rows.  With ``K`` wanted (the quasi-static engine)
    the system is solved to convergence (:func:`coupled_forces`) and K_dd gets G^T S G =
    (L^-1 G_A)^T (L^-1 G_A), L the Cholesky factor of the tangent's loaded block; without
    (the dynamic engine, steps of 1e-5 s) one sweep per step (:func:`lagged_forces`).
    ``modal`` (m + HEADER, modes) the disc's modes (:mod:`rvsim.physics._fe_modes`; ``table``
    is then their residual): each approach is less the modes' deflection at its foot, and the
    elastic forces are added to the modal force.  Returns (energy, dissipated power,
    converged).  ``hole`` (7, or empty: the holes held): the disc's crank-hole state of
    :mod:`rvsim.physics._fe_holes` (Q read, Q summed, stretch, ds/dQ, d(Q_x, Q_y, Q_theta)/dQ):
    each approach is less
    c_sp(u) Q (``table``'s last column, :func:`stretch_column`), the stretch
    s = sum c_sp F + ``css`` Q is stored and the energy gains Q s - css Q^2 / 2; with ``K``
    wanted, the solve's response to Q is stored too (:func:`_hole_derivatives`)."""
    n = count
    # one block of work space: delta, foot, own compliances, guess, forces, C_ii, k; with K
    # 5 n of scratch, L^-1 G, the interpolated C and the factor L
    space = np.empty(7 * n + (8 * n + 2 * n * n if want else 0))
    delta = space[:n]
    foot = space[n:2 * n]
    cb = space[2 * n:3 * n]
    guess = space[3 * n:4 * n]
    fel = space[4 * n:5 * n]
    cii = space[5 * n:6 * n]
    k = space[6 * n:7 * n]
    for a in range(n):
        delta[a] = work[a, 0]
        if hole.shape[0] > 0:       # the crank holes' load moves the profile (_fe_holes)
            delta[a] -= hole[0] * stretch_column(table, work[a, 2])
        foot[a] = work[a, 2]
        cb[a] = work[a, 6]
        guess[a] = elastic[slots[a]]
    moving = modal.shape[1] > 0
    # per pin with modes: its segments (lower, upper), the upper's weight, the self-term
    at = np.empty((4, n if moving else 0))
    if moving:
        for a in range(n):
            i0, i1, frac = _segment(foot[a], table.shape[0])
            deflection, at[3, a] = foot_modes(modal, i0, i1, frac)
            at[0, a], at[1, a], at[2, a] = i0, i1, frac
            delta[a] -= deflection
    index = np.empty(3 * n if want else 0, dtype=np.int64)
    if want:
        scratch = space[7 * n:12 * n]
        sg = space[12 * n:15 * n].reshape((n, 3))
        cm = space[15 * n:15 * n + n * n].reshape((n, n))
        jac = space[15 * n + n * n:15 * n + 2 * n * n].reshape((n, n))
        energy, _, converged, na = _solve_coupled(table, delta, foot, guess, n, c, cb, fel,
                                                  cm, k, jac, scratch, index)
        for a in range(n):
            cii[a] = cm[a, a]
    else:
        sg = jac = space[:0].reshape((0, 0))
        na = 0
        if moving:
            energy = lagged_forces(table, delta, foot, guess, n, c, cb, fel, cii, at[3])
        else:
            energy = lagged_forces(table, delta, foot, guess, n, c, cb, fel, cii)
        converged = True
    power = 0.0
    for a in range(n):
        i = slots[a]
        f = fel[a]
        fn = f
        rate = work[a, 1]
        if f > 0.0 and zeta > 0.0 and rate != 0.0:
            # tangent stiffness of the contact's own law at f: 1 / (0.9 c f^-0.1 + cb)
            k_contact = 1.0 / (EXPONENT * c * f ** (EXPONENT - 1.0) + cb[a])
            k_series = 1.0 / (1.0 / k_contact + cii[a])
            fn, pw = damped(f, k_series, rate, zeta, mass)
            power += pw
        forces[i] = fn
        elastic[i] = f
        if moving:
            add_modal_force(modal, int(at[0, a]), int(at[1, a]), at[2, a], f)
        Q[d] += fn * work[a, 3]
        Q[d + 1] += fn * work[a, 4]
        Q[d + 2] += fn * work[a, 5]
    if want:
        # K_dd += G^T S G = Y^T Y, Y = L^-1 G_A (G the rows d gap / d(x, y, theta))
        if na < 0:
            for p in range(3):
                K[d + p, d + p] = np.nan
            if hole.shape[0] > 0:
                hole[3:7] = np.nan
        else:
            active = index[2 * n:2 * n + na]
            y = sg[:na]
            for x in range(na):
                for r in range(3):
                    y[x, r] = work[active[x], 3 + r]
            _forward(jac, y, na)
            for p in range(3):
                for r in range(3):
                    total = 0.0
                    for x in range(na):
                        total += y[x, p] * y[x, r]
                    K[d + p, d + r] += total
            if hole.shape[0] > 0:
                _hole_derivatives(table, work, active, jac, y, na, css, scratch, hole)
    if hole.shape[0] > 0:           # the holes' stretch and its strain energy (_fe_holes)
        s = css * hole[0]
        for a in range(n):
            s += stretch_column(table, work[a, 2]) * fel[a]
        hole[2] = s
        energy += hole[0] * s - 0.5 * css * hole[0] * hole[0]
    return energy, power, converged
