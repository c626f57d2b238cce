"""Self-contained HTML reports: one page, figures embedded as PNG data, no network requests.

``write_study_report(folder)`` reads a study folder (study.json, results.csv, analysis.json,
results.sqlite) and writes ``folder/report.html``; ``write_run_report`` does the same for one
simulation.  Figures come from :mod:`rvsim.plots`.
"""

from __future__ import annotations

import html
import json
import types
from pathlib import Path

import numpy as np
import pandas as pd

from ._files import atomic_write_text
from .errors import InputFileError
from .html import page as _page, parameters_table as _parameters_table, png as _png, \
    png_bytes as _png_bytes, summary_block as _summary_block, table as _table, \
    target as _target

__all__ = ["write_study_report", "write_run_report", "write_ltca_report",
           "write_hysteresis_report"]

#: what a reader of a study's answers should know of a scheme other than the explicit one
#: (measured on the paper's 36 runs, docs/benchmarks.md, issue 14)
_SCHEME_NOTES = {"implicit-bearings": (
    ". Its mean TE is within 1e-4 of the explicit scheme's (7.2e-5 over the paper's 36 "
    "runs); its peaks (peak-to-peak TE, largest pin force) differ by about 0.3 % (median), "
    "up to a few % on some runs, because it slows the crank modes (docs/model.md section 9). "
    "The explicit scheme's answers: --scheme explicit")}

def _arcmin(value) -> str:
    return "not available" if value is None else f"{float(value):.4f} arcmin"


def _value(value, response: str) -> str:
    """A predicted ``response`` with its unit (arcmin for the TE indices)."""
    if response.endswith("_arcmin"):
        return _arcmin(value)
    return "not available" if value is None else f"{float(value):.4g}"


def _history_object(history: dict):
    return types.SimpleNamespace(time=history["time"], omega_in=history["omega_in"],
                                 omega_out=history["omega_out"], te=history["te"],
                                 ratio=float(history["ratio"]),
                                 steady_start=float(history["steady_start"]))


def _results_layout(results: pd.DataFrame, factors: list[str], analysis: dict,
                    response: str = "te_mean_arcmin") -> pd.DataFrame:
    """Table 3 layout: runs, then k1..k3, R, rank and optimum rows."""
    from .analysis.indices import response_label

    table = results.set_index("run")[factors + [response]].copy()
    table = table.astype(object)
    table.index = table.index.astype(str)
    order = analysis["order"].split(">") if analysis.get("order") else []

    def levels(f: str) -> list:   # analysis.json of older versions has no "levels"
        k = analysis["range"][f]["k"]
        return analysis["range"][f].get("levels") or list(range(1, len(k) + 1))

    every = sorted({lv for f in factors for lv in levels(f)})
    extra = {}
    for lv in every:
        extra[f"k{lv}"] = [analysis["range"][f]["k"][levels(f).index(lv)] if lv in levels(f)
                           else float("nan") for f in factors] + [""]
    extra["R"] = [analysis["range"][f]["R"] for f in factors] + [""]
    extra["rank"] = [order.index(f) + 1 if f in order else "-" for f in factors] + [""]
    extra["optimal level"] = [analysis["optimum"][f] for f in factors] + [""]
    for name, values in extra.items():
        table.loc[name] = values
    table.index.name = "run"
    label = "TE [arcmin]" if response == "te_mean_arcmin" else response_label(response)
    return table.rename(columns={response: label})


