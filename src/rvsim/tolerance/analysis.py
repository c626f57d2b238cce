"""``rvsim tolerance``: Monte Carlo (and Sobol) of a tolerance study into a folder.

The folder holds the study runner's store (results.sqlite: resumable, one row per reducer),
study.json, results.csv (one row per Monte Carlo reducer), summary.json and report.html.
"""

from __future__ import annotations

import json
from pathlib import Path

from ..errors import InputFileError
from .montecarlo import (collect, study_torque, monte_carlo_units, run_samples, summarise,
                         write_json, write_results_csv)
from .sensitivity import check_base, check_groups, sobol_count, sobol_indices, sobol_units
from .spec import ToleranceStudy, check_samples

__all__ = ["tolerance_analysis"]


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
    return summary
