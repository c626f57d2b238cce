"""``rvsim study`` and ``rvsim analyze``."""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

from ..errors import InputFileError, ParameterError
from ._common import (number, add_command, check_load, check_output_folder, path_text,
                      positive_int, print_json, probability, scheduler_address, stopped_line)

__all__ = ["register"]


def _response_column(table, response: str | None, factors=None) -> str:
    """The analysed column: --response (checked: in the table, numeric, not a factor) or the
    default (the paper's mean TE).  Without named factors, a column of level codes the table's
    own factors would include is a factor too."""
    from ..analysis._table import factor_columns, is_coded
    from ..analysis.indices import check_response

    if factors is None:
        try:
            factors = [c for c in factor_columns(table, "") if is_coded(table[c])]
        except InputFileError:            # no factor at all: the analysis says so
            factors = []
    return check_response(table, response, factors=factors)


def _as_option(exc: ParameterError, args: argparse.Namespace) -> ParameterError:
    """``exc`` in the words of the command line: a refused ``time_step`` is the --time-step
    option's fault when the option gave it (the study's range check or a run's step count)."""
    if exc.field == "time_step" and args.time_step is not None:
        return ParameterError("--time-step", exc.reason)
    return exc


def _check_loads(study) -> None:
    """The study's heaviest run against its rating (one warning line, or the refusal)."""
    from ..parameters.rating import peak_load

    def load(r):
        return (peak_load(r) if study.engine == "dynamic"
                else (abs(r.operating.load_torque), "operating.load_torque"))

    runs = zip(study.table()["run"], study.reducers())
    run, heaviest = max(runs, key=lambda p: load(p[1])[0] / p[1].rating.momentary_torque)
    torque, field = load(heaviest)
    check_load(heaviest, torque, f"{field} (study run {int(run)})")