def _response_analysis(results: pd.DataFrame, analysis: dict, factors: list[str],
                       response: str | None, sn: str | None = None) -> tuple[str, dict]:
    """(response, its analysis): analysis.json's when it analysed ``response`` (default: the
    one it analysed, else the paper's mean TE) with the S/N kind ``sn`` (default: the one it
    took), else the analysis of ``response`` computed from the finished runs.  A response the
    table cannot give raises ParameterError (--response), a kind it cannot take (--sn)."""
    from .analysis.signal_noise import table_kind

    from .analysis import analyze_table
    from .analysis._table import drop_failed_runs
    from .analysis.indices import check_response

    stored = analysis.get("response", "te_mean_arcmin")
    if (response is None or response == stored) and (
            sn is None or table_kind(stored, sn) == analysis.get("sn_kind", "smaller")):
        return stored, analysis
    response = stored if response is None else response
    ok, _ = drop_failed_runs(results)
    check_response(ok, response, factors=factors)
    try:
        fresh = analyze_table(ok, response, factors, alpha=analysis.get("alpha", 0.1), sn=sn)
    except InputFileError as exc:
        fresh = {"error": f"analysis not possible: {exc}"}
    fresh.update(runs_ok=int(len(ok)), runs_total=int(len(results)), response=response,
                 fresh=True)
    return response, fresh


def write_study_report(folder: str | Path, *, study=None, alpha: float | None = None,
                       response: str | None = None, sn: str | None = None) -> Path:
    """Write ``folder/report.html`` from a finished study folder (nothing if it is damaged),
    analysing ``response`` (default: the column analysis.json analysed) with the S/N kind
    ``sn`` (default: analysis.json's)."""
    folder = Path(folder)
    results, analysis, definition = _read_study_folder(folder)
    factors = [f["label"] for f in definition["factors"]]
    if alpha is not None and not 0.0 < alpha < 1.0:
        raise InputFileError(f"alpha: must be between 0 and 1, exclusive (got {alpha})")
    response, analysis = _response_analysis(results, analysis, factors, response, sn)
    try:
        page = _study_page(folder, results, analysis, definition, factors, alpha, response)
    except (KeyError, TypeError, ValueError, IndexError, AttributeError) as exc:
        # files that pass the structure checks but still disagree with each other
        raise InputFileError(f"{folder}: damaged study files ({type(exc).__name__}: {exc}); "
                             "run 'rvsim study' again") from None
    try:
        return atomic_write_text(folder / "report.html", page)
    except OSError as exc:
        raise InputFileError(f"{folder / 'report.html'}: cannot write ({exc.strerror or exc})"
                             ) from None


def _load_json(path: Path) -> dict:
    def constant(name: str):  # files of older versions hold bare NaN: read it as null
        return None

    try:
        data = json.loads(path.read_text(encoding="utf-8"), parse_constant=constant)
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFileError(f"{path}: cannot read ({exc})") from None
    except json.JSONDecodeError as exc:
        raise InputFileError(f"{path}: not valid JSON ({exc})") from None
    if not isinstance(data, dict):
        raise InputFileError(f"{path}: expected a JSON object")
    return data


def _require(data: dict, path: Path, keys: dict[str, type | tuple]) -> None:
    for key, kind in keys.items():
        if not isinstance(data.get(key), kind):
            raise InputFileError(f"{path}: '{key}' missing or malformed; run 'rvsim study' "
                                 "again")


