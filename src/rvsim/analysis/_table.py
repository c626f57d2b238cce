"""Checking a design-of-experiments results table before analysing it."""

from __future__ import annotations

import pandas as pd

from ..errors import InputFileError

__all__ = ["check_design_table", "factor_columns"]


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
    if len(out) <= sum(out[f].nunique() - 1 for f in factors) + 1:
        raise InputFileError("too few runs for a main-effects model of these factors")
    return out
