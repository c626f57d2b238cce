"""Matplotlib figures (imported lazily: the core does not need matplotlib).

Every function takes an optional ``ax``/``fig`` and returns the figure; axes carry units.
"""

from __future__ import annotations

import math

from ._matplotlib import plain, pyplot
from .analysis.figures import main_effects_plot   # public here too (issue 31 step 6)

__all__ = ["pyplot", "plain", "main_effects_plot", "speed_plot", "te_plot", "spectrum_plot",
           "figure_to_png", "pin_load_map", "te_revolution_plot", "order_spectrum_plot",
           "hysteresis_plot", "mark_orders", "headroom"]

_ARCMIN = math.pi / 10800.0

#: the old private name of :func:`pyplot` (issue 31 step 5)
_pyplot = pyplot


def speed_plot(result, ax=None, *, fig=None):
    """Input and output speed against time (paper Fig. 4), each on its own scale: drawn on
    one axis with the output multiplied by the ratio, the output's ripple hid the input
    (issue 34 item 2).  By default (or into ``fig``) two panels sharing the time axis [deg/s,
    rpm on the right]; into a given ``ax``, the input on it and the output on a twin y-axis."""
    plt = pyplot()
    deg = 180.0 / math.pi
    if ax is not None:
        ax.plot(result.time, result.omega_in * deg, color="C0", lw=0.8, label="input shaft")
        ax.set_ylabel("input shaft [deg/s]", color="C0")
        twin = ax.twinx()
        twin.plot(result.time, result.omega_out * deg, color="C1", lw=0.8, label="output")
        twin.set_ylabel("output (carrier) [deg/s]", color="C1")
        ax.set_xlabel("time [s]")
        ax.grid(alpha=0.3)
        return ax.figure
    if fig is None:
        fig = plt.figure(figsize=(7, 4.4))
    top, bottom = fig.subplots(2, 1, sharex=True)
    rpm = deg / 6.0                       # deg/s per rpm
    for panel, omega, name, color in ((top, result.omega_in, "input shaft", "C0"),
                                      (bottom, result.omega_out, "output (carrier)", "C1")):
        panel.plot(result.time, omega * deg, color=color, lw=0.8)
        panel.set_ylabel(f"{name}\n[deg/s]")
        panel.secondary_yaxis("right", functions=(lambda v: v / rpm, lambda v: v * rpm)
                              ).set_ylabel("[rpm]")
        panel.grid(alpha=0.3)
    bottom.set_xlabel("time [s]")
    fig.tight_layout()
    return fig


def te_plot(results: dict, steady_start: float, ax=None):
    """Transmission error against time for several runs (Fig. 5): the main axis zoomed on the
    steady window (t >= ``steady_start``), the whole run with its start-up transient in an
    inset, the window shaded there (the transient's +-15 arcmin set the scale and squashed
    the steady differences: issue 34 item 2)."""
    plt = pyplot()
    fig, ax = (plt.subplots(figsize=(7, 3.6)) if ax is None else (ax.figure, ax))
    arcmin = 180.0 * 60.0 / math.pi
    end = max(r.time[-1] for r in results.values())
    steady = [r.te[r.time >= steady_start] * arcmin for r in results.values()]
    steady = [v for v in steady if v.size]
    for label, result in results.items():
        window = result.time >= steady_start
        ax.plot(result.time[window], result.te[window] * arcmin, lw=0.8, label=plain(label))
    if steady:
        lo, hi = min(float(v.min()) for v in steady), max(float(v.max()) for v in steady)
        pad = 0.08 * max(hi - lo, 1e-6 * max(abs(hi), 1.0))
        ax.set_ylim(lo - pad, hi + 0.9 * (hi - lo) + 2 * pad)   # room above for the inset
        ax.set_xlim(steady_start, end)
    ax.set_xlabel("time [s] (steady window)")
    ax.set_ylabel("transmission error [arcmin]")
    ax.grid(alpha=0.3)
    if len(results) > 1:
        ax.legend(fontsize="x-small", ncol=min(len(results), 5), loc="lower left",
                  bbox_to_anchor=(0.0, 1.0), frameon=False)     # above the axes, off the data
    inset = ax.inset_axes([0.56, 0.58, 0.42, 0.38])
    for result in results.values():
        inset.plot(result.time, result.te * arcmin, lw=0.5)
    inset.axvspan(steady_start, end, color="0.85", zorder=0)
    inset.set_title("whole run, steady window shaded", fontsize=7)
    inset.tick_params(labelsize=6)
    inset.set_facecolor((1, 1, 1, 0.9))
    fig.tight_layout()
    return fig


