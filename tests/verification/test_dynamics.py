"""Verification of the dynamic model against analytic limits (issue 3, item 4).

* zero errors and no load: TE == 0 and speed ratio 121 to solver precision (what is left is
  the start-up vibration decaying through the contact damping);
* rigid crank bearings: the pin loads follow the textbook distribution (pins with a positive
  lever arm l_i carry F_i proportional to l_i**(1/0.9) under the Palmgren law, the rest carry
  nothing; both discs share equally) and the crank bearing forces follow from the disc's force
  and moment balance with the pin resultant shared equally by the two cranks;
* steady torque balance T_in * 121 = T_out (no friction) within 0.2 % (measured 0.059 %);
* halving the time step (5e-6 s to 2.5e-6 s, shortened paper run 2) changes the steady mean TE
  by < 4e-6 relative (measured 7.7e-7) and the largest pin force (taken at every step) by
  < 4e-4 (measured 7.9e-5);
* energy: input work = output work + dissipation (+ changes of kinetic and potential energy and
  the work of the time-varying mesh stiffness) within 1e-5 of the input work over the steady
  window (measured 2.3e-6), halving the step more than halves the residual (first order);
* regression pins: the mean and peak-to-peak TE and the largest pin force of paper runs 1-3.

Tolerances are a small factor (2-10) above what was measured (figures in each test); the
pinned numbers are deterministic to the last bit on one machine, pinned to 1e-6 relative so
that another platform's floating point passes and any change of the model fails.
"""

import math

import numpy as np
import pytest

from rvsim.dynamics import simulate
from rvsim.errors import SimulationError
from rvsim.geometry.cycloid import pin_contact_geometry
from rvsim.geometry.involute import gear_geometry
from rvsim.parameters import RV40E, paper_run_values, with_values
from rvsim.units import ARCMIN
from tests.verification.textbook import textbook_pin_forces

# a shortened schedule (same physics, faster ramps) keeps these tests quick
QUICK = {"operating.speed_ramp_time": 0.2, "operating.load_start": 0.2,
         "operating.load_ramp_end": 0.4, "operating.steady_start": 0.6,
         "operating.duration": 1.0}
# and half of it (the runs' own steady window from 0.3 s)
SHORT = {"operating.speed_ramp_time": 0.1, "operating.load_start": 0.1,
         "operating.load_ramp_end": 0.2, "operating.steady_start": 0.3,
         "operating.duration": 0.4}


@pytest.fixture(scope="module")
def paper_run_2():
    """Paper run 2 at the default step (pinned below; its torque and energy balances)."""
    reducer = with_values(RV40E, paper_run_values(2))
    return reducer, simulate(reducer)


@pytest.fixture(scope="module")
def halved_step():
    """Shortened paper run 2 at the default 5e-6 s and at half of it (the step's effect on the
    steady window does not need the whole 4 s: 2026-11-28, issue 30, the 4 s runs measured
    5.6e-8 on the mean TE)."""
    reducer = with_values(RV40E, {**paper_run_values(2), **QUICK})
    return simulate(reducer), simulate(reducer, time_step=2.5e-6)


def test_zero_error_no_load_gives_zero_te_and_ratio_121():
    reducer = with_values(RV40E, {"E": 0, **QUICK})
    result = simulate(reducer)
    window = result.time >= 0.6
    # what is left is start-up vibration decaying through contact damping: < 2e-4 arcmin
    # (measured 9.1e-5 over 0.6-1 s; 1.6e-5 over 1.5-2 s of a 2 s run); the mean is zero to
    # 5e-7 arcmin (measured 1.1e-7)
    assert np.max(np.abs(result.te[window])) / ARCMIN < 2e-4
    assert abs(np.mean(result.te[window])) / ARCMIN < 5e-7
    assert result.metrics["speed_ratio"] == pytest.approx(121.0, abs=2e-5)  # measured 8.1e-6


@pytest.fixture(scope="module")
def rigid_bearings():
    # the bare carrier (no load inertia): these are static balances, and a load inertia brings
    # the drive's torsional mode down to the pin-passing orders, whose ringing they would see
    # (x 300 of the conforming law at 5e-7 s: x 1000 of it would need 2.5e-7 s for stability)
    # the bare carrier settles within milliseconds of the load ramp: a 0.12 s schedule
    # (2026-11-28, issue 30; the 0.7 s one measured 0.61 %, 0.22 % and 3.3 % below)
    reducer = with_values(RV40E, {"operating.speed_ramp_time": 0.03,
                                  "operating.load_start": 0.03, "operating.load_ramp_end": 0.06,
                                  "operating.steady_start": 0.09, "operating.duration": 0.12,
                                  "contact.bushing_stiffness_factor": 3e2,
                                  "operating.load_inertia": 0.0})
    return reducer, simulate(reducer, time_step=5e-7, sample_rate=500)


