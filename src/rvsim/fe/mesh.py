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
import os
import signal

import numpy as np

from ..geometry._curve import profile_points
from ..errors import ParameterError, RvsimError
from ._extra import require

__all__ = ["Circle", "PlaneMesh", "mesh_plane_region", "check_plane_region", "in_child",
           "MAX_TRIANGLES", "MESH_SECONDS", "disc_outline", "gmsh_model",
           "gmsh_elements", "drop_unused_nodes"]


#: the most triangles a plane region may need: five times the finest admissible RV-40E disc
#: (0.375 mm elements, about 190 000 six-node triangles, 750 000 dofs: fe.sizes); a larger
#: region (a carrier of metres at a disc's element size) would take hours and gigabytes
MAX_TRIANGLES = 1_000_000
#: the longest a mesh may take [s]: gmsh has no time bound of its own, and on a region it
#: cannot mesh it ran forever at 100 % CPU (issue 30); the slowest admissible mesh, the
#: finest crank, takes well under a minute (docs/decisions.md, issue 30)
MESH_SECONDS = 600.0


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


def mesh_plane_region(outline: np.ndarray, holes: list[Circle], size: float,
                      field: str = "flexibility.model") -> PlaneMesh:
    """Mesh the region inside the closed polygon ``outline`` (n, 2), counter-clockwise, one
    edge per polygon side, minus the circular ``holes``; target element size ``size`` [m].
    A region gmsh cannot mesh (a hole crossing the outline or another hole) or too many
    elements are refused first, as ``field``; the meshing runs in a child process
    (:func:`in_child`)."""
    check_plane_region(outline, holes, size, field)
    return in_child(_mesh_plane_region, outline, holes, size)


def _mesh_plane_region(outline: np.ndarray, holes: list[Circle], size: float) -> PlaneMesh:
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


def _segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of each point (k, 2) to the nearest of the segments a[i]-b[i] (n, 2)."""
    d = b - a
    t = np.einsum("kni,ni->kn", points[:, None, :] - a[None], d) / np.einsum("ni,ni->n", d, d)
    nearest = a[None] + np.clip(t, 0.0, 1.0)[..., None] * d[None]
    return np.linalg.norm(points[:, None, :] - nearest, axis=2).min(axis=1)


def check_plane_region(outline: np.ndarray, holes: list[Circle], size: float,
                       field: str) -> None:
    """Refuse, as ``field``, a region gmsh cannot mesh: a hole not wholly inside the outline,
    two holes that overlap (gmsh meshed such a carrier forever), or one needing more than
    :data:`MAX_TRIANGLES` triangles of ``size``."""
    outline = np.asarray(outline, dtype=float)
    x, y = outline[:, 0], outline[:, 1]
    area = 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    if holes:
        centres = np.array([[h.x, h.y] for h in holes])
        radii = np.array([h.radius for h in holes])
        reach = _segment_distance(centres, outline, np.roll(outline, -1, axis=0))
        inside = np.array([_inside(c, outline) for c in centres])
        for h, r, ok in zip(holes, reach, inside):
            if not ok or r <= h.radius:
                raise ParameterError(field, f"a hole of radius {h.radius * 1e3:.4g} mm at "
                                            f"({h.x * 1e3:.4g}, {h.y * 1e3:.4g}) mm reaches "
                                            "beyond the part's outline: no body to mesh")
        gaps = np.hypot(*(centres[:, None, :] - centres[None]).transpose(2, 0, 1))
        gaps -= radii[:, None] + radii[None]
        np.fill_diagonal(gaps, np.inf)
        if gaps.min() <= 0:
            i, j = np.unravel_index(np.argmin(gaps), gaps.shape)
            raise ParameterError(field, f"the holes at ({centres[i][0] * 1e3:.4g}, "
                                        f"{centres[i][1] * 1e3:.4g}) and ({centres[j][0] * 1e3:.4g},"
                                        f" {centres[j][1] * 1e3:.4g}) mm overlap: no body to mesh")
        area -= float(np.pi * np.sum(radii ** 2))
    triangles = 4.0 / math.sqrt(3.0) * area / size ** 2       # equilateral triangles of side h
    if triangles > MAX_TRIANGLES:
        raise ParameterError(field, f"the part needs about {triangles:.3g} triangles of "
                                    f"{size * 1e3:.3g} mm, more than {MAX_TRIANGLES:,} "
                                    "(hours and gigabytes): a smaller part or a coarser "
                                    "flexibility.fe_element_size")


def _inside(point: np.ndarray, polygon: np.ndarray) -> bool:
    """Whether ``point`` lies inside the closed ``polygon`` (n, 2) (crossing count)."""
    a, b = polygon, np.roll(polygon, -1, axis=0)
    crosses = (a[:, 1] > point[1]) != (b[:, 1] > point[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[:, 0] + (point[1] - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(crosses & (x > point[0])) % 2)


def in_child(function, *args, seconds: float | None = None):
    """``function(*args)`` run in a forked child process, its result sent back.

    gmsh meshes inside one C call that neither a Python signal handler nor an alarm can
    interrupt: a mesh that never ended could not be stopped by Ctrl-C or SIGTERM (issue 30).
    Here the parent waits on the child's pipe, where a stop signal raises at once; the child
    is killed when the parent stops, and after ``seconds`` (:data:`MESH_SECONDS`) it is
    killed and the mesh refused.  The child dies with the parent (PR_SET_PDEATHSIG).  Where
    no process can be started (a process limit), and in a study's or tolerance run's worker
    (a daemonic process, which may have no children; its parent stops and kills it), the
    function runs in this process."""
    import multiprocessing
    from multiprocessing.connection import wait

    from .._stopping import signals_blocked

    if multiprocessing.current_process().daemon:
        return function(*args)
    seconds = MESH_SECONDS if seconds is None else seconds
    context = multiprocessing.get_context("fork")
    receive, send = context.Pipe(duplex=False)
    with signals_blocked():
        try:
            child = context.Process(target=_child_main, args=(send, os.getpid(), function, args),
                                    daemon=True)
            child.start()
        except OSError:
            receive.close()
            send.close()
            return function(*args)
    send.close()
    try:
        if not wait([receive, child.sentinel], timeout=seconds):
            raise RvsimError(f"flexibility.model: the mesher did not finish in {seconds:.0f} s "
                             "(stopped): a coarser flexibility.fe_element_size or a part "
                             "geometry gmsh can mesh")
        try:
            ok, value = receive.recv()
        except (EOFError, OSError):
            raise RvsimError(f"flexibility.model: the mesher's process died (exit code "
                             f"{child.exitcode}; out of memory?): a coarser "
                             "flexibility.fe_element_size needs less") from None
    finally:
        receive.close()
        if child.is_alive():
            child.kill()
        child.join()
    if not ok:
        raise value
    return value


def _child_main(send, parent: int, function, args) -> None:
    for name in ("SIGINT", "SIGTERM", "SIGHUP"):     # the parent decides; it kills this child
        number = getattr(signal, name, None)
        if number is not None:
            signal.signal(number, signal.SIG_IGN if number == signal.SIGINT else signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, [signal.SIGINT, signal.SIGTERM])
    from .._stopping import die_with_parent

    die_with_parent(parent)
    try:
        result = (True, function(*args))
    except Exception as exc:          # noqa: BLE001 - raised again in the parent
        result = (False, exc)
    try:
        send.send(result)
    finally:
        send.close()
        os._exit(0)