def _read_study_folder(folder: Path) -> tuple[pd.DataFrame, dict, dict]:
    """results.csv, analysis.json and study.json of a study folder, structure checked.

    Raises :class:`InputFileError` naming the file at fault; creates nothing.
    """
    if not folder.is_dir():
        what = "a file" if folder.exists() else "no such folder"
        raise InputFileError(f"{folder}: not a study folder ({what}; give the --out folder of "
                             "'rvsim study')")
    needed = [folder / n for n in ("results.csv", "analysis.json", "study.json")]
    missing = [p.name for p in needed if not p.is_file()]
    if missing and (folder / "allocation.json").is_file():
        # its report.html is the allocation's, written by the command from its optimiser's
        # history, which the folder does not keep
        raise InputFileError(f"{folder}: a tolerance allocation's folder: its report.html is "
                             "written by 'rvsim allocate' (run the same command again to "
                             "write it; the evaluated reducers are reused)")
    if missing:
        raise InputFileError(f"{folder}: not a study folder (missing {', '.join(missing)}; "
                             "run 'rvsim study' first)")
    definition = _load_json(folder / "study.json")
    _require(definition, folder / "study.json", {"name": str, "design": str, "reducer": str,
                                                  "steady_start": (int, float),
                                                  "factors": list})
    for f in definition["factors"]:
        if not isinstance(f, dict) or not isinstance(f.get("label"), str) \
                or not isinstance(f.get("parameter"), str) \
                or not isinstance(f.get("levels"), list):
            raise InputFileError(f"{folder / 'study.json'}: malformed factor entry {f!r}")
    labels = [f["label"] for f in definition["factors"]]
    if not labels:
        raise InputFileError(f"{folder / 'study.json'}: no factors")
    analysis = _load_json(folder / "analysis.json")
    if "error" not in analysis:
        _require(analysis, folder / "analysis.json", {"range": dict, "order": (str, type(None)),
                                                      "optimum": dict, "anova": dict,
                                                      "prediction": dict})
        if set(analysis["range"]) != set(labels):
            raise InputFileError(f"{folder / 'analysis.json'}: its factors "
                                 f"({', '.join(analysis['range'])}) are not those of "
                                 f"study.json ({', '.join(labels)})")
    path = folder / "results.csv"
    try:
        results = pd.read_csv(path, keep_default_na=False, na_values=[""])
    except (OSError, UnicodeDecodeError, pd.errors.ParserError, pd.errors.EmptyDataError
            ) as exc:
        raise InputFileError(f"{path}: cannot read ({str(exc).strip()})") from None
    columns = ["run", "status", "key"] + labels
    # a robust study's rows hold the replicates' statistics (issue 33): its mean TE's mean
    metric = "te_mean_arcmin_mean" if "noise" in definition else "te_mean_arcmin"
    if "status" in results.columns and (results["status"] == "ok").any():
        columns.append(metric)    # a study none of whose runs finished has no metric
    absent = [c for c in columns if c not in results.columns]
    if absent:
        raise InputFileError(f"{path}: missing column(s) {', '.join(absent)} (truncated or "
                             "not written by 'rvsim study')")
    runs = pd.to_numeric(results["run"], errors="coerce")
    if runs.isna().any() or results["status"].isna().any() or not len(results):
        raise InputFileError(f"{path}: incomplete rows (truncated?); run 'rvsim study' again")
    total = analysis.get("runs_total")
    if isinstance(total, int) and total != len(results):
        raise InputFileError(f"{path}: {len(results)} rows, analysis.json counts {total} runs "
                             "(truncated?); run 'rvsim study' again")
    if (results["status"] == "ok").any():
        ok = results[results["status"] == "ok"]
        if pd.to_numeric(ok[metric], errors="coerce").isna().any():
            raise InputFileError(f"{path}: a finished run has no {metric} (truncated?)")
    return results, analysis, definition


