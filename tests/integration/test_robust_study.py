"""A robust study end to end (issue 33 item 2): a study file with a [noise] section, every run
built 3 times with drawn part errors on the quasi-static engine (L4, 96 positions), the rows'
replicate statistics and S/N ratios, the analysis of S/N and mean, resume, and the [noise]
section's bad inputs (item 6: one line, exit 2, nothing written)."""

import json
import textwrap

import pandas as pd
import pytest

from tests.conftest import run_cli

STUDY = """
name = "tiny robust"
design = "L4"
engine = "quasi-static"
[set]
"operating.load_torque" = 300
"clearances.crank_arm_bushing" = 0.01
[factors.F]
parameter = "errors.pin_radius"
levels = [0.01, 0.03]
[factors.I]
parameter = "errors.equidistant_modification"
levels = [0.016, 0.048]
[factors.H]
parameter = "errors.pin_circle_radius"
levels = [0.01, 0.03]
"""
NOISE = """
[noise]
samples = 3
seed = 1
positions = 96
[noise.tolerances.pin_radius]
tolerance = 0.002
distribution = "normal"
[noise.tolerances.eccentricity]
tolerance = 0.002
distribution = "normal"
"""


def _write(folder, noise=NOISE, study=STUDY, name="robust.toml"):
    path = folder / name
    path.write_text(textwrap.dedent(study) + textwrap.dedent(noise))
    return path


@pytest.fixture(scope="module")
def robust(tmp_path_factory):
    root = tmp_path_factory.mktemp("robust")
    path = _write(root)
    res = run_cli("study", str(path), "--out", str(root / "out"), "--workers", "1",
                  "--no-report", "--json")
    assert res.code == 0, res.err
    return root, path, json.loads(res.out)


def test_rows_hold_replicate_statistics_and_sn(robust):
    root, _, printed = robust
    rows = pd.read_csv(root / "out" / "results.csv")
    assert len(rows) == 4 and (rows["status"] == "ok").all()
    assert (rows["replicates"] == 3).all() and (rows["replicates_ok"] == 3).all()
    for m in ("ate_arcmin", "te_mean_arcmin", "max_pin_force_n"):
        for s in ("mean", "std", "p5", "p50", "p95", "sn", "sn_smaller", "sn_nominal",
                  "sn_larger"):
            assert rows[f"{m}_{s}"].notna().all(), f"{m}_{s}"
    assert "ate_arcmin" not in rows        # one number per replicate is not a row's number
    # ordered percentiles, the S/N of the ATE its smaller-the-better ratio
    assert (rows["ate_arcmin_p5"] <= rows["ate_arcmin_p50"]).all()
    assert (rows["ate_arcmin_p50"] <= rows["ate_arcmin_p95"]).all()
    assert (rows["ate_arcmin_sn"] == rows["ate_arcmin_sn_smaller"]).all()
    # smaller-the-better from mean and std: mean(y^2) = ybar^2 + s^2 (n - 1) / n
    n = 3
    msq = rows["ate_arcmin_mean"] ** 2 + rows["ate_arcmin_std"] ** 2 * (n - 1) / n
    import numpy as np
    assert np.allclose(rows["ate_arcmin_sn_smaller"], -10 * np.log10(msq), rtol=0, atol=1e-9)
    # the analysis: S/N (the study's response) and the mean beside it
    analysis = json.loads((root / "out" / "analysis.json").read_text())
    assert analysis["response"] == "ate_arcmin_sn"
    assert set(analysis["order"].split(">")) == {"F", "I", "H"}
    assert "ate_arcmin_mean" in analysis["also"]
    assert set(analysis["also"]["ate_arcmin_mean"]["order"].split(">")) == {"F", "I", "H"}
    study = json.loads((root / "out" / "study.json").read_text())
    assert study["noise"]["samples"] == 3 and study["noise"]["seed"] == 1


def test_resume_gives_identical_rows(robust):
    root, path, _ = robust
    before = (root / "out" / "results.csv").read_text()
    res = run_cli("study", str(path), "--out", str(root / "out"), "--workers", "1",
                  "--no-report")
    assert res.code == 0, res.err
    assert (root / "out" / "results.csv").read_text() == before


def test_analyze_ranks_by_sn_and_by_mean(robust):
    root, _, _ = robust
    table = str(root / "out" / "results.csv")
    for column in ("ate_arcmin_sn", "ate_arcmin_mean", "ate_arcmin_sn_nominal"):
        res = run_cli("analyze", table, "--response", column, "--json")
        assert res.code == 0, res.err
        assert json.loads(res.out)["response"] == column
    res = run_cli("analyze", table)          # a robust folder: its S/N, then its mean
    assert res.code == 0, res.err
    assert "ate_arcmin_sn" in res.out and "ate_arcmin_mean" in res.out


# --- bad inputs: one line, exit 2, nothing written ---------------------------------------------

