"""rvsim tolerance / rvsim allocate as a user runs them, and their bad input (issue 11)."""

import json
import shutil

import pytest

from tests.integration.answer_block import answer

# SMALL, and the small_run fixture (its study run once with its report, read by the browser
# test too), live in conftest.py
from tests.integration.conftest import SMALL


@pytest.fixture
def small(tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(SMALL)
    return path


def test_tolerance_writes_summary_results_and_report(tmp_path, small, cli, small_run):
    res, folder = small_run
    assert res.code == 0, res.err
    out = shutil.copytree(folder, tmp_path / "o")
    summary = json.loads((out / "summary.json").read_text())
    assert summary["samples"] == 6 and summary["ok"] + summary["binds"] == 6
    for metric in ("ate_arcmin", "te_mean_arcmin", "lost_motion_arcmin",
                   "torsional_rigidity_nm_per_arcmin"):
        m = summary["metrics"][metric]
        assert m["p5"] <= m["p50"] <= m["p95"] and "binding_share" in m
    assert set(summary["sobol"]["ate_arcmin"]) == {"pin_radius", "disc_holes",
                                                   "clearances.crank_arm_bushing"}
    assert {"S1", "ST", "S1_conf", "ST_conf"} <= set(
        summary["sobol"]["ate_arcmin"]["pin_radius"])
    page = (out / "report.html").read_text()
    assert page.count("<img") >= 4
    rows = answer(page)                   # the answer first (issue 34 item 2)
    assert rows["ATE p95"][0] == f"{summary['metrics']['ate_arcmin']['p95']:.4g} arcmin"
    lost = summary["metrics"]["lost_motion_arcmin"]["p95"]
    assert rows["lost motion p95"][0] == f"{lost:.3g} arcmin"
    assert rows["lost motion p95"][2] == ("within the class" if 0.3 <= lost <= 1.0 else
                                          "above the class's 1 arcmin" if lost > 1 else
                                          "within; below the typical 0.3-0.6 arcmin")
    assert len((out / "results.csv").read_text().splitlines()) == 7
    # `rvsim report` rebuilds the same page from the folder (it said "not a study folder")
    (out / "report.html").unlink()
    rebuilt = cli("report", str(out))
    assert rebuilt.code == 0, rebuilt.err
    assert (out / "report.html").read_text() == page
    (out / "summary.json").write_text('{"metrics": {}}')      # damaged: one line
    damaged = cli("report", str(out))
    assert damaged.code == 2 and damaged.err == (
        f"rvsim: error: {out}: damaged tolerance study files (KeyError: 'study'); run "
        "'rvsim tolerance' on it again\n")
    # re-running resumes: nothing is evaluated again, the same numbers come out (without a
    # second report: the page is checked above)
    again = cli("tolerance", str(small), "--out", str(out), "--workers", "1", "--sobol", "2",
                "--json", "--no-report")
    assert again.code == 0 and json.loads(again.out)["metrics"] == summary["metrics"]


def test_identical_seeds_identical_results_locally_and_on_dask(tmp_path, small):
    distributed = pytest.importorskip("distributed")
    from rvsim.tolerance import load_tolerance_study, tolerance_analysis

    study = load_tolerance_study(small)
    local = tolerance_analysis(study, tmp_path / "local", samples=4, workers=1, report=False)
    # one worker process: the reducers are drawn here, a worker only evaluates them; the
    # sharing of a run among several Dask workers is tested on a study (test_study.py)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        remote = tolerance_analysis(study, tmp_path / "dask", samples=4, report=False,
                                    scheduler=cluster.scheduler_address)
    assert remote["metrics"] == local["metrics"]


def test_study_command_runs_a_tolerance_study(tmp_path, small, cli):
    res = cli("study", str(small), "--out", str(tmp_path / "s"), "--workers", "1",
              "--no-report")
    assert res.code == 0, res.err
    assert (tmp_path / "s" / "summary.json").exists()


