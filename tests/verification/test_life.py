"""Rating life of the crank bearings (issue 32 item 5; docs/model.md section 19): ISO 281's
dynamic load ratings against hand calculations, the life law, the mean load of a known load
cycle, the tapered pair rule, the kinematics, and the engine's numbers against the same
formulas applied to the quasi-static loads."""

import math

import numpy as np
import pytest

from rvsim.errors import ParameterError
from rvsim.parameters import RV40E
from rvsim.parameters.rv40e_bearings import RV40E_ROLLING
from rvsim.physics import rating_life as iso

RPM = 2.0 * math.pi / 60.0


# --- dynamic load ratings against hand calculations ----------------------------------------

def test_needle_rating_by_hand():
    # RV-40E-bearings: Z = 20 needles of 3 mm, L_we = 12 mm, D_pw = 25 + 3 = 28 mm, alpha = 0.
    # gamma = 3 / 28 = 0.107143; f_c between 0.10 (84.2) and 0.11 (85.4): 85.0571;
    # C = 1.1 x 85.0571 x 12^(7/9) [6.90817] x 20^(3/4) [9.45742] x 3^(29/27) [3.25434]
    #   = 19893.1 N
    c = iso.roller_dynamic_rating(20, 3e-3, 12e-3, 28e-3)
    assert iso.roller_fc(3.0 / 28.0) == pytest.approx(85.057143, abs=1e-6)
    assert c == pytest.approx(19893.11, rel=1e-6)


def test_tapered_rating_by_hand():
    # Z = 15 rollers of 5 mm, L_we = 8 mm, D_pw = 20 + 5 = 25 mm, alpha = 15 deg:
    # gamma = 5 cos 15 / 25 = 0.193185, f_c between 0.19 (88.8) and 0.20 (88.7): 88.76815;
    # C = 1.1 x 88.76815 x (8 cos 15)^(7/9) x 15^(3/4) x 5^(29/27) = 20566.3 N
    c = iso.roller_dynamic_rating(15, 5e-3, 8e-3, 25e-3, math.radians(15.0))
    assert c == pytest.approx(20566.33, rel=1e-6)


def test_ball_rating_by_hand():
    # main bearing row: Z = 30 balls of 9 mm on 140 mm, alpha = 40 deg: gamma = 0.049246,
    # f_c between 0.04 (43.8) and 0.05 (46.7): 46.48126;
    # C = 1.3 x 46.48126 x cos(40)^0.7 x 30^(2/3) x 9^1.8 = 25268.7 N
    c = iso.ball_dynamic_rating(30, 9e-3, 140e-3, math.radians(40.0))
    assert c == pytest.approx(25268.71, rel=1e-6)
    # above 25.4 mm: 3.647 D^1.4 in place of D^1.8 (ISO 281 Eq. 3), continuous within 0.1 %
    below = iso.ball_dynamic_rating(12, 25.4e-3, 400e-3, 0.0)
    above = iso.ball_dynamic_rating(12, 25.4001e-3, 400e-3, 0.0)
    assert above == pytest.approx(below, rel=2e-3)


def test_roller_table_matches_the_closed_form():
    # ISO/TR 1281-1: f_c = 207.9 lambda nu gamma^(2/9) (1 - gamma)^(29/27) (1 + gamma)^(-1/4)
    # [1 + (1.04 ((1 - gamma) / (1 + gamma))^(143/108))^(9/2)]^(-2/9), lambda nu = 0.83: the
    # table is this formula rounded to 0.1 (measured: within 0.06 %)
    for gamma, fc in zip(*iso.ROLLER_FC_TABLE):
        closed = 207.9 * 0.83 * gamma ** (2 / 9) * (1 - gamma) ** (29 / 27) \
            * (1 + gamma) ** -0.25 \
            * (1 + (1.04 * ((1 - gamma) / (1 + gamma)) ** (143 / 108)) ** 4.5) ** (-2 / 9)
        assert closed == pytest.approx(fc, abs=0.05 + 1e-9)


