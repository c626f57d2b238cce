"""Per-part errors (:class:`~rvsim.parameters.PartErrors`) as the arrays the kernel uses.

One implementation for the dynamic model, the quasi-static engine and the assembly check:

* :func:`pin_centres`: the actual pin centres in housing axes (nominal circle, its error and
  the random pin positions; moved from :mod:`.cycloid`, issue 31 step 8, which imports it).
* :func:`pin_table`: the kernel's ``pins`` array, (zp, 3) or (zp, 3 + 2 K): pin centres
  (column 0, 1), the opening of each pin's gap by its own size and the pin-hole clearance
  (column 2: minus the radius deviation plus half the diametral pin-hole clearance), and, when
  a disc's profile deviates, its normal deviation sampled at zp * K equal steps of the profile
  parameter u (disc k in columns 3 + k K .. 3 + (k + 1) K - 1, row i holding u from
  2 pi i K / (zp K) on; :func:`rvsim.geometry._curve.profile_deviation` interpolates).
* :func:`eccentric_errors`, :func:`hole_offsets`, :func:`bore_offsets`: the cranks' eccentrics,
  the disc holes and the carrier bores.

A disc's pitch deviation and phase turn its teeth about the disc centre: a tooth turned by
delta moves its flank along the outward normal by -delta * (n x q) (q the pin-centre curve, n
its outward normal), to first order; that and the form deviation make one normal deviation
per disc (docs/tolerances.md).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..errors import ParameterError
from ..parameters import Reducer
from ._curve import lever_arms

__all__ = ["check_parts", "pin_centres", "pin_table", "profile_deviation_samples",
           "eccentric_errors", "hole_offsets", "bore_offsets", "SAMPLES_PER_TOOTH",
           "read_profile_csv"]

#: samples of a disc's profile deviation per tooth (linear interpolation between them)
SAMPLES_PER_TOOTH = 64


def _discs(r: Reducer) -> int:
    return r.layout.disc_count if r.layout.single_stage else 2


def _cranks(r: Reducer) -> int:
    return 1 if r.layout.single_stage else 2


def check_parts(r: Reducer) -> None:
    """ParameterError unless every per-part field has the right length and finite values."""
    p, c = r.parts, r.cycloid
    discs, cranks = _discs(r), _cranks(r)
    lengths = {"pin_radial": c.pin_count, "pin_tangential": c.pin_count,
               "pin_radius": c.pin_count, "disc_phase": discs,
               "eccentricity": 2 * cranks, "eccentric_phase": 2 * cranks,
               "carrier_holes": 2 * cranks}
    for name, n in lengths.items():
        value = getattr(p, name)
        if value and len(value) != n:
            raise ParameterError(f"parts.{name}", f"needs {n} values (got {len(value)})")
        if value and not all(math.isfinite(float(v)) for v in value):
            raise ParameterError(f"parts.{name}", "values must be finite numbers")
    for name, inner in (("disc_pitch", c.disc_teeth), ("disc_holes", 2 * cranks)):
        value = getattr(p, name)
        if value and (len(value) != discs or any(len(v) != inner for v in value)):
            raise ParameterError(f"parts.{name}", f"needs {discs} rows of {inner} values")
    for row in p.profile_harmonics:
        if len(row) != 4 or not 0 <= int(row[0]) < discs or int(row[1]) < 0:
            raise ParameterError("parts.profile_harmonics", "rows are (disc, order >= 0, "
                                 f"amplitude, phase), disc from 0 to {discs - 1}")
    if p.profile_points and len(p.profile_points) != discs:
        raise ParameterError("parts.profile_points", f"needs one table per disc ({discs})")
    if p.disc_holes and r.layout.single_stage:
        raise ParameterError("parts.disc_holes", "the single-stage drive has no crank holes in "
                             "its discs (its eccentric bore is on the axis)")


def _tooth_rotation(r: Reducer, disc: int, u: np.ndarray) -> np.ndarray:
    """Rotation of disc ``disc``'s flank at profile parameter u [rad]: its phase plus its
    cumulative pitch deviation, interpolated linearly between the teeth (tooth m's space at
    u = 2 pi m / zc)."""
    p, c = r.parts, r.cycloid
    rotation = np.full(u.shape, float(p.disc_phase[disc]) if p.disc_phase else 0.0)
    if p.disc_pitch:
        arc = np.asarray(p.disc_pitch[disc], dtype=float)
        teeth = 2.0 * np.pi * np.arange(c.disc_teeth) / c.disc_teeth
        rotation += np.interp(u, teeth, arc / c.pin_circle_radius, period=2.0 * np.pi)
    return rotation


def profile_deviation_samples(r: Reducer, disc: int, u: np.ndarray) -> np.ndarray:
    """Normal deviation of disc ``disc``'s profile at parameters ``u`` [m] (positive: excess
    material, the gap to a pin closes by it)."""
    p, c, e = r.parts, r.cycloid, r.errors
    rg = c.pin_circle_radius - e.radial_modification
    out = np.zeros(u.shape)
    for d, order, amplitude, phase in p.profile_harmonics:
        if int(d) == disc:
            out += float(amplitude) * np.cos(float(order) * u + float(phase))
    if p.profile_points:
        table = np.asarray(p.profile_points[disc], dtype=float).reshape(-1, 2)
        if len(table):
            out += np.interp(u, table[:, 0], table[:, 1], period=2.0 * np.pi)
    if p.disc_pitch or p.disc_phase:
        lever = lever_arms(u, rg, c.eccentricity, float(c.pin_count))
        out -= _tooth_rotation(r, disc, u) * lever
    return out


def pin_centres(reducer: Reducer) -> np.ndarray:
    """Actual pin centres in housing axes, shape (zp, 2) [m].

    Pin circle r_p + H; with ``errors.pin_position_tolerance`` t > 0 every pin is moved
    radially and along the circle by independent uniform amounts in [-t, t], drawn from
    ``numpy.random.default_rng(errors.pin_position_seed)`` (reproducible).
    """
    c, e = reducer.cycloid, reducer.errors
    gamma = 2.0 * np.pi * np.arange(c.pin_count) / c.pin_count
    radius = np.full(c.pin_count, c.pin_circle_radius + e.pin_circle_radius)
    if e.pin_position_tolerance > 0.0:
        rng = np.random.default_rng(e.pin_position_seed)
        tol = e.pin_position_tolerance
        radius = radius + rng.uniform(-tol, tol, c.pin_count)
        gamma = gamma + rng.uniform(-tol, tol, c.pin_count) / c.pin_circle_radius
    return radius[:, None] * np.column_stack([np.cos(gamma), np.sin(gamma)])


def pin_table(r: Reducer) -> np.ndarray:
    """The kernel's ``pins`` array (module docstring), a fresh copy (built once per reducer:
    the assembly check, the model and both quasi-static tests of a Monte Carlo reducer share
    it)."""
    return _pin_table(r).copy()


@functools.lru_cache(maxsize=8)
def _pin_table(r: Reducer) -> np.ndarray:
    check_parts(r)
    p, c = r.parts, r.cycloid
    centres = pin_centres(r)
    zp = c.pin_count
    if p.pin_radial or p.pin_tangential:
        radius = np.hypot(centres[:, 0], centres[:, 1])
        gamma = np.arctan2(centres[:, 1], centres[:, 0])
        if p.pin_radial:
            radius = radius + np.asarray(p.pin_radial, dtype=float)
        if p.pin_tangential:
            gamma = gamma + np.asarray(p.pin_tangential, dtype=float) / c.pin_circle_radius
        centres = radius[:, None] * np.column_stack([np.cos(gamma), np.sin(gamma)])
    opening = np.full(zp, 0.5 * r.errors.pin_hole_clearance)
    if p.pin_radius:
        opening -= np.asarray(p.pin_radius, dtype=float)
    columns = [centres, opening[:, None]]
    if p.has_profile:
        per_row = math.ceil(SAMPLES_PER_TOOTH * c.disc_teeth / zp)
        u = 2.0 * np.pi * np.arange(zp * per_row) / (zp * per_row)
        for disc in range(2):
            samples = (profile_deviation_samples(r, disc, u) if disc < _discs(r)
                       else np.zeros(u.shape))
            columns.append(samples.reshape(zp, per_row))
    return np.ascontiguousarray(np.hstack(columns))


def eccentric_errors(r: Reducer) -> tuple[np.ndarray, np.ndarray]:
    """(size [m], phase [rad]) deviation of each eccentric, index 2 j + k (4 each)."""
    p = r.parts
    size, phase = np.zeros(4), np.zeros(4)
    if p.eccentricity:
        size[:len(p.eccentricity)] = p.eccentricity
    if p.eccentric_phase:
        phase[:len(p.eccentric_phase)] = p.eccentric_phase
    return size, phase


def hole_offsets(r: Reducer) -> np.ndarray:
    """(2 cranks, 4): crank j's hole in disc 0 (dx, dy) and disc 1 (dx, dy), disc axes [m]."""
    out = np.zeros((2, 4))
    for disc, row in enumerate(r.parts.disc_holes):
        for crank in range(len(row) // 2):
            out[crank, 2 * disc:2 * disc + 2] = row[2 * crank:2 * crank + 2]
    return out


def bore_offsets(r: Reducer) -> np.ndarray:
    """(2 cranks, 2): radial and tangential offset of crank j's carrier bores [m]."""
    out = np.zeros((2, 2))
    holes = r.parts.carrier_holes
    for crank in range(len(holes) // 2):
        out[crank] = holes[2 * crank:2 * crank + 2]
    return out


def read_profile_csv(path, discs: int = 2) -> tuple:
    """Measured normal deviations of the discs' profiles from a CSV file with the columns
    ``disc`` (1-based), ``angle_deg`` (the profile parameter u in degrees) and
    ``deviation_um`` (positive: excess material), one row per measured point, as a gear
    measuring machine exports them; returns :attr:`PartErrors.profile_points` (SI)."""
    import pandas as pd

    from ..errors import InputFileError

    try:
        frame = pd.read_csv(path)
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise InputFileError(f"{path}: cannot read as CSV ({exc})") from None
    missing = {"disc", "angle_deg", "deviation_um"} - set(frame.columns)
    if missing:
        raise InputFileError(f"{path}: needs the columns disc, angle_deg, deviation_um "
                             f"(missing {', '.join(sorted(missing))})")
    try:
        data = frame[["disc", "angle_deg", "deviation_um"]].astype(float).to_numpy()
    except ValueError:
        raise InputFileError(f"{path}: disc, angle_deg and deviation_um must be numbers") \
            from None
    if not np.all(np.isfinite(data)):
        raise InputFileError(f"{path}: disc, angle_deg and deviation_um must be finite")
    bad = ~np.isin(data[:, 0], np.arange(1, discs + 1))
    if bad.any():
        raise InputFileError(f"{path}: disc must be 1..{discs} (row {int(np.argmax(bad)) + 2})")
    out = []
    for disc in range(1, discs + 1):
        rows = data[data[:, 0] == disc]
        rows = rows[np.argsort(rows[:, 1])]
        out.append(tuple((math.radians(a), d * 1e-6) for _, a, d in rows))
    return tuple(out)
