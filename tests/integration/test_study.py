"""Study runner: parallel runs, resumable store, failed rows, input errors, schemes and steps.
(kill -9 of a study and Dask clusters: test_study_faults.py.)"""

import json
import shutil
import sqlite3

import pandas as pd
import pytest

from rvsim.doe import load_study, run
from rvsim.errors import ParameterError
from tests.integration.answer_block import answer
from tests.conftest import run_cli
from tests.integration.conftest import factors, write_study


def _stored(folder):
    path = folder / "results.sqlite"
    if not path.exists():
        return {}
    with sqlite3.connect(path) as db:
        try:
            return dict(db.execute("SELECT key, finished FROM runs").fetchall())
        except sqlite3.OperationalError:
            return {}


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """The small study run once by the command line (two workers, its report): (study file,
    folder, the command's JSON summary).  Tests that change the folder work on a copy."""
    root = tmp_path_factory.mktemp("finished")
    path = write_study(root)
    out = root / "out"
    res = run_cli("study", str(path), "--out", str(out), "--workers", "2", "--json")
    assert res.code == 0, res.err
    return path, out, json.loads(res.out)


def test_study_cli_writes_outputs_and_rerun_skips(finished, cli):
    small_study, out, summary = finished
    assert summary["runs"] == 4 and summary["failed"] == 0
    for name in ("results.csv", "analysis.json", "main_effects.png", "report.html",
                 "study.json"):
        assert (out / name).exists()
    table = pd.read_csv(out / "results.csv")
    assert list(table["run"]) == [1, 2, 3, 4]
    assert {"H", "I", "E", "te_mean_arcmin", "te_pp_arcmin", "speed_ratio", "status"} <= set(
        table.columns)
    # the report names the scheme of every dynamic study, the default one too
    assert "Integration scheme: explicit, step 5e-06 s" in (out / "report.html").read_text()
    # the report opens with its answer (issue 34 item 2)
    analysis = json.loads((out / "analysis.json").read_text())
    rows = answer((out / "report.html").read_text())
    assert rows["factor order by range"][0] == analysis["order"]
    predicted = analysis["prediction"]["predicted"]
    assert rows["predicted response at the optimum"][0] == f"{predicted:.4f} arcmin"
    definition = json.loads((out / "study.json").read_text())
    for f in definition["factors"]:
        level = analysis["optimum"][f["label"]]
        assert rows[f"optimum {f['label']} ({f['parameter']})"][1] == f"level {level}"
    assert "Confirmation run" in rows["text"] and "rvsim simulate --params" in rows["text"]
    first = _stored(out)
    res = cli("study", str(small_study), "--out", str(out), "--no-report")
    assert res.code == 0
    assert _stored(out) == first  # nothing re-evaluated


def test_a_study_whose_runs_all_fail_exits_1_with_one_line(tmp_path, cli):
    path = write_study(tmp_path, factors=factors(
        S=("contact.bushing_stiffness_factor", [1e5, 1e6]), H=("H", [0.0, 0.01]),
        E=("E", [100, 200])))
    out = tmp_path / "out"
    res = cli("study", str(path), "--out", str(out), "--workers", "1", "--no-report")
    assert res.code == 1 and res.out == ""
    assert res.err.startswith("rvsim: error: study: all 4 runs failed (run 1: ")
    assert res.err.count("\n") == 1
    assert len(pd.read_csv(out / "results.csv")) == 4      # the failed rows are kept
    # --json: the status on stdout as well (it printed nothing there)
    again = cli("study", str(path), "--out", str(out), "--workers", "1", "--no-report",
                "--json")
    assert again.code == 1 and again.err == res.err
    payload = json.loads(again.out)
    assert payload["status"] == "all_failed" and payload["runs"] == 4
    assert payload["first_failure"]["run"] == 1 and payload["first_failure"]["status"]


def test_failed_row_is_stored_and_does_not_stop_the_study(tmp_path):
    # two runs on one worker: the first fails (a bushing 10^6 times stiffer), the second runs
    path = write_study(tmp_path, design="full", factors=factors(
        S=("contact.bushing_stiffness_factor", [1e6, 1.0])))
    results = run(load_study(path), tmp_path / "out", workers=1, progress=False)
    stiff = results["S"] == 1
    assert list(stiff) == [True, False]
    assert (results.loc[~stiff, "status"] == "ok").all()
    assert (results.loc[stiff, "status"] != "ok").all()
    assert results.loc[stiff, "error"].str.len().min() > 0


