"""Verification of the crank bearings (issue 10): closed forms of rolling-bearing load
distribution (Stribeck / Harris & Kotzalas, Rolling Bearing Analysis, 5th ed., Ch. 7), the
Palmgren roller deflection, the conforming bushing law and the two engines with bearings.

Measured (2026-11-22) and the tolerance of each test:

* zero clearance, 20 needles, a roller in the load line: the discrete sum of the roller
  forces equals Z Qmax Jr(0.5) of the continuous integral within 1.07e-4 relative (tolerance
  2e-4); Jr(0.5) = 0.24480 = 1 / 4.085 (Harris, three digits: 4.08; tolerance 0.006);
* radial stiffness at zero clearance = 10/9 Fr / delta_r to 1e-15 (tolerance 1e-12);
* load zone: with clearance the loaded rollers are exactly those with cos(psi) > g /
  delta_r; 2000 rollers follow Z Qmax Jr(eps) within 1.7e-7 (tolerance 1e-6);
* conforming law: F(delta) inverts delta(F) to 1e-15 relative (tolerance 1e-12); the energy
  equals the integral of F d(delta) within 1.2e-8, the quadrature's error at the logarithmic
  end (tolerance 1e-7); stiffness factor s scales
  the force exactly (1e-12);
* conforming law against Johnson's approach of two cylinders with Hertz's width of the
  conforming pair, written independently: 4.4e-16 (tolerance 1e-13); its wrap at b = R within
  dR / 2R; its neat-fit limit 2.29 times stiffer than Johnson's approach at b = R (2026-11-28);
* the paper's RV-40E across the roughness-sourced floors (2.5 / 5 / 10 um): rigidity and lost
  motion of real runs pinned to 1e-9 (a finding of issue 32 item 2, not a tuning);
* the stiffness matrix of the bearing set (cage terms included) gives the local torsional
  stiffness within 1.8e-5 of the finite-difference derivative (tolerance 1e-4);
* the dynamic steady mean TE at a quarter of the paper's speed equals the quasi-static mean
  within 1.34e-5 (zero errors) and 4.6e-6 (paper run 2) relative (tolerance 5e-5; one crank
  period from 0.4 s, 2026-11-28: 5.1e-6 and 8.5e-6 over two from 0.8 s).
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from rvsim.bearings import conforming_constants, main_bearing_stiffness, roller_coefficient
from rvsim.physics import _layout as L
from rvsim.physics._bearings import (WRAP_RATIO, conforming_approach, conforming_force,
                                     roller_set)
from rvsim.physics.compliance import PALMGREN_REFERENCE
from rvsim.errors import ParameterError
from rvsim.parameters import RV40E as RV40E_PAPER, paper_run_values, with_values
from rvsim.parameters.rv40e_bearings import RV40E_ROLLING
from rvsim.quasistatic import hysteresis, solve_path

#: the compiled laws are called with the engine's own argument types (float64 counts, the shift
#: given: NaN is "computed here"), so they load from numba's cache instead of compiling a
#: signature of their own
NAN = math.nan

# the rolling bearings without the set's friction (friction has tests of its own)
BEARINGS = RV40E_ROLLING
STEEL = PALMGREN_REFERENCE
C = roller_coefficient(0.012, STEEL, STEEL, STEEL)


def _jr(eps):
    """Harris's radial integral of a line-contact bearing (load exponent 10/9)."""
    limit = math.acos(max(-1.0, 1.0 - 2.0 * eps))
    value, _ = quad(lambda psi: (1.0 - (1.0 - math.cos(psi)) / (2.0 * eps)) ** (10.0 / 9.0)
                    * math.cos(psi), -limit, limit, epsabs=1e-14, epsrel=1e-12)
    return value / (2.0 * math.pi)


def test_palmgren_roller_deflection_on_both_raceways():
    q = 1000.0
    millimetres = 2.0 * 3.84e-5 * q ** 0.9 / 12.0 ** 0.8      # Harris Eq. 7.9, two contacts
    assert C * q ** 0.9 == pytest.approx(millimetres * 1e-3, rel=1e-12)