def test_allocate_loosens_tolerances_within_the_target(tmp_path, small, cli):
    out = tmp_path / "a"
    res = cli("allocate", str(small), "--target", "ate_p95=0.5", "--out", str(out),
              "--samples", "4", "--workers", "1", "--max-evaluations", "8", "--json")
    assert res.code == 0, res.err
    result = json.loads(res.out)
    assert result["cost"] <= result["cost_start"]
    assert result["targets"][0]["achieved"] <= 0.5 * (1 + 1e-4)
    # no more reducers bind than with the tolerances as given (a constraint of its own)
    share = result["targets"][1]
    assert share["metric"] == "binding_share" and "(as given)" in share["target"]
    assert result["binding_share"] <= share["limit"]
    assert (out / "allocation.json").exists() and (out / "report.html").exists()
    rows = answer((out / "report.html").read_text())
    target = result["targets"][0]
    assert rows["target ate_p95=0.5"] == [f"{target['achieved']:.4g}", "0.5", "met"]
    # `rvsim report` of that folder says what writes its page: it said "not a study folder
    # (missing results.csv, analysis.json; run 'rvsim study' first)"
    res = cli("report", str(out))
    assert res.code == 2 and "a tolerance allocation's folder: its report.html is written by " \
        "'rvsim allocate'" in res.err


def _bad(tmp_path, body):
    path = tmp_path / "bad.toml"
    path.write_text(body)
    return str(path)


@pytest.mark.parametrize("body, field", [
    (SMALL.replace("[tolerances.pin_radius]", "[tolerances.pin_colour]"), "pin_colour"),
    (SMALL.replace("tolerance = 0.002", "tolerance = -0.002"), "tolerance"),
    # 1e308 mm went on: every reducer "bound on assembly", with numpy's overflow warnings
    (SMALL.replace("tolerance = 0.002", "tolerance = 1e308"),
     "'tolerances.pin_radius.tolerance': must be at most 1 mm (got 1e+308)"),
    (SMALL.replace("tolerance = 0.002", "tolerance = 2"), "at most 1 mm (got 2)"),
    (SMALL.replace("[tolerances.pin_radius]", "[tolerances.disc_phase]").replace(
        "tolerance = 0.002", "tolerance = 61"), "at most 60 arcmin (got 61)"),
    (SMALL.replace('distribution = "normal"', 'distribution = "cauchy"'), "distribution"),
    (SMALL.replace('distribution = "normal"', 'per = "batch"'), "per"),
    (SMALL.replace("samples = 6", "samples = 1"), "samples"),
])
def test_bad_tolerance_files_are_one_line(tmp_path, cli, body, field):
    res = cli("tolerance", _bad(tmp_path, body), "--out", str(tmp_path / "o"))
    assert res.code == 2 and res.err.count("\n") == 1 and field in res.err, res.err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("args, text", [
    (["--samples", "0"], "samples"),
    (["--samples", "2000000"], "samples"),
    (["--sobol", "3"], "power of 2"),
])
def test_bad_options_are_one_line(tmp_path, small, cli, args, text):
    res = cli("tolerance", str(small), "--out", str(tmp_path / "o"), *args)
    assert res.code == 2 and res.err.count("\n") == 1 and text in res.err, res.err
    assert not (tmp_path / "o").exists()


def test_too_few_evaluations_are_one_line(tmp_path, small, cli):
    res = cli("allocate", str(small), "--target", "ate_p95=0.5", "--out", str(tmp_path / "o"),
              "--max-evaluations", "4")
    assert res.code == 2 and res.err.count("\n") == 1, res.err
    assert "--max-evaluations" in res.err and "at least 5" in res.err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("target, text", [
    ("ate_p95=0.0001", "cannot be met even at the tightest tolerances"),
    ("colour_p95=1", "not METRIC_pNN=VALUE"),
    ("ate_p95=-1", "positive"),
    ("ate_p100=1", "percentile"),
    ("ate_p95=1,ate_p95=2", "given twice"),
    ("binding_share=0.1", "at least one percentile target"),
    ("ate_p95=1,binding_share=1.5", "from 0 to below 1"),
])
def test_bad_targets_are_one_line(tmp_path, small, cli, target, text):
    res = cli("allocate", str(small), "--target", target, "--out", str(tmp_path / "o"),
              "--samples", "2", "--workers", "1")
    assert res.code == 2 and res.err.count("\n") == 1 and text in res.err, res.err
    assert not (tmp_path / "o").exists()          # no partial folder