@pytest.mark.parametrize("factors, words", [
    ('[factors.X]\nparameter = "nope.nothing"\nlevels = [1, 2]\n', "unknown parameter"),
    ('[factors.H]\nparameter = "H"\nlevels = [0.0, 0.01, 0.02]\n', "no free 3-level column"),
    ('[factors.H]\nparameter = "clearances.support_carrier"\nlevels = [0.0, -0.01]\n',
     "negative"),
    ('[factors.H]\nparameter = "H"\nlevels = [0.0]\n', "at least 2"),
    ('[factors." "]\nparameter = "H"\nlevels = [0.0, 0.01]\n',
     "parameter 'factors': a factor's label is blank (' ')"),
    ('[factors.""]\nparameter = "H"\nlevels = [0.0, 0.01]\n',
     "parameter 'factors': a factor's label is empty ('')"),
    ('[factors." H"]\nparameter = "H"\nlevels = [0.0, 0.01]\n', "start or end with a space"),
])
def test_study_input_errors_before_any_run(tmp_path, cli, factors, words):
    path = write_study(tmp_path, factors=factors)
    out = tmp_path / "out"
    res = cli("study", str(path), "--out", str(out))
    assert res.code == 2 and words in res.err and res.err.count("\n") == 1
    assert not (out / "results.sqlite").exists()


def test_samples_of_a_design_that_takes_none_are_refused(tmp_path, cli):
    # found by a hostile review: `samples = 7` in a full-factorial study did nothing, silently
    path = write_study(tmp_path, design="full", extra="samples = 7",
                       factors='[factors.H]\nparameter = "H"\nlevels = [0.0, 0.01]\n')
    res = cli("study", str(path), "--out", str(tmp_path / "out"))
    assert res.code == 2 and res.err == (
        "rvsim: error: parameter 'samples': is for the lhs and sobol designs only (this "
        "study's design is full: its runs are its table's)\n")
    assert not (tmp_path / "out").exists()
    path.write_text(path.read_text().replace("samples = 7", "seed = 3"))
    res = cli("study", str(path), "--out", str(tmp_path / "out"))
    assert res.code == 2 and "parameter 'seed': is for the lhs and sobol designs only" \
        in res.err


def test_unreachable_scheduler_is_a_clear_error(tmp_path, small_study, cli):
    res = cli("study", str(small_study), "--out", str(tmp_path / "o"), "--scheduler",
              "tcp://127.0.0.1:9")
    assert res.code == 2 and "Dask scheduler" in res.err
    assert not (tmp_path / "o").exists()


def test_paper_l36_definition_validates_all_runs():
    from rvsim.doe import paper_l36

    reducers = paper_l36().reducers()
    assert len(reducers) == 36
    with pytest.raises(ParameterError):
        from rvsim.parameters import paper_run_values
        paper_run_values(0)


@pytest.mark.parametrize("args, words", [
    (("report", "/nonexistent/folder"), "not a study folder"),
    (("study", "no-such-study", "--out", "x"), "unknown study"),
    (("study", "/nonexistent/s.toml", "--out", "x"), "not found"),
    (("study", "paper-l36"), "--out"),
])
def test_report_and_study_error_paths(cli, args, words):
    res = cli(*args)
    assert res.code == 2 and words in res.err and res.err.count("\n") == 1


def test_report_command_rewrites_the_report(tmp_path, finished, cli):
    out = tmp_path / "out"
    shutil.copytree(finished[1], out)
    (out / "report.html").unlink()
    before = sorted(p.name for p in out.iterdir())
    res = cli("report", str(out), "--alpha", "0.05", "--json")
    assert res.code == 0, res.err
    # the report reads the store without writing beside it (no -wal / -shm files)
    assert sorted(p.name for p in out.iterdir()) == sorted(before + ["report.html"])
    assert json.loads(res.out)["report"].endswith("report.html")
    assert "alpha = 0.05" in (out / "report.html").read_text()