def test_outside_the_table_is_refused():
    with pytest.raises(ParameterError, match="outside ISO 281's table"):
        iso.roller_fc(0.31, "bearings.needle_diameter")
    with pytest.raises(ParameterError, match="bearings.main_ball_diameter"):
        iso.ball_fc(0.005, "bearings.main_ball_diameter")


# --- the life law, the mean load, the pair rule --------------------------------------------

@pytest.mark.parametrize("p", [iso.BALL_EXPONENT, iso.ROLLER_EXPONENT])
def test_life_scaling(p):
    assert iso.rating_life(1000.0, 1000.0, p) == pytest.approx(1e6, rel=1e-15)
    base = iso.rating_life(20000.0, 2500.0, p)
    assert iso.rating_life(20000.0, 5000.0, p) == pytest.approx(base / 2.0 ** p, rel=1e-14)
    assert iso.rating_life(20000.0, 0.0, p) == math.inf


def test_mean_load_of_a_known_cycle():
    # two equal halves of 1 kN and 2 kN, p = 3: ((1 + 8) / 2)^(1/3) kN = 1650.964 N
    assert iso.mean_load([1000.0, 2000.0], 3.0) == pytest.approx(1650.9636, rel=1e-7)
    # 3 revolutions at 1 kN and 1 at 2 kN: ((3 + 8) / 4)^(1/3) kN = 2.75^(1/3) = 1401.0197 N
    assert iso.mean_load([1000.0, 2000.0], 3.0, [3, 1]) == pytest.approx(1401.0197, rel=1e-7)
    # F = F0 (1 + cos t) sampled uniformly, p = 3: mean of (1 + cos)^3 = 1 + 3/2 = 5/2
    t = np.linspace(0.0, 2.0 * math.pi, 4096, endpoint=False)
    assert iso.mean_load(1000.0 * (1.0 + np.cos(t)), 3.0) == pytest.approx(
        1000.0 * 2.5 ** (1.0 / 3.0), rel=1e-12)
    # a constant load is its own mean, for any exponent
    assert iso.mean_load([1234.5] * 7, 10.0 / 3.0) == pytest.approx(1234.5, rel=1e-14)


def test_tapered_pair_rule_by_hand():
    alpha = math.radians(15.0)
    e, x, y = iso.tapered_factors(alpha)
    assert (e, x, y) == pytest.approx((1.5 * math.tan(alpha), 0.4, 0.4 / math.tan(alpha)))
    # equal radial loads: each carries its own induced force, F_a / F_r = 1.25 tan(alpha) < e
    pa, pb = iso.tapered_pair_loads(2000.0, 2000.0, alpha)
    assert (float(pa), float(pb)) == (2000.0, 2000.0)
    # 2000 N and 1000 N: both carry 0.5 x 2000 / Y = 669.9 N; the light one has F_a / F_r =
    # 0.670 > e = 0.402: P = 0.4 x 1000 + Y x 669.9 = 400 + 1000 = 1400 N
    pa, pb = iso.tapered_pair_loads(2000.0, 1000.0, alpha)
    assert float(pa) == 2000.0 and float(pb) == pytest.approx(1400.0, rel=1e-12)


def test_paired_axial_loads_by_hand():
    # induced 1 x F_r; a: 1000 N, b: 3000 N, no external force: both carry b's 3000 N
    fa_a, fa_b = iso.paired_axial_loads(1000.0, 3000.0, 1.0)
    assert (float(fa_a), float(fa_b)) == (3000.0, 3000.0)
    # 500 N onto b: a's 1000 + 500 < b's own 3000: b 3000, a 2500
    fa_a, fa_b = iso.paired_axial_loads(1000.0, 3000.0, 1.0, 500.0)
    assert (float(fa_a), float(fa_b)) == (2500.0, 3000.0)
    # 4000 N onto b: a keeps its own 1000, b carries 1000 + 4000
    fa_a, fa_b = iso.paired_axial_loads(1000.0, 3000.0, 1.0, 4000.0)
    assert (float(fa_a), float(fa_b)) == (1000.0, 5000.0)


