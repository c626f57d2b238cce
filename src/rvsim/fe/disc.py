"""The cycloid disc as a finite-element body condensed onto its profile (docs/model.md
"Finite-element bodies").

The disc is a plane-stress plate of the disc width (its load is uniform across the width: no
tilt in the model), meshed by :func:`rvsim.fe.mesh.mesh_plane_region` in the profile axes of
one disc, held at the edges of its two crank holes (the arm bushings carry it there; their own
compliance is switch C), free at the bore and the pillar holes.  The profile is cut into
``zc x flexibility.fe_segments_per_tooth`` *contact segments* of equal steps of the curve
parameter u; the table ``C[i, j]`` is the mean inward normal displacement over segment j under
a unit inward normal force spread uniformly over segment i [m/N].  A pin contact at foot
parameter u is read from the table by interpolation between segment centres
(:mod:`rvsim.physics._fe_contacts`).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import scipy.sparse as sp

from ..errors import ParameterError
from ..parameters import Reducer
from ..parameters.fe_sizes import disc_element_size
from . import cache
from .elasticity import PlaneStressBody, edge_load
from .mesh import Circle, disc_outline, mesh_plane_region

__all__ = ["DiscTable", "disc_body", "disc_geometry", "disc_table", "disc_tables", "FE_VERSION"]

#: bump when the discretisation changes (part of every cache key)
FE_VERSION = 1


@dataclasses.dataclass(frozen=True)
class DiscTable:
    """Condensed compliance of one disc between its ``segments`` contact segments."""

    compliance: np.ndarray      # (segments, segments) [m/N]
    segments: int
    n_dofs: int
    n_triangles: int
    seconds: float              # meshing + condensation time (0 when loaded from the cache)
    cached: bool


def disc_geometry(reducer: Reducer, disc: int = 0) -> dict:
    """Everything the disc's mesh depends on, in SI (the cache key's input)."""
    from ..geometry.cycloid import profile_of
    from ..geometry.involute import gear_geometry

    if reducer.layout.single_stage:
        raise ParameterError("flexibility.model", "the finite-element disc is built for the "
                             "RV reducer only so far (use closed-form for the single-stage "
                             "drive)")
    c, k, f = reducer.cycloid, reducer.crank, reducer.flexibility
    prof = profile_of(reducer)
    phase = disc * math.pi / c.disc_teeth - reducer.errors.rotation_modification
    crank_circle = gear_geometry(reducer).centre_distance
    hole = k.eccentric_radius + k.arm_bushing_thickness
    crank_holes = [(crank_circle * math.cos(phase + j * math.pi),
                    crank_circle * math.sin(phase + j * math.pi), hole) for j in range(2)]
    pillars = [(crank_circle * math.cos(phase + math.pi / 2 + 2 * math.pi * j
                                        / c.pillar_hole_count),
                crank_circle * math.sin(phase + math.pi / 2 + 2 * math.pi * j
                                        / c.pillar_hole_count), c.pillar_hole_radius)
               for j in range(c.pillar_hole_count)] if c.pillar_hole_radius > 0 else []
    m = reducer.materials.cycloid_disc
    return {"rg": prof.generating_radius, "a": prof.eccentricity, "zp": prof.pin_count,
            "offset": prof.offset, "crank_holes": crank_holes, "pillars": pillars,
            "bore": c.disc_bore_radius, "E": m.elastic_modulus, "nu": m.poisson_ratio,
            "width": c.disc_width, "size": disc_element_size(reducer),
            "segments": c.disc_teeth * f.fe_segments_per_tooth, "version": FE_VERSION}


def disc_body(g: dict) -> tuple[PlaneStressBody, np.ndarray, sp.csc_matrix]:
    """Mesh and assemble the disc of geometry ``g`` (:func:`disc_geometry`): the body, its
    supported dofs (the crank-hole edges) and the unit loads of its contact segments
    (n_dofs x segments)."""
    body, hole_nodes, loads = _disc_mesh(g)
    supported = np.concatenate([body.supported_dofs(hole_nodes[j]) for j in range(2)])
    return body, supported, loads


def _disc_mesh(g: dict) -> tuple[PlaneStressBody, tuple, sp.csc_matrix]:
    """The body, the vertices on each hole's circle and the segments' unit loads."""
    segments = g["segments"]
    dense = disc_outline(g["rg"], g["a"], g["zp"], g["offset"], 16 * segments)
    length = float(np.sum(np.linalg.norm(np.roll(dense, -1, axis=0) - dense, axis=1)))
    per_segment = max(1, round(length / segments / g["size"]))
    n_edges = segments * per_segment
    outline = disc_outline(g["rg"], g["a"], g["zp"], g["offset"], n_edges)
    holes = [Circle(x, y, r) for x, y, r in g["crank_holes"]]
    holes += [Circle(0.0, 0.0, g["bore"])] if g["bore"] > 0 else []
    holes += [Circle(x, y, r) for x, y, r in g["pillars"]]
    mesh = mesh_plane_region(outline, holes, g["size"])
    body = PlaneStressBody(mesh.points, mesh.triangles, g["E"], g["nu"], g["width"])
    nodes = mesh.outline
    loads = sp.hstack([
        edge_load(body, [(int(nodes[e]), int(nodes[(e + 1) % n_edges]))
                         for e in range(s * per_segment, (s + 1) * per_segment)])
        for s in range(segments)]).tocsc()
    return body, mesh.holes, loads


def _compute(g: dict) -> tuple[np.ndarray, int, int]:
    """Mesh, assemble and condense: (table, dofs, triangles)."""
    body, supported, loads = disc_body(g)
    table = body.compliance(loads, supported)
    return table, int(body.n_dofs), int(body.mesh.t.shape[1])


def disc_table(reducer: Reducer, disc: int = 0) -> DiscTable:
    """The condensed compliance table of disc ``disc`` (from the cache when there)."""
    g = disc_geometry(reducer, disc)

    def compute():
        table, n_dofs, n_tri = _compute(g)
        return {"compliance": table, "n_dofs": np.array(n_dofs),
                "n_triangles": np.array(n_tri)}

    arrays, seconds, from_cache = cache.cached("cycloid-disc", g, compute)
    return DiscTable(arrays["compliance"], g["segments"], int(arrays["n_dofs"]),
                     int(arrays["n_triangles"]), seconds, from_cache)


def disc_tables(reducer: Reducer) -> np.ndarray:
    """Tables of both discs, shape (2, segments, segments), for the kernel.

    Disc 2 is disc 1 turned half a turn; with an odd tooth count that turn is a whole number
    (zc + 1) / 2 of tooth pitches, so disc 2's table is disc 1's with its segments shifted by
    that many teeth (no second mesh); with an even count it is meshed on its own.
    """
    first = disc_table(reducer, 0).compliance
    zc = reducer.cycloid.disc_teeth
    odd = zc % 2 == 1
    shift = (zc + 1) // 2 * reducer.flexibility.fe_segments_per_tooth if odd else 0
    second = None if odd else disc_table(reducer, 1).compliance
    # the cache hands the same (read-only) arrays out while their files are unchanged: the
    # stack built from them is kept (a model per call of the engines; 2 ms per RV-40E)
    for sources, tables in _STACKED:
        if sources[0] is first and sources[1] is second and sources[2] == shift:
            return tables
    if odd:
        second_table = np.roll(first, shift, axis=(0, 1))
    else:
        second_table = second
    tables = np.stack([first, second_table])
    _STACKED.insert(0, ((first, second, shift), tables))
    del _STACKED[4:]
    return tables


#: the last tables of :func:`disc_tables` with the arrays they were built from (shared: the
#: engines only read them)
_STACKED: list = []
