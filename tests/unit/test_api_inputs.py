"""The Python API given what a user might pass it (a hostile review of the tenth session):
rvsim's own errors naming the field, never a silent number or a bare TypeError."""

import dataclasses

import numpy as np
import pytest

from rvsim import RV40E, with_values
from rvsim.analysis import analyze_table, catalogue
from rvsim.doe import Study, StudyFactor
from rvsim.doe.runner import evaluate
from rvsim.errors import ParameterError
from rvsim.geometry import pin_gaps
from rvsim.parameters import paper_l36_scheme, validate
from rvsim.quasistatic import solve_path


def _replaced(group: str, **values):
    return dataclasses.replace(RV40E, **{group: dataclasses.replace(getattr(RV40E, group),
                                                                   **values)})


@pytest.mark.parametrize("reducer, words", [
    # "no" for a flag ran the flexible disc (truthy): TE 0.55877 where rigid gives 0.55365
    (_replaced("flexibility", cycloid_disc="no"),
     "parameter 'flexibility.cycloid_disc': must be true or false (got 'no')"),
    (_replaced("cycloid", eccentricity="1.5e-3"),
     "parameter 'cycloid.eccentricity': must be a number (got '1.5e-3')"),
    (_replaced("cycloid", eccentricity=None), "must be a number (got None)"),
    (_replaced("cycloid", disc_teeth=39.0, pin_count=40.0), "must be a whole number (got 39.0)"),
    (dataclasses.replace(RV40E, gears=None), "parameter 'gears.module': missing"),
    (None, "parameter 'reducer': must be a parameter set"),
])
def test_a_reducer_built_in_python_is_checked_for_types(reducer, words):
    with pytest.raises(ParameterError) as info:
        validate(reducer)
    assert words in str(info.value)


def test_numpy_numbers_are_numbers():
    validate(_replaced("cycloid", eccentricity=np.float64(RV40E.cycloid.eccentricity)))


def test_array_lengths_and_disc_indices_are_checked():
    # a shorter torque array was read past its end and reported "ok"
    with pytest.raises(ParameterError, match=r"one torque per input angle.*\(3,\) and \(5,\)"):
        solve_path(RV40E, np.linspace(0.0, 1.0, 5), np.full(3, 300.0))
    # disc=2 placed a disc where none is: a 40 mm "overlap"
    with pytest.raises(ParameterError, match="'disc': must be 0 or 1"):
        pin_gaps(RV40E, 0.0, disc=2)


def test_a_study_built_in_python_is_checked_as_a_file_is():
    alias = (StudyFactor("H", "H", (0.0, 0.01, 0.02)),
             StudyFactor("P", "errors.pin_circle_radius", (0.03, 0.04, 0.05)))
    with pytest.raises(ParameterError, match="sets errors.pin_circle_radius, which factor H"):
        Study(name="x", design="L9", factors=alias)
    one = (StudyFactor("H", "H", (0.0, 0.01)),)
    with pytest.raises(ParameterError, match="is also varied by factor H"):
        Study(name="x", design="L4", factors=one, fixed=(("errors.pin_circle_radius", 0.05),))
    with pytest.raises(ParameterError, match="'engine': must be one of dynamic, quasi-static"):
        Study(name="x", design="L4", factors=one, engine="quasi_static")
    with pytest.raises(ParameterError, match="'hysteresis'"):
        Study(name="x", design="L4", factors=one, hysteresis=True)
    outcome = evaluate(RV40E, 2e-5, engine="quasistatic")    # ran a dynamic simulation
    assert outcome["status"] == "error" and "unknown engine 'quasistatic'" in outcome["error"]


@pytest.mark.parametrize("alpha", [5, float("nan"), -1, "0.1", True])
def test_alpha_is_a_probability(alpha):
    # alpha = 5 (a percent typed as a number) made all 15 factors significant
    with pytest.raises(ParameterError, match="'alpha': must be a number between 0 and 1"):
        analyze_table(paper_l36_scheme().drop(columns=["note"]), "te_arcmin", alpha=alpha)


def test_catalogue_fractions_and_rated_torques_are_checked():
    torque = np.r_[np.linspace(-1, 1, 5), np.linspace(1, -1, 5)] * 412.0
    angle = torque * 1e-6
    branch = np.r_[np.ones(5), -np.ones(5)]
    for fraction in (float("nan"), -0.03, 1.5):
        with pytest.raises(catalogue.CurveError, match="fraction"):
            catalogue.lost_motion(torque, angle, branch, 412.0, fraction=fraction)
    with pytest.raises(catalogue.CurveError, match="rated"):
        catalogue.torsional_rigidity(torque, angle, True)


def test_a_run_stopped_before_its_window_has_no_numbers():
    from rvsim.dynamics import simulate

    stopped = simulate(with_values(RV40E, {"operating.duration": 1.6}), time_step=1e-4,
                       raise_on_failure=False)
    assert stopped.status != "ok"
    assert np.isnan(stopped.metrics["energy_residual"])      # it read a perfect 0.0
    assert np.isnan(stopped.metrics["max_pin_force_n"])      # and 0.0 N


def test_a_tolerance_built_in_python_is_checked_as_a_file_is():
    from rvsim.tolerance import Tolerance

    # a misspelled distribution was drawn as normal, a NaN tolerance drew NaN parts, and
    # a letter alias failed later with a bare KeyError
    with pytest.raises(ParameterError, match="unknown distribution 'normall'"):
        Tolerance("pin_radius", 0.005, distribution="normall")
    with pytest.raises(ParameterError, match="'per'|\\.per'"):
        Tolerance("pin_radius", 0.005, per="features")
    with pytest.raises(ParameterError, match="needs a finite number"):
        Tolerance("pin_radius", float("nan"))
    with pytest.raises(ParameterError, match="unknown error"):
        Tolerance("nope", 0.005)
    assert Tolerance("H", 0.005).name == "errors.pin_circle_radius"


