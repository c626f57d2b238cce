"""Verification of the friction elements and the efficiency (issue 10, items 4, 5, 8).

* friction zero (every coefficient 0, pins free to turn, another oil): the dynamic and the
  quasi-static results equal the frictionless model's to the last bit;
* energy balance with friction in a dynamic run: input work = output work + dissipated work
  (+ the changes of kinetic and potential energy and the parametric work) within 1e-4 of the
  input work (measured 1.5e-5; the issue asks 1 %), the friction taking 9.8 % of it;
* the quasi-static torque-reversal loop's area equals the friction work of the cycle
  (measured 3.8e-4 relative: both are sums over the same 200 steps);
* efficiency with the mesh friction alone against the hand calculation of the model
  (Ohlendorf's loss factor), the no-load running torque with Palmgren's viscous bearing torque
  alone against the bearings' relative speeds, and the quasi-static efficiency against a
  dynamic run at one point.

Tolerances are a small factor above what was measured (figures in each test).
"""

import math

import numpy as np
import pytest

from rvsim.dynamics import simulate
from rvsim.friction import TYPICAL_FRICTION, bearing_diameters, gear_loss_factor
from rvsim.parameters import RV40E, with_values
from rvsim.parameters.rv40e import paper_run_values
from rvsim.parameters.rv40e_bearings import RV40E_ROLLING
from rvsim.quasistatic import efficiency, hysteresis, ltca
from rvsim.quasistatic.torque_reversal import TEST_OUTPUT_SPEED, sweep_torques
from rvsim.quasistatic.transmission import solve_path

SHORT = {"operating.speed_ramp_time": 0.1, "operating.load_start": 0.1,
         "operating.load_ramp_end": 0.2, "operating.steady_start": 0.3,
         "operating.duration": 0.4}
#: the finite-element disc (coarse; crankshafts and plates rigid): pin friction on the
#: coupled contacts (docs/model.md section 17)
FE_DISC = {"A": 1, "flexibility.model": "fe", "flexibility.fe_element_size": 4.0,
           "flexibility.fe_segments_per_tooth": 2, "flexibility.fe_crank": False,
           "flexibility.fe_carrier": False}
#: the closed-form tooth, and the finite-element disc (skipped without the FE extra)
BODIES = [pytest.param({}, id="closed-form"),
          pytest.param(FE_DISC, id="fe-disc", marks=pytest.mark.fe)]
#: friction switched on everywhere with every coefficient zero
ZERO_FRICTION = {"friction.pins_turn": True, "friction.oil_viscosity": 32.0,
                 "friction.arm_bearing_diameter": 30.0}


def test_zero_friction_dynamic_run_is_the_frictionless_one():
    # bit for bit: any schedule that loads the reducer shows it (0.2 s, half of SHORT)
    brief = {name: 0.5 * value for name, value in SHORT.items()}
    plain = simulate(with_values(RV40E, brief))
    zero = simulate(with_values(RV40E, {**brief, **ZERO_FRICTION}))
    assert np.array_equal(plain.channels, zero.channels)
    assert plain.energy == zero.energy


def test_zero_friction_quasistatic_is_the_frictionless_one():
    zero = with_values(RV40E, ZERO_FRICTION)
    a, b = hysteresis(RV40E, points_per_branch=10), hysteresis(zero, points_per_branch=10)
    assert np.array_equal(a.angle, b.angle)
    a = ltca(RV40E, positions=12, allow_aliasing=True)
    b = ltca(zero, positions=12, allow_aliasing=True)
    assert np.array_equal(a.te, b.te) and np.array_equal(a.pin_forces, b.pin_forces)


@pytest.fixture(scope="module")
def typical_run():
    """The 0.4 s run with the typical friction everywhere (closed-form bodies): its energy
    balance and the quasi-static efficiency at its operating point are checked on it (a 1 s
    schedule until 2026-11-28)."""
    reducer = with_values(RV40E, {**SHORT, **TYPICAL_FRICTION})
    return reducer, simulate(reducer)