def test_zero_clearance_load_distribution_is_stribecks():
    # Harris: Fr = Z Qmax / 4.08 (three digits): measured 1 / 4.085
    assert 1.0 / _jr(0.5) == pytest.approx(4.08, abs=0.006)
    z, delta_r = 20.0, 5e-6
    sx, sy, *_ , kxx, kxy, kyy, _, _ = roller_set(delta_r, 0.0, 0.0, 0.0, z, 0.0, C, 0.0, 1.0,
                                                  0.0, 1.0)
    q_max = (delta_r / C) ** (1.0 / 0.9)
    assert sx == pytest.approx(z * q_max * _jr(0.5), rel=2e-4)   # measured 1.07e-4
    assert abs(sy) < 1e-12 * sx
    assert kxx == pytest.approx(10.0 / 9.0 * sx / delta_r, rel=1e-12)
    assert abs(kxy) < 1e-9 * kxx


@pytest.mark.parametrize("ratio", [0.2, 0.5, 0.8])
def test_load_zone_follows_clearance(ratio):
    delta_r = 10e-6
    gap = ratio * delta_r
    z = 2000.0
    sx, *_ = roller_set(delta_r, 0.0, 0.0, 0.0, z, 0.0, C, gap, 1.0, 0.0, 1.0)
    eps = 0.5 * (1.0 - gap / delta_r)
    q_max = ((delta_r - gap) / C) ** (1.0 / 0.9)
    assert sx == pytest.approx(z * q_max * _jr(eps), rel=1e-6)  # measured up to 1.7e-7
    # the loaded rollers are those inside the load zone |psi| < acos(gap / delta_r)
    zone = math.acos(gap / delta_r)
    for k in (10, 20):
        psi = 2.0 * math.pi * np.arange(k) / k + 0.05
        loaded = [roller_set(delta_r, 0.0, 0.0, 0.0, 1.0, p, C, gap, 1.0, 0.0, 1.0)[0] > 0.0
                  for p in psi]
        inside = np.cos(psi) > math.cos(zone)
        assert loaded == list(inside)


def test_tapered_rollers_scale_with_contact_angle():
    alpha = math.radians(15.0)
    plain = roller_set(4e-6, 1e-6, 0.0, 0.0, 15.0, 0.1, C, 0.0, 1.0, 0.0, 1.0)
    tapered = roller_set(4e-6 / math.cos(alpha), 1e-6 / math.cos(alpha), 0.0, 0.0, 15.0, 0.1, C,
                         0.0, math.cos(alpha), 0.0, 1.0)
    # same normal approach per roller: the radial resultant is cos(alpha) of the plain one
    assert tapered[0] == pytest.approx(plain[0] * math.cos(alpha), rel=1e-12)
    assert tapered[1] == pytest.approx(plain[1] * math.cos(alpha), rel=1e-12)


def test_conforming_law_inverts_and_stores_its_work():
    j1, a1 = conforming_constants(0.015, STEEL, STEEL, 5e-6)
    j2, a2 = conforming_constants(0.015, STEEL, STEEL, 10e-6)
    cb = 1e-10
    for f in (10.0, 1e3, 0.5 * a1 / WRAP_RATIO, 3.0 * a1 / WRAP_RATIO):
        delta, _, energy = conforming_approach(f, j1, a1, j2, a2, cb)
        force, k, _ = conforming_force(delta, j1, a1, j2, a2, cb, 0.0, NAN)
        assert force == pytest.approx(f, rel=1e-12)
        work, _ = quad(lambda x: x * conforming_approach(x, j1, a1, j2, a2, cb)[1], 0.0, f,
                       points=[a1 / WRAP_RATIO, a2 / WRAP_RATIO], limit=200, epsrel=1e-13)
        assert energy == pytest.approx(work, rel=1e-7)   # measured 1.2e-8 (quadrature)
        # warm start from a neighbouring force converges to the same root
        assert conforming_force(delta, j1, a1, j2, a2, cb, 2.0 * f, NAN)[0] == pytest.approx(
            f, rel=1e-12)


