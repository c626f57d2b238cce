"""Checking a design-of-experiments results table before analysing it."""

from __future__ import annotations

import pandas as pd

from ..errors import InputFileError

__all__ = ["check_design_table", "drop_failed_runs", "factor_columns", "read_table",
           "RESULT_COLUMNS", "is_coded",
           "is_balanced", "UNBALANCED_NOTE", "MAX_LEVEL"]

#: largest response magnitude analysed: sums of squares of larger values overflow doubles
_LARGEST_RESPONSE = 1e150

#: note attached to analyses of tables whose levels do not occur equally often
UNBALANCED_NOTE = ("unbalanced table (levels not equally often, e.g. a failed run): level "
                   "means are plain averages and the ANOVA uses the regression fit's adjusted "
                   "sums of squares (each factor after all others: Type II = Type III for "
                   "main effects)")


def read_table(path) -> pd.DataFrame:
    """Read a CSV results table; a free-text last column may contain unquoted commas."""
    import csv
    import io
    from pathlib import Path

    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputFileError(f"{path}: file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(f"{path}: cannot read ({exc})") from None
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
    if not lines:
        raise InputFileError(f"{path}: empty table")
    header = next(csv.reader([lines[0]]))
    repeated = sorted({h for h in header if header.count(h) > 1})
    if repeated:
        raise InputFileError(f"{path}: column(s) {', '.join(repeated)} appear more than once")
    rows = []
    for number, line in enumerate(lines[1:], start=2):
        fields = next(csv.reader([line]))
        if len(fields) > len(header):  # unquoted commas in the last (text) column
            fields = fields[:len(header) - 1] + [",".join(fields[len(header) - 1:])]
        if len(fields) < len(header):
            fields += [""] * (len(header) - len(fields))
        rows.append(fields)
    frame = pd.read_csv(io.StringIO(""), names=header) if not rows else pd.DataFrame(
        rows, columns=header)
    for name in frame.columns:
        converted = pd.to_numeric(frame[name].replace("", float("nan")), errors="coerce")
        if converted.notna().sum() == (frame[name] != "").sum():
            frame[name] = converted
    return frame


#: columns of a study's results.csv besides its factors: a factor label must not be one of
#: them (doe.study refuses it), and `rvsim analyze` does not take them for factors.  Every
#: metric column starts with ``te_`` or is listed here (tests/integration/test_study_engines.py
#: checks the list against real runs of each engine).
RESULT_COLUMNS = frozenset({
    "run", "status", "error", "key", "reducer", "steps", "wall_s", "ate_arcmin", "ate_note",
    # the dynamic engine
    "sim_time_s", "speed_ratio", "energy_residual", "max_pin_force_n", "guard_substep_checks",
    "guard_substep_checks_steady", "guard_peak_omega_dt", "implicit_factorisations",
    "implicit_alerts", "implicit_fallbacks",
    # the quasi-static engine and its torque reversal
    "max_contact_stress_mpa", "pins_in_contact_max", "pins_in_contact_min", "positions",
    "torque_nm", "torsional_stiffness_nm_per_arcmin", "backlash_arcmin",
    "hysteresis_loss_arcmin", "lost_motion_arcmin", "points", "rated_torque_nm",
    "torsional_rigidity_nm_per_arcmin",
    # keys of ltca's summary that are no run metric (the reducer's limit, a verdict's text):
    # left out of a study's rows, reserved as labels all the same
    "static_contact_stress_mpa", "contact_stress_verdict"})


def is_coded(values: pd.Series) -> bool:
    """A column of level codes 1..k (k >= 2), each code on two runs or more: a run-order or
    run-number column (each code once: Minitab's StdOrder, RunOrder) is not a factor."""
    numbers = pd.to_numeric(values, errors="coerce")
    if not numbers.notna().all():
        return False
    counts = numbers.value_counts()
    return (len(counts) >= 2 and set(counts.index) == set(range(1, len(counts) + 1))
            and counts.min() >= 2)


def factor_columns(table: pd.DataFrame, response: str, factors=None) -> list[str]:
    """The factor columns: given, or every single-letter column A-Z other than the response and
    every other column of level codes (:func:`is_coded`) that is not one of a study's result
    columns (a study's factor may have any label)."""
    if factors is not None:
        repeated = sorted({f for f in factors if list(factors).count(f) > 1})
        if repeated:
            raise InputFileError(f"factor column(s) {', '.join(repeated)} given twice")
        if response in factors:
            raise InputFileError(f"'{response}' is the response, not a factor column")
        missing = [f for f in factors if f not in table.columns]
        if missing:
            raise InputFileError(f"factor column(s) {', '.join(missing)} not in the table")
        return list(factors)
    def is_factor(column) -> bool:
        name = str(column)
        if column == response or name.lower() in RESULT_COLUMNS or name.lower().startswith("te_"):
            return False
        if len(name) == 1 and name.isalpha():
            return True
        return is_coded(table[column])

    cols = [c for c in table.columns if is_factor(c)]
    if not cols:
        raise InputFileError("no factor columns found (expected single-letter columns A, B, "
                             "..., or columns of level codes 1, 2, ...; name them with "
                             "--factors)")
    return cols


def is_balanced(data: pd.DataFrame, factors: list[str]) -> bool:
    """True when every factor's levels occur equally often."""
    return all(data[f].value_counts().nunique() == 1 for f in factors)


#: largest level number a design table may use (level numbers index a factor's levels)
MAX_LEVEL = 1000


def drop_failed_runs(table: pd.DataFrame) -> tuple[pd.DataFrame, int]:
    """The rows of a study's results table whose run finished ``ok`` (a table without a
    ``status`` column is returned whole), and how many rows were left out."""
    if "status" not in table.columns:
        return table, 0
    ok = table["status"].astype(str).str.strip() == "ok"
    return table[ok].reset_index(drop=True), int((~ok).sum())


def check_design_table(table: pd.DataFrame, response: str, factors: list[str]) -> pd.DataFrame:
    """Validate levels and response; return a clean copy (integer levels, float response).

    Errors name the column: a missing, non-numeric, infinite or all-zero response, non-integer
    levels, fewer than two levels, or two factor columns that vary together (confounded).
    Unbalanced tables pass (see :func:`is_balanced`).
    """
    import numpy as np

    if response not in table.columns:
        raise InputFileError(f"response column '{response}' not in the table (columns: "
                             f"{', '.join(map(str, table.columns))})")
    if isinstance(table[response], pd.DataFrame):
        raise InputFileError(f"response column '{response}' appears more than once")
    if not len(table):
        raise InputFileError("the table has no rows (no finished run to analyse)")
    out = table.copy()
    y = pd.to_numeric(out[response], errors="coerce")
    if y.isna().any():
        bad = int(np.flatnonzero(y.isna().to_numpy())[0])
        raise InputFileError(f"response column '{response}': row {bad + 1} is missing or "
                             f"not a number ('{table[response].iloc[bad]}')")
    if not np.isfinite(y.to_numpy(dtype=float)).all():
        bad = int(np.flatnonzero(~np.isfinite(y.to_numpy(dtype=float)))[0])
        raise InputFileError(f"response column '{response}': row {bad + 1} is not finite "
                             f"({y.iloc[bad]})")
    if (y.abs() > _LARGEST_RESPONSE).any():
        bad = int(np.flatnonzero((y.abs() > _LARGEST_RESPONSE).to_numpy())[0])
        raise InputFileError(f"response column '{response}': row {bad + 1} ({y.iloc[bad]:g}) "
                             f"is beyond +-{_LARGEST_RESPONSE:g} (its square would overflow)")
    if (y == 0).all():
        raise InputFileError(f"response column '{response}': every value is zero (nothing to "
                             "analyse; the S/N ratio is undefined)")
    out[response] = y.astype(float)
    for f in factors:
        if isinstance(out[f], pd.DataFrame):
            raise InputFileError(f"factor column '{f}' appears more than once")
        levels = pd.to_numeric(out[f], errors="coerce")
        if levels.isna().any() or (levels != levels.round()).any() or (levels < 1).any() \
                or (levels > MAX_LEVEL).any():
            raise InputFileError(f"factor column '{f}': levels must be whole numbers 1, 2, 3, "
                                 f"... (at most {MAX_LEVEL})")
        levels = levels.astype(int)
        if levels.nunique() < 2:
            raise InputFileError(f"factor column '{f}': needs at least two levels")
        out[f] = levels
    codes = {f: tuple(pd.factorize(out[f])[0]) for f in factors}
    seen: dict[tuple, str] = {}
    for f in factors:
        if codes[f] in seen:
            raise InputFileError(f"factor columns '{seen[codes[f]]}' and '{f}' vary together "
                                 "(confounded: their effects cannot be separated)")
        seen[codes[f]] = f
    if len(out) < sum(out[f].nunique() - 1 for f in factors) + 1:
        raise InputFileError("too few runs for a main-effects model of these factors")
    return out
