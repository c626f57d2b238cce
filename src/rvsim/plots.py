"""Matplotlib figures (imported lazily: the core does not need matplotlib).

Every function takes an optional ``ax``/``fig`` and returns the figure; axes carry units.
"""

from __future__ import annotations

import math


__all__ = ["main_effects_plot", "speed_plot", "te_plot", "spectrum_plot", "figure_to_png",
           "pin_load_map", "te_revolution_plot", "order_spectrum_plot", "hysteresis_plot"]

_ARCMIN = math.pi / 10800.0


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
        axis.plot(range(1, len(k) + 1), k, "o-", color="C0")
        axis.axhline(analysis.grand_mean, color="0.6", lw=0.8, ls="--")
        axis.set_title(factor)
        axis.set_xticks(range(1, len(k) + 1))
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


def spectrum_plot(result, ax=None, *, pin_count: int = 40, planet_teeth: int = 54):
    """Amplitude spectrum of the steady TE against orders of the crank rotation relative to
    the carrier (which turns ``pin_count`` times faster than the carrier)."""
    plt = _pyplot()
    fig, ax = (plt.subplots(figsize=(7, 3.2)) if ax is None else (ax.figure, ax))
    from .dynamics.result import te_spectrum

    orders, amplitude = te_spectrum(result.time, result.te, result.omega_out,
                                    result.steady_start, pin_count)
    ax.plot(orders, amplitude, lw=0.8)
    top = ax.get_ylim()[1]
    marks = ((1, "crank"), (pin_count - 1, "zc"), (pin_count, "zp, pin passing"),
             (planet_teeth, "sun-planet mesh"))
    for i, (order, name) in enumerate(marks):
        ax.axvline(order, color="C3", lw=0.7, ls="--")
        ax.text(order, top * (0.92 - 0.08 * i), f" {name}", color="C3", fontsize=7)
    ax.set_xlim(0, 100)
    ax.set_xlabel("order of crank rotation relative to the carrier [-]")
    ax.set_ylabel("TE amplitude [arcmin]")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def pin_load_map(result, fig=None):
    """Pin force [N] over one output revolution, one heat map per disc: pin number against
    the output angle (an LTCA result: ``pin_forces`` (n, 2, zp), ``input_angle``, ``ratio``)."""
    plt = _pyplot()
    import numpy as np

    forces = np.asarray(result.pin_forces)
    if fig is None:
        fig = plt.figure(figsize=(8, 5.6))
    axes = fig.subplots(2, 1, sharex=True)
    out_deg = np.degrees(np.asarray(result.input_angle) / result.ratio)
    step = out_deg[1] - out_deg[0] if out_deg.size > 1 else 1.0
    extent = (out_deg[0], out_deg[-1] + step, 0.5, forces.shape[2] + 0.5)
    top = max(float(forces.max()), 1e-12)
    for disc, ax in enumerate(axes):
        image = ax.imshow(forces[:, disc, :].T, aspect="auto", origin="lower", extent=extent,
                          cmap="viridis", vmin=0.0, vmax=top, interpolation="nearest")
        ax.set_ylabel(f"disc {disc + 1}: pin [-]")
    axes[-1].set_xlabel("output angle [deg]")
    fig.colorbar(image, ax=list(axes), label="pin contact force [N]")
    return fig


