"""Bench recordings: read CSV or Parquet files into SI arrays (:func:`read_recording`).

A *recording* is a time series of encoder angles (input, output) with optional torques, speeds
and oil temperature; a *TE curve* is what many benches export instead: output position, TE
and direction.  Columns are found by their default names (:data:`DEFAULT_COLUMNS`) or by a
:class:`ColumnMap` (command line ``--column`` or a small TOML, docs/user_guide.md,
"Test-bench data"); values are turned into SI here and nowhere else.

Angles that an absolute encoder reports within one revolution (0-360 deg, or 0 to the counts per
revolution) are made continuous (:func:`unwrapped`).

Every problem with a file is an :class:`~rvsim.errors.InputFileError` whose message starts with
the file name: missing or misnamed columns, non-numeric values, NaN gaps, time that does not
increase.
"""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np

from .._files import read_toml
from ..errors import InputFileError
from ..parameters import plain_number

__all__ = ["Recording", "ColumnMap", "ColumnSpec", "read_recording", "read_column_map",
           "parse_column_option", "point_from_name", "unwrapped", "check_ratio",
           "missing_mapped", "no_column_error", "DEFAULT_COLUMNS", "QUANTITIES", "UNITS"]

#: canonical quantity -> (default column name, its unit)
DEFAULT_COLUMNS: dict[str, tuple[str, str]] = {
    "time": ("time_s", "s"),
    "input_angle": ("input_angle_deg", "deg"),
    "output_angle": ("output_angle_deg", "deg"),
    "input_torque": ("input_torque_nm", "N*m"),
    "output_torque": ("output_torque_nm", "N*m"),
    "input_speed": ("input_speed_rpm", "rpm"),
    "output_speed": ("output_speed_rpm", "rpm"),
    "oil_temperature": ("oil_temperature_c", "C"),
    # a ready-made TE curve: output position, TE, direction (+1 / -1 or forward / backward)
    "te": ("te_arcsec", "arcsec"),
    "direction": ("direction", "-"),
}
QUANTITIES = tuple(DEFAULT_COLUMNS)

_TURN = 2.0 * math.pi
#: unit -> (kind, factor to SI); "counts" needs counts per revolution
UNITS: dict[str, tuple[str, float]] = {
    "s": ("time", 1.0), "ms": ("time", 1e-3), "us": ("time", 1e-6),
    "deg": ("angle", math.pi / 180.0), "rad": ("angle", 1.0), "rev": ("angle", _TURN),
    "arcmin": ("angle", math.pi / 10800.0), "arcsec": ("angle", math.pi / 648000.0),
    "urad": ("angle", 1e-6), "counts": ("angle", float("nan")),
    "N*m": ("torque", 1.0), "Nm": ("torque", 1.0), "kN*m": ("torque", 1e3),
    "N*mm": ("torque", 1e-3),
    "rpm": ("speed", _TURN / 60.0), "rad/s": ("speed", 1.0), "deg/s": ("speed", math.pi / 180.0),
    "C": ("temperature", 1.0), "degC": ("temperature", 1.0),
    "-": ("direction", 1.0),
}
#: kind -> the largest magnitude in SI that any bench records (an hour at 10,000 rpm is 4e6
#: rad; of a time, its distance from the first: 30 years); a value beyond it is a unit or
#: export error, refused before it overflows an analysis
LIMITS: dict[str, float] = {"time": 1e9, "angle": 1e9, "torque": 1e9, "speed": 1e6,
                            "temperature": 1e4, "direction": 1.0}
_KIND = {"time": "time", "input_angle": "angle", "output_angle": "angle", "te": "angle",
         "input_torque": "torque", "output_torque": "torque", "input_speed": "speed",
         "output_speed": "speed", "oil_temperature": "temperature", "direction": "direction"}


@dataclasses.dataclass(frozen=True)
class ColumnSpec:
    """Where one quantity is in the file and in which unit."""

    column: str                     # header name, or a 1-based position for a header-less file
    unit: str
    counts_per_revolution: float | None = None

    def factor(self) -> float:
        if self.unit == "counts":
            return _TURN / self.counts_per_revolution
        return UNITS[self.unit][1]