def test_main_bearing_loads_by_hand():
    alpha = math.radians(40.0)
    assert iso.angular_contact_factors(alpha) == pytest.approx((1.14, 0.35, 0.57), abs=1e-12)
    assert iso.angular_contact_factors(math.radians(37.5)) == pytest.approx(
        (1.045, 0.36, 0.615), abs=1e-12)
    with pytest.raises(ParameterError, match="bearings.main_contact_angle"):
        iso.angular_contact_factors(math.radians(15.0), "bearings.main_contact_angle")
    # 800 N*m over 60 mm: +-13 333.3 N on the rows; induced 1.216 tan 40 = 1.02035 x F_r =
    # 13 604.6 N; 2000 N onto b: b carries 15 604.6 N, F_a / F_r = 1.170 > e = 1.14:
    # P_b = 0.35 x 13 333.3 + 0.57 x 15 604.6 = 13 561.3 N; a: 1.020 < e, P_a = F_r
    pa, pb = iso.main_bearing_loads(0.0, 800.0, 2000.0, 0.06, alpha)
    k = 1.216 * math.tan(alpha)
    assert pa == pytest.approx(800.0 / 0.06, rel=1e-14)
    assert pb == pytest.approx(0.35 * 800.0 / 0.06 + 0.57 * (k * 800.0 / 0.06 + 2000.0),
                               rel=1e-14)
    assert pb == pytest.approx(13561.3, abs=0.1)
    # a pure thrust: both rows unloaded radially, P = Y F_a on the row it pushes
    pa, pb = iso.main_bearing_loads(0.0, 0.0, 1000.0, 0.06, alpha)
    assert (pa, pb) == pytest.approx((0.0, 570.0), abs=1e-9)


def test_hours_system_and_catalogue_rule():
    # 1e6 revolutions at 600 rpm: 1e6 / 600 / 60 = 27.78 h
    assert iso.life_hours(1e6, 600.0 * RPM) == pytest.approx(1e6 / 600.0 / 60.0, rel=1e-14)
    # n equal bearings: L / n^(1/e); an unloaded bearing (infinite life) drops out
    assert iso.system_life([1000.0] * 4, 9 / 8) == pytest.approx(1000.0 / 4 ** (8 / 9), rel=1e-14)
    assert iso.system_life([1000.0, math.inf]) == pytest.approx(1000.0, rel=1e-14)
    # mixed slopes: sum (t / L_i)^e_i = 1 solved; equal slopes agree with the closed form
    mixed = iso.system_life([1000.0, 2000.0], [9 / 8, 10 / 9])
    assert (mixed / 1000.0) ** (9 / 8) + (mixed / 2000.0) ** (10 / 9) == pytest.approx(
        1.0, rel=1e-12)
    # the root finder (slopes differing by 1e-12) against the closed form
    assert iso.system_life([1000.0, 2000.0], [9 / 8, 9 / 8 * (1 + 1e-12)]) == pytest.approx(
        iso.system_life([1000.0, 2000.0], 9 / 8), rel=1e-10)
    # K (N0 / N) (T0 / T)^(10/3): K at the rating point, / 2 at twice the speed, / 2^(10/3)
    # at twice the torque
    assert iso.catalogue_life(6000.0, 15.0, 15.0, 412.0, 412.0) == 6000.0
    assert iso.catalogue_life(6000.0, 15.0, 30.0, 412.0, 412.0) == pytest.approx(3000.0)
    assert iso.catalogue_life(6000.0, 15.0, 15.0, 412.0, 824.0) == pytest.approx(
        6000.0 / 2.0 ** (10.0 / 3.0), rel=1e-14)


# --- the engine -----------------------------------------------------------------------------

def test_crank_speed_is_pin_count_times_output():
    from rvsim.quasistatic.bearing_life import crank_speed

    # i = 1 + (54 / 18) x 40 = 121: the crank turns (18 / 54) x 120 = 40 = zp times per
    # output turn relative to the carrier
    assert crank_speed(RV40E, 15.0 * RPM) == pytest.approx(600.0 * RPM, rel=1e-14)


