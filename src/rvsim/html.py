"""HTML building blocks of rvsim's self-contained reports: one page, tables, figures embedded
as PNG data, no network requests (issue 31 step 5: moved out of :mod:`rvsim.report` unchanged,
so that the reports of studies, tolerance runs, test-rig fits and efficiency maps share them
without reaching into another module's private names).

Layer "figures and HTML" (docs/architecture.md): imports only the foundation and, inside the
functions, :mod:`rvsim.plots` (figures) and :mod:`rvsim.parameters` (the parameters table).
"""

from __future__ import annotations

import base64
import html
import math
from pathlib import Path

import numpy as np
import pandas as pd

from .errors import InputFileError

__all__ = ["page", "table", "png", "png_bytes", "parameters_table", "target", "CSS",
           "summary_block", "trust_box"]

#: the style sheet of every report page
CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:2em auto;
max-width:1100px;color:#222;padding:0 1em}
h1{font-size:1.6em}h2{font-size:1.25em;border-bottom:1px solid #ccc;padding-bottom:.2em;
margin-top:2em}table{border-collapse:collapse;font-size:.85em;margin:.5em 0;
display:block;overflow-x:auto;max-width:100%}.wide{overflow-x:auto}
th,td{border:1px solid #ccc;padding:.2em .5em;text-align:right}th{background:#f3f3f3}
td.l,th.l{text-align:left}.sig{font-weight:bold;background:#fff3cd}img{max-width:100%}
.note{color:#555;font-size:.9em}.summary td{text-align:left}
#summary{border:2px solid #2b6cb0;border-radius:6px;padding:.3em 1em .8em;margin:1em 0;
background:#f7fbff}#summary h2{margin-top:.4em;border:0}#summary table{font-size:.95em}
#summary th{text-align:left}
.trust{font-size:.85em;color:#333}.trust summary{cursor:pointer}
.ok{color:#1a7f37}.miss{color:#b42318}
"""


def png(fig) -> str:
    """A matplotlib figure as an ``<img>`` element with its PNG inline."""
    from .plots import figure_to_png

    return png_bytes(figure_to_png(fig))


def png_bytes(png: bytes) -> str:
    """PNG bytes as an ``<img>`` element (data URL)."""
    data = base64.b64encode(png).decode("ascii")
    return f'<img alt="figure" src="data:image/png;base64,{data}">'


def table(frame: pd.DataFrame, *, index: bool = True, highlight=None) -> str:
    """``frame`` as an HTML table (numbers to 4 significant digits, right-aligned; text
    escaped); rows whose index is in ``highlight`` are marked."""
    rows = []
    head = ([f'<th class="l">{html.escape(str(frame.index.name or ""))}</th>'] if index else [])
    head += [f"<th>{html.escape(str(c))}</th>" for c in frame.columns]
    rows.append("<tr>" + "".join(head) + "</tr>")
    for idx, row in frame.iterrows():
        cls = ' class="sig"' if highlight and idx in highlight else ""
        # a number in the index as it reads (1500, not 1500.0)
        label = f"{idx:g}" if isinstance(idx, (float, np.floating)) else str(idx)
        cells = [f'<td class="l">{html.escape(label)}</td>'] if index else []
        for value in row:
            numeric = isinstance(value, (int, float, np.number)) and not isinstance(value, bool)
            if isinstance(value, float):
                text = "" if math.isnan(value) else f"{value:.4g}"
            else:
                text = str(value)
            align = "" if numeric else ' class="l"'
            cells.append(f"<td{align}>{html.escape(text)}</td>")
        rows.append(f"<tr{cls}>" + "".join(cells) + "</tr>")
    return "<table>" + "".join(rows) + "</table>"


def page(title: str, body: list[str]) -> str:
    """A complete HTML page of the ``body`` fragments, with the report style sheet."""
    return (f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>"
            f"{html.escape(title)}</title><style>{CSS}</style></head><body>"
            + "\n".join(body) + "</body></html>")


def parameters_table(reducer) -> str:
    """The reducer's parameters in user units (materials and operating left out)."""
    from .parameters import parameter_table

    params = pd.DataFrame(parameter_table(reducer)).set_index("name")
    return table(params[[not name.startswith(("materials", "operating"))
                          for name in params.index]])


def target(path: str | Path) -> Path:
    """``path`` of a report to write; :class:`InputFileError` if its folder does not exist."""
    path = Path(path)
    if not path.parent.exists():
        raise InputFileError(f"{path}: folder {path.parent} does not exist")
    return path


def summary_block(title: str, rows: list[tuple], notes: list[str] | None = None,
                  trust: bool = True) -> str:
    """The block every report opens with (issue 34 item 2): ``rows`` of (quantity, this run's
    figure, the class / target / reference, verdict) as text, ``notes`` below (HTML), then the
    "how far to trust this" box (:func:`trust_box`)."""
    frame = pd.DataFrame([[str(c) for c in r] for r in rows],
                         columns=["quantity", "this run", "class / target", "verdict"])
    parts = [f"<section id='summary'><h2>{html.escape(title)}</h2>",
             table(frame.set_index("quantity"))]
    parts += [f"<p>{n}</p>" for n in notes or []]
    if trust:
        parts.append(trust_box())
    return "".join(parts) + "</section>"


def trust_box() -> str:
    """"How far to trust this": the model against the paper and the catalogue of its class,
    as measured, from src/rvsim/data/trust.csv (:mod:`rvsim.analysis.trust`), one line open
    and the table folded."""
    from .analysis.trust import MEASURED, trust_rows

    rows = trust_rows()
    lead = {r["key"]: r for r in rows}
    line = (f"model vs paper: mean TE model/paper {lead['paper_te_mean']['ratio']}, factor "
            f"order: {lead['paper_factor_order']['ratio'].split(';')[0]}; model vs catalogue "
            f"class: rigidity model/class {lead['rigidity']['ratio']}, lost motion "
            f"{lead['lost_motion']['ratio']}, L10 life model/class {lead['life_l10']['ratio']}")
    frame = pd.DataFrame([{"against": r["against"], "quantity": r["quantity"],
                           "published": r["published"], "model": r["box_model"],
                           "model / published": r["ratio"]} for r in rows])
    return (f"<details class='trust' id='trust'><summary><b>How far to trust this</b> "
            f"(measured {MEASURED}): {html.escape(line)}</summary>"
            + table(frame, index=False)
            + "<p class='note'>Sources, conditions and where the model misses: "
            "docs/validation.md (its first tables come from src/rvsim/data/trust.csv).</p>"
            "</details>")
