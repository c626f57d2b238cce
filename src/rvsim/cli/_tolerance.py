"""``rvsim tolerance`` (Monte Carlo and Sobol of a tolerance study) and ``rvsim allocate``."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import InputFileError
from ._common import (add_command, check_load, check_output_folder, path_text, positive_int,
                      print_json, reducer_of, scheduler_address, stopped_line, whole)

__all__ = ["register", "load_any_tolerance_study"]


def load_any_tolerance_study(name: str, params: str | None = None):
    """A built-in tolerance study's name or a tolerance study .toml file; ``params`` (a reducer
    TOML file or a built-in set's name, --params) replaces the study's own reducer, the
    study's [set] values and tolerances applied to it."""
    import dataclasses

    from ..tolerance.spec import BUILT_IN_TOLERANCE_STUDIES, load_tolerance_study

    if name in BUILT_IN_TOLERANCE_STUDIES and not Path(name).exists():
        study = BUILT_IN_TOLERANCE_STUDIES[name]()
    elif Path(name).suffix == ".toml":
        study = load_tolerance_study(name)
    else:
        raise InputFileError(f"unknown tolerance study '{name}' (built in: "
                         f"{', '.join(BUILT_IN_TOLERANCE_STUDIES)}; or a .toml file)")
    if params is not None:
        study = dataclasses.replace(study, base=reducer_of(params), params=params)
        study.nominal     # the nominal reducer must be valid
    check_load(study.nominal, *study.largest_load())    # the largest load drawn
    return study


def run_tolerance_command(study, args) -> int:
    """Shared by ``rvsim tolerance`` and ``rvsim study`` given a tolerance study."""
    from ..tolerance.analysis import tolerance_analysis
    from ..tolerance.montecarlo import failure_line, share_text, torque_text

    check_output_folder(args.out, "--out")
    folder = Path(args.out)
    progress = not getattr(args, "no_progress", False) and sys.stderr.isatty()
    try:
        summary = tolerance_analysis(study, folder, samples=getattr(args, "samples", None),
                                     sobol=getattr(args, "sobol", 0) or 0,
                                     workers=args.workers, scheduler=args.scheduler,
                                     progress=progress,
                                     report=not getattr(args, "no_report", False))
    except KeyboardInterrupt as exc:            # Ctrl-C, or SIGTERM / SIGHUP (Terminated)
        line, code = stopped_line(exc, folder, "reducers")
        print(line, file=sys.stderr)
        return code
    failed = failure_line(summary)
    if summary["samples"] and summary["failed"] == summary["samples"]:
        # nothing assembled, bound or solved: a failure of the study, not a result
        if args.json:
            print_json({"status": "all_failed", "folder": str(folder),
                        "samples": summary["samples"], "failures": summary["failures"]})
        print(f"rvsim: error: tolerance: all {summary['samples']} reducers failed: {failed}; "
              f"their rows are in {folder}/results.csv", file=sys.stderr)
        return 1
    if args.json:
        print_json({"folder": str(folder), **{k: v for k, v in summary.items()
                                              if k != "tolerances"}})
        return 0
    print(f"{study.name}: {summary['samples']} reducers, {summary['ok']} analysed, "
          f"{summary['binds']} bind on assembly ({share_text(summary['binding_share'])}), "
          f"{summary['failed']} failed -> {folder}/summary.json, results.csv, report.html")
    if summary.get("torque_drawn"):
        print(f"  output torque {torque_text(summary)}")
    if failed:
        print(f"rvsim: note: failed reducers: {failed} (each one's reason: results.csv)",
              file=sys.stderr)
    for name, m in summary["metrics"].items():
        if m["n"]:
            print(f"  {name}: mean {m['mean']:.4g}, p5 {m['p5']:.4g}, p50 {m['p50']:.4g}, "
                  f"p95 {m['p95']:.4g}")
    for note in summary.get("sobol_notes", []):
        print(f"rvsim: note: {note}", file=sys.stderr)
    return 0


def _tolerance(args: argparse.Namespace) -> int:
    study = load_any_tolerance_study(args.study, args.params)
    return run_tolerance_command(study, args)


