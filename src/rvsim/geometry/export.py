"""Export of the cycloid disc profile for grinding or wire-cut: CSV points or DXF.

DXF goes through ezdxf: one closed LWPOLYLINE in millimetres ($INSUNITS = 4) on layer
``CYCLOID_PROFILE``, plus the pin circle and the disc centre as construction geometry on layer
``CONSTRUCTION``.  The polyline's chordal deviation from the exact profile is reported so the
user can choose the point count for the tolerance of the machine.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._files import atomic_write
from ..errors import InputFileError, ParameterError
from ..parameters import Reducer
from .cycloid import profile_of

__all__ = ["export_profile", "chordal_deviation", "least_points", "SUPPORTED_SUFFIXES"]

SUPPORTED_SUFFIXES = (".csv", ".dxf")


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


def export_profile(reducer: Reducer, path: str | Path, *, points: int = 36000) -> dict:
    """Write the disc profile to ``path`` (.csv or .dxf); return a summary dict."""
    path = Path(path)
    # the name's ending, also of a name that is only the ending (".dxf", whose suffix Python
    # reads as empty)
    suffix = next((s for s in SUPPORTED_SUFFIXES if path.name.lower().endswith(s)),
                  path.suffix.lower())
    if suffix not in SUPPORTED_SUFFIXES:
        raise InputFileError(f"{path}: unsupported profile format '{path.suffix}' "
                             f"(use {' or '.join(SUPPORTED_SUFFIXES)})")
    if points < least_points(reducer):
        raise ParameterError("points", f"must be at least {least_points(reducer)} "
                             f"(3 per tooth of the {reducer.cycloid.disc_teeth}-tooth disc; "
                             f"got {points})")
    if not path.parent.exists():
        raise InputFileError(f"{path}: folder {path.parent} does not exist")
    xy_mm = profile_of(reducer).points(points) * 1e3

    if suffix == ".csv":
        def write(tmp: Path) -> None:
            np.savetxt(tmp, xy_mm, delimiter=",", header="x_mm,y_mm", comments="", fmt="%.9f")
    else:
        def write(tmp: Path) -> None:
            import ezdxf

            doc = ezdxf.new("R2010", setup=False)
            doc.header["$INSUNITS"] = 4  # millimetres
            doc.layers.add("CYCLOID_PROFILE", color=7)
            doc.layers.add("CONSTRUCTION", color=8)
            msp = doc.modelspace()
            polyline = msp.add_lwpolyline([], close=True,
                                          dxfattribs={"layer": "CYCLOID_PROFILE"})
            # ezdxf appends given points one at a time, copying its vertex array each time
            # (quadratic: 100 000 points took 67 s, 1 000 000 hours); the whole array at
            # once: x, y, start width, end width, bulge
            vertices = np.zeros((len(xy_mm), 5))
            vertices[:, :2] = xy_mm
            polyline.lwpoints.set(vertices)
            c = reducer.cycloid
            msp.add_circle((0.0, 0.0), c.pin_circle_radius * 1e3,
                           dxfattribs={"layer": "CONSTRUCTION"})
            msp.add_point((0.0, 0.0), dxfattribs={"layer": "CONSTRUCTION"})
            doc.saveas(tmp)
    summary = {"file": str(path), "points": points,       # computed before the file is there
               "chordal_deviation_mm": chordal_deviation(reducer, points) * 1e3,
               "teeth": reducer.cycloid.disc_teeth}
    atomic_write(path, write)
    return summary