@pytest.mark.filterwarnings("error::UserWarning")
def test_a_binding_share_target_that_cannot_be_met_is_one_line(tmp_path, cli):
    """disc holes so loose that reducers bind even at a quarter of the tolerance"""
    body = SMALL.replace("[tolerances.disc_holes]\ntolerance = 0.004",
                         "[tolerances.disc_holes]\ntolerance = 0.03")
    res = cli("allocate", _bad(tmp_path, body), "--target", "ate_p95=5,binding_share=0",
              "--out", str(tmp_path / "o"), "--samples", "4", "--workers", "1")
    assert res.code == 2 and res.err.count("\n") == 1, res.err
    assert "binding_share=0 cannot be met even at the tightest" in res.err
    assert not (tmp_path / "o").exists()


def test_every_reducer_binding_is_reported_without_warnings(tmp_path, small, cli):
    """A tolerance so loose that every reducer binds: summary and report, nothing on stderr."""
    path = _bad(tmp_path, SMALL.replace("tolerance = 0.002", "tolerance = 1.0"))   # the largest
    res = cli("tolerance", path, "--out", str(tmp_path / "o"), "--workers", "1",
              "--samples", "2")
    assert res.code == 0 and res.err == "", res.err
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["binds"] == 2 and summary["binding_share"] == 1.0


INVALID = """name = "invalid"
samples = 3
seed = 4
positions = 81
[tolerances."materials.pin.poisson_ratio"]
tolerance = 5
distribution = "uniform"
"""


def test_every_reducer_failing_is_an_error_naming_the_reason(tmp_path, cli):
    """Seed 4 draws Poisson ratios 4.67, 5.04 and 1.36 (over 0.5): no reducer is a result."""
    path = _bad(tmp_path, INVALID)
    out = tmp_path / "o"
    res = cli("tolerance", path, "--out", str(out), "--workers", "1")
    assert res.code == 1 and res.out == "" and res.err.count("\n") == 1, res.err
    assert res.err.startswith("rvsim: error: tolerance: all 3 reducers failed: 3 invalid "
                              "(sample 0, invalid: parameter 'materials.pin.poisson_ratio': "
                              "must not exceed 0.5 (got 4.67056))"), res.err
    rows = (out / "results.csv").read_text().splitlines()
    assert rows[0].split(",")[-2:] == ["error", "key"]
    assert "must not exceed 0.5 (got 5.03818)" in rows[2]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["binding_share"] is None
    assert summary["failures"]["invalid"]["count"] == 3
    assert "n/a" in (out / "report.html").read_text()
    again = cli("tolerance", path, "--out", str(out), "--workers", "1", "--json", "--no-report")
    assert again.code == 1 and again.err == res.err
    payload = json.loads(again.out)
    assert payload["status"] == "all_failed" and payload["failures"]["invalid"]["count"] == 3


def test_some_reducers_failing_are_counted_with_a_note(tmp_path, cli):
    path = _bad(tmp_path, INVALID)
    res = cli("tolerance", path, "--out", str(tmp_path / "o"), "--workers", "1",
              "--samples", "8", "--no-report")
    assert res.code == 0, res.err
    assert "8 reducers, 3 analysed, 0 bind on assembly (0.00 %), 5 failed" in res.out
    assert res.err.startswith("rvsim: note: failed reducers: 5 invalid (sample 0, ")


def test_allocate_does_not_loosen_into_reducers_the_model_refuses(tmp_path, cli):
    """Loosening the Poisson ratio's tolerance costs nothing in TE, but past about 0.26 the
    drawn ratios pass 0.5 and those reducers are invalid; left out of the percentiles, they
    used to make the loosest tolerance look best (a hostile test: 2 of 3 reducers invalid at
    the chosen point).  Their share is a constraint: at most that of the tolerances as given
    (here none).  This run's search visits 0.379 and 0.4 (1 and 2 of 4 invalid) and ends at
    0.242 with none."""
    path = _bad(tmp_path, SMALL_POISSON)
    res = cli("allocate", path, "--out", str(tmp_path / "a"), "--samples", "4", "--workers",
              "1", "--target", "ate_p95=0.5", "--max-evaluations", "8", "--json")
    assert res.code == 0, res.err
    result = json.loads(res.out)
    assert result["failed_share"] == 0.0
    tried = [h["failed_share"] for h in json.loads(
        (tmp_path / "a" / "allocation.json").read_text())["history"]]
    assert max(tried) > 0.0                     # the search did go where reducers fail
    allocated = {t["name"]: t["allocated"] for t in result["tolerances"]}
    assert allocated["materials.pin.poisson_ratio"] < 0.26
    assert "failed_share<=0 (as given)" in [t["target"] for t in result["targets"]]


