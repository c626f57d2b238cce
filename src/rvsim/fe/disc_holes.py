"""The cycloid disc condensed onto its pin contact segments *and* its two crank holes
(docs/model.md section 17, "Crank holes as load points"; issue 13, Deliver 2).

:mod:`rvsim.fe.disc` holds the disc at the edges of its crank holes, so the web between the
holes, which the two arm bushings load, is rigid there.  Here the hole edges are free and each
hole is a *load point*: a unit force along x or y spread uniformly over the hole's edge, whose
functional is the edge's mean displacement (the hole's centre as the bushing sees it; the wall's
local compression under the bushing's pressure belongs to the bushing's own law, switch C, as
for the carrier's bores, :mod:`rvsim.fe.carrier`).

The free disc has three rigid-body motions.  They are removed by a statically determinate
*reference*: the rigid part of the two holes' displacements is zero, i.e. the mean of the two
holes' displacements (2 conditions) and their relative displacement across the line through
them (1 condition) vanish.  With the holes symmetric about the disc centre this is the
least-squares rigid motion of the two hole centres, so the kernel's disc coordinates (centre
and angle) keep their meaning: the rigid motion of the crank holes.  An unbalanced load (the
disc's inertia in the dynamic engine) is carried by the reference's reactions, uniform
tractions on the hole edges.  The compliance over the loads B (segments, then hole 0 x, y,
hole 1 x, y) is

    C = B^T P^T K0^-1 P B,   P = I - G (R^T G)^-1 R^T,

R the rigid modes, G the reference's functionals and K0 the stiffness held at three dofs (any
determinate nodal support: P balances every load, P^T removes the rigid motion; C is the same
for any choice).  C is symmetric positive semi-definite: the reference makes three hole
combinations zero, so relative to it the two holes can only move apart along the line
through them by a *stretch* s (hole 0 by -s/2 e, hole 1 by +s/2 e, e the unit vector from hole 0
to hole 1), whose conjugate force is Q = e . (S_1 - S_0) / 2 (S_k the force on hole k).  The
engines use that form: the pin block, the column c_sp (the stretch under a unit force on segment
j, = the segment's displacement under unit Q, Maxwell-Betti) and c_ss (the stretch under
unit Q).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import scipy.sparse as sp

from ..parameters import Reducer
from . import cache
from .disc import _disc_mesh, disc_geometry
from .elasticity import PlaneStressBody, edge_force

__all__ = ["DiscHoleTable", "disc_hole_table", "disc_hole_tables", "hole_loads",
           "rigid_modes", "reference_functionals", "referenced_compliance", "HOLES_VERSION"]

#: bump when this condensation changes (part of the cache key, with rvsim.fe.disc.FE_VERSION)
HOLES_VERSION = 1


@dataclasses.dataclass(frozen=True)
class DiscHoleTable:
    """Condensed compliance of one disc over its ``segments`` contact segments and its two
    crank holes, relative to the holes' rigid motion (module docstring)."""

    compliance: np.ndarray      # (segments + 4)^2 [m/N]: segments, hole 0 x, y, hole 1 x, y
    stretch: np.ndarray         # (segments + 1): c_sp [m/N] per segment, then c_ss [m/N]
    axis: np.ndarray            # (2,) unit vector from hole 0 to hole 1 (profile axes)
    segments: int
    n_dofs: int
    n_triangles: int
    seconds: float              # meshing + condensation time (0 when loaded from the cache)
    cached: bool


def hole_loads(body: PlaneStressBody, hole_nodes) -> np.ndarray:
    """(n_dofs, 4): a unit force along x, then y, spread uniformly over the edge of hole 0,
    then of hole 1 (``hole_nodes`` the vertices on each hole's circle)."""
    boundary = body.mesh.facets[:, body.mesh.boundary_facets()]
    columns = []
    for j in range(2):
        on = set(int(n) for n in hole_nodes[j])
        edges = [(int(a), int(b)) for a, b in boundary.T if int(a) in on and int(b) in on]
        columns += [edge_force(body, edges, np.array(d)) for d in ([1.0, 0.0], [0.0, 1.0])]
    return np.column_stack(columns)


def rigid_modes(body: PlaneStressBody) -> np.ndarray:
    """(n_dofs, 3): the plane rigid motions (unit x, unit y, unit rotation about the origin)
    at every dof of the P2 basis."""
    basis = body.basis
    component = np.full(basis.N, -1)
    for dofs in (basis.nodal_dofs, basis.facet_dofs):
        component[dofs[0]] = 0
        component[dofs[1]] = 1
    if np.any(component < 0):
        raise AssertionError("a dof of the P2 basis is neither a vertex's nor an edge's")
    x, y = basis.doflocs
    r = np.zeros((basis.N, 3))
    r[component == 0, 0] = 1.0
    r[component == 1, 1] = 1.0
    r[:, 2] = np.where(component == 0, -y, x)
    return r


