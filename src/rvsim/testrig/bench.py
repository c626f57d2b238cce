"""A file or a folder of bench recordings -> the standard numbers per operating point.

A folder holds any number of ``.csv`` / ``.parquet`` files; each file's operating point
(speed, torque, oil temperature) comes from its name (``fwd_15rpm_300Nm_40C.csv``) or from a
``manifest.csv`` beside them (columns ``file`` and any of ``speed_rpm``, ``torque_nm``,
``temperature_c``, ``test``, ``ratio``; when it exists it lists the files to analyse).  Files
with the same point form one operating point (e.g. a forward, a backward and a torque-reversal
recording); a file whose point is given nowhere is a point of its own, its values measured.
"""

from __future__ import annotations

import csv
import dataclasses
import math
from pathlib import Path

import numpy as np

from ..analysis.catalogue import CurveError
from .._keywords import renamed
from ..errors import InputFileError
from ..parameters import plain_number
from . import analysis as A
from .recording import (ColumnMap, Recording, check_ratio, missing_mapped, no_column_error,
                        point_from_name, read_recording)

__all__ = ["FileResult", "PointResult", "analyse_path", "analyse_recording", "list_files",
           "check_model_ratio", "RATIO_TOLERANCE", "MANIFEST"]

#: the measured ratio may differ from the expected one by this fraction
RATIO_TOLERANCE = 0.01
#: beyond this fraction (and within RATIO_TOLERANCE) the TE carries the ratio's trend: noted
#: (a TE of 1 arcmin moves a one-revolution measurement of the ratio by 5e-5)
RATIO_NOTE = 2e-4
MANIFEST = "manifest.csv"
#: most output travel of a torque-reversal recording [rad] (a reversal moves it by arcminutes)
REVERSAL_TRAVEL = math.radians(18.0)
_SUFFIXES = (".csv", ".parquet", ".pq", ".tsv", ".txt")
_RPM = 2.0 * math.pi / 60.0


@dataclasses.dataclass
class FileResult:
    """One recording analysed."""

    path: Path
    test: str                          # transmission_error | torque_reversal | te_curve
    measured: dict                     # operating point measured from the data
    directions: list | None = None     # [DirectionTE]
    loop: tuple | None = None          # (torque, angle, branch) catalogue form
    efficiency: float | None = None
    ratio_measured: float | None = None
    ratio_expected: float | None = None    # the ratio the file was analysed with
    samples: int = 0
    notes: list = dataclasses.field(default_factory=list)   # what a reader must know


@dataclasses.dataclass
class PointResult:
    """The files of one operating point and their combined numbers."""

    point: dict
    files: list

    def leading_direction(self):
        """The TE direction whose spectrum stands for the point: the first forward one of any
        file, else the first direction (None without TE)."""
        found = [d for f in self.files for d in f.directions or []]
        return next((d for d in found if d.direction > 0), found[0] if found else None)


def list_files(path: str | Path) -> list[tuple[Path, dict]]:
    """(file, declared point and options) of a file or folder (see the module docstring)."""
    path = Path(path)
    if path.is_file():
        return [(path, point_from_name(path.name))]
    if not path.is_dir():
        raise InputFileError(f"{path}: no such file or folder")
    manifest = path / MANIFEST
    if manifest.is_file():
        return _read_manifest(manifest)
    files = sorted(p for p in path.iterdir() if p.is_file() and p.suffix.lower() in _SUFFIXES
                   and not p.name.startswith("."))
    if not files:
        raise InputFileError(f"{path}: no .csv or .parquet recordings in the folder")
    return [(p, point_from_name(p.name)) for p in files]


