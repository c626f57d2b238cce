"""Figures of design analyses: the main-effect plot (level means per factor, the paper's
Figs. 8-10) and the interaction plots (issue 31 step 6: moved here from :mod:`rvsim.plots` and
:mod:`rvsim.analysis.interactions` unchanged; both names stay public there too).

matplotlib is imported on the first figure only (:mod:`rvsim._matplotlib`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from .._display import check_axes
from .._matplotlib import plain, pyplot

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["main_effects_plot", "interaction_plots"]


def main_effects_plot(analysis, ax=None, *, factors=None, ylabel=None):
    """Level means of each factor (the paper's Figs. 8-10), one panel per factor."""
    check_axes(ax)
    plt = pyplot()
    factors = factors or list(analysis.level_means)
    if ax is None:
        cols = min(5, len(factors))
        rows = math.ceil(len(factors) / cols)
        fig, axes = plt.subplots(rows, cols, figsize=(2.4 * cols, 2.3 * rows), sharey=True,
                                 squeeze=False)
        axes = axes.ravel()
        for extra in axes[len(factors):]:
            extra.set_visible(False)
    else:
        axes = [ax] * len(factors)
        fig = ax.figure
    label = ylabel or f"mean of {plain(analysis.response)}"
    for axis, factor in zip(axes, factors):
        k = analysis.level_means[factor]
        levels = getattr(analysis, "levels", {}).get(factor) or list(range(1, len(k) + 1))
        axis.plot(levels, k, "o-", color="C0")
        axis.axhline(analysis.grand_mean, color="0.6", lw=0.8, ls="--")
        axis.set_title(plain(factor))
        axis.set_xticks(levels)
        axis.set_xlabel("level")
    axes[0].set_ylabel(label)
    fig.tight_layout()
    return fig


def interaction_plots(table: pd.DataFrame, response: str, pairs: list[tuple[str, str]],
                      ylabel: str | None = None):
    """One panel per pair (A, B): the mean response at each level of A, a line per level of B
    (parallel lines: no interaction)."""
    plt = pyplot()
    n = max(1, len(pairs))
    cols = min(3, n)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.3 * rows), squeeze=False)
    for ax, (a, b) in zip(axes.flat, pairs):
        means = table.groupby([b, a])[response].mean().unstack(a)
        for level, row in means.iterrows():
            ax.plot(range(1, row.size + 1), row.values, marker="o",
                    label=plain(f"{b} = {level}"))
        ax.set_xticks(range(1, means.shape[1] + 1), [str(c) for c in means.columns])
        ax.set_xlabel(plain(f"level of {a}"))
        ax.set_ylabel(plain(ylabel or response))
        ax.set_title(plain(f"{a} x {b}"))
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    fig.tight_layout()
    return fig
