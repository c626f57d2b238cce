"""Laws of the crank bearings (numba; docs/model.md section "Bearings").

* :func:`conforming_force`: a journal in a bushing bore of nearly the same radius (two
  conforming interfaces in series, journal - bushing and bushing - bore, plus a linear
  compliance).  Each interface follows Johnson's approach of two cylinders in contact
  (K. L. Johnson, *Contact Mechanics*, 1985, Sec. 5.6, as reviewed for internal contact by
  Pereira, Ramalho & Ambrosio 2011, Nonlinear Dyn. 63:681-697):

      delta = F / (pi L E*) * (ln(4 pi L E* dR / F) - 1) = j F (ln(a / F) - 1),

  j = 1 / (pi L E*), a = 4 pi L E* dR, dR the radial difference of the two surfaces.  The
  Hertz half-width b of the conforming pair satisfies a / F = (4 R / b)^2, so the law holds
  while b is small against R; where b would reach R (F = a / 16: the contact wraps the
  journal) it is continued linearly with its tangent compliance there.
* :func:`roller_set`: a rolling bearing without rings of its own or with them, every roller a
  Palmgren line contact with both raceways in series, at angles that follow the cage.
"""

from __future__ import annotations

import math

import numba

from .._jit import CACHE, NO_REFCOUNT
from .._cache_guard import invalidate_stale_cache
from ._contact_law import contact

invalidate_stale_cache(__file__)

__all__ = ["WRAP_RATIO", "johnson_interface", "conforming_approach", "conforming_force",
           "conforming_force_carried", "conforming_force_from",
           "conforming_start",
           "bushing_shift",
           "radial_stiffness", "roller_set"]

#: a / F at which the Hertz half-width of the conforming pair reaches the journal radius
WRAP_RATIO = 16.0
#: Newton steps below this fraction of the force end the iteration (:func:`conforming_force`)
NEWTON_CLOSE = 3e-7
#: relative Newton steps up to which ln(a1 / F) follows the step by its series
#: (:func:`log_ratio`) instead of a new logarithm
SERIES_LIMIT = 1e-2
#: relative changes up to which Newton starts from the Taylor predictor even beyond the
#: series (a positive start: Newton converges from any, monotonically once below the root)
PREDICTOR_LIMIT = 0.5
_LOG_WRAP = math.log(WRAP_RATIO)
#: 1 / n of the series of ln(1 + x) (:func:`log_ratio`)
_INV2, _INV3, _INV4, _INV5, _INV6, _INV7, _INV8 = (1.0 / n for n in range(2, 9))


@numba.njit(cache=CACHE, inline="always")
def _interface(f, log, j, a):
    """:func:`johnson_interface` with ``log`` = ln(a / f) given (used only below F = a / 16)."""
    f_wrap = a / WRAP_RATIO
    if f <= f_wrap:
        return j * f * (log - 1.0), j * (log - 2.0), j * f * f * (0.5 * log - 0.75)
    slope = j * (_LOG_WRAP - 2.0)
    delta_wrap = j * f_wrap * (_LOG_WRAP - 1.0)
    energy_wrap = j * f_wrap * f_wrap * (0.5 * _LOG_WRAP - 0.75)
    return (delta_wrap + slope * (f - f_wrap), slope,
            energy_wrap + 0.5 * slope * (f * f - f_wrap * f_wrap))


@numba.njit(**NO_REFCOUNT)
def johnson_interface(f, j, a):
    """Approach, compliance d(delta)/dF and stored energy of one conforming interface at the
    force ``f`` > 0 (Johnson's law, continued linearly beyond F = a / 16)."""
    return _interface(f, math.log(a / f), j, a)


@numba.njit(cache=CACHE, inline="always")
def _conforming(f, j1, a1, j2, a2, cb, shift):
    """:func:`conforming_approach` with ``shift`` = ln(a2 / a1) given: one logarithm per
    evaluation, ln(a2 / f) = ln(a1 / f) + shift."""
    return _conforming_log(f, math.log(a1 / f), j1, a1, j2, a2, cb, shift)


