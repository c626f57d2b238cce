"""Loads against the reducer's rating, and positions counts that alias (issue 30).

Each row is a command line (``{file}`` stands for a file written from the row's text) and the
words its one-line error must contain: exit 2, nothing written.  A load above the rated torque
but within the momentary maximum runs, with one ``rvsim: warning:`` line.
"""

from __future__ import annotations

import dataclasses
import os
import shutil

import pytest

from rvsim.errors import ParameterError
from rvsim.parameters import BUILT_IN_SETS, RV40E, load_toml

from .conftest import SHORT
from .test_bad_inputs import expect_one_line_error, listing

EXAMPLE = "docs/examples/testrig"


def _tolerance_file(extra: str = "", body: str = "[tolerances.pin_radius]\ntolerance = 0.003\n"
                    ) -> str:
    return f'name = "t"\nsamples = 2\n{extra}\n{body}'


LOAD_TOLERANCE = "[tolerances.\"operating.load_torque\"]\ntolerance = 2000\n"
PROFILE = "[tolerances.profile_form]\ntolerance = 0.001\norders = [{}]\n"
HEAVY_STUDY = (f'name = "heavy"\ndesign = "L4"\n{SHORT}\n[factors.E]\n'
               'parameter = "operating.load_torque"\nlevels = [300.0, 2500.0]\n')
LOW_RATING = ["--set", "rating.rated_torque=100", "--set", "rating.start_stop_torque=150",
              "--set", "rating.momentary_torque=200"]

#: command line -> words the error must contain
ROWS = {
    # A. torque against the rating (RV-40E: rated 412, start/stop 1029, momentary 2058 N*m)
    "ltca --torque 1e5": (["ltca", "--torque", "1e5"],
                          "'--torque': 100000 N*m is above the momentary maximum torque of "
                          "RV-40E, 2058 N*m"),
    "ltca --torque -3000 (other flanks)": (["ltca", "--torque=-3000"], "'--torque': 3000 N*m"),
    "ltca load 2100 by --set": (["ltca", "--set", "E=2100"], "'operating.load_torque'"),
    "ltca cycloid-drive 1500": (["ltca", "--params", "cycloid-drive", "--torque", "1500"],
                                "of cycloid-drive, 1000 N*m"),
    "hysteresis --rated-torque 5000": (["hysteresis", "--rated-torque", "5000"],
                                       "'--rated-torque': 5000 N*m"),
    "hysteresis rated above start/stop": (["hysteresis", "--set", "rating.rated_torque=3000"],
                                          "'rating.start_stop_torque': must be at least the "
                                          "rated torque 3000"),
    "efficiency --torques 100,3000": (["efficiency", "--torques", "100,3000"],
                                      "'--torques': 3000 N*m"),
    "simulate E=2100": (["simulate", "--set", "E=2100"], "'operating.load_torque': 2100 N*m"),
    "simulate E=2050 + fluctuation": (["simulate", "--set", "E=2050", "--set", "D=true"],
                                      "'operating.load_torque + operating.fluctuation_"
                                      "amplitude': 2091.2 N*m"),
    "study with a 2500 N*m level": (["study", "{file}", "--out", "out", "--no-progress"],
                                    "'operating.load_torque (study run 3)': 2500 N*m"),
    "tolerance: load 300 +- 2000": (["tolerance", "{file}", "--out", "out"],
                                    "'tolerances.operating.load_torque': 2300 N*m"),
    "testrig --compare above momentary": (["testrig", EXAMPLE, "--compare", *LOW_RATING],
                                          "'torque_nm (of the recordings)'"),
    "calibrate above momentary": (["calibrate", EXAMPLE, "--fit", "errors.disc_runout",
                                   "--out", "fit", *LOW_RATING],
                                  "'torque_nm (of the recordings)'"),
    # B. positions that alias the pin order (RV-40E: zp = 40; cycloid-drive: 30)
    "ltca --paper-run 2 --positions 8": (["ltca", "--paper-run", "2", "--positions", "8"],
                                         "'--positions': must be at least 81 for RV-40E "
                                         "(got 8): fewer than 81 positions alias the 40th "
                                         "(pin) order"),
    "ltca --positions 40": (["ltca", "--positions", "40"], "at least 81"),
    "ltca --positions 80": (["ltca", "--positions", "80"], "at least 81"),
    "ltca cycloid-drive --positions 60": (["ltca", "--params", "cycloid-drive", "--positions",
                                           "60"], "at least 61 for cycloid-drive (got 60): "
                                           "fewer than 61 positions alias the 30th (pin)"),
    "tolerance positions = 40": (["tolerance", "{file}", "--out", "out"],
                                 "'positions': must be at least 81"),
    "tolerance profile_form order 1e9": (["tolerance", "{file}", "--out", "out"],
                                         "'tolerances.profile_form.orders': the 1000000000th "
                                         "(profile form) order needs at least 2000000001"),
    "tolerance profile_form order 200 at 360": (["tolerance", "{file}", "--out", "out"],
                                                "'positions': must be at least 401 for RV-40E "
                                                "(got 360): fewer than 401 positions alias "
                                                "the 200th (profile form) order"),
    "allocate positions = 8": (["allocate", "{file}", "--target", "ate_p95=0.0001", "--out",
                                "out"], "'positions': must be at least 81"),
    "calibrate --positions 40": (["calibrate", EXAMPLE, "--fit", "errors.disc_runout",
                                  "--positions", "40", "--out", "fit"],
                                 "'--positions': must be at least 81"),
    "testrig --compare --points 64": (["testrig", EXAMPLE, "--compare", "--points", "64"],
                                      "'--points': must be at least 81"),
}