def test_sampling_study_lhs(tmp_path, cli):
    path = write_study(tmp_path, design="lhs", factors=factors(
        H=("H", "range", [0.0, 0.03]), I=("I", "range", [0.0, 0.04])),
        extra='samples = 6\nseed = 3\nscheme = "implicit-bearings"')   # 4 times cheaper
    study = load_study(path)
    table = study.table()
    assert len(table) == 6 and table["H"].between(0, 0.03).all()
    results = run(study, tmp_path / "out", workers=2, progress=False)
    assert (results["status"] == "ok").all()
    # TE grows with both clearances: correlation with H * 0.68 + I 0.99992 (measured, either
    # scheme: their mean TEs agree to 1e-4 arcmin)
    assert results["te_mean_arcmin"].corr(results["H"] * 0.68 + results["I"]) > 0.9995


def test_run_length_is_checked_before_any_run(tmp_path, cli):
    """Regression (hostile review): a [set] duration whose histories cannot fit in memory
    ran every row into an error, then exited 2 with a misleading line, leaving files."""
    path = tmp_path / "long.toml"
    path.write_text('name = "long"\ndesign = "L4"\n[set]\n"operating.duration" = 1e9\n'
                    '[factors.H]\nparameter = "H"\nlevels = [0.0, 0.02]\n')
    res = cli("study", str(path), "--out", str(tmp_path / "out"), "--no-progress")
    assert res.code == 2 and len(res.err.strip().splitlines()) == 1
    assert "'duration'" in res.err and "study run 1" in res.err
    assert not (tmp_path / "out").exists()


def test_study_with_the_implicit_bearings_scheme(tmp_path, cli):
    """Issue 14: a study's scheme, from its file or from --scheme, is part of the study's
    definition: the same file run with the other scheme into its folder is refused."""
    path = write_study(tmp_path, extra='scheme = "implicit-bearings"')
    study = load_study(path)
    assert study.scheme == "implicit-bearings"
    out = tmp_path / "out"
    res = cli("study", str(path), "--out", str(out), "--no-report", "--no-progress")
    assert res.code == 0, res.err
    assert not (out / "report.html").exists()                 # --no-report
    table = pd.read_csv(out / "results.csv")
    assert (table["status"] == "ok").all() and (table["steps"] == 20_000).all()
    assert (table["implicit_fallbacks"] == 0).all()
    assert json.loads((out / "study.json").read_text())["scheme"] == "implicit-bearings"
    # its report names the scheme and what it does to the peak answers
    res = cli("report", str(out))
    assert res.code == 0, res.err
    page = (out / "report.html").read_text()
    assert "Integration scheme: implicit-bearings, step 2e-05 s" in page
    assert "slows the crank modes" in page
    # the same file run explicitly into the same folder is another study: refused, with the
    # way to resume it
    res = cli("study", str(path), "--out", str(out), "--no-report", "--no-progress",
              "--scheme", "explicit")
    assert res.code == 2 and res.err.count("\n") == 1
    assert "with the implicit-bearings integration scheme (step 2e-05 s), not explicit" \
        in res.err and "resume it with --scheme implicit-bearings" in res.err
    # ... but only where that option resumes it: with another step as well, the folder holds
    # a different definition, and the refusal says so
    (tmp_path / "stepped").mkdir()
    stepped = write_study(tmp_path / "stepped", extra="time_step = 1e-5")
    res = cli("study", str(stepped), "--out", str(out), "--no-report", "--no-progress",
              "--scheme", "explicit")
    assert res.code == 2 and res.err.count("\n") == 1
    assert "study.json differs in scheme: implicit-bearings in the folder, explicit here; " \
        "time_step: 2e-05 in the folder, 1e-05 here)" in res.err
    assert "--scheme" not in res.err and "--time-step" not in res.err


