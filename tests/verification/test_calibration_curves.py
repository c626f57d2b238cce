"""Fits to bench curves (issue 33 item 5): the stiffness scalings are the compliance budget's
stiffening; round trips on loop curves and efficiency points made by the model itself with
known parameters recover them (estimates and 95 % intervals pinned from a real run); data that
cannot separate two parameters say so."""

import dataclasses
import runpy
from pathlib import Path

import numpy as np
import pytest

from rvsim.errors import ParameterError
from rvsim.parameters import BUILT_IN_SETS, RV40E, Stiffness, with_values
from rvsim.physics.stiffening import ELEMENTS
from rvsim.quasistatic import hysteresis
from rvsim.quasistatic.efficiency import efficiency_points
from rvsim.testrig.calibration import calibrate
from rvsim.testrig.curves import EfficiencyPoints, LoopCurve
from rvsim.units import ARCMIN

ARCSEC = ARCMIN / 60.0


def test_stiffness_groups_are_the_budgets_elements():
    assert tuple(f.name for f in dataclasses.fields(Stiffness)) == ELEMENTS


def test_a_stiffness_scaling_is_the_budgets_stiffening_in_every_run():
    scaled = hysteresis(with_values(RV40E, {"stiffness.pins": 2.0,
                                            "stiffness.arm_bearings": 0.5}),
                        points_per_branch=4)
    stiffened = hysteresis(RV40E, points_per_branch=4, stiffen={"pins": 2.0,
                                                                "arm_bearings": 0.5})
    assert np.array_equal(scaled.angle, stiffened.angle)
    # the standard sweep given as a torque history is the standard test, bit for bit
    followed = hysteresis(RV40E, torques=stiffened.torque)
    assert np.array_equal(followed.angle, hysteresis(RV40E, points_per_branch=4).angle)
    assert np.array_equal(followed.branch, stiffened.branch)
    with pytest.raises(ParameterError, match="stiffness.input_coupling.*no such element"):
        hysteresis(with_values(RV40E, {"stiffness.input_coupling": 2.0}), points_per_branch=4)


def _loop(reducer, points_per_branch, noise_arcsec, seed):
    run = hysteresis(reducer, points_per_branch=points_per_branch)
    angle = run.angle + np.random.default_rng(seed).normal(0.0, noise_arcsec * ARCSEC,
                                                           run.angle.size)
    return LoopCurve(Path("loop.csv"), run.torque, angle + 1.5 * ARCMIN, run.branch)


def test_loop_round_trip_recovers_stiffness_scalings_and_a_clearance():
    true = {"stiffness.pins": 0.8, "stiffness.arm_bearings": 0.7,
            "clearances.crank_arm_bushing": 0.004}
    loop = _loop(with_values(RV40E, true), 8, 0.1, 7)
    fit = calibrate([], RV40E, list(true), loops=[loop])
    assert fit.status == "ok" and fit.unit == "arcsec" and fit.residuals == 41
    # pinned from the run of 2026-11-28 (41 samples, 0.1 arcsec noise)
    assert fit.estimate == pytest.approx([0.779018, 0.710650, 0.00400048], rel=1e-4)
    assert fit.ci_low == pytest.approx([0.733746, 0.688620, 0.00398053], rel=1e-4)
    assert fit.ci_high == pytest.approx([0.824290, 0.732679, 0.00402043], rel=1e-4)
    assert fit.rms_arcsec == pytest.approx(0.0727, abs=1e-4)     # the noise: 0.1 arcsec
    assert np.all((fit.ci_low < list(true.values())) & (list(true.values()) < fit.ci_high))
    assert fit.reducer.stiffness.pins == pytest.approx(fit.estimate[0], rel=1e-12)


def test_efficiency_round_trip_recovers_viscous_and_coulomb_friction():
    base = BUILT_IN_SETS["RV-40E-bearings"]
    true = {"friction.arm_bearing_f0": 4.5, "contact.friction_coefficient": 0.03}
    speeds, torques = np.array([500.0, 500.0, 3000.0, 3000.0]), np.array([100.0, 400.0] * 2)
    measured = efficiency_points(with_values(base, true), speeds, torques)
    measured += np.random.default_rng(5).normal(0.0, 0.001, measured.size)
    points = EfficiencyPoints(Path("points.csv"), speeds, torques, measured, None)
    fit = calibrate([], base, list(true), efficiency=points)
    assert fit.status == "ok" and fit.unit == "%"
    assert fit.to_dict()["rms_percent"] == pytest.approx(fit.rms_arcsec)
    # pinned from the run of 2026-11-28 (4 points, 0.1 percentage point noise)
    assert fit.estimate == pytest.approx([4.40278, 0.0305851], rel=1e-4)
    assert fit.ci_low == pytest.approx([3.54867, 0.0283573], rel=1e-4)
    assert fit.ci_high == pytest.approx([5.25690, 0.0328129], rel=1e-4)
    assert fit.rms_arcsec == pytest.approx(0.0608, abs=1e-4)     # percentage points
    assert np.all((fit.ci_low < list(true.values())) & (list(true.values()) < fit.ci_high))


def test_two_clearances_in_series_are_not_identifiable_from_a_loop():
    """The eccentric's and the disc hole's clearances at the arm bushing add up: a loop sees
    their sum only (the existing rule: correlation >= 0.999 or a singular direction)."""
    loop = _loop(with_values(RV40E, {"clearances.crank_arm_bushing": 0.004}), 4, 0.1, 7)
    fit = calibrate([], RV40E, ["clearances.crank_arm_bushing",
                                "clearances.disc_arm_bushing"], loops=[loop])
    assert fit.status == "not_identifiable"
    assert np.all(np.isnan(fit.ci_low)) and np.all(np.isnan(fit.ci_high))
    assert any("cannot tell clearances.crank_arm_bushing and clearances.disc_arm_bushing "
               "apart" in n for n in fit.notes)


def test_the_example_loop_is_what_its_script_makes():
    """docs/examples/hysteresis_loop.csv (the user guide's fit) from its stated parameters."""
    import pandas as pd

    root = Path(__file__).resolve().parents[2]
    script = runpy.run_path(str(root / "scripts" / "make_loop_example.py"))
    made, stored = script["make"](), pd.read_csv(script["OUT"])
    assert list(stored.columns) == list(made.columns)
    assert np.allclose(stored.to_numpy(), made.to_numpy(), rtol=1e-9, atol=1e-12)


def test_efficiency_points_at_their_own_lubricant_temperature():
    """Each point's temperature_c is the model's operating.temperature there (the viscosity
    law of RV-40E-bearings makes it matter): the model's own points leave no residual."""
    from rvsim.testrig.calibration import _efficiency_residuals

    base = BUILT_IN_SETS["RV-40E-bearings"]
    speeds, torques = np.array([3000.0, 3000.0]), np.array([200.0, 200.0])
    temperatures = np.array([20.0, 60.0])
    model = [efficiency_points(with_values(base, {"operating.temperature": t}), [n], [q])[0]
             for n, q, t in zip(speeds, torques, temperatures)]
    assert model[0] < model[1] - 0.005           # thicker oil at 20 degC: more viscous loss
    points = EfficiencyPoints(Path("points.csv"), speeds, torques, np.array(model),
                              temperatures)
    assert np.array_equal(_efficiency_residuals(points, base), [0.0, 0.0])
