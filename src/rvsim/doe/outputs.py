"""Files a finished study leaves in its folder: results.csv, analysis.json, main_effects.png."""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from .._files import atomic_write_text
from .._json import dumps
from ..analysis import analyze_table, range_analysis
from ..errors import InputFileError

__all__ = ["write_study_outputs", "prepare_outputs"]


def prepare_outputs() -> None:
    """Import what :func:`write_study_outputs` and the study report use (statsmodels and
    patsy, matplotlib; about 0.8 s): the study runner calls it when its last runs leave a core
    free, so that the time after the runs is the analysis and the figures alone."""
    import statsmodels.regression.linear_model  # noqa: F401
    import patsy  # noqa: F401

    from .. import html  # noqa: F401     the report's building blocks (a layer below doe)
    from ..analysis import anova, interactions, range_analysis  # noqa: F401
    from ..plots import pyplot

    pyplot()


def write_study_outputs(folder: Path, results: pd.DataFrame, factors: list[str],
                        *, alpha: float = 0.1, response: str = "te_mean_arcmin",
                        also: tuple = (), sn: str | None = None) -> dict:
    """results.csv, analysis.json and main_effects.png in ``folder``; returns the analysis
    of ``response`` (default the paper's mean TE; analysis.json names it).  ``also``: further
    columns analysed alike into ``analysis["also"][column]`` (a robust study's mean beside
    its S/N ratio, issue 33).  ``sn``: the S/N kind of the response table (None: the
    response's own sense; :func:`rvsim.analysis.analyze_table`).

    Everything is computed before the first file is written; each file is written atomically.
    """
    folder = Path(folder)
    from ..analysis._table import drop_failed_runs
    from ..analysis.indices import response_bench_note, response_label

    ok, _ = drop_failed_runs(results)
    figure = None
    try:
        analysis = analyze_table(ok, response, factors, alpha=alpha, sn=sn)
        analysis["runs_ok"] = int(len(ok))
        analysis["runs_total"] = int(len(results))
    except InputFileError as exc:
        analysis = {"error": f"analysis not possible: {exc}", "runs_ok": int(len(ok)),
                    "runs_total": int(len(results))}
    else:
        from ..plots import main_effects_plot

        figure = main_effects_plot(range_analysis(ok, response, factors),
                                   ylabel=response_label(response))
    analysis["response"] = response
    analysis["response_note"] = response_bench_note(response)
    interactions = _interactions(ok, factors, analysis, response)
    for column in also:
        try:
            other = analyze_table(ok, column, factors, alpha=alpha)
        except InputFileError as exc:
            other = {"error": f"analysis not possible: {exc}"}
        other["response_note"] = response_bench_note(column)
        analysis.setdefault("also", {})[column] = other
    try:
        atomic_write_text(folder / "results.csv", results.to_csv(index=False))
        atomic_write_text(folder / "analysis.json", dumps(analysis, indent=2))
        if figure is not None:
            from ..plots import figure_to_png

            figure_to_png(figure, folder / "main_effects.png")
        else:  # a figure of an earlier analysis would contradict analysis.json
            (folder / "main_effects.png").unlink(missing_ok=True)
        if interactions is not None:
            from ..plots import figure_to_png

            figure_to_png(interactions, folder / "interactions.png")
        else:
            (folder / "interactions.png").unlink(missing_ok=True)
    except OSError as exc:
        raise InputFileError(f"{folder}: cannot write the study outputs "
                             f"({exc.strerror or exc})") from None
    return analysis


def _interactions(ok: pd.DataFrame, factors: list[str], analysis: dict,
                  response: str = "te_mean_arcmin"):
    """ANOVA with two-factor interactions into ``analysis["interactions"]`` when the design
    leaves the degrees of freedom (issue 11); returns the interaction plots of the strongest
    pairs (None when it does not)."""
    from ..analysis.interactions import interaction_anova, interaction_degrees, \
        interaction_plots

    from ..analysis.indices import response_label

    if response not in ok.columns or len(factors) < 2:
        return None
    need, have = interaction_degrees(ok, factors)
    if need >= have:
        return None
    try:
        table = interaction_anova(ok, response, factors)
    except InputFileError:          # the finished runs alias some terms (a stopped study)
        return None
    analysis["interactions"] = {name: {k: (None if v != v else float(v)) for k, v in row.items()}
                                for name, row in table.iterrows()}
    pairs = [tuple(name.split(" x ")) for name in table.index if " x " in name][:6]
    return interaction_plots(ok, response, pairs, ylabel=response_label(response))