@dataclasses.dataclass(frozen=True)
class ColumnMap:
    """Column names and units that differ from the defaults, and an optional ratio."""

    columns: dict = dataclasses.field(default_factory=dict)   # quantity -> ColumnSpec
    ratio: float | None = None
    source: str = "command line"

    def spec(self, quantity: str) -> ColumnSpec:
        if quantity in self.columns:
            return self.columns[quantity]
        name, unit = DEFAULT_COLUMNS[quantity]
        return ColumnSpec(name, unit)

    def merged(self, other: "ColumnMap") -> "ColumnMap":
        """This map with ``other``'s entries (and ratio, if it has one) taking precedence."""
        return ColumnMap({**self.columns, **other.columns},
                         other.ratio if other.ratio is not None else self.ratio,
                         other.source)


def _spec(quantity: str, column, unit: str | None, cpr, where: str) -> ColumnSpec:
    if quantity not in DEFAULT_COLUMNS:
        raise InputFileError(f"{where}: unknown quantity '{quantity}' (known: "
                             f"{', '.join(QUANTITIES)})")
    unit = unit or DEFAULT_COLUMNS[quantity][1]
    if unit not in UNITS:
        known = ", ".join(u for u, (k, _) in UNITS.items() if k == _KIND[quantity])
        raise InputFileError(f"{where}: unknown unit '{unit}' for {quantity} (known: {known})")
    if UNITS[unit][0] != _KIND[quantity]:
        raise InputFileError(f"{where}: unit '{unit}' is not a unit of {_KIND[quantity]} "
                             f"(for {quantity})")
    if unit == "counts":
        try:
            cpr = plain_number(cpr)
        except (TypeError, ValueError):
            need = "needs the counts per revolution" if cpr is None else \
                "needs the counts per revolution as a number"
            raise InputFileError(f"{where}: {quantity} in counts {need} (got {cpr!r})") \
                from None
        if not (math.isfinite(cpr) and cpr > 0):
            raise InputFileError(f"{where}: counts per revolution of {quantity} must be a "
                                 f"finite positive number (got {cpr:g})")
    elif cpr is not None:
        raise InputFileError(f"{where}: counts per revolution given for {quantity}, whose unit "
                             f"is '{unit}', not counts")
    column = str(column).strip()
    if not column:
        raise InputFileError(f"{where}: empty column name for {quantity}")
    return ColumnSpec(column, unit, cpr if unit == "counts" else None)


def parse_column_option(text: str) -> tuple[str, ColumnSpec]:
    """``QUANTITY=COLUMN[:UNIT[:COUNTS_PER_REV]]`` as given to ``--column``."""
    quantity, sep, rest = text.partition("=")
    if not sep or not rest.strip():
        raise InputFileError(f"--column {text}: expected QUANTITY=COLUMN[:UNIT[:COUNTS_PER_REV]]")
    parts = rest.split(":")
    if len(parts) > 3:
        raise InputFileError(f"--column {text}: expected QUANTITY=COLUMN[:UNIT[:COUNTS_PER_REV]]")
    column, unit, cpr = (parts + [None, None])[:3]
    quantity = quantity.strip()
    return quantity, _spec(quantity, column, unit or None, cpr, f"--column {text}")


def check_ratio(value, where: str) -> float:
    """A bench reducer's ratio from a file: a finite number above 1 (InputFileError)."""
    try:
        value = plain_number(value)
    except (TypeError, ValueError):
        raise InputFileError(f"{where}: ratio must be a number (got {value!r})") from None
    if not (math.isfinite(value) and value > 1):       # as --ratio: a negative one is a typo
        raise InputFileError(f"{where}: ratio must be a finite number above 1 (got {value:g})")
    return value


def read_column_map(path: str | Path) -> ColumnMap:
    """A column map from TOML: ``ratio = 81`` and one table per quantity, e.g.
    ``[input_angle]`` with ``column = "enc1"``, ``unit = "counts"``,
    ``counts_per_revolution = 4096``."""
    path = Path(path)
    data = read_toml(path, "column map TOML file")
    ratio = check_ratio(data.pop("ratio"), str(path)) if "ratio" in data else None
    columns = {}
    for quantity, table in data.items():
        if not isinstance(table, dict):
            raise InputFileError(f"{path}: '{quantity}' must be a table with column and unit "
                                 "(or the top-level 'ratio')")
        unknown = set(table) - {"column", "unit", "counts_per_revolution"}
        if unknown:
            raise InputFileError(f"{path}: [{quantity}] has unknown keys "
                                 f"{', '.join(sorted(unknown))}")
        columns[quantity] = _spec(quantity, table.get("column", DEFAULT_COLUMNS.get(
            quantity, ("",))[0]), table.get("unit"), table.get("counts_per_revolution"),
            str(path))
    return ColumnMap(columns, ratio, str(path))


