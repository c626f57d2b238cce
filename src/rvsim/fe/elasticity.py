"""Plane linear elasticity on quadratic triangles (scikit-fem) and static condensation onto
boundary loads (docs/model.md "Finite-element bodies").

The body is meshed with six-node (P2) triangles; its stiffness is that of a plate of
``thickness`` in plane stress, Lame's first parameter lambda* = 2 lambda mu / (lambda + 2 mu),
or of a slice of a long body in plane strain (``plane_strain``: lambda itself).
A *boundary load* is a unit resultant spread as a uniform traction over a set of straight
boundary edges; the same vector read as a functional is the traction-weighted mean of the
displacement over those edges.  The compliance between loads i and j is
C_ij = b_i^T K^-1 b_j with the supports' degrees of freedom removed: symmetric and positive
definite by construction (Maxwell-Betti).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["Factor", "PlaneStressBody", "edge_force", "edge_load", "COMPLIANCE_BLOCK"]

#: right-hand sides solved at a time by :meth:`PlaneStressBody.compliance`
COMPLIANCE_BLOCK = 128


class PlaneStressBody:
    """Stiffness of a plane-stress plate on a :class:`rvsim.fe.mesh.PlaneMesh`-like mesh
    (``points`` (2, n), ``triangles`` (3, m)), material E [Pa], nu [-], thickness [m]; with
    ``plane_strain`` a slice of that thickness of a long body held at zero axial strain."""

    def __init__(self, points: np.ndarray, triangles: np.ndarray, elastic_modulus: float,
                 poisson_ratio: float, thickness: float, plane_strain: bool = False):
        from ._extra import require

        require()
        from skfem import Basis, ElementTriP2, ElementVector, MeshTri, asm
        from skfem.models.elasticity import lame_parameters, linear_elasticity

        self.mesh = MeshTri(points, triangles)
        self.basis = Basis(self.mesh, ElementVector(ElementTriP2()))
        lam, mu = lame_parameters(elastic_modulus, poisson_ratio)
        lam_plane = lam if plane_strain else 2.0 * lam * mu / (lam + 2.0 * mu)
        self.thickness = thickness
        self.stiffness = (thickness * asm(linear_elasticity(lam_plane, mu),
                                          self.basis)).tocsc()
        # facet index of each mesh edge (sorted node pair)
        facets = self.mesh.facets
        self._facet_of = {(int(a), int(b)): f for f, (a, b) in enumerate(facets.T)}

    @property
    def n_dofs(self) -> int:
        return self.basis.N

    def node_dofs(self, nodes: np.ndarray) -> np.ndarray:
        """Degrees of freedom (x and y) of mesh vertices ``nodes``, shape (2, len(nodes))."""
        return self.basis.nodal_dofs[:, nodes]

    def edge_dofs(self, a: int, b: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x, y) dofs of vertex a, vertex b and the edge's midside node."""
        f = self._facet_of[(min(a, b), max(a, b))]
        return (self.basis.nodal_dofs[:, a], self.basis.nodal_dofs[:, b],
                self.basis.facet_dofs[:, f])

    def supported_dofs(self, nodes: np.ndarray) -> np.ndarray:
        """Every dof on the boundary through the vertices ``nodes`` (vertices and the midside
        nodes of the boundary edges joining two of them): clamps a hole's edge."""
        chosen = set(int(n) for n in nodes)
        dofs = [self.basis.nodal_dofs[:, nodes].ravel()]
        boundary = self.mesh.boundary_facets()
        for f in boundary:
            a, b = self.mesh.facets[:, f]
            if int(a) in chosen and int(b) in chosen:
                dofs.append(self.basis.facet_dofs[:, f])
        return np.unique(np.concatenate(dofs))

    def mass(self, density: float) -> sp.csc_matrix:
        """Consistent mass matrix of the plate, density [kg/m^3] x thickness x the integral of
        u . v over the mesh (same P2 basis as the stiffness)."""
        from skfem import BilinearForm
        from skfem.helpers import dot

        @BilinearForm
        def vector_mass(u, v, _):
            return dot(u, v)

        return (density * self.thickness * vector_mass.assemble(self.basis)).tocsc()

    def factor(self, supported: np.ndarray) -> "Factor":
        """Sparse Cholesky factor of the stiffness with ``supported`` dofs held at zero."""
        return Factor(self.stiffness, supported)

    def displacements(self, loads: np.ndarray, supported: np.ndarray) -> np.ndarray:
        """K^-1 B for the columns of ``loads`` (n_dofs, k), ``supported`` dofs held at zero
        (sparse Cholesky, cholespy; the stiffness is scaled to unit mean diagonal first)."""
        factor = self.factor(supported)
        u = np.zeros((self.n_dofs, loads.shape[1]))
        u[factor.free] = factor.solve(_dense(loads[factor.free]))
        return u

    def compliance(self, loads: np.ndarray, supported: np.ndarray) -> np.ndarray:
        """C = B^T K^-1 B for the columns of ``loads`` (n_dofs, k), ``supported`` dofs held at
        zero, symmetrised (the asymmetry is round-off).  Solved COMPLIANCE_BLOCK columns at a
        time: memory of a block of displacements, not of all k."""
        factor = self.factor(supported)
        free = loads[factor.free]
        k = loads.shape[1]
        c = np.empty((k, k))
        for start in range(0, k, COMPLIANCE_BLOCK):
            part = factor.solve(_dense(free[:, start:start + COMPLIANCE_BLOCK]))
            c[:, start:start + COMPLIANCE_BLOCK] = np.asarray(free.T @ part)
        return 0.5 * (c + c.T)


