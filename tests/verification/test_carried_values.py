"""What the kernel carries from one step to the next instead of computing it again (issue 14,
docs/model.md section 9): the contact laws' series, the pins' cosines and sines of their foot
and F**0.9, the bushings' logarithm shift.  Each against the direct computation, to tolerances
a few times the round-off measured."""

import math

import numpy as np
import pytest

from rvsim.physics._bearings import (SERIES_LIMIT as LOG_LIMIT, bushing_shift,
                                     conforming_force, log_ratio)
from rvsim.physics._contact_law import (EXPONENT, SERIES_LIMIT as POWER_LIMIT, power_ratio,
                                        spring_force, spring_force_power)
from rvsim.dynamics.model import build_model
from rvsim.geometry._curve import ROTATION_LIMIT, TRACKING_LIMIT, pin_gap, rotated
from rvsim.parameters import RV40E

X = np.concatenate([-np.geomspace(1e-2, 1e-9, 60), [0.0], np.geomspace(1e-9, 1e-2, 60)])


#: the turns up to ROTATION_LIMIT (3e-2 since the scheme implicit-bearings' 4x larger step)
D = np.concatenate([-np.geomspace(3e-2, 1e-9, 60), [0.0], np.geomspace(1e-9, 3e-2, 60)])


def test_series_limits_as_documented():
    assert POWER_LIMIT == LOG_LIMIT == 1e-2
    assert ROTATION_LIMIT == 3e-2


@pytest.mark.parametrize("x", X)
def test_power_series_within_round_off(x):
    assert power_ratio(x) == pytest.approx((1.0 + x) ** EXPONENT, rel=4e-16, abs=0)  # 2.2e-16


@pytest.mark.parametrize("x", X)
def test_log_series_within_round_off(x):
    assert log_ratio(x) == pytest.approx(math.log1p(x), rel=4e-16, abs=1e-300)


@pytest.mark.parametrize("d", D)
def test_rotation_within_round_off(d):
    c0, s0 = math.cos(0.7), math.sin(0.7)
    c, s = rotated(c0, s0, d)
    assert c == pytest.approx(math.cos(0.7 + d), abs=4e-16)
    assert s == pytest.approx(math.sin(0.7 + d), abs=4e-16)


def test_rotation_keeps_unit_length_over_a_million_turns():
    c, s = 1.0, 0.0
    for _ in range(1000):
        for _ in range(1000):
            c, s = rotated(c, s, 3.3e-5)
    assert c * c + s * s == pytest.approx(1.0, abs=1e-15)
    assert c == pytest.approx(math.cos(33.0), abs=1e-10)   # the angle's own round-off


def test_pin_gap_with_carried_trig_equals_the_direct_one():
    model = build_model(RV40E, 5e-6)
    from rvsim.physics import _layout as L
    rg, a, zp = model.P[L.RG], model.P[L.A_GEN], model.P[L.ZP]
    clearance = model.P[L.PROFILE_OFFSET] - model.P[L.PIN_RADIUS]
    rng = np.random.default_rng(3)
    worst_gap = worst_trig = worst_u = 0.0
    tracked = 0
    for _ in range(200):
        nominal = rng.uniform(-4.0, 4.0)
        u_c = nominal + rng.uniform(-0.02, 0.02)
        x, y, *_ = _point(u_c, rg, a, zp)
        qx, qy = x * (1 + 1e-6), y * (1 + 1e-6)          # near the curve: tracked
        carried = np.array([u_c, math.cos(u_c), math.sin(u_c), math.cos(zp * u_c),
                            math.sin(zp * u_c)])
        # the foot moved since (within the tracking step) and the disc turned (within the
        # carried turn): the carried values are turned by previous - u_c, then by du
        previous = u_c + rng.uniform(-0.9, 0.9) * min(TRACKING_LIMIT, ROTATION_LIMIT / zp)
        direct = pin_gap(qx, qy, nominal, previous, rg, a, zp, clearance, True, carried[0:0])
        turned = pin_gap(qx, qy, nominal, previous, rg, a, zp, clearance, True, carried)
        tracked += abs(turned[1] - previous) <= TRACKING_LIMIT
        worst_u = max(worst_u, abs(turned[1] - direct[1]))
        worst_gap = max(worst_gap, abs(turned[0] - direct[0]))
        # tracked: what is carried belongs to the start (previous), the next call turns it
        # through this call's Newton step as well
        u = carried[0]
        exact = (math.cos(u), math.sin(u), math.cos(zp * u), math.sin(zp * u))
        assert u == previous
        worst_trig = max(worst_trig, max(abs(carried[1 + k] - exact[k]) for k in range(4)))
    assert tracked == 200             # every case took the tracked (carried) path
    assert worst_u < 4e-15            # rad; measured 8.9e-16 (1 ulp of u ~ 4)
    assert worst_gap < 1e-16          # m; measured 3.5e-17 (the point's round-off)
    # measured 2.9e-14: cos(zp u) of zp u ~ 160 rad carries that much from rounding zp u
    assert worst_trig < 6e-14


