"""Checking a design-of-experiments results table before analysing it."""

from __future__ import annotations

import pandas as pd

from ..errors import InputFileError

__all__ = ["check_design_table", "factor_columns", "read_table"]


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


def factor_columns(table: pd.DataFrame, response: str, factors=None) -> list[str]:
    """The factor columns: given, or every single-letter column A-Z other than the response."""
    if factors is not None:
        missing = [f for f in factors if f not in table.columns]
        if missing:
            raise InputFileError(f"factor column(s) {', '.join(missing)} not in the table")
        return list(factors)
    cols = [c for c in table.columns if len(str(c)) == 1 and str(c).isalpha() and c != response]
    if not cols:
        raise InputFileError("no factor columns found (expected single-letter columns A, B, ...)")
    return cols


def check_design_table(table: pd.DataFrame, response: str, factors: list[str]) -> pd.DataFrame:
    """Validate levels and response; return a clean copy (integer levels, float response).

    Errors name the column: a missing or non-numeric response, non-integer levels, fewer than
    two levels, or an unbalanced factor (levels not equally often).
    """
    if response not in table.columns:
        raise InputFileError(f"response column '{response}' not in the table (columns: "
                             f"{', '.join(map(str, table.columns))})")
    out = table.copy()
    y = pd.to_numeric(out[response], errors="coerce")
    if y.isna().any():
        bad = int(y.isna().idxmax())
        raise InputFileError(f"response column '{response}': row {bad + 1} is missing or "
                             f"not a number ('{table[response].iloc[bad]}')")
    out[response] = y.astype(float)
    for f in factors:
        levels = pd.to_numeric(out[f], errors="coerce")
        if levels.isna().any() or (levels != levels.round()).any():
            raise InputFileError(f"factor column '{f}': levels must be whole numbers 1, 2, 3, ...")
        levels = levels.astype(int)
        counts = levels.value_counts()
        if len(counts) < 2:
            raise InputFileError(f"factor column '{f}': needs at least two levels")
        if counts.nunique() != 1:
            raise InputFileError(f"factor column '{f}': unbalanced design (level counts "
                                 f"{dict(sorted(counts.items()))})")
        out[f] = levels
    if len(out) < sum(out[f].nunique() - 1 for f in factors) + 1:
        raise InputFileError("too few runs for a main-effects model of these factors")
    return out
