"""The crankshaft as a 3-D finite-element body condensed onto its eccentrics (docs/model.md
section 17, "Crankshaft").

The kernel's crank is a rigid shaft carried at two nodes, the lower and upper support
stations (docs/model.md section 5).  What a flexible crank adds is the deflection of its
eccentrics *relative to the straight line through its support stations*: this module computes
that compliance.  The shaft is meshed in 3-D (gmsh, OpenCASCADE kernel: the journal cylinder
from the lower to the upper support band, one eccentric cylinder per disc, offset by the
eccentricity, opposite for the two discs; the planet gear overhang is not meshed) with
ten-node (P2) tetrahedra (scikit-fem, isotropic linear elasticity).

Loads and functionals (each the same vector, Maxwell-Betti): on eccentric k,

* a *force* d (d = x, y): a uniform traction d / A over the eccentric's cylindrical face, whose
  functional is the face's mean displacement along d;
* a *tilt* d: a traction d (z - z_k) / J over the face (J = integral of (z - z_k)^2 dA), a
  unit moment e_z x d, whose functional is the face's mean slope du_d/dz;

each balanced by the reactions of a beam simply supported at the two support bands (uniform
tractions over the journal's face in each band; forces only, the bushings carry no moment)
and, for the force's torque about the crank axis, a uniform torsional traction over the upper
band (the side of the planet gear).  A balanced load does no work on a rigid motion, so the
compliance C = W^T K^-1 W does not depend on the 3-2-1 support that removes the rigid motions
for the solve, and each functional is measured relative to the support line (translations of
the bands, the upper band's twist).  C is 8 x 8: (force x, force y, tilt x, tilt y) of
eccentric 1, then of eccentric 2, in the crank frame with eccentric 1 towards +x.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from ..parameters import Reducer
from ..parameters.fe_sizes import check_crank_element_size
from . import cache
from .elasticity import Factor
from .mesh import drop_unused_nodes, gmsh_elements, gmsh_model, in_child

__all__ = ["CRANK_ELEMENT_SIZE", "crank_geometry", "crank_table", "shaft_compliance"]

#: bump when the discretisation changes (part of every cache key)
CRANK_FE_VERSION = 1


#: default element size of the crank [m]: 3-D P2 tetrahedra cost far more than the disc's
#: triangles (RV-40E: 30 500 dofs, 16 s CPU at 3 mm; 80 000 dofs, 95 s at 2 mm)
CRANK_ELEMENT_SIZE = 3e-3


def crank_geometry(reducer: Reducer, size: float = CRANK_ELEMENT_SIZE) -> dict:
    """Everything the crank's mesh depends on, in SI (the cache key's input); ``size`` the
    element size [m]."""
    k, m = reducer.crank, reducer.materials.crankshaft
    return {"journal_radius": k.journal_radius, "eccentric_radius": k.eccentric_radius,
            "eccentricity": reducer.cycloid.eccentricity,
            "supports": [k.lower_support_z, k.upper_support_z],
            "support_width": k.support_bushing_width,
            "stations": [k.disc1_z, k.disc2_z], "eccentric_width": reducer.cycloid.disc_width,
            "E": m.elastic_modulus, "nu": m.poisson_ratio,
            "size": size, "version": CRANK_FE_VERSION}


def _mesh_shaft(g: dict, size: float):
    """Tetrahedra of the journal and the eccentric cylinders: (points (3, n), tets (4, m))."""
    with gmsh_model("rvsim-crank") as gmsh:
        occ = gmsh.model.occ
        low, high = min(g["supports"]), max(g["supports"])
        half = 0.5 * g["support_width"]
        # the journal in pieces cut at the edges of the support bands and of the eccentrics,
        # so that every band is a set of whole mesh faces
        cuts = [low - half, low + half, high - half, high + half]
        cuts += [z + sign * 0.5 * g["eccentric_width"] for z in g["stations"] for sign in (-1, 1)]
        cuts = sorted({round(c, 12) for c in cuts if low - half <= c <= high + half})
        parts = [(3, occ.addCylinder(0, 0, z0, 0, 0, z1 - z0, g["journal_radius"]))
                 for z0, z1 in zip(cuts[:-1], cuts[1:]) if z1 - z0 > 1e-9]
        for j, z in enumerate(g["stations"]):
            if g["eccentric_radius"] > g["journal_radius"] or g["eccentricity"] > 0:
                x = g["eccentricity"] * (1 if j == 0 else -1)
                parts.append((3, occ.addCylinder(x, 0, z - 0.5 * g["eccentric_width"], 0, 0,
                                                 g["eccentric_width"],
                                                 g["eccentric_radius"])))
        # conformal pieces (shared faces meshed once); the union is the crank
        occ.fragment(parts[:1], parts[1:])
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.5 * size)
        gmsh.model.mesh.generate(3)
        points, tets, _ = gmsh_elements(gmsh, 4, 4)
    points, tets, _ = drop_unused_nodes(points, tets)
    return points, tets


def _band(mesh, centre: tuple[float, float], radius: float, z0: float, z1: float):
    """Boundary facets on the cylinder of ``radius`` about ``centre`` between z0 and z1 (all
    three vertices on the cylinder, the facet's centroid inside the band)."""
    p = mesh.p
    facets = mesh.boundary_facets()
    v = p[:, mesh.facets[:, facets]]                   # (3, 3 vertices, facets)
    dist = np.hypot(v[0] - centre[0], v[1] - centre[1])
    on = np.all(np.abs(dist - radius) < 1e-6 * radius + 1e-9, axis=0)
    zc = v[2].mean(axis=0)
    # the cylinder's side, not an end face whose vertices happen to sit on its rim
    normal = np.cross((v[:, 1] - v[:, 0]).T, (v[:, 2] - v[:, 0]).T)
    side = np.abs(normal[:, 2]) < 0.5 * np.linalg.norm(normal, axis=1)
    return facets[on & side & (zc > z0) & (zc < z1)]


def _curved(mesh, cylinders: list[tuple[float, float, float]]):
    """The quadratic (ten-node) mesh of ``mesh`` with the midside nodes of the boundary edges
    on a cylinder (both ends on it) moved onto it: isoparametric P2, the faceted cylinders'
    O(h^2) loss of section stiffness removed."""
    from skfem import MeshTet2

    quadratic = MeshTet2.from_mesh(mesh)
    doflocs = quadratic.doflocs.copy()
    n_vertices = mesh.p.shape[1]
    for e in mesh.boundary_edges():
        a, b = mesh.edges[:, e]
        for cx, cy, r in cylinders:
            ends = [math.hypot(mesh.p[0, v] - cx, mesh.p[1, v] - cy) for v in (a, b)]
            if all(abs(d - r) < 1e-6 * r for d in ends):
                m = doflocs[:, n_vertices + e]
                rho = math.hypot(m[0] - cx, m[1] - cy)
                doflocs[0, n_vertices + e] = cx + (m[0] - cx) * r / rho
                doflocs[1, n_vertices + e] = cy + (m[1] - cy) * r / rho
                break
    return MeshTet2(doflocs, mesh.t)


def shaft_compliance(g: dict) -> tuple[np.ndarray, int, int]:
    """Mesh, assemble and condense the crank of geometry ``g``: (C 8x8, dofs, tetrahedra)."""
    from ._extra import require

    require()
    from skfem import Basis, ElementTetP2, ElementVector, FacetBasis, LinearForm, MeshTet, asm
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    points, tets = in_child(_mesh_shaft, g, g["size"])   # stoppable, time-bounded
    cylinders = [(0.0, 0.0, g["journal_radius"])]
    cylinders += [(g["eccentricity"] * (1 if j == 0 else -1), 0.0, g["eccentric_radius"])
                  for j in range(len(g["stations"]))]
    mesh = _curved(MeshTet(points, tets), cylinders)
    element = ElementVector(ElementTetP2())
    basis = Basis(mesh, element)
    stiffness = asm(linear_elasticity(*lame_parameters(g["E"], g["nu"])), basis)

    def traction(facets, field):
        """Consistent load of the traction field(x) (3, ...) over ``facets``."""
        fb = FacetBasis(mesh, element, facets=facets)

        @LinearForm
        def form(v, w):
            t = field(w.x)
            return t[0] * v[0] + t[1] * v[1] + t[2] * v[2]

        return form.assemble(fb)

    def integral(facets, scalar):
        fb = FacetBasis(mesh, element, facets=facets)
        from skfem import Functional

        return Functional(lambda w: scalar(w.x)).assemble(fb)

    low, high = min(g["supports"]), max(g["supports"])
    half = 0.5 * g["support_width"]
    rj = g["journal_radius"]
    span = high - low
    bands = {"low": _band(mesh, (0, 0), rj, low - half, low + half),
             "high": _band(mesh, (0, 0), rj, high - half, high + half)}
    area = {k: integral(f, lambda x: 1.0 + 0 * x[0]) for k, f in bands.items()}
    z_band = {k: integral(f, lambda x: x[2]) / area[k] for k, f in bands.items()}
    polar = integral(bands["high"], lambda x: x[0] ** 2 + x[1] ** 2)
    unit = np.eye(3)

    def band_force(key, d):
        return traction(bands[key], lambda x: unit[d][:, None, None] / area[key]
                        + 0 * x)

    twist = traction(bands["high"], lambda x: np.stack([-x[1], x[0], 0 * x[2]]) / polar)
    columns = []
    plain = g["eccentric_radius"] <= rj and g["eccentricity"] <= 0
    for j, z in enumerate(g["stations"]):
        cx = g["eccentricity"] * (1 if j == 0 else -1)
        radius = rj if plain else g["eccentric_radius"]
        half_e = 0.5 * g["eccentric_width"]
        face = _band(mesh, (cx, 0.0), radius, z - half_e, z + half_e)
        a = integral(face, lambda x: 1.0 + 0 * x[0])
        zc = integral(face, lambda x: x[2]) / a
        xc, yc = integral(face, lambda x: x[0]) / a, integral(face, lambda x: x[1]) / a
        jz = integral(face, lambda x: (x[2] - zc) ** 2)
        s = (zc - z_band["low"]) / (z_band["high"] - z_band["low"])
        for d in (0, 1):                          # force along x, y
            torque = xc * unit[d][1] - yc * unit[d][0]
            w = (traction(face, lambda x, d=d: unit[d][:, None, None] / a + 0 * x)
                 - (1 - s) * band_force("low", d) - s * band_force("high", d) - torque * twist)
            columns.append(w)
        for d in (0, 1):                          # tilt about e_z x d
            w = (traction(face, lambda x, d=d: unit[d][:, None, None] * (x[2] - zc) / jz)
                 + band_force("low", d) / span - band_force("high", d) / span)
            columns.append(w)
    loads = np.column_stack(columns)
    # 3-2-1 support: three vertices of the lower band's rim
    vertices = np.unique(mesh.facets[:, bands["low"]])
    target = [(rj, 0.0), (-rj, 0.0), (0.0, rj)]
    pick = [vertices[np.argmin(np.hypot(mesh.p[0, vertices] - tx, mesh.p[1, vertices] - ty)
                               + np.abs(mesh.p[2, vertices] - low))] for tx, ty in target]
    nd = basis.nodal_dofs
    held = np.array([*nd[:, pick[0]], nd[1, pick[1]], nd[2, pick[1]], nd[2, pick[2]]])
    factor = Factor(sp.csc_matrix(stiffness), held)
    u = factor.solve(loads[factor.free])
    c = loads[factor.free].T @ u
    return 0.5 * (c + c.T), int(basis.N), int(tets.shape[1])


def crank_table(reducer: Reducer, size: float = CRANK_ELEMENT_SIZE
                ) -> cache.CondensedTable:
    """The crank's compliance table with elements of ``size`` [m] (from the cache when
    there)."""
    check_crank_element_size(reducer, size)
    g = crank_geometry(reducer, size)
    return cache.condensed_table("crankshaft", g, lambda: shaft_compliance(g))