@pytest.mark.parametrize("body", BODIES)
def test_energy_balance_with_friction(body, request):
    if body:        # the FE disc on the 0.4 s schedule (1 s until 2026-11-28: 10.4 %, -3.2e-5)
        result = simulate(with_values(RV40E, {**SHORT, **TYPICAL_FRICTION, **body}))
    else:
        result = request.getfixturevalue("typical_run")[1]
    e = result.energy
    # measured 2026-11-28: 10.1 % and 10.4 % of the input work dissipated, residuals -6.8e-6
    # and -3.7e-5 (the FE disc's neighbours' forces lag one step)
    assert e["dissipated"] > 0.09 * e["input_work"]
    assert abs(e["relative_residual"]) < 2e-4


@pytest.mark.parametrize("body", BODIES)
def test_hysteresis_loop_area_is_the_friction_work(body):
    reducer = with_values(RV40E, {**TYPICAL_FRICTION, **body})
    torque, branch = sweep_torques(reducer.rating.rated_torque, 50)
    path = solve_path(reducer, np.zeros(len(torque)), -torque,
                      carrier_rate=TEST_OUTPUT_SPEED * branch)
    assert path.status == "ok"
    cycle = slice(50, 251)              # -rated -> +rated -> -rated: one closed cycle
    angle = path.q[cycle, 0]
    area = np.trapezoid(torque[cycle], angle)
    f = path.friction_forces[cycle]
    work = -np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(path.q[cycle], axis=0))
    assert area > 0.0
    # measured 2.3e-3 (3.8e-4 with the Palmgren bushings), FE disc 1.8e-3
    assert area == pytest.approx(work, rel=4e-3)
    # loading needs more torque than unloading: the loading branch lags
    up = np.interp(300.0, torque[100:151], angle[50:101])
    down = np.interp(300.0, torque[150:201][::-1], angle[100:151][::-1])
    assert up < down


def test_mesh_friction_efficiency_against_hand_calculation():
    mu = 0.05
    # the hand formula holds for one loaded flank: with no backlash (RV-40E) the radial approach
    # of the crank loads the coast flank too (both flanks are contacts), which adds its friction
    reducer = with_values(RV40E, {"friction.mesh_coefficient": mu, "gears.backlash": 0.02})
    loss = mu * gear_loss_factor(reducer)
    i = reducer.ratio
    # the sun supplies the friction torque mu H_V F rb1; its reaction on the planet reaches
    # the carrier: eta = (1 + mu H_V / i) / (1 + mu H_V)
    expected = (1.0 + loss / i) / (1.0 + loss)
    result = efficiency(reducer, speeds_rpm=[1000.0], torques=[100.0, 412.0])
    assert result.efficiency == pytest.approx(expected, abs=5e-7)     # measured 2.2e-7


def test_viscous_bearing_torque_against_relative_speeds():
    f0, nu = 3.0, 100.0
    reducer = with_values(RV40E, {"friction.arm_bearing_f0": f0,
                                  "friction.support_bearing_f0": f0,
                                  "friction.oil_viscosity": nu})
    speed = 2000.0                                                   # input rpm
    result = efficiency(reducer, speeds_rpm=[speed], torques=[412.0])
    g = reducer.gears
    i = reducer.ratio
    relative = speed * (1.0 - 1.0 / i) * g.sun_teeth / g.planet_teeth   # crank vs carrier, rpm
    torque = 0.0
    for dm in bearing_diameters(reducer):                            # 4 arm + 4 support
        m0 = 1e-7 * f0 * (nu * relative) ** (2.0 / 3.0) * (dm * 1e3) ** 3 * 1e-3
        torque += 4 * m0
    expected = torque * relative / speed
    assert result.no_load_running_torque[0] == pytest.approx(expected, rel=1e-8)  # 2.9e-10