def test_conforming_law_limits():
    j, a = conforming_constants(0.015, STEEL, STEEL, 5e-6)
    # continuous approach and compliance where the contact wraps the journal
    f_wrap = a / WRAP_RATIO
    below = conforming_approach(f_wrap * (1 - 1e-9), j, a, j, a, 0.0)
    above = conforming_approach(f_wrap * (1 + 1e-9), j, a, j, a, 0.0)
    assert below[0] == pytest.approx(above[0], rel=1e-8)
    assert below[1] == pytest.approx(above[1], rel=1e-7)
    # light load: Johnson's closed form of two interfaces
    f = 50.0
    assert conforming_approach(f, j, a, j, a, 0.0)[0] == pytest.approx(
        2.0 * f / (math.pi * 0.015 * STEEL.elastic_modulus / (2 * (1 - 0.09)))
        * (math.log(a / f) - 1.0), rel=1e-12)
    # a stiffness factor s multiplies the force at every approach
    js, as_ = conforming_constants(0.015, STEEL, STEEL, 5e-6, stiffness_factor=7.0)
    delta = conforming_approach(2e3, j, a, j, a, 0.0)[0]
    assert conforming_force(delta, js, as_, js, as_, 0.0, 0.0, NAN)[0] == pytest.approx(
        7.0 * 2e3, rel=1e-12)


def test_bearing_stiffness_matrix_gives_local_torsional_stiffness():
    reducer = with_values(BEARINGS, paper_run_values(2))
    torque = 300.0
    step = 1e-3 * torque
    for angle in (0.3, 1.1):
        path = solve_path(reducer, np.full(3, angle),
                          np.array([torque, torque - step, torque + step]))
        assert path.status == "ok"
        finite_difference = 2.0 * step / (path.q[1, L.CARRIER] - path.q[2, L.CARRIER])
        # measured 1.3e-5, 1.8e-5
        assert path.torsional_stiffness[0] == pytest.approx(finite_difference, rel=1e-4)


@pytest.mark.parametrize("run", [0, 2])
def test_engines_agree_with_bearings(run):
    from tests.verification.test_quasistatic import engines_mean_te, low_speed

    values = {} if run == 0 else paper_run_values(run)
    static, dynamic = engines_mean_te(low_speed(with_values(BEARINGS, values)))
    # measured 1.34e-5 (zero errors), 4.6e-6 (run 2)
    assert static == pytest.approx(dynamic, rel=5e-5)


def test_main_bearing_stiffness_is_positive_and_scales_with_preload():
    soft = main_bearing_stiffness(BEARINGS)
    stiff = main_bearing_stiffness(with_values(BEARINGS, {"bearings.main_preload": 0.008}))
    # linearised Hertz point contacts: stiffness ~ preload approach^0.5
    assert stiff.tilting == pytest.approx(2.0 * soft.tilting, rel=1e-12)
    assert soft.radial > 0 and soft.axial > 0


def test_needles_must_fit_the_space_and_preload_is_not_an_interference():
    # 0.5 mm of interference: elastic preload far above the static limit (issue 32), refused
    # where the engines build their model, not by validate
    from rvsim.bearings import check_preload

    with pytest.raises(ParameterError) as info:
        check_preload(with_values(BEARINGS, {"bearings.needle_diameter": 3.5}))
    assert info.value.field == "assembly" and "needle rollers do not fit" in info.value.reason
    assert "above the static limit" in info.value.reason
    preloaded = with_values(BEARINGS, {"bearings.support_clearance": -0.002,
                                       "bearings.needle_clearance": -0.002})
    path = solve_path(preloaded, np.array([0.3]), np.array([0.0]))
    # preloaded rollers push symmetrically: no load, no wind-up
    assert path.status == "ok" and abs(path.q[0, L.CARRIER] - 0.3 / BEARINGS.ratio) < 1e-12


def test_needle_internal_clearance_is_room_for_a_misplaced_hole():
    """The needles fit while the eccentric is off its disc hole's centre by less than their
    radial play, half the bearing's radial internal clearance (rvsim.bearings.arm_play): a
    hole 4 um off fits 10 um of internal clearance, 6 um off does not (it bound at any
    offset before issue 33's test prototypes)."""
    import dataclasses

    from rvsim.geometry.assembly import assembly_overlaps
    from rvsim.parameters import PartErrors

    def needle_overlap(dx, clearance):
        r = with_values(BEARINGS, {"bearings.needle_clearance": clearance})
        holes = ((dx, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0))      # crank 1's hole in disc 1
        r = dataclasses.replace(r, parts=PartErrors(disc_holes=holes))
        return max(o.approach for o in assembly_overlaps(r) if "needle" in o.parts)

    assert needle_overlap(4e-6, 0.010) == pytest.approx(-1e-6, abs=1e-12)
    assert needle_overlap(6e-6, 0.010) == pytest.approx(1e-6, abs=1e-12)
    assert needle_overlap(4e-6, -0.002) == pytest.approx(4e-6, abs=1e-12)   # preload: no room


