"""A pin in its housing groove as a finite-element body: the compliance c_pin(psi) of the pin
under the disc's contact force at angle psi from the groove axis (docs/model.md sections 6
and 17).

The pin's cross-section is a plane-strain slice of the disc width (the pin is held along its
whole length in the groove and loaded uniformly across the disc's width: the axial strain of a
long cylinder under a line load is held by the material beside the slice, the assumption of
the Hertz line contact and of Roark's formula), meshed by :func:`rvsim.fe.mesh.
mesh_plane_region` with six-node triangles (:class:`rvsim.fe.elasticity.PlaneStressBody`).
Pin axes: x along the groove axis (the outward radial of the pin circle), the groove the half
circle |theta| <= 90 deg.

* **Groove**: rigid (the housing is rigid in the model), conforming (groove radius = pin
  radius: the pin-hole clearance is the kernel's kinematic opening), frictionless (greased).
  The pin touches it where it presses on it: Signorini's conditions at the boundary nodes of
  the groove arc (normal displacement into the groove zero where the groove pushes, the node
  free where it would have to pull) solved by an active set, one tangential hold at the groove
  bottom for the rigid rotation (the loads have no moment about the pin axis, so it carries
  nothing).  With zero clearance and a rigid groove the contact set does not depend on the
  load's size, so the compliance is exactly linear (no linearisation at a rated load).
* **Load**: a unit force along the contact normal (x turned by psi) spread uniformly over an
  arc of the pin's surface centred on the contact point (theta = psi + 180 deg), as wide as the
  disc's contact segment (:mod:`rvsim.fe.disc`; capped at the pin radius; the arc's end edges
  loaded in part, so the width does not depend on the mesh); the same vector is
  the functional (Maxwell-Betti): c_pin(psi) = f^T u [m/N], the mean approach of the loaded
  arc along the force relative to the groove.
* **Table**: psi = k * :data:`TABLE_STEP_DEG`, k = 0 .. :data:`TABLE_STEPS` (symmetric in psi:
  the groove is), cached by the geometry's hash (:mod:`rvsim.fe.cache`); the kernel reads it
  from P (``_layout.PIN_FE_STEP``, ``PIN_FE0``) through
  :func:`rvsim.physics._pin_compliance.pin_series_compliance`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import scipy.sparse as sp

from ..parameters import Reducer
from . import cache
from .elasticity import Factor, PlaneStressBody, edge_force
from .mesh import mesh_plane_region

__all__ = ["PinModel", "PinTable", "TABLE_STEPS", "pin_geometry", "pin_table", "PIN_VERSION"]

#: table intervals and their size: psi = 0 .. 80 deg (the kernel's P block holds
#: TABLE_STEPS + 1 values; the reducer's contacts stay below arcsin(a zp / r_p), 47 deg for
#: the RV-40E, docs/model.md section 6)
TABLE_STEPS = 8             # = physics._layout.PIN_FE_N - 1 (tests/verification/test_fe_pin.py)
TABLE_STEP_DEG = 10.0
#: bump when the discretisation changes (part of every cache key)
PIN_VERSION = 1
#: boundary edges per load arc (at least)
EDGES_PER_LOAD = 16


@dataclasses.dataclass(frozen=True)
class PinTable:
    """c_pin at psi = 0, step, .. [m/N], with the size of the mesh."""

    psi: np.ndarray             # (TABLE_STEPS + 1,) [rad]
    compliance: np.ndarray      # (TABLE_STEPS + 1,) [m/N]
    n_dofs: int
    n_triangles: int
    seconds: float              # meshing + solves (0 when loaded from the cache)
    cached: bool


def _disc_segment_length(reducer: Reducer) -> float:
    """Arc length of one contact segment of the finite-element disc [m]."""
    from ..geometry.cycloid import profile_of
    from .mesh import disc_outline

    c, f = reducer.cycloid, reducer.flexibility
    prof = profile_of(reducer)
    segments = c.disc_teeth * f.fe_segments_per_tooth
    dense = disc_outline(prof.generating_radius, prof.eccentricity, prof.pin_count,
                         prof.offset, 16 * segments)
    return float(np.sum(np.linalg.norm(np.roll(dense, -1, axis=0) - dense, axis=1))) / segments


def pin_geometry(reducer: Reducer) -> dict:
    """Everything the pin table depends on, in SI (the cache key's input)."""
    c, m = reducer.cycloid, reducer.materials.pin
    radius = c.pin_radius - reducer.errors.pin_radius
    return {"radius": radius, "E": m.elastic_modulus, "nu": m.poisson_ratio,
            "length": c.disc_width, "load_width": min(_disc_segment_length(reducer), radius),
            "steps": TABLE_STEPS, "step_deg": TABLE_STEP_DEG, "version": PIN_VERSION}


class PinModel:
    """The meshed pin of geometry ``g`` (:func:`pin_geometry`); :meth:`solve` gives c_pin at
    an angle psi."""

    def __init__(self, g: dict, edges_per_load: int = EDGES_PER_LOAD):
        radius = g["radius"]
        self.load_angle = g["load_width"] / radius
        # boundary edges: a multiple of 4 (the groove's ends on nodes), at least
        # ``edges_per_load`` of them across the load arc
        n = 4 * math.ceil(2.0 * math.pi * edges_per_load / self.load_angle / 4)
        self.n_edges = n
        self.edge_angle = 2.0 * math.pi / n
        theta = self.edge_angle * np.arange(n)
        outline = radius * np.column_stack([np.cos(theta), np.sin(theta)])
        edge = 2.0 * radius * math.sin(0.5 * self.edge_angle)
        mesh = mesh_plane_region(outline, [], 2.0 * edge)
        self.body = PlaneStressBody(mesh.points, mesh.triangles, g["E"], g["nu"], g["length"],
                                    plane_strain=True)
        self.outline = mesh.outline
        self.radius = radius
        # boundary nodes of the groove arc (vertices and midside nodes), their angles and dofs
        dofs, angles = [], []
        for k in range(n):
            a, b = int(self.outline[k]), int(self.outline[(k + 1) % n])
            da, _, dm = self.body.edge_dofs(a, b)
            for d, t in ((da, theta[k]), (dm, theta[k] + 0.5 * self.edge_angle)):
                t = (t + math.pi) % (2.0 * math.pi) - math.pi
                if abs(t) <= 0.5 * math.pi + 1e-9:
                    dofs.append(d)
                    angles.append(t)
        self.groove_dofs = np.array(dofs, dtype=np.int64)       # (k, 2) x and y dofs
        self.groove_angles = np.array(angles)
        self._rotation = self._rotate()
        self.stiffness = (self._rotation.T @ self.body.stiffness @ self._rotation).tocsc()
        self.bottom = int(np.argmin(np.abs(self.groove_angles)))

    def _rotate(self) -> sp.csc_matrix:
        """u = R w: at each groove node w holds (normal, tangential) displacement, elsewhere
        (x, y)."""
        n_dofs = self.body.n_dofs
        rot = sp.lil_matrix((n_dofs, n_dofs))
        rot.setdiag(1.0)
        for (dx, dy), t in zip(self.groove_dofs, self.groove_angles):
            c, s = math.cos(t), math.sin(t)
            rot[dx, dx], rot[dx, dy] = c, -s
            rot[dy, dx], rot[dy, dy] = s, c
        return rot.tocsc()

    def load(self, psi: float) -> np.ndarray:
        """Unit force along (cos psi, sin psi) spread uniformly over the load arc centred at
        psi + 180 deg, in (x, y) dofs (the arc's end edges loaded in part)."""
        n = self.n_edges
        start = (psi + math.pi - 0.5 * self.load_angle) / self.edge_angle
        stop = start + self.load_angle / self.edge_angle
        edges, spans = [], []
        for k in range(math.floor(start), math.ceil(stop)):
            s0, s1 = max(start - k, 0.0), min(stop - k, 1.0)
            if s1 > s0:
                edges.append((int(self.outline[k % n]), int(self.outline[(k + 1) % n])))
                spans.append((s0, s1))
        return edge_force(self.body, edges, np.array([math.cos(psi), math.sin(psi)]), spans)

    def solve(self, psi: float, start: np.ndarray | None = None, max_sets: int = 60
              ) -> tuple[float, np.ndarray, int]:
        """(c_pin(psi) [m/N], contact flags of the groove nodes, active-set iterations), the
        active set started from ``start`` (default: the whole groove)."""
        f = self._rotation.T @ self.load(psi)
        normal = self.groove_dofs[:, 0]             # w_n dof of each groove node (rotated)
        active = np.ones(len(normal), dtype=bool) if start is None else start.copy()
        for iteration in range(1, max_sets + 1):
            held = np.concatenate([normal[active], [self.groove_dofs[self.bottom, 1]]])
            factor = Factor(self.stiffness, held)
            w = np.zeros(self.body.n_dofs)
            w[factor.free] = factor.solve(f[factor.free])
            reaction = self.stiffness @ w - f        # the groove's force on the pin
            pulls = active & (reaction[normal] > 1e-12 * np.abs(reaction[normal]).max())
            enters = ~active & (w[normal] > 1e-9 * np.abs(w).max())  # moving into the groove
            if not pulls.any() and not enters.any():
                return float(f @ w), active, iteration
            active = (active & ~pulls) | enters
        raise RuntimeError("pin groove contact set did not settle")  # pragma: no cover


def _compute(g: dict) -> dict:
    model = PinModel(g)
    psi = np.radians(g["step_deg"]) * np.arange(g["steps"] + 1)
    values, active = [], None
    for p in psi:             # the contact set shrinks with psi: start from the last one
        value, active, _ = model.solve(float(p), active)
        values.append(value)
    values = np.array(values)
    return {"psi": psi, "compliance": values, "n_dofs": np.array(model.body.n_dofs),
            "n_triangles": np.array(model.body.mesh.t.shape[1])}


def pin_table(reducer: Reducer) -> PinTable:
    """c_pin over psi = 0 .. 80 deg for the reducer's pins (from the cache when there)."""
    g = pin_geometry(reducer)
    arrays, seconds, from_cache = cache.cached("pin-in-groove", g, lambda: _compute(g))
    return PinTable(arrays["psi"], arrays["compliance"], int(arrays["n_dofs"]),
                    int(arrays["n_triangles"]), seconds, from_cache)

