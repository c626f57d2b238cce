"""HTML report of an efficiency map (``rvsim efficiency --report``): the catalogue's curves of
efficiency against output torque, one per input speed, and the running torques."""

from __future__ import annotations

import html
from pathlib import Path

import pandas as pd

from ._files import atomic_write_text
from .html import page as _page, parameters_table as _parameters_table, png as _png, \
    summary_block as _summary_block, table as _table, target as _target

__all__ = ["efficiency_plot", "write_efficiency_report"]


def efficiency_plot(result, fig=None):
    """Efficiency [%] against output torque, one curve per input speed (as catalogues draw
    it)."""
    from .plots import pyplot

    plt = pyplot()
    if fig is None:
        fig = plt.figure(figsize=(7, 4.5))
    ax = fig.add_subplot(1, 1, 1)
    frame = result.to_frame()
    for speed, rows in frame.groupby("input_speed_rpm"):
        ax.plot(rows["output_torque_nm"], 100.0 * rows["efficiency"], marker="o",
                label=f"{speed:g} rpm input")
    ax.set_xlabel("output torque [N*m]")
    ax.set_ylabel("efficiency [%]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return fig


def write_efficiency_report(result, reducer, path: str | Path) -> Path:
    """Write an HTML page for one efficiency ``result`` of ``reducer``."""
    path = _target(path)
    summary = result.summary()
    table = result.to_frame().pivot(index="output_torque_nm", columns="input_speed_rpm",
                                    values="efficiency")
    table.columns = [f"{c:g} rpm" for c in table.columns]
    table.index.name = "output torque [N*m]"
    running = pd.DataFrame(summary["no_load_running_torque"]).set_index("input_speed_rpm")
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
            "<h2>Efficiency against output torque</h2>", _png(efficiency_plot(result)),
            "<h2>Efficiency map</h2>", _table(table),
            "<h2>No-load running torque (input) [N*m]</h2>", _table(running),
            f"<p>Starting torque (input): {summary['starting_torque_nm']:.4g} N*m; "
            f"computed in {summary['wall_s']:.2f} s, status {summary['status']}.</p>",
            f"<p>Lubricant at {summary['temperature_c']:g} degC: "
            f"{summary['oil_viscosity_mm2_s']:.4g} mm^2/s (ASTM D341); lip seals' drag "
            f"(ISO/TR 14179-2): {summary['seal_torque_input_nm']:.4g} N*m on the input, "
            f"{summary['seal_torque_output_nm']:.4g} N*m on the output.</p>",
            "<h2>Parameters</h2>", _parameters_table(reducer)]
    return atomic_write_text(path, _page(f"rvsim efficiency {reducer.name}", body))