def test_quasistatic_efficiency_matches_a_dynamic_run(typical_run):
    reducer, result = typical_run
    dynamic = result.energy
    eta_dynamic = dynamic["output_work"] / (dynamic["input_work"] - dynamic["kinetic_change"]
                                            - dynamic["potential_change"])
    rpm = reducer.operating.input_speed * 30.0 / math.pi
    static = efficiency(reducer, speeds_rpm=[rpm], torques=[reducer.operating.load_torque])
    # measured 4.0e-4 on the 0.4 s run (6.4e-5 on the 1 s one: the carrier still settles;
    # 3.3e-5 with the one-flank mesh)
    assert static.efficiency[0, 0] == pytest.approx(eta_dynamic, abs=1e-3)


@pytest.mark.parametrize("source", [
    ("contact.friction_coefficient",), ("friction.mesh_coefficient",),
    ("friction.arm_bearing_f0", "friction.arm_bearing_f1"),
    ("friction.support_bearing_f0", "friction.support_bearing_f1"),
])
def test_each_friction_source_alone_converges_through_zero_torque(source):
    # at 0 N*m nothing is loaded but the bearings' viscous torque: the direction of travel is
    # held per point, so the Coulomb forces settle (a direction taken afresh at each update
    # turned the support bearings' torque over and back: not_converged)
    reducer = with_values(RV40E, {name: TYPICAL_FRICTION[name] for name in source})
    result = hysteresis(reducer, points_per_branch=10)
    assert result.status == "ok" and result.converged.all()
    assert result.summary()["torsional_rigidity_nm_per_arcmin"] > 0


def test_te_depends_on_the_direction_of_travel_only_with_friction():
    angles = np.linspace(0.0, 2.0, 9)
    load = np.full(len(angles), 300.0)
    speed = RV40E.operating.input_speed

    def te(reducer, sign):
        path = solve_path(reducer, angles[::sign], load, input_speed=sign * speed)
        assert path.status == "ok"
        return (angles[::sign] / reducer.ratio - path.q[:, 0])[::sign]

    plain = te(RV40E, 1)
    # without friction both ways reach the same equilibria, to the solver's tolerance
    assert np.abs(plain - te(RV40E, -1)).max() < 1e-10         # measured 6.4e-12 rad
    rough = with_values(RV40E, TYPICAL_FRICTION)
    forwards, backwards = te(rough, 1), te(rough, -1)
    # forwards the friction adds to the load the drive winds up against (>= 1.39e-6 rad
    # measured with the conforming bushings), backwards, with the load helping the motion, it
    # takes away
    assert np.all(forwards - plain > 1e-6) and np.all(plain - backwards > 1e-6)


@pytest.mark.parametrize("base, run, extra", [
    (RV40E, 2, {"contact.friction_coefficient": 0.05}),
    (RV40E, 3, TYPICAL_FRICTION),
    (RV40E_ROLLING, 2, TYPICAL_FRICTION),
    (RV40E_ROLLING, 3, TYPICAL_FRICTION),
])
def test_torque_reversal_with_friction_and_clearances_converges(base, run, extra):
    # with the paper's clearances every contact unloads at 0 N*m: the friction held during a
    # search used to push the bodies across their play there (not_converged at 0 N*m for paper
    # runs 2 and 3).  With the input held and no torque the reducer sticks where it came from
    # (docs/model.md section 15), so the clearance loop is the frictionless one
    plain = hysteresis(with_values(base, paper_run_values(run))).summary()
    rough = hysteresis(with_values(base, {**paper_run_values(run), **extra}))
    assert rough.status == "ok" and rough.converged.all()
    s = rough.summary()
    # measured 6e-5 .. 1.1e-4 relative (the elastic part of the lost motion changes with
    # friction)
    assert s["lost_motion_arcmin"] == pytest.approx(plain["lost_motion_arcmin"], rel=3e-4)
    # measured 7e-5 .. 6e-4 relative below the frictionless backlash
    assert s["backlash_arcmin"] == pytest.approx(plain["backlash_arcmin"], rel=1.5e-3)
    assert s["backlash_arcmin"] <= plain["backlash_arcmin"]
