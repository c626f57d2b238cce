"""Contact law shared by every force element of the kernel (numba; docs/model.md section 5).

Palmgren line contact in series with a linear compliance, damping that vanishes at first touch,
the rank-one update of a stiffness matrix, and the largest Hertz pressure of a line contact.
"""

from __future__ import annotations

import math

import numba

from .._jit import CACHE, NO_REFCOUNT
from .._cache_guard import invalidate_stale_cache

invalidate_stale_cache(__file__)

__all__ = ["EXPONENT", "spring_force", "spring_force_power", "spring_force_from", "spring_start",
           "power_ratio", "damping", "damped", "contact", "add_rank_one", "hertz_pressure"]

EXPONENT = 0.9          # Palmgren line contact: delta = C * F**0.9
_INV_EXPONENT = 1.0 / EXPONENT
#: Newton steps below this fraction of the force end the iteration (:func:`spring_force`)
NEWTON_CLOSE = 1e-6
#: relative Newton steps up to which F**0.9 follows the step by its binomial series
#: (:func:`power_ratio`: truncation error below 1e-20) instead of a new power
SERIES_LIMIT = 1e-2
#: relative changes up to which Newton starts from the Taylor predictor even beyond the
#: series (:func:`spring_force_from`)
PREDICTOR_LIMIT = 0.5


#: the ratios C(p, n) / C(p, n - 1) = (p - n + 1) / n of the binomial series of (1 + x)^p
_B1, _B2, _B3, _B4, _B5, _B6, _B7, _B8 = ((EXPONENT - n + 1.0) / n for n in range(1, 9))
#: F'' / 2 of the law in units of c F^0.9 k^3 / F^2: EXPONENT (1 - EXPONENT) / 2
_HALF_CURVE = 0.5 * EXPONENT * (1.0 - EXPONENT)


@numba.njit(cache=CACHE, inline="always")
def power_ratio(x):
    """(1 + x) ** EXPONENT by its binomial series to x^8 (Horner, constant coefficients), for
    |x| <= SERIES_LIMIT (the next term, C(0.9, 9) x^9, is below 1e-20)."""
    return 1.0 + _B1 * x * (1.0 + _B2 * x * (1.0 + _B3 * x * (1.0 + _B4 * x * (
        1.0 + _B5 * x * (1.0 + _B6 * x * (1.0 + _B7 * x * (1.0 + _B8 * x)))))))


@numba.njit(**NO_REFCOUNT)
def spring_force(delta, c, cb, guess):
    """Force of a Palmgren contact in series with a linear compliance, for approach ``delta``.

    delta = c * F**0.9 + cb * F.  ``guess`` is the force of the previous step (0 if none):
    Newton from it converges in one or two iterations.  Returns (F, tangent stiffness
    dF/ddelta, stored energy).
    """
    f, k, energy, _ = spring_force_power(delta, c, cb, guess, 0.0)
    return f, k, energy


@numba.njit(**NO_REFCOUNT)
def spring_force_power(delta, c, cb, guess, guess_power):
    """:func:`spring_force` with ``guess_power`` = guess**0.9 where the caller carries it (0:
    computed here), and F**0.9 returned as well, for the caller to carry to its next call:
    (F, tangent stiffness, stored energy, F**0.9).  Carried, F**0.9 follows each step by its
    series (:func:`power_ratio`), so that a contact in touch takes no power at all."""
    if cb == 0.0:
        f = (delta / c) ** _INV_EXPONENT
        # c f^0.9 = delta: stiffness f / (0.9 delta), energy 0.9/1.9 delta f
        return f, f / (EXPONENT * delta), EXPONENT / (1.0 + EXPONENT) * delta * f, delta / c
    if guess > 0.0:
        f = guess
        fe = guess_power if guess_power > 0.0 else f ** EXPONENT
    else:
        # secant compliance at the contact-only force: below the root
        f = (delta / c) ** _INV_EXPONENT
        f = delta / (c * f ** (EXPONENT - 1.0) + cb)
        fe = f ** EXPONENT
    for _ in range(20):
        # Newton on g(F) = c F^0.9 + cb F - delta (concave, increasing): the error after a
        # step s is at most (|g''| / 2 g') s^2 <= 0.05 s^2 / F, so a step below NEWTON_CLOSE F
        # leaves a relative error below 1e-13; F^0.9 follows every step by its series (two
        # divisions per iteration: 1 / F and the step)
        inv_f = 1.0 / f
        step = (c * fe + cb * f - delta) / (EXPONENT * c * fe * inv_f + cb)
        new = f - step
        x = -step * inv_f
        if new <= 0.0:
            new = 1e-3 * f
        elif abs(step) <= NEWTON_CLOSE * new:
            fe *= power_ratio(x)
            f = new
            inv_f *= 1.0 - x * (1.0 - x)     # 1 / (F (1 + x)), |x| <= 1e-6: error below 1e-18
            break
        if abs(x) <= SERIES_LIMIT:            # F^0.9 by its series: one power at most
            fe *= power_ratio(x)
        else:
            fe = new ** EXPONENT
        f = new
    else:                                     # the iterations ran out (not seen)
        inv_f = 1.0 / f
    stiffness = 1.0 / (EXPONENT * c * fe * inv_f + cb)
    energy = EXPONENT / (1.0 + EXPONENT) * c * fe * f + 0.5 * cb * f * f
    return f, stiffness, energy, fe


