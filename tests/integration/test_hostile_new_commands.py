"""Hostile inputs to the commands and options added on 2026-11-28 (life, hysteresis --budget,
temperature and seals, units in --set and TOML, --response, profile --out .svg): each row is
what a hostile user typed and the words the one-line error must hold.  After the command the
working folder holds exactly what it held before (no partial file)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.conftest import run_cli

LOOP = str(Path(__file__).resolve().parents[2] / "docs" / "examples" / "hysteresis_loop.csv")
EFF = "input_speed_rpm,output_torque_nm,efficiency,temperature_c\n"
QS = 'name = "u"\ndesign = "L4"\nengine = "quasi-static"\n[factors.H]\nparameter = "H"\n'

# (command line, words the one error line must contain)
BAD_ROWS = {
    # Decimal's context overflowed converting 1e9999999 um to mm: a decimal.Overflow traceback
    "--set H=1e9999999um": (["params", "--set", "H=1e9999999um"],
                            "'errors.pin_circle_radius': '1e9999999um' is not a finite number"),
    "TOML pin_circle_radius = '1e9999999um'": (
        ["params", "--params", "{toml:[errors]\npin_circle_radius = \"1e9999999um\"\n}"],
        "'errors.pin_circle_radius': '1e9999999um' is not a finite number"),
    # tapered_factors divided by tan(0): a ZeroDivisionError traceback after the LTCA run
    "life support_contact_angle=0": (
        ["life", "--params", "RV-40E-bearings", "--set", "bearings.support_contact_angle=0"],
        "'bearings.support_contact_angle': 0 deg: ISO 281 rates tapered roller bearings with "
        "a contact angle above 0 deg"),
    # Walther's 10^(10^z) overflowed far below 40 degC: an OverflowError traceback
    "viscosity law overflows at -20 degC": (
        ["params", "--params", "RV-40E-bearings", "--set", "friction.oil_viscosity=1e9",
         "--set", "friction.oil_viscosity_100=2.1", "--set", "operating.temperature=-20"],
        "'operating.temperature': -20 degC: the viscosity law gives more than 1e+21 mm^2/s"),
    "viscosity law overflows at the cloud point": (
        ["efficiency", "--params", "RV-40E-bearings", "--set", "friction.oil_viscosity=1e6",
         "--set", "friction.oil_viscosity_100=2.1", "--set", "friction.oil_cloud_point=-270",
         "--set", "operating.temperature=-270"],
        "'operating.temperature': -270 degC: the viscosity law gives more than"),
    # a life of 1e-20 h printed as ok: the main bearings' static capacity (ISO 76) bounds the
    # external loads before any run
    "life --moment 1e12": (
        ["life", "--params", "RV-40E-bearings", "--moment", "1e12"],
        "'--moment': 1e+12 N*m: a main bearing row's equivalent load 1.667e+13 N is above its "
        "basic static load rating C0 = 2.92e+04 N (ISO 76)"),
    "life --thrust 1e12": (
        ["life", "--params", "RV-40E-bearings", "--thrust", "1e12"],
        "'--thrust': 1e+12 N: a main bearing row's equivalent load 5.7e+11 N is above its "
        "basic static load rating C0"),
    "life --radial-load 1e12 --moment 10": (
        ["life", "--params", "RV-40E-bearings", "--radial-load", "1e12", "--moment", "10"],
        "'--radial-load': 1e+12 N: a main bearing row's equivalent load"),
    # the life run at 1.2e8 rpm input ended not_converged, exit 1: refused before any run
    "life --output-speed 1e6": (
        ["life", "--params", "RV-40E-bearings", "--output-speed", "1e6"],
        "'--output-speed': 1e+06 rpm at the output is above the allowable output speed of "
        "RV-40E-bearings, 70 rpm (rating.allowable_output_speed, 100 % duty)"),
    "life --output-speed 70.5": (
        ["life", "--params", "RV-40E-bearings", "--output-speed", "70.5"],
        "'--output-speed': 70.5 rpm at the output is above the allowable output speed"),
    "rated output speed above the allowable": (
        ["life", "--params", "RV-40E-bearings", "--set", "rating.rated_output_speed=80"],
        "'rating.allowable_output_speed': must be at least the rated output speed 80 rpm"),
    # 1000-5000 degC were accepted where the oil's two points keep the law above 2 mm^2/s
    "operating.temperature=1000": (
        ["efficiency", "--params", "RV-40E-bearings", "--set", "operating.temperature=1000"],
        "'operating.temperature': 1000 degC is above the lubricant's highest temperature "
        "friction.oil_max_temperature = 150 degC (mineral base oils degrade from 110-150 degC)"),
    "operating.temperature=5000 (simulate)": (
        ["simulate", "--params", "RV-40E-bearings", "--set", "operating.temperature=5000"],
        "'operating.temperature': 5000 degC is above the lubricant's highest temperature"),
    "oil_max_temperature below the cloud point": (
        ["params", "--params", "RV-40E-bearings", "--set", "friction.oil_max_temperature=-30"],
        "'friction.oil_max_temperature': -30 degC must be above the cloud point"),
    # a 1 km input seal gave an efficiency of 1e-8 as ok: each seal is bounded by its part
    "1 km input seal": (
        ["efficiency", "--set", "friction.input_seal_count=1", "--set",
         "friction.input_seal_diameter=1e6"],
        "'friction.input_seal_diameter': 1e+06 mm is larger than the discs' central bore the "
        "input shaft passes through, 2 cycloid.disc_bore_radius (40 mm)"),
    "output seal beyond the pin ring": (
        ["simulate", "--set", "friction.output_seal_count=2", "--set",
         "friction.output_seal_diameter=171mm"],
        "'friction.output_seal_diameter': 171 mm is larger than the pin ring's outer diameter, "
        "2 (cycloid.pin_circle_radius + cycloid.pin_radius) (170 mm)"),
    "cycloid-drive input seal beyond its bore": (
        ["params", "--params", "cycloid-drive", "--set", "friction.input_seal_count=1",
         "--set", "friction.input_seal_diameter=37"],
        "'friction.input_seal_diameter': 37 mm is larger than the discs' central bore"),
    # the repeated-level rule compared the texts: "0um" and "0mm" ran as two levels of H
    "levels ['0um', '0mm']": (
        ["study", "{toml:" + QS + 'levels = ["0um", "0mm"]\n}', "--out", "o"],
        "'factors.H.levels': level '0mm' is given twice (as '0um')"),
    "levels [0.02, '20 um']": (
        ["study", "{toml:" + QS + 'levels = [0.02, "20 um"]\n}', "--out", "o"],
        "'factors.H.levels': level '20 um' is given twice (as 0.02)"),
    # fourth session's hostile test (hostile5) of calibrate --loop/--efficiency and [stiffness]
    # the file's 200 degC was refused as 'operating.temperature', which the user never set
    "--efficiency temperature_c 200": (
        ["calibrate", "--efficiency", "{csv:" + EFF + "500,100,0.9,200\n3000,400,0.9,40\n}",
         "--params", "RV-40E-bearings", "--fit", "contact.friction_coefficient", "--out", "f"],
        "in.csv: temperature_c: data row 1: 200 degC is above the lubricant's "
        "highest temperature"),
    # refused as 'speeds' (no such option of calibrate)
    "--efficiency input_speed_rpm 1e9": (
        ["calibrate", "--efficiency", "{csv:" + EFF + "1e9,100,0.9,40\n3000,400,0.9,40\n}",
         "--params", "RV-40E-bearings", "--fit", "contact.friction_coefficient", "--out", "f"],
        "in.csv: input_speed_rpm: data row 1 (1e+09) is above the model's "
        "100000 rpm"),
    # status ok: 1.606 mm, 95 % interval 0 .. 113 409 mm, RMS unchanged
    "--fit flexibility.fe_element_size": (
        ["calibrate", "--loop", LOOP, "--fit", "flexibility.fe_element_size", "--out", "f"],
        "'flexibility.fe_element_size': cannot be fitted (an element size of the "
        "finite-element mesh: the model's resolution"),
    # status model_fails, exit 1, after the fit's first step
    "--fit stiffness.input_coupling on an RV reducer": (
        ["calibrate", "--loop", LOOP, "--fit", "stiffness.input_coupling", "--out", "f"],
        "'stiffness.input_coupling': cannot be fitted: this model has no such element"),
    # the same data twice: status ok, every interval narrower by sqrt(2)
    "--loop twice": (["calibrate", "--loop", LOOP, "--loop", LOOP, "--fit", "stiffness.pins",
                      "--out", "f"], "'--loop': " + LOOP + ": given twice"),
    "--loop a folder": (["calibrate", "--loop", ".", "--fit", "stiffness.pins", "--out", "f"],
                        ": is a folder, not a table"),
    # 'params' printed a set every other command refuses
    "params allowable speed 1 rad/s": (
        ["params", "--set", "rating.allowable_output_speed=1rad/s"],
        "'rating.allowable_output_speed': must be at least the rated output speed 15 rpm "
        "(got 9.5493)"),
}


def _listing(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def _expand(args: list[str], folder: Path) -> list[str]:
    out = []
    for arg in args:
        for kind in ("toml", "csv"):
            if arg.startswith("{" + kind + ":") and arg.endswith("}"):
                path = folder / f"in.{kind}"
                path.write_text(arg[len(kind) + 2:-1])
                arg = str(path)
        out.append(arg)
    return out


@pytest.mark.parametrize("key", list(BAD_ROWS))
def test_bad_input_is_one_line_exit_2_no_file(key, tmp_path, monkeypatch):
    args, words = BAD_ROWS[key]
    monkeypatch.chdir(tmp_path)
    args = _expand(args, tmp_path)
    before = _listing(tmp_path)
    res = run_cli(*args)
    assert res.code == 2, (res.out, res.err)
    assert res.err.count("\n") == 1 and res.err.startswith("rvsim: error: "), res.err
    assert words in res.err, res.err
    assert "Traceback" not in res.err and res.out == ""
    assert _listing(tmp_path) == before


def test_tapered_factors_refuse_a_zero_contact_angle():
    """ISO 281 Table 8 gives X, Y of tapered roller bearings for alpha != 0 only (Y = 0.4
    cot(alpha) is infinite at 0); the smallest positive angle still gives finite factors."""
    import math

    from rvsim.errors import ParameterError
    from rvsim.physics.rating_life import tapered_factors

    with pytest.raises(ParameterError, match="support_contact_angle"):
        tapered_factors(0.0, "bearings.support_contact_angle")
    e, x, y = tapered_factors(math.radians(15.0))
    assert (e, x, y) == (1.5 * math.tan(math.radians(15.0)), 0.4,
                         0.4 / math.tan(math.radians(15.0)))


def test_viscosity_law_within_the_ceiling_is_unchanged():
    """The ceiling only refuses what the law cannot give: the RV-40E-bearings oil (ISO VG 100
    estimate) at 0 degC keeps its viscosity, the ASTM D341 line's own value."""
    import dataclasses

    from rvsim.friction import lubricant_viscosity
    from rvsim.parameters import BUILT_IN_SETS
    from rvsim.physics.losses import walther_viscosity

    r = BUILT_IN_SETS["RV-40E-bearings"]
    r = dataclasses.replace(r, operating=dataclasses.replace(r.operating, temperature=0.0))
    f = r.friction
    assert lubricant_viscosity(r) == walther_viscosity(0.0, f.oil_viscosity,
                                                       f.oil_viscosity_100)