def _study(args: argparse.Namespace) -> int:
    from ..doe import BUILT_IN_STUDIES, load_study, run, write_study_outputs
    from ..tolerance.spec import BUILT_IN_TOLERANCE_STUDIES, is_tolerance_file

    if args.study in BUILT_IN_TOLERANCE_STUDIES or (Path(args.study).suffix == ".toml"
                                                    and is_tolerance_file(args.study)):
        from ._tolerance import load_any_tolerance_study, run_tolerance_command

        if args.scheme not in (None, "explicit"):
            raise ParameterError("--scheme", "a tolerance study runs the quasi-static "
                                 "engine: the integration scheme is the dynamic engine's")
        if args.time_step is not None:
            raise ParameterError("--time-step", "a tolerance study runs the quasi-static "
                                 "engine, which takes no time step")
        if args.response is not None:
            raise ParameterError("--response", _TOLERANCE_RESPONSE)
        if args.sn is not None:
            raise ParameterError("--sn", _TOLERANCE_SN)

        return run_tolerance_command(load_any_tolerance_study(args.study), args)
    from ..tolerance.robust import BUILT_IN_ROBUST_STUDIES, is_robust_file, load_robust_study

    if args.study in BUILT_IN_STUDIES:
        study = BUILT_IN_STUDIES[args.study]()
    elif args.study in BUILT_IN_ROBUST_STUDIES:
        study = BUILT_IN_ROBUST_STUDIES[args.study]()
    elif Path(args.study).suffix == ".toml":
        study = (load_robust_study if is_robust_file(args.study) else load_study)(args.study)
    else:
        raise InputFileError(f"unknown study '{args.study}' (built in: "
                             f"{', '.join([*BUILT_IN_STUDIES, *BUILT_IN_ROBUST_STUDIES])}; "
                             "or a .toml file)")
    if args.scheme is not None:
        if study.engine != "dynamic" and args.scheme != "explicit":
            raise ParameterError("--scheme", f"the study runs the {study.engine} engine: the "
                                 "integration scheme is the dynamic engine's")
        if study.engine == "dynamic":
            study = dataclasses.replace(study, scheme=args.scheme)
    if args.time_step is not None:
        if study.engine != "dynamic":
            raise ParameterError("--time-step", f"the study runs the {study.engine} engine, "
                                 "which takes no time step")
        try:
            study = dataclasses.replace(study, time_step=args.time_step)
        except ParameterError as exc:
            raise _as_option(exc, args) from None
    _check_loads(study)
    response = _study_response(study, args.response)
    from ..analysis.signal_noise import table_kind

    table_kind(response, args.sn)           # before any run (an unknown or nominal kind)
    check_output_folder(args.out, "--out")   # before the runs, not after them
    folder = Path(args.out)
    progress = not args.no_progress and sys.stderr.isatty()
    factors = [f.label for f in study.factors]
    summary = {}

    def finish(results) -> None:       # runs while the folder is locked
        if args.response is not None and (results["status"] == "ok").any():
            from ..analysis._table import drop_failed_runs
            from ..analysis.indices import check_response

            # a metric only some schemes give (the guard's counters): before any output
            check_response(drop_failed_runs(results)[0], response, factors=factors)
        summary["analysis"] = write_study_outputs(folder, results, factors, alpha=args.alpha,
                                                  response=response, sn=args.sn,
                                                  also=_robust_also(study, response))
        if not args.no_report:
            from ..report import write_study_report

            write_study_report(folder, study=study)

    from ..doe._workers import WorkerStartError
    from ..doe.outputs import prepare_outputs

    try:
        results = run(study, folder, workers=args.workers, scheduler=args.scheduler,
                      progress=progress, finish=finish, prepare=prepare_outputs)
    except ParameterError as exc:
        raise _as_option(exc, args) from None
    except KeyboardInterrupt as exc:            # Ctrl-C, or SIGTERM / SIGHUP (Terminated)
        line, code = stopped_line(exc, folder, "runs")
        print(line, file=sys.stderr)
        return code
    except WorkerStartError as exc:
        print(f"rvsim: error: {exc}; finished runs are kept in {folder}", file=sys.stderr)
        return 1
    analysis = summary["analysis"]
    failed = int((results["status"] != "ok").sum())
    if len(results) and failed == len(results):
        # nothing to analyse: a failure of the study, not a result (exit 1, one line)
        first = results.iloc[0]
        error = first["error"] if isinstance(first["error"], str) else ""   # NaN: none given
        reason = f"{first['status']}" + (f": {error}" if error else "")
        if args.json:
            print_json({"status": "all_failed", "folder": str(folder), "runs": int(len(results)),
                        "first_failure": {"run": int(first["run"]),
                                          "status": str(first["status"]), "error": error}})
        print(f"rvsim: error: study: all {len(results)} runs failed (run {int(first['run'])}: "
              f"{reason.splitlines()[0][:300]}); their rows are in {folder}/results.csv",
              file=sys.stderr)
        return 1
    if args.json:
        print_json({"folder": str(folder), "runs": int(len(results)), "failed": failed,
                    "analysis": analysis})
    else:
        print(f"{study.name}: {len(results)} runs, {failed} failed -> {folder}/results.csv, "
              f"analysis.json" + ("" if args.no_report else ", report.html"))
        if args.response is not None:
            print(f"response {analysis['response_note']}")
        if study.noise is not None:
            print(f"robust study: {study.noise.samples} noise replicates per run")
        _print_order(analysis, response if study.noise is not None else "")
        for column, other in analysis.get("also", {}).items():
            _print_order(other, column)
    return 0


def _print_order(analysis: dict, column: str) -> None:
    """The factor order line of one analysed column (``column``: named when given)."""
    by = f"factor order by range{f' of {column}' if column else ''}"
    if analysis.get("constant_response"):
        print(f"{by}: none (the response is constant)")
    elif "order" in analysis:
        print(f"{by}: {analysis['order']}")
    elif "error" in analysis:        # e.g. too few finished runs for the model
        print(analysis["error"])


def _robust_also(study, response: str) -> tuple:
    """A robust study's companion column of ``response``: the mean beside an S/N ratio
    (the S/N beside a mean), analysed alike (issue 33: effects on S/N and on the mean)."""
    if study.noise is None:
        return ()
    return _companion(response)