@numba.njit(cache=CACHE, inline="always")
def spring_start(delta, c, f0, fe0, d0, k0):
    """Newton's start of :func:`spring_force_from` relative to the last solution: F / f0 - 1
    at the approach ``delta`` by the second-order Taylor expansion of the inverse law (F'' =
    0.09 c f0^0.9 k0^3 / f0^2)."""
    inv_f0 = 1.0 / f0
    move = k0 * (delta - d0) * inv_f0                   # first order, relative to f0
    return move * (1.0 + _HALF_CURVE * c * fe0 * inv_f0 * k0 * move)


@numba.njit(**NO_REFCOUNT)
def spring_force_from(delta, c, cb, f0, fe0, d0, k0):
    """:func:`spring_force_power` started from the previous solution's Taylor expansion: the
    force ``f0`` > 0 with ``fe0`` = f0**0.9 at the approach ``d0`` and the stiffness ``k0``,
    all carried by the caller from its last call (``cb`` may have changed since: the
    predictor is only Newton's start).

    The predictor f0 + k0 dd + F'' dd^2 / 2 (dd = delta - d0; F'' = 0.09 c f0^0.9 k0^3 / f0^2
    from the law's curvature) is off by the third order of the change, so where the force
    changes by up to about 1 % per call Newton's first step is already below NEWTON_CLOSE F:
    one evaluation per call, F**0.9 by its series from ``fe0``.  The same stopping rule as
    :func:`spring_force_power`, so the same accuracy; a change beyond SERIES_LIMIT (or no
    series compliance) is left to that function, started from the predictor with a fresh
    power (up to PREDICTOR_LIMIT) or from ``f0``.  Returns (F, stiffness, energy, F**0.9)."""
    x = spring_start(delta, c, f0, fe0, d0, k0)
    if cb == 0.0 or not abs(x) <= SERIES_LIMIT:
        # beyond the series: Newton from the predictor all the same (a fresh power), or
        # from f0 beyond PREDICTOR_LIMIT
        if cb != 0.0 and abs(x) <= PREDICTOR_LIMIT:
            return spring_force_power(delta, c, cb, f0 + f0 * x, 0.0)
        return spring_force_power(delta, c, cb, f0, fe0)
    f = f0 + f0 * x
    inv_f = 1.0 / f
    fe = fe0 * power_ratio(x)
    step = (c * fe + cb * f - delta) / (EXPONENT * c * fe * inv_f + cb)
    new = f - step
    if abs(step) <= NEWTON_CLOSE * new:
        y = -step * inv_f                                # |y| <= 1e-6
        fe *= 1.0 + EXPONENT * y * (1.0 + _B2 * y * (1.0 + _B3 * y))
        inv_f *= 1.0 - y * (1.0 - y)
        stiffness = 1.0 / (EXPONENT * c * fe * inv_f + cb)
        energy = EXPONENT / (1.0 + EXPONENT) * c * fe * new + 0.5 * cb * new * new
        return new, stiffness, energy, fe
    return spring_force_power(delta, c, cb, f, fe)


@numba.njit(**NO_REFCOUNT)
def contact(delta, rate, c, cb, zeta, mass, guess):
    """Normal force of a compliant contact with damping that vanishes at first touch.

    Damping is 2 zeta sqrt(k m) at the current tangent stiffness k (zero at delta = 0); the total
    force never pulls.  Returns (force, stored energy, dissipated power, elastic force,
    tangent stiffness of the elastic force).
    """
    f, k, energy = spring_force(delta, c, cb, guess)
    fn, power = damped(f, k, rate, zeta, mass)
    return fn, energy, power, f, k


@numba.njit(cache=CACHE, inline="always")
def damping(k, zeta, mass):
    """The contacts' damping coefficient 2 zeta sqrt(k m) at the tangent stiffness ``k`` (zero
    at first touch; docs/model.md section 5): the one damping law of every element (contacts,
    gear mesh, input coupling)."""
    return 2.0 * zeta * math.sqrt(k * mass)


@numba.njit(**NO_REFCOUNT)
def damped(f, k, rate, zeta, mass):
    """Elastic force ``f`` of tangent stiffness ``k`` plus damping 2 zeta sqrt(k m)
    (:func:`damping`) at the approach rate; the total never pulls.  Returns (force, dissipated
    power)."""
    fn = f + damping(k, zeta, mass) * rate
    if fn < 0.0:
        fn = 0.0
    return fn, (fn - f) * rate


@numba.njit(**NO_REFCOUNT)
def add_rank_one(K, index, g, scale):
    """K[index, index] += scale * g g^T (``index``, ``g``: tuples of one length)."""
    for a in range(len(index)):
        for b in range(len(index)):
            K[index[a], index[b]] += scale * g[a] * g[b]


@numba.njit(cache=CACHE, inline="always")
def hertz_pressure(force, e_star, curvature, length):
    """Largest Hertz pressure p0 = sqrt(F E* (1/R1 + 1/R2) / (pi L)) [Pa] of two cylinders in
    line contact over ``length`` carrying ``force``, ``curvature`` the sum of the two bodies'
    curvatures (negative for a concave body; zero or less: no pressure) and ``e_star`` the
    pair's effective modulus (K. L. Johnson, *Contact Mechanics*, 1985, section 4.3; the pin
    contacts' stresses of the quasi-static engine and the rolling bearings' preload check,
    rvsim.bearings.roller_preloads)."""
    return math.sqrt(force * e_star * max(curvature, 0.0) / (math.pi * length))
