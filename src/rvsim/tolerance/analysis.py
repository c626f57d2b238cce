"""``rvsim tolerance``: Monte Carlo (and Sobol) of a tolerance study into a folder.

The folder holds the study runner's store (results.sqlite: resumable, one row per reducer),
study.json, results.csv (one row per Monte Carlo reducer), summary.json and report.html.
"""

from __future__ import annotations

import json
from pathlib import Path

from .._display import Headline, draw, number, without_status
from ..errors import InputFileError, check_type
from .montecarlo import (collect, study_torque, monte_carlo_units, run_samples, summarise,
                         write_json, write_results_csv)
from .sensitivity import check_base, check_groups, sobol_count, sobol_indices, sobol_units
from .spec import ToleranceStudy, check_samples

__all__ = ["tolerance_analysis", "ToleranceSummary"]


class ToleranceSummary(Headline, dict):
    """What :func:`tolerance_analysis` returns: the dict of summary.json (its keys as before),
    shown as the report's opening rows (:func:`rvsim.analysis.headline.tolerance_rows`);
    ``values`` holds each metric's value per Monte Carlo reducer (NaN where none),
    ``to_frame()`` them as a DataFrame, ``plot(metric=...)`` one metric's distribution."""

    def __init__(self, summary: dict, values: dict):
        super().__init__(summary)
        self.values = values

    def headline(self) -> tuple[str, list[tuple]]:
        from ..analysis.headline import tolerance_rows

        rows = without_status(tolerance_rows(self))
        mean = self["metrics"].get("te_mean_arcmin")     # the paper's index, not in the rows
        if mean:
            rows.insert(1, ("mean TE p5 / p50 / p95", " / ".join(
                number(mean.get(k)) for k in ("p5", "p50", "p95")) + " arcmin"))
        return (f"Tolerance study {self['study']}: {self['samples']} reducers, {self['ok']} "
                f"analysed, {self['binds']} bind, {self['failed']} failed", rows)

    def to_frame(self):
        """One row per Monte Carlo reducer, one column per metric (unit-suffixed names)."""
        import pandas as pd

        return pd.DataFrame(self.values)

    def plot(self, ax=None, *, metric: str = "ate_arcmin"):
        """Histogram and cumulative distribution of ``metric`` with p5, p50 and p95
        (:func:`rvsim.tolerance.report.distribution_figure`); returns the first panel's
        Axes."""
        from .report import distribution_figure

        if metric not in self.values:
            from ..errors import ParameterError

            raise ParameterError("metric", f"not a metric of this study (it has "
                                 f"{', '.join(self.values)})")
        return draw(distribution_figure, ax, metric, self.values[metric],
                    self["metrics"][metric], panels=True)


def tolerance_analysis(study: ToleranceStudy, folder: str | Path, *, samples: int | None = None,
                       sobol: int = 0, workers: int | None = None,
                       scheduler: str | None = None, progress: bool = False,
                       report: bool = True) -> dict:
    """Run the study's Monte Carlo (``samples`` reducers, default the study's) and, with
    ``sobol`` > 0, the Sobol design of base size ``sobol``; write the folder's files and
    return the summary."""
    from .._files import atomic_write_text
    from ..doe.folder import check_same_study, lock_folder
    from .._stopping import stop_signals
    from ..doe.runner import check_scheduler
    from ..doe.store import ResultStore

    check_type(study, ToleranceStudy, "study", "a tolerance study "
               "(rvsim.load_tolerance_study(path), rvsim.BUILT_IN_TOLERANCE_STUDIES[name]())")
    folder = Path(folder)
    n = check_samples(study.samples if samples is None else samples)
    if sobol:
        check_base(sobol)
        check_groups(study)
    if folder.exists() and not folder.is_dir():
        raise InputFileError(f"{folder}: exists and is not a folder")
    if (folder / "allocation.json").exists():  # its report.html would be replaced
        raise InputFileError(f"{folder}: holds a tolerance allocation (allocation.json), whose "
                             "report.html this study would replace: give another --out folder")
    if scheduler:
        check_scheduler(scheduler)
    study.nominal                                     # validated before anything is written
    from .allocation import cost_table

    cost_table(study)                                 # as `allocate` reads the same file
    definition = study.definition()
    designs = {"monte-carlo": (n, lambda: monte_carlo_units(study, n))}
    if sobol:
        designs["sobol"] = (sobol_count(study, sobol), lambda: iter(sobol_units(study, sobol)))
    folder.mkdir(parents=True, exist_ok=True)
    with lock_folder(folder), stop_signals():
        store = ResultStore(folder)
        try:
            check_same_study(folder, definition, bool(store.finished()))
            atomic_write_text(folder / "study.json", json.dumps(definition, indent=2,
                                                                default=str))
            keys = run_samples(study, folder, designs, workers=workers, scheduler=scheduler,
                               progress=progress, store=store)
            status, values, errors = collect(store, keys["monte-carlo"])
            summary = {"study": study.name, "reducer": study.base.name,
                       **study_torque(study),
                       "positions": study.positions, "seed": study.seed,
                       "tolerances": definition["tolerances"], **summarise(status, values, errors)}
            write_results_csv(folder / "results.csv", status, values, keys["monte-carlo"],
                              errors)
            if sobol:
                s_status, s_values, _ = collect(store, keys["sobol"])
                summary.update(sobol_indices(study, s_values, s_status))
        finally:
            store.close()
        write_json(folder / "summary.json", summary)
        if report:
            from .report import write_tolerance_report

            write_tolerance_report(folder, summary, values, status)
    return ToleranceSummary(summary, values)
