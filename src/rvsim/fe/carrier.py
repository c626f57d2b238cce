"""The carrier (and the flange) as a plane-stress body condensed onto its crank bores
(docs/model.md section 17, "Carrier").

With ``flexibility.fe_carrier`` the engines' crank support bushings bear on these plates'
bores (rvsim.physics._fe_carrier); else on rigid bores that turn with the carrier.  This
module computes how far a bore moves, relative to the carrier held at
its rim, under a bearing load on it or on the other bore: a plane-stress plate of radius
``cycloid.carrier_radius`` and thickness ``thickness`` (default half of
``cycloid.carrier_thickness``: the carrier and the flange each take one support), with the
central bore (``cycloid.disc_bore_radius``, the input shaft's passage) and the crank bores
(journal + bushing wall, on the crank circle a_w, opposite), clamped at the rim (the main
bearings hold it radially and the output flange's bolts turn it).  A load is a unit force
along x or y spread uniformly over a bore's edge; its functional is the edge's mean
displacement along it.  The table is 4 x 4 (bore 1 x, y, bore 2 x, y) in the carrier frame
with bore 1 on +x.  The pillars joining carrier and flange, and the plates' bending out of
their plane, are not in the model.
"""

from __future__ import annotations

import math

import numpy as np

from ..parameters import Reducer
from . import cache
from .elasticity import PlaneStressBody, edge_force
from .mesh import Circle, mesh_plane_region

__all__ = ["carrier_geometry", "carrier_table", "plate_compliance"]

#: bump when the discretisation changes (part of every cache key)
CARRIER_FE_VERSION = 1


def carrier_geometry(reducer: Reducer, thickness: float | None = None) -> dict:
    """Everything the carrier's mesh depends on, in SI (the cache key's input)."""
    from ..geometry.involute import gear_geometry
    from ..parameters.fe_sizes import disc_element_size

    c, k, m = reducer.cycloid, reducer.crank, reducer.materials.carrier
    return {"radius": c.carrier_radius, "bore": c.disc_bore_radius,
            "crank_circle": gear_geometry(reducer).centre_distance,
            "crank_bore": k.journal_radius + k.arm_bushing_thickness,
            "thickness": c.carrier_thickness / 2 if thickness is None else thickness,
            "E": m.elastic_modulus, "nu": m.poisson_ratio,
            "size": disc_element_size(reducer), "version": CARRIER_FE_VERSION}


def plate_compliance(g: dict) -> tuple[np.ndarray, int, int]:
    """Mesh, assemble and condense the carrier plate ``g``: (C 4x4, dofs, triangles)."""
    size = g["size"]
    n = max(16, 4 * round(2 * math.pi * g["radius"] / size / 4))
    angle = 2 * math.pi * np.arange(n) / n
    outline = g["radius"] * np.column_stack([np.cos(angle), np.sin(angle)])
    bores = [Circle(sign * g["crank_circle"], 0.0, g["crank_bore"]) for sign in (1, -1)]
    holes = bores + ([Circle(0.0, 0.0, g["bore"])] if g["bore"] > 0 else [])
    mesh = mesh_plane_region(outline, holes, size, field="cycloid.carrier_radius")
    body = PlaneStressBody(mesh.points, mesh.triangles, g["E"], g["nu"], g["thickness"])
    rim = body.supported_dofs(mesh.outline)
    boundary = body.mesh.facets[:, body.mesh.boundary_facets()]
    columns = []
    for j in range(2):
        on = set(int(v) for v in mesh.holes[j])
        edges = [(int(a), int(b)) for a, b in boundary.T if int(a) in on and int(b) in on]
        for d in (np.array([1.0, 0.0]), np.array([0.0, 1.0])):
            columns.append(edge_force(body, edges, d))
    loads = np.column_stack(columns)
    c = body.compliance(loads, rim)
    return c, int(body.n_dofs), int(mesh.triangles.shape[1])


def carrier_table(reducer: Reducer, thickness: float | None = None
                  ) -> cache.CondensedTable:
    """The carrier's bore compliance table (from the cache when there); ``thickness`` [m] of
    the plate, default half the carrier + flange thickness."""
    g = carrier_geometry(reducer, thickness)
    return cache.condensed_table("carrier", g, lambda: plate_compliance(g))