def test_report_of_a_constant_response(tmp_path):
    """``rvsim study --response te_window_revolutions`` (1.0 in every quasi-static run) wrote
    analysis.json with "order": null (the analysis's "constant response") and then refused
    its own folder ("'order' missing or malformed; run 'rvsim study' again", exit 2, after
    every run had finished).  The page says the order is none."""
    import json

    import pandas as pd

    from rvsim.doe.outputs import write_study_outputs

    folder = tmp_path / "study"
    folder.mkdir()
    table = pd.DataFrame({"run": [1, 2, 3, 4], "H": [1, 1, 2, 2], "I": [1, 2, 1, 2],
                          "te_mean_arcmin": [0.45, 2.23, 0.61, 1.9],
                          "te_window_revolutions": [1.0] * 4,
                          "status": ["ok"] * 4, "error": [""] * 4, "key": list("abcd")})
    analysis = write_study_outputs(folder, table, ["H", "I"],
                                   response="te_window_revolutions")
    assert analysis["order"] is None and analysis["constant_response"] is True
    definition = {"name": "qs", "design": "L4", "samples": None, "seed": 0,
                  "time_step": 1e-5, "reducer": "RV-40E", "steady_start": 3.0,
                  "factors": [{"label": f, "parameter": p, "levels": [0.0, 0.02],
                               "low": None, "high": None}
                              for f, p in (("H", "errors.pin_circle_radius"),
                                           ("I", "errors.equidistant_modification"))],
                  "fixed": []}
    (folder / "study.json").write_text(json.dumps(definition))
    res = run_cli("report", str(folder))
    assert res.code == 0 and res.err == "", res.err
    page = (folder / "report.html").read_text()
    assert "none (the response is constant)" in page