@pytest.mark.parametrize("stored", ["{corrupt", "", "null", "42", "[1, 2]", '"text"'])
def test_a_folder_whose_study_json_is_damaged_is_one_line(tmp_path, small_study, cli, stored):
    """A folder with results but a study.json that is not a study's definition is refused
    with one line (a review found that the scheme's message raised AttributeError on it)."""
    from rvsim.doe.store import ResultStore

    out = tmp_path / "out"
    out.mkdir()
    (out / "study.json").write_text(stored)
    store = ResultStore(out)
    store.put("k", {"status": "ok", "metrics": {}})
    store.close()
    res = cli("study", str(small_study), "--out", str(out), "--no-progress")
    assert res.code == 2 and res.err.count("\n") == 1, res.err
    assert "holds the results of another study" in res.err
    assert (out / "study.json").read_text() == stored


def test_paper_l36_runs_implicit_bearings_and_an_explicit_folder_says_how_to_resume(
        tmp_path, cli):
    """The paper's study runs implicit-bearings (docs/decisions.md); a folder of its runs
    made with the explicit scheme (a paper-l36 folder from before 2026-11-26, unless run with
    --scheme implicit-bearings) is refused before anything runs, naming the option that
    resumes it."""
    import dataclasses

    from rvsim.doe import paper_l36
    from rvsim.doe.runner import _definition
    from rvsim.doe.store import ResultStore

    study = paper_l36()
    assert (study.scheme, study.time_step) == ("implicit-bearings", None)
    old = dataclasses.replace(study, scheme="explicit")
    out = tmp_path / "old"
    out.mkdir()
    stored = json.dumps(_definition(old, 5e-6, old.reducers()[0]), indent=2, default=str)
    (out / "study.json").write_text(stored)
    store = ResultStore(out)
    store.put("k", {"status": "ok", "metrics": {}})
    store.close()
    res = cli("study", "paper-l36", "--out", str(out), "--no-progress")
    assert res.code == 2 and res.err.count("\n") == 1, res.err
    assert "holds the runs of study 'paper-l36' with the explicit integration scheme " \
        "(step 5e-06 s), not implicit-bearings; resume it with --scheme explicit " \
        "(Python: scheme=\"explicit\"), or give a new --out folder" in res.err
    assert (out / "study.json").read_text() == stored            # untouched, nothing run
    assert not (out / "results.csv").exists()


def test_scheme_belongs_to_the_dynamic_engine():
    from rvsim.doe import Study, paper_l36
    import dataclasses
    study = paper_l36()
    assert dataclasses.replace(study, scheme="implicit-bearings").scheme == "implicit-bearings"
    with pytest.raises(ParameterError) as info:
        dataclasses.replace(study, engine="quasi-static", scheme="implicit-bearings")
    assert info.value.field == "scheme"
    assert Study is type(study)


@pytest.mark.parametrize("extra, args, words", [
    ('scheme = "fast"', (), "parameter 'scheme'"),
    ('scheme = 3', (), "'scheme' must be"),
    ('engine = "quasi-static"\nscheme = "implicit-bearings"', (), "parameter 'scheme'"),
    ('engine = "quasi-static"', ("--scheme", "implicit-bearings"), "--scheme"),
    ("", ("--scheme", "bogus"), "invalid choice"),
    ("", ("--time-step", "0"), "parameter '--time-step': must be a number of seconds in"),
    ("", ("--time-step", "nan"), "parameter '--time-step': must be a number of seconds in"),
    ("", ("--time-step", "1"), "parameter '--time-step': must be a number of seconds in"),
    ("", ("--time-step", "fast"), "argument --time-step: 'fast' is not a number"),
    ('engine = "quasi-static"', ("--time-step", "1e-5"),
     "parameter '--time-step': the study runs the quasi-static engine"),
    ("", ("--time-step", "1e-12"), "parameter '--time-step': 0.4 s at 1e-12 s per step is "
     "4e+11 steps, more than the 1e+09 a run may take"),
    ("", ("--time-step", "-inf"), "parameter '--time-step': must be a number of seconds in"),
    # the input's own error before the (unreachable) scheduler's
    ("", ("--time-step", "1e-12", "--scheduler", "tcp://127.0.0.1:1"),
     "parameter '--time-step': 0.4 s at 1e-12 s"),
])
def test_study_scheme_and_time_step_errors(tmp_path, cli, extra, args, words):
    path = write_study(tmp_path, extra=extra)
    out = tmp_path / "out"
    res = cli("study", str(path), "--out", str(out), *args)
    assert res.code == 2 and words in res.err and res.err.count("\n") == 1
    assert not out.exists()


