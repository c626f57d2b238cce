"""report.html of a tolerance study (self-contained: figures embedded) and its figures."""

from __future__ import annotations

import html
import math
from pathlib import Path

import numpy as np
import pandas as pd

from .._files import atomic_write_text
from .engine import METRICS
from .montecarlo import failure_line, share_text, torque_text

__all__ = ["write_tolerance_report", "distribution_figure", "sobol_figure", "sobol_table",
           "sobol_advice", "write_allocation_report"]


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


def _unresolved(index: float, conf: float) -> bool:
    """An index whose 95 % interval is wider than the index: zero is inside it (an index of
    exactly 0 with no interval, an error the metric does not depend on, is resolved; a NaN
    interval is not)."""
    return not conf <= abs(index)


def sobol_figure(metric: str, indices: dict):
    """Bar chart of S1 and ST with their 95 % confidence intervals; an index whose interval
    is wider than itself (:func:`_unresolved`) drawn hatched and pale."""
    from ..plots import plain, pyplot

    plt = pyplot()
    names = list(indices)
    pos = np.arange(len(names))
    fig, ax = plt.subplots(figsize=(10, 3.4))
    for key, shift, color in (("S1", -0.2, "C0"), ("ST", 0.2, "C1")):
        value = np.array([indices[n][key] for n in names])
        conf = np.array([indices[n][f"{key}_conf"] for n in names])
        weak = np.array([_unresolved(v, c) for v, c in zip(value, conf)])
        for mask, label, style in ((~weak, key, {}),
                                   (weak, f"{key}, interval wider than the index",
                                    {"alpha": 0.35, "hatch": "//"})):
            if mask.any():
                ax.bar(pos[mask] + shift, value[mask], 0.4, yerr=conf[mask], color=color,
                       label=label, capsize=2, **style)
    ax.axhline(0.0, color="0.4", lw=0.6)
    ax.set_xticks(pos, [plain(n) for n in names], rotation=30, ha="right", fontsize=8)
    ax.set_ylabel("Sobol index [-]")
    ax.legend(fontsize="x-small", ncol=4, loc="lower center", bbox_to_anchor=(0.5, 1.0),
              title=plain(metric), title_fontsize="small", frameon=False)
    fig.tight_layout()
    return fig


def sobol_table(indices: dict) -> pd.DataFrame:
    """S1 and ST [-] with their 95 % half-intervals, each flagged when the interval is wider
    than the index or the index is negative (sampling error: a true index is >= 0)."""
    rows = []
    for name, i in indices.items():
        flags = [f"{k}: interval wider than the index" for k in ("S1", "ST")
                 if _unresolved(i[k], i[f"{k}_conf"])]
        flags += [f"{k} < 0: sampling error" for k in ("S1", "ST") if i[k] < 0]
        rows.append({"error": name, "S1 [-]": round(i["S1"], 3),
                     "S1 +-95 % [-]": round(i["S1_conf"], 3), "ST [-]": round(i["ST"], 3),
                     "ST +-95 % [-]": round(i["ST_conf"], 3), "flag": "; ".join(flags)})
    return pd.DataFrame(rows).set_index("error")


def sobol_advice(indices: dict, base: int, errors: int, worth: float = 0.05) -> str:
    """Advice on the Sobol base sample size: the bootstrap intervals shrink as 1/sqrt(base)
    (Saltelli et al. 2010), so an index S of interval c needs the base times (2 c / S)^2 for
    its interval to be half the index; asked for the total indices of at least ``worth``
    (smaller ones are read as 'about zero').  Empty when every such index is resolved."""
    need = [(2.0 * i["ST_conf"] / i["ST"]) ** 2 for i in indices.values()
            if i["ST"] >= worth and _unresolved(i["ST"], 2.0 * i["ST_conf"])]
    if not need:
        return ""
    factor = max(need)
    target = int(min(65536, 2 ** math.ceil(math.log2(max(2.0, base * factor)))))
    return (f"{len(need)} total index(es) of at least {worth:g} have an interval wider than "
            f"half the index: intervals shrink as 1/sqrt(base); --sobol {target} (now "
            f"{base}: {target * (2 * errors + 2)} reducers) would bring them to half the "
            "index.")


def _unit(name: str) -> str:
    """The user unit of toleranced error ``name`` (spec.Tolerance.unit), "" if unknown."""
    from .spec import FEATURES, SPECS

    if name in FEATURES:
        return FEATURES[name][0]
    return SPECS[name].unit if name in SPECS else ""


