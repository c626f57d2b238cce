"""The contract between the quasi-static engine and the catalogue half (issue 9): the result
objects' fields, shapes and summary keys, checked on ``rvsim.quasistatic``."""

import json

import numpy as np
import pytest

import rvsim.quasistatic as qs
from rvsim.analysis import catalogue
from rvsim.parameters import RV40E
from rvsim.units import ARCMIN


LTCA_KEYS = {"te_mean_arcmin", "te_pp_arcmin", "max_pin_force_n", "pins_in_contact_min",
             "pins_in_contact_max", "max_contact_stress_mpa", "torsional_stiffness_nm_per_arcmin",
             "positions", "wall_s", "status"}
HYST_KEYS = {"rated_torque_nm", "torsional_rigidity_nm_per_arcmin", "lost_motion_arcmin",
             "backlash_arcmin", "hysteresis_loss_arcmin", "wall_s", "status"}


@pytest.fixture(scope="module")
def ltca_run():
    return qs.ltca(RV40E, torque=412.0, positions=72, allow_aliasing=True)


@pytest.fixture(scope="module")
def loop():
    return qs.hysteresis(RV40E)


def test_ltca_result_fields(ltca_run):
    r = ltca_run
    n, zp = 72, RV40E.cycloid.pin_count
    assert r.status == "ok" and r.converged.all()
    assert r.input_angle.shape == r.output_angle.shape == r.te.shape == (n,)
    assert r.pin_forces.shape == r.contact_stress.shape == (n, 2, zp)
    assert r.torsional_stiffness.shape == (n,)
    assert np.allclose(r.te, r.input_angle / r.ratio - r.output_angle, rtol=0, atol=1e-15)
    assert np.allclose(r.te_relative, r.te - r.te.mean(), rtol=0, atol=1e-15)
    summary = r.summary()
    assert LTCA_KEYS <= set(summary) and summary["positions"] == n
    assert summary["te_pp_arcmin"] == pytest.approx(np.ptp(r.te) / ARCMIN, rel=1e-12)
    spectrum = r.spectrum()
    orders, amplitude = catalogue.order_spectrum(r.input_angle / r.ratio, r.te)
    assert np.allclose(spectrum["order"], orders)
    assert np.allclose(spectrum["amplitude_arcmin"], amplitude / ARCMIN)
    assert len(r.to_frame()) == n
    # the largest contact stress against ISO 76's static limit (issue 34 item 6)
    assert summary["max_contact_stress_mpa"] == pytest.approx(623.286, rel=1e-5)
    assert summary["static_contact_stress_mpa"] == 4000.0
    assert summary["contact_stress_verdict"] == "below the static limit (16 % of 4000 MPa)"
    assert r.contact_stress_warning() is None


def test_hysteresis_result_fields(loop):
    assert loop.status == "ok" and loop.rated_torque == pytest.approx(412.0)
    assert set(np.unique(loop.branch)) <= {1, -1}
    summary = loop.summary()
    assert HYST_KEYS <= set(summary)
    t, a, b = loop.torque, loop.angle, loop.branch
    assert summary["backlash_arcmin"] == pytest.approx(catalogue.backlash(t, a, b) / ARCMIN,
                                                       rel=1e-12)
    assert summary["torsional_rigidity_nm_per_arcmin"] > 0
    assert len(loop.to_frame()) == t.size


def test_commands_on_the_engine(cli, tmp_path):
    joint = tmp_path / "joint.json"
    res = cli("hysteresis", "--json", "--export", str(joint), "--report",
              str(tmp_path / "h.html"))
    assert res.code == 0, res.err
    assert HYST_KEYS <= set(json.loads(res.out))
    from rvsim.joint_model import load_joint_model

    assert load_joint_model(joint)["reducer"]["rated_torque_nm"] == pytest.approx(412.0)
    res = cli("ltca", "--positions", "81", "--json", "--report", str(tmp_path / "l.html"))
    assert res.code == 0, res.err
    assert LTCA_KEYS <= set(json.loads(res.out))


def test_summary_of_a_stopped_torque_reversal_names_its_status():
    # a test that stops early (no raise) cannot give the catalogue quantities: NaN beside the
    # status, not an exception from summary()
    from rvsim.parameters import RV40E, with_values
    from rvsim.quasistatic import hysteresis

    # the momentary maximum raised with it: above it a load is refused (issue 30)
    unrated = with_values(RV40E, {"rating.momentary_torque": 1e9})
    loop = hysteresis(unrated, rated_torque=1e9, points_per_branch=2, raise_on_failure=False)
    assert loop.status == "not_converged" and not loop.converged.all()
    summary = loop.summary()
    assert summary["status"] == "not_converged"
    assert np.isnan(summary["torsional_rigidity_nm_per_arcmin"])
