"""Compiled evaluation of the cycloid pin-centre curve (no objects, no raises).

Symbols (paper Eq. 18, repaired; docs/model.md "Cycloid profile"):

======  =====================================================================
``rg``  generating pin-circle radius r_p - J (radial-moving modification)  [m]
``a``   design eccentricity                                                [m]
``zp``  number of pins                                                     [-]
``u``   curve parameter = polar angle of the generating pin in disc axes   [rad]
======  =====================================================================

The pin-centre curve in disc axes is the curtate epitrochoid

    q(u) = rg * (cos u, sin u) - a * (cos zp*u, sin zp*u),

traversed counter-clockwise.  The disc profile is q offset inwards by r_rp + I (equidistant
modification).  For a pin centre Q the signed distance to q along the outward normal, plus the
offset, minus the pin radius, is the exact tooth gap; it is found by Newton iteration on the
foot point, not from a polyline.

This module is the one implementation of the curve (:func:`curve_point`), of the profile
(:func:`profile_points`) and of a pin's gap (:func:`pin_gap`, the pin centre taken into the
profile axes of a disc); the compiled kernel and the geometry functions both call it.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .._cache_guard import invalidate_stale_cache
from .._jit import CACHE, NO_REFCOUNT, REFCOUNT

# the compile options come from rvsim._jit: clear this module's cached code when they change
invalidate_stale_cache(__file__)
__all__ = ["curve_point", "curve_from", "rotated", "foot_point", "nearest_point", "curvature", "profile_points",
           "profile_axes", "pin_gap", "pin_gaps_at", "pin_opening", "profile_deviation", "lever_arms", "curvatures",
           "deviated_gap",
           "TRACKING_LIMIT", "ROTATION_LIMIT"]

#: largest Newton correction [rad of u] accepted when a foot point is tracked from the previous
#: one; beyond it the foot is searched again robustly (:func:`pin_gap`)
TRACKING_LIMIT = 1e-4
#: largest turn [rad of zp u] by which :func:`pin_gap` carries the foot's cosines and sines
#: (:func:`rotated`) instead of computing them anew
ROTATION_LIMIT = 3e-2
#: 1 / n! of the series of cos and sin (:func:`rotated`)
_INV6, _INV24, _INV120, _INV720, _INV5040 = (1.0 / n for n in (6, 24, 120, 720, 5040))


@numba.njit(**NO_REFCOUNT)
def curve_point(u, rg, a, zp):
    """Point, first and second derivative of q(u): (x, y, dx, dy, ddx, ddy)."""
    cu, su, cz, sz = curve_trig(u, zp)
    return curve_from(cu, su, cz, sz, rg, a, zp)


@numba.njit(cache=CACHE, inline="always")
def curve_trig(u, zp):
    """cos u, sin u, cos zp u and sin zp u: what :func:`curve_from` takes."""
    return math.cos(u), math.sin(u), math.cos(zp * u), math.sin(zp * u)


@numba.njit(cache=CACHE, inline="always")
def rotated(c, s, d):
    """(cos, sin) of an angle d from the angle whose cosine and sine are (c, s), for |d| <=
    :data:`ROTATION_LIMIT`: cos d and sin d by their series (truncation below 2e-17), the pair
    brought back to unit length to first order (so that rounding cannot drift it)."""
    d2 = d * d         # (the series' coefficients are constants: no division per call)
    cd = 1.0 - d2 * (0.5 - d2 * (_INV24 - d2 * _INV720))
    sd = d * (1.0 - d2 * (_INV6 - d2 * (_INV120 - d2 * _INV5040)))
    cn = c * cd - s * sd
    sn = s * cd + c * sd
    scale = 1.5 - 0.5 * (cn * cn + sn * sn)
    return cn * scale, sn * scale


@numba.njit(cache=CACHE, inline="always")
def curve_from(cos_u, sin_u, cos_z, sin_z, rg, a, zp):
    """:func:`curve_point` from the cosines and sines of u and zp u."""
    x = rg * cos_u - a * cos_z
    y = rg * sin_u - a * sin_z
    dx = -rg * sin_u + a * zp * sin_z
    dy = rg * cos_u - a * zp * cos_z
    ddx = -rg * cos_u + a * zp * zp * cos_z
    ddy = -rg * sin_u + a * zp * zp * sin_z
    return x, y, dx, dy, ddx, ddy


@numba.njit(**NO_REFCOUNT)
def foot_point(qx, qy, u0, rg, a, zp, iterations):
    """Parameter of the point of q nearest to (qx, qy), by Newton from ``u0``."""
    u = u0
    for _ in range(iterations):
        x, y, dx, dy, ddx, ddy = curve_point(u, rg, a, zp)
        rx = qx - x
        ry = qy - y
        g = -(rx * dx + ry * dy)
        h = dx * dx + dy * dy - (rx * ddx + ry * ddy)
        if h <= 0.0:
            h = dx * dx + dy * dy
        step = g / h
        limit = 0.25 / zp          # a quarter of a lobe's phase: keeps cold starts on the lobe
        if step > limit:
            step = limit
        elif step < -limit:
            step = -limit
        u -= step
        if abs(step) < 1e-15:
            break
    return u


@numba.njit(**NO_REFCOUNT)
def nearest_point(qx, qy, centre, rg, a, zp):
    """Parameter of the point of q nearest to (qx, qy) among one period around ``centre``.

    Robust where Newton alone is not (a point near the medial axis of a concave stretch has
    two feet): 17 samples over +-pi/zp (one lobe period) pick the basin of the global
    minimum, then guarded Newton converges in it.
    """
    best_u = centre
    best_d = 1e300
    width = math.pi / zp
    h = width / 8.0
    # the samples' cosines and sines by rotation from the first (4 transcendental calls
    # instead of 34; the samples only pick the basin, foot_point refines with exact ones)
    c1, s1 = math.cos(centre - 8 * h), math.sin(centre - 8 * h)
    cz, sz = math.cos(zp * (centre - 8 * h)), math.sin(zp * (centre - 8 * h))
    dc1, ds1 = math.cos(h), math.sin(h)
    dcz, dsz = math.cos(zp * h), math.sin(zp * h)
    for j in range(-8, 9):
        x = rg * c1 - a * cz
        y = rg * s1 - a * sz
        d = (qx - x) ** 2 + (qy - y) ** 2
        if d < best_d:
            best_d = d
            best_u = centre + j * h
        c1, s1 = c1 * dc1 - s1 * ds1, s1 * dc1 + c1 * ds1
        cz, sz = cz * dcz - sz * dsz, sz * dcz + cz * dsz
    return foot_point(qx, qy, best_u, rg, a, zp, 12)


@numba.njit(**NO_REFCOUNT)
def curvature(u, rg, a, zp):
    """Signed curvature of q at ``u``; positive where the centre of curvature is inside."""
    _, _, dx, dy, ddx, ddy = curve_point(u, rg, a, zp)
    speed = math.sqrt(dx * dx + dy * dy)
    return (dx * ddy - dy * ddx) / (speed * speed * speed)


@numba.njit(**REFCOUNT)
def profile_points(u, rg, a, zp, offset):
    """Points of the profile (q offset inwards by ``offset``) at parameters ``u``: (n, 2)."""
    n = u.shape[0]
    out = np.empty((n, 2))
    for i in range(n):
        x, y, dx, dy, _, _ = curve_point(u[i], rg, a, zp)
        norm = math.sqrt(dx * dx + dy * dy)
        out[i, 0] = x - offset * dy / norm
        out[i, 1] = y + offset * dx / norm
    return out


@numba.njit(cache=CACHE, inline="always")
def profile_axes(px, py, ox, oy, cos_t, sin_t, shift_x, shift_y):
    """A point (px, py) in housing axes, in the profile axes of a disc.

    The disc centre is at (ox, oy), its profile turned by the angle whose cosine and sine are
    ``cos_t``, ``sin_t`` and its centre (shift_x, shift_y) off the disc centre (runout), in
    profile axes.
    """
    dx = px - ox
    dy = py - oy
    return cos_t * dx + sin_t * dy - shift_x, -sin_t * dx + cos_t * dy - shift_y


@numba.njit(cache=CACHE, inline="always")
def pin_gap(qx, qy, nominal, previous, rg, a, zp, clearance, track, carried):
    """Gap of the pin centred at (qx, qy) (profile axes) to the profile.

    ``clearance`` is the profile offset minus the pin radius: gap = signed distance of the pin
    centre from q (positive outside) + clearance.  The foot point is searched robustly over one
    lobe period around the pin's ``nominal`` parameter, or, with ``track``, taken one guarded
    Newton step from ``previous`` (the foot of the previous time step) when that step is below
    :data:`TRACKING_LIMIT` and stays on the lobe: the foot is then exact to ~ zp du^2 and the
    point to ~ a zp^3 du^3, far below a nanometre of gap.

    ``carried`` (5 values, or none): u_c, cos u_c, sin u_c, cos zp u_c, sin zp u_c at a
    parameter near the foot found last; where ``previous`` is within :data:`ROTATION_LIMIT`
    / zp of u_c, the cosines and sines at ``previous`` are turned from them instead of
    computed (four transcendental calls per pin and step saved), and they are written for
    ``previous`` (tracked: the next call turns them through this call's Newton step too,
    instead of this call turning them) or for the robust foot.

    Returns (gap, u, nx, ny): foot parameter and unit outward normal of q there.
    """
    u = previous
    keep = carried.shape[0] > 0
    turn = u - carried[0] if keep else math.inf
    if track and abs(zp * turn) <= ROTATION_LIMIT:
        cu, su = rotated(carried[1], carried[2], turn)
        cz, sz = rotated(carried[3], carried[4], zp * turn)
    else:
        cu, su, cz, sz = curve_trig(u, zp)
    x, y, tx, ty, ddx, ddy = curve_from(cu, su, cz, sz, rg, a, zp)
    robust = not track
    if track:
        rx, ry = qx - x, qy - y
        speed2 = tx * tx + ty * ty
        h = speed2 - (rx * ddx + ry * ddy)
        if h < 0.25 * speed2:
            h = speed2
        du = (rx * tx + ry * ty) / h
        if abs(du) > TRACKING_LIMIT or abs(u + du - nominal) > math.pi / zp:
            robust = True
        else:
            # the cosines and sines carried are those at u before this step (the next call
            # turns them through du as well): no turn here
            if keep:
                carried[0], carried[1], carried[2], carried[3], carried[4] = u, cu, su, cz, sz
            x += du * (tx + 0.5 * du * ddx)
            y += du * (ty + 0.5 * du * ddy)
            tx += du * ddx
            ty += du * ddy
            u += du
    if robust:
        u = nearest_point(qx, qy, nominal, rg, a, zp)
        cu, su, cz, sz = curve_trig(u, zp)
        x, y, tx, ty, _, _ = curve_from(cu, su, cz, sz, rg, a, zp)
        if keep:
            carried[0], carried[1], carried[2], carried[3], carried[4] = u, cu, su, cz, sz
    inv_norm = 1.0 / math.sqrt(tx * tx + ty * ty)
    nx = ty * inv_norm
    ny = -tx * inv_norm
    return (qx - x) * nx + (qy - y) * ny + clearance, u, nx, ny


@numba.njit(**REFCOUNT)
def curvatures(u, rg, a, zp):
    """:func:`curvature` at each of the parameters ``u``."""
    out = np.empty(u.shape[0])
    for i in range(u.shape[0]):
        out[i] = curvature(u[i], rg, a, zp)
    return out


@numba.njit(**REFCOUNT)
def lever_arms(u, rg, a, zp):
    """n x q of the pin-centre curve at parameters ``u`` (n the unit outward normal): the
    gap's derivative with respect to the disc's rotation for a pin on the curve [m]."""
    out = np.empty(u.shape[0])
    for i in range(u.shape[0]):
        x, y, tx, ty, _, _ = curve_point(u[i], rg, a, zp)
        out[i] = (ty * y + tx * x) / math.sqrt(tx * tx + ty * ty)
    return out


@numba.njit(cache=CACHE, inline="always")
def pin_opening(pins, i):
    """Pin i's own opening of its gap [m]: column 2 of a per-part ``pins`` array (its radius
    deviation and the pin-hole clearance, rvsim.geometry.deviations.pin_table), else 0."""
    return pins[i, 2] if pins.shape[1] > 2 else 0.0


@numba.njit(cache=CACHE, inline="always")
def _deviation_sample(pins, base, per_row, n, j):
    j = j % n
    return pins[j // per_row, base + j % per_row]


@numba.njit(cache=CACHE, inline="always")
def profile_deviation(pins, disc, u):
    """Normal deviation of disc ``disc``'s profile at parameter ``u`` [m] (positive: excess
    material), interpolated in the samples that columns 3 .. of a per-part ``pins`` array hold
    (rvsim.geometry.deviations.pin_table), and its slope d/du; zeros without them.

    Catmull-Rom (cubic Hermite) interpolation: the deviation's slope is continuous, so the
    contact force and the equilibrium residual are (a linear interpolation's kinks leave
    positions where no equilibrium exists to the solver's tolerance)."""
    columns = pins.shape[1]
    if columns <= 3:
        return 0.0, 0.0
    per_row = (columns - 3) // 2
    n = pins.shape[0] * per_row
    x = u / (2.0 * math.pi)
    x = (x - math.floor(x)) * n
    j = int(math.floor(x))
    f = x - j
    base = 3 + disc * per_row
    p0 = _deviation_sample(pins, base, per_row, n, j - 1)
    p1 = _deviation_sample(pins, base, per_row, n, j)
    p2 = _deviation_sample(pins, base, per_row, n, j + 1)
    p3 = _deviation_sample(pins, base, per_row, n, j + 2)
    c1 = p2 - p0
    c2 = 2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3
    c3 = 3.0 * (p1 - p2) + p3 - p0
    value = p1 + 0.5 * f * (c1 + f * (c2 + f * c3))
    slope = 0.5 * (c1 + f * (2.0 * c2 + 3.0 * f * c3)) * n / (2.0 * math.pi)
    return value, slope


@numba.njit(cache=CACHE, inline="always")
def deviated_gap(pins, disc, u, gap, nx, ny, rg, a, zp):
    """A pin's gap and gap gradient (the profile normal tilted by the deviation's slope) with
    disc ``disc``'s profile deviation at foot parameter ``u`` (:func:`profile_deviation`):
    gap - d(u), and n - d'(u) t / |t|^2, t = dq/du, so that the contact force stays the
    gradient of the contact energy."""
    if pins.shape[1] <= 3:
        return gap, nx, ny
    value, slope = profile_deviation(pins, disc, u)
    _, _, tx, ty, _, _ = curve_point(u, rg, a, zp)
    speed = math.sqrt(tx * tx + ty * ty)
    # unit tangent (-ny, nx); du/dQ = t / |t|^2
    return gap - value, nx + slope * ny / speed, ny - slope * nx / speed


@numba.njit(**REFCOUNT)
def pin_gaps_at(pins, ox, oy, angle, shift_x, shift_y, rg, a, zp, clearance, disc):
    """Robust :func:`pin_gap` of every pin (rows of ``pins``, housing axes) to one disc.

    Pin i's nominal foot parameter is gamma_i - angle, gamma_i = 2 pi i / n (exact in the
    kinematic pose).  Returns (gap, u, nx, ny, qx, qy) arrays: the pin centres (qx, qy) and the
    normals in profile axes.
    """
    n = pins.shape[0]
    cos_t = math.cos(angle)
    sin_t = math.sin(angle)
    out = np.empty((6, n))
    for i in range(n):
        qx, qy = profile_axes(pins[i, 0], pins[i, 1], ox, oy, cos_t, sin_t, shift_x, shift_y)
        nominal = 2.0 * math.pi * i / n - angle
        gap, u, nx, ny = pin_gap(qx, qy, nominal, nominal, rg, a, zp,
                                 clearance + pin_opening(pins, i), False, out[0, 0:0])
        gap, nx, ny = deviated_gap(pins, disc, u, gap, nx, ny, rg, a, zp)
        out[0, i] = gap
        out[1, i] = u
        out[2, i] = nx
        out[3, i] = ny
        out[4, i] = qx
        out[5, i] = qy
    return out[0], out[1], out[2], out[3], out[4], out[5]
