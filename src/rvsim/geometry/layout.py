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

__all__ = ["crank_angles", "crank_holes", "disc_count", "output_pins", "output_hole_clearance",
           "crank_hole_radius", "pillar_angles", "neighbour_distance",
           "roller_pitch_diameter"]


def crank_angles(reducer: Reducer) -> np.ndarray:
    """Assembly angles of the cranks about the housing axis (RV: 0 and pi; single-stage: 0)."""
    return np.array([0.0]) if reducer.layout.single_stage else np.array([0.0, math.pi])


def crank_holes(reducer: Reducer) -> np.ndarray:
    """Centres of the cranks' holes in a disc at the assembled pose, (n_cranks, 2) [m]."""
    if reducer.layout.single_stage:
        return np.zeros((1, 2))
    from .involute import gear_geometry

    angles = crank_angles(reducer)
    return gear_geometry(reducer).centre_distance * np.column_stack([np.cos(angles),
                                                                     np.sin(angles)])


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