def test_budget_of_a_paper_run_converges_at_the_default_factor():
    """``hysteresis --paper-run 2 --budget`` ended not_converged (arm bearings stiffened),
    exit 1, like 35 of the 36 paper runs at 1e4 x: the first point past zero torque crosses
    the clearance, and 200 Newton iterations were not enough against a stiffened contact.
    That point is now solved by continuation in the factor (the model's own laws, then a
    decade at a time): 36 of 36 converge, with the shares of a direct solve given 3000
    iterations (to 2e-12; docs/decisions.md, issue 30/32 fourth session)."""
    import json

    res = run_cli("hysteresis", "--paper-run", "2", "--budget", "--json")
    assert res.code == 0 and res.err == "", res.err
    budget = json.loads(res.out)["budget"]
    assert budget["status"] == "ok" and budget["factor"] == 1e4
    shares = {row["element"]: row["share"] for row in budget["elements"]}
    assert shares == pytest.approx({"pins": 0.45017, "arm_bearings": 0.27617,
                                    "support_bearings": 0.26966, "gear_mesh": 0.00540},
                                   abs=1e-5)
    assert budget["rigidity_nm_per_arcmin"] == pytest.approx(639.206, abs=1e-3)


def test_input_speeds_above_the_allowable_output_speed_warn():
    """efficiency / grid --speeds are input speeds: divided by the ratio (121) and held to
    rating.allowable_output_speed (70 rpm): one warning above it, nothing within it; life()
    refuses the same speed (no run)."""
    import math

    from rvsim.cli._common import check_input_speeds, flush_warnings, _WARNINGS
    from rvsim.errors import ParameterError
    from rvsim.parameters import BUILT_IN_SETS, RV40E
    from rvsim.quasistatic import life

    flush_warnings(show=False)
    check_input_speeds(RV40E, [500.0, 8470.0], "--speeds")       # 70.0 rpm: within
    assert _WARNINGS == []
    check_input_speeds(RV40E, [500.0, 9000.0], "--speeds")
    assert _WARNINGS == ["rvsim: warning: --speeds (9000 rpm at the input, ratio 121): 74.38 "
                         "rpm at the output is above the allowable output speed of RV-40E, 70 "
                         "rpm (rating.allowable_output_speed, 100 % duty)"]
    flush_warnings(show=False)
    with pytest.raises(ParameterError, match="70.01 rpm at the output") as info:
        life(BUILT_IN_SETS["RV-40E-bearings"], output_speed=70.01 * 2 * math.pi / 60)
    assert info.value.field == "output_speed"