@numba.njit(cache=CACHE, inline="always")
def _conforming_log(f, log, j1, a1, j2, a2, cb, shift):
    """:func:`_conforming` with ``log`` = ln(a1 / f) given."""
    d1, c1, e1 = _interface(f, log, j1, a1)
    d2, c2, e2 = _interface(f, log + shift, j2, a2)
    return d1 + d2 + cb * f, c1 + c2 + cb, e1 + e2 + 0.5 * cb * f * f


@numba.njit(**NO_REFCOUNT)
def conforming_approach(f, j1, a1, j2, a2, cb):
    """Approach, compliance and energy of two conforming interfaces and a linear compliance
    ``cb`` in series, at the force ``f`` > 0."""
    return _conforming(f, j1, a1, j2, a2, cb, bushing_shift(a1, a2))


@numba.njit(**NO_REFCOUNT)
def conforming_curvature(f, a1, j1, a2, j2):
    """d(compliance)/dF of the two conforming interfaces at the force ``f`` > 0: -j / F for an
    interface below F = a / 16, zero on its linear continuation."""
    return -_curving(f, a1, j1, a2, j2) / f


@numba.njit(**NO_REFCOUNT)
def bushing_shift(a1, a2):
    """ln(a2 / a1), the shift between the logarithms of a conforming bushing's two interfaces
    (0 where a2 = a1, or where the bushing has none: a1 or a2 = 0); the model computes it once
    per run for :func:`conforming_force`."""
    return 0.0 if a2 == a1 or a1 <= 0.0 or a2 <= 0.0 else math.log(a2 / a1)


@numba.njit(**NO_REFCOUNT)
def conforming_force(delta, j1, a1, j2, a2, cb, guess, shift=math.nan):
    """Force, tangent stiffness dF/d(delta) and stored energy of the conforming bushing at the
    approach ``delta`` > 0 (inverse of :func:`conforming_approach`).

    The approach is a concave increasing function of the force, so Newton's method converges
    monotonically once an iterate lies below the root, and one step from above lands below
    it; ``guess`` (the previous step's force, 0: none) saves most iterations.  Newton's error
    after a step s is at most (|delta''| / 2 delta') s^2 <= 0.65 s^2 / F (the compliance is at
    least (j1 + j2)(ln 16 - 2)), so a step below :data:`NEWTON_CLOSE` F leaves a relative
    error below 1e-13: the iteration stops there, the compliance and energy carried from the
    last evaluation to the new force to first order (their error is of the same order).
    ``shift``: ln(a2 / a1) (:func:`bushing_shift`; omitted: computed here).
    """
    f, k, e, _ = conforming_force_carried(delta, j1, a1, j2, a2, cb, guess, shift)
    return f, k, e


@numba.njit(**NO_REFCOUNT)
def conforming_force_carried(delta, j1, a1, j2, a2, cb, guess, shift=math.nan):
    """:func:`conforming_force` that returns ln(a1 / F) as well, for the caller to carry to
    :func:`conforming_force_from`: (F, stiffness, energy, ln(a1 / F))."""
    f = guess
    if not f > 0.0:
        # the secant compliance is at least j1 + j2 + cb: an upper bound of the root
        f = delta / (j1 + j2 + cb)
    if shift != shift:
        shift = bushing_shift(a1, a2)
    return _conforming_newton(delta, f, math.log(a1 / f), j1, a1, j2, a2, cb, shift)