def _companion(response: str) -> tuple:
    import re

    found = re.fullmatch(r"(.+)_sn(_smaller|_nominal|_larger)?", response)
    if found:
        return (f"{found.group(1)}_mean",)
    found = re.fullmatch(r"(.+)_mean", response)
    return (f"{found.group(1)}_sn",) if found else ()


_TOLERANCE_RESPONSE = ("a tolerance study reports the distribution of every metric "
                       "(summary.json: ate_arcmin, te_mean_arcmin, ...); --response chooses "
                       "the analysed column of a designed study")


_TOLERANCE_SN = ("a tolerance study has no design to rank factors on; --sn chooses the S/N "
                 "kind of a designed study's analysis")

_SN_HELP = ("S/N ratio of the response table: smaller (-10 log10 y^2), larger (-10 log10 "
            "1/y^2; its optimum the largest level mean); default the response's own sense "
            "(larger for a stiffness, rigidity, rated torque, pins in contact, efficiency; "
            "smaller for the rest); nominal needs replicates: a [noise] study's "
            "m_sn_nominal column")


def _study_response(study, response: str | None) -> str:
    """The column a study's analysis and report analyse: --response, checked against the
    metric columns of the study's engine before any run, or the paper's mean TE."""
    from ..doe.engines import metric_columns

    if study.noise is not None:
        columns = study.noise.columns(study)
        if response is None:   # the bench's index's S/N; a dynamic run's window is usually
            # a part of an output revolution: the paper's index's, as a plain dynamic study's
            return "ate_arcmin_sn" if study.engine == "quasi-static" else "te_mean_arcmin_sn"
        if response not in columns:
            raise ParameterError("--response", f"'{response}' is not a column of the robust "
                                 f"study's rows (e.g. ate_arcmin_sn, ate_arcmin_mean, "
                                 f"ate_arcmin_std, ate_arcmin_p95; docs/user_guide.md)")
        if response.startswith("ate_arcmin") and study.engine == "dynamic":
            _check_ate_window(study)
        return response
    if response is None:
        return "te_mean_arcmin"
    columns = metric_columns(study.engine, study.hysteresis)
    if response not in columns:
        raise ParameterError("--response", f"'{response}' is not a metric of the "
                             f"{study.engine} engine's runs (numeric columns: "
                             f"{', '.join(columns)})")
    if response == "ate_arcmin" and study.engine == "dynamic":
        _check_ate_window(study)
    return response


def _check_ate_window(study) -> None:
    """A dynamic study analysed by its ATE needs steady windows of an output revolution
    (docs/decisions.md, issue 33): refused before any run when the first run's is shorter."""
    import math

    reducer = study.reducers()[0]
    op = reducer.operating
    revolutions = ((op.duration - op.steady_start) * op.input_speed
                   / (2.0 * math.pi * abs(reducer.ratio)))
    if revolutions < 1.0:
        needed = 2.0 * math.pi * abs(reducer.ratio) / op.input_speed
        raise ParameterError("--response", f"ate_arcmin (peak-to-peak TE over one output "
                             f"revolution) needs a steady window of {needed:.4g} s at "
                             f"{math.degrees(op.input_speed):g} deg/s; the study's run 1 has "
                             f"{op.duration - op.steady_start:.4g} s "
                             f"({revolutions:.3g} revolution; raise operating.duration, or "
                             "analyse te_pp_arcmin, the peak-to-peak over that window)")


def _names(option: str, text: str | None) -> list[str] | None:
    """A comma-separated list of column names (None when the option is not given)."""
    if text is None:
        return None
    names = [n.strip() for n in text.split(",")]
    if not any(names) or not all(names):
        raise ParameterError(option, f"'{text}': expected comma-separated column names, none "
                             "empty")
    return names


def _study_factors(path: str, table) -> list[str] | None:
    """The factor labels of the study whose results.csv ``path`` is (its study.json beside
    it), where the table has them all; None otherwise (the table's own columns decide)."""
    import json
    from pathlib import Path

    try:
        stored = json.loads((Path(path).parent / "study.json").read_text(encoding="utf-8"))
        labels = [f["label"] for f in stored["factors"]]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if labels and all(isinstance(x, str) and x in table.columns for x in labels):
        return labels
    return None


