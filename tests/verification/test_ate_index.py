"""The bench's index, the ATE (issue 33, item 1): the peak-to-peak of TE over one output
revolution (GB/T 35089-2018, the catalogues; docs/catalogue_tests.md), beside the paper's mean
TE, under one name (``ate_arcmin``) in every engine's JSON.

Hand checks: the ATE is max - min of the returned TE curve over the revolution; over several
complete revolutions the largest of theirs; none below one revolution."""

import math

import numpy as np
import pytest

from rvsim.analysis.catalogue import angular_transmission_error
from rvsim.dynamics import Result
from rvsim.parameters import RV40E
from rvsim.physics import _layout as L
from rvsim.quasistatic import ltca
from rvsim.units import ARCMIN

TWO_PI = 2.0 * math.pi


# --- the curve function --------------------------------------------------------------------

def test_one_revolution_of_positions_is_its_peak_to_peak():
    n = 360
    angle = np.arange(n) * TWO_PI / n
    te = 0.3 + 0.2 * np.sin(40 * angle) + 0.05 * np.cos(3 * angle)
    ate, covered = angular_transmission_error(angle, te)
    assert covered == pytest.approx(1.0, abs=1e-12)
    assert ate == te.max() - te.min()           # max - min, to the bit


def test_the_largest_complete_revolution_counts_and_a_part_does_not():
    n = 100                                     # per revolution; 2.5 revolutions
    angle = np.arange(250) * TWO_PI / n
    amplitude = np.array([1.0, 3.0, 9.0])[(np.arange(250) // n)]
    te = amplitude * np.sin(7 * angle)
    ate, covered = angular_transmission_error(angle, te)
    assert covered == pytest.approx(2.5, abs=1e-12)
    second = te[n:2 * n]                        # the larger complete one; not the last half
    assert ate == second.max() - second.min()
    assert ate == pytest.approx(6.0, rel=2e-3)  # 2 * 3 (samples miss the crests by < 0.2 %)


def test_less_than_a_revolution_has_no_ate():
    angle = np.linspace(0.0, 0.4 * TWO_PI, 401)[:-1]       # 400 samples of 0.001 revolution
    ate, covered = angular_transmission_error(angle, np.sin(angle))
    assert math.isnan(ate) and covered == pytest.approx(0.4, abs=1e-12)
    ate, covered = angular_transmission_error(-angle, np.sin(angle))   # either direction
    assert math.isnan(ate) and covered == pytest.approx(0.4, abs=1e-12)
    assert angular_transmission_error([0.0], [1.0])[1] == 0.0


# --- the quasi-static engine: its peak-to-peak over the revolution is the ATE ----------------

def test_ltca_ate_is_the_peak_to_peak_of_its_revolution():
    result = ltca(RV40E, positions=16, allow_aliasing=True)
    s = result.summary()
    assert s["te_window_revolutions"] == pytest.approx(1.0, abs=1e-12)
    assert s["ate_arcmin"] == s["te_pp_arcmin"]             # the same number, to the bit
    te = result.te / ARCMIN
    assert s["ate_arcmin"] == pytest.approx(te.max() - te.min(), rel=1e-12)


def test_ltca_over_two_revolutions_and_over_half_of_one():
    two = ltca(RV40E, positions=32, revolutions=2.0, allow_aliasing=True)
    s = two.summary()
    te = two.te / ARCMIN
    assert s["te_window_revolutions"] == pytest.approx(2.0, abs=1e-12)
    assert s["ate_arcmin"] == pytest.approx(max(np.ptp(te[:16]), np.ptp(te[16:])), rel=1e-12)
    half = ltca(RV40E, positions=16, revolutions=0.5, allow_aliasing=True).summary()
    assert half["ate_arcmin"] != half["ate_arcmin"]          # NaN: no ATE from half a turn
    assert half["te_window_revolutions"] == pytest.approx(0.5, abs=1e-12)
    assert half["te_pp_arcmin"] > 0.0                        # its peak-to-peak stays


# --- the dynamic engine: the steady window, honestly -------------------------------------------

def _result(revolutions: float, steady_start: float = 1.0, duration: float = 3.0) -> Result:
    """A synthetic run: the output turns ``revolutions`` during the steady window (uniformly,
    from t = 0), TE = 0.5 + 0.1 t arcmin + a 40th-order ripple of 0.02 arcmin."""
    time = np.arange(0.0, duration, 1e-3)
    rate = revolutions * TWO_PI / (duration - steady_start)
    theta_out = rate * time
    te = (0.5 + 0.1 * time + 0.02 * np.sin(40 * theta_out)) * ARCMIN
    channels = np.zeros((time.size, L.N_CHANNELS))
    channels[:, L.CHANNEL_NAMES.index("time")] = time
    channels[:, L.CHANNEL_NAMES.index("theta_out")] = theta_out
    channels[:, L.CHANNEL_NAMES.index("theta_in")] = 121.0 * (theta_out + te)
    channels[:, L.CHANNEL_NAMES.index("omega_out")] = rate
    channels[:, L.CHANNEL_NAMES.index("omega_in")] = 121.0 * rate
    return Result(time=time, channels=channels, pin_forces=np.ones((time.size, 2, 40)),
                  ratio=121.0, steady_start=steady_start, status="ok", steps=time.size,
                  wall_s=0.0, energy={})


def _ramp_ripple_pp(period: float, periods: int, a: float = 0.1, b: float = 0.02) -> float:
    """max - min of a t + b sin(2 pi t / period) over ``periods`` whole periods from phase 0:
    the extrema lie where cos(phase) = -k, k = a / (b omega); the lowest is the first trough
    (phase 2 pi - arccos(-k)), the highest the last crest (arccos(-k) + 2 pi (periods - 1))."""
    omega = TWO_PI / period
    k = a / (b * omega)
    return (a / omega * (2.0 * math.acos(-k) + TWO_PI * (periods - 2))
            + 2.0 * b * math.sqrt(1.0 - k * k))


def test_dynamic_window_over_a_revolution_gives_the_ate():
    r = _result(1.5)
    s = r.summary()
    window = r.time >= r.steady_start
    te = r.te[window] / ARCMIN
    first = te[: int(round(window.sum() / 1.5))]             # the window's first revolution
    assert s["te_window_revolutions"] == pytest.approx(1.5, rel=1e-9)
    assert s["ate_arcmin"] == pytest.approx(np.ptp(first), rel=1e-9)
    # by hand: the revolution holds 40 ripple periods of 1/30 s, the whole window 60
    assert s["ate_arcmin"] == pytest.approx(_ramp_ripple_pp(1 / 30, 40), abs=1.5e-4)
    assert s["te_pp_arcmin"] == pytest.approx(_ramp_ripple_pp(1 / 30, 60), abs=1.5e-4)
    assert "ate_note" not in s


def test_dynamic_window_shorter_than_a_revolution_says_so():
    s = _result(0.4).summary()
    assert s["ate_arcmin"] != s["ate_arcmin"]
    assert s["te_window_revolutions"] == pytest.approx(0.4, rel=1e-9)
    assert "0.4 of an output revolution" in s["ate_note"]
    assert s["te_pp_arcmin"] == pytest.approx(_ramp_ripple_pp(0.125, 16), abs=1.5e-4)
