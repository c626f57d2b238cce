"""Plots that show their data (issue 34 item 2), on made-up signals (no run): the steady
window's zoom, both speeds on their own scales, order labels that do not overlap, Sobol
indices whose interval is wider than the index flagged with advice on the sample size."""

import math
import types

import numpy as np
import pytest

from rvsim.units import ARCMIN


def _run(steady_start=0.3):
    """A TE of +-15 arcmin start-up transient, then 1.70 +- 0.02 arcmin."""
    time = np.linspace(0.0, 0.4, 4001)
    te = np.where(time < 0.2, 15.0 * np.sin(2 * np.pi * 40 * time),
                  1.70 + 0.02 * np.sin(2 * np.pi * 300 * time)) * ARCMIN
    omega_in = np.minimum(time / 0.1, 1.0) * math.radians(7000.0)
    return types.SimpleNamespace(time=time, te=te, omega_in=omega_in,
                                 omega_out=omega_in / 121.0, ratio=121.0,
                                 steady_start=steady_start)


def test_te_plot_zooms_on_the_steady_window_with_the_transient_inset():
    from rvsim.plots import pyplot, te_plot

    fig = te_plot({"run 1": _run(), "run 2": _run()}, 0.3)
    ax = fig.axes[0]
    low, high = ax.get_ylim()
    assert low < 1.68 and high > 1.72 and high - low < 0.2  # the +-15 arcmin not in the scale
    assert ax.get_xlim() == (0.3, 0.4)
    (inset,) = ax.child_axes                                 # the whole run, window shaded
    assert inset.get_ylim()[1] > 15.0 and inset.get_xlim()[0] < 0.0 + 0.03
    pyplot().close(fig)


def test_speed_plot_draws_the_output_on_its_own_scale():
    from rvsim.plots import pyplot, speed_plot

    fig = speed_plot(_run())
    top, bottom = fig.axes[:2]
    assert top.lines[0].get_ydata().max() == pytest.approx(7000.0, rel=1e-12)       # deg/s
    assert bottom.lines[0].get_ydata().max() == pytest.approx(7000.0 / 121, rel=1e-12)
    pyplot().close(fig)
    fig, ax = pyplot().subplots()          # into a caller's axis: the output on a twin axis
    speed_plot(_run(), ax=ax)
    assert [a.lines[0].get_ydata().max() for a in fig.axes] == pytest.approx(
        [7000.0, 7000.0 / 121], rel=1e-12)
    pyplot().close(fig)


def test_order_labels_do_not_overlap_on_a_log_axis():
    from rvsim.analysis.catalogue import reducer_orders
    from rvsim.parameters import RV40E
    from rvsim.plots import order_spectrum_plot, pyplot

    marks = reducer_orders(RV40E)          # 39, 40, 78, 80 and 121: labels were on each other
    orders = np.arange(0, 400)
    amplitude = np.where(orders == 80, 0.0136, 0.0)
    fig = order_spectrum_plot(orders, amplitude, marks)
    ax = fig.axes[0]
    assert ax.get_xscale() == "log"
    renderer = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(renderer) for t in ax.texts]
    assert len(boxes) == 6       # 1, 39, 40 (two names), 78, 80, 121; the mesh's 2160 is off
    assert "crank (rel. carrier), pins zp" in [t.get_text().strip() for t in ax.texts]
    assert not [(a, b) for i, a in enumerate(boxes) for b in boxes[i + 1:] if a.overlaps(b)]
    assert ax.get_ylim()[1] > 0.0136                       # the line below the labels' rows
    pyplot().close(fig)


def test_sobol_indices_wider_than_their_interval_flagged_with_advice():
    from rvsim.tolerance.report import sobol_advice, sobol_table

    indices = {"disc_pitch": {"S1": -0.05, "S1_conf": 0.4, "ST": 0.3, "ST_conf": 0.5},
               "pin_radius": {"S1": 0.6, "S1_conf": 0.1, "ST": 0.65, "ST_conf": 0.1},
               "carrier_holes": {"S1": 0.001, "S1_conf": 0.01, "ST": 0.01, "ST_conf": 0.02}}
    table = sobol_table(indices)
    assert table.loc["disc_pitch", "flag"] == ("S1: interval wider than the index; ST: "
                                               "interval wider than the index; S1 < 0: "
                                               "sampling error")
    assert table.loc["pin_radius", "flag"] == ""
    # an error the metric does not depend on: exactly 0, no interval, not flagged
    zero = sobol_table({"k": {"S1": 0.0, "S1_conf": 0.0, "ST": 0.0, "ST_conf": 0.0}})
    assert zero.loc["k", "flag"] == ""
    # ST 0.3 +- 0.5 at base 2: (2 * 0.5 / 0.3)^2 = 11.1 times the base, 22.2 -> 32; ST 0.01
    # is below 0.05 and read as about zero
    assert sobol_advice(indices, base=2, errors=3) == (
        "1 total index(es) of at least 0.05 have an interval wider than half the index: "
        "intervals shrink as 1/sqrt(base); --sobol 32 (now 2: 256 reducers) would bring them "
        "to half the index.")
    assert sobol_advice({"pin_radius": indices["pin_radius"]}, base=2, errors=1) == ""