def _point(u, rg, a, zp):
    from rvsim.geometry._curve import curve_point
    return curve_point(u, rg, a, zp)


@pytest.mark.parametrize("change", [0.0, 1e-7, -3e-5, 2e-3, -8e-3, 0.3])
def test_carried_power_finds_the_root(change):
    # the approach of a known force, solved from the previous force with its power carried:
    # Newton's steps below 1e-2 carry F^0.9 by the series, the last one to first order
    c, cb = 2.3e-9, 1.7e-10
    guess = 850.0
    root = guess * (1 + change)
    delta = c * root ** EXPONENT + cb * root
    f, k, e, fe = spring_force_power(delta, c, cb, guess, guess ** EXPONENT)
    assert f == pytest.approx(root, rel=2e-14)             # measured 4.1e-15 at most
    assert fe == pytest.approx(f ** EXPONENT, rel=1e-15)   # what the next call is given
    assert (f, k, e) == pytest.approx(spring_force(delta, c, cb, 0.0), rel=2e-14)


@pytest.mark.parametrize("change", [1e-7, -3e-5, 2e-3, -8e-3, 0.3])
def test_conforming_force_with_carried_logarithm_finds_the_root(change):
    from rvsim.physics import _layout as L
    from rvsim.physics._bearings import conforming_approach
    P = build_model(RV40E, 5e-6).P
    law = (P[L.SUP_J1], P[L.SUP_A1], P[L.SUP_J2], P[L.SUP_A2_U], 0.0)
    guess = 4000.0
    root = guess * (1 + change)
    delta, _, _ = conforming_approach(root, *law)
    f, k, e = conforming_force(delta, *law, guess, P[L.SUP_SHIFT_U])
    assert f == pytest.approx(root, rel=3e-14)           # measured 6.1e-15
    _, compliance, energy = conforming_approach(f, *law)
    assert 1.0 / k == pytest.approx(compliance, rel=3e-14)   # measured 5.2e-15
    assert e == pytest.approx(energy, rel=5e-15)             # measured 8.9e-16


def test_bushing_shift_given_or_computed_is_the_same_force():
    model = build_model(RV40E, 5e-6)
    from rvsim.physics import _layout as L
    P = model.P
    args = (P[L.SUP_J1], P[L.SUP_A1], P[L.SUP_J2], P[L.SUP_A2_U], 0.0, 4000.0)
    assert P[L.SUP_SHIFT_U] == bushing_shift(P[L.SUP_A1], P[L.SUP_A2_U]) != 0.0
    given = conforming_force(3e-6, *args, P[L.SUP_SHIFT_U])
    computed = conforming_force(3e-6, *args, math.nan)    # NaN (the default): computed
    assert given == computed          # bit for bit: the same logarithm
    assert bushing_shift(1.0, 1.0) == bushing_shift(0.0, 2.0) == 0.0