def test_a_tolerance_study_takes_no_time_step(tmp_path, cli):
    out = tmp_path / "out"
    res = cli("study", "rv40e-tolerances", "--out", str(out), "--time-step", "1e-5")
    assert res.code == 2 and res.err.count("\n") == 1
    assert "parameter '--time-step': a tolerance study runs the quasi-static engine" in res.err
    assert not out.exists()


def test_study_time_step_option_is_the_studys_step(tmp_path, cli):
    """--time-step sets every dynamic run's step, as a study file's time_step does: the runs
    take it, study.json records it, and a folder of another step is another study."""
    path = write_study(tmp_path, extra='scheme = "implicit-bearings"')
    out = tmp_path / "out"
    res = cli("study", str(path), "--out", str(out), "--no-report", "--no-progress",
              "--time-step", "2.5e-5")
    assert res.code == 0, res.err
    table = pd.read_csv(out / "results.csv")
    assert (table["status"] == "ok").all() and (table["steps"] == 16_000).all()
    assert json.loads((out / "study.json").read_text())["time_step"] == 2.5e-5
    res = cli("study", str(path), "--out", str(out), "--no-report", "--no-progress")
    assert res.code == 2 and res.err.count("\n") == 1
    # the refusal names the step that differs, with both values
    assert "study.json differs in time_step: 2.5e-05 in the folder, 2e-05 here)" in res.err
    assert "resume it with --time-step 2.5e-05, or give a new --out folder" in res.err
    # ... which it does
    res = cli("study", str(path), "--out", str(out), "--no-report", "--no-progress",
              "--time-step", "2.5e-05")
    assert res.code == 0, res.err


def test_a_study_none_of_whose_runs_finished_still_reports(tmp_path, monkeypatch, capsys):
    """Every run an exception (no metric at all in results.csv): the report is still written,
    with the failed runs, and the command ends with its one line and exit 1.  (Before, the
    report refused results.csv for its missing te_mean_arcmin and the command ended with that
    misleading line and exit 2.)  In-process, so that the forked worker inherits the fault."""
    import rvsim.doe.runner as runner
    from rvsim.cli import main

    def broken(*args, **kwargs):
        return {"status": "error", "error": "RuntimeError: injected", "metrics": {}}

    monkeypatch.setattr(runner, "evaluate", broken)
    path = write_study(tmp_path)
    out = tmp_path / "out"
    code = main(["study", str(path), "--out", str(out), "--workers", "1", "--no-progress"])
    err = capsys.readouterr().err
    assert code == 1 and err.count("\n") == 1
    assert err.startswith("rvsim: error: study: all 4 runs failed (run 1: error: "
                          "RuntimeError: injected)")
    table = pd.read_csv(out / "results.csv")
    assert "te_mean_arcmin" not in table.columns and (table["status"] == "error").all()
    page = (out / "report.html").read_text()
    assert "Failed runs" in page and "RuntimeError: injected" in page
    assert "analysis not possible" in page


def test_the_summary_says_when_the_analysis_is_not_possible(tmp_path, monkeypatch, capsys):
    """Runs finished, but too few for the analysis: the text summary says so (it printed the
    counts alone, as if the analysis had been written; found by review)."""
    import rvsim.doe.runner as runner
    from rvsim.cli import main

    original = runner.evaluate
    calls = []

    def first_only(*args, **kwargs):      # in the one forked worker: its first run only
        calls.append(1)
        if len(calls) == 1:
            return original(*args, **kwargs)
        return {"status": "error", "error": "RuntimeError: injected", "metrics": {}}

    monkeypatch.setattr(runner, "evaluate", first_only)
    path = write_study(tmp_path, extra='scheme = "implicit-bearings"')   # its one run: cheap
    out = tmp_path / "out"
    code = main(["study", str(path), "--out", str(out), "--workers", "1", "--no-progress",
                 "--no-report"])
    printed = capsys.readouterr().out
    assert code == 0
    assert printed.splitlines()[0].endswith("4 runs, 3 failed -> "
                                            f"{out}/results.csv, analysis.json")
    assert printed.splitlines()[1].startswith("analysis not possible: ")