SMALL_POISSON = """name = "poisson"
samples = 4
seed = 3
positions = 81
[set]
"errors.equidistant_modification" = 0.010
[tolerances.pin_radius]
tolerance = 0.002
[tolerances."materials.pin.poisson_ratio"]
tolerance = 0.1
distribution = "uniform"
"""


def test_imputed_sobol_outcomes_are_said(tmp_path, cli):
    """Half the Sobol design's reducers fail here (Poisson ratios over 0.5); their outcomes are
    the mean of the others, which summary.json counted but the command did not say."""
    path = _bad(tmp_path, SMALL_POISSON.replace("tolerance = 0.1", "tolerance = 5").replace(
        "seed = 3", "seed = 1"))
    res = cli("tolerance", path, "--out", str(tmp_path / "o"), "--workers", "1", "--samples",
              "6", "--sobol", "2", "--no-report")
    assert res.code == 0, res.err
    assert ("rvsim: note: Sobol indices: 6 of the 12 reducers of the design bind or fail and "
            "were given the mean of the others") in res.err


def test_single_stage_tolerance_study(tmp_path):
    import dataclasses

    from rvsim.tolerance import cycloid_drive_tolerances, tolerance_analysis

    study = dataclasses.replace(cycloid_drive_tolerances(), positions=61)
    summary = tolerance_analysis(study, tmp_path / "cd", samples=3, workers=1, report=False)
    assert summary["ok"] + summary["binds"] == 3 and summary["failed"] == 0
    assert summary["metrics"]["ate_arcmin"]["n"] == summary["ok"]


def test_a_full_factorial_study_gets_the_interaction_anova(tmp_path, cli):
    from tests.integration.conftest import write_study

    study = write_study(tmp_path, design="full", extra='engine = "quasi-static"')
    res = cli("study", str(study), "--out", str(tmp_path / "f"), "--workers", "1",
              "--no-report")
    assert res.code == 0, res.err
    analysis = json.loads((tmp_path / "f" / "analysis.json").read_text())
    assert {"H x I", "H x E", "I x E", "Error", "Total"} <= set(analysis["interactions"])
    assert (tmp_path / "f" / "interactions.png").exists()


def test_measured_profile_from_csv(tmp_path):
    import dataclasses
    import math

    from rvsim.geometry import pin_gaps
    from rvsim.parameters import PartErrors, with_values
    from rvsim.tolerance import load_tolerance_study

    rows = ["disc,angle_deg,deviation_um"]
    rows += [f"{d},{a},1.5" for d in (1, 2) for a in range(0, 360, 3)]
    (tmp_path / "profile.csv").write_text("\n".join(rows) + "\n")
    (tmp_path / "s.toml").write_text(SMALL.replace('seed = 3',
                                                   'seed = 3\nprofile_csv = "profile.csv"'))
    study = load_tolerance_study(tmp_path / "s.toml")
    nominal = study.nominal
    # 1.5 um of excess material everywhere = an equidistant modification 1.5 um smaller
    plain = dataclasses.replace(with_values(nominal, {"I": 0.010 - 0.0015}, check=False),
                                parts=PartErrors())
    assert max(abs(pin_gaps(nominal, 0.3) - pin_gaps(plain, 0.3))) < 1e-12
    drawn = study.realise(study.unit_sample(0))
    assert drawn.parts.profile_points == nominal.parts.profile_points
    assert drawn.parts.pin_radius                       # the drawn errors are added to it
    assert not math.isnan(pin_gaps(drawn, 0.3)[0])


def test_bad_profile_csv_is_one_line(tmp_path, cli):
    (tmp_path / "profile.csv").write_text("disc,angle\n1,0\n")
    path = tmp_path / "s.toml"
    path.write_text(SMALL.replace('seed = 3', 'seed = 3\nprofile_csv = "profile.csv"'))
    res = cli("tolerance", str(path), "--out", str(tmp_path / "o"))
    assert res.code == 2 and res.err.count("\n") == 1 and "deviation_um" in res.err, res.err