def _study_page(folder: Path, results: pd.DataFrame, analysis: dict, definition: dict,
                factors: list[str], alpha: float | None,
                response: str = "te_mean_arcmin") -> str:
    from .analysis import range_analysis, sn_response_table
    from .analysis.anova import ZERO_RESPONSE_NOTE
    from .analysis.range_analysis import larger_is_better
    from .analysis.indices import response_bench_note, response_label
    from .doe.store import ResultStore
    from .plots import main_effects_plot, spectrum_plot, speed_plot, te_plot

    alpha = alpha if alpha is not None else analysis.get("alpha", 0.1)
    # issue 9: a study on the quasi-static engine has no time window
    index = ("mean TE over one output revolution, quasi-static engine"
             if definition.get("engine") == "quasi-static" else
             f"mean TE for t &ge; {definition['steady_start']:g} s")
    body = [f"<h1>RV reducer study: {html.escape(definition['name'])}</h1>",
            f"<p class='note'>Reducer: {html.escape(definition['reducer'])}. Design "
            f"{html.escape(definition['design'])}, {len(results)} runs, "
            f"{int((results['status'] == 'ok').sum())} finished. Transmission error TE = "
            f"theta_in/i - theta_out (paper Eq. 22); index: {index}.</p>",
            "<p class='note'>Analysed here: " + html.escape(response_bench_note(response))
            + ". Which index is which: docs/validation.md; another column: rvsim report "
            "--response COLUMN.</p>"]
    body.append("<h2>Study definition</h2>")
    fdef = pd.DataFrame([{"factor": f["label"], "parameter": f["parameter"],
                          "levels / range": ", ".join(map(str, f["levels"])) if f["levels"]
                          else f"{f['low']} .. {f['high']}"} for f in definition["factors"]]
                        ).set_index("factor")
    body.append(_table(fdef))
    if definition.get("fixed"):
        body.append("<p class='note'>Fixed for every run: " + html.escape(", ".join(
            f"{k} = {v}" for k, v in definition["fixed"])) + "</p>")
    if definition.get("noise"):          # a robust study (issue 33)
        noise = definition["noise"]
        body.append("<p class='note'>Noise factors: every run built " + html.escape(
            f"{noise['samples']} times (seed {noise['seed']}) with drawn " + ", ".join(
                f"{t['name']} ({t['distribution']}, {t['tolerance']:g})"
                for t in noise["tolerances"])) + "; each row holds the replicates' mean, "
            "std, percentiles and S/N ratios (docs/user_guide.md section 14)</p>")
    if definition.get("engine", "dynamic") == "dynamic" and definition.get("time_step"):
        # issue 14: every dynamic study names its scheme (study.json omits the explicit one)
        scheme = definition.get("scheme", "explicit")
        body.append("<p class='note'>Integration scheme: " + html.escape(
            f"{scheme}, step {definition['time_step']:g} s") + _SCHEME_NOTES.get(scheme, "")
            + "</p>")

    histories = {}
    if (folder / "results.sqlite").is_file():   # opening a missing store would create one
        store = ResultStore(folder, readonly=True)  # a report never writes the store
        try:
            keys = list(store.finished())
            for _, row in results.head(10).iterrows():
                if row["status"] != "ok":
                    continue
                full = [k for k in keys if k.startswith(str(row["key"]))]
                hist = store.history(full[0]) if full else None
                if hist is not None:
                    histories[f"run {int(row['run'])}"] = _history_object(hist)
        finally:
            store.close()
    if histories:
        first = next(iter(histories.values()))
        body += ["<h2>Input and output speed (Fig. 4)</h2>",
                 f"<p class='note'>{html.escape(next(iter(histories)))}: input (upper panel) and "
                 f"output (lower panel, the ratio {first.ratio:g} slower), each on its own "
                 "scale.</p>", _png(speed_plot(first)),
                 "<h2>Transmission error of the first runs (Fig. 5)</h2>",
                 _png(te_plot(histories, first.steady_start)),
                 "<h2>TE spectrum</h2>",
                 f"<p class='note'>{html.escape(next(iter(histories)))}, steady window; orders "
                 "of the crank rotation relative to the carrier, with the crank, pin-passing, "
                 "sun-planet mesh and load-fluctuation orders marked (the fluctuation acts only "
                 "in runs with it switched on).</p>",
                 _png(spectrum_plot(first, pin_count=int(definition.get("pin_count", 40)),
                                    planet_teeth=definition.get("planet_teeth", 54),
                                    fluctuation_frequency=definition.get(
                                        "fluctuation_frequency")))]
    if "error" in analysis:
        body.append(f"<h2>Analysis</h2><p>{html.escape(analysis['error'])}</p>")
    else:
        ok = results[results["status"] == "ok"]
        # analysis.json of an earlier version has no sn_kind: its table was smaller-the-better
        kind = analysis.get("sn_kind", None if larger_is_better(response) else "smaller")
        body += ["<h2>Results and range analysis (Table 3 layout)</h2>",
                 _table(_results_layout(ok, factors, analysis, response)),
                 "<p>Factor order by range: <b>"
                 + html.escape(analysis["order"] or "none (the response is constant)")
                 + "</b>. "
                 + ("Optimum (larger is better: an S/N ratio): " if larger_is_better(response)
                    else "Optimum (larger is better): " if kind == "larger"
                    else "Optimum (smaller is better): ") + html.escape(" ".join(
                     f"{f}{lvl}" for f, lvl in analysis["optimum"].items())) + "</p>"]
        anova = pd.DataFrame(analysis["anova"]).T.astype(float)   # null -> NaN
        anova.index.name = "source"
        anova = anova.rename(columns={"df": "DF", "adj_ss": "Adj SS", "adj_ms": "Adj MS",
                                      "f": "F-Value", "p": "P-Value"})
        anova["DF"] = anova["DF"].astype(int)
        significant = [s for s in anova.index if s not in ("Error", "Total")
                       and anova.loc[s, "P-Value"] < alpha]
        body += ["<h2>Analysis of variance (Table 8 layout)</h2>",
                 _table(anova, highlight=significant),
                 f"<p>Significant at alpha = {alpha:g} (highlighted): "
                 f"{html.escape(', '.join(significant) or 'none')}. Predicted "
                 + ("TE" if response == "te_mean_arcmin" else html.escape(response))
                 + " at the optimum from the significant factors"
                 + (": " if significant else " (none: the grand mean): ")
                 + _value(analysis["prediction"].get("predicted"), response) + ".</p>"]
        body += [f"<p class='note'>{html.escape(note)}</p>" for note in analysis.get("notes", [])]
        # the study's main_effects.png (doe.outputs draws it from the same rows, whatever the
        # alpha) rather than the same figure drawn again: 1.3 s of the paper study's 18 s
        # (not when this report analyses another column than the study did)
        effects = folder / "main_effects.png"
        body += ["<h2>Main effects (Figs. 8-10)</h2>",
                 _png_bytes(effects.read_bytes())
                 if effects.is_file() and not analysis.get("fresh") else
                 _png(main_effects_plot(range_analysis(ok, response, factors),
                                        ylabel=response_label(response))),
                 f"<h2>Signal-to-noise ratios ({kind or 'larger'} is better"
                 + (", -10 log10(1/y^2)" if kind == "larger" else "") + ")</h2>"]
        sn = None if kind is None else sn_response_table(ok, response, factors, kind)
        body.append(_table(sn.round(4)) if sn is not None else
                    f"<p class='note'>{html.escape(ZERO_RESPONSE_NOTE)}</p>"
                    if kind is not None else
                    f"<p class='note'>{html.escape(response)} is itself an S/N ratio over the "
                    "noise replicates (see the range analysis above)</p>")
        for column, other in analysis.get("also", {}).items():   # a robust study's mean
            if other.get("order"):
                body.append(f"<p>Factor order by range of {html.escape(column)}: <b>"
                            f"{html.escape(other['order'])}</b>.</p>")
    failed = results[results["status"] != "ok"]
    if len(failed):
        body += ["<h2>Failed runs</h2>",
                 _table(failed.set_index("run")[["status", "error"]])]
    body.insert(1, _study_summary(results, analysis, definition, alpha, response))
    return _page(f"rvsim study {definition['name']}", body)