@numba.njit(**NO_REFCOUNT)
def conforming_force_from(delta, j1, a1, j2, a2, cb, shift, f0, d0, k0, log0):
    """:func:`conforming_force` started from the previous solution's Taylor expansion: the
    force ``f0`` > 0 at the approach ``d0``, with the stiffness ``k0`` and ``log0`` = ln(a1 /
    f0), all four carried by the caller from its last call.

    The predictor f0 + k0 dd + F'' dd^2 / 2 (dd = delta - d0, F'' = j k0^3 / f0 from the law's
    curvature, j = j1 + j2 below the wrap) is off by the third order of the change, so that
    where the force changes by up to about 1 % per call Newton's first step is already below
    NEWTON_CLOSE F: one evaluation of the law per call instead of two or three, ln(a1 / F)
    by its series from ``log0``, and the divisions off the chain of dependent operations.
    The same stopping rule as :func:`conforming_force`, so the same accuracy; a change beyond
    SERIES_LIMIT starts Newton from the predictor with a fresh logarithm (beyond
    PREDICTOR_LIMIT from ``f0``, as :func:`conforming_force` starts from its guess).
    Returns (F, stiffness, energy, ln(a1 / F))."""
    x = conforming_start(delta, f0, d0, k0, a1, j1, a2, j2)
    if not abs(x) <= SERIES_LIMIT:
        # beyond the series: Newton from the predictor all the same (a fresh logarithm),
        # which is off by the third order of the change, or from f0 beyond PREDICTOR_LIMIT
        return conforming_force_carried(delta, j1, a1, j2, a2, cb,
                                        f0 + f0 * x if abs(x) <= PREDICTOR_LIMIT else f0,
                                        shift)
    f = f0 + f0 * x
    inv_f = 1.0 / f
    log = log0 - log_ratio(x)
    d, c, e = _conforming_log(f, log, j1, a1, j2, a2, cb, shift)
    inv_c = 1.0 / c
    step = (d - delta) * inv_c
    new = f - step
    if abs(step) <= NEWTON_CLOSE * new:
        e -= f * c * step
        y = -step * inv_f                               # |y| <= 3e-7
        # the stiffness 1 / (c + dc) to second order in dc / c, as in _conforming_newton
        z = _curving(f, a1, j1, a2, j2) * step * inv_f * inv_c
        return (new, inv_c * (1.0 - z * (1.0 - z)), e,
                log - y * (1.0 - y * (0.5 - y * _INV3)))
    if abs(step) <= SERIES_LIMIT * f:
        log -= log_ratio(-step * inv_f)
    else:
        new = f - step if f - step > 0.0 else 0.01 * f
        log = math.log(a1 / new)
    return _conforming_newton(delta, new, log, j1, a1, j2, a2, cb, shift)


@numba.njit(cache=CACHE, inline="always")
def conforming_start(delta, f0, d0, k0, a1, j1, a2, j2):
    """Newton's start of :func:`conforming_force_from` relative to the last solution: F / f0
    - 1 at the approach ``delta`` by the second-order Taylor expansion of the inverse law
    (F'' = j k0^3 / f0, :func:`_curving`)."""
    move = k0 * (delta - d0) * (1.0 / f0)              # first order, relative to f0
    return move * (1.0 + 0.5 * _curving(f0, a1, j1, a2, j2) * k0 * move)


@numba.njit(cache=CACHE, inline="always")
def _curving(f, a1, j1, a2, j2):
    """j of the interfaces that follow Johnson's law at the force ``f`` (below F = a / 16):
    the compliance's slope is -j / F (:func:`conforming_curvature`)."""
    j = 0.0
    if f <= a1 / WRAP_RATIO:
        j += j1
    if f <= a2 / WRAP_RATIO:
        j += j2
    return j


@numba.njit(cache=CACHE, inline="always")
def _conforming_newton(delta, f, log, j1, a1, j2, a2, cb, shift):
    """Newton on the conforming law from the force ``f`` > 0 with ``log`` = ln(a1 / f) (the
    stopping rule of :func:`conforming_force`): (F, stiffness, energy, ln(a1 / F))."""
    for _ in range(60):
        d, c, e = _conforming_log(f, log, j1, a1, j2, a2, cb, shift)
        inv_c = 1.0 / c
        step = (d - delta) * inv_c
        new = f - step
        if new <= 0.0:
            new = 0.01 * f
        elif abs(step) <= NEWTON_CLOSE * new:
            change = new - f
            e += f * c * change
            # the stiffness 1 / (c + dc) to second order in dc / c (at most ~1e-6 here: the
            # error is of the third order, below 1e-18) instead of a division
            x = conforming_curvature(f, a1, j1, a2, j2) * change * inv_c
            return new, inv_c * (1.0 - x * (1.0 - x)), e, log - log_ratio(change / f)
        if abs(step) <= SERIES_LIMIT * f:   # ln(a1 / F) by its series: one logarithm per call
            log -= log_ratio(-step / f)
        else:
            log = math.log(a1 / new)
        f = new
    d, c, e = _conforming(f, j1, a1, j2, a2, cb, shift)
    return f, 1.0 / c, e, math.log(a1 / f)


