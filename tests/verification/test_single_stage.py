"""Verification of the single-stage cycloid drive ``cycloid-drive`` in both engines (issue 9,
items 6 and 9).

Measured (2026-11-22) and the tolerance of each test:

* zero errors, no load: |TE| = 0 over a revolution (quasi-static; tolerance 1e-14 rad); under
  rated torque the TE after one output revolution equals the TE at its start to 1.8e-11 rad
  (tolerance 1e-10 rad; the ratio is exact, i = -zc); the dynamic model's steady speed ratio is
  -zc within 3.1e-12 relative (tolerance 2e-11) and its TE without load stays below 2.1e-14 rad
  (tolerance 1e-13 rad; measured 2026-11-28 on a 0.5 s schedule, the one below measures
  8.4e-13 and 1.75e-14);
* rigid bearings (bushing stiffness x 1e5), zero clearance: ring pin loads follow the textbook
  distribution within 0.51 % of the largest (tolerance 0.8 %; the largest deviation at the pin
  leaving contact), output pin loads within 0.081 % (tolerance 0.15 %);
* the dynamic model's steady mean TE at a quarter of the input speed, constant load, over two
  eccentric turns, equals the quasi-static mean over the same input angles within 1.0e-6
  relative (tolerance 5e-6; the issue asks 1 %; shorter schedules leave more of the load
  ramp's ringing in the window: 3.7e-6 over one turn, 1.0e-5 over one turn from 0.3 s);
* torque reversal with an output pin clearance c_w: backlash = 2 c_w / R_w within 3.1e-7
  (tolerance 1e-6);
* torque balance: the moment of the output pin forces about the housing axis equals the output
  torque within 5.9e-12 of it (tolerance 1e-10);
* the output flange's row and column of the stiffness matrix (output pins only) equal central
  differences of the forces within 6.8e-9 of the largest entry (tolerance 1e-7); the condensed
  torsional stiffness equals dT/dTE within 6.6e-3 (tolerance 1e-2, see the test).
"""

import math

import numpy as np
import pytest

from rvsim.cli import main
from rvsim.physics import _layout as L
from rvsim.dynamics import simulate
from rvsim.physics._forces import forces_at
from rvsim.dynamics.model import build_model
from rvsim.errors import ParameterError
from rvsim.geometry.layout import output_pins
from rvsim.parameters import BUILT_IN_SETS, load_toml, with_values
from rvsim.quasistatic import hysteresis, ltca, solve_path
from rvsim.units import ARCMIN
from tests.verification.textbook import textbook_output_pin_forces, textbook_pin_forces

DRIVE = BUILT_IN_SETS["cycloid-drive"]


def test_zero_errors_no_load_gives_zero_te_and_exact_ratio():
    assert DRIVE.ratio == -DRIVE.cycloid.disc_teeth
    result = ltca(DRIVE, torque=0.0, positions=36)
    assert result.status == "ok"
    assert np.max(np.abs(result.te)) < 1e-14                # measured 0
    angle = np.linspace(0.0, 2.0 * math.pi * DRIVE.ratio, 37)
    path = solve_path(DRIVE, angle, np.full(len(angle), DRIVE.rating.rated_torque))
    te = angle / DRIVE.ratio - path.q[:, L.CARRIER]
    assert path.status == "ok" and te[0] > 1e-4             # wound up under load
    assert abs(te[-1] - te[0]) < 1e-10                      # measured 1.8e-11 rad


def _low_speed(load):
    speed = 1750.0                                          # deg/s: a quarter of the set's
    eccentric_period = 360.0 / speed
    steady = 0.8
    return with_values(DRIVE, {
        "operating.load_torque": load, "operating.input_speed": math.radians(speed),
        "operating.speed_ramp_time": 0.2, "operating.load_start": 0.2,
        "operating.load_ramp_end": 0.4, "operating.steady_start": steady,
        "operating.duration": steady + 2.0 * eccentric_period, "operating.load_inertia": 0.0})


#: the unloaded run needs no long window (nothing rings without load): one eccentric turn
#: from 0.3 s
UNLOADED = {"operating.speed_ramp_time": 0.1, "operating.load_start": 0.1,
            "operating.load_ramp_end": 0.2, "operating.steady_start": 0.3,
            "operating.duration": 0.3 + 360.0 / 1750.0}


def test_dynamic_ratio_and_unloaded_te():
    result = simulate(with_values(_low_speed(0.0), UNLOADED))
    assert result.status == "ok"
    ratio = result.metrics["speed_ratio"]
    assert ratio == pytest.approx(DRIVE.ratio, rel=2e-11)   # measured 3.1e-12
    window = result.time >= 0.3
    assert np.max(np.abs(result.te[window])) < 1e-13       # measured 2.1e-14 rad


