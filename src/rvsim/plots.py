"""Matplotlib figures (imported lazily: the core does not need matplotlib).

Every function takes an optional ``ax``/``fig`` and returns the figure; axes carry units.
"""

from __future__ import annotations

import math


__all__ = ["main_effects_plot", "speed_plot", "te_plot", "spectrum_plot", "figure_to_png"]


def _pyplot():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def main_effects_plot(analysis, ax=None, *, factors=None, ylabel=None):
    """Level means of each factor (the paper's Figs. 8-10), one panel per factor."""
    plt = _pyplot()
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
    label = ylabel or f"mean of {analysis.response}"
    for axis, factor in zip(axes, factors):
        k = analysis.level_means[factor]
        levels = getattr(analysis, "levels", {}).get(factor) or list(range(1, len(k) + 1))
        axis.plot(levels, k, "o-", color="C0")
        axis.axhline(analysis.grand_mean, color="0.6", lw=0.8, ls="--")
        axis.set_title(factor)
        axis.set_xticks(levels)
        axis.set_xlabel("level")
    axes[0].set_ylabel(label)
    fig.tight_layout()
    return fig


def speed_plot(result, ax=None):
    """Input and output speed against time (paper Fig. 4)."""
    plt = _pyplot()
    fig, ax = (plt.subplots(figsize=(7, 3.2)) if ax is None else (ax.figure, ax))
    deg = 180.0 / math.pi
    ax.plot(result.time, result.omega_in * deg, label="input shaft")
    ax.plot(result.time, result.omega_out * deg * result.ratio, label=f"output x {result.ratio:g}")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("speed [deg/s]")
    ax.legend(loc="lower right")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def te_plot(results: dict, steady_start: float, ax=None):
    """Transmission error against time for several runs, steady window shaded (Fig. 5)."""
    plt = _pyplot()
    fig, ax = (plt.subplots(figsize=(7, 3.4)) if ax is None else (ax.figure, ax))
    arcmin = 180.0 * 60.0 / math.pi
    for label, result in results.items():
        ax.plot(result.time, result.te * arcmin, lw=0.8, label=str(label))
    ax.axvspan(steady_start, max(r.time[-1] for r in results.values()), color="0.9",
               label="steady window")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("transmission error [arcmin]")
    ax.legend(fontsize="small", ncol=2)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def spectrum_plot(result, ax=None, *, pin_count: int = 40, planet_teeth: int = 54,
                  fluctuation_frequency: float | None = None):
    """Amplitude spectrum of the steady TE against orders of the crank rotation relative to
    the carrier (which turns ``pin_count`` times faster than the carrier).  A
    ``fluctuation_frequency`` [Hz] of the load is marked at its order too."""
    plt = _pyplot()
    fig, ax = (plt.subplots(figsize=(7, 3.2)) if ax is None else (ax.figure, ax))
    from .dynamics.result import crank_frequency, te_spectrum

    orders, amplitude = te_spectrum(result.time, result.te, result.omega_out,
                                    result.steady_start, pin_count)
    ax.plot(orders, amplitude, lw=0.8)
    top = ax.get_ylim()[1]
    marks = [(1, "crank"), (pin_count - 1, "zc"), (pin_count, "zp, pin passing"),
             (planet_teeth, "sun-planet mesh")]
    crank_hz = crank_frequency(result.time, result.omega_out, result.steady_start, pin_count)
    if fluctuation_frequency and crank_hz > 0:
        marks.insert(1, (fluctuation_frequency / crank_hz,
                         f"load fluctuation {fluctuation_frequency:g} Hz"))
    for i, (order, name) in enumerate(marks):
        ax.axvline(order, color="C3", lw=0.7, ls="--")
        ax.text(order, top * (0.92 - 0.08 * i), f" {name}", color="C3", fontsize=7)
    ax.set_xlim(0, 100)
    ax.set_xlabel("order of crank rotation relative to the carrier [-]")
    ax.set_ylabel("TE amplitude [arcmin]")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def figure_to_png(fig, path=None) -> bytes:
    """PNG bytes of ``fig`` (also written to ``path``, atomically, if given); closes the
    figure."""
    import io

    plt = _pyplot()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    plt.close(fig)
    data = buffer.getvalue()
    if path is not None:
        from ._files import atomic_write

        atomic_write(path, lambda tmp: tmp.write_bytes(data))
    return data