def test_bushings_and_single_stage_have_no_rating_life():
    from rvsim.quasistatic import life

    with pytest.raises(ParameterError, match="bushings have no rating life"):
        life(RV40E)
    with pytest.raises(ParameterError, match="output_speed"):
        life(RV40E_ROLLING, output_speed=0.0)
    with pytest.raises(ParameterError, match="torque"):
        life(RV40E_ROLLING, torque=-1.0)
    with pytest.raises(ParameterError, match="momentary maximum"):
        life(RV40E_ROLLING, torque=3000.0)


@pytest.fixture(scope="module")
def rated():
    from rvsim.quasistatic import life

    return life(RV40E_ROLLING, positions=81)


def test_engine_applies_iso_281_to_the_quasi_static_loads(rated):
    from rvsim.quasistatic import ltca
    import dataclasses

    r = RV40E_ROLLING
    assert rated.status == "ok" and rated.torque == r.rating.rated_torque
    assert rated.crank_speed == pytest.approx(40 * r.rating.rated_output_speed, rel=1e-14)
    running = dataclasses.replace(r, operating=dataclasses.replace(
        r.operating, input_speed=r.rating.rated_output_speed * r.ratio))
    run = ltca(running, torque=412.0, positions=81)
    needle = rated.bearings[0]
    assert needle.name == "arm needles crank 1 disc 1"
    p = iso.mean_load(run.arm_forces[:, 0, 0], 10.0 / 3.0)
    assert needle.equivalent_load == pytest.approx(p, rel=1e-12)
    assert needle.l10 == pytest.approx(1e6 * (needle.dynamic_rating / p) ** (10.0 / 3.0),
                                       rel=1e-12)
    assert needle.l10_hours == pytest.approx(needle.l10 / 600.0 / 60.0, rel=1e-12)
    # the reducer's life is its shortest bearing's; the system life is below it
    lives = [b.l10_hours for b in rated.bearings if b.status == "ok"]
    assert len(lives) == 8 and rated.life_hours == min(lives)
    assert rated.system_life_hours < rated.life_hours
    # the catalogue rule at its own rating point is K
    assert rated.catalogue_life == pytest.approx(6000.0 * 3600.0, rel=1e-12)
    main = rated.bearings[-1]
    assert main.status == "needs_external_load" and math.isnan(main.l10_hours)
    assert rated.crank_life_hours == rated.life_hours
    summary = rated.summary()
    assert summary["life_ratio_to_catalogue"] == pytest.approx(
        rated.life_hours / 6000.0, rel=1e-12)


def test_needle_life_follows_the_torque(rated):
    # the needle loads grow nearly in proportion to the torque: half the torque gives
    # 2^(10/3) = 10.08 times the life (measured: 10.083, loads within 0.05 % of half)
    from rvsim.quasistatic import life

    half = life(RV40E_ROLLING, torque=206.0, positions=81)
    assert half.life_hours / rated.life_hours == pytest.approx(2.0 ** (10.0 / 3.0), rel=3e-3)


def test_main_bearings_under_external_loads():
    # the worse direction of the thrust: row 2 at P = 13 561 N (test above), C = 25 268.7 N,
    # 15 rpm: L10 = (C / P)^3 = 6.469e6 revolutions = 7188 h
    from rvsim.quasistatic.bearing_life import main_bearing_rows

    rows = main_bearing_rows(RV40E_ROLLING, 25268.71, 15.0 * RPM, 0.0, 800.0, 2000.0)
    assert [r.name for r in rows] == ["main bearing row 1", "main bearing row 2"]
    worst = max(rows, key=lambda r: r.equivalent_load)
    assert worst.equivalent_load == pytest.approx(13561.3, abs=0.1)
    assert worst.l10 == pytest.approx(1e6 * (25268.71 / worst.equivalent_load) ** 3, rel=1e-14)
    assert worst.l10_hours == pytest.approx(worst.l10 / 15.0 / 60.0, rel=1e-12)
    assert worst.l10_hours == pytest.approx(7188.0, abs=1.0)
    with pytest.raises(ParameterError, match="moment"):
        from rvsim.quasistatic import life

        life(RV40E_ROLLING, moment=-1.0)