def _study_summary(results: pd.DataFrame, analysis: dict, definition: dict, alpha: float,
                   response: str) -> str:
    """The block the study report opens with (issue 34 item 2): ranking, significant
    factors, optimum in real values, predicted response, a confirmation run."""
    from .analysis.headline import confirmation_command, study_rows
    from .parameters import SPECS

    finished = f"{int((results['status'] == 'ok').sum())} of {len(results)} runs finished"
    if "error" in analysis:
        return _summary_block("Answer", [("runs", finished, "-", analysis["error"])])
    significant = [s for s, row in analysis["anova"].items() if s not in ("Error", "Total")
                   and row.get("p") is not None and row["p"] < alpha]
    units = {name: spec.unit for name, spec in SPECS.items()}
    rows = study_rows(definition, analysis, significant, units,
                      _value(analysis["prediction"].get("predicted"), response))
    rows.insert(0, ("analysed response", response, "-", finished))
    command = confirmation_command({**definition,
                                    "reducer": definition["reducer"].split(" (")[0]},
                                   analysis.get("optimum", {}))
    return _summary_block("Answer", rows, notes=[
        f"Significant at alpha = {alpha:g}. Confirmation run (every factor at its optimum "
        f"level): <code>{html.escape(command)}</code>"])


def _speed_note(result, reducer) -> str:
    """What the speed curve of Fig. 4 shows, in words, with this run's figures."""
    op = reducer.operating
    deg = 180.0 / np.pi
    out = result.omega_out * deg
    steady_in = op.input_speed * deg
    rigid = steady_in / result.ratio          # the output speed of a rigid, backlash-free drive

    def span(lo, hi):
        m = (result.time >= lo) & (result.time < hi)
        return (out[m].min(), out[m].max()) if m.any() else None

    text = [f"The input follows the STEP ramp to {steady_in:.0f} deg/s over "
            f"{op.speed_ramp_time:g} s (Eq. 19) (upper panel); a rigid, backlash-free drive "
            f"would turn the output (lower panel) at that speed / {result.ratio:g} = "
            f"{rigid:.2f} deg/s.  The carrier drives a load of {op.load_inertia:g} kg*m^2 "
            "(operating.load_inertia)."]
    before = span(0.0, op.load_start)
    if before is not None:
        lo, hi = before
        if op.load_fluctuation:
            cause = (f"the fluctuating torque of Eq. (20) ({op.fluctuation_amplitude:g} N*m at "
                     f"{op.fluctuation_frequency:g} Hz) acts on the unloaded carrier and "
                     "throws it back and forth through the play of the clearances, errors and "
                     "modifications, and the contacts ring after each impact")
        else:
            cause = ("without load the carrier is only dragged along; start-up vibration and "
                     "the play of clearances and errors show as deviations")
        text.append(f"Before the load is applied (t < {op.load_start:g} s) the output "
                    f"speed ranges from {lo:.3g} to {hi:.3g} deg/s: "
                    f"{cause}.")
    steady = span(op.steady_start, float("inf"))
    if steady is not None:
        lo, hi = steady
        text.append(f"Once the {op.load_torque:g} N*m load has taken up the play (t >= "
                    f"{op.steady_start:g} s) it stays between {lo:.3g} and {hi:.3g} deg/s "
                    f"({100 * (lo / rigid - 1):+.1f} % to {100 * (hi / rigid - 1):+.1f} "
                    f"% from the rigid drive's): what remains is the torsional vibration of the "
                    f"loaded drive{_speed_peaks(result, reducer)}.")
    return "<p class='note'>" + html.escape(" ".join(text)) + "</p>"


