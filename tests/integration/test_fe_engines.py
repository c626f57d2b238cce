"""flexibility.model = fe in both engines and the CLI (coarse meshes: the tests stay fast)."""

from __future__ import annotations

import json

import pytest

from tests.conftest import HAS_FE, NO_FE

if not HAS_FE:
    pytest.skip(NO_FE, allow_module_level=True)

# the disc's figures: the finite-element crank (on by default with model = fe) left out
COARSE = ("--set", "flexibility.fe_element_size=4", "--set",
          "flexibility.fe_segments_per_tooth=2", "--set", "flexibility.fe_crank=false")
SHORT = ("--set", "operating.duration=0.3", "--set", "operating.speed_ramp_time=0.1",
         "--set", "operating.load_start=0.1", "--set", "operating.load_ramp_end=0.2",
         "--set", "operating.steady_start=0.2")


def _ltca(cli, *extra):
    result = cli("ltca", "--positions", "81", "--torque", "412", "--json", "--set", "A=1",
                 *extra)
    assert result.code == 0, result.err
    return json.loads(result.out)


def test_ltca_with_the_fe_disc_is_softer_than_the_tooth_model(cli):
    closed = _ltca(cli)
    fe = _ltca(cli, "--set", "flexibility.model=fe", *COARSE)
    assert fe["status"] == "ok"
    # the web and the coupling add compliance (measured with the default mesh at the rated
    # 412 N*m, 360 positions: stiffness 213.6 -> 208.1 N*m/arcmin, TE mean 2.143 -> 2.194
    # arcmin)
    assert fe["torsional_stiffness_nm_per_arcmin"] < closed["torsional_stiffness_nm_per_arcmin"]
    assert fe["te_mean_arcmin"] > closed["te_mean_arcmin"]
    assert fe["te_mean_arcmin"] < 1.1 * closed["te_mean_arcmin"]


def test_switch_a_off_leaves_the_model_unchanged(cli):
    rigid = cli("ltca", "--positions", "81", "--json")
    fe = cli("ltca", "--positions", "81", "--json", "--set", "flexibility.model=fe", *COARSE,
             "--set", "flexibility.fe_carrier=false")
    drop = ("wall_s",)
    a, b = json.loads(rigid.out), json.loads(fe.out)
    assert {k: v for k, v in a.items() if k not in drop} == \
        {k: v for k, v in b.items() if k not in drop}


def test_simulate_with_the_fe_disc(cli):
    closed = cli("simulate", "--json", "--set", "A=1", *SHORT)
    fe = cli("simulate", "--json", "--set", "A=1", "--set", "flexibility.model=fe", *COARSE,
             *SHORT)
    assert fe.code == 0, fe.err
    a, b = json.loads(closed.out), json.loads(fe.out)
    assert b["status"] == "ok"
    assert b["te_mean_arcmin"] > a["te_mean_arcmin"]


def test_bad_model_name_is_one_line(cli):
    result = cli("ltca", "--set", "flexibility.model=ansys")
    assert result.code == 2
    assert result.err == ("rvsim: error: parameter 'flexibility.model': 'ansys' is not one "
                          "of closed-form, fe\n")


def test_pin_friction_with_the_fe_disc(cli):
    """Pin friction with the FE disc (refused before 2026-11-25; the physics is checked in
    tests/verification/test_friction.py): both engines run it."""
    friction = ("--set", "contact.friction_coefficient=0.05", "--set",
                "flexibility.fe_carrier=false", *COARSE)
    summary = _ltca(cli, "--set", "flexibility.model=fe", *friction)
    assert summary["status"] == "ok"
    result = cli("simulate", "--json", "--set", "A=1", "--set", "flexibility.model=fe",
                 *friction, *SHORT)
    assert result.code == 0, result.err
    assert json.loads(result.out)["status"] == "ok"


def test_the_fe_carrier_softens_every_command(cli):
    """flexibility.fe_carrier (default on with model = fe): the support bushings bear on
    finite-element plates, in the quasi-static and the dynamic engine."""
    rigid = cli("ltca", "--positions", "81", "--json", "--set", "flexibility.model=fe",
                *COARSE, "--set", "flexibility.fe_carrier=false")
    plate = cli("ltca", "--positions", "81", "--json", "--set", "flexibility.model=fe", *COARSE)
    a, b = json.loads(rigid.out), json.loads(plate.out)
    assert b["status"] == "ok"
    # the plates add 1.7e-8 rad/(N*m) (docs/validation.md): stiffness -6 %, mean TE +4 %
    assert b["torsional_stiffness_nm_per_arcmin"] == pytest.approx(
        0.94 * a["torsional_stiffness_nm_per_arcmin"], rel=0.01)
    assert b["te_mean_arcmin"] == pytest.approx(1.04 * a["te_mean_arcmin"], rel=0.01)
    loop = cli("hysteresis", "--json", "--set", "flexibility.model=fe", *COARSE)
    assert loop.code == 0, loop.err
    dynamic = cli("simulate", "--json", "--set", "flexibility.model=fe", *COARSE, *SHORT)
    assert dynamic.code == 0, dynamic.err
    assert json.loads(dynamic.out)["status"] == "ok"