FILES = {
    "study with a 2500 N*m level": HEAVY_STUDY,
    "tolerance: load 300 +- 2000": _tolerance_file(body=LOAD_TOLERANCE),
    "tolerance positions = 40": _tolerance_file("positions = 40"),
    "tolerance profile_form order 1e9": _tolerance_file(body=PROFILE.format(1_000_000_000)),
    "tolerance profile_form order 200 at 360": _tolerance_file(body=PROFILE.format(200)),
    "allocate positions = 8": _tolerance_file("positions = 8"),
}


@pytest.mark.parametrize("case", list(ROWS))
def test_refused(tmp_path, monkeypatch, cli, case):
    monkeypatch.chdir(tmp_path)
    shutil.copytree(os.path.join(os.path.dirname(__file__), "..", "..", EXAMPLE), EXAMPLE)
    args, words = ROWS[case]
    if case in FILES:
        (tmp_path / "case.toml").write_text(FILES[case])
        args = [a.replace("{file}", "case.toml") for a in args]
    before = listing(tmp_path)
    expect_one_line_error(cli(*args), words)
    assert listing(tmp_path) == before


def test_above_rated_runs_with_one_warning(cli):
    res = cli("ltca", "--torque", "500", "--positions", "81", "--json")
    assert res.code == 0, res.err
    assert res.err == ("rvsim: warning: --torque: 500 N*m is above the rated torque of RV-40E, "
                       "412 N*m (within the allowable start/stop torque; rating.*)\n")


def test_within_rated_no_warning_and_toml_without_new_keys(tmp_path):
    from rvsim.parameters.rating import check_torque

    # a parameter file written before the new keys keeps its base set's values
    path = tmp_path / "old.toml"
    path.write_text('base = "cycloid-drive"\n[rating]\nrated_torque = 200\n')
    drive = load_toml(path)
    assert drive.rating == BUILT_IN_SETS["cycloid-drive"].rating
    assert check_torque(RV40E, 412.0, "torque") is None
    assert "start/stop torque 1029 N*m, a momentary load only" in check_torque(
        RV40E, 1500.0, "torque")


def test_python_api_refuses_too():
    from rvsim.analysis.sampling import minimum_positions
    from rvsim.quasistatic import efficiency, hysteresis, ltca
    from rvsim.tolerance.spec import rv40e_tolerances

    for call, field in ((lambda: ltca(RV40E, torque=2059.0), "torque"),
                        (lambda: hysteresis(RV40E, rated_torque=2100.0), "rated_torque"),
                        (lambda: efficiency(RV40E, torques=[2100.0]), "torques")):
        with pytest.raises(ParameterError) as info:
            call()
        assert info.value.field == field and "momentary maximum" in info.value.reason
    with pytest.raises(ParameterError, match="at least 81"):
        dataclasses.replace(rv40e_tolerances(), positions=40)
    assert minimum_positions(RV40E) == 81
    assert minimum_positions(BUILT_IN_SETS["cycloid-drive"]) == 61


