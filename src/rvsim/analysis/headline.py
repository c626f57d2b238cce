"""The headline figures every report opens with (issue 34 item 2), as rows of text.

Each function takes a command's summary (the dict its ``--json`` prints, or a study's
analysis) and returns rows (quantity, this run's figure, the class / target / reference,
verdict) for :func:`rvsim.html.summary_block`.  The class's figures come from
src/rvsim/data/trust.csv (:func:`rvsim.analysis.trust.catalogue_figure`), the one source of
the "how far to trust it" figures; nothing here holds a number of its own.
"""

from __future__ import annotations

import math

from .trust import catalogue_figure, trust_rows

__all__ = ["ltca_rows", "hysteresis_rows", "efficiency_rows", "run_rows", "tolerance_rows",
           "allocation_rows", "grid_rows", "testrig_rows", "study_rows", "confirmation_command"]

NA = "not available"


def _num(value, digits: int = 4, unit: str = "") -> str:
    """``value`` to ``digits`` significant digits with ``unit``; "not available" if missing."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return NA
    return f"{float(value):.{digits}g}" + (f" {unit}" if unit else "")


def _finite(value) -> bool:
    return value is not None and isinstance(value, (int, float)) and math.isfinite(value)


def _class(key: str) -> str:
    return catalogue_figure(key)["published"]


def _against_limit(value, key: str) -> str:
    """Verdict of ``value`` against the class's upper limit (and typical range if any)."""
    c = catalogue_figure(key)
    if not _finite(value) or c["limit"] is None:
        return "-"
    if value > c["limit"]:
        return f"above the class's {c['limit']:g} {c['unit']}"
    if c["low"] is not None and value < c["low"]:
        return f"within; below the typical {c['low']:g}-{c['high']:g} {c['unit']}"
    return "within the class"


def _torque_row(torque, rated) -> tuple:
    share = f"{100.0 * abs(torque) / rated:.0f} % of rated" if _finite(rated) and rated else "-"
    return ("output torque", _num(torque, 4, "N*m"), _num(rated, 4, "N*m") + " rated", share)


def _static_limit(summary: dict) -> str:
    """The static contact-stress limit of the run's reducer (``rating.static_contact_stress``,
    ISO 76 by default), "-" when the summary has none."""
    limit = summary.get("static_contact_stress_mpa")
    return "-" if limit is None else (_num(limit, 4, "MPa") + " static limit "
                                      "(rating.static_contact_stress, ISO 76 by default)")


def ltca_rows(summary: dict, rated_torque: float | None) -> list[tuple]:
    """``rvsim ltca``: ATE and TE peak-to-peak, mean TE, largest contact stress."""
    ate = summary.get("ate_arcmin")
    return [_torque_row(summary.get("torque_nm"), rated_torque),
            ("angular transmission error (ATE, p-p over one output revolution)",
             _num(ate, 4, "arcmin"), _class("ate_pp"),
             "reference only (another size)" if _finite(ate) else "-"),
            ("TE peak-to-peak over the positions", _num(summary.get("te_pp_arcmin"), 4,
                                                        "arcmin"), "-", "-"),
            ("mean TE (lost motion plus wind-up)", _num(summary.get("te_mean_arcmin"), 4,
                                                         "arcmin"), "-", "-"),
            ("largest pin-disc contact stress (Hertz)",
             _num(summary.get("max_contact_stress_mpa"), 4, "MPa"), _static_limit(summary),
             summary.get("contact_stress_verdict", "-")),
            ("status", summary.get("status", NA), "ok", "")]


def hysteresis_rows(summary: dict) -> list[tuple]:
    """``rvsim hysteresis``: the catalogue quantities against the class."""
    rigidity = summary.get("torsional_rigidity_nm_per_arcmin")
    c = catalogue_figure("rigidity")
    ratio = (f"{rigidity / c['low']:.2f} x the class "
             f"({'stiffer' if rigidity >= c['low'] else 'softer'})" if _finite(rigidity)
             else "-")
    rows = [("torsional rigidity", _num(rigidity, 4, "N*m/arcmin"), c["published"], ratio)]
    for key, name in (("lost_motion", "lost_motion_arcmin"),
                      ("hysteresis_loss", "hysteresis_loss_arcmin")):
        value = summary.get(name)
        rows.append((catalogue_figure(key)["quantity"], _num(value, 3, "arcmin"),
                     _class(key), _against_limit(value, key)))
    rows.append(("backlash", _num(summary.get("backlash_arcmin"), 3, "arcmin"), "-", "-"))
    rows.append(("status", summary.get("status", NA), "ok", ""))
    return rows


