"""The speed-torque grid's natural frequency, order frequencies and main orders against hand
calculations (issue 33 item 4)."""

import math
import types

import numpy as np
import pytest

from rvsim.doe.grid import _excitation, main_orders
from rvsim.doe.modes import natural_frequency, output_inertia, torsional_mode
from rvsim.parameters import RV40E, with_values
from rvsim.units import ARCMIN


def test_natural_frequency_of_an_inertia_on_a_spring():
    # 1e5 N*m/rad, 0.25 kg*m^2: omega = sqrt(4e5) = 632.4555320336759 rad/s
    assert natural_frequency(1e5, 0.25) == pytest.approx(632.4555320336759 / (2 * math.pi),
                                                         rel=1e-15)
    assert math.isnan(natural_frequency(0.0, 0.25))


def test_the_rv40e_output_mode_at_200_nm_by_hand():
    """The RV-40E at 200 N*m: the output inertia is the 0.3 kg*m^2 load, the carrier's 0.0151520
    and the two discs' 0.0066246 each (docs/model.md section 21); the stiffness is the ltca's
    mean local stiffness with the input held, 832.08 N*m/arcmin (2026-11-28)."""
    mode = torsional_mode(RV40E, 200.0)
    inertia = 0.3 + 0.0151520270319697 + 2 * 0.0066245958558432605
    assert mode.inertia == pytest.approx(inertia, rel=1e-12)
    assert mode.stiffness == pytest.approx(2860451.963427986, rel=1e-9)
    hand = math.sqrt(2860451.963427986 / inertia) / (2 * math.pi)   # 469.7 Hz
    assert hand == pytest.approx(469.71, abs=0.01)
    assert mode.frequency == pytest.approx(hand, rel=1e-9)
    low, high = mode.band
    assert low <= mode.frequency <= high
    # the driven load is part of the output inertia
    heavy = with_values(RV40E, {"operating.load_inertia": "3.0"}, check=False)
    assert output_inertia(heavy) == pytest.approx(inertia + 2.7, rel=1e-12)
    assert mode.summary()["torsional_stiffness_nm_per_arcmin"] == pytest.approx(
        2860451.963427986 * ARCMIN, rel=1e-12)


def test_orders_inside_the_half_power_band_are_marked():
    # orders 10 and 40 at 5 Hz output: 50 and 200 Hz; f_n 51 Hz with zeta 0.05: 50 / 51 is
    # inside 1 -+ 0.05, 200 / 51 is not
    out = _excitation({"a": 10.0, "b 2": 40.0}, 5.0, 51.0, 0.05)
    assert out["f_a_hz"] == 50.0 and out["f_b_2_hz"] == 200.0
    assert out["nearest_order"] == "a"
    assert out["nearest_order_ratio"] == pytest.approx(50.0 / 51.0, rel=1e-15)
    assert out["resonance"] == "a"
    assert _excitation({"a": 10.0}, 5.0, 60.0, 0.05)["resonance"] == ""
    assert _excitation({"a": 10.0}, 5.0, float("nan"), 0.05)["nearest_order"] == ""


def test_main_orders_of_a_known_te():
    """TE = 0.01 cos(39 a) + 0.004 cos(80 a) arcmin over 1.1 output revolutions sampled in time
    after a 0.2 s start: orders 39 and 80 with their amplitudes (linear resampling error below
    1e-5 arcmin at 4000 samples a revolution)."""
    ratio = 121.0
    time = np.arange(0.0, 1.3, 1.0 / 4000.0)
    theta_in = 2 * math.pi * ratio * time          # one output revolution a second
    nominal = theta_in / ratio
    te = (0.01 * np.cos(39 * nominal) + 0.004 * np.cos(80 * nominal)) * ARCMIN
    result = types.SimpleNamespace(time=time, steady_start=0.2, theta_in=theta_in, te=te,
                                   ratio=ratio)
    out = main_orders(result)
    assert (out["order1"], out["order2"]) == (39.0, 80.0)
    assert out["order1_arcmin"] == pytest.approx(0.01, abs=1e-5)
    assert out["order2_arcmin"] == pytest.approx(0.004, abs=1e-5)
    assert out["order3_arcmin"] < 1e-5


def test_the_dynamic_engine_rings_at_the_predicted_frequency():
    """The RV-40E loaded at 200 N*m within 0.01 s at 100 rpm (the mesh at 30 Hz, far below):
    the output rings in the TE after the load step at 473.8 Hz (peak of the Hann spectrum of
    0.5 s, interpolated; 0.3 s gave 480.6 Hz, just above the band: 3.3 Hz bins), 0.9 % above
    f_n = 469.7 Hz and inside its band (docs/model.md section 21: 415.3 / 563.0 Hz at 100 /
    412 N*m against 413.0 / 564.0 Hz)."""
    from rvsim.dynamics import simulate

    reducer = with_values(RV40E, {"operating.input_speed": "100rpm",
                                  "operating.load_torque": "200",
                                  "operating.speed_ramp_time": "0.02",
                                  "operating.load_start": "0.02",
                                  "operating.load_ramp_end": "0.03",
                                  "operating.steady_start": "0.04",
                                  "operating.duration": "0.54"})
    result = simulate(reducer)
    window = result.time >= 0.04
    te = result.te[window] - result.te[window].mean()
    spectrum = np.abs(np.fft.rfft(te * np.hanning(te.size)))
    step = 1.0 / (te.size * (result.time[1] - result.time[0]))
    k = int(np.argmax(np.where(np.arange(spectrum.size) * step > 50.0, spectrum, 0.0)))
    a, b, c = np.log(spectrum[k - 1:k + 2])
    peak = (k + 0.5 * (a - c) / (a - 2 * b + c)) * step
    mode = torsional_mode(reducer)
    low, high = mode.band
    assert low <= peak <= high
    assert peak == pytest.approx(PEAK_200, rel=1e-6)
    assert abs(peak / mode.frequency - 1.0) < 0.012


#: the interpolated ringing peak of the 0.5 s window [Hz] (2026-11-28)
PEAK_200 = 473.79033806115865