def _metric_unit(name: str) -> str:
    """The unit in brackets at the end of the metric's description (engine.METRICS)."""
    text = METRICS.get(name, ("", ""))[1]
    return text[text.rindex("[") + 1:-1] if text.endswith("]") else "-"


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
            _table(pd.DataFrame([{"name": t["name"], "tolerance": t["tolerance"],
                                  "unit": _unit(t["name"]),
                                  "distribution": t["distribution"], "per": t["per"],
                                  "orders [-]": ", ".join(map(str, t.get("orders") or ()))}
                                 for t in summary["tolerances"]]), index=False),
            "<h2>Distributions</h2>"]
    rows = {name: {k: m[k] for k in ("mean", "std", "p5", "p50", "p95")}
            for name, m in summary["metrics"].items()}
    frame = pd.DataFrame(rows).T.astype(float)
    frame.insert(0, "unit", [_metric_unit(name) for name in frame.index])
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
        base = summary["sobol_samples"] // (2 * max(1, len(summary["tolerances"])) + 2)
        for metric, indices in summary["sobol"].items():
            body.append(f"<h3>{html.escape(metric)}</h3>")
            if metric == "binds":
                body.append("<p class='note'>binds is a 0/1 outcome: its indices rest on the "
                            "few reducers that bind and say which errors make a reducer bind, "
                            "not shares of a spread; read them with their intervals.</p>")
            body.append(_png(sobol_figure(metric, indices)))
            advice = sobol_advice(indices, base, len(indices))
            if advice:
                body.append(f"<p class='miss'>{html.escape(advice)}</p>")
            body.append("<div class='wide'>" + _table(sobol_table(indices)) + "</div>")
            top = summary["sobol_second_order"][metric][:5]
            pairs = pd.DataFrame([{"pair": " x ".join(p["pair"]), "S2 [-]": round(p["S2"], 3),
                                   "S2 +-95 % [-]": round(p["S2_conf"], 3),
                                   "flag": ("interval wider than the index"
                                            if _unresolved(p["S2"], p["S2_conf"]) else "")}
                                  for p in top])
            body.append(f"<p>strongest interactions of {html.escape(metric)}:</p>"
                        + _table(pairs, index=False))
    path = Path(folder) / "report.html"
    atomic_write_text(path, _page(f"rvsim tolerance: {summary['study']}", body))
    return path


def _feasible(result: dict, achieved: dict) -> bool:
    from .allocation import Target

    return all(achieved.get(t["target"]) is not None and Target(
        t["metric"], t.get("percentile"), t["limit"], t["target"]).margin(
            achieved[t["target"]]) >= 0.0 for t in result["targets"])


def convergence_figure(result: dict):
    """The search, evaluation by evaluation: relative cost (1 = as given; filled where every
    target is met, the cheapest such so far as a line) and each target's achieved value over
    its limit (1 = on the limit; shares of binding or failing reducers left out)."""
    from ..plots import plain, pyplot

    plt = pyplot()
    history = result["history"]
    n = np.arange(1, len(history) + 1)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 5), sharex=True)
    cost = np.array([h["cost"] for h in history]) / result["cost_start"]
    ok = np.array([_feasible(result, h["achieved"]) for h in history])
    top.plot(n[ok], cost[ok], "o", color="C2", ms=4, label="meets every target")
    top.plot(n[~ok], cost[~ok], "o", mfc="none", color="C3", ms=4, label="misses a target")
    best = np.minimum.accumulate(np.where(ok, cost, np.inf))
    top.step(n[np.isfinite(best)], best[np.isfinite(best)], where="post", color="C2", lw=1,
             label="cheapest so far")
    top.set_ylabel("relative cost [-]\n(1 = as given)")
    top.legend(fontsize="x-small")
    for t in result["targets"]:
        if t.get("percentile") is None or not t["limit"]:
            continue
        ratio = [h["achieved"].get(t["target"], np.nan) / t["limit"] for h in history]
        bottom.plot(n, ratio, ".-", lw=0.8, label=plain(t["target"]))
    bottom.axhline(1.0, color="0.3", lw=0.8, ls="--")
    bottom.set_ylabel("achieved / target [-]")
    bottom.set_xlabel("Monte Carlo evaluation [-] (1: as given, 2: all at the tightest)")
    if bottom.lines[:-1]:
        bottom.legend(fontsize="x-small")
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def before_after_figure(result: dict):
    """Left: each tolerance as given and as allocated, on a log axis inside its cost bounds
    (grey); right: each target's achieved value over its limit as given and as allocated."""
    from ..plots import plain, pyplot

    plt = pyplot()
    tol = result["tolerances"]
    targets = [t for t in result["targets"] if t.get("percentile") is not None and t["limit"]]
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 0.9 + 0.32 * max(len(tol), 4)),
                                      gridspec_kw={"width_ratios": [3, 2]})
    y = np.arange(len(tol))
    left.barh(y, [t["loosest"] - t["tightest"] for t in tol], left=[t["tightest"] for t in tol],
              color="0.9", label="cost bounds")
    left.plot([t["given"] for t in tol], y, "o", color="C0", label="as given")
    left.plot([t["allocated"] for t in tol], y, "D", mfc="none", color="C1", label="allocated")
    left.set_yticks(y, [plain(f"{t['name']} [{t['unit']}]") for t in tol], fontsize=7)
    left.set_xscale("log")
    left.set_xlabel("tolerance [unit of each row]")
    left.invert_yaxis()
    left.legend(fontsize="x-small", loc="lower right")
    first = result["history"][0]["achieved"] if result.get("history") else {}
    z = np.arange(len(targets))
    right.barh(z - 0.2, [first.get(t["target"], np.nan) / t["limit"] for t in targets], 0.4,
               color="C0", label="as given")
    right.barh(z + 0.2, [t["achieved"] / t["limit"] for t in targets], 0.4, color="C1",
               label="allocated")
    right.axvline(1.0, color="0.3", lw=0.8, ls="--")
    right.set_yticks(z, [plain(t["target"]) for t in targets], fontsize=7)
    right.invert_yaxis()
    right.set_xlabel("achieved / target [-]")
    right.legend(fontsize="x-small")
    for ax in (left, right):
        ax.grid(alpha=0.3, axis="x")
    fig.tight_layout()
    return fig