def efficiency_rows(frame, summary: dict, rated_torque: float) -> list[tuple]:
    """``rvsim efficiency``: efficiency at the torque nearest the rated one, each speed
    (``frame``: the result's to_frame()), running and starting torque."""
    rows = []
    if len(frame):
        nearest = frame.loc[(frame["output_torque_nm"] - rated_torque).abs().idxmin(),
                            "output_torque_nm"]
        for _, row in frame[frame["output_torque_nm"] == nearest].iterrows():
            rows.append((f"efficiency at {nearest:g} N*m, {row['input_speed_rpm']:g} rpm input",
                         _num(100.0 * row["efficiency"], 4, "%"), _class("efficiency_rated"),
                         "no catalogue figure to compare"))
    rows.append(("no-load running torque at the input",
                 _num(summary.get("no_load_running_torque_nm"), 3, "N*m"),
                 _class("no_load_torque"), "-"))
    rows.append(("starting torque at the input", _num(summary.get("starting_torque_nm"), 3,
                                                      "N*m"), _class("starting_torque"), "-"))
    rows.append(("status", summary.get("status", NA), "ok", ""))
    return rows


def run_rows(summary: dict) -> list[tuple]:
    """``rvsim simulate``: the TE indices of the steady window against the paper's range."""
    paper = {r["key"]: r for r in trust_rows("paper")}["paper_te_mean"]
    return [("mean TE, steady window", _num(summary.get("te_mean_arcmin"), 4, "arcmin"),
             "paper's 36 runs: " + paper["published"].split(" (")[0],
             "model/paper " + paper["ratio"] + " on the paper's runs"),
            ("TE peak-to-peak, steady window", _num(summary.get("te_pp_arcmin"), 4, "arcmin"),
             "-", "-"),
            ("ATE (p-p over one output revolution)", _num(summary.get("ate_arcmin"), 4,
                                                           "arcmin"), _class("ate_pp"), "-"),
            ("largest pin force", _num(summary.get("max_pin_force_n"), 4, "N"), "-", "-"),
            ("status", summary.get("status", NA), "ok", "")]


def tolerance_rows(summary: dict) -> list[tuple]:
    """``rvsim tolerance``: the percentiles against the class (no target: ``rvsim allocate
    --target`` sets one)."""
    metrics = summary.get("metrics", {})
    rows = []

    def get(metric, key):
        return (metrics.get(metric) or {}).get(key)

    if "ate_arcmin" in metrics:
        rows.append(("ATE p95", _num(get("ate_arcmin", "p95"), 4, "arcmin"), _class("ate_pp"),
                     "no target set (rvsim allocate --target ate_p95=...)"))
    if "lost_motion_arcmin" in metrics:
        value = get("lost_motion_arcmin", "p95")
        rows.append(("lost motion p95", _num(value, 3, "arcmin"), _class("lost_motion"),
                     _against_limit(value, "lost_motion")))
    if "torsional_rigidity_nm_per_arcmin" in metrics:
        value = get("torsional_rigidity_nm_per_arcmin", "p5")
        c = catalogue_figure("rigidity")
        rows.append(("torsional rigidity p5", _num(value, 4, "N*m/arcmin"), c["published"],
                     f"{value / c['low']:.2f} x the class" if _finite(value) else "-"))
    share = summary.get("binding_share")
    rows.append(("reducers that bind on assembly",
                 _num(100.0 * share, 3, "%") if _finite(share) else NA, "-", "-"))
    return rows