@dataclasses.dataclass
class Recording:
    """One bench file in SI: angles [rad], torques [N*m], speeds [rad/s], time [s]; absent
    quantities are None.  ``kind`` is "series" (a time series of angles) or "te_curve"
    (output position [rad] in ``output_angle``, TE [rad] in ``te``, ``direction`` +-1)."""

    path: Path
    kind: str
    time: np.ndarray | None = None
    input_angle: np.ndarray | None = None
    output_angle: np.ndarray | None = None
    input_torque: np.ndarray | None = None
    output_torque: np.ndarray | None = None
    input_speed: np.ndarray | None = None
    output_speed: np.ndarray | None = None
    oil_temperature: np.ndarray | None = None
    te: np.ndarray | None = None
    direction: np.ndarray | None = None
    columns: tuple = ()              # the file's column names (header-less: "1", "2", ...)
    ratio: float | None = None       # from the column map, if it gives one

    @property
    def samples(self) -> int:
        return len(self.output_angle)


def _sniff(path: Path) -> tuple[str, str, bool, int]:
    """(delimiter, decimal mark, has header, comment lines before it) of a CSV file from its
    first lines (lines starting with '#' before the data are comments)."""
    try:
        with path.open("r", encoding="utf-8-sig", errors="replace") as handle:
            lines = [line.strip() for _, line in zip(range(20), handle)]
    except OSError as exc:
        raise InputFileError(f"{path}: cannot read ({exc.strerror or exc})") from None
    skip = 0
    while skip < len(lines) and (not lines[skip] or lines[skip].startswith("#")):
        skip += 1
    lines = lines[skip:]
    if not lines:
        raise InputFileError(f"{path}: the file is empty")
    first = lines[0]
    sep = ";" if first.count(";") > 0 else ("\t" if "\t" in first else ",")
    # the decimal mark from every data line read: a first row of whole numbers (a recording
    # zeroed at its start) has none
    data = lines[1:] or [first]
    decimal = "," if sep == ";" and any("," in line for line in data) else "."

    def numeric(field: str) -> bool:
        try:
            float(field.strip().replace(decimal, ".") if decimal == "," else field)
            return True
        except ValueError:
            return False

    header = not all(numeric(f) for f in first.split(sep))
    return sep, decimal, header, skip


def _read_table(path: Path):
    """A pandas DataFrame of the file; header-less CSV columns are named "1", "2", ..."""
    import pandas as pd

    suffix = path.suffix.lower()
    if not path.is_file():         # a folder, a pipe or a device was "file not found"
        raise InputFileError(f"{path}: " + ("is a folder, not a table" if path.is_dir() else
                                            "not a regular file" if path.exists() else
                                            "file not found"))
    if suffix in (".parquet", ".pq"):
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            raise InputFileError(f"{path}: reading Parquet needs pyarrow (pip install "
                                 "'rvsim[parquet]')") from None
        try:
            return pd.read_parquet(path)
        except Exception as exc:     # pyarrow raises its own types for a damaged file
            raise InputFileError(f"{path}: not a readable Parquet file ({exc})") from None
    if suffix not in (".csv", ".txt", ".tsv"):
        raise InputFileError(f"{path}: unknown file type '{suffix}' (use .csv or .parquet)")
    sep, decimal, header, skip = _sniff(path)
    try:
        frame = pd.read_csv(path, sep=sep, decimal=decimal, header=0 if header else None,
                            skiprows=skip, encoding="utf-8-sig")
    except (pd.errors.ParserError, UnicodeDecodeError, ValueError) as exc:
        raise InputFileError(f"{path}: not a readable CSV file "
                             f"({str(exc).splitlines()[0]})") from None
    if not header:
        frame.columns = [str(i + 1) for i in range(frame.shape[1])]
    else:
        frame.columns = [str(c).strip() for c in frame.columns]
        # trailing separators of a spreadsheet export (a,b,c,,): columns without header or
        # value, which pandas names "Unnamed: 3" (refused as unknown columns, hostile5)
        frame = frame.drop(columns=[c for c in frame.columns
                                    if c.startswith("Unnamed: ") and frame[c].isna().all()])
    return frame