def te_revolution_plot(result, fig=None):
    """TE over the output revolution: from the nominal assembly (top) and relative to the
    loaded, clearance-taken-up state, i.e. minus its mean (bottom) [arcmin]."""
    plt = _pyplot()
    import numpy as np

    if fig is None:
        fig = plt.figure(figsize=(8, 4.6))
    top, bottom = fig.subplots(2, 1, sharex=True)
    out_deg = np.degrees(np.asarray(result.input_angle) / result.ratio)
    te = np.asarray(result.te) / _ARCMIN
    top.plot(out_deg, te, lw=0.9)
    top.axhline(te.mean(), color="0.5", lw=0.8, ls="--", label=f"mean {te.mean():.4g}")
    top.set_ylabel("TE [arcmin]")
    top.legend(fontsize="small", loc="upper right")
    bottom.plot(out_deg, te - te.mean(), lw=0.9, color="C1")
    bottom.set_ylabel("TE - mean [arcmin]")
    bottom.set_xlabel("output angle [deg]")
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def order_spectrum_plot(orders, amplitude_arcmin, marks: dict, ax=None):
    """TE amplitude [arcmin] against orders of the output revolution, ``marks`` (name ->
    order) drawn as dashed lines (orders that coincide share one line)."""
    plt = _pyplot()
    import numpy as np

    fig, ax = (plt.subplots(figsize=(8, 3.4)) if ax is None else (ax.figure, ax))
    orders = np.asarray(orders)
    amplitude = np.asarray(amplitude_arcmin)
    ax.vlines(orders[1:], 0.0, amplitude[1:], lw=1.0)
    limit = min(float(orders[-1]), 1.15 * max(marks.values()))
    ax.set_xlim(0, limit)
    top = float(amplitude[1:][orders[1:] <= limit].max(initial=0.0)) or 1.0
    ax.set_ylim(0, 1.35 * top)
    grouped: dict[float, list[str]] = {}
    for name, order in marks.items():
        grouped.setdefault(float(order), []).append(name)
    for i, (order, names) in enumerate(sorted(grouped.items())):
        if order > limit:
            continue
        ax.axvline(order, color="C3", lw=0.7, ls="--")
        ax.text(order, 1.32 * top * (1 - 0.09 * (i % 4)), " " + ", ".join(names), color="C3",
                fontsize=7, va="top")
    ax.set_xlabel("order of the output revolution [-]")
    ax.set_ylabel("TE amplitude [arcmin]")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def hysteresis_plot(result, rated: float, ax=None):
    """Output angle [arcmin] against output torque [N*m] of the torque-reversal test, with
    the catalogue quantities marked: rigidity interval (50-100 % of rated, secants), the
    +-3 % lost-motion mid-points and the loop width at 0 N*m."""
    plt = _pyplot()
    import numpy as np

    from .analysis import catalogue as cat

    fig, ax = (plt.subplots(figsize=(8, 5)) if ax is None else (ax.figure, ax))
    t, a, b = (np.asarray(v, dtype=float) for v in (result.torque, result.angle, result.branch))
    (tu, au), (td, ad) = cat.loop_branches(t, a, b)
    ax.plot(t, a / _ARCMIN, color="0.8", lw=0.8, label="first loading (not in the loop)")
    ax.plot(tu, au / _ARCMIN, ".-", color="C0", lw=1.0, ms=3, label="torque increasing")
    ax.plot(td, ad / _ARCMIN, ".-", color="C1", lw=1.0, ms=3, label="torque decreasing")
    for sign, (bt, ba) in ((1.0, (tu, au)), (-1.0, (td, ad))):
        ax.axvspan(sign * 0.5 * rated, sign * rated, color="C2", alpha=0.08)
        ends = [cat.angle_at(bt, ba, sign, sign * f * rated, "plot") for f in (0.5, 1.0)]
        ax.plot([sign * 0.5 * rated, sign * rated], np.array(ends) / _ARCMIN, color="C2",
                lw=2.0, label="rigidity secant 50-100 % of rated" if sign > 0 else None)
    mids = []
    for sign in (1.0, -1.0):
        value = sign * cat.LOST_MOTION_FRACTION * rated
        mids.append(0.5 * (cat.angle_at(tu, au, sign, value, "plot")
                           + cat.angle_at(td, ad, sign, value, "plot")))
        ax.plot([value], [mids[-1] / _ARCMIN], "D", color="C3", ms=6,
                label="lost motion mid-points (+-3 %)" if sign > 0 else None)
    loss_low = cat.angle_at(tu, au, -1.0, 0.0, "plot")
    loss_high = cat.angle_at(td, ad, 1.0, 0.0, "plot")
    ax.annotate("", xy=(0.0, loss_high / _ARCMIN), xytext=(0.0, loss_low / _ARCMIN),
                arrowprops=dict(arrowstyle="<->", color="C4", lw=1.2))
    ax.text(0.02 * rated, 0.5 * (loss_low + loss_high) / _ARCMIN,
            " hysteresis loss / backlash\n at 0 N*m", color="C4", fontsize=8, va="center")
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.axvline(0.0, color="0.6", lw=0.5)
    ax.set_xlabel("output torque [N*m]")
    ax.set_ylabel("output angle, input locked [arcmin]")
    ax.legend(fontsize="small", loc="upper left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def figure_to_png(fig, path=None) -> bytes:
    """PNG bytes of ``fig`` (also written to ``path`` if given); closes the figure."""
    import io

    plt = _pyplot()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    plt.close(fig)
    data = buffer.getvalue()
    if path is not None:
        with open(path, "wb") as handle:
            handle.write(data)
    return data
