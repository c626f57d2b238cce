"""HTML report of an efficiency map (``rvsim efficiency --report``): the catalogue's map of
efficiency [%] over input speed and output torque (heat map and table) and the running
torques."""

from __future__ import annotations

import html
from pathlib import Path

import pandas as pd

from ._files import atomic_write_text
from .html import page as _page, parameters_table as _parameters_table, png as _png, \
    summary_block as _summary_block, table as _table, target as _target

__all__ = ["efficiency_plot", "write_efficiency_report"]


def efficiency_plot(result, fig=None):
    """Efficiency [%] as a heat map over input speed [rpm] and output torque [N*m], each
    point's cell written with its value (issue 34 item 2: one curve per speed on an
    auto-zoomed axis drew the map as coinciding lines).  Cells span half-way to their
    neighbours, on the axes' true scales."""
    import numpy as np

    from .plots import pyplot

    plt = pyplot()
    if fig is None:
        fig = plt.figure(figsize=(7, 4.5))
    ax = fig.add_subplot(1, 1, 1)
    speeds, torques = result.speeds_rpm(), np.asarray(result.output_torque, dtype=float)
    value = 100.0 * np.asarray(result.efficiency, dtype=float).T     # (torques, speeds)

    def edges(x):
        if x.size == 1:
            return np.array([0.8 * x[0], 1.2 * x[0]])
        mid = 0.5 * (x[1:] + x[:-1])
        return np.concatenate([[2 * x[0] - mid[0]], mid, [2 * x[-1] - mid[-1]]])

    low, high = float(value.min()), float(value.max())
    if high - low < 0.05:                       # a flat map: a band of 0.1 % around it
        low, high = low - 0.05, high + 0.05
    mesh = ax.pcolormesh(edges(speeds), edges(torques), value, cmap="viridis", vmin=low,
                         vmax=high, shading="flat")
    for i, torque in enumerate(torques):
        for j, speed in enumerate(speeds):
            dark = value[i, j] < low + 0.55 * (high - low)
            ax.text(speed, torque, f"{value[i, j]:.1f}", ha="center", va="center", fontsize=8,
                    color="white" if dark else "black")
    ax.set_xticks(speeds, [f"{s:g}" for s in speeds])
    ax.set_yticks(torques, [f"{t:g}" for t in torques])
    ax.set_xlabel("input speed [rpm]")
    ax.set_ylabel("output torque [N*m]")
    fig.colorbar(mesh, ax=ax, label="efficiency [%]")
    fig.tight_layout()
    return fig


def write_efficiency_report(result, reducer, path: str | Path) -> Path:
    """Write an HTML page for one efficiency ``result`` of ``reducer``."""
    path = _target(path)
    summary = result.summary()
    table = result.percent_table()
    table.columns = [f"{c:g} rpm" for c in table.columns]
    table.index.name = "output torque [N*m]"
    running = pd.DataFrame(summary["no_load_running_torque"]).rename(columns={
        "input_speed_rpm": "input speed [rpm]", "torque_nm": "torque [N*m]"}
    ).set_index("input speed [rpm]")
    note = "" if result.friction else (
        "<p class='note'>This parameter set has no friction: efficiency 1, no running or "
        "starting torque (set contact.friction_coefficient and friction.*).</p>")
    from .analysis.headline import efficiency_rows

    answer = _summary_block("Answer", efficiency_rows(result.to_frame(), summary,
                                                      reducer.rating.rated_torque))
    body = [f"<h1>Efficiency: {html.escape(reducer.name)}</h1>", answer, note,
            "<p class='note'>Quasi-static: each point is the mean over "
            f"{result.positions} equilibria over one crank revolution, friction following the "
            "input turning forwards at the point's speed (docs/model.md section 15). "
            "Efficiency = output power / input power; no-load running torque = input torque "
            "at zero output torque; starting torque = the largest input torque at zero load "
            f"at {summary['starting_speed_rpm']:g} rpm (input side).</p>",
            "<h2>Efficiency map</h2>", _png(efficiency_plot(result)),
            "<h3>Efficiency [%]: output torque against input speed</h3>", _table(table),
            "<h2>No-load running torque (input)</h2>", _table(running),
            f"<p class='note'>Input torques below {summary['input_torque_resolution_nm']:.2g} "
            "N*m (the solver's tolerance, 1e-7 of the rated torque, carried to the input) "
            "are round-off and shown as 0.</p>",
            f"<p>Starting torque (input): {summary['starting_torque_nm']:.4g} N*m; "
            f"computed in {summary['wall_s']:.2f} s, status {summary['status']}.</p>",
            f"<p>Lubricant at {summary['temperature_c']:g} degC: "
            f"{summary['oil_viscosity_mm2_s']:.4g} mm^2/s (ASTM D341); lip seals' drag "
            f"(ISO/TR 14179-2): {summary['seal_torque_input_nm']:.4g} N*m on the input, "
            f"{summary['seal_torque_output_nm']:.4g} N*m on the output.</p>",
            "<h2>Parameters</h2>", _parameters_table(reducer)]
    return atomic_write_text(path, _page(f"rvsim efficiency {reducer.name}", body))
