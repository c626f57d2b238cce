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
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["curve_point", "foot_point", "nearest_point", "signed_distance", "signed_distances",
           "curvature"]


@numba.njit(cache=True, fastmath=False)
def curve_point(u, rg, a, zp):
    """Point, first and second derivative of q(u): (x, y, dx, dy, ddx, ddy)."""
    cu = math.cos(u)
    su = math.sin(u)
    cz = math.cos(zp * u)
    sz = math.sin(zp * u)
    x = rg * cu - a * cz
    y = rg * su - a * sz
    dx = -rg * su + a * zp * sz
    dy = rg * cu - a * zp * cz
    ddx = -rg * cu + a * zp * zp * cz
    ddy = -rg * su + a * zp * zp * sz
    return x, y, dx, dy, ddx, ddy


@numba.njit(cache=True)
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


@numba.njit(cache=True)
def nearest_point(qx, qy, centre, rg, a, zp):
    """Parameter of the point of q nearest to (qx, qy) among one period around ``centre``.

    Robust where Newton alone is not (a point near the medial axis of a concave stretch has
    two feet): 17 samples over +-pi/zp (one lobe period) pick the basin of the global
    minimum, then guarded Newton converges in it.
    """
    best_u = centre
    best_d = 1e300
    width = math.pi / zp
    for j in range(-8, 9):
        u = centre + j * width / 8.0
        x = rg * math.cos(u) - a * math.cos(zp * u)
        y = rg * math.sin(u) - a * math.sin(zp * u)
        d = (qx - x) ** 2 + (qy - y) ** 2
        if d < best_d:
            best_d = d
            best_u = u
    return foot_point(qx, qy, best_u, rg, a, zp, 12)


@numba.njit(cache=True)
def signed_distance(qx, qy, u0, rg, a, zp, iterations):
    """Signed distance of (qx, qy) from q, positive outside: (s, u, nx, ny).

    The nearest point is searched over one lobe period around ``u0`` (``iterations`` > 0) or
    taken as ``u0`` (``iterations`` = 0); (nx, ny) is the unit outward normal there.
    """
    u = nearest_point(qx, qy, u0, rg, a, zp) if iterations > 0 else u0
    x, y, dx, dy, _, _ = curve_point(u, rg, a, zp)
    norm = math.sqrt(dx * dx + dy * dy)
    nx = dy / norm
    ny = -dx / norm
    s = (qx - x) * nx + (qy - y) * ny
    return s, u, nx, ny


@numba.njit(cache=True)
def signed_distances(qx, qy, u0, rg, a, zp, iterations):
    """Vectorised :func:`signed_distance`; returns (s, u) arrays."""
    n = qx.shape[0]
    s = np.empty(n)
    u = np.empty(n)
    for i in range(n):
        s[i], u[i], _, _ = signed_distance(qx[i], qy[i], u0[i], rg, a, zp, iterations)
    return s, u


@numba.njit(cache=True)
def curvature(u, rg, a, zp):
    """Signed curvature of q at ``u``; positive where the centre of curvature is inside."""
    _, _, dx, dy, ddx, ddy = curve_point(u, rg, a, zp)
    speed = math.sqrt(dx * dx + dy * dy)
    return (dx * ddy - dy * ddx) / (speed * speed * speed)
