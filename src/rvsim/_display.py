"""How a parameter set or a result shows itself in a console or a notebook (issue 34 item 5):
a few headline rows with units as ``repr`` and as an HTML table (``_repr_html_``), and the
``.plot(ax=None)`` of results drawn by the existing figure functions.

Foundation layer: imports nothing of rvsim at module level.  A result's figure function lives
in a higher layer (:mod:`rvsim.plots`, the reports), so it is looked up by its dotted name on
the first ``.plot()`` (:func:`figure`), as pandas finds its plotting backend: an engine never
imports the figures (docs/architecture.md, "Layers"; tests/unit/test_display.py resolves every
name used).
"""

from __future__ import annotations

import html
import math
from importlib import import_module

__all__ = ["Headline", "number", "figure", "draw", "without_status"]


def number(value, unit: str = "", digits: int = 4) -> str:
    """``value`` to ``digits`` significant digits, with its unit; "not available" for None or
    NaN (a quantity a run could not give; the reports' word, :mod:`rvsim.analysis.headline`)."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "not available"
    text = f"{value:.{digits}g}" if isinstance(value, float) else str(value)
    return f"{text} {unit}".rstrip()


class Headline:
    """Mixin: ``__repr__`` (a line per row) and ``_repr_html_`` (a table) from
    ``self.headline()`` -> (title, rows).

    A row is (quantity, value) or, as the reports' opening block has it
    (:mod:`rvsim.analysis.headline`), (quantity, value, class or reference, verdict).
    Dataclasses using it are declared with ``repr=False``."""

    def headline(self) -> tuple[str, list[tuple]]:
        raise NotImplementedError

    def _rows(self) -> tuple[str, list[tuple]]:
        """``headline()``, or a title that says why there is none (a repr never raises)."""
        try:
            return self.headline()
        except Exception as exc:          # noqa: BLE001 - shown, not swallowed
            return (f"{type(self).__name__} (no headline: {type(exc).__name__}: {exc})", [])

    def __repr__(self) -> str:
        title, rows = self._rows()
        width = max((len(row[0]) for row in rows), default=0)
        lines = [title]
        for label, value, *rest in rows:     # the verdict, not the class's text (HTML has it)
            extra = str(rest[-1]) if rest and rest[-1] not in ("", "-") else ""
            lines.append(f"  {label:<{width}}  {value}" + (f"  ({extra})" if extra else ""))
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        title, rows = self._rows()
        head = ("<tr><th>quantity</th><th>value</th><th>class or reference</th>"
                "<th>verdict</th></tr>" if any(len(row) > 2 for row in rows) else "")
        cell = "<td style='text-align:left{}'>{}</td>"       # a value and its unit on one line
        body = "".join("<tr>" + "".join(cell.format(";white-space:nowrap" if i == 1 else "",
                                                    html.escape(str(x)))
                                        for i, x in enumerate(row)) + "</tr>" for row in rows)
        return (f"<table><caption style='text-align:left'><b>{html.escape(title)}</b>"
                f"</caption>{head}{body}</table>")


def without_status(rows: list[tuple]) -> list[tuple]:
    """A report's headline rows without their status row (a repr's title says it)."""
    return [row for row in rows if row[0] != "status"]


def figure(module: str, name: str):
    """The figure function ``name`` of the module ``module`` (dotted, e.g. "rvsim.plots")."""
    return getattr(import_module(module), name)


def check_axes(ax) -> None:
    """Refuse an ``ax`` that is neither None nor a matplotlib Axes with one TypeError naming
    it (``result.plot(ax="x")`` was an AttributeError from deep in matplotlib).  Imports
    nothing: an Axes exists only once matplotlib is imported."""
    import sys

    axes = sys.modules.get("matplotlib.axes")
    if ax is None or (axes is not None and isinstance(ax, axes.Axes)):
        return
    raise TypeError(f"ax must be a matplotlib Axes (e.g. from plt.subplots()) or None, not "
                    f"{type(ax).__name__} {ax!r:.40}")


def draw(function, ax=None, *args, panels: bool = False, **options):
    """Draw ``function(*args, **options)`` on ``ax`` (a new figure if None) and return the
    Axes drawn on (the first panel's of a figure of several).

    ``panels``: the function draws a figure of several panels (it takes ``fig``): given an
    ``ax``, that Axes must be alone in its figure and the panels replace it there."""
    check_axes(ax)
    if not panels:
        fig = function(*args, ax=ax, **options)
        return ax if ax is not None else fig.axes[0]
    fig = None
    if ax is not None:
        fig = ax.figure
        if len(fig.axes) != 1:
            from .errors import ParameterError

            raise ParameterError("ax", "this result draws a figure of several panels: pass an "
                                 "Axes alone in its figure, or none")
        ax.remove()
    fig = function(*args, fig=fig, **options)
    return fig.axes[0]