def test_a_finite_element_disc_on_the_single_stage_drive_is_refused_at_once():
    # it passed validation and failed at the first run: a study ran its other runs first
    from rvsim.parameters import BUILT_IN_SETS

    with pytest.raises(ParameterError, match="built for the RV reducer only so far"):
        with_values(BUILT_IN_SETS["cycloid-drive"], {"A": 1, "flexibility.model": "fe"})


def _bearings():
    from rvsim.parameters import BUILT_IN_SETS

    return BUILT_IN_SETS["RV-40E-bearings"]


def _l36_tolerances():
    from rvsim.tolerance.spec import rv40e_tolerances

    return rv40e_tolerances()


SET = "must be a parameter set (rvsim.parameters.Reducer: rvsim.RV40E"


# a notebook user's wrong arguments (issue 30, fifth session): each was an AttributeError or a
# numpy ValueError from inside rvsim, or a run asked numpy for 7.45 GiB
@pytest.mark.parametrize("call, field, words", [
    ("rvsim.ltca('RV-40E')", "reducer", SET),
    ("rvsim.hysteresis('RV-40E')", "reducer", SET),
    ("rvsim.life('RV-40E')", "reducer", SET),
    ("rvsim.compliance_budget('RV-40E')", "reducer", SET),
    ("rvsim.with_values('RV-40E', {'H': 0.02})", "reducer", SET),
    ("rvsim.with_values(RV40E, [('H', 0.02)])", "values",
     "must be a dict of parameter names (or factor letters) to values in user units"),
    ("rvsim.hysteresis(RV40E, torques='abc')", "torques", "must be numbers [N*m] (got 'abc')"),
    ("rvsim.ltca(RV40E, positions=10 ** 9)", "positions",
     "must be at most 100000, the most the command line takes (got 1000000000)"),
    ("rvsim.life(_bearings(), positions=10 ** 9)", "positions", "must be at most 100000"),
    ("rvsim.calibrate([], RV40E, ['stiffness.pins'], loops=['loop.csv'])", "loops",
     "must be a list of loop curves (rvsim.testrig.curves.read_loop(path)) (got str)"),
    ("rvsim.calibrate([], RV40E, ['stiffness.pins'], efficiency='points.csv')", "efficiency",
     "must be efficiency points (rvsim.testrig.curves.read_efficiency(path)) or None"),
    ("rvsim.calibrate('bench', RV40E, ['stiffness.pins'])", "points",
     "must be a list of analysed recordings (rvsim.analyse_path) (got str)"),
    ("rvsim.calibrate([], RV40E, ['stiffness.pins'], max_evaluations=-1)", "max_evaluations",
     "must be a whole number >= 1 (got -1)"),
    ("rvsim.calibrate([], RV40E, 'stiffness.pinz')", "stiffness.pinz", "unknown parameter"),
    ("rvsim.tolerance_analysis('rv40e-tolerances', OUT)", "study",
     "must be a tolerance study (rvsim.load_tolerance_study(path), "
     "rvsim.BUILT_IN_TOLERANCE_STUDIES[name]()) (got str)"),
    ("rvsim.allocate('rv40e-tolerances', 'ate_p95=0.3', OUT)", "study",
     "must be a tolerance study"),
    ("rvsim.allocate(_l36_tolerances(), {'ate_p95': 0.3}, OUT)", "targets",
     "must be a list of targets (parse_targets(\"ate_p95=0.3\"), or that text) (got dict)"),
    ("rvsim.run_study('paper-l36', OUT)", "study",
     "must be a study (rvsim.load_study(path), rvsim.BUILT_IN_STUDIES[name]()) (got str)"),
    ("rvsim.analyse_path('docs/examples/testrig', 'RV-40E')", "reducer", SET),
    ("rvsim.analyse_path('docs/examples/testrig', RV40E, positions=3)", "positions",
     "must be 64 to 65536 (got 3)"),
    ("rvsim.read_recording('docs/examples/testrig/reversal.csv', 'x')", "column_map",
     "must be a ColumnMap"),
    ("rvsim.load_toml(None)", "path", "must be the path of a TOML file (got NoneType)"),
    ("rvsim.hysteresis(RV40E, stiffen='pins')", "stiffen",
     "must be a dict of element names to factors"),
    ("rvsim.hysteresis(RV40E, points_per_branch=10 ** 8)", "points_per_branch",
     "must be an integer from 2 to 19999, a test of at most 100000 points (got 100000000)"),
    ("rvsim.compliance_budget(RV40E, points_per_branch=10 ** 7)", "points_per_branch",
     "must be an integer from 2 to 19999"),
    ("rvsim.efficiency(RV40E, speeds_rpm=[500], torques=[412], positions=10 ** 9)",
     "positions", "must be an integer from 2 to 100000 (got 1000000000)"),
])
def test_a_notebook_users_wrong_arguments_are_named(call, field, words, tmp_path):
    import rvsim

    with pytest.raises(ParameterError) as info:
        eval(call, {"rvsim": rvsim, "RV40E": RV40E, "_bearings": _bearings,
                    "_l36_tolerances": _l36_tolerances, "OUT": str(tmp_path / "out")})
    assert info.value.field == field and words in info.value.reason
    assert not (tmp_path / "out").exists()