def _analyze(args: argparse.Namespace) -> int:
    from ..analysis import analyze_table, anova, range_analysis
    from ..analysis._table import drop_failed_runs, read_table

    # a failed run's numbers are no response (rvsim study leaves them out the same way)
    table, failed = drop_failed_runs(read_table(args.table))
    factors = _names("--factors", args.factors)
    if factors is None:
        factors = _study_factors(args.table, table)
    pool = tuple(_names("--pool", args.pool) or ())
    robust = args.response is None and _is_robust_folder(args.table)
    if robust:             # a robust study's S/N of the ATE, then its mean (issue 33)
        response = _response_column(table, "ate_arcmin_sn" if "ate_arcmin_sn" in table
                                    else "te_mean_arcmin_sn", factors)
    else:
        response = _response_column(table, args.response, factors)
    result = analyze_table(table, response, factors, pool=pool, alpha=args.alpha, sn=args.sn)
    if robust:
        also = _companion(response)[0]
        result["also"] = {also: analyze_table(table, _response_column(table, also, factors),
                                              factors, pool=pool, alpha=args.alpha)}
    if failed:
        result.setdefault("notes", []).insert(0, f"{failed} run(s) whose status is not 'ok' "
                                              "left out")
    from ..analysis.indices import response_bench_note

    result["response"] = response
    result["response_note"] = response_bench_note(response)
    if args.json:
        print_json(result)
        return 0
    print(f"response {response_bench_note(response)}\n")
    print(result.range_analysis.to_df().round(4).to_string())
    if result.get("constant_response"):
        print(f"\norder: none: the response '{response}' is constant (to round-off), so the "
              "factors cannot be ranked")
    else:
        print(f"\norder: {result['order']}")
    print("\nANOVA (main effects)")
    print(anova(table, response, factors, pool=pool).to_df().round(4).to_string())
    print(f"\nsignificant at alpha = {args.alpha}: {', '.join(result['significant']) or 'none'}")
    for note in result.get("notes", []):
        print(f"note: {note}")
    for column, other in result.get("also", {}).items():
        print(f"\n\nresponse {response_bench_note(column)}\n")
        print(range_analysis(table, column, factors).to_df().round(4).to_string())
        print(f"\norder: {other.get('order', 'none')}")
        print("\nANOVA (main effects)")
        print(anova(table, column, factors, pool=pool).to_df().round(4).to_string())
        print(f"\nsignificant at alpha = {args.alpha}: "
              f"{', '.join(other['significant']) or 'none'}")
    return 0