def _speed_peaks(result, reducer) -> str:
    """The two strongest frequencies of the steady output speed, with their crank orders."""
    from .dynamics.result import crank_frequency

    window = result.time >= result.steady_start
    speed = result.omega_out[window]
    if len(speed) < 16:
        return ""
    amplitude = np.abs(np.fft.rfft((speed - speed.mean()) * np.hanning(len(speed))))
    freq = np.fft.rfftfreq(len(speed), result.time[1] - result.time[0])
    crank_hz = crank_frequency(result.time, result.omega_out, result.steady_start,
                               reducer.cycloid.pin_count)
    peaks = []
    for i in np.argsort(amplitude[1:])[::-1] + 1:
        if all(abs(freq[i] - f) > 5.0 for f in peaks):
            peaks.append(freq[i])
        if len(peaks) == 2:
            break
    words = [f"{f:.1f} Hz (crank order {f / crank_hz:.2f})" if crank_hz > 0 else f"{f:.1f} Hz"
             for f in peaks]
    return "; its strongest components are at " + " and ".join(words)


def write_run_report(result, reducer, path: str | Path) -> Path:
    """Write an HTML page for one simulation ``result`` of ``reducer``."""
    from .parameters import parameter_table
    from .plots import spectrum_plot, speed_plot, te_plot

    path = Path(path)
    if not path.parent.exists():
        raise InputFileError(f"{path}: folder {path.parent} does not exist")
    summary = pd.DataFrame([{"metric": k, "value": v} for k, v in result.summary().items()]
                           ).set_index("metric")
    params = pd.DataFrame(parameter_table(reducer)).set_index("name")
    changed = params[[not name.startswith("materials") for name in params.index]]
    window = result.time >= result.steady_start
    forces = result.pin_forces[window].mean(axis=0)
    from ._matplotlib import pyplot

    plt = pyplot()

    fig, ax = plt.subplots(figsize=(7, 3))
    pins = np.arange(1, forces.shape[1] + 1)
    ax.bar(pins - 0.2, forces[0], width=0.4, label="disc 1")
    ax.bar(pins + 0.2, forces[1], width=0.4, label="disc 2")
    ax.set_xlabel("pin number [-]")
    ax.set_ylabel("mean contact force [N]")
    ax.legend()
    fig.tight_layout()
    single = reducer.layout.single_stage
    kind = "Single-stage cycloid drive" if single else "RV reducer"
    if single and reducer.layout.ring_output:
        kind += " (pin ring output)"
    from .analysis.headline import run_rows

    body = [f"<h1>{kind} simulation: {html.escape(reducer.name)}</h1>",
            _summary_block("Answer", run_rows(result.summary())),
            "<h2>Summary</h2>", _table(summary),
            "<h2>Input and output speed (Fig. 4)</h2>", _speed_note(result, reducer),
            _png(speed_plot(result)),
            "<h2>Transmission error (Fig. 5)</h2>",
            _png(te_plot({"TE": result}, result.steady_start)),
            "<h2>TE spectrum</h2>",
            _png(spectrum_plot(result, pin_count=reducer.cycloid.pin_count,
                               planet_teeth=None if single else reducer.gears.planet_teeth,
                               fluctuation_frequency=(reducer.operating.fluctuation_frequency
                                                      if reducer.operating.load_fluctuation
                                                      else None))),
            "<h2>Pin contact forces (steady window mean)</h2>", _png(fig),
            "<h2>Parameters</h2>", _table(changed)]
    return atomic_write_text(path, _page(f"rvsim {reducer.name}", body))


