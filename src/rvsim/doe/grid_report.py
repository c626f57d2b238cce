"""The speed-torque grid's HTML report: the ATE and the mean twist over speed per torque, and
the Campbell diagram (each order's frequency against input speed, the natural frequency at
each torque as a band), so that a resonance shows where it is (issue 33 item 4)."""

from __future__ import annotations

from html import escape
from pathlib import Path

import numpy as np
import pandas as pd

from .._files import atomic_write_text
from .._matplotlib import pyplot

__all__ = ["write_grid_report", "campbell_plot", "grid_curves_plot"]


def grid_curves_plot(table: pd.DataFrame):
    """ATE and mean TE [arcmin] against input speed, one line per (torque, temperature)."""
    plt = pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.6))
    for (torque, temp), rows in table.groupby(["output_torque_nm", "temperature_c"]):
        rows = rows.sort_values("input_speed_rpm")
        label = f"{torque:g} N*m, {temp:g} degC"
        left.plot(rows["input_speed_rpm"], rows["ate_arcmin"], "o-", label=label)
        right.plot(rows["input_speed_rpm"], rows["te_mean_arcmin"], "o-", label=label)
    left.set_ylabel("ATE over one output revolution [arcmin]")
    right.set_ylabel("mean twist (mean TE) [arcmin]")
    for ax in (left, right):
        ax.set_xlabel("input speed [rpm]")
        ax.grid(alpha=0.3)
    left.legend(fontsize=7)
    fig.tight_layout()
    return fig


def campbell_plot(table: pd.DataFrame, orders: dict):
    """Each named order's frequency against input speed (lines), the natural frequency's band
    at each torque (shaded) and, at each point, the frequency of the run's largest TE order
    (dots)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.2))
    speed = np.linspace(0.0, 1.1 * float(table["input_speed_rpm"].max()), 50)
    first = table.iloc[0]
    per_rpm = first["output_speed_rpm"] / first["input_speed_rpm"] / 60.0   # output Hz / rpm
    top = 0.0
    for name, order in orders.items():
        f = order * per_rpm * speed
        ax.plot(speed, f, lw=0.8, label=name)
        top = max(top, float(f[-1]))
    modes = table.groupby("output_torque_nm")[["natural_frequency_min_hz",
                                               "natural_frequency_hz",
                                               "natural_frequency_max_hz"]].first()
    for torque, row in modes.iterrows():
        if np.isfinite(row["natural_frequency_hz"]):
            ax.axhspan(row["natural_frequency_min_hz"], row["natural_frequency_max_hz"],
                       color="C3", alpha=0.25)
            ax.axhline(row["natural_frequency_hz"], color="C3", lw=0.8, ls="--")
            ax.text(speed[-1], row["natural_frequency_max_hz"], f"f_n at {torque:g} N*m ",
                    color="C3", fontsize=7, va="bottom", ha="right")
    measured = table["order1"] * table["output_speed_rpm"] / 60.0
    ax.plot(table["input_speed_rpm"], measured, "ko", ms=4, label="largest TE order, run")
    top = max(top, float(np.nanmax(measured, initial=0.0)))
    for speed_rpm in table["input_speed_rpm"].unique():
        ax.axvline(speed_rpm, color="0.7", lw=0.6)
    finite = modes["natural_frequency_max_hz"].dropna()
    ceiling = max(1.05 * top, 1.2 * float(finite.max())) if len(finite) else 1.05 * top
    ax.set_ylim(0.0, ceiling or 1.0)
    ax.set_xlim(0.0, speed[-1])
    ax.set_xlabel("input speed [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), title="orders",
              title_fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def write_grid_report(path: str | Path, reducer, table: pd.DataFrame, summary: dict) -> Path:
    """A self-contained HTML page of the grid (figures inline), written atomically."""
    from ..analysis.headline import grid_rows
    from ..html import page, parameters_table, png, summary_block
    from ..html import table as html_table

    path = Path(path)
    columns = ["input_speed_rpm", "output_torque_nm", "temperature_c", "status", "ate_arcmin",
               "te_mean_arcmin", "order1", "order1_arcmin", "order2", "order2_arcmin",
               "natural_frequency_hz", "nearest_order", "nearest_order_ratio", "resonance"]
    body = [f"<h1>Speed-torque grid: {summary['reducer']}</h1>",
            summary_block("Answer", grid_rows(table, summary)),
            f"<p class='note'>{summary['points']} points on the dynamic engine ("
            f"{summary['scheme']}, step {summary['time_step_s']:g} s), each run for "
            f"{summary['duration_rule']}; ATE: the peak-to-peak TE over one output revolution "
            "(what a bench records); mean twist: the mean TE over it (no bench sees it: its "
            "encoders are zeroed at an arbitrary moment). Natural frequency: the output "
            "inertia on the reducer's torsional stiffness with the input held, at each "
            "torque (band: the stiffness's least and largest over the revolution); "
            "resonance: an order inside its half-power band f_n (1 -+ zeta).</p>",
            "<h2>ATE and mean twist</h2>", png(grid_curves_plot(table)),
            "<h2>Orders against the natural frequency (Campbell diagram)</h2>",
            png(campbell_plot(table, summary["orders"])),
            "<h2>Points</h2>", html_table(table[columns], index=False),
            "<h2>Parameters</h2>", parameters_table(reducer)]
    atomic_write_text(path, page(f"rvsim grid: {summary['reducer']}", body))
    return path