def _column(frame, path: Path, quantity: str, spec: ColumnSpec):
    import pandas as pd

    if spec.column not in frame.columns:
        return None
    values = frame[spec.column]
    if quantity == "direction" and not pd.api.types.is_numeric_dtype(values):
        text = values.astype(str).str.strip().str.lower()
        mapped = text.map({"forward": 1.0, "fwd": 1.0, "+1": 1.0, "1": 1.0, "cw": 1.0,
                           "backward": -1.0, "bwd": -1.0, "reverse": -1.0, "-1": -1.0,
                           "ccw": -1.0})
        if mapped.isna().any():
            row = int(np.flatnonzero(mapped.isna().to_numpy())[0])
            raise InputFileError(f"{path}: column '{spec.column}' data row {row + 1}: "
                                 f"direction '{values.iloc[row]}' is not forward/backward or "
                                 "+1/-1")
        return mapped.to_numpy(dtype=float)
    numbers = pd.to_numeric(values, errors="coerce").to_numpy(dtype=float)
    bad = np.isnan(numbers)
    if bad.any():
        rows = np.flatnonzero(bad)
        text_bad = rows[values.iloc[rows].notna().to_numpy()]
        if text_bad.size:
            row = int(text_bad[0])
            raise InputFileError(f"{path}: column '{spec.column}' data row {row + 1}: "
                                 f"'{values.iloc[row]}' is not a number")
        # a NaN gap: name the first run of missing rows
        stop = rows[0]
        while stop + 1 < numbers.size and bad[stop + 1]:
            stop += 1
        span = (f"data row {rows[0] + 1}" if stop == rows[0]
                else f"data rows {rows[0] + 1}-{stop + 1}")
        raise InputFileError(f"{path}: column '{spec.column}' has a NaN gap at {span} "
                             f"({rows.size} missing values in all)")
    if not np.all(np.isfinite(numbers)):
        row = int(np.flatnonzero(~np.isfinite(numbers))[0])
        raise InputFileError(f"{path}: column '{spec.column}' data row {row + 1} is infinite")
    if quantity == "direction":
        if not np.all(np.isin(numbers, (1.0, -1.0))):
            raise InputFileError(f"{path}: column '{spec.column}': direction must be +1 or -1")
        return numbers
    numbers = numbers * spec.factor()
    limit = LIMITS[_KIND[quantity]]
    # a time may be a logger's clock (Unix time, 1.8e9 s): only its span counts
    huge = np.flatnonzero(~(np.abs(numbers - (numbers[0] if quantity == "time" else 0.0))
                            <= limit))
    if huge.size:
        row = int(huge[0])
        raise InputFileError(f"{path}: column '{spec.column}' data row {row + 1}: "
                             f"'{values.iloc[row]}' {spec.unit} is beyond any bench's "
                             f"{quantity.replace('_', ' ')} ({limit:g} in SI units): check the "
                             "unit")
    return numbers


def _headerless_map(frame, column_map: ColumnMap) -> ColumnMap:
    """Default columns of a header-less file: time, input angle, output angle, input torque,
    output torque, oil temperature, in that order and the default units (mapped ones win)."""
    order = ("time", "input_angle", "output_angle", "input_torque", "output_torque",
             "oil_temperature")
    columns = {q: ColumnSpec(str(i + 1), DEFAULT_COLUMNS[q][1])
               for i, q in enumerate(order[:frame.shape[1]])}
    return ColumnMap(columns, column_map.ratio, column_map.source).merged(column_map)


def missing_mapped(column_map: ColumnMap, columns) -> list[tuple[str, str]]:
    """(quantity, column) of the columns mapped by ``column_map`` that ``columns`` lacks."""
    return [(q, spec.column) for q, spec in column_map.columns.items()
            if spec.column not in columns]