def _summary_table(summary: dict) -> str:
    return _table(pd.DataFrame([{"metric": k, "value": v} for k, v in summary.items()]
                               ).set_index("metric"))


def write_ltca_report(result, reducer, path: str | Path) -> Path:
    """Write an HTML page for one quasi-static LTCA ``result`` (TE over one output
    revolution) of ``reducer``: pin loads, TE, its order spectrum."""
    from .analysis.catalogue import order_spectrum, reducer_orders
    from .analysis.headline import ltca_rows
    from .plots import order_spectrum_plot, pin_load_map, te_revolution_plot
    from .units import ARCMIN

    path = _target(path)
    orders, amplitude = order_spectrum(np.asarray(result.input_angle) / result.ratio, result.te)
    marks = reducer_orders(reducer)
    lines = pd.DataFrame({"order": orders, "amplitude [arcmin]": amplitude / ARCMIN})
    floor = 1e-9 * max(float(lines["amplitude [arcmin]"].max()), 1e-300)  # round-off lines
    lines = lines[(lines["order"] > 0) & (lines["amplitude [arcmin]"] > floor)]
    lines = lines.nlargest(10, "amplitude [arcmin]").rename(columns={"order": "order [-]"}
                                                            ).set_index("order [-]")
    names = {}
    for name, order in marks.items():
        names.setdefault(order, []).append(name)
    lines["marked as"] = [", ".join(names.get(float(o), [])) for o in lines.index]
    body = [f"<h1>Quasi-static LTCA: {html.escape(reducer.name)} at {result.torque:g} N*m</h1>",
            _summary_block("Answer", ltca_rows(result.summary(), reducer.rating.rated_torque)),
            "<p class='note'>Static equilibrium of the whole reducer at equally spaced input "
            "angles over one output revolution, one direction, constant output torque. "
            "TE = theta_in/i - theta_out. The mean TE is measured from the nominal assembly "
            "(lost motion plus wind-up: the paper's kind of index); the peak-to-peak is the "
            "catalogue's angular transmission error; the TE relative to the loaded state "
            "(TE minus its mean) is what a rig that zeroes its encoders while running "
            "sees.</p>",
            "<h2>Summary</h2>", _summary_table(result.summary()),
            "<h2>Transmission error over one output revolution</h2>",
            _png(te_revolution_plot(result)),
            "<h2>TE order spectrum</h2>",
            "<p class='note'>Amplitudes of the TE in orders of the output revolution, "
            "rectangular window over the whole revolution (exact at integer orders); the "
            "reducer's orders are marked (docs/catalogue_tests.md derives them).</p>",
            _png(order_spectrum_plot(orders, amplitude / ARCMIN, marks)),
            "<h3>Largest lines</h3>", _table(lines),
            "<h2>Pin load distribution</h2>",
            "<p class='note'>Contact force of every pin against the output angle, one map "
            "per disc.</p>", _png(pin_load_map(result)),
            "<h2>Parameters</h2>", _parameters_table(reducer)]
    return atomic_write_text(path, _page(f"rvsim ltca {reducer.name}", body))


