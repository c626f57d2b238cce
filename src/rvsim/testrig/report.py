"""HTML report of bench recordings, with the model beside them (``rvsim testrig --report``).

Per operating point: the numbers (measured, simulated, difference), the TE over the output
revolution per direction, the order spectra and the torque-reversal loop, measured and
simulated on the same axes.
"""

from __future__ import annotations

import html
import math
from pathlib import Path

import numpy as np
import pandas as pd

from .._files import atomic_write_text
from ..html import page as _page, png as _png, table as _table
from .analysis import ARCMIN, ARCSEC

__all__ = ["write_testrig_report"]

_ROWS = ("ate_pp_arcmin", "te_rms_arcsec", "forward_backward_offset_arcmin",
         "lost_motion_arcmin", "backlash_arcmin", "hysteresis_loss_arcmin",
         "torsional_rigidity_nm_per_arcmin", "efficiency_pct")    # % as everywhere else


def _te_figure(measured, simulated):
    from ..plots import pyplot

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.4))
    for source, style, result in (("measured", "-", measured), ("model", "--", simulated)):
        if result is None:
            continue
        for f in result.files:
            for d in f.directions or []:
                name = "forward" if d.direction > 0 else "backward"
                ax.plot(np.degrees(d.curve_angle), d.curve / ARCMIN, style, lw=0.9,
                        label=f"{source}, {name}")
    ax.set_xlabel("output angle [deg]")
    ax.set_ylabel("TE - mean [arcmin]")
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def _spectrum_figure(measured, simulated, marks):
    from ..plots import headroom, mark_orders, pyplot

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.4))
    lines = []
    for result in (measured, simulated):
        d = None if result is None else result.leading_direction()
        lines.append(None if d is None else d.spectrum())
    # up to a little beyond the highest of the leading lines
    leading = [] if lines[0] is None else list(
        lines[0][0][np.argsort(lines[0][1][1:])[::-1][:3] + 1])
    limit = 1.2 * max(leading + [2.0 * max(o for o in marks.values() if o < 100)])
    top = 0.0
    for (source, color, style), line in zip((("measured", "C0", "-"), ("model", "C1", "o")),
                                            lines):
        if line is None:
            continue
        orders, amplitude = line
        keep = (orders > 0) & (orders <= 1.25 * limit)
        top = max(top, float(amplitude[keep].max(initial=0.0)) / ARCSEC)
        if style == "-":
            ax.vlines(orders[keep], 0.0, amplitude[keep] / ARCSEC, color=color, lw=1.0,
                      label=source)
        else:
            shown = keep & (amplitude > 0.01 * amplitude[keep].max())
            ax.plot(orders[shown], amplitude[shown] / ARCSEC, "o", mfc="none", color=color,
                    ms=5, label=source)
    ax.set_xlabel("order of the output revolution [-]")
    ax.set_ylabel("TE amplitude [arcsec]")
    ax.grid(alpha=0.3, which="both")
    rows = mark_orders(ax, marks, limit=limit, style=":")
    headroom(ax, top, rows)
    ax.legend(fontsize="small", loc="center right")
    fig.tight_layout()
    return fig


def _loop_figure(measured, simulated):
    from ..plots import pyplot

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for source, style, result in (("measured", ".-", measured), ("model", "--", simulated)):
        if result is None:
            continue
        loop = next((f.loop for f in result.files if f.loop is not None), None)
        if loop is None:
            continue
        t, a, _ = loop
        # an encoder zero makes the angle's level arbitrary: both loops centred
        ax.plot(t, (a - 0.5 * (a.max() + a.min())) / ARCMIN, style, lw=0.8, ms=2,
                label=source)
    ax.set_xlabel("output torque [N*m]")
    ax.set_ylabel("output angle, centred [arcmin]")
    ax.legend(fontsize="small")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def _numbers(summary: dict) -> str:
    sim = summary.get("simulated") or {}
    diff = summary.get("difference") or {}
    rows = []
    for key in _ROWS:
        if summary.get(key) is None and sim.get(key) is None:
            continue
        rows.append({"quantity": key, "measured": summary.get(key, math.nan),
                     "model": sim.get(key, math.nan), "difference": diff.get(key, math.nan)})
    for name, value in (diff.get("te_curve_rms_arcsec") or {}).items():
        rows.append({"quantity": f"rms of TE curve difference, {name} [arcsec]",
                     "measured": math.nan, "model": math.nan, "difference": value})
    frame = pd.DataFrame(rows).set_index("quantity")
    return _table(frame.astype(object).where(frame.notna(), math.nan))


def write_testrig_report(results, reducer, path: str | Path) -> Path:
    """``results``: [(summary dict, measured PointResult, simulated PointResult or None)]."""
    from ..analysis.catalogue import reducer_orders

    from ..analysis.headline import testrig_rows
    from ..html import summary_block

    marks = reducer_orders(reducer)
    body = ["<h1>Test-bench data: " + html.escape(reducer.name) + "</h1>",
            summary_block("Answer", testrig_rows([s for s, _, _ in results])),
            "<p class='note'>TE = theta_in/i - theta_out over each complete output revolution "
            "of each direction, its mean removed (an encoder zero makes it arbitrary); the "
            "curves are revolution-synchronous averages; lost motion, backlash, hysteresis "
            "loss and rigidity as in GB/T 35089-2018 (docs/catalogue_tests.md). The model is "
            "the quasi-static engine at each point's output torque.</p>"]
    for summary, measured, simulated in results:
        point = ", ".join(f"{k} {v:g}" for k, v in summary["point"].items()) or "point"
        body.append(f"<h2>{html.escape(point)}</h2>")
        body.append("<p class='note'>files: " + html.escape(", ".join(summary["files"]))
                    + "</p>")
        body.append(_numbers(summary))
        for note in summary.get("notes", []) + ([summary["note"]] if "note" in summary else []):
            body.append("<p class='note'>note: " + html.escape(note) + "</p>")
        if summary.get("ate_pp_arcmin") is not None:
            body += ["<h3>Transmission error over one output revolution</h3>",
                     _png(_te_figure(measured, simulated)),
                     "<h3>Order spectrum (forward, if recorded)</h3>",
                     _png(_spectrum_figure(measured, simulated, marks))]
        if summary.get("lost_motion_arcmin") is not None:
            body += ["<h3>Torque-reversal loop</h3>", _png(_loop_figure(measured, simulated))]
    return atomic_write_text(Path(path), _page(f"rvsim testrig {reducer.name}", body))