def test_a_reducer_both_invalid_and_binding_is_invalid(tmp_path):
    """A drawn value the model refuses comes first: such a reducer was counted as binding
    (scrap of a real part) because the assembly was checked before the values."""
    from rvsim.tolerance import load_tolerance_study
    from rvsim.tolerance.engine import evaluate_sample

    path = _bad(tmp_path, INVALID + "[tolerances.pin_radius]\ntolerance = 1.0\n")
    study = load_tolerance_study(path)
    reducer = study.realise(study.unit_sample(0))
    assert reducer.materials.pin.poisson_ratio > 0.5
    outcome = evaluate_sample(reducer, 12)
    assert outcome["status"] == "invalid", outcome
    assert "'materials.pin.poisson_ratio': must not exceed 0.5" in outcome["error"]
    # the same draw with a valid Poisson ratio binds
    import dataclasses

    valid = dataclasses.replace(reducer, materials=dataclasses.replace(
        reducer.materials, pin=dataclasses.replace(reducer.materials.pin, poisson_ratio=0.3)))
    assert evaluate_sample(valid, 12)["status"] == "binds"


def test_sobol_of_a_single_toleranced_error_is_refused(tmp_path, cli):
    # found by a hostile review: SALib reads one group as none, so the study ran 1312
    # reducers instead of 64 and reported pin 0's index (S1 -0.0009) as the feature's
    single = SMALL.split("[tolerances.disc_holes]")[0]
    (tmp_path / "one.toml").write_text(single)
    res = cli("tolerance", str(tmp_path / "one.toml"), "--out", str(tmp_path / "o"),
              "--workers", "1", "--sobol", "16")
    assert res.code == 2 and res.err == (
        "rvsim: error: parameter 'sobol': Sobol indices need two or more toleranced errors "
        "(this study has 1: pin_radius; with one, all the variance is its own)\n")
    assert not (tmp_path / "o").exists()


def test_tolerance_files_checked_alike_and_folders_not_mixed(tmp_path, small, cli, small_run):
    # found by a hostile review: `tolerance` ran a file whose [cost] table `allocate` refuses
    bad = tmp_path / "bad.toml"
    bad.write_text(SMALL + "[cost.nosuch]\nweight = -1\n")
    res = cli("tolerance", str(bad), "--out", str(tmp_path / "t"), "--workers", "1")
    assert res.code == 2 and res.err == (
        "rvsim: error: parameter 'cost.nosuch': not a toleranced error of this study\n")
    assert not (tmp_path / "t").exists()
    # and the bounds too (a reviewer's case: they were checked by allocate alone)
    bad.write_text(SMALL + "[cost.pin_radius]\ntightest = 5.0\nloosest = 1.0\n")
    res = cli("tolerance", str(bad), "--out", str(tmp_path / "t"), "--workers", "1")
    assert res.code == 2 and res.err == (
        "rvsim: error: parameter 'cost.pin_radius': tightest must be below loosest\n")
    # an impossible target in a folder that was there: it keeps what it held, and no more
    kept = tmp_path / "kept"
    kept.mkdir()
    (kept / "keep.txt").write_text("x")
    res = cli("allocate", str(small), "--out", str(kept), "--workers", "1", "--samples", "4",
              "--max-evaluations", "5", "--target", "ate_p95=0.0001")
    assert res.code == 2 and "cannot be met even at the tightest tolerances" in res.err
    assert sorted(p.name for p in kept.iterdir()) == ["keep.txt"]
    # a tolerance study and an allocation do not share a folder (each would replace the
    # other's report.html)
    out = shutil.copytree(small_run[1], tmp_path / "o")         # a tolerance study's folder
    page = (out / "report.html").read_text()
    res = cli("allocate", str(small), "--out", str(out), "--workers", "1", "--samples", "4",
              "--max-evaluations", "5", "--target", "ate_p95=0.5")
    assert res.code == 2 and "holds a tolerance study (summary.json)" in res.err
    assert (out / "report.html").read_text() == page and not (out / "allocation.json").exists()
    (out / "summary.json").rename(tmp_path / "summary.json")
    (out / "allocation.json").write_text("{}")
    res = cli("tolerance", str(small), "--out", str(out), "--workers", "1")
    assert res.code == 2 and "holds a tolerance allocation (allocation.json)" in res.err

