"""Result post-processing: metrics and spectrum on synthetic signals with known answers."""

import numpy as np
import pytest

from rvsim.dynamics import te_metrics, te_spectrum
from rvsim.units import ARCMIN


def _signal(order=40.0, amplitude=0.2, mean=1.5, pins=40):
    time = np.arange(0.0, 4.0, 1e-3)
    omega_out = np.full_like(time, np.deg2rad(57.85))
    crank_hz = omega_out[0] * pins / (2 * np.pi)
    te = (mean + amplitude * np.sin(2 * np.pi * order * crank_hz * time)) * ARCMIN
    return time, te, omega_out


def test_metrics_of_a_sinusoid():
    time, te, omega_out = _signal()
    m = te_metrics(time, te, 121 * omega_out, omega_out, 1.5)
    assert m["te_mean_arcmin"] == pytest.approx(1.5, abs=1e-3)
    assert m["te_pp_arcmin"] == pytest.approx(0.4, abs=1e-3)
    assert m["te_std_arcmin"] == pytest.approx(0.2 / np.sqrt(2), rel=1e-2)
    assert m["speed_ratio"] == pytest.approx(121.0)


def test_spectrum_finds_the_order_and_amplitude():
    time, te, omega_out = _signal(order=40.0, amplitude=0.2)
    orders, amplitude = te_spectrum(time, te, omega_out, 1.5, 40)
    peak = np.argmax(amplitude)
    assert orders[peak] == pytest.approx(40.0, abs=0.5)
    assert amplitude[peak] == pytest.approx(0.2, rel=0.1)


def test_empty_window_gives_nan_metrics():
    time, te, omega_out = _signal()
    m = te_metrics(time, te, omega_out, omega_out, 10.0)
    assert np.isnan(m["te_mean_arcmin"])


def test_crank_frequency_is_the_order_unit_of_the_spectrum():
    from rvsim.dynamics.result import crank_frequency

    time, te, omega_out = _signal()
    assert crank_frequency(time, omega_out, 1.5, 40) == pytest.approx(
        np.deg2rad(57.85) * 40 / (2 * np.pi), rel=1e-12)
    assert crank_frequency(time, omega_out, 10.0, 40) == 0.0


def test_spectrum_plot_marks_the_load_fluctuation_order():
    import types

    from rvsim.plots import spectrum_plot

    time, te, omega_out = _signal()
    run = types.SimpleNamespace(time=time, te=te, omega_out=omega_out, steady_start=1.5)
    crank_hz = np.deg2rad(57.85) * 40 / (2 * np.pi)
    fig = spectrum_plot(run, fluctuation_frequency=20.0)
    lines = [line.get_xdata()[0] for line in fig.axes[0].lines[1:]]
    labels = [text.get_text() for text in fig.axes[0].texts]
    assert any(abs(x - 20.0 / crank_hz) < 1e-9 for x in lines)
    assert any("load fluctuation 20 Hz" in label for label in labels)
    plain = spectrum_plot(run)
    assert not any("load fluctuation" in t.get_text() for t in plain.axes[0].texts)