@pytest.mark.parametrize("values, field", [
    ({"bearings.needle_clearance": 7.0}, "bearings.needle_clearance"),       # > tooth height
    ({"bearings.support_clearance": -0.5}, "bearings.support_clearance"),    # absurd preload
])
def test_bearing_clearances_are_validated(values, field):
    with pytest.raises(ParameterError) as info:
        with_values(BEARINGS, values)
    assert info.value.field == field


def test_conforming_law_is_johnsons_approach_with_the_hertz_width():
    """Issue 32 item 2: the law against its closed forms, written independently.

    Hertz's half-width of the conforming pair (journal R, bore R + dR: relative radius R (R +
    dR) / dR) in Johnson's approach of two cylinders (Contact Mechanics, Sec. 5.6, one term
    2 ln(4 R_i / b) - 1 per body) is the law to round-off (measured 4.4e-16, tolerance 1e-13);
    the law's wrap force a / 16 is where b reaches R, within sqrt(1 + dR / R) - 1 (2.0e-4 at
    5 um on 12.5 mm; bound dR / 2R), so b / R = 4 sqrt(F / a) (docs/model.md section 16).
    For dR -> 0 the law is its linear continuation, compliance j (ln 16 - 2) per interface
    (1e-12), while Johnson's approach with the width of a neat fit held at b = R (the
    90-degree arc of a zero-clearance pin) has j (ln 16 - 1): 2.29 times as compliant
    (docs/decisions.md, issue 32 item 2: a finding, not changed)."""
    length, radius, e_star = 0.015, 0.0125, STEEL.elastic_modulus / (2 * (1 - 0.09))
    for dr in (1e-6, 5e-6, 20e-6):
        j, a = conforming_constants(length, STEEL, STEEL, dr)
        relative = radius * (radius + dr) / dr
        for f in (10.0, 1e3, 0.9 * a / WRAP_RATIO):
            b = math.sqrt(4.0 * f * relative / (math.pi * length * e_star))
            johnson = f / (math.pi * length * e_star) * (
                2.0 * math.log(4.0 * radius / b) - 1.0
                + 2.0 * math.log(4.0 * (radius + dr) / b) - 1.0) / 2.0
            assert conforming_approach(f, j, a, 0.0, 1.0, 0.0)[0] == pytest.approx(
                johnson, rel=1e-13)
        b_wrap = math.sqrt(4.0 * a / WRAP_RATIO * relative / (math.pi * length * e_star))
        assert b_wrap / radius - 1.0 == pytest.approx(math.sqrt(1 + dr / radius) - 1.0,
                                                      rel=1e-9)
        assert 0.0 < b_wrap / radius - 1.0 <= 0.5 * dr / radius
    j, a = conforming_constants(length, STEEL, STEEL, 1e-12)
    f = 3e3
    _, compliance, _ = conforming_approach(f, j, a, 0.0, 1.0, 0.0)
    assert compliance == pytest.approx(j * (math.log(16.0) - 2.0), rel=1e-12)
    neat_fit = j * (2.0 * math.log(4.0) - 1.0)
    assert neat_fit / compliance == pytest.approx(2.294, abs=5e-4)


@pytest.mark.parametrize("floor, rigidity, lost_motion", [
    (0.0025, 1589.1827288210375, 0.06726488041357453),   # two N4 surfaces: Rz 1.25 + 1.25 um
    (0.005, 1049.6354240463436, 0.07569187314818702),    # N5 (Ra 0.4 um): the default
    (0.01, 772.6740381077581, 0.08411626822324729),      # N6 (Ra 0.8 um): Rz 5 + 5 um
])
def test_bushing_floor_moves_the_paper_set_across_the_ground_roughness(floor, rigidity,
                                                                       lost_motion):
    """Issue 32 item 2, a finding pinned (not a knob): the floor of the conforming law's radial
    difference is the summed Rz of the two ground surfaces of an interface (docs/model.md
    section 16); over the sourced range of ground seats the paper's RV-40E moves by +51 / -26 %
    in rigidity (rvsim hysteresis, 2026-11-28)."""
    summary = hysteresis(with_values(RV40E_PAPER, {
        "bearings.bushing_min_radial_difference": floor})).summary()
    assert summary["torsional_rigidity_nm_per_arcmin"] == pytest.approx(rigidity, rel=1e-9)
    assert summary["lost_motion_arcmin"] == pytest.approx(lost_motion, rel=1e-9)
