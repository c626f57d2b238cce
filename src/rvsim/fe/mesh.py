"""Plane triangle meshes of the reducer's parts from the parameter set (gmsh; docs/model.md
"Finite-element bodies").

The cycloid disc is meshed in the profile axes of one disc (the frame in which the kernel
evaluates the pin gaps, :func:`rvsim.geometry._curve.profile_axes`): its outer boundary is the
(modified) profile sampled at uniform steps of the curve parameter u, one mesh edge per step,
so every profile node has a known u; the crank holes, the central bore and the pillar holes
are circles.  The element size ``h`` is the target edge length everywhere: the profile is cut
into edges of about ``h`` (a multiple of the contact segments, see
:mod:`rvsim.fe.disc`), the circles into edges of about ``h``; gmsh fills the inside growing
from the boundary sizes.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math

import numpy as np

from ..geometry._curve import profile_points
from ._extra import require

__all__ = ["Circle", "PlaneMesh", "mesh_plane_region", "disc_outline", "gmsh_model",
           "gmsh_elements", "drop_unused_nodes"]


@dataclasses.dataclass(frozen=True)
class Circle:
    """A circular hole (centre x, y and radius) [m]."""

    x: float
    y: float
    radius: float


@dataclasses.dataclass(frozen=True)
class PlaneMesh:
    """Triangles of a plane region: ``points`` (2, n) [m], ``triangles`` (3, m) node indices,
    ``outline`` the node index of each outer-boundary point in the order given (counter-
    clockwise), ``holes`` the node indices on each hole's circle."""

    points: np.ndarray
    triangles: np.ndarray
    outline: np.ndarray
    holes: tuple[np.ndarray, ...]


def disc_outline(rg: float, a: float, zp: int, offset: float, n: int) -> np.ndarray:
    """``n`` points of the disc profile at u = 2 pi k / n (profile axes), shape (n, 2) [m]."""
    u = 2.0 * math.pi * np.arange(n) / n
    return profile_points(u, rg, a, float(zp), offset)


@contextlib.contextmanager
def gmsh_model(name: str):
    """A gmsh model ``name`` (gmsh initialised for it unless it already was; one thread, no
    terminal output); yields the gmsh module, removes the model afterwards.  Without gmsh
    (or its system libraries): one RvsimError saying what to install."""
    require()
    import gmsh

    own = not gmsh.isInitialized()
    if own:
        handlers = _signal_handlers()
        gmsh.initialize(readConfigFiles=False)
        _restore(handlers)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add(name)
        try:
            yield gmsh
        finally:
            gmsh.model.remove()
    finally:
        if own:
            gmsh.finalize()
            _restore(handlers)


def _signal_handlers() -> dict:
    """The Python handlers of the stop signals, where they can be set (the main thread).

    gmsh's initialize and finalize replace the C handlers of SIGINT and SIGTERM (finalize
    leaves the default: the process killed outright, without rvsim's line and clean-up, a
    reviewer's ltca of a finite-element disc ended -15 on SIGTERM); Python's table still holds
    its own, which :func:`_restore` installs again."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return {}
    names = ("SIGINT", "SIGTERM", "SIGHUP")
    return {getattr(signal, n): signal.getsignal(getattr(signal, n)) for n in names
            if hasattr(signal, n)}


def _restore(handlers: dict) -> None:
    import signal

    for number, handler in handlers.items():
        if handler is not None:             # None: a handler not set from Python
            signal.signal(number, handler)


def gmsh_elements(gmsh, element_type: int, nodes_per_element: int
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The current gmsh mesh as (points (3, n), elements (nodes_per_element, m) of
    ``element_type`` as node indices, index: gmsh node tag -> node index)."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    points = coords.reshape(-1, 3).T.copy()
    _, nodes = gmsh.model.mesh.getElementsByType(element_type)
    elements = index[nodes.astype(np.int64)].reshape(-1, nodes_per_element).T.copy()
    return points, elements, index


def drop_unused_nodes(points: np.ndarray, elements: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Keep the nodes the elements use (gmsh meshes the circles' centre points as lone
    nodes): (points, elements, renumber: old index -> new index, -1 for a dropped node)."""
    used = np.unique(elements)
    renumber = np.full(points.shape[1], -1, dtype=np.int64)
    renumber[used] = np.arange(len(used))
    return points[:, used].copy(), renumber[elements], renumber


def mesh_plane_region(outline: np.ndarray, holes: list[Circle], size: float) -> PlaneMesh:
    """Mesh the region inside the closed polygon ``outline`` (n, 2), counter-clockwise, one
    edge per polygon side, minus the circular ``holes``; target element size ``size`` [m]."""
    with gmsh_model("rvsim") as gmsh:
        geo = gmsh.model.geo
        n = len(outline)
        # a side longer than the point size would be split: give each point the longest side
        sides = np.linalg.norm(np.roll(outline, -1, axis=0) - outline, axis=1)
        edge = 1.01 * float(sides.max())
        point_tags = [geo.addPoint(float(x), float(y), 0.0, edge) for x, y in outline]
        lines = [geo.addLine(point_tags[i], point_tags[(i + 1) % n]) for i in range(n)]
        loops = [geo.addCurveLoop(lines)]
        hole_arcs = []
        for hole in holes:
            centre = geo.addPoint(hole.x, hole.y, 0.0, size)
            corners = [geo.addPoint(hole.x + hole.radius * math.cos(k * math.pi / 2),
                                    hole.y + hole.radius * math.sin(k * math.pi / 2), 0.0, size)
                       for k in range(4)]
            arcs = [geo.addCircleArc(corners[k], centre, corners[(k + 1) % 4]) for k in range(4)]
            hole_arcs.append(arcs)
            loops.append(geo.addCurveLoop(arcs))
        geo.addPlaneSurface(loops)
        geo.synchronize()
        gmsh.option.setNumber("Mesh.Algorithm", 6)          # Frontal-Delaunay
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 1)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 4.0 * size)
        gmsh.model.mesh.generate(2)
        points, triangles, index = gmsh_elements(gmsh, 2, 3)
        outline_nodes = np.array([index[int(gmsh.model.mesh.getNodes(0, tag)[0][0])]
                                  for tag in point_tags], dtype=np.int64)
        hole_nodes = []
        for arcs in hole_arcs:
            found = [index[gmsh.model.mesh.getNodes(1, arc, includeBoundary=True)[0]
                           .astype(np.int64)] for arc in arcs]
            hole_nodes.append(np.unique(np.concatenate(found)))
    points, triangles, renumber = drop_unused_nodes(points[:2], triangles)
    return PlaneMesh(points, triangles, renumber[outline_nodes],
                     tuple(renumber[h] for h in hole_nodes))