def _read_manifest(manifest: Path) -> list[tuple[Path, dict]]:
    import pandas as pd

    try:
        frame = pd.read_csv(manifest, sep=None, engine="python", comment="#",
                            encoding="utf-8-sig")    # Excel's "CSV UTF-8" starts with a BOM
    except (pd.errors.ParserError, pd.errors.EmptyDataError, csv.Error, UnicodeDecodeError,
            ValueError, OSError) as exc:
        raise InputFileError(f"{manifest}: not a readable CSV file ({exc})") from None
    frame.columns = [str(c).strip() for c in frame.columns]
    if "file" not in frame.columns:
        raise InputFileError(f"{manifest}: missing column 'file'")
    known = {"file", "speed_rpm", "torque_nm", "temperature_c", "test", "ratio"}
    unknown = set(frame.columns) - known
    if unknown:
        raise InputFileError(f"{manifest}: unknown columns {', '.join(sorted(unknown))} "
                             f"(known: {', '.join(sorted(known))})")
    out = []
    for row, record in enumerate(frame.to_dict("records"), start=2):
        name = record.pop("file")
        if isinstance(name, float) and math.isnan(name) or not str(name).strip():
            raise InputFileError(f"{manifest}: row {row}: the file cell is empty")
        target = manifest.parent / str(name).strip()
        if not target.is_file():
            raise InputFileError(f"{manifest}: row {row}: file {target.name} not found")
        declared = {}
        for key, value in record.items():
            if isinstance(value, float) and math.isnan(value):
                continue
            if key == "test":
                value = str(value).strip()
                if value not in ("transmission_error", "torque_reversal", "te_curve"):
                    raise InputFileError(f"{manifest}: row {row}: test must be "
                                         "transmission_error, torque_reversal or te_curve "
                                         f"(got {value!r})")
            elif key == "ratio":
                value = check_ratio(value, f"{manifest}: row {row}")
            else:
                try:
                    value = plain_number(value)
                except ValueError:
                    raise InputFileError(f"{manifest}: row {row}: {key} '{value}' is not a "
                                         "number") from None
                if not math.isfinite(value):
                    raise InputFileError(f"{manifest}: row {row}: {key} must be a finite "
                                         f"number (got {value})")
            declared[key] = value
        out.append((target, declared))
    if not out:
        raise InputFileError(f"{manifest}: lists no files")
    return out


def _longest_run(phi: np.ndarray, runs=None) -> tuple[int, int]:
    runs = A._segments(phi, A.REVERSAL_FRACTION * 2.0 * math.pi) if runs is None else runs
    if not runs:
        return 0, phi.size
    a, b, _ = max(runs, key=lambda r: abs(phi[r[1] - 1] - phi[r[0]]))
    return a, b


def _classify(rec: Recording, declared: dict, ratio: float) -> str:
    if "test" in declared:
        return declared["test"]
    if rec.kind == "te_curve":
        return "te_curve"
    if rec.output_torque is not None:
        turns = (0.0 if rec.input_angle is None
                 else np.ptp(rec.input_angle) / abs(ratio) / (2.0 * math.pi))
        # a reversal turns the output by arcminutes: one that turns it by tens of degrees
        # while the input hardly turns is a TE recording with the input's unit wrong (the
        # ratio check then says so)
        if turns < 0.5 and rec.output_torque.min() < 0.0 < rec.output_torque.max() \
                and np.ptp(rec.output_angle) < REVERSAL_TRAVEL:
            return "torque_reversal"
    return "transmission_error"


def _need(rec: Recording, names: tuple, test: str) -> None:
    missing = [n for n in names if getattr(rec, n) is None]
    if missing:
        raise InputFileError(f"{rec.path}: a {test.replace('_', ' ')} recording needs "
                             f"{', '.join(missing)} (map columns with --column or --map)")