# Newton started from the previous solution's Taylor expansion (the kernel's bushings and pins
# carry the approach and stiffness of their last solution): the same root, whatever the change
# (beyond the series, 1e-2, Newton starts from the predictor up to PREDICTOR_LIMIT, 0.5)
CHANGES = [0.0, 1e-7, -3e-5, 2e-3, -8e-3, 0.05, -0.03, 0.3, 0.9, -0.5]


@pytest.mark.parametrize("f0", [40.0, 4000.0, 60000.0])     # 60 kN: both interfaces wrapped
@pytest.mark.parametrize("change", CHANGES)
def test_conforming_force_from_the_last_solution_finds_the_root(f0, change):
    from rvsim.physics import _layout as L
    from rvsim.physics._bearings import (conforming_approach, conforming_force_carried,
                                         conforming_force_from)
    P = build_model(RV40E, 5e-6).P
    law = (P[L.SUP_J1], P[L.SUP_A1], P[L.SUP_J2], P[L.SUP_A2_U], 0.0)
    d0, _, _ = conforming_approach(f0, *law)
    last, k0, _, log0 = conforming_force_carried(d0, *law, 1.01 * f0, P[L.SUP_SHIFT_U])
    assert log0 == pytest.approx(math.log(law[1] / last), abs=2e-15)
    root = last * (1 + change)
    delta, compliance, energy = conforming_approach(root, *law)
    f, k, e, log = conforming_force_from(delta, *law, P[L.SUP_SHIFT_U], last, d0, k0, log0)
    assert f == pytest.approx(root, rel=6e-14)                # measured 3.1e-14 at most
    assert 1.0 / k == pytest.approx(compliance, rel=1e-14)    # measured 4.4e-15
    assert e == pytest.approx(energy, rel=7e-14)              # measured 3.6e-14
    assert log == pytest.approx(math.log(law[1] / f), abs=2e-15)   # measured 8.9e-16


@pytest.mark.parametrize("cb", [1.7e-10, 1.8e-10])    # the series compliance may have changed
@pytest.mark.parametrize("change", CHANGES[:-1])
def test_spring_force_from_the_last_solution_finds_the_root(cb, change):
    from rvsim.physics._contact_law import spring_force_from
    c = 2.3e-9
    d0 = c * 850.0 ** EXPONENT + 1.7e-10 * 850.0
    last, k0, _, fe0 = spring_force_power(d0, c, 1.7e-10, 0.0, 0.0)
    root = last * (1 + change)
    delta = c * root ** EXPONENT + cb * root
    f, k, e, fe = spring_force_from(delta, c, cb, last, fe0, d0, k0)
    direct = spring_force(delta, c, cb, 0.0)
    assert f == pytest.approx(root, rel=1e-14)                # measured 4.1e-15 at most
    assert k == pytest.approx(direct[1], rel=1.5e-15)         # measured 5.6e-16
    assert e == pytest.approx(direct[2], rel=2e-14)           # measured 8.2e-15
    assert fe == pytest.approx(f ** EXPONENT, rel=5e-16)      # measured 2.2e-16


# the predictors themselves: third order in the change (what makes one evaluation per call).
# Measured |F_start / F - 1| / |change|^3 over changes 1e-4..1e-2: conforming law 0.0138 (40
# N), 0.462 (4 kN), 0 (60 kN, both interfaces on their linear continuation); Palmgren law
# 0.0123.  A first-order start would be off by about 0.1 change^2: 1e-7 at 1e-3
@pytest.mark.parametrize("f0, bound", [(40.0, 0.03), (4000.0, 0.9), (60000.0, 1e-9)])
@pytest.mark.parametrize("change", [1e-4, -1e-3, 1e-3, -1e-2, 1e-2])
def test_conforming_start_is_third_order(f0, bound, change):
    from rvsim.physics import _layout as L
    from rvsim.physics._bearings import (NEWTON_CLOSE, conforming_approach,
                                         conforming_force_carried, conforming_start)
    P = build_model(RV40E, 5e-6).P
    law = (P[L.SUP_J1], P[L.SUP_A1], P[L.SUP_J2], P[L.SUP_A2_U], 0.0)
    d0, _, _ = conforming_approach(f0, *law)
    last, k0, _, _ = conforming_force_carried(d0, *law, 1.01 * f0, P[L.SUP_SHIFT_U])
    root = last * (1 + change)
    delta, _, _ = conforming_approach(root, *law)
    start = last * (1 + conforming_start(delta, last, d0, k0, law[1], law[0], law[3], law[2]))
    assert abs(start / root - 1) <= bound * abs(change) ** 3 + 4e-16
    if abs(change) <= 1e-3:       # Newton's first step from there already ends the iteration
        d, c, _ = conforming_approach(start, *law)
        assert abs(d - delta) / c <= NEWTON_CLOSE * start