BAD = {
    "a control factor's parameter": (
        NOISE + '[noise.tolerances."errors.pin_circle_radius"]\ntolerance = 0.001\n',
        "noise.tolerances.errors.pin_circle_radius", "control factor H"),
    "samples 0": (NOISE.replace("samples = 3", "samples = 0"), "noise.samples", "from 2"),
    "samples beyond the bound": (NOISE.replace("samples = 3", "samples = 20000"),
                                 "noise.samples", "10000"),
    "samples missing": (NOISE.replace("samples = 3", ""), "noise.samples", "missing"),
    "an unknown part": (NOISE + "[noise.tolerances.pin_colour]\ntolerance = 0.001\n",
                        "noise.tolerances.pin_colour", "unknown error"),
    "an unknown key": (NOISE.replace("seed = 1", "seed = 1\nreplicates = 4"), "noise",
                       "replicates"),
    "the study's [set]": (NOISE + '[noise.set]\n"operating.load_torque" = 200\n',
                          "noise.set", "[set]"),
    "no tolerances": ("[noise]\nsamples = 3\n", "noise.tolerances", "at least one"),
    "a negative seed": (NOISE.replace("seed = 1", "seed = -1"), "noise.seed", ">= 0"),
    "aliased positions": (NOISE.replace("positions = 96", "positions = 48"), "noise.positions",
                          "alias"),
}


@pytest.mark.parametrize("case", BAD)
def test_bad_noise_section_is_one_line_and_writes_nothing(tmp_path, case):
    noise, field, words = BAD[case]
    path = _write(tmp_path, noise)
    out = tmp_path / "out"
    res = run_cli("study", str(path), "--out", str(out))
    assert res.code == 2, (res.out, res.err)
    assert res.err.count("\n") == 1 and res.err.startswith("rvsim: error: "), res.err
    assert field in res.err and words in res.err and "Traceback" not in res.err
    assert not out.exists()


def test_bad_response_of_a_robust_study(tmp_path):
    path = _write(tmp_path)
    res = run_cli("study", str(path), "--out", str(tmp_path / "out"), "--response",
                  "ate_arcmin")
    assert res.code == 2 and res.err.count("\n") == 1, res.err
    assert "--response" in res.err and "ate_arcmin_sn" in res.err
    assert not (tmp_path / "out").exists()


def test_noise_positions_with_the_dynamic_engine(tmp_path):
    path = _write(tmp_path, study=STUDY.replace('engine = "quasi-static"', ""))
    res = run_cli("study", str(path), "--out", str(tmp_path / "out"))
    assert res.code == 2 and res.err.count("\n") == 1, res.err
    assert "noise.positions" in res.err and "dynamic" in res.err


def test_a_dynamic_robust_study_loads_with_the_papers_index(tmp_path):
    """The dynamic engine is accepted (each replicate a simulation): loaded, not run here."""
    from rvsim.cli._study import _study_response
    from rvsim.tolerance.robust import load_robust_study

    path = _write(tmp_path, noise=NOISE.replace("positions = 96", ""),
                  study=STUDY.replace('engine = "quasi-static"', ""))
    study = load_robust_study(path)
    assert study.engine == "dynamic" and study.noise.samples == 3
    assert "te_mean_arcmin_sn" in study.noise.columns(study)
    assert "steps_mean" not in study.noise.columns(study)        # bookkeeping: no statistics
    assert _study_response(study, None) == "te_mean_arcmin_sn"


def test_plain_loader_points_to_the_robust_one(tmp_path):
    from rvsim.doe import load_study
    from rvsim.errors import InputFileError

    with pytest.raises(InputFileError, match="load_robust_study"):
        load_study(_write(tmp_path))


def test_paper_l36_robust_definition():
    from rvsim.tolerance.robust import paper_l36_robust

    study = paper_l36_robust()
    assert study.engine == "quasi-static" and study.design == "L36" and len(study.table()) == 36
    assert study.noise.samples == 20 and study.noise.spec.seed == 1
    names = [t.name for t in study.noise.spec.tolerances]
    assert "clearances.crank_arm_bushing" not in names         # factor K's parameter
    assert names == ["pin_radius", "pin_radial", "pin_tangential", "disc_pitch", "profile_form",
                     "eccentricity", "disc_holes", "carrier_holes"]


def test_report_names_the_noise_and_maximises_the_sn(robust):
    root, _, _ = robust
    res = run_cli("report", str(root / "out"))
    assert res.code == 0, res.err
    page = (root / "out" / "report.html").read_text()
    assert "Noise factors: every run built 3 times (seed 1)" in page
    assert "Optimum (larger is better: an S/N ratio)" in page
    assert "Factor order by range of ate_arcmin_mean" in page


def test_runs_times_replicates_beyond_the_bound_is_refused(tmp_path):
    """Replicates beyond memory: 200 LHS runs x 10 000 replicates, over the 1 000 000
    evaluations a study may hold (tolerance.robust.MAX_EVALUATIONS)."""
    study = ('name = "big"\ndesign = "lhs"\nsamples = 200\nengine = "quasi-static"\n'
             '[factors.F]\nparameter = "errors.pin_radius"\nrange = [0.01, 0.03]\n')
    path = _write(tmp_path, NOISE.replace("samples = 3", "samples = 10000"), study=study)
    res = run_cli("study", str(path), "--out", str(tmp_path / "out"))
    assert res.code == 2 and res.err.count("\n") == 1, res.err
    assert res.err == ("rvsim: error: parameter 'noise.samples': 200 runs x 10000 replicates = "
                       "2000000 evaluations, more than the 1000000 a study may have\n")
    assert not (tmp_path / "out").exists()