@numba.njit(cache=CACHE, inline="always")
def log_ratio(x):
    """ln(1 + x) by its series to x^8 (Horner, constant coefficients), for |x| <=
    SERIES_LIMIT (the next term, x^9 / 9, is below 2e-19)."""
    return x * (1.0 - x * (_INV2 - x * (_INV3 - x * (_INV4 - x * (
        _INV5 - x * (_INV6 - x * (_INV7 - x * _INV8)))))))


@numba.njit(**NO_REFCOUNT)
def radial_stiffness(nx, ny, k, force, dist):
    """dS/dr of a force ``force`` along n = r / dist with tangent stiffness ``k``: k n n^T +
    F/dist t t^T (the normal turns with r)."""
    turn = force / dist
    return (k * nx * nx + turn * ny * ny, (k - turn) * nx * ny, k * ny * ny + turn * nx * nx)


@numba.njit(**NO_REFCOUNT)
def roller_set(rx, ry, vx, vy, count, cage, c, gap, cos_alpha, zeta, mass):
    """Resultant of a rolling bearing's rollers on its inner raceway centre displaced by (rx,
    ry) (velocity (vx, vy)) from the outer raceway centre.

    Roller i sits at the angle cage + 2 pi i / count; its approach is (r . n_i - gap) cos
    alpha (``gap`` = half the radial internal clearance, negative: preload), its force the
    Palmgren law delta = c Q^0.9 of both raceway contacts in series (``c``), damped like every
    contact (zeta, mass).  Returns (Sx, Sy, energy, dissipated power, largest roller force,
    kxx, kxy, kyy, gx, gy): S = sum Q_i cos(alpha) n_i pushes the outer raceway away from the
    inner one; k = dS/dr and g = dS/d(cage) of the elastic forces (the tangent stiffness).
    """
    sx = sy = energy = power = largest = 0.0
    kxx = kxy = kyy = gx = gy = 0.0
    pitch = 2.0 * math.pi / count
    cos_p, sin_p = math.cos(pitch), math.sin(pitch)
    n = int(count)
    # roller directions by rotation from roller 0 (no trigonometric call per roller)
    cx, cy = math.cos(cage), math.sin(cage)
    for i in range(n):
        nx, ny = cx, cy
        cx, cy = nx * cos_p - ny * sin_p, nx * sin_p + ny * cos_p
        delta = (rx * nx + ry * ny - gap) * cos_alpha
        if delta <= 0.0:
            continue
        rate = (vx * nx + vy * ny) * cos_alpha
        fn, e, pw, fel, k = contact(delta, rate, c, 0.0, zeta, mass, 0.0)
        energy += e
        power += pw
        if fn > largest:
            largest = fn
        sx += fn * cos_alpha * nx
        sy += fn * cos_alpha * ny
        kc = k * cos_alpha * cos_alpha
        kxx += kc * nx * nx
        kxy += kc * nx * ny
        kyy += kc * ny * ny
        # d/dpsi of fel cos(alpha) n_i: the approach changes along the tangent (-ny, nx)
        along = (-rx * ny + ry * nx) * k * cos_alpha * cos_alpha
        gx += along * nx - fel * cos_alpha * ny
        gy += along * ny + fel * cos_alpha * nx
    return sx, sy, energy, power, largest, kxx, kxy, kyy, gx, gy