def test_pin_load_sharing_follows_textbook(rigid_bearings):
    reducer, result = rigid_bearings
    i = len(result.time) - 1
    crank_angle = -reducer.cycloid.disc_teeth * result.theta_out[i]
    torques = []
    for disc in (0, 1):
        force = result.pin_forces[i, disc]
        expected, lever = textbook_pin_forces(reducer, crank_angle, disc, force)
        # measured 0.78 % of the largest force
        assert np.max(np.abs(force - expected)) < 0.01 * force.max()
        assert np.all(force[lever < -1e-3] == 0.0)
        torques.append(force @ lever)
    assert torques[0] == pytest.approx(torques[1], rel=0.005)  # measured 0.14 %


def test_crank_bearing_forces_follow_disc_balance(rigid_bearings):
    reducer, result = rigid_bearings
    i = len(result.time) - 1
    crank_angle = -reducer.cycloid.disc_teeth * result.theta_out[i]
    centre = gear_geometry(reducer).centre_distance
    theta = result.theta_out[i]
    for disc in (0, 1):
        lever, normal = pin_contact_geometry(reducer, crank_angle, disc=disc)
        force = result.pin_forces[i, disc]
        resultant = -(force[:, None] * normal).sum(axis=0)     # pins on the disc
        moment = force @ lever                                  # about the disc centre
        for crank in (0, 1):
            angle = theta + crank * math.pi
            hole = centre * np.array([math.cos(angle), math.sin(angle)])
            tangent = np.array([-hole[1], hole[0]]) / centre
            bearing = -resultant / 2 - moment / (2 * centre) * tangent
            simulated = result.arm_bushing_forces[i, crank, disc]
            # measured up to 0.77 % (up to 3.3 % at other instants: the crank's own inertia
            # and the bushings' tilt)
            assert simulated == pytest.approx(np.linalg.norm(bearing), rel=0.02)


def test_steady_torque_balance(paper_run_2):
    _, result = paper_run_2
    window = result.time >= 1.5
    torque_in = result.channel("torque_in")[window].mean()
    torque_out = result.channel("torque_load")[window].mean()
    assert torque_in * 121 == pytest.approx(torque_out, rel=0.002)  # measured 0.059 %


def test_halving_time_step_changes_mean_te_below_4e_6(halved_step):
    coarse, fine = halved_step
    a, b = coarse.metrics["te_mean_arcmin"], fine.metrics["te_mean_arcmin"]
    # measured 7.7e-7 (3.4e-5 between 1e-5 s and 5e-6 s on the 4 s run)
    assert abs(a - b) < 4e-6 * abs(b)


def test_halving_time_step_changes_largest_pin_force_below_4e_4(halved_step):
    # taken at every step, not from the samples (measured 7.9e-5; the 2 kHz samples' maximum
    # moves 1 % with a step whose samples fall elsewhere: docs/benchmarks.md)
    coarse, fine = halved_step
    assert fine.metrics["max_pin_force_n"] == pytest.approx(coarse.metrics["max_pin_force_n"],
                                                            rel=4e-4)


def test_largest_pin_force_is_every_steps():
    # sampled at every step the histories' maximum over the window is the reported one, to
    # the bit; at the default 2 kHz the samples miss the peak (1769.9 N against 1796.7 N),
    # and the report does not change
    reducer = with_values(RV40E, {**paper_run_values(3), **SHORT, "operating.duration": 0.32})
    every = simulate(reducer, sample_rate=1.0 / 5e-6)
    default = simulate(reducer)
    assert every.steps == default.steps == 64_000
    peak = every.metrics["max_pin_force_n"]
    window = every.time >= 0.3 - 1e-12
    assert peak == every.pin_forces[window].max()
    assert default.metrics["max_pin_force_n"] == peak
    sampled = default.pin_forces[default.time >= 0.3 - 1e-12].max()
    assert sampled < peak
    # the history of each evaluation's largest pin force
    assert np.array_equal(default.channel("pin_f_max"), default.pin_forces.max(axis=(1, 2)))


def test_energy_balance_within_1e_5(paper_run_2, halved_step):
    _, result = paper_run_2
    e = result.energy
    assert e["input_work"] > 100.0
    assert abs(e["relative_residual"]) < 1e-5  # measured 2.3e-6 (6.5e-6 at 1e-5 s)
    assert e["dissipated"] >= 0.0
    # first order in dt: the shortened run's residual measured -2.4e-6 at 5e-6 s, -7.1e-7 at
    # 2.5e-6 s
    coarse, fine = halved_step
    assert abs(fine.energy["relative_residual"]) < 0.5 * abs(coarse.energy["relative_residual"])
    assert abs(fine.energy["relative_residual"]) < 2e-6