def test_fe_carrier_with_roller_supports_is_refused(cli):
    result = cli("ltca", "--set", "flexibility.model=fe", "--set",
                 "bearings.support_rollers=true", *COARSE)
    assert result.code == 2
    assert result.err.startswith("rvsim: error: parameter 'flexibility.fe_carrier': ")
    assert result.err.count("\n") == 1
    ok = cli("ltca", "--positions", "81", "--json", "--set", "flexibility.model=fe", "--set",
             "bearings.support_rollers=true", "--set", "flexibility.fe_carrier=false", *COARSE)
    assert ok.code == 0, ok.err


def test_bad_fe_carrier_value_is_one_line(cli):
    result = cli("ltca", "--set", "flexibility.fe_carrier=maybe")
    assert result.code == 2
    assert result.err == ("rvsim: error: parameter 'flexibility.fe_carrier': 'maybe' is not a "
                          "yes/no value (use true or false)\n")


@pytest.mark.parametrize("setting, field, bounds", [
    ("flexibility.fe_crank_element_size=30", "flexibility.fe_crank_element_size",
     "between 1.25 and 10 mm"),
    ("flexibility.fe_crank_element_size=1e-6", "flexibility.fe_crank_element_size",
     "between 1.25 and 10 mm"),
    ("flexibility.fe_element_size=0.01", "flexibility.fe_element_size",
     "between 0.375 and 12 mm"),
    ("flexibility.fe_element_size=50", "flexibility.fe_element_size",
     "between 0.375 and 12 mm"),
])
def test_element_sizes_out_of_range_are_refused_before_meshing(cli, tmp_path, setting, field,
                                                               bounds, fresh_fe_cache):
    """A 30 mm crank mesh made scikit-fem raise, a 1 um one ran for hours: both one line, and
    before any body is meshed (a bad disc size used to be refused after the 3-D crank was
    meshed: 24 s with an empty cache)."""
    result = cli("ltca", "--set", "flexibility.model=fe", "--set", setting)
    assert result.code == 2
    assert result.err.startswith(f"rvsim: error: parameter '{field}': must lie {bounds}")
    assert result.err.count("\n") == 1
    assert not any(tmp_path.rglob("*.npz"))        # the fresh cache: nothing was meshed


def test_a_study_level_or_a_set_value_of_an_inadmissible_size_is_refused_at_once(cli, tmp_path,
                                                                                 fresh_fe_cache):
    """The sizes are part of the parameters' validation: a study refuses the run whose level
    is inadmissible before anything runs, and `rvsim params` does not print such a set (a
    hostile test found the study meshing, then storing the runs as failed)."""
    study = tmp_path / "fe_sizes.toml"
    study.write_text('name = "sizes"\ndesign = "L4"\nengine = "quasi-static"\n[set]\n'
                     '"flexibility.model" = "fe"\n"flexibility.cycloid_disc" = true\n'
                     '[factors.H]\nparameter = "H"\nlevels = [0.0, 0.01]\n'
                     '[factors.S]\nparameter = "flexibility.fe_element_size"\n'
                     'levels = [1.6, 50]\n')
    res = cli("study", str(study), "--out", str(tmp_path / "out"), "--no-progress")
    assert res.code == 2 and res.err.count("\n") == 1, res.err
    assert "'flexibility.fe_element_size': must lie between 0.375 and 12 mm" in res.err
    assert "(study run 2)" in res.err
    assert not (tmp_path / "out").exists() and not any(tmp_path.rglob("*.npz"))
    res = cli("params", "--toml", "--set", "flexibility.model=fe", "--set",
              "flexibility.fe_element_size=50")
    assert res.code == 2 and res.out == "" and "flexibility.fe_element_size" in res.err
    # a size the model does not mesh stays free
    res = cli("params", "--toml", "--set", "flexibility.fe_element_size=50")
    assert res.code == 0, res.err


def test_the_fe_crank_refuses_needle_bearings(cli):
    result = cli("ltca", "--params", "RV-40E-bearings", "--set", "flexibility.model=fe")
    assert result.code == 2
    assert result.err.count("\n") == 1 and "flexibility.fe_crank" in result.err


def test_bad_crank_element_size_is_one_line(cli):
    result = cli("ltca", "--set", "flexibility.fe_crank_element_size=0")
    assert result.code == 2
    assert result.err.startswith("rvsim: error: parameter 'flexibility.fe_crank_element_size'")
    assert result.err.count("\n") == 1