def _older_status(result: dict) -> str:
    """The plain status of an allocation.json written before ``status_text`` (its status was
    "ok" or "stopped: " and SciPy's message)."""
    from .allocation import status_text

    status = str(result.get("status", ""))
    evaluations = int(result.get("evaluations", 0))
    if status == "ok":
        return status_text(True, 0, None, evaluations)
    if "MAXFUN" in status:
        return status_text(False, 0, None, evaluations)
    return status_text(False, 0, 1 << 30, evaluations) + (f" ({status})" if status else "")


def write_allocation_report(folder: Path, result: dict) -> Path:
    from ..analysis.headline import allocation_rows
    from ..html import page as _page, png as _png, summary_block, table as _table
    from .allocation import Target

    met = [t.get("achieved") is not None and Target(
        t["metric"], t.get("percentile"), t["limit"], t["target"]).margin(t["achieved"]) >= 0.0
        for t in result["targets"]]
    status = result.get("status_text") or _older_status(result)
    columns = {"name": "name", "unit": "unit", "given": "given", "allocated": "allocated",
               "tightest": "tightest", "loosest": "loosest", "weight": "cost weight [-]",
               "exponent": "cost exponent [-]"}
    tolerances = pd.DataFrame(result["tolerances"])
    tolerances = tolerances[[c for c in columns if c in tolerances]].rename(columns=columns)
    targets = pd.DataFrame([{"target": t["target"], "limit": t["limit"],
                             "achieved as given": (result["history"][0]["achieved"].get(
                                 t["target"]) if result.get("history") else None),
                             "achieved": t["achieved"], "at the tightest": t["at_tightest"]}
                            for t in result["targets"]])
    body = [f"<h1>Tolerance allocation: {html.escape(result['study'])}</h1>",
            summary_block("Answer", allocation_rows(result, met),
                          [f"<b>{html.escape(status[0].upper() + status[1:])}</b>."]),
            f"<p>Relative cost {result['cost']:.4g} (all tolerances as given: "
            f"{result['cost_start']:.4g}); {result['evaluations']} Monte Carlo evaluations of "
            f"{result['samples']} reducers each (common random numbers).</p>",
            *(f"<p class='note'>{html.escape(n)}</p>" for n in result.get("notes", [])),
            "<h2>Before and after</h2>"]
    if result.get("history"):
        body += [_png(before_after_figure(result)), "<h2>Convergence</h2>",
                 _png(convergence_figure(result))]
    body += ["<h2>Tolerances</h2>",
             "<p class='note'>given, allocated, tightest and loosest in each row's unit.</p>",
             _table(tolerances, index=False),
             "<h2>Targets</h2>",
             "<p class='note'>limit and achieved values in the metric's unit (arcmin, "
             "N*m/arcmin; shares as fractions [-]).</p>",
             _table(targets, index=False)]
    if result.get("optimizer_message"):
        body.append(f"<p class='note'>SciPy COBYLA's message: "
                    f"{html.escape(result['optimizer_message'])}</p>")
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
