"""Export of the cycloid disc for grinding or wire-cut: CSV points of the profile, or the
whole disc as a DXF or SVG drawing.

DXF goes through ezdxf, in millimetres ($INSUNITS = 4): the profile as one closed LWPOLYLINE on
layer ``CYCLOID_PROFILE``, each hole of the disc a CIRCLE on the layer of its kind (``BORE``,
``CRANK_HOLES``, ``PILLAR_HOLES``; a single-stage drive's ``BORE`` and ``OUTPUT_PIN_HOLES``:
:func:`rvsim.geometry.layout.disc_holes`), plus the pin circle and the disc centre as
construction geometry on layer ``CONSTRUCTION``.  SVG (xml.etree) holds the same: one group
per layer, the profile a closed path, the holes ``circle`` elements, in millimetres with the
y axis up as in the DXF.  The polyline's chordal deviation from the exact profile is reported
so the user can choose the point count for the tolerance of the machine.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .._files import atomic_write
from ..errors import InputFileError, ParameterError
from ..parameters import Reducer
from .cycloid import check_disc, profile_of
from .layout import disc_count, disc_holes

__all__ = ["export_profile", "chordal_deviation", "least_points", "disc_drawing",
           "SUPPORTED_SUFFIXES", "PROFILE_LAYER", "CONSTRUCTION_LAYER"]

SUPPORTED_SUFFIXES = (".csv", ".dxf", ".svg")
PROFILE_LAYER = "CYCLOID_PROFILE"
CONSTRUCTION_LAYER = "CONSTRUCTION"
_INKSCAPE = "http://www.inkscape.org/namespaces/inkscape"    # its layers: groups of the SVG


def chordal_deviation(reducer: Reducer, points: int) -> float:
    """Largest distance [m] between the exact profile and a ``points``-vertex polyline."""
    prof = profile_of(reducer)
    fine = prof.points(points * 8)
    coarse = prof.points(points)
    # vertex i of the coarse polyline is fine point 8 i; mid-chord distances on each chord
    a = coarse
    b = np.roll(coarse, -1, axis=0)
    worst = 0.0
    for k in range(1, 8):
        p = fine[k::8]
        d = b - a
        t = np.einsum("ij,ij->i", p - a, d) / np.einsum("ij,ij->i", d, d)
        proj = a + t[:, None] * d
        worst = max(worst, float(np.max(np.linalg.norm(p - proj, axis=1))))
    return worst


def least_points(reducer: Reducer) -> int:
    """The fewest profile points :func:`export_profile` writes: three per tooth."""
    return 3 * reducer.cycloid.disc_teeth


def disc_drawing(reducer: Reducer, points: int, disc: int = 0) -> dict[str, np.ndarray]:
    """What a drawing of disc ``disc`` (0 or 1) holds, in millimetres: ``CYCLOID_PROFILE``
    (points x 2, the profile turned by its tooth phase -disc pi / zc) and one layer per kind
    of hole (rows x, y, radius; :func:`~rvsim.geometry.layout.disc_holes`)."""
    disc = check_disc(disc)
    phase = -disc * math.pi / reducer.cycloid.disc_teeth
    layers = {PROFILE_LAYER: profile_of(reducer).points(points, phase) * 1e3}
    for kind, holes in disc_holes(reducer).items():
        layers[kind.upper()] = holes * 1e3
    return layers


def _write_dxf(tmp: Path, layers: dict[str, np.ndarray], pin_circle_mm: float) -> None:
    import ezdxf

    doc = ezdxf.new("R2010", setup=False)
    doc.header["$INSUNITS"] = 4  # millimetres
    doc.layers.add(PROFILE_LAYER, color=7)
    doc.layers.add(CONSTRUCTION_LAYER, color=8)
    msp = doc.modelspace()
    polyline = msp.add_lwpolyline([], close=True, dxfattribs={"layer": PROFILE_LAYER})
    # ezdxf appends given points one at a time, copying its vertex array each time
    # (quadratic: 100 000 points took 67 s, 1 000 000 hours); the whole array at
    # once: x, y, start width, end width, bulge
    xy_mm = layers[PROFILE_LAYER]
    vertices = np.zeros((len(xy_mm), 5))
    vertices[:, :2] = xy_mm
    polyline.lwpoints.set(vertices)
    for layer, holes in layers.items():
        if layer == PROFILE_LAYER:
            continue
        doc.layers.add(layer, color=7)
        for x, y, radius in holes:
            msp.add_circle((float(x), float(y)), float(radius), dxfattribs={"layer": layer})
    msp.add_circle((0.0, 0.0), pin_circle_mm, dxfattribs={"layer": CONSTRUCTION_LAYER})
    msp.add_point((0.0, 0.0), dxfattribs={"layer": CONSTRUCTION_LAYER})
    doc.saveas(tmp)


def _write_svg(tmp: Path, layers: dict[str, np.ndarray]) -> None:
    """The drawing as SVG in millimetres: one group per layer (an Inkscape layer), the
    profile a closed path, each hole a circle; y up (the DXF's frame) by a flipped group."""
    from xml.etree import ElementTree as ET

    xy = layers[PROFILE_LAYER]
    reach = float(np.max(np.abs(xy))) + 1.0                     # 1 mm margin
    size = f"{2.0 * reach:.6f}"
    ET.register_namespace("inkscape", _INKSCAPE)
    svg = ET.Element("svg", {"xmlns": "http://www.w3.org/2000/svg", "version": "1.1",
                             "width": f"{size}mm", "height": f"{size}mm",
                             "viewBox": f"{-reach:.6f} {-reach:.6f} {size} {size}"})
    flipped = ET.SubElement(svg, "g", {"transform": "scale(1,-1)", "fill": "none",
                                       "stroke": "black", "stroke-width": "0.1"})
    for layer, shapes in layers.items():
        shapes = np.round(shapes, 9) + 0.0       # 9 decimals, and no "-0.000000000"
        group = ET.SubElement(flipped, "g", {"id": layer, f"{{{_INKSCAPE}}}label": layer,
                                             f"{{{_INKSCAPE}}}groupmode": "layer"})
        if layer == PROFILE_LAYER:
            text = " ".join(f"{x:.9f},{y:.9f}" for x, y in shapes)
            ET.SubElement(group, "path", {"d": f"M {text} Z"})
            continue
        for x, y, radius in shapes:
            ET.SubElement(group, "circle", {"cx": f"{x:.9f}", "cy": f"{y:.9f}",
                                            "r": f"{radius:.9f}"})
    ET.ElementTree(svg).write(tmp, encoding="utf-8", xml_declaration=True)


def export_profile(reducer: Reducer, path: str | Path, *, points: int = 36000,
                   disc: int = 0) -> dict:
    """Write disc ``disc``'s profile (.csv) or whole drawing (.dxf, .svg: profile and holes)
    to ``path``; return a summary dict."""
    path = Path(path)
    # the name's ending, also of a name that is only the ending (".dxf", whose suffix Python
    # reads as empty)
    suffix = next((s for s in SUPPORTED_SUFFIXES if path.name.lower().endswith(s)),
                  path.suffix.lower())
    if suffix not in SUPPORTED_SUFFIXES:
        raise InputFileError(f"{path}: unsupported profile format '{path.suffix}' "
                             f"(use {', '.join(SUPPORTED_SUFFIXES)})")
    if points < least_points(reducer):
        raise ParameterError("points", f"must be at least {least_points(reducer)} "
                             f"(3 per tooth of the {reducer.cycloid.disc_teeth}-tooth disc; "
                             f"got {points})")
    if not path.parent.exists():
        raise InputFileError(f"{path}: folder {path.parent} does not exist")
    if check_disc(disc) >= disc_count(reducer):
        raise ParameterError("disc", f"the reducer has {disc_count(reducer)} disc "
                             f"(layout.disc_count); got disc {disc + 1}")
    layers = disc_drawing(reducer, points, disc)
    xy_mm = layers[PROFILE_LAYER]

    if suffix == ".csv":
        def write(tmp: Path) -> None:
            np.savetxt(tmp, xy_mm, delimiter=",", header="x_mm,y_mm", comments="", fmt="%.9f")
    elif suffix == ".dxf":
        def write(tmp: Path) -> None:
            _write_dxf(tmp, layers, reducer.cycloid.pin_circle_radius * 1e3)
    else:
        def write(tmp: Path) -> None:
            _write_svg(tmp, layers)
    summary = {"file": str(path), "points": points,       # computed before the file is there
               "chordal_deviation_mm": chordal_deviation(reducer, points) * 1e3,
               "teeth": reducer.cycloid.disc_teeth, "disc": disc + 1,
               "holes": ({} if suffix == ".csv" else
                         {layer: len(h) for layer, h in layers.items()
                          if layer != PROFILE_LAYER})}
    atomic_write(path, write)
    return summary