def _allocate(args: argparse.Namespace) -> int:
    from ..tolerance.allocation import allocate, parse_targets
    from ..tolerance.montecarlo import write_json
    from ..tolerance.report import write_allocation_report

    study = load_any_tolerance_study(args.study, args.params)
    targets = parse_targets(args.target)
    check_output_folder(args.out, "--out")
    folder = Path(args.out)
    samples = study.samples if args.samples is None else args.samples
    if args.samples is None:
        samples = min(samples, 200)
    result = allocate(study, targets, folder, samples=samples, workers=args.workers,
                      scheduler=args.scheduler, max_evaluations=args.max_evaluations)
    write_json(folder / "allocation.json", result)
    write_allocation_report(folder, result)
    if args.json:
        print_json({k: v for k, v in result.items() if k != "history"})
        return 0
    print(f"{study.name}: {result['status']}, relative cost {result['cost']:.4g} (as given "
          f"{result['cost_start']:.4g}), {result['evaluations']} evaluations of {samples} "
          f"reducers -> {folder}/allocation.json, report.html")
    print(f"  {result['status_text']}")
    for t in result["tolerances"]:
        print(f"  {t['name']}: {t['given']:g} -> {t['allocated']:.4g} {t['unit']}")
    for t in result["targets"]:
        print(f"  {t['target']}: achieved {t['achieved']:.4g}")
    for note in result.get("notes", []):
        print(f"  note: {note}")
    return 0


def _common(p) -> None:
    p.add_argument("study", help="'rv40e-tolerances', 'cycloid-drive-tolerances' or a "
                   "tolerance study .toml file")
    p.add_argument("--out", required=True, metavar="DIR", type=path_text, help="output folder")
    p.add_argument("--params", metavar="FILE", type=path_text,
                   help="the reducer: a TOML file or a built-in set's name, in place of the "
                        "study's 'params' (its [set] values and tolerances apply to it)")
    p.add_argument("--samples", type=whole, metavar="N",
                   help="Monte Carlo reducers (2 .. 1000000; default: the study's)")
    p.add_argument("--workers", type=positive_int,
                   help="local worker processes (default: one per core)")
    p.add_argument("--scheduler", metavar="ADDRESS", type=scheduler_address,
                   help="run on this Dask scheduler")
    p.add_argument("--json", action="store_true", help="print a JSON summary")


def register(sub) -> None:
    p = add_command(sub, "tolerance", "Monte Carlo of a tolerance study (and Sobol indices)",
                    "Draw N reducers from the tolerances of a study (built in: "
                    "rv40e-tolerances, cycloid-drive-tolerances; or a TOML file with a "
                    "[tolerances] table), check each one's assembly and analyse it on the "
                    "quasi-static engine (transmission error over one output revolution, lost "
                    "motion, torsional rigidity), in parallel or on a Dask cluster, each "
                    "result stored as it arrives (re-running resumes).  Writes "
                    "DIR/summary.json (mean, std, p5, p50, p95 of each metric, binding share, "
                    "Sobol indices), results.csv and report.html.",
                    ["rvsim tolerance rv40e-tolerances --out tol --samples 200",
                     "rvsim tolerance rv40e-tolerances --out tol --samples 200 --sobol 32",
                     "rvsim tolerance docs/examples/table1_errors.toml --params "
                     "docs/examples/prototype_1.toml --out tp1",
                     "rvsim tolerance my_tolerances.toml --out tol --scheduler "
                     "tcp://127.0.0.1:8786"])
    _common(p)
    p.add_argument("--sobol", type=whole, metavar="BASE", default=0,
                   help="also compute Sobol indices from BASE x (2 x errors + 2) reducers "
                        "(BASE a power of 2; 0, the default: no Sobol indices)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-report", action="store_true", help="skip report.html")
    p.set_defaults(func=_tolerance)

    p = add_command(sub, "allocate", "loosest tolerances that meet percentile targets",
                    "Search the tolerances of a tolerance study for the least relative cost "
                    "(cost model: docs/decisions.md; [cost.NAME] tables of the study file edit "
                    "it) whose Monte Carlo percentiles meet the targets, with common random "
                    "numbers and SciPy's COBYLA.  Writes DIR/allocation.json and report.html.",
                    ["rvsim allocate rv40e-tolerances --target ate_p95=0.3 --out alloc",
                     "rvsim allocate my_tolerances.toml --target ate_p95=0.3,"
                     "lost_motion_p95=2.5 --samples 100 --out alloc"])
    _common(p)
    p.add_argument("--target", required=True, metavar="METRIC_pNN=VALUE[,...]",
                   help="e.g. ate_p95=0.3,lost_motion_p95=2.5 (arcmin); "
                        "torsional_rigidity_p5=200 is a lower bound; binding_share=0.01 "
                        "limits the reducers that bind on assembly (default: no more than "
                        "with the tolerances as given)")
    p.add_argument("--max-evaluations", type=positive_int, default=60,
                   help="optimiser iterations (default 60)")
    p.set_defaults(func=_allocate)
