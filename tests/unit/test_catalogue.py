"""Catalogue quantities on synthetic curves whose answers are known in closed form."""

import math

import numpy as np
import pytest

from rvsim.analysis.catalogue import (CurveError, backlash, hysteresis_loss, loop_branches,
                                      lost_motion, order_spectrum, reducer_orders,
                                      sweep_branches, torsional_rigidity,
                                      transmission_error_pp)
from rvsim.errors import RvsimError
from rvsim.parameters import RV40E

RATED = 412.0
K1, K2 = 2.0e5, 4.0e5            # N*m/rad below / above the knee
KNEE = 0.2 * RATED
CLEAR = 3.0e-4                   # total free play [rad]
SHIFT = 0.5e-4                   # friction: each branch shifted by this, away from the other


def _elastic(t):
    """Wind-up of a two-slope spring, odd in the torque."""
    m = np.abs(t)
    wind = np.where(m <= KNEE, m / K1, KNEE / K1 + (m - KNEE) / K2)
    return np.sign(t) * wind


def _branch(t, sign, came_from):
    """Angle of the increasing (sign=+1) or decreasing (-1) branch; a sample at 0 N*m sits on
    the side the sweep came from."""
    side = np.where(t > 0, 1.0, np.where(t < 0, -1.0, came_from))
    return _elastic(t) + side * CLEAR / 2 - sign * SHIFT


def _loop(n=41, with_zero=True, virgin=True):
    grid = np.linspace(-RATED, RATED, n)
    if not with_zero:
        inner = grid[:-1] + 0.37 * (grid[1] - grid[0])
        grid = np.concatenate([[-RATED], inner, [RATED]])
    up_t, down_t = grid, grid[::-1]
    parts_t = [up_t, down_t]
    parts_a = [_branch(up_t, 1.0, -1.0), _branch(down_t, -1.0, 1.0)]
    parts_b = [np.ones(up_t.size), -np.ones(down_t.size)]
    if virgin:   # 0 -> -rated from the centred state: not part of the loop
        first = np.linspace(0.0, -RATED, 11)
        parts_t.insert(0, first)
        parts_a.insert(0, _elastic(first) * 1.3)
        parts_b.insert(0, -np.ones(first.size))
    # order: virgin (-1), up (+1), down (-1)
    return np.concatenate(parts_t), np.concatenate(parts_a), np.concatenate(parts_b)


@pytest.mark.parametrize("with_zero", [True, False])
def test_loop_quantities_exact(with_zero):
    t, a, b = _loop(with_zero=with_zero)
    assert torsional_rigidity(t, a, RATED, branch=b) == pytest.approx(K2, rel=1e-12)
    # the loop width at 0 N*m: free play plus both friction shifts
    assert backlash(t, a, b) == pytest.approx(CLEAR + 2 * SHIFT, rel=1e-12)
    assert hysteresis_loss(t, a, b, RATED) == pytest.approx(CLEAR + 2 * SHIFT, rel=1e-12)
    # mid-points of the width at +-3 %: elastic wind-up at 3 % plus half the free play each
    expected = CLEAR + 2 * 0.03 * RATED / K1
    assert lost_motion(t, a, b, RATED) == pytest.approx(expected, rel=1e-12)


def test_rigidity_interval_and_directions():
    t = np.linspace(-RATED, RATED, 81)
    a = _elastic(t)
    assert torsional_rigidity(t, a, RATED) == pytest.approx(K2, rel=1e-12)
    assert torsional_rigidity(t, a, RATED, direction="negative") == pytest.approx(K2, rel=1e-12)
    # over 0..20 % the secant is the first slope
    assert torsional_rigidity(t, a, RATED, 0.0, 0.2) == pytest.approx(K1, rel=1e-12)
    # a loop without friction or clearance: everything but the rigidity is zero
    up = np.linspace(-RATED, RATED, 21)
    tt = np.concatenate([up, up[::-1]])
    bb = np.concatenate([np.ones(21), -np.ones(21)])
    aa = _elastic(tt)
    assert backlash(tt, aa, bb) == pytest.approx(0.0, abs=1e-18)
    assert hysteresis_loss(tt, aa, bb) == pytest.approx(0.0, abs=1e-18)


@pytest.mark.parametrize("call, words", [
    (lambda t, a, b: torsional_rigidity(t, a, 2 * RATED, branch=b), "never reaches"),
    (lambda t, a, b: torsional_rigidity(t, a, -1.0, branch=b), "positive finite"),
    (lambda t, a, b: lost_motion(t[b > 0], a[b > 0], b[b > 0], RATED), "no decreasing branch"),
    (lambda t, a, b: lost_motion(t[:3], a[:3], b[:3], RATED), "no increasing"),
    (lambda t, a, b: backlash(t, a[:-1], b), "has"),
    (lambda t, a, b: backlash(t, np.where(t > 0, np.nan, a), b), "NaN"),
    (lambda t, a, b: backlash(t, a, b * 2), r"\+1"),
])
def test_bad_loops(call, words):
    t, a, b = _loop()
    with pytest.raises(RvsimError, match=words):
        call(t, a, b)


def test_small_reversal_gives_backlash_not_hysteresis_loss():
    # a reversal at +-5 % of rated: the catalogue reads backlash from such a loop
    grid = np.linspace(-0.05 * RATED, 0.05 * RATED, 11)
    t = np.concatenate([grid, grid[::-1][1:]])
    b = np.concatenate([np.ones(11), -np.ones(10)])
    a = np.concatenate([_branch(grid, 1.0, -1.0), _branch(grid[::-1][1:], -1.0, 1.0)])
    assert backlash(t, a, b) == pytest.approx(CLEAR + 2 * SHIFT, rel=1e-12)
    with pytest.raises(CurveError, match="reaches only"):
        hysteresis_loss(t, a, b, RATED)


