"""``rvsim ltca`` / ``rvsim hysteresis`` as a user runs them, on the real quasi-static engine
(failures are made by wrapping the engine's functions, so their paths are tested too)."""

import dataclasses
import json
import math

import pytest

import rvsim.quasistatic as qs
from rvsim.joint_model import JOINT_MODEL_SCHEMA, load_joint_model
from rvsim.parameters import RV40E, paper_run_values, with_values
from rvsim.quasistatic.torque_reversal import hysteresis as real_hysteresis
from rvsim.quasistatic.transmission import ltca as real_ltca
from tests.integration.answer_block import answer


@pytest.fixture
def engine(monkeypatch):
    """The real ``rvsim.quasistatic``; tests replace its functions through ``monkeypatch``."""
    return qs

LTCA_KEYS = {"te_mean_arcmin", "te_pp_arcmin", "max_pin_force_n", "pins_in_contact_min",
             "pins_in_contact_max", "max_contact_stress_mpa", "torsional_stiffness_nm_per_arcmin",
             "positions", "wall_s", "status"}
HYST_KEYS = {"rated_torque_nm", "torsional_rigidity_nm_per_arcmin", "lost_motion_arcmin",
             "backlash_arcmin", "hysteresis_loss_arcmin", "wall_s", "status"}


def test_ltca_json(cli):
    res = cli("ltca", "--torque", "412", "--positions", "720", "--json")
    assert res.code == 0, res.err
    data = json.loads(res.out)
    assert LTCA_KEYS <= set(data) and data["status"] == "ok" and data["positions"] == 720
    # a stress above the static limit is a result: a verdict and one warning (issue 34 item 6)
    res = cli("ltca", "--paper-run", "2", "--set", "rating.static_contact_stress=1000")
    assert res.code == 0 and "peak-to-peak" in res.out
    assert res.out.splitlines()[-1] == ("largest contact stress 1032 MPa: above the static "
                                        "limit (103 % of 1000 MPa): permanent deformation "
                                        "expected")
    assert res.err == ("rvsim: warning: largest contact stress 1032 MPa is above the static "
                       "limit 1000 MPa (rating.static_contact_stress): permanent deformation "
                       "expected\n")


def test_hysteresis_json_and_text(cli):
    res = cli("hysteresis", "--paper-run", "3", "--json")
    assert res.code == 0, res.err
    data = json.loads(res.out)
    assert HYST_KEYS <= set(data) and data["rated_torque_nm"] == 412.0
    # the command prints the engine's own figures for the run's reducer
    engine = qs.hysteresis(with_values(RV40E, paper_run_values(3))).summary()
    for key in ("torsional_rigidity_nm_per_arcmin", "lost_motion_arcmin", "backlash_arcmin",
                "hysteresis_loss_arcmin"):
        assert data[key] == pytest.approx(engine[key], rel=1e-12), key
    assert data["torsional_rigidity_nm_per_arcmin"] > 0
    assert "lost motion" in cli("hysteresis").out


def test_reports_and_export(cli, tmp_path):
    ltca_page, loop_page, joint = (tmp_path / n for n in ("l.html", "h.html", "joint.json"))
    assert cli("ltca", "--report", str(ltca_page)).code == 0
    res = cli("hysteresis", "--set", "I=0.02", "--report", str(loop_page), "--export",
              str(joint), "--json")
    assert res.code == 0, res.err
    for page in (ltca_page, loop_page):
        text = page.read_text()
        assert text.startswith("<!DOCTYPE html>") and "http" not in text.replace(
            "https://json", "")
    model = load_joint_model(joint)
    summary = json.loads(res.out)
    # each page opens with its answer (issue 34 item 2)
    rows = answer(loop_page.read_text())
    rigidity = summary["torsional_rigidity_nm_per_arcmin"]
    assert rows["torsional rigidity"] == [f"{rigidity:.4g} N*m/arcmin", "113 N*m/arcmin (P*)",
                                          f"{rigidity / 113:.2f} x the class (stiffer)"]
    assert rows["lost motion"][0] == f"{summary['lost_motion_arcmin']:.3g} arcmin"
    rows = answer(ltca_page.read_text())
    assert rows["output torque"] == ["300 N*m", "412 N*m rated", "73 % of rated"]
    assert rows["largest pin-disc contact stress (Hertz)"] == [
        "532.1 MPa", "4000 MPa static limit (rating.static_contact_stress, ISO 76 by default)",
        "below the static limit (13 % of 4000 MPa)"]
    arcmin = math.pi / 10800
    assert model["backlash_rad"] == pytest.approx(summary["backlash_arcmin"] * arcmin, rel=1e-12)
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.validate(model, JOINT_MODEL_SCHEMA)