def reference_functionals(holes: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """(n_dofs, 3) G: the mean of the two holes' displacements (x, y) and their relative
    displacement across the ``axis`` (hole loads ``holes`` (n_dofs, 4) read as functionals)."""
    across = np.array([-axis[1], axis[0]])
    m = np.array([[0.5, 0.0, -across[0]],
                  [0.0, 0.5, -across[1]],
                  [0.5, 0.0, across[0]],
                  [0.0, 0.5, across[1]]])
    return holes @ m


def referenced_compliance(body: PlaneStressBody, loads: np.ndarray, g: np.ndarray,
                          r: np.ndarray, held: np.ndarray) -> tuple[np.ndarray, float]:
    """C = B^T P^T K0^-1 P B (module docstring) for the columns of ``loads`` (n_dofs, k):
    ``g`` the reference's functionals, ``r`` the rigid modes, ``held`` three dofs of a
    determinate nodal support.  Returns (C symmetrised, its relative asymmetry before)."""
    b = loads.toarray() if sp.issparse(loads) else np.asarray(loads)
    balanced = b - g @ np.linalg.solve(r.T @ g, r.T @ b)
    factor = body.factor(held)
    u = np.zeros_like(balanced)
    u[factor.free] = factor.solve(balanced[factor.free])
    u -= r @ np.linalg.solve(g.T @ r, g.T @ u)
    c = b.T @ u
    asymmetry = float(np.max(np.abs(c - c.T)) / np.max(np.abs(c)))
    return 0.5 * (c + c.T), asymmetry


def _determinate_support(body: PlaneStressBody, hole_nodes) -> np.ndarray:
    """Three dofs that hold the plane body's rigid motion and nothing more: x and y of a vertex
    on hole 0, and at the farthest vertex of hole 1 the component most across the line
    joining them."""
    pts = body.mesh.p
    a = int(hole_nodes[0][0])
    far = np.asarray(hole_nodes[1])
    b = int(far[np.argmax(np.hypot(pts[0, far] - pts[0, a], pts[1, far] - pts[1, a]))])
    dx, dy = pts[:, b] - pts[:, a]
    dofs = body.node_dofs(np.array([a, b]))
    return np.array([dofs[0, 0], dofs[1, 0], dofs[1, 1] if abs(dx) >= abs(dy) else dofs[0, 1]])


def stretch_terms(compliance: np.ndarray, axis: np.ndarray, segments: int) -> np.ndarray:
    """(segments + 1): c_sp (the stretch s = e . (h_1 - h_0) under a unit load on each segment)
    and c_ss (the stretch under unit Q: forces -e on hole 0 and +e on hole 1)."""
    m = segments
    row = (-axis[0] * compliance[m] - axis[1] * compliance[m + 1]
           + axis[0] * compliance[m + 2] + axis[1] * compliance[m + 3])
    pull = np.array([-axis[0], -axis[1], axis[0], axis[1]])
    return np.concatenate([row[:m], [row[m:] @ pull]])


def _compute(g: dict) -> dict:
    body, hole_nodes, segment_loads = _disc_mesh(g)
    holes = hole_loads(body, hole_nodes)
    (x0, y0, _), (x1, y1, _) = g["crank_holes"]
    axis = np.array([x1 - x0, y1 - y0]) / np.hypot(x1 - x0, y1 - y0)
    loads = np.column_stack([segment_loads.toarray(), holes])
    c, asymmetry = referenced_compliance(body, loads, reference_functionals(holes, axis),
                                         rigid_modes(body),
                                         _determinate_support(body, hole_nodes))
    return {"compliance": c, "stretch": stretch_terms(c, axis, g["segments"]), "axis": axis,
            "asymmetry": np.array(asymmetry), "n_dofs": np.array(body.n_dofs),
            "n_triangles": np.array(body.mesh.t.shape[1])}


def disc_hole_table(reducer: Reducer, disc: int = 0) -> DiscHoleTable:
    """The condensed compliance of disc ``disc`` over its segments and crank holes (from the
    cache when there)."""
    g = disc_geometry(reducer, disc)
    arrays, seconds, from_cache = cache.cached("cycloid-disc-holes",
                                               {**g, "holes_version": HOLES_VERSION},
                                               lambda: _compute(g))
    return DiscHoleTable(arrays["compliance"], arrays["stretch"], arrays["axis"],
                         g["segments"], int(arrays["n_dofs"]), int(arrays["n_triangles"]),
                         seconds, from_cache)


def disc_hole_tables(reducer: Reducer) -> tuple[np.ndarray, np.ndarray]:
    """The kernel's arrays: tables (2, segments, segments + 1), each disc's pin block relative
    to its holes' rigid motion with its column c_sp appended, and (2,) c_ss.  Disc 2 is disc 1
    turned by (zc + 1) / 2 tooth pitches (odd zc, :func:`rvsim.fe.disc.disc_tables`): its
    segments are shifted, and the turn swaps its holes and reverses the axis, which leaves the
    stretch (the holes' distance) and so c_sp and c_ss as they are; an even zc is meshed on
    its own."""
    first = disc_hole_table(reducer, 0)
    m = first.segments
    zc = reducer.cycloid.disc_teeth
    tables = np.empty((2, m, m + 1))
    css = np.empty(2)
    tables[0, :, :m] = first.compliance[:m, :m]
    tables[0, :, m] = first.stretch[:m]
    css[0] = first.stretch[m]
    if zc % 2 == 1:
        shift = (zc + 1) // 2 * reducer.flexibility.fe_segments_per_tooth
        tables[1, :, :m] = np.roll(first.compliance[:m, :m], shift, axis=(0, 1))
        tables[1, :, m] = np.roll(first.stretch[:m], shift)
        css[1] = css[0]
    else:
        second = disc_hole_table(reducer, 1)
        tables[1, :, :m] = second.compliance[:m, :m]
        tables[1, :, m] = second.stretch[:m]
        css[1] = second.stretch[m]
    return tables, css