def test_quasi_static_te_equals_dynamic_mean_at_low_speed():
    reducer = _low_speed(150.0)
    dynamic = simulate(reducer)
    window = dynamic.time >= reducer.operating.steady_start - 1e-12
    theta_in = dynamic.channel("theta_in")[window][::10]
    path = solve_path(reducer, theta_in, np.full(len(theta_in), 150.0))
    assert path.status == "ok"
    te = theta_in / reducer.ratio - path.q[:, L.CARRIER]
    assert te.mean() == pytest.approx(dynamic.te[window].mean(), rel=5e-6)  # measured 1.0e-6
    # the spectrum's orders are the drive's own 30 pins' (a review found them the RV-40E's 40
    # whatever the reducer)
    assert dynamic.spectrum().equals(dynamic.spectrum(pin_count=30))
    assert not dynamic.spectrum().equals(dynamic.spectrum(pin_count=40))


def test_rigid_bearings_follow_textbook_ring_and_output_pin_loads():
    reducer = with_values(DRIVE, {"contact.bushing_stiffness_factor": 1e5})
    angle = np.linspace(0.0, 2.0 * math.pi * reducer.ratio / 10.0, 12, endpoint=False)
    path = solve_path(reducer, angle, np.full(len(angle), 200.0))
    assert path.status == "ok"
    for k in range(len(angle)):
        # the eccentric's actual angle places the discs (the output pins' deflection turns the
        # output, not the discs: -zc x output angle is 0.9 deg off at 200 N*m)
        crank_angle = path.q[k, L.CRANK0 + 4]
        for disc in (0, 1):
            force = path.pin_forces[k, disc]
            expected, _ = textbook_pin_forces(reducer, crank_angle, disc, force)
            assert np.max(np.abs(force - expected)) < 0.008 * force.max()   # measured 0.51 %
            force = path.output_pin_forces[k, disc]
            expected, _ = textbook_output_pin_forces(reducer, crank_angle, disc, force)
            assert np.max(np.abs(force - expected)) < 0.0015 * force.max()  # measured 0.081 %


@pytest.mark.parametrize("values", [{}, {"layout.disc_count": 1,
                                         "layout.output_pin_clearance": 0.01,
                                         "clearances.crank_arm_bushing": 0.005}])
def test_output_pin_forces_balance_output_torque(values):
    reducer = with_values(DRIVE, values)
    torque = 150.0
    angle = np.linspace(0.0, 2.0 * math.pi * reducer.ratio / 20.0, 5)
    path = solve_path(reducer, angle, np.full(len(angle), torque))
    assert path.status == "ok"
    pins = output_pins(reducer)
    for k in range(len(angle)):
        q = path.q[k]
        c, s = math.cos(q[L.CARRIER]), math.sin(q[L.CARRIER])
        px, py = c * pins[:, 0] - s * pins[:, 1], s * pins[:, 0] + c * pins[:, 1]
        moment = 0.0
        for disc in range(reducer.layout.disc_count):
            d = L.DISC0 + L.DISC_STRIDE * disc
            ct, st = math.cos(q[d + 2]), math.sin(q[d + 2])
            rx = px - q[d] - (ct * pins[:, 0] - st * pins[:, 1])
            ry = py - q[d + 1] - (st * pins[:, 0] + ct * pins[:, 1])
            dist = np.hypot(rx, ry)
            force = path.output_pin_forces[k, disc]
            # -F n on each pin of the flange
            moment += np.sum(force * (rx * py - ry * px) / dist)
        assert moment == pytest.approx(torque, rel=1e-10)  # measured 5.9e-12


def test_parameters_of_the_other_topology_are_refused():
    with pytest.raises(ParameterError, match="clearances.support_flange"):
        with_values(DRIVE, {"L": 0.005})
    with pytest.raises(ParameterError, match="layout.disc_count"):
        with_values(BUILT_IN_SETS["RV-40E"], {"layout.disc_count": 1})
    with pytest.raises(ParameterError, match="layout.output_pin_circle_radius"):
        with_values(DRIVE, {"layout.output_pin_circle_radius": 52.0})