class Factor:
    """Sparse Cholesky factorisation (cholespy) of a stiffness ``stiffness`` restricted to the
    dofs not in ``supported`` (``free``, sorted); scaled to unit mean diagonal first."""

    def __init__(self, stiffness: sp.spmatrix, supported: np.ndarray):
        from cholespy import CholeskySolverD, MatrixType

        self.free = np.setdiff1d(np.arange(stiffness.shape[0]), supported)
        a = stiffness.tocsc()[self.free][:, self.free].tocoo()
        self._scale = 1.0 / float(np.mean(a.diagonal()))
        self._solver = CholeskySolverD(a.shape[0], a.row.astype(np.int32),
                                       a.col.astype(np.int32), a.data * self._scale,
                                       MatrixType.COO)

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """K_ff^-1 rhs for a vector or the columns of a matrix over the free dofs."""
        b = np.ascontiguousarray(rhs, dtype=float)
        x = np.zeros_like(b)
        self._solver.solve(b, x)
        return x * self._scale


def _dense(matrix) -> np.ndarray:
    return matrix.toarray() if sp.issparse(matrix) else np.asarray(matrix)


def edge_load(body: PlaneStressBody, edges: list[tuple[int, int]], direction: str = "inward"
              ) -> np.ndarray:
    """Load vector (sparse column, n_dofs x 1) of a unit resultant spread uniformly over
    straight boundary ``edges`` (vertex pairs, counter-clockwise along the outer boundary),
    normal to each edge: ``inward`` pushes into the body.  Consistent P2 load: 1/6 of an
    edge's share at each vertex, 2/3 at the midside node."""
    rows, values = [], []
    pts = body.mesh.p
    lengths = [float(np.linalg.norm(pts[:, b] - pts[:, a])) for a, b in edges]
    total = sum(lengths)
    sign = 1.0 if direction == "inward" else -1.0
    for (a, b), length in zip(edges, lengths):
        dx, dy = pts[:, b] - pts[:, a]
        # outward normal of a counter-clockwise outer boundary: (dy, -dx) / length
        nx, ny = sign * -dy / length, sign * dx / length
        share = length / total
        da, db, dm = body.edge_dofs(a, b)
        for dofs, weight in ((da, 1.0 / 6.0), (db, 1.0 / 6.0), (dm, 2.0 / 3.0)):
            rows += [int(dofs[0]), int(dofs[1])]
            values += [weight * share * nx, weight * share * ny]
    return sp.csc_matrix((values, (rows, np.zeros(len(rows), dtype=np.int64))),
                         shape=(body.n_dofs, 1))


def edge_force(body: PlaneStressBody, edges: list[tuple[int, int]], direction: np.ndarray,
               spans: list[tuple[float, float]] | None = None) -> np.ndarray:
    """Load vector (dense, n_dofs) of a unit force along ``direction`` (a unit vector) spread
    uniformly over boundary ``edges`` (vertex pairs): a bearing load on a hole's edge, whose
    functional is the mean displacement of the edge along ``direction``.  Consistent P2 load
    as in :func:`edge_load`; ``spans`` (s0, s1) per edge load only that part of it (fractions
    of the way from its first vertex to its second: the integrals of the quadratic shape
    functions over [s0, s1])."""
    pts = body.mesh.p
    spans = [(0.0, 1.0)] * len(edges) if spans is None else spans
    lengths = [float(np.linalg.norm(pts[:, b] - pts[:, a])) * (s1 - s0)
               for (a, b), (s0, s1) in zip(edges, spans)]
    total = sum(lengths)
    load = np.zeros(body.n_dofs)
    for (a, b), length, (s0, s1) in zip(edges, lengths, spans):
        da, db, dm = body.edge_dofs(a, b)
        weights = (_shape_integrals(s1) - _shape_integrals(s0)) / (s1 - s0)
        for dofs, weight in zip((da, db, dm), weights):
            load[dofs] += weight * length / total * np.asarray(direction)
    return load


def _shape_integrals(s: float) -> np.ndarray:
    """Integrals over [0, s] of the P2 edge shape functions of the first vertex, the second
    and the midside node (1/6, 1/6, 2/3 at s = 1)."""
    return np.array([s - 1.5 * s * s + 2.0 * s ** 3 / 3.0, -0.5 * s * s + 2.0 * s ** 3 / 3.0,
                     2.0 * s * s - 4.0 * s ** 3 / 3.0])
