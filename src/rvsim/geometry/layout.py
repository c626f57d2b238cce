"""Where the crank holes and output-pin holes of a disc are, for either topology.

The RV reducer has two crankshafts on the crank circle (the involute stage's centre distance);
the single-stage drive has one eccentric shaft on the housing axis and output pins on the
output flange that run in holes of the discs (docs/model.md section 13).  The dynamic model,
the quasi-static engine and the assembly check take the layout from here.
"""

from __future__ import annotations

import math

import numpy as np

from ..parameters import Reducer

__all__ = ["crank_angles", "crank_radius", "crank_holes", "disc_count", "output_pins",
           "output_hole_clearance",
           "crank_hole_radius", "pillar_angles", "neighbour_distance",
           "roller_pitch_diameter", "arm_bushing_play", "support_bushing_play", "disc_holes"]


def crank_angles(reducer: Reducer) -> np.ndarray:
    """Assembly angles of the cranks about the housing axis (RV: 0 and pi; single-stage: 0)."""
    return np.array([0.0]) if reducer.layout.single_stage else np.array([0.0, math.pi])


def crank_radius(reducer: Reducer) -> float:
    """Radius of the circle of the cranks' axes: the involute stage's centre distance (RV),
    0 (single-stage: the eccentric shaft on the housing axis) [m]."""
    if reducer.layout.single_stage:
        return 0.0
    from .involute import gear_geometry

    return gear_geometry(reducer).centre_distance


def crank_holes(reducer: Reducer) -> np.ndarray:
    """Centres of the cranks' holes in a disc at the assembled pose, (n_cranks, 2) [m]."""
    if reducer.layout.single_stage:
        return np.zeros((1, 2))
    angles = crank_angles(reducer)
    return crank_radius(reducer) * np.column_stack([np.cos(angles), np.sin(angles)])


def disc_count(reducer: Reducer) -> int:
    """Number of cycloid discs (the RV model: 2)."""
    return reducer.layout.disc_count if reducer.layout.single_stage else 2


def output_pins(reducer: Reducer) -> np.ndarray:
    """Output pin centres on the flange at output angle 0 = their holes' centres in a disc
    at disc angle 0, (n_w, 2) [m]; empty for the RV reducer."""
    if not reducer.layout.single_stage:
        return np.zeros((0, 2))
    lay = reducer.layout
    angles = 2.0 * math.pi * np.arange(lay.output_pin_count) / lay.output_pin_count
    return lay.output_pin_circle_radius * np.column_stack([np.cos(angles), np.sin(angles)])


def output_hole_clearance(reducer: Reducer) -> float:
    """Hole radius minus pin radius: the design eccentricity a plus the pin's clearance [m].

    The hole is made for the design eccentricity; the pin centre sits |offset| from the hole
    centre, which is the actual eccentricity a - G when disc and flange turn together, so a
    pin touches its hole when |offset| exceeds a + clearance (G opens it by G)."""
    return reducer.cycloid.eccentricity + reducer.layout.output_pin_clearance


def crank_hole_radius(reducer: Reducer) -> float:
    """Radius of a crank hole of the disc (RV) or of its central bore (single-stage): the
    eccentric plus the radial space of its arm bushing or needles [m]."""
    return reducer.crank.eccentric_radius + reducer.crank.arm_bushing_thickness


def pillar_angles(reducer: Reducer) -> np.ndarray:
    """Angles of the RV disc's pillar holes on the crank circle: a quarter turn from the first
    crank hole, evenly spaced (as :func:`rvsim.fe.disc.disc_geometry` meshes them) [rad]."""
    n = reducer.cycloid.pillar_hole_count
    return 0.5 * math.pi + 2.0 * math.pi * np.arange(n) / max(n, 1)


def neighbour_distance(radius: float, count: int) -> float:
    """Distance between the centres of neighbours of ``count`` parts evenly spaced on a circle
    of ``radius`` (pins, rollers, holes): the chord 2 r sin(pi / n) [m]."""
    return 2.0 * radius * math.sin(math.pi / count)


def roller_pitch_diameter(inner_radius: float, roller_diameter: float) -> float:
    """Pitch (roller-centre) diameter of a set of rollers running directly on a shaft of
    ``inner_radius`` (the eccentric or the journal is the inner raceway) [m]."""
    return 2.0 * inner_radius + roller_diameter


def arm_bushing_play(reducer: Reducer) -> float:
    """Radial play of the arm bushing, eccentric in its disc hole: K + M [m] (the rolling
    bearing's clearance, where fitted, is added by its users: :func:`rvsim.bearings.arm_play`,
    the checks)."""
    cl = reducer.clearances
    return cl.crank_arm_bushing + cl.disc_arm_bushing


def support_bushing_play(reducer: Reducer, upper: bool) -> float:
    """Radial play of a support bushing, crank journal in its lower (flange, O + L) or upper
    (carrier, O + N) bore [m]."""
    cl = reducer.clearances
    return cl.crank_support_bushing + (cl.support_carrier if upper else cl.support_flange)


def disc_holes(reducer: Reducer) -> dict[str, np.ndarray]:
    """Every hole of a disc in the disc's own frame (centre at the origin, crank holes on
    the x axis), by kind: rows x, y, radius [m].

    RV reducer: ``"bore"`` (the central bore, left out at radius 0), ``"crank_holes"`` (on
    the crank circle: :func:`crank_holes`, :func:`crank_hole_radius`) and ``"pillar_holes"``
    (:func:`pillar_angles` on the crank circle, left out when there are none).  Single-stage
    drive: ``"bore"`` is the eccentric's hole (:func:`crank_hole_radius`; the set's
    ``cycloid.disc_bore_radius`` and pillar holes are not parts of it) and
    ``"output_pin_holes"`` those of the output pins (:func:`output_pins`, radius pin +
    :func:`output_hole_clearance`).  The holes are the same in both discs."""
    def rows(centres: np.ndarray, radius: float) -> np.ndarray:
        return np.column_stack([centres, np.full(len(centres), radius)])

    hole = crank_hole_radius(reducer)
    if reducer.layout.single_stage:
        holes = {"bore": rows(np.zeros((1, 2)), hole)}
        pins = output_pins(reducer)
        if len(pins):
            holes["output_pin_holes"] = rows(pins, reducer.layout.output_pin_radius
                                             + output_hole_clearance(reducer))
        return holes
    c = reducer.cycloid
    holes = {"bore": rows(np.zeros((1, 2)), c.disc_bore_radius)} \
        if c.disc_bore_radius > 0.0 else {}
    holes["crank_holes"] = rows(crank_holes(reducer), hole)
    if c.pillar_hole_count > 0 and c.pillar_hole_radius > 0.0:
        from .involute import gear_geometry

        angles = pillar_angles(reducer)
        crank_circle = gear_geometry(reducer).centre_distance
        holes["pillar_holes"] = rows(crank_circle * np.column_stack([np.cos(angles),
                                                                     np.sin(angles)]),
                                     c.pillar_hole_radius)
    return holes
