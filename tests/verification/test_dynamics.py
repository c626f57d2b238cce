"""Verification of the dynamic model against analytic limits (issue 3, item 4).

* zero errors and no load: TE == 0 and speed ratio 121 to solver precision;
* rigid crank bearings: the pin loads follow the textbook distribution (pins with a positive
  lever arm l_i carry F_i proportional to l_i**(1/0.9) under the Palmgren law, the rest carry
  nothing; both discs share equally) and the crank bearing forces follow from the disc's force
  and moment balance with the pin resultant shared equally by the two cranks;
* steady torque balance T_in * 121 = T_out (no friction) within 1 %;
* halving the time step changes the steady mean TE by < 0.5 %;
* energy: input work = output work + dissipation (+ changes of kinetic and potential energy and
  the work of the time-varying mesh stiffness) within 1 % over the steady window.
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

# a shortened schedule (same physics, faster ramps) keeps these tests quick
QUICK = {"operating.speed_ramp_time": 0.2, "operating.load_start": 0.2,
         "operating.load_ramp_end": 0.4, "operating.steady_start": 0.6,
         "operating.duration": 1.0}


@pytest.fixture(scope="module")
def paper_run_2():
    reducer = with_values(RV40E, paper_run_values(2))
    return reducer, simulate(reducer), simulate(reducer, time_step=5e-6)


def test_zero_error_no_load_gives_zero_te_and_ratio_121():
    reducer = with_values(RV40E, {"E": 0, "operating.duration": 2.0})
    result = simulate(reducer)
    window = result.time >= 1.5
    # what is left is start-up vibration decaying through contact damping: < 1e-4 arcmin
    # (measured 5e-5); the mean is zero to 1e-6 arcmin
    assert np.max(np.abs(result.te[window])) / ARCMIN < 1e-4
    assert abs(np.mean(result.te[window])) / ARCMIN < 1e-6
    assert result.metrics["speed_ratio"] == pytest.approx(121.0, abs=1e-4)  # measured 6e-6


@pytest.fixture(scope="module")
def rigid_bearings():
    reducer = with_values(RV40E, {**QUICK, "contact.bushing_stiffness_factor": 1e3,
                                  "operating.duration": 0.7})
    return reducer, simulate(reducer, time_step=1e-6, sample_rate=500)


def test_pin_load_sharing_follows_textbook(rigid_bearings):
    reducer, result = rigid_bearings
    i = len(result.time) - 1
    crank_angle = -reducer.cycloid.disc_teeth * result.theta_out[i]
    torques = []
    for disc in (0, 1):
        lever, _ = pin_contact_geometry(reducer, crank_angle, disc=disc)
        force = result.pin_forces[i, disc]
        shape = np.where(lever > 0, np.abs(lever) ** (1 / 0.9), 0.0)
        expected = shape * (force @ lever) / (shape @ lever)
        assert np.max(np.abs(force - expected)) < 0.02 * force.max()
        assert np.all(force[lever < -1e-3] == 0.0)
        torques.append(force @ lever)
    assert torques[0] == pytest.approx(torques[1], rel=0.01)


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
            assert simulated == pytest.approx(np.linalg.norm(bearing), rel=0.03)


def test_steady_torque_balance(paper_run_2):
    _, result, _ = paper_run_2
    window = result.time >= 1.5
    torque_in = result.channel("torque_in")[window].mean()
    torque_out = result.channel("torque_load")[window].mean()
    assert torque_in * 121 == pytest.approx(torque_out, rel=0.01)


def test_halving_time_step_changes_mean_te_below_half_percent(paper_run_2):
    _, coarse, fine = paper_run_2
    a, b = coarse.metrics["te_mean_arcmin"], fine.metrics["te_mean_arcmin"]
    assert abs(a - b) < 0.005 * abs(b)


def test_energy_balance_within_one_percent(paper_run_2):
    _, result, _ = paper_run_2
    e = result.energy
    assert e["input_work"] > 100.0
    assert abs(e["relative_residual"]) < 0.01
    assert e["dissipated"] >= 0.0


def test_friction_dissipates_and_balance_still_holds():
    reducer = with_values(RV40E, {**QUICK, "contact.friction_coefficient": 0.05,
                                  "I": 0.016, "J": 0.026})
    result = simulate(reducer)
    assert result.energy["dissipated"] > 0.01 * result.energy["input_work"]
    assert abs(result.energy["relative_residual"]) < 0.01


def test_unstable_step_reports_status():
    reducer = with_values(RV40E, QUICK)
    with pytest.raises(SimulationError) as info:
        simulate(reducer, time_step=1e-4)
    assert info.value.status in ("diverged", "runaway_penetration")
    partial = simulate(reducer, time_step=1e-4, raise_on_failure=False)
    assert partial.status == info.value.status
    assert partial.steps < 1.0 / 1e-4