def mark_orders(ax, marks: dict, *, limit: float, color: str = "C3", style: str = "--"):
    """Dashed lines at the ``marks`` (name -> order) up to ``limit`` on an order axis
    (log-scaled here, from 0.8), names that coincide on one line, each label written
    horizontally in the first row at the top of the axes where it overlaps no other label
    (the vertical labels of a linear axis overlapped each other and the lines: issue 34
    item 2).  Returns the number of label rows; the caller leaves that much room above its
    data (:func:`headroom`)."""
    from matplotlib.transforms import blended_transform_factory

    ax.set_xscale("log")
    ax.set_xlim(0.8, 1.25 * limit)
    grouped: dict[float, list[str]] = {}
    for name, order in marks.items():
        if 0 < float(order) <= limit:
            grouped.setdefault(float(order), []).append(name)
    ax.figure.tight_layout()                       # the final axes box, before measuring
    renderer = ax.figure.canvas.get_renderer()
    right = ax.get_window_extent(renderer).x1
    where = blended_transform_factory(ax.transData, ax.transAxes)
    placed: list = []
    rows = 0
    for order in sorted(grouped):
        ax.axvline(order, color=color, lw=0.7, ls=style)
        for row in range(12):
            text = ax.text(order, 0.97 - 0.075 * row, " " + ", ".join(grouped[order]) + " ",
                           transform=where, color=color, fontsize=7, va="top", ha="left",
                           bbox=dict(facecolor="white", edgecolor="none", alpha=0.8, pad=0.5))
            box = text.get_window_extent(renderer)
            if box.x1 > right:
                text.set_ha("right")
                box = text.get_window_extent(renderer)
            if not any(box.overlaps(other) for other in placed) or row == 11:
                placed.append(box.expanded(1.02, 1.1))
                rows = max(rows, row + 1)
                break
            text.remove()
    return rows


def headroom(ax, top: float, rows: int) -> None:
    """y from 0 to above ``top`` with room for ``rows`` label rows of :func:`mark_orders`."""
    ax.set_ylim(0.0, (top or 1.0) / max(0.2, 0.95 - 0.075 * rows))


def spectrum_plot(result, ax=None, *, pin_count: int = 40, planet_teeth: int | None = 54,
                  fluctuation_frequency: float | None = None):
    """Amplitude spectrum of the steady TE against orders of the crank rotation relative to
    the carrier (which turns ``pin_count`` times faster than the carrier).  A
    ``fluctuation_frequency`` [Hz] of the load is marked at its order too; ``planet_teeth``
    None (a single-stage drive): no sun-planet mesh order."""
    plt = pyplot()
    fig, ax = (plt.subplots(figsize=(7, 3.2)) if ax is None else (ax.figure, ax))
    from .dynamics.result import crank_frequency, te_spectrum

    orders, amplitude = te_spectrum(result.time, result.te, result.omega_out,
                                    result.steady_start, pin_count)
    keep = orders > 0
    ax.plot(orders[keep], amplitude[keep], lw=0.8)
    marks = {"crank": 1, "zc": pin_count - 1, "zp, pin passing": pin_count}
    if planet_teeth is not None:
        marks["sun-planet mesh"] = planet_teeth
    crank_hz = crank_frequency(result.time, result.omega_out, result.steady_start, pin_count)
    if fluctuation_frequency and crank_hz > 0:
        marks[f"load fluctuation {fluctuation_frequency:g} Hz"] = (fluctuation_frequency
                                                                  / crank_hz)
    ax.set_xlabel("order of crank rotation relative to the carrier [-]")
    ax.set_ylabel("TE amplitude [arcmin]")
    ax.grid(alpha=0.3, which="both")
    rows = mark_orders(ax, marks, limit=100.0)
    shown = keep & (orders <= 125.0)
    headroom(ax, float(amplitude[shown].max(initial=0.0)), rows)
    fig.tight_layout()
    return fig


def pin_load_map(result, fig=None):
    """Pin force [N] over one output revolution, one heat map per disc: pin number against
    the output angle (an LTCA result: ``pin_forces`` (n, discs, zp), ``input_angle``,
    ``ratio``)."""
    plt = pyplot()
    import numpy as np

    forces = np.asarray(result.pin_forces)
    if fig is None:
        fig = plt.figure(figsize=(8, 5.6))
    axes = fig.subplots(forces.shape[1], 1, sharex=True, squeeze=False)[:, 0]
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
    plt = pyplot()
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
    plt = pyplot()
    import numpy as np

    fig, ax = (plt.subplots(figsize=(8, 3.4)) if ax is None else (ax.figure, ax))
    orders = np.asarray(orders)
    amplitude = np.asarray(amplitude_arcmin)
    limit = min(float(orders[-1]), 1.15 * max(marks.values()))
    keep = (orders > 0) & (orders <= 1.25 * limit)
    ax.vlines(orders[keep], 0.0, amplitude[keep], lw=1.0)
    ax.set_xlabel("order of the output revolution [-]")
    ax.set_ylabel("TE amplitude [arcmin]")
    ax.grid(alpha=0.3, which="both")
    rows = mark_orders(ax, marks, limit=limit)
    headroom(ax, float(amplitude[keep].max(initial=0.0)), rows)
    fig.tight_layout()
    return fig