def test_friction_dissipates_and_balance_still_holds():
    reducer = with_values(RV40E, {**QUICK, "contact.friction_coefficient": 0.05,
                                  "I": 0.016, "J": 0.026})
    result = simulate(reducer)
    assert result.energy["dissipated"] > 0.03 * result.energy["input_work"]  # measured 4.5 %
    assert abs(result.energy["relative_residual"]) < 1e-4  # measured 1.7e-5


def test_unstable_step_reports_status():
    reducer = with_values(RV40E, QUICK)
    with pytest.raises(SimulationError) as info:
        simulate(reducer, time_step=1e-4)
    assert info.value.status in ("diverged", "runaway_penetration")
    partial = simulate(reducer, time_step=1e-4, raise_on_failure=False)
    assert partial.status == info.value.status
    assert partial.steps < 1.0 / 1e-4


# (te_mean_arcmin, te_pp_arcmin, max_pin_force_n) of the paper's runs at the default step,
# measured 2026-11-22 with operating.load_inertia = 0.3 kg m^2 (docs/validation.md); re-pinned
# for the two-flank sun-planet mesh and the conforming bushings with the 5e-6 s step of issue 10
# (before both: 4.1476, 1.0450, 874.37 / 9.2602, 1.1619, 1328.42 / 14.3729, 1.5263, 1727.08;
# docs/decisions.md), and re-pinned for the faster kernel of issue 14 (same physics, other
# rounding; before: 3.3745810629783386, 0.1742743314709907, 761.7890007333014 /
# 8.100121040256605, 0.41565929759822673, 1207.2903257609764 / 12.961114241408588,
# 0.6780180152296236, 1642.1394312128896), and again for issue 14's carried values (the
# contact laws' series, the pins' carried cosines and powers: other rounding, 2026-11-26;
# before: 3.374585558284625, 0.17428258572410593, 763.7551172649006 / 8.100119452864666,
# 0.41565931094815944, 1207.3041158690949 / 12.96111977432062, 0.6755408931098632,
# 1642.1394311592592), and again for the Newton starts from the last solution's Taylor
# expansion, the pins' foot trig carried from the Newton step's start and one cosine and sine
# per angle and force evaluation (issue 14, 2026-11-26 second session; before:
# 3.3745875804065286, 0.17318310272807969, 768.2609516934006 / 8.100121572273315,
# 0.4156592871405618, 1207.4976128660169 / 12.96111937030543, 0.6791068291972042,
# 1642.1394310321145), and again for the laws' Newton started from the Taylor predictor also
# beyond the series and the pins' foot cosines turned by series up to 3e-2 rad (issue 14,
# 2026-11-26 third session; before: 3.3745801006857574, 0.17409963561643815,
# 762.4121843450818 / 8.100121367155177, 0.4156592919823856, 1207.4023364790394 /
# 12.961117917445181, 0.6755408931663496, 1642.1394312353582), and again for the largest pin
# force taken at every step instead of from the 2 kHz samples (2026-11-26 fourth session; the
# TE unchanged; before: 775.4986921520194 / 1207.4039592136874 / 1642.139431107833).  The
# pins hold one machine's
# arithmetic bit for bit: the kernel with
# the step changed by 1e-12 relative moves run 1's peak-to-peak TE and largest pin force by up
# to 3 % and its mean TE by 2.5e-6, run 3's peak-to-peak TE by up to 0.55 % (0.675541-0.679253
# arcmin; docs/benchmarks.md, issue 14)
PINNED = {1: (3.3745838618238206, 0.17692377881200283, 775.5549711206271),
          2: (8.100120794254853, 0.4156592977936411, 1216.2155968370018),
          3: (12.961119882552872, 0.6755408931068096, 1642.2694567844965)}


@pytest.mark.parametrize("run", [1, 3])
def test_paper_runs_are_pinned(run):
    metrics = simulate(with_values(RV40E, paper_run_values(run))).metrics
    measured = (metrics["te_mean_arcmin"], metrics["te_pp_arcmin"], metrics["max_pin_force_n"])
    assert measured == pytest.approx(PINNED[run], rel=1e-6)


def test_paper_run_2_is_pinned(paper_run_2):
    metrics = paper_run_2[1].metrics
    measured = (metrics["te_mean_arcmin"], metrics["te_pp_arcmin"], metrics["max_pin_force_n"])
    assert measured == pytest.approx(PINNED[2], rel=1e-6)