def test_toml_base_and_set_name_on_the_command_line(tmp_path, capsys):
    path = tmp_path / "drive.toml"
    path.write_text('base = "cycloid-drive"\n[layout]\noutput_pin_clearance = 0.005\n')
    reducer = load_toml(path)
    assert reducer.layout.single_stage and reducer.layout.output_pin_clearance == 5e-6
    assert main(["ltca", "--params", str(path), "--positions", "61", "--json"]) == 0
    assert '"status": "ok"' in capsys.readouterr().out
    assert main(["hysteresis", "--params", "cycloid-drive", "--json"]) == 0
    assert '"status": "ok"' in capsys.readouterr().out
    short = tmp_path / "short.toml"
    short.write_text('base = "cycloid-drive"\n[operating]\nduration = 0.2\nsteady_start = 0.15\n'
                     'speed_ramp_time = 0.05\nload_start = 0.05\nload_ramp_end = 0.1\n')
    assert main(["simulate", "--params", str(short), "--json"]) == 0
    out = capsys.readouterr().out
    assert '"status": "ok"' in out and '"reducer": "cycloid-drive"' in out
    assert main(["simulate", "--params", "cycloid-drive", "--paper-run", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["rvsim: error: parameter 'paper-run': the paper's runs are runs of the "
                   "RV-40E; 'cycloid-drive' is a single-stage drive"]


def _forces(reducer, q, theta_in, torque, want_stiffness):
    """The kernel's force evaluation at rest (the quasi-static residual) and its matrix."""
    model = build_model(reducer, 1e-5)
    zp, n_out = reducer.cycloid.pin_count, reducer.layout.output_pin_count
    Q = np.zeros(L.N_DOF)
    K = np.zeros((L.N_DOF, L.N_DOF) if want_stiffness else (0, 0))
    forces_at(model.P, q, np.zeros(L.N_DOF), theta_in, 0.0, torque, model.pins,
              2.0 * np.pi * np.arange(zp) / zp, model.holes, model.crank_angles,
              model.mesh_phase, np.zeros((2, zp)), np.zeros((2, zp), dtype=np.int64), 1,
              np.zeros((2, zp)), np.zeros((2, zp)), np.zeros((2, L.OUT_SLOT0 + n_out)), Q, K,
              want_stiffness, np.zeros(L.N_CHANNELS), np.zeros((2, 4)), np.zeros((2, 2)), model.fe)
    return Q, K


@pytest.mark.parametrize("values", [{}, {"layout.output_pin_clearance": 0.01}])
def test_output_pin_stiffness_is_the_derivative_of_the_forces(values):
    """The output pins are the only elements on the output flange: the flange's row and column
    of the stiffness matrix are theirs alone, and equal central differences of -Q."""
    reducer = with_values(DRIVE, values)
    path = solve_path(reducer, np.array([-0.3]), np.array([150.0]))
    q = path.q[0]
    _, K = _forces(reducer, q, -0.3, 150.0, True)
    h = 1e-9
    column = np.zeros(L.N_DOF)
    row = np.zeros(L.N_DOF)
    for i in range(L.N_DOF):
        dq = np.zeros(L.N_DOF)
        dq[i] = h
        diff = -(_forces(reducer, q + dq, -0.3, 150.0, False)[0]
                 - _forces(reducer, q - dq, -0.3, 150.0, False)[0]) / (2.0 * h)
        row[i] = diff[L.CARRIER]
        if i == L.CARRIER:
            column = diff
    scale = np.abs(K[L.CARRIER]).max()
    assert np.max(np.abs(K[L.CARRIER] - row)) < 1e-7 * scale     # measured 5.3e-9
    assert np.max(np.abs(K[:, L.CARRIER] - column)) < 1e-7 * scale  # measured 6.8e-9


def test_local_stiffness_is_derivative_of_loaded_te():
    """As for the RV (tests/verification/test_quasistatic.py), less close: the condensed
    matrix leaves out the ring pins' profile-curvature terms (docs/model.md, "Quasi-static
    analysis"), and the disc's rotation, stiff against its translations, amplifies them; the
    condensed finite-difference matrix gives the finite-difference stiffness exactly."""
    torque = 150.0
    step = 1e-3 * torque
    for angle in (-0.3, -1.1):
        path = solve_path(DRIVE, np.full(3, angle),
                          np.array([torque, torque - step, torque + step]))
        assert path.status == "ok"
        finite_difference = 2.0 * step / (path.q[1, L.CARRIER] - path.q[2, L.CARRIER])
        # measured 6.6e-3 and 5.7e-3
        assert path.torsional_stiffness[0] == pytest.approx(finite_difference, rel=1e-2)


@pytest.mark.parametrize("clearance", [0.005, 0.02])
def test_backlash_of_the_output_pins_is_twice_clearance_over_pin_circle(clearance):
    """Input locked at 0: the eccentric points along x and the pin at 90 deg moves straight
    away from its hole's centre as the output turns, so it closes its clearance c_w after a
    turn of c_w / R_w each way (exactly: |r| = a + R_w sin(dtheta) + O(dtheta^2) for it)."""
    reducer = with_values(DRIVE, {"layout.output_pin_clearance": clearance})
    result = hysteresis(reducer, points_per_branch=20)
    expected = 2.0 * clearance * 1e-3 / reducer.layout.output_pin_circle_radius
    # measured 3.1e-7 and 1.3e-7 relative
    assert result.summary()["backlash_arcmin"] * ARCMIN == pytest.approx(expected, rel=1e-6)


def test_rv_only_parameters_change_nothing_in_a_single_stage_drive():
    other = with_values(DRIVE, {"gears.planet_teeth": 200, "gears.module": 5.0,
                                "crank.gear_z": 80.0, "cycloid.pillar_hole_count": 6,
                                "cycloid.disc_bore_radius": 40.0})
    a = ltca(DRIVE, torque=150.0, positions=8)
    b = ltca(other, torque=150.0, positions=8)
    assert np.array_equal(a.te, b.te) and np.array_equal(a.pin_forces, b.pin_forces)