def test_main_bearing_static_rating_bounds_the_external_loads():
    """ISO 76: C0 = f0 Z Dw^2 cos(alpha) with f0 interpolated at Dw cos(alpha) / Dpw; the
    RV-40E-bearings main bearing (30 balls of 9 mm on 140 mm, 40 deg): gamma = 0.04925,
    f0 = 15.5 + 0.925 x 0.2 = 15.685, C0 = 29.2 kN.  life() refuses a moment whose row load
    exceeds it (1800 N*m: 30.0 kN) before the LTCA run, names the API's field, and runs at
    1600 N*m (row 26.7 kN)."""
    import math

    from rvsim.errors import ParameterError
    from rvsim.parameters import BUILT_IN_SETS
    from rvsim.physics.rating_life import ball_static_rating
    from rvsim.quasistatic.bearing_life import check_static_capacity

    a = math.radians(40.0)
    gamma = 9.0 * math.cos(a) / 140.0
    f0 = 15.5 + (gamma - 0.04) / 0.01 * 0.2
    assert ball_static_rating(30, 9e-3, 0.14, a) == pytest.approx(
        f0 * 30 * 81.0 * math.cos(a), rel=1e-12)
    r = BUILT_IN_SETS["RV-40E-bearings"]
    check_static_capacity(r, 0.0, 1600.0, 0.0)
    with pytest.raises(ParameterError, match="1800 N.m: a main bearing row's equivalent load "
                       "3e\\+04 N") as info:
        check_static_capacity(r, 0.0, 1800.0, 0.0)
    assert info.value.field == "moment"