def test_no_zero_crossing_and_too_few_points():
    t = np.array([10.0, 100.0, 400.0, 100.0, 10.0])
    b = np.array([1, 1, 1, -1, -1])
    with pytest.raises(CurveError, match="does not cross 0"):
        backlash(t, t / K1, b)
    t = np.array([-RATED, RATED, -RATED])
    with pytest.raises(CurveError, match="too few points"):
        lost_motion(t, t / K1, np.array([1, 1, -1]), RATED)
    with pytest.raises(CurveError, match="too few points on the negative side"):
        torsional_rigidity([0.0, 300.0, 200.0, 412.0], [0, 1, 2, 3], RATED)
    with pytest.raises(CurveError, match="repeats a value"):
        torsional_rigidity([0.0, 300.0, 300.0, 412.0], [0, 1, 2, 3], RATED)


def test_branches_from_the_sweep_direction():
    # the engine's sequence 0 -> -rated -> 0 -> +rated -> 0 -> -rated, no branch given
    t, a, b = _loop(virgin=True)
    keep = np.r_[True, np.diff(t) != 0]          # drop the repeated turning point
    t, a, b = t[keep], a[keep], b[keep]
    assert np.array_equal(sweep_branches(t)[1:], b[1:])
    assert torsional_rigidity(t, a, RATED) == pytest.approx(K2, rel=1e-12)
    assert torsional_rigidity(t, a, RATED) == torsional_rigidity(t, a, RATED, branch=b)


def _te(theta):
    return (1e-4 * np.cos(39 * theta + 0.3) + 4e-5 * np.cos(40 * theta - 1.1)
            + 2e-5 * np.cos(theta + 2.0) + 7e-6 * np.cos(121 * theta) + 3e-5)


@pytest.mark.parametrize("revolutions, n", [(1, 360), (2, 1001), (1, 720)])
def test_order_spectrum_exact_for_integer_orders(revolutions, n):
    theta = 0.2 + np.arange(n) * 2 * np.pi * revolutions / n
    orders, amp, phase = order_spectrum(theta, _te(theta), with_phase=True)
    at = {int(round(o)): i for i, o in enumerate(orders) if abs(o - round(o)) < 1e-9}
    for order, amplitude, ph in ((39, 1e-4, 0.3), (40, 4e-5, -1.1), (1, 2e-5, 2.0),
                                 (121, 7e-6, 0.0)):
        assert amp[at[order]] == pytest.approx(amplitude, rel=1e-9)
        assert phase[at[order]] == pytest.approx(ph, abs=1e-9)
    assert amp[0] == pytest.approx(3e-5, rel=1e-9)
    others = np.setdiff1d(np.arange(orders.size), [at[k] for k in (0, 1, 39, 40, 121)])
    assert np.max(amp[others]) < 1e-17     # round-off of 1e-4 amplitudes
    # reversed direction: same amplitudes and phases
    back = -theta
    orders_b, amp_b, phase_b = order_spectrum(back, _te(back), with_phase=True)
    assert np.allclose(amp_b, amp, rtol=0, atol=1e-17)
    assert phase_b[at[39]] == pytest.approx(0.3, abs=1e-9)


def test_order_spectrum_hann_and_errors():
    theta = np.arange(360) * 2 * np.pi / 360
    orders, amp = order_spectrum(theta, 1e-4 * np.cos(20 * theta), window="hann")
    assert amp[20] == pytest.approx(1e-4, rel=1e-12)
    assert amp[19] == pytest.approx(0.5e-4, rel=1e-12)    # Hann leaks half into neighbours
    with pytest.raises(CurveError, match="whole output revolutions"):
        order_spectrum(theta[:300], np.zeros(300))
    with pytest.raises(CurveError, match="equally spaced"):
        order_spectrum(theta ** 1.01, np.zeros(360))
    with pytest.raises(CurveError, match="too few"):
        order_spectrum(theta[:3], np.zeros(3))
    with pytest.raises(CurveError, match="window"):
        order_spectrum(theta, np.zeros(360), window="flat")


def test_te_pp_and_orders_of_the_rv40e():
    assert transmission_error_pp([1.0, -2.0, 0.5]) == 3.0
    with pytest.raises(CurveError, match="too few"):
        transmission_error_pp([1.0])
    orders = reducer_orders(RV40E)
    assert orders["crank (rel. carrier)"] == pytest.approx(40.0, rel=1e-14)  # = zp
    assert orders["disc teeth zc"] == 39 and orders["pins zp"] == 40
    assert orders["input shaft i"] == 121 and orders["sun-planet mesh"] == 120 * 18
    assert math.isclose(orders["2 zc"], 78)


def test_reversal_point_starts_the_next_branch():
    # an engine may label the turning point -rated with the run that ends there
    t, a, b = _loop(virgin=True)
    up = np.flatnonzero(b > 0)
    t2, a2, b2 = np.delete(t, up[0]), np.delete(a, up[0]), np.delete(b, up[0])
    assert t2[up[0] - 1] == -RATED and b2[up[0] - 1] == -1      # turning point kept, as -1
    (tu, _), _ = loop_branches(t2, a2, b2)
    assert tu[0] == -RATED
    assert lost_motion(t2, a2, b2, RATED) == pytest.approx(lost_motion(t, a, b, RATED),
                                                          rel=1e-12)