def hysteresis_plot(result, rated: float, fig=None):
    """Output angle [arcmin] against output torque [N*m] of the torque-reversal test, with
    the catalogue quantities marked: rigidity interval (50-100 % of rated, secants), the
    +-3 % lost-motion mid-points and the loop width at 0 N*m.  Left the whole loop, right a
    zoom on +-10 % of rated where lost motion and backlash live."""
    plt = pyplot()
    import numpy as np

    from .analysis import catalogue as cat

    if fig is None:
        fig = plt.figure(figsize=(10, 4.8))
    whole, zoom = fig.subplots(1, 2, gridspec_kw={"width_ratios": [3, 2]})
    t, a, b, _ = cat.loop_arrays(result)              # converged points
    (tu, au), (td, ad) = cat.loop_branches(t, a, b)
    mids = [0.5 * (cat.angle_at(tu, au, sign, sign * cat.LOST_MOTION_FRACTION * rated, "plot")
                   + cat.angle_at(td, ad, sign, sign * cat.LOST_MOTION_FRACTION * rated,
                                  "plot")) for sign in (1.0, -1.0)]
    loss = (cat.angle_at(tu, au, -1.0, 0.0, "plot"), cat.angle_at(td, ad, 1.0, 0.0, "plot"))
    changes = np.flatnonzero(np.diff(b) != 0)
    first = slice(0, changes[0] + 1) if changes.size >= 2 else slice(0, 0)
    for ax in (whole, zoom):
        ax.plot(t[first], a[first] / _ARCMIN, color="0.6", lw=0.8,
                label="first loading (not in the loop)")
        # each branch as sampled, in sweep order (a torque-controlled test crosses its free
        # play between the sample at 0 N*m and the next one)
        ax.plot(tu, au / _ARCMIN, ".-", color="C0", lw=1.0, ms=3, label="torque increasing")
        ax.plot(td, ad / _ARCMIN, ".-", color="C1", lw=1.0, ms=3, label="torque decreasing")
        for sign, mid in zip((1.0, -1.0), mids):
            ax.plot([sign * cat.LOST_MOTION_FRACTION * rated], [mid / _ARCMIN], "D",
                    color="C3", ms=6, label="lost motion mid-points (+-3 %)" if sign > 0
                    else None)
        ax.axhline(0.0, color="0.6", lw=0.5)
        ax.axvline(0.0, color="0.6", lw=0.5)
        ax.set_xlabel("output torque [N*m]")
        ax.grid(alpha=0.3)
    for sign, (bt, ba) in ((1.0, (tu, au)), (-1.0, (td, ad))):
        whole.axvspan(sign * 0.5 * rated, sign * rated, color="C2", alpha=0.08)
        ends = [cat.angle_at(bt, ba, sign, sign * f * rated, "plot") for f in (0.5, 1.0)]
        whole.plot([sign * 0.5 * rated, sign * rated], np.array(ends) / _ARCMIN, color="C2",
                   lw=2.0, label="rigidity secant 50-100 % of rated" if sign > 0 else None)
    whole.set_ylabel("output angle, input locked [arcmin]")
    whole.legend(fontsize="x-small", loc="upper left")
    near = np.abs(t) <= 0.1 * rated
    span = a[near] / _ARCMIN if near.any() else a / _ARCMIN
    pad = 0.1 * max(float(np.ptp(span)), 1e-6)
    zoom.set_xlim(-0.1 * rated, 0.1 * rated)
    zoom.set_ylim(span.min() - pad, span.max() + pad)
    width = (loss[1] - loss[0]) / _ARCMIN
    if abs(width) > 0.03 * (zoom.get_ylim()[1] - zoom.get_ylim()[0]):   # visible: an arrow
        for ax in (whole, zoom):
            ax.annotate("", xy=(0.0, loss[1] / _ARCMIN), xytext=(0.0, loss[0] / _ARCMIN),
                        arrowprops=dict(arrowstyle="<->", color="C4", lw=1.2))
    zoom.text(0.03, 0.97, f"loop width at 0 N*m: {width:.3g} arcmin\n(backlash, hysteresis "
              f"loss)\nlost motion (+-3 %): {(mids[0] - mids[1]) / _ARCMIN:.3g} arcmin",
              transform=zoom.transAxes, color="C4", fontsize=8, va="top",
              bbox=dict(facecolor="white", edgecolor="none", alpha=0.85))
    zoom.set_title("zoom: +-10 % of rated", fontsize=9)
    fig.tight_layout()
    return fig


def figure_to_png(fig, path=None) -> bytes:
    """PNG bytes of ``fig`` (also written to ``path``, atomically, if given); closes the
    figure."""
    import io

    plt = pyplot()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    plt.close(fig)
    data = buffer.getvalue()
    if path is not None:
        from ._files import atomic_write

        atomic_write(path, lambda tmp: tmp.write_bytes(data))
    return data
