"""A study's results in Python (issue 34 item 5): :func:`run_study` runs a study into its
folder (:func:`rvsim.doe.runner.run`, resumable) and returns a :class:`StudyResult`, the
results table with its analysis, shown as its answer."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from .._display import Headline, check_axes
from ..errors import InputFileError, check_type
from .study import Study

__all__ = ["StudyResult", "run_study"]


@dataclasses.dataclass(repr=False)
class StudyResult(Headline):
    """The results table of ``study`` (one row per run, ``status`` ok or why not) and its
    ``folder`` (the store: a second :func:`run_study` reuses every finished run).  Shown as
    the analysis' answer; ``analysis()`` the full analysis, ``plot()`` the main effects."""

    study: Study
    folder: Path
    table: object                   # pandas.DataFrame

    def to_frame(self):
        """The results table, as results.csv holds it, except that a sampling design's
        factor columns (values in the parameter's unit) carry that unit ("H" -> "H_mm");
        a level design's hold level numbers (1, 2, 3: no unit)."""
        if not self.study.is_sampling:
            return self.table
        from ..analysis import suffix_of_unit
        from ..parameters._io import SPECS

        return self.table.rename(columns={
            f.label: f.label + suffix_of_unit(SPECS[f.parameter].unit)
            for f in self.study.factors if f.parameter in SPECS})

    def analysis(self, response: str | None = None, alpha: float = 0.1):
        """Range analysis, ANOVA and S/N ratios of ``response`` over the runs that finished
        ``ok`` (:func:`rvsim.analysis.analyze_table`; None: the study's default column)."""
        from ..analysis import analyze_table
        from ..analysis._table import drop_failed_runs

        ok, _ = drop_failed_runs(self.table)
        return analyze_table(ok, response, [f.label for f in self.study.factors], alpha=alpha)

    def headline(self) -> tuple[str, list[tuple]]:
        """Runs finished, and the analysis' answer (or why there is none)."""
        total = len(self.table)
        ok = int((self.table["status"] == "ok").sum()) if "status" in self.table else total
        title = (f"Study {self.study.name}: {ok} of {total} runs ok ({self.study.engine} "
                 f"engine, {self.study.design}), in {self.folder}")
        try:
            analysis = self.analysis()
        except InputFileError as exc:
            return title, [("analysis", f"not possible: {exc}")]
        return title, [("response", analysis.response)] + analysis.headline()[1]

    def plot(self, ax=None):
        """Main effects of the default response (:meth:`rvsim.analysis.StudyAnalysis.plot`);
        returns the Axes."""
        check_axes(ax)                      # before the analysis is computed
        return self.analysis().plot(ax)


def run_study(study: Study, folder: str | Path, *, workers: int | None = None,
              scheduler: str | None = None, progress: bool = True) -> StudyResult:
    """Run ``study`` into ``folder`` (:func:`rvsim.doe.runner.run`: local workers, or the
    Dask ``scheduler``; a folder that holds finished runs of the same study resumes) and
    return its :class:`StudyResult`.  The files ``rvsim study`` adds (results.csv,
    analysis.json, the report) are the command's."""
    from .runner import run

    check_type(study, Study, "study", "a study (rvsim.load_study(path), "
               "rvsim.BUILT_IN_STUDIES[name]())")
    table = run(study, folder, workers=workers, scheduler=scheduler, progress=progress)
    return StudyResult(study, Path(folder), table)