def _is_robust_folder(path: str) -> bool:
    """Whether the results.csv ``path`` is a robust study's (its study.json has noise)."""
    import json

    try:
        stored = json.loads((Path(path).parent / "study.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(stored, dict) and "noise" in stored


def _report(args: argparse.Namespace) -> int:
    from ..report import write_study_report

    folder = Path(args.folder)
    if (folder / "summary.json").is_file() and not (folder / "analysis.json").is_file():
        from ..tolerance.report import rebuild_tolerance_report   # a tolerance study's folder

        if args.response is not None:
            raise ParameterError("--response", _TOLERANCE_RESPONSE)
        if args.sn is not None:
            raise ParameterError("--sn", _TOLERANCE_SN)
        path = rebuild_tolerance_report(folder)
    else:
        path = write_study_report(args.folder, alpha=args.alpha, response=args.response,
                                  sn=args.sn)
    if args.json:
        print_json({"report": str(path)})
    else:
        print(f"wrote {path}")
    return 0


def register(sub) -> None:
    p = add_command(sub, "report", "write the HTML report of a study folder",
                    "Write DIR/report.html (self-contained: figures embedded, "
                    "no network requests) from a folder made by 'rvsim study' (or by "
                    "'rvsim tolerance').",
                    ["rvsim report study"])
    p.add_argument("folder", type=path_text, help="study folder")
    p.add_argument("--alpha", type=probability, help="significance level marked in the ANOVA "
                   "(default: the study's)")
    p.add_argument("--response", metavar="COLUMN", help="analyse this numeric column of "
                   "results.csv (default: the one the study analysed, te_mean_arcmin unless "
                   "'rvsim study --response' chose another; ate_arcmin is what a bench "
                   "measures)")
    p.add_argument("--sn", choices=("smaller", "nominal", "larger"), help=_SN_HELP)
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=_report)

    p = add_command(sub, "study", "run a design of experiments (dynamic or quasi-static engine)",
                    "Run every row of a study (built in: paper-l36, the paper's "
                    "Table 2 factors on its L36 array; or a TOML study file) in parallel, "
                    "store each result as it finishes (re-running skips finished rows), "
                    "then write results.csv, analysis.json, main_effects.png and "
                    "report.html into the output folder.",
                    ["rvsim study paper-l36 --out study",
                    "rvsim study my_study.toml --out tol --workers 2",
                    "rvsim study paper-l36 --out study --scheduler tcp://127.0.0.1:8786",
                    "rvsim study paper-l36 --out reference --scheme explicit",
                    "rvsim study paper-l36-robust --out rob --workers 2"])
    p.add_argument("study", help="'paper-l36', 'paper-l36-robust' (its L36 with 20 noise "
                   "replicates of per-part errors per run), a tolerance study "
                   "('rv40e-tolerances': runs as 'rvsim tolerance' does) or a study .toml file "
                   "(with a [noise] section: a robust study)")
    p.add_argument("--out", required=True, metavar="DIR", type=path_text, help="study folder")
    p.add_argument("--workers", type=positive_int,
                   help="local worker processes (default: one per core)")
    p.add_argument("--scheduler", metavar="ADDRESS", type=scheduler_address,
                   help="run on this Dask scheduler")
    p.add_argument("--alpha", type=probability, default=0.1,
                   help="significance level (default 0.1)")
    p.add_argument("--scheme", choices=("explicit", "implicit-bearings"),
                   help="integration scheme of the dynamic runs (default: the study's; "
                   "paper-l36: implicit-bearings, about half the explicit scheme's time, "
                   "mean TE within 7.2e-5 relative; a study file: explicit unless it names one; "
                   "docs/model.md section 9)")
    p.add_argument("--time-step", type=number, metavar="SECONDS",
                   help="integration step of the dynamic runs [s] (default: the study's, "
                   "else the scheme's: 2e-5 s implicit-bearings, 5e-6 s explicit; paper-l36 "
                   "at 2.5e-5 s: 12-16 %% less CPU, its energy residuals up to 1.3e-4 "
                   "instead of 5.8e-5; docs/benchmarks.md)")
    p.add_argument("--response", metavar="COLUMN", help="metric column analysed (range "
                   "analysis, ANOVA, report; default te_mean_arcmin, the paper's index, which "
                   "no bench can check; ate_arcmin: the peak-to-peak TE over one output "
                   "revolution a bench measures; docs/validation.md)")
    p.add_argument("--sn", choices=("smaller", "nominal", "larger"), help=_SN_HELP)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--no-report", action="store_true", help="skip report.html")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    p.set_defaults(func=_study)

    p = add_command(sub, "analyze", "range analysis and ANOVA of a results table",
                    "Range analysis (k, R, order, optimum), a main-effects "
                    "ANOVA as Minitab prints it, S/N ratios (the response's sense, or --sn) and "
                    "the "
                    "predicted optimum of a design table (factor columns A, B, ... with "
                    "level numbers, one response column).",
                    ["rvsim analyze study/results.csv --json",
                    "rvsim analyze table3.csv --response te_arcmin --pool B,C"])
    p.add_argument("table", type=path_text, help="CSV file")
    p.add_argument("--response", metavar="COLUMN", help="numeric response column (default "
                   "te_mean_arcmin, the paper's index, or te_arcmin; e.g. ate_arcmin, the "
                   "bench's index)")
    p.add_argument("--sn", choices=("smaller", "nominal", "larger"), help=_SN_HELP)
    p.add_argument("--factors", help="comma-separated factor columns (default: a study "
                   "folder's own factors, else the single-letter columns and the columns of "
                   "level codes)")
    p.add_argument("--pool", help="comma-separated factors pooled into error")
    p.add_argument("--alpha", type=probability, default=0.1,
                   help="significance level (default 0.1)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_analyze)
