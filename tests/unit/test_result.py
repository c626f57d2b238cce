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
