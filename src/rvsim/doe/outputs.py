"""Files a finished study leaves in its folder: results.csv, analysis.json, main_effects.png."""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from .._files import atomic_write_text
from .._json import dumps
from ..analysis import analyze_table, range_analysis
from ..errors import InputFileError

__all__ = ["write_study_outputs"]


def write_study_outputs(folder: Path, results: pd.DataFrame, factors: list[str],
                        *, alpha: float = 0.1) -> dict:
    """results.csv, analysis.json and main_effects.png in ``folder``; returns the analysis."""
    atomic_write_text(folder / "results.csv", results.to_csv(index=False))
    ok = results[results["status"] == "ok"]
    try:
        analysis = analyze_table(ok, "te_mean_arcmin", factors, alpha=alpha)
        analysis["runs_ok"] = int(len(ok))
        analysis["runs_total"] = int(len(results))
    except InputFileError as exc:
        analysis = {"error": f"analysis not possible: {exc}", "runs_ok": int(len(ok)),
                    "runs_total": int(len(results))}
    atomic_write_text(folder / "analysis.json", dumps(analysis, indent=2))
    if "error" not in analysis:
        from ..plots import figure_to_png, main_effects_plot

        figure_to_png(main_effects_plot(range_analysis(ok, "te_mean_arcmin", factors),
                                        ylabel="mean TE [arcmin]"),
                      folder / "main_effects.png")
    return analysis


