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

__all__ = ["Headline", "number", "figure", "draw"]


def number(value, unit: str = "", digits: int = 4) -> str:
    """``value`` to ``digits`` significant digits, with its unit; "n/a" for None or NaN (a
    quantity a run could not give)."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "n/a"
    text = f"{value:.{digits}g}" if isinstance(value, float) else str(value)
    return f"{text} {unit}".rstrip()


class Headline:
    """Mixin: ``__repr__`` and ``_repr_html_`` from ``self.headline()`` -> (title, rows of
    (label, text)).  Dataclasses using it are declared with ``repr=False``."""

    def headline(self) -> tuple[str, list[tuple[str, str]]]:
        raise NotImplementedError

    def __repr__(self) -> str:
        title, rows = self.headline()
        width = max((len(label) for label, _ in rows), default=0)
        return "\n".join([title] + [f"  {label:<{width}}  {text}" for label, text in rows])

    def _repr_html_(self) -> str:
        title, rows = self.headline()
        body = "".join(f"<tr><th style='text-align:left'>{html.escape(label)}</th>"
                       f"<td style='text-align:left'>{html.escape(text)}</td></tr>"
                       for label, text in rows)
        return (f"<table><caption style='text-align:left'><b>{html.escape(title)}</b>"
                f"</caption>{body}</table>")


def figure(module: str, name: str):
    """The figure function ``name`` of the module ``module`` (dotted, e.g. "rvsim.plots")."""
    return getattr(import_module(module), name)


def draw(function, ax=None, *args, panels: bool = False, **options):
    """Draw ``function(*args, **options)`` on ``ax`` (a new figure if None) and return the
    Axes drawn on (the first panel's of a figure of several).

    ``panels``: the function draws a figure of several panels (it takes ``fig``): given an
    ``ax``, that Axes must be alone in its figure and the panels replace it there."""
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