@pytest.mark.parametrize("args, words", [
    (("ltca", "--positions", "4"), "8 to 100000"),
    (("ltca", "--positions", "1000001"), "8 to 100000"),
    (("ltca", "--torque", "nan"), "finite"),
    (("ltca", "--torque", "inf"), "finite"),
    (("ltca", "--report", "x.pdf"), ".html"),
    (("ltca", "--report", "."), "."),
    (("ltca", "--report", "no/such/dir/x.html"), "does not exist"),
    (("ltca", "--paper-run", "40"), "1 to 36"),
    (("hysteresis", "--export", "joint.txt"), ".json"),
    (("hysteresis", "--rated-torque", "-3"), "positive"),
    (("hysteresis", "--set", "I=-0.02"), "assembly"),
])
def test_errors_before_computing(cli, engine, args, words, monkeypatch):
    def boom(*a, **k):
        raise AssertionError("computed before the arguments were checked")

    monkeypatch.setattr(engine, "ltca", boom)
    monkeypatch.setattr(engine, "hysteresis", boom)
    res = cli(*args)
    assert res.code == 2 and words in res.err and res.err.count("\n") == 1, res.err


def test_report_folder_rejected(cli, tmp_path):
    folder = tmp_path / "page.html"
    folder.mkdir()
    res = cli("hysteresis", "--report", str(folder))
    assert res.code == 2 and "is a folder" in res.err


def _not_converged(real):
    """``real`` (ltca or hysteresis) whose result says its last point did not converge."""
    def call(reducer, **kwargs):
        result = real(reducer, **{**kwargs, "raise_on_failure": False})
        converged = result.converged.copy()
        converged[-1] = False
        return dataclasses.replace(result, status="not_converged", converged=converged)
    return call


def test_failed_solve_exits_1_with_status(cli, engine, tmp_path, monkeypatch):
    monkeypatch.setattr(engine, "ltca", _not_converged(real_ltca))
    monkeypatch.setattr(engine, "hysteresis", _not_converged(real_hysteresis))
    page = tmp_path / "x.html"
    res = cli("ltca", "--positions", "81", "--json", "--report", str(page))
    assert res.code == 1 and json.loads(res.out)["status"] == "not_converged"
    assert "not_converged" in res.err and not page.exists()
    res = cli("hysteresis")
    assert res.code == 1 and "status not_converged" in res.err


def test_engine_curve_without_catalogue_quantities_exits_1(cli, engine, monkeypatch):
    real = real_hysteresis

    def short(reducer, **kwargs):   # a loop that never reaches rated torque
        loop = real(reducer, **kwargs)
        loop.torque = loop.torque * (300.0 / 412.0)
        return loop

    monkeypatch.setattr(engine, "hysteresis", short)
    res = cli("hysteresis", "--json")
    assert res.code == 1 and json.loads(res.out)["status"] == "invalid_curve"
    assert "never reaches 412 N*m" in res.err


def test_hysteresis_export_and_report_are_written_together(tmp_path, cli, monkeypatch):
    """A hostile test's SIGTERM near the end left joint.json without its report."""
    import rvsim.report

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(rvsim.report, "write_hysteresis_report", interrupted)
    res = cli("hysteresis", "--export", str(tmp_path / "j.json"), "--report",
              str(tmp_path / "h.html"))
    assert res.code == 130 and res.err == "rvsim: interrupted\n"
    assert list(tmp_path.iterdir()) == []