def no_column_error(path: Path, missing: list[tuple[str, str]], columns) -> InputFileError:
    quantity, column = missing[0]
    found = ", ".join(f"'{c}'" for c in list(columns)[:12])
    return InputFileError(f"{path}: no column '{column}' (mapped to {quantity}); the file has "
                          f"{found} (map columns with --column or --map)")


def read_recording(path: str | Path, column_map: ColumnMap | None = None, *,
                   strict: bool = True) -> Recording:
    """The bench file at ``path`` in SI (see the module docstring).  ``strict``: a column
    that ``column_map`` maps must be in the file (a folder's files may lack some, see
    :func:`rvsim.testrig.bench.analyse_path`)."""
    from ..errors import check_type

    check_type(column_map, (ColumnMap, type(None)), "column_map", "a ColumnMap "
               "(rvsim.testrig.recording.ColumnMap, read_column_map(path)) or None")
    path = Path(path)
    column_map = column_map or ColumnMap()
    frame = _read_table(path)
    if frame.shape[0] == 0:
        raise InputFileError(f"{path}: the file has a header but no data rows")
    headerless = all(c.isdigit() for c in frame.columns)
    if headerless:
        column_map = _headerless_map(frame, column_map)
    missing = missing_mapped(column_map, frame.columns)
    if strict and missing:                           # a mapped column must be there
        raise no_column_error(path, missing, frame.columns)
    values = {q: _column(frame, path, q, column_map.spec(q)) for q in QUANTITIES}
    has = {q for q, v in values.items() if v is not None}
    if "te" in has:
        kind = "te_curve"
        required = ("output_angle", "te")
    else:
        kind = "series"
        required = ("time", "output_angle")
    missing = [q for q in required if q not in has]
    if kind == "series" and "input_angle" not in has and "output_torque" not in has:
        missing.append("input_angle")
    if missing:
        wanted = ", ".join(f"'{column_map.spec(q).column}' ({q})" for q in missing)
        found = ", ".join(f"'{c}'" for c in frame.columns[:12])
        raise InputFileError(f"{path}: missing column {wanted}; the file has {found} "
                             "(map columns with --column or --map)")
    if frame.shape[0] < 4:
        raise InputFileError(f"{path}: only {frame.shape[0]} data rows")
    if kind == "series":
        steps = np.diff(values["time"])
        if not np.all(steps > 0):
            row = int(np.flatnonzero(~(steps > 0))[0]) + 2
            raise InputFileError(f"{path}: time does not increase at data row {row} "
                                 f"({values['time'][row - 2]:g} s then "
                                 f"{values['time'][row - 1]:g} s)")
        for q in ("input_angle", "output_angle"):
            if values[q] is not None:
                values[q] = unwrapped(values[q])
    return Recording(path=path, kind=kind, ratio=column_map.ratio,
                     columns=tuple(frame.columns), **{q: values[q] for q in QUANTITIES})


def unwrapped(angle: np.ndarray) -> np.ndarray:
    """An angle [rad] made continuous if it is an absolute encoder's reading within one
    revolution (all values within one turn, and steps of more than half a turn between
    samples, which no sampled rotation makes): the turns are counted (numpy.unwrap).  Any
    other angle is returned unchanged."""
    if angle.size < 2 or np.ptp(angle) > _TURN * (1.0 + 1e-9):
        return angle
    if not np.any(np.abs(np.diff(angle)) > 0.5 * _TURN):
        return angle
    return np.unwrap(angle, period=_TURN)


_POINT_PATTERN = re.compile(r"(?<![A-Za-z])([-+]?\d+(?:[.p]\d+)?)\s*(rpm|nm|degc|c)(?![A-Za-z])",
                            re.IGNORECASE)


def point_from_name(name: str) -> dict:
    """Operating point in a file name, e.g. ``fwd_15rpm_200Nm_40C.csv`` -> speed 15 rpm,
    torque 200 N*m, temperature 40 C ('p' may stand for the decimal point: 12p5Nm)."""
    found = {}
    keys = {"rpm": "speed_rpm", "nm": "torque_nm", "c": "temperature_c", "degc": "temperature_c"}
    for number, unit in _POINT_PATTERN.findall(Path(name).stem):
        found.setdefault(keys[unit.lower()], float(number.replace("p", ".")))
    return found