def analyse_recording(rec: Recording, declared: dict, reducer, *, points: int = A.DEFAULT_POINTS
                      ) -> FileResult:
    """The standard analyses of one recording (its test found from its columns, or given)."""
    # a ratio given (manifest, map, --ratio) is a magnitude: its sense is the parameter set's
    # (the cycloid drive's output turns against its input)
    given = declared.get("ratio") or rec.ratio
    expected = math.copysign(given, reducer.ratio) if given else reducer.ratio
    test = _classify(rec, declared, expected)
    measured: dict = {}
    if rec.oil_temperature is not None:
        measured["temperature_c"] = float(np.mean(rec.oil_temperature))
    result = FileResult(rec.path, test, measured, samples=rec.samples,
                        ratio_expected=None if test == "te_curve" else abs(expected))
    try:
        if test == "torque_reversal":
            _need(rec, ("time", "output_angle", "output_torque"), test)
            angle = rec.output_angle - (0.0 if rec.input_angle is None
                                        else rec.input_angle / expected)
            result.loop = A.reversal_curve(rec.output_torque, angle)
            # read the catalogue quantities here, so that a loop that cannot give them is an
            # error naming this file
            A.reversal_summary(*result.loop, reducer.rating.rated_torque)
            measured["torque_nm"] = float(np.max(np.abs(rec.output_torque)))
            return result
        if test == "te_curve":
            _need(rec, ("output_angle", "te", "direction"), test)
            result.directions = A.te_curve_directions(rec.output_angle, rec.te, rec.direction,
                                                      points)
        else:
            _need(rec, ("time", "input_angle", "output_angle"), test)
            phi = rec.input_angle / expected
            runs = A.input_runs(rec.input_angle, expected)
            a, b = _longest_run(phi, runs)
            _check_ratio(rec, result, a, b, expected)
            result.directions = A.te_directions(rec.input_angle, rec.output_angle, expected,
                                                points, runs)
            measured["speed_rpm"] = float(abs(phi[b - 1] - phi[a]) * abs(expected)
                                          / (rec.time[b - 1] - rec.time[a]) / _RPM)
            if rec.output_torque is not None:
                measured["torque_nm"] = float(np.mean(np.abs(rec.output_torque)))
            if rec.input_torque is not None and rec.output_torque is not None:
                result.efficiency = _efficiency(rec, runs, result.notes)
        if not result.directions:
            travel = _travel(rec, expected, test)
            raise InputFileError(f"{rec.path}: shorter than one output revolution (the longest "
                                 "run in one direction covers "
                                 f"{math.floor(travel * 1e4) / 1e4:g} of a revolution)")
    except CurveError as exc:
        raise InputFileError(f"{rec.path}: read as a {test.replace('_', ' ')} recording: "
                             f"{exc}") from None
    return result


def _travel(rec: Recording, ratio: float, test: str) -> float:
    position = rec.output_angle if test == "te_curve" else rec.input_angle / ratio
    a, b = _longest_run(position)
    return abs(position[b - 1] - position[a]) / (2.0 * math.pi)


def _ratio_over(rec: Recording, i: int, j: int) -> float | None:
    """Input travel over output travel from sample i to sample j (signed; None where the output
    stands still)."""
    turned = rec.output_angle[j] - rec.output_angle[i]
    return None if turned == 0.0 else (rec.input_angle[j] - rec.input_angle[i]) / turned


def _check_ratio(rec: Recording, result: FileResult, a: int, b: int, expected: float) -> None:
    """The ratio measured over the longest run (input over output travel, signed) against the
    expected one: an output that stands still or turns against the input, or a ratio more
    than RATIO_TOLERANCE off, is refused (encoders, units, counts); one more than RATIO_NOTE
    off is noted, since the TE then carries its trend."""
    measured = _ratio_over(rec, a, b - 1)
    if measured is None:
        turns = abs((rec.input_angle[b - 1] - rec.input_angle[a]) / expected) / (2.0 * math.pi)
        raise InputFileError(f"{rec.path}: the output angle stands still while the input "
                             f"turns {turns:.3g} output revolutions: check the output encoder "
                             "and its column")
    if measured / expected < 0:
        raise InputFileError(f"{rec.path}: the output turns against the ratio's sense "
                             f"(measured ratio {measured:.5g}, expected {expected:+g}): the "
                             "encoders count in opposite directions; negate one of the angle "
                             "columns in the file")
    result.ratio_measured = abs(measured)
    off = measured / expected - 1.0
    if abs(off) > RATIO_TOLERANCE:
        raise InputFileError(
            f"{rec.path}: the measured ratio {abs(measured):.5g} differs from "
            f"{abs(expected):g} by {100 * off:+.3g} % (more than {100 * RATIO_TOLERANCE:g} %): "
            "check the angle units and counts per revolution")
    # the trend from the run's middle 80 %: its start holds the lost motion taken up after a
    # reversal (a few arcmin over the run's revolution on the example recording)
    progress = np.abs(rec.input_angle[a:b] - rec.input_angle[a])
    middle = _ratio_over(rec, a + int(np.argmax(progress >= 0.1 * progress[-1])),
                         a + int(np.argmax(progress >= 0.9 * progress[-1])))
    trend = 0.0 if middle is None else middle / expected - 1.0
    if abs(trend) > RATIO_NOTE:
        result.notes.append(
            f"{rec.path.name}: the measured ratio {abs(expected) * (1.0 + trend):.6g} differs "
            f"from {abs(expected):g} by {100 * trend:+.3g} %: the TE carries a trend of about "
            f"{abs(trend) * 21600.0:.3g} arcmin per output revolution (give the bench "
            "reducer's exact ratio with --ratio, or check the encoders' counts)")