def test_a_singular_stiffness_is_a_status(tmp_path, monkeypatch):
    """``hysteresis --set stiffness.pins=1e8`` (and ltca, efficiency, life) ended in numba's
    LinAlgError traceback: the condensed stiffness of stiffnesses 1e8 apart cannot be
    inverted in double precision.  It is the point's status, singular_stiffness (the compliance
    budget's word), exit 1, one line, no file."""
    monkeypatch.chdir(tmp_path)
    res = run_cli("hysteresis", "--set", "stiffness.pins=1e8", "--csv", "loop.csv")
    assert res.code == 1 and res.out == ""
    assert res.err == "rvsim: hysteresis failed: status singular_stiffness\n"
    assert _listing(tmp_path) == []


def test_analyze_table_refuses_what_is_not_a_table():
    """``rvsim.analyze_table("results.csv")`` (or a Study) was an AttributeError."""
    import rvsim
    from rvsim.errors import ParameterError

    with pytest.raises(ParameterError, match="'table': a pandas DataFrame .* got str"):
        rvsim.analyze_table("results.csv")


def test_plot_of_a_failed_loop_names_its_status():
    """``.plot()`` of a failed torque reversal raised the curve reader's "curve 'branch': the
    curve has no increasing branch"; it names the test's status."""
    import numpy as np

    from rvsim.errors import SimulationError
    from rvsim.quasistatic.torque_reversal import HysteresisResult

    failed = HysteresisResult(torque=np.zeros(3), angle=np.full(3, np.nan),
                              branch=np.ones(3), rated_torque=412.0,
                              status="singular_stiffness", wall_s=0.0,
                              converged=np.zeros(3, bool), torsional_stiffness=np.zeros(3))
    with pytest.raises(SimulationError, match=r"ended singular_stiffness \(0 of 3 points"):
        failed.plot()
