"""report.html of a tolerance study (self-contained: figures embedded) and its figures."""

from __future__ import annotations

import html
from pathlib import Path

import numpy as np
import pandas as pd

from .._files import atomic_write_text
from .engine import METRICS
from .montecarlo import failure_line, share_text, torque_text

__all__ = ["write_tolerance_report", "distribution_figure", "sobol_figure",
           "write_allocation_report"]


def distribution_figure(name: str, x: np.ndarray, stats: dict, fig=None):
    """Histogram and empirical cumulative distribution of one metric, p5/p50/p95 marked
    (on ``fig``, a new figure if None)."""
    from ..plots import pyplot

    if fig is None:
        fig = pyplot().figure(figsize=(10, 3.4))
    left, right = fig.subplots(1, 2)
    x = np.sort(x[np.isfinite(x)])
    if x.size:
        left.hist(x, bins=min(50, max(5, x.size // 10)), color="#4477aa")
        right.plot(x, np.arange(1, x.size + 1) / x.size, color="#4477aa")
        for key, style in (("p5", ":"), ("p50", "--"), ("p95", "-")):
            if stats.get(key) is not None:
                for ax in (left, right):
                    ax.axvline(stats[key], color="#cc3311", linestyle=style, label=key)
    left.set_xlabel(name)
    left.set_ylabel("reducers")
    right.set_xlabel(name)
    right.set_ylabel("cumulative share")
    if x.size:             # every reducer bound or failed: nothing drawn, no legend
        right.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    return fig


def sobol_figure(metric: str, indices: dict):
    """Bar chart of S1 and ST with their 95 % confidence intervals."""
    from ..plots import pyplot

    plt = pyplot()
    names = list(indices)
    pos = np.arange(len(names))
    fig, ax = plt.subplots(figsize=(10, 3.4))
    s1 = [indices[n]["S1"] for n in names]
    st = [indices[n]["ST"] for n in names]
    ax.bar(pos - 0.2, s1, 0.4, yerr=[indices[n]["S1_conf"] for n in names], label="S1")
    ax.bar(pos + 0.2, st, 0.4, yerr=[indices[n]["ST_conf"] for n in names], label="ST")
    ax.set_xticks(pos, names, rotation=30, ha="right", fontsize=8)
    ax.set_ylabel("Sobol index")
    ax.set_title(metric)
    ax.legend()
    fig.tight_layout()
    return fig


def write_tolerance_report(folder: Path, summary: dict, values: dict, status) -> Path:
    from ..analysis.headline import tolerance_rows
    from ..html import page as _page, png as _png, summary_block, table as _table

    body = [f"<h1>Tolerance study: {html.escape(summary['study'])}</h1>",
            summary_block("Answer", tolerance_rows(summary)),
            f"<p>{summary['samples']} reducers ({html.escape(summary['reducer'])}) drawn from "
            f"the tolerances (seed {summary['seed']}); {summary['ok']} analysed, "
            f"{summary['binds']} bind on assembly (binding share "
            f"{share_text(summary['binding_share'])}), {summary['failed']} failed"
            f"{html.escape(': ' + failure_line(summary) if summary['failed'] else '')}. "
            f"Transmission error at {html.escape(torque_text(summary))} over one output "
            "revolution "
            f"({summary['positions']} positions); lost motion and rigidity from the "
            "torque-reversal test (quasi-static engine).</p>",
            "<h2>Tolerances</h2>",
            _table(pd.DataFrame([{**t, "orders": ", ".join(map(str, t.get("orders") or ()))}
                                 for t in summary["tolerances"]]), index=False),
            "<h2>Distributions</h2>"]
    rows = {name: {k: m[k] for k in ("mean", "std", "p5", "p50", "p95")}
            for name, m in summary["metrics"].items()}
    frame = pd.DataFrame(rows).T.astype(float)
    frame.index.name = "metric"
    body.append(_table(frame))
    for name, x in values.items():
        body.append(f"<h3>{html.escape(name)}</h3><p class='note'>"
                    f"{html.escape(METRICS.get(name, ('', ''))[1])}</p>")
        body.append(_png(distribution_figure(name, x, summary["metrics"][name])))
    if summary.get("sobol"):
        body.append(f"<h2>Sobol indices</h2><p>{summary['sobol_samples']} reducers of the "
                    "Saltelli-Sobol design (SALib), 95 % bootstrap intervals; "
                    f"{summary['sobol_imputed']} without a value given the mean.</p>")
        for note in summary.get("sobol_notes", []):
            body.append(f"<p class='note'>{html.escape(note)}</p>")
        for metric, indices in summary["sobol"].items():
            body.append(_png(sobol_figure(metric, indices)))
            top = summary["sobol_second_order"][metric][:5]
            pairs = pd.DataFrame([{"pair": " x ".join(p["pair"]), "S2": p["S2"],
                                   "S2_conf": p["S2_conf"]} for p in top])
            body.append(f"<p>strongest interactions of {html.escape(metric)}:</p>"
                        + _table(pairs, index=False))
    path = Path(folder) / "report.html"
    atomic_write_text(path, _page(f"rvsim tolerance: {summary['study']}", body))
    return path


def write_allocation_report(folder: Path, result: dict) -> Path:
    from ..analysis.headline import allocation_rows
    from ..html import page as _page, summary_block, table as _table
    from .allocation import Target

    met = [t.get("achieved") is not None and Target(
        t["metric"], t.get("percentile"), t["limit"], t["target"]).margin(t["achieved"]) >= 0.0
        for t in result["targets"]]

    body = [f"<h1>Tolerance allocation: {html.escape(result['study'])}</h1>",
            summary_block("Answer", allocation_rows(result, met)),
            f"<p>status: <b>{html.escape(result['status'])}</b>; relative cost "
            f"{result['cost']:.4g} (all tolerances as given: {result['cost_start']:.4g}); "
            f"{result['evaluations']} Monte Carlo evaluations of {result['samples']} reducers "
            "each (common random numbers).</p>",
            *(f"<p class='note'>{html.escape(n)}</p>" for n in result.get("notes", [])),
            "<h2>Tolerances</h2>",
            _table(pd.DataFrame(result["tolerances"]), index=False),
            "<h2>Targets</h2>",
            _table(pd.DataFrame(result["targets"]), index=False)]
    path = Path(folder) / "report.html"
    atomic_write_text(path, _page(f"rvsim allocate: {result['study']}", body))
    return path


def rebuild_tolerance_report(folder: str | Path) -> Path:
    """report.html of a tolerance folder again, from its summary.json and results.csv (the
    Monte Carlo reducers; ``rvsim report`` on a folder of ``rvsim tolerance``)."""
    import json

    from ..errors import InputFileError

    folder = Path(folder)
    try:
        summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
        frame = pd.read_csv(folder / "results.csv")
        status = frame["status"].to_numpy(dtype=object)
        values = {m: pd.to_numeric(frame[m], errors="coerce").to_numpy(dtype=float)
                  for m in summary["metrics"]}
        return write_tolerance_report(folder, summary, values, status)
    except (ValueError, KeyError, TypeError, AttributeError, pd.errors.ParserError) as exc:
        # a summary.json or results.csv that is not what rvsim tolerance writes
        raise InputFileError(f"{folder}: damaged tolerance study files ({type(exc).__name__}: "
                             f"{exc}); run 'rvsim tolerance' on it again") from None
    except OSError as exc:
        raise InputFileError(f"{folder}: cannot read or write the tolerance study files "
                             f"({exc.strerror or exc})") from None
