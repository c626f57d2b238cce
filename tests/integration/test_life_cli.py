"""``rvsim life``: bad input is one line and exit 2, nothing printed on stdout; a good run
prints the table or one JSON object with the documented keys (issue 32 item 5)."""

import json

import pytest

BEARINGS = ("--params", "RV-40E-bearings")

BAD = [
    ((), "'bearings.arm_needles': the paper's bushings have no rating life"),
    (("--params", "cycloid-drive"), "layout.stages"),
    (BEARINGS + ("--torque", "0"), "'--torque': must be positive"),
    (BEARINGS + ("--torque=-412",), "'--torque': must be positive"),
    (BEARINGS + ("--torque", "nan"), "'--torque': must be a finite number"),
    (BEARINGS + ("--torque", "inf"), "'--torque': must be a finite number"),
    (BEARINGS + ("--torque", "abc"), "--torque"),
    (BEARINGS + ("--torque", "2100"), "'--torque': 2100 N*m is above the momentary maximum"),
    (BEARINGS + ("--output-speed", "0"), "'--output-speed': must be positive"),
    (BEARINGS + ("--output-speed=-15",), "'--output-speed': must be positive"),
    (BEARINGS + ("--output-speed", "inf"), "'--output-speed': must be a finite number"),
    (BEARINGS + ("--positions", "7"), "'--positions': must be 8 to 100000"),
    (BEARINGS + ("--positions", "2.5"), "invalid int"),
    (BEARINGS + ("--set", "rating.rated_output_speed=0"), "rating.rated_output_speed"),
    (BEARINGS + ("--set", "bearings.needle_diameter=0.2"),
     "'bearings.needle_diameter': D cos(alpha) / D_pw = 0.007937 is outside ISO 281's table"),
    (("--params", "{tmp}/missing.toml"), "not found"),
    (BEARINGS + ("--moment=-1",), "'--moment': must be zero or positive"),
    (BEARINGS + ("--thrust", "nan"), "'--thrust': must be a finite number"),
    (BEARINGS + ("--radial-load=-5",), "'--radial-load': must be zero or positive"),
    (BEARINGS + ("--moment", "100", "--set", "bearings.main_contact_angle=15"),
     "'bearings.main_contact_angle': 15 deg is outside ISO 281's table"),
]


@pytest.mark.parametrize("args, words", BAD, ids=[" ".join(a) or "bushings" for a, _ in BAD])
def test_bad_input_is_one_line_exit_2(cli, tmp_path, args, words):
    res = cli("life", *(a.format(tmp=tmp_path) for a in args))
    assert res.code == 2, res.err
    assert res.err.startswith("rvsim: error: ") and res.err.count("\n") == 1, res.err
    assert words in res.err and res.out == ""


KEYS = {"reducer", "torque_nm", "output_speed_rpm", "crank_speed_rpm", "life_hours",
        "limiting_bearing", "system_life_hours", "crank_life_hours", "catalogue_life_hours",
        "life_ratio_to_catalogue", "bearings", "positions", "wall_s", "status"}
BEARING_KEYS = {"name", "kind", "status", "dynamic_rating_n", "equivalent_load_n",
                "peak_load_n", "speed_rpm", "life_exponent", "l10_million_revolutions",
                "l10_hours"}


def test_json_keys_at_the_rating_point(cli):
    res = cli("life", *BEARINGS, "--positions", "81", "--json")
    assert res.code == 0 and res.err == "", res.err
    data = json.loads(res.out)
    assert set(data) == KEYS and data["status"] == "ok"
    assert data["torque_nm"] == 412.0
    assert data["output_speed_rpm"] == pytest.approx(15.0, rel=1e-14)
    assert data["crank_speed_rpm"] == pytest.approx(600.0, rel=1e-14)
    assert data["catalogue_life_hours"] == pytest.approx(6000.0, rel=1e-14)
    assert len(data["bearings"]) == 9
    for b in data["bearings"]:
        assert set(b) == BEARING_KEYS
    rated = [b for b in data["bearings"] if b["status"] == "ok"]
    assert len(rated) == 8 and data["life_hours"] == min(b["l10_hours"] for b in rated)
    main = data["bearings"][-1]
    assert main["status"] == "needs_external_load" and main["l10_hours"] is None
    assert main["speed_rpm"] == pytest.approx(15.0, rel=1e-14)


def test_text_and_options(cli):
    res = cli("life", *BEARINGS, "--positions", "81", "--torque", "300", "--output-speed",
              "10")
    assert res.code == 0 and res.err == "", res.err
    lines = res.out.splitlines()
    assert lines[0].startswith("RV-40E-bearings at 300 N*m, output 10 rpm (cranks 400 rpm")
    assert len(lines) == 2 + 9 + 2 and "needs_external_load" in lines[-3]
    assert lines[-2].startswith("rating life ") and "catalogue rule" in lines[-1]


def test_main_bearing_loads(cli):
    res = cli("life", *BEARINGS, "--positions", "81", "--moment", "800", "--thrust", "2000",
              "--json")
    assert res.code == 0, res.err
    data = json.loads(res.out)
    rows = [b for b in data["bearings"] if b["name"].startswith("main")]
    assert [b["status"] for b in rows] == ["ok", "ok"] and len(data["bearings"]) == 10
    # 13 561 N on the worse row (tests/verification/test_life.py), 7188 h at 15 rpm: now the
    # shortest life; the ratio to the catalogue stays the crank bearings'
    assert data["limiting_bearing"] == "main bearing row 2"
    assert data["life_hours"] == pytest.approx(7188.0, abs=1.0)
    assert data["crank_life_hours"] > data["life_hours"]
    assert data["life_ratio_to_catalogue"] == pytest.approx(
        data["crank_life_hours"] / 6000.0, rel=1e-12)


def test_above_rated_torque_warns(cli):
    res = cli("life", *BEARINGS, "--positions", "81", "--torque", "824", "--json")
    assert res.code == 0 and json.loads(res.out)["status"] == "ok"
    assert res.err.startswith("rvsim: warning: --torque: 824 N*m is above the rated torque")
    assert res.err.count("\n") == 1


def test_help_lists_life(cli):
    res = cli("--help")
    assert "life" in res.out
    res = cli("life", "--help")
    assert res.code == 0 and "--output-speed" in res.out and "ISO 281" in res.out


def test_failed_solve_is_a_status(cli):
    # the momentary rating raised with it (as in the ltca hostile test): the solve does not
    # converge, exit 1, every crank bearing carries the status and no life
    res = cli("life", *BEARINGS, "--positions", "81", "--torque", "1e9", "--json",
              "--set", "rating.start_stop_torque=1e9", "--set", "rating.momentary_torque=1e9")
    assert res.code == 1
    data = json.loads(res.out)
    assert data["status"] == "not_converged" and data["life_hours"] is None
    crank = [b for b in data["bearings"] if not b["name"].startswith("main")]
    assert {b["status"] for b in crank} == {"not_converged"}
    assert all(b["l10_hours"] is None for b in crank)
    assert res.err.splitlines()[0] == "rvsim: life failed: status not_converged"