def _budget_section(budget) -> list[str]:
    """The compliance budget (rvsim.quasistatic.budget) as a heading, a note and a table, the
    softest element first."""
    from .units import ARCMIN

    shares, stiffness = budget.shares, budget.element_stiffness
    rows = [{"element": budget.labels[i], "share [%]": 100.0 * shares[i],
             "own stiffness [N*m/arcmin]": stiffness[i] * ARCMIN if stiffness[i] > 0
             else float("nan"),
             "rigidity with it stiffened [N*m/arcmin]": budget.stiffened_rigidity[i] * ARCMIN}
            for i in budget.order()]
    return ["<h2>Compliance budget</h2>",
            f"<p class='note'>Each element {budget.factor:g} times stiffer in turn, everything "
            "else unchanged; share = (C - C<sub>i</sub>) / C of the torsional compliance C = "
            "1 / rigidity (secant 50-100 % of rated), own stiffness = 1 / (C - C<sub>i</sub>) "
            f"at the output. Rigidity {budget.rigidity * ARCMIN:.2f} N*m/arcmin; sum of the "
            f"shares {100.0 * (1.0 - budget.residual):.1f} %, residual "
            f"{100.0 * budget.residual:.1f} % (what a stiffened element keeps, load sharing "
            "of parallel elements; docs/model.md section 12).</p>",
            _table(pd.DataFrame(rows).set_index("element"))]


def write_hysteresis_report(result, reducer, path: str | Path, *, budget=None) -> Path:
    """Write an HTML page for one torque-reversal (hysteresis) ``result`` of ``reducer``, with
    its compliance ``budget`` (rvsim.quasistatic.budget) when given."""
    from .analysis.headline import hysteresis_rows
    from .plots import hysteresis_plot

    path = _target(path)
    summary = result.summary()
    rated = result.rated_torque
    body = [f"<h1>Torque-reversal test: {html.escape(reducer.name)}</h1>",
            _summary_block("Answer", hysteresis_rows(summary)),
            "<p class='note'>Input shaft locked; output torque 0 &rarr; -rated &rarr; 0 &rarr; "
            f"+rated &rarr; 0 &rarr; -rated, rated = {rated:g} N*m. Definitions of GB/T "
            "35089-2018: torsional rigidity = b/a, the secant between 50 % and 100 % of rated "
            "torque (both directions averaged); lost motion = the angle between the "
            "mid-points of the hysteresis width at +3 % and -3 % of rated; backlash = the "
            "free play crossed at 0 N*m; hysteresis loss = the loop width at 0 N*m after "
            "loading to rated and unloading.</p>",
            "<h2>Catalogue quantities</h2>", _summary_table(summary),
            *(_budget_section(budget) if budget is not None else []),
            "<h2>Torque-angle curve</h2>", _png(hysteresis_plot(result, rated)),
            "<h2>Parameters</h2>", _parameters_table(reducer)]
    return atomic_write_text(path, _page(f"rvsim hysteresis {reducer.name}", body))