ALIAS_REASON = ("must be at least {need} for {name} (got {got}): fewer than {need} positions "
                "alias the {order} (pin) order of the output revolution")


def test_python_entry_points_refuse_positions_that_alias_as_the_command_line():
    """``ltca(RV40E, positions=3)`` returned status ok (hostile5): every Python entry point
    that takes a positions count refuses with the command line's check and reason, before
    any solve (issue 30, fifth session)."""
    from rvsim.quasistatic import life, ltca
    from rvsim.testrig import curves
    from rvsim.testrig.calibration import calibrate
    from rvsim.testrig.model import compare_point
    from rvsim.tolerance.robust import with_noise
    from rvsim.tolerance.spec import rv40e_tolerances

    drive, bearings = BUILT_IN_SETS["cycloid-drive"], BUILT_IN_SETS["RV-40E-bearings"]
    loop = curves.read_loop("docs/examples/hysteresis_loop.csv")
    rv40e = dict(need=81, name="RV-40E", order="40th")
    for call, field, reason in (
            (lambda: ltca(RV40E, positions=3), "positions", ALIAS_REASON.format(got=3, **rv40e)),
            (lambda: ltca(RV40E, positions=80), "positions", ALIAS_REASON.format(got=80, **rv40e)),
            # per output revolution: 40 over half of one are 80
            (lambda: ltca(RV40E, positions=40, revolutions=0.5), "positions",
             ALIAS_REASON.format(got=80, **rv40e)
             + " (positions 40 over 0.5 output revolutions)"),
            (lambda: ltca(drive, positions=60), "positions",
             ALIAS_REASON.format(need=61, name="cycloid-drive", got=60, order="30th")),
            (lambda: life(bearings, positions=40), "positions",
             ALIAS_REASON.format(got=40, need=81, name="RV-40E-bearings", order="40th")),
            (lambda: calibrate([], RV40E, ["stiffness.pins"], positions=40, loops=[loop]),
             "positions", ALIAS_REASON.format(got=40, **rv40e)),
            (lambda: compare_point(None, RV40E, points=64), "points",
             ALIAS_REASON.format(got=64, **rv40e)),
            (lambda: with_noise(rvsim_l36(), rv40e_tolerances().tolerances[:1], 2,
                                positions=40), "noise.positions",
             ALIAS_REASON.format(got=40, **rv40e))):
        with pytest.raises(ParameterError) as info:
            call()
        assert (info.value.field, info.value.reason) == (field, reason)
    # a probe of a few poses, on purpose
    assert ltca(RV40E, torque=412.0, positions=2, allow_aliasing=True).status == "ok"
    with pytest.raises(ParameterError, match="'positions': must be a whole number "
                                             r"\(got 'x'\)"):
        life(bearings, positions="x")


def rvsim_l36():
    from rvsim.doe.study import paper_l36

    return paper_l36()


def test_the_paper_runs_at_400_n_m_with_fluctuation_are_above_rated():
    # 400 N*m + 41.2 N*m fluctuation (factor levels E3, D1): 7 % above the rated 412 N*m for
    # a moment, within the start/stop torque: a warning, not a refusal
    from rvsim.parameters import with_values
    from rvsim.parameters.rating import check_torque, peak_load

    run = with_values(RV40E, {"E": 400, "D": True})
    assert peak_load(run) == (441.2, "operating.load_torque + operating.fluctuation_amplitude")
    assert check_torque(run, *peak_load(run)) == (
        "operating.load_torque + operating.fluctuation_amplitude: 441.2 N*m is above the rated "
        "torque of RV-40E, 412 N*m (within the allowable start/stop torque; rating.*)")
    steady = with_values(RV40E, {"E": 400})
    assert check_torque(steady, *peak_load(steady)) is None


def test_a_refusal_after_a_warning_is_still_one_line(tmp_path, cli):
    # a load above rated (a warning) and an output that cannot be written (a refusal): the
    # refusal alone, as for any bad input
    (tmp_path / "t.toml").write_text(_tolerance_file(
        body='[tolerances."operating.load_torque"]\ntolerance = 200\n'))
    (tmp_path / "out").write_text("a file, not a folder")
    res = cli("tolerance", str(tmp_path / "t.toml"), "--out", str(tmp_path / "out"))
    expect_one_line_error(res, "exists and is not a folder")
