"""The one kinematic pose of the force elements (numba): crank stations and the forces on
them, the cosines and sines one force evaluation shares, the discs' frames and profile angle,
the eccentrics' directions and the crank holes' stations (docs/model.md sections 2-4; moved out
of ``dynamics/_kernel.py``, issue 31 step 9)."""

from __future__ import annotations

import math

import numba

from .._cache_guard import invalidate_stale_cache
from .._jit import CACHE, NO_REFCOUNT

invalidate_stale_cache(__file__)

from ._fe_holes import hole_shift, holes_on  # noqa: E402
from ._layout import (CARRIER, CRANK0, CRANK_STRIDE, DISC0, DISC_STRIDE, ECC_PHASE0,  # noqa: E402
                      ECC_TURN0, FRAME_TURN0, PROFILE_ROT, W_D1_L, W_D1_U, W_D2_L,
                      W_D2_U, ZC)


@numba.njit(**NO_REFCOUNT)
def crank_point(q, v, j, wl, wu):
    """Position and velocity of crank j's axis at the axial station with weights (wl, wu)."""
    b = CRANK0 + CRANK_STRIDE * j
    return (wl * q[b] + wu * q[b + 2], wl * q[b + 1] + wu * q[b + 3],
            wl * v[b] + wu * v[b + 2], wl * v[b + 1] + wu * v[b + 3])


@numba.njit(**NO_REFCOUNT)
def add_crank_force(Q, j, wl, wu, fx, fy):
    b = CRANK0 + CRANK_STRIDE * j
    Q[b] += wl * fx
    Q[b + 1] += wl * fy
    Q[b + 2] += wu * fx
    Q[b + 3] += wu * fy


@numba.njit(cache=CACHE, inline="always")
def line_trig(q, crank_angle):
    """Cosine and sine of a crank's nominal angle about the centre, q[carrier] + its assembly
    angle: the line of centres of its mesh and the direction of its bores."""
    line = q[CARRIER] + crank_angle
    return math.cos(line), math.sin(line)


@numba.njit(cache=CACHE, inline="always")
def angle_trig(q, crank_angles):
    """The cosines and sines one force evaluation shares between its elements (one call per
    angle, docs/decisions.md): cranks 0 and 1's nominal angles (:func:`line_trig`), discs 0
    and 1's rotations (:func:`disc_trig`), as (cos, sin, cos, sin, cos, sin, cos, sin)."""
    c0, s0 = line_trig(q, crank_angles[0])
    c1, s1 = line_trig(q, crank_angles[1])
    d0, e0 = disc_trig(q, 0)
    d1, e1 = disc_trig(q, 1)
    return c0, s0, c1, s1, d0, e0, d1, e1


@numba.njit(cache=CACHE, inline="always")
def _disc_frame(P, q, v, disc):
    """Disc ``disc``'s profile angle: (cos, sin) and the housing velocity seen from the disc
    centre in disc axes (rotation part excluded), and its angular velocity."""
    cos_d, sin_d = disc_trig(q, disc)
    return _disc_frame_at(P, q, v, disc, cos_d, sin_d)


@numba.njit(cache=CACHE, inline="always")
def profile_turn(P, disc):
    """Disc ``disc``'s profile angle less its rotation q[theta]: the half-tooth offset of
    disc 1 and the rotation modification (model.build_model turns it into P[FRAME_TURN0 ..])."""
    return -disc * math.pi / P[ZC] + P[PROFILE_ROT]


@numba.njit(cache=CACHE, inline="always")
def _disc_frame_at(P, q, v, disc, cos_d, sin_d):
    """:func:`_disc_frame` from the cosine and sine of the disc's rotation q[theta] (turned
    by the constant P[FRAME_TURN0 + 2 disc ..]: no trigonometric call)."""
    d = DISC0 + DISC_STRIDE * disc
    vx, vy, w = v[d], v[d + 1], v[d + 2]
    angle = q[d + 2] + profile_turn(P, disc)
    cos_f, sin_f = P[FRAME_TURN0 + 2 * disc], P[FRAME_TURN0 + 2 * disc + 1]
    cos_t, sin_t = cos_d * cos_f - sin_d * sin_f, sin_d * cos_f + cos_d * sin_f
    return angle, cos_t, sin_t, cos_t * vx + sin_t * vy, -sin_t * vx + cos_t * vy, w


@numba.njit(**NO_REFCOUNT)
def arm_station(P, holes, crank, disc):
    """Station weights (wl, wu) of disc ``disc``'s eccentric on crank ``crank`` and the centre
    of its hole in the disc's axes (with the per-disc hole offsets of per-part errors, and the
    hole's elastic displacement when the FE disc's holes are load points: added by the
    callers, :func:`rvsim.physics._fe_holes.hole_shift`)."""
    wl = P[W_D1_L] if disc == 0 else P[W_D2_L]
    wu = P[W_D1_U] if disc == 0 else P[W_D2_U]
    hole_x, hole_y = holes[crank, 0], holes[crank, 1]
    if holes.shape[1] > 2:
        hole_x += holes[crank, 2 + 2 * disc]
        hole_y += holes[crank, 3 + 2 * disc]
    return wl, wu, hole_x, hole_y


@numba.njit(cache=CACHE, inline="always")
def hole_station(P, holes, crank, disc, elastic):
    """:func:`arm_station` with the hole's elastic displacement when the FE disc's holes are
    load points (``elastic`` the kernel's arm state; physics._fe_holes)."""
    wl, wu, hole_x, hole_y = arm_station(P, holes, crank, disc)
    if holes_on(P):
        dx, dy = hole_shift(P, elastic, crank, disc)
        hole_x += dx
        hole_y += dy
    return wl, wu, hole_x, hole_y


@numba.njit(cache=CACHE, inline="always")
def eccentric_angle(P, q, crank, disc):
    """Direction of crank ``crank``'s eccentric for disc ``disc``."""
    return q[CRANK0 + CRANK_STRIDE * crank + 4] + disc * math.pi + P[ECC_PHASE0 + 2 * crank + disc]


@numba.njit(cache=CACHE, inline="always")
def disc_trig(q, disc):
    """Cosine and sine of disc ``disc``'s rotation q[theta]."""
    angle = q[DISC0 + DISC_STRIDE * disc + 2]
    return math.cos(angle), math.sin(angle)


@numba.njit(cache=CACHE, inline="always")
def eccentric_trig(P, q, crank):
    """Cosines and sines of crank ``crank``'s two eccentrics (disc 1's turned from disc 0's by
    the constant P[ECC_TURN0 + 2 crank ..]): (cos, sin disc 0, cos, sin disc 1)."""
    phi = eccentric_angle(P, q, crank, 0)
    c0, s0 = math.cos(phi), math.sin(phi)
    ct, st = P[ECC_TURN0 + 2 * crank], P[ECC_TURN0 + 2 * crank + 1]
    return c0, s0, c0 * ct - s0 * st, s0 * ct + c0 * st


@numba.njit(**NO_REFCOUNT)
def arm_trig(P, q, crank, disc):
    """(cos, sin) of disc ``disc``'s rotation and of crank ``crank``'s eccentric for it, the
    trigonometric arguments of :func:`arm_geometry` and :func:`arm_bushing` for a caller
    that has none at hand (:func:`crank_bearings` shares them between the elements)."""
    cos_t, sin_t = disc_trig(q, disc)
    c0, s0, c1, s1 = eccentric_trig(P, q, crank)
    return (cos_t, sin_t, c0, s0) if disc == 0 else (cos_t, sin_t, c1, s1)