def _efficiency(rec: Recording, runs, notes: list) -> float | None:
    values = []
    for a, b, _ in runs:
        if b - a < 4:
            continue
        part = slice(a, b)
        values.append(A.run_efficiency(
            rec.time[part], rec.input_angle[part], rec.output_angle[part],
            rec.input_torque[part], rec.output_torque[part],
            None if rec.input_speed is None else rec.input_speed[part],
            None if rec.output_speed is None else rec.output_speed[part]))
    if not values:
        return None
    value = float(np.mean(values))
    if not math.isfinite(value):
        notes.append(f"{rec.path.name}: no efficiency: the input power is too small to divide "
                     "by (check the torque columns and their units)")
        return None
    if not 0.0 < value <= 1.0:
        notes.append(f"{rec.path.name}: the efficiency {value:.4g} from the torque columns is "
                     "outside 0 to 1: check their units, signs and which is input and which "
                     "output")
    return value


def _point_key(declared: dict) -> tuple:
    return tuple((k, round(declared[k], 6)) for k in ("speed_rpm", "torque_nm", "temperature_c")
                 if k in declared)


@renamed(points="positions")
def analyse_path(path: str | Path, reducer, column_map: ColumnMap | None = None, *,
                 positions: int = A.DEFAULT_POINTS) -> list[PointResult]:
    """Every recording of a file or folder, analysed and grouped into operating points, its
    TE at ``positions`` equally spaced output angles per revolution (``rvsim testrig
    --positions``; ``points``, its old name, is deprecated).

    A column that ``column_map`` maps must be in a single file; a folder's files may lack it
    (the oil temperature of some runs only), but not all of them, and a file whose analysis
    fails while it lacks a mapped column is reported as lacking it."""
    from ..parameters import check_reducer

    check_reducer(reducer)
    A.check_points(positions, "positions")
    column_map = column_map or ColumnMap()
    folder = Path(path).is_dir()
    groups: dict = {}
    seen: set = set()
    for file, declared in list_files(path):
        rec = read_recording(file, column_map, strict=not folder)
        seen.update(rec.columns)
        try:
            result = analyse_recording(rec, declared, reducer, points=positions)
        except InputFileError:
            missing = missing_mapped(column_map, rec.columns)
            if missing:               # the likelier cause: a mapped column this file lacks
                raise no_column_error(file, missing, rec.columns) from None
            raise
        key = _point_key(declared) or (("file", file.name),)
        point = {k: v for k, v in declared.items() if k in ("speed_rpm", "torque_nm",
                                                              "temperature_c")}
        for k, v in result.measured.items():
            point.setdefault(k, v)
        group = groups.setdefault(key, PointResult(point, []))
        group.files.append(result)
    nowhere = missing_mapped(column_map, seen)
    if nowhere:
        quantity, column = nowhere[0]
        raise InputFileError(f"{path}: no file has column '{column}' (mapped to {quantity})")
    return list(groups.values())


def check_model_ratio(point: PointResult, reducer) -> None:
    """A file analysed with a ratio (``--ratio``, map, manifest) that differs from the parameter
    set's by more than :data:`RATIO_TOLERANCE` cannot be compared with that model."""
    for f in point.files:
        if f.ratio_expected is None:
            continue
        off = f.ratio_expected / abs(reducer.ratio) - 1.0
        if abs(off) > RATIO_TOLERANCE:
            raise InputFileError(f"{f.path}: its ratio {f.ratio_expected:g} differs from the "
                                 f"parameter set's {abs(reducer.ratio):g} by {100 * off:+.1f} "
                                 "%: give the bench reducer's parameters with --params")