@pytest.mark.parametrize("change", [1e-4, -1e-3, 1e-3, -1e-2, 1e-2])
def test_spring_start_is_third_order(change):
    from rvsim.physics._contact_law import NEWTON_CLOSE, spring_start
    c, cb = 2.3e-9, 1.7e-10
    d0 = c * 850.0 ** EXPONENT + cb * 850.0
    last, k0, _, fe0 = spring_force_power(d0, c, cb, 0.0, 0.0)
    root = last * (1 + change)
    delta = c * root ** EXPONENT + cb * root
    start = last * (1 + spring_start(delta, c, last, fe0, d0, k0))
    assert abs(start / root - 1) <= 0.025 * abs(change) ** 3 + 4e-16
    if abs(change) <= 1e-3:
        step = (c * start ** EXPONENT + cb * start - delta) / (
            EXPONENT * c * start ** (EXPONENT - 1) + cb)
        assert abs(step) <= NEWTON_CLOSE * start


def test_shared_cosines_equal_the_direct_ones():
    # one cosine and sine per angle (docs/model.md section 9): the constant turns of
    # model.fill_turns against the per-element formulas, with per-part eccentric phases and a
    # rotation modification.  Measured 2.5e-14 (eccentric) and 8e-15 (frame): the round-off
    # of angles up to 150 rad
    from rvsim.physics import _frames as Fr
    from rvsim.physics import _layout as L
    from rvsim.dynamics.model import fill_turns
    P = build_model(RV40E, 5e-6).P.copy()
    P[L.ECC_PHASE0:L.ECC_PHASE0 + 4] = 1e-3, -2e-3, 3e-3, 0.5
    P[L.PROFILE_ROT] = 8.7e-4
    fill_turns(P)
    rng = np.random.default_rng(5)
    worst = 0.0
    for _ in range(50):
        q = rng.uniform(-150.0, 150.0, L.N_DOF)
        crank_angles = np.array([0.0, math.pi])
        trig = Fr.angle_trig(q, crank_angles)
        for j in range(2):
            line = q[L.CARRIER] + crank_angles[j]
            worst = max(worst, abs(trig[2 * j] - math.cos(line)),
                        abs(trig[2 * j + 1] - math.sin(line)))
            ecc = Fr.eccentric_trig(P, q, j)
            for disc in range(2):
                phi = q[L.CRANK0 + L.CRANK_STRIDE * j + 4] + disc * math.pi + P[
                    L.ECC_PHASE0 + 2 * j + disc]
                worst = max(worst, abs(ecc[2 * disc] - math.cos(phi)),
                            abs(ecc[2 * disc + 1] - math.sin(phi)))
        for disc in range(2):
            theta = q[L.DISC0 + L.DISC_STRIDE * disc + 2]
            frame = Fr._disc_frame_at(P, q, np.zeros(L.N_DOF), disc, trig[4 + 2 * disc],
                                      trig[5 + 2 * disc])
            angle = theta - disc * math.pi / P[L.ZC] + P[L.PROFILE_ROT]
            worst = max(worst, abs(frame[1] - math.cos(angle)), abs(frame[2] - math.sin(angle)))
    assert worst < 1e-13