def allocation_rows(result: dict, met: list[bool]) -> list[tuple]:
    """``rvsim allocate``: each target against what the found tolerances achieve (``met``:
    whether each target is met, by the allocation's own test)."""
    rows = []
    for t, ok in zip(result.get("targets", []), met):
        rows.append((f"target {t['target']}", _num(t.get("achieved"), 4),
                     _num(t.get("limit"), 4), "met" if ok else "not met"))
    rows.append(("relative cost (1 = the tolerances as given)",
                 _num(result["cost"] / result["cost_start"], 3)
                 if result.get("cost_start") else NA, "-", "-"))
    return rows


def grid_rows(table, summary: dict) -> list[tuple]:
    """``rvsim grid``: the largest ATE and where, resonances."""
    ok = table[table["status"] == "ok"] if "status" in table else table
    rows = []
    if len(ok) and ok["ate_arcmin"].notna().any():
        worst = ok.loc[ok["ate_arcmin"].idxmax()]
        rows.append(("largest ATE over the grid", _num(worst["ate_arcmin"], 4, "arcmin"),
                     _class("ate_pp"), f"at {worst['input_speed_rpm']:g} rpm, "
                     f"{worst['output_torque_nm']:g} N*m"))
    if "resonance" in ok:
        hits = int(ok["resonance"].astype(bool).sum())
        rows.append(("points with an order in resonance", str(hits), "0",
                     "none" if hits == 0 else "see the Campbell diagram"))
    rows.append(("points finished", f"{len(ok)} of {len(table)}", "-", ""))
    return rows


def testrig_rows(results: list) -> list[tuple]:
    """``rvsim testrig``: each point's measured figures beside the model's (``results``: the
    summaries)."""
    rows = []
    for summary in results:
        point = ", ".join(f"{k} {v:g}" for k, v in summary.get("point", {}).items()) or "point"
        sim = summary.get("simulated") or {}
        for key, label, unit in (("ate_pp_arcmin", "ATE", "arcmin"),
                                 ("lost_motion_arcmin", "lost motion", "arcmin"),
                                 ("torsional_rigidity_nm_per_arcmin", "torsional rigidity",
                                  "N*m/arcmin")):
            if summary.get(key) is None:
                continue
            model = sim.get(key)
            rows.append((f"{label} ({point})", _num(summary[key], 4, unit) + " measured",
                         ("model " + _num(model, 4, unit)) if model is not None else
                         "model not run (--compare)",
                         f"model/measured {model / summary[key]:.2f}"
                         if _finite(model) and _finite(summary[key]) and summary[key] else "-"))
    return rows


def confirmation_command(definition: dict, optimum: dict) -> str:
    """The ``rvsim`` line that runs a study's optimum once (the confirmation run)."""
    command = "ltca" if definition.get("engine") == "quasi-static" else "simulate"
    parts = [f"rvsim {command} --params {definition['reducer']}"]
    parts += [f"--set {k}={v}" for k, v in definition.get("fixed") or []]
    for f in definition["factors"]:
        level = optimum.get(f["label"])
        if level is None or not f.get("levels"):
            continue
        parts.append(f"--set {f['parameter']}={f['levels'][int(level) - 1]}")
    if command == "simulate" and definition.get("scheme"):
        parts.append(f"--scheme {definition['scheme']}")
    return " ".join(parts)


def study_rows(definition: dict, analysis: dict, significant: list[str], units: dict,
               predicted: str) -> list[tuple]:
    """A study: factor order, significant factors, the optimum in real values with units,
    the predicted response.  ``units``: parameter -> unit."""
    rows = [("factor order by range", analysis.get("order") or "none (constant response)",
             "-", "-"),
            ("significant factors", ", ".join(significant) or "none", "-",
             "-" if definition.get("noise") else
             "a deterministic model's error term is its interactions, not noise")]
    for f in definition["factors"]:
        level = analysis.get("optimum", {}).get(f["label"])
        if level is None or not f.get("levels"):
            continue
        value = f["levels"][int(level) - 1]
        unit = units.get(f["parameter"], "")
        rows.append((f"optimum {f['label']} ({f['parameter']})",
                     f"{value} {unit}".strip(), f"level {level}",
                     "significant" if f["label"] in significant else ""))
    rows.append(("predicted response at the optimum", predicted, "-",
                 "confirm with the run below"))
    return rows
