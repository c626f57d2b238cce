"""``engine = "quasi-static"`` in a study file (issue 9, item 4), on the real engine."""

import textwrap

import pytest

import rvsim.quasistatic as qs
from rvsim.doe import load_study, run
from rvsim.doe.engines import evaluate_quasi_static
from rvsim.errors import InputFileError, ParameterError, SimulationError
from rvsim.parameters import RV40E, with_values

STUDY = """
name = "qs"
design = "L9"
{extra}
[factors.H]
parameter = "H"
levels = [0.0, 0.01, 0.02]
[factors.I]
parameter = "I"
levels = [0.0, 0.01, 0.02]
"""


def _study(tmp_path, extra):
    path = tmp_path / "qs.toml"
    path.write_text(textwrap.dedent(STUDY.format(extra=extra)))
    return path


def test_quasi_static_study_runs_with_catalogue_responses(tmp_path):
    study = load_study(_study(tmp_path, 'engine = "quasi-static"\nhysteresis = true'))
    assert (study.engine, study.hysteresis) == ("quasi-static", True)
    results = run(study, tmp_path / "out", workers=1, progress=False)
    assert (results["status"] == "ok").all() and len(results) == 9
    for column in ("te_mean_arcmin", "te_pp_arcmin", "max_pin_force_n",
                   "torsional_rigidity_nm_per_arcmin", "lost_motion_arcmin", "backlash_arcmin"):
        assert results[column].notna().all(), column
    # the backlash grows with the clearance-opening errors H (pin circle) and I (equidistant
    # modification): the design sees it
    by_level = results.groupby("H")["backlash_arcmin"].mean()
    assert by_level.is_monotonic_increasing and by_level.iloc[-1] > by_level.iloc[0]
    # with and without the hysteresis test, the rows of one reducer are different store
    # entries (a folder holds one study definition: the second goes to its own folder)
    again = run(load_study(_study(tmp_path, 'engine = "quasi-static"')), tmp_path / "out2",
                workers=1, progress=False)
    assert "backlash_arcmin" not in again.columns or again["backlash_arcmin"].isna().all()
    assert set(again["key"]).isdisjoint(results["key"])


@pytest.mark.parametrize("extra, words", [
    ('engine = "static"', "engine must be one of"),
    ('hysteresis = true', "needs engine"),
    ('engine = "quasi-static"\nhysteresis = "yes"', "true or false"),
])
def test_engine_key_errors(tmp_path, extra, words):
    with pytest.raises(InputFileError, match=words):
        load_study(_study(tmp_path, extra))


def test_outcome_shape_and_failures(monkeypatch):
    outcome = evaluate_quasi_static(RV40E)
    assert outcome["status"] == "ok" and "error" not in outcome and outcome["wall_s"] >= 0
    assert outcome["metrics"]["positions"] == 360 and "status" not in outcome["metrics"]

    def stopped(*args, **kwargs):
        raise SimulationError("not_converged", "quasi-static analysis stopped at position 3 "
                              "of 360: not converged")

    monkeypatch.setattr(qs, "ltca", stopped)
    failed = evaluate_quasi_static(RV40E)
    assert failed["status"] == "not_converged" and "not converged" in failed["error"]
    monkeypatch.undo()

    def broken(*args, **kwargs):
        raise RuntimeError("solver exploded")

    monkeypatch.setattr(qs, "hysteresis", broken)
    outcome = evaluate_quasi_static(RV40E, hysteresis=True)
    assert outcome["status"] == "error" and "solver exploded" in outcome["error"]


def test_no_factor_label_can_overwrite_a_metric_column(tmp_path):
    # found by a hostile review: a factor labelled energy_residual (or max_pin_force_n) was
    # accepted and results.csv held the metric in its column, the levels lost.  Every key of
    # a real run's summary, of each engine and scheme, must be reserved.
    from rvsim.doe.study import RESULT_COLUMNS
    from rvsim.dynamics import simulate
    from rvsim.quasistatic import hysteresis, ltca

    # the integration tests' 0.4 s schedule: the same keys as 1.6 s runs (compared), a quarter
    # of the CPU
    short = with_values(RV40E, {"operating.duration": 0.4, "operating.speed_ramp_time": 0.1,
                                "operating.load_start": 0.1, "operating.load_ramp_end": 0.2,
                                "operating.steady_start": 0.3})
    summaries = [simulate(short, scheme="implicit-bearings").summary(),
                 simulate(short, time_step=7e-6).summary(),           # with the step guard
                 ltca(RV40E, positions=16, allow_aliasing=True).summary(),
                 hysteresis(RV40E).summary()]
    keys = {k for s in summaries for k in s}
    assert {"guard_substep_checks", "implicit_alerts", "backlash_arcmin"} <= keys
    assert sorted(k for k in keys if k not in RESULT_COLUMNS and not k.startswith("te_")) == []
    path = tmp_path / "bad.toml"
    path.write_text(STUDY.format(extra="").replace("[factors.H]", "[factors.energy_residual]"))
    with pytest.raises(ParameterError, match="factors.energy_residual"):
        load_study(path)


def test_a_time_step_in_a_quasi_static_study_is_refused(tmp_path):
    # it entered the folder's identity, which the command line (refusing --time-step for
    # this engine) could then never match: the folder was locked to the file
    path = _study(tmp_path, 'engine = "quasi-static"\ntime_step = 1e-5')
    with pytest.raises(ParameterError, match="quasi-static engine, which takes no time step"):
        load_study(path)
