"""The paper's three test prototypes (issue 33, item 3): the files of docs/examples load, hold
Table 7's part data and the bearing clearances of Sec. 3.5, the Table 1 error file holds
Table 1's sizes, and the documented command runs (docs/validation.md, "Prototype predictions
(made before any comparison)")."""

import csv
import json
from pathlib import Path

import pytest

from rvsim.parameters import load_toml
from rvsim.tolerance.spec import load_tolerance_study

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "docs" / "examples"
TABLE1 = ROOT / "tests" / "reference" / "data" / "table1_sensitivity.csv"

# Table 7 (mm): pin gear radius, eccentricity, pin centre circle radius, equidistant and
# radial-moving modification; Sec. 3.5: the arm and support bearings' clearance; Sec. 3.5 and
# Table 3: L36 run (its load level E, N*m) of the virtual prototype each one was built from
TABLE7 = {1: (2.980, 1.490, 82.020, 0.032, 0.052, 0.005, 0.005, 300.0),
          2: (2.970, 1.485, 82.030, 0.048, 0.078, 0.010, 0.010, 400.0),
          3: (2.990, 1.495, 82.010, 0.032, 0.052, 0.010, 0.005, 200.0)}
# Table 3 rows 2, 3, 4: levels of K, L, M, N, O (Table 2: 0, 0.005, 0.010 mm)
RUN_CLEARANCES = {1: (0.005,) * 5, 2: (0.010,) * 5, 3: (0.005, 0.005, 0.010, 0.010, 0.010)}
MM = 1e-3


def _sizes(r):
    c, e = r.cycloid, r.errors
    return (c.pin_radius - e.pin_radius, c.eccentricity - e.eccentricity,
            c.pin_circle_radius + e.pin_circle_radius, e.equidistant_modification,
            e.radial_modification)


@pytest.mark.parametrize("n", [1, 2, 3])
def test_prototype_files_hold_table7(n):
    bushings = load_toml(EXAMPLES / f"prototype_{n}.toml")
    bearings = load_toml(EXAMPLES / f"prototype_{n}_bearings.toml")
    *sizes, arm, support, load = TABLE7[n]
    for r in (bushings, bearings):
        assert _sizes(r) == pytest.approx([s * MM for s in sizes], abs=1e-12)
        assert r.operating.load_torque == load
        assert (r.flexibility.cycloid_disc, r.flexibility.pin, r.flexibility.arm_bushing) \
            == (True, True, True)
    # the paper's bushings: run n + 1's clearances K-O; no rolling bearings
    cl = bushings.clearances
    assert (cl.crank_arm_bushing, cl.support_flange, cl.disc_arm_bushing, cl.support_carrier,
            cl.crank_support_bushing) == pytest.approx([c * MM for c in RUN_CLEARANCES[n]])
    assert not bushings.bearings.arm_needles and not bushings.bearings.support_rollers
    # the bearings: Sec. 3.5's internal clearances, no bushing clearance on top
    b = bearings.bearings
    assert b.arm_needles and b.support_rollers
    assert (b.needle_clearance, b.support_clearance) == pytest.approx((arm * MM, support * MM))
    assert not any(vars(bearings.clearances).values())


def test_prototypes_differ_where_table7_says():
    files = {n: load_toml(EXAMPLES / f"prototype_{n}_bearings.toml") for n in TABLE7}
    # TP 1 and TP 3 share the modifications and the support bearings, nothing else of Table 7
    same = [a == pytest.approx(b, abs=1e-12) for a, b in zip(_sizes(files[1]),
                                                             _sizes(files[3]))]
    assert same == [False, False, False, True, True]
    assert files[1].bearings.needle_clearance != files[3].bearings.needle_clearance
    assert all(x != pytest.approx(y, abs=1e-12)
               for x, y in zip(_sizes(files[1]), _sizes(files[2])))


def test_error_file_holds_table1_sizes():
    study = load_tolerance_study(EXAMPLES / "table1_errors.toml")
    rows = {int(r["serial"]): float(r["error_value_mm"])
            for r in csv.DictReader(line for line in TABLE1.open() if not line.startswith("#"))}
    tol = {t.name: t for t in study.tolerances}
    nominal = study.nominal.errors
    assert nominal.pin_hole_clearance == pytest.approx(rows[4] * MM)          # row 4
    assert nominal.disc_runout == pytest.approx(rows[7] * MM)                 # row 7
    assert tol["errors.disc_runout_phase"].tolerance == 180.0
    for name, row in (("pin_tangential", 3), ("pin_radial", 3), ("disc_pitch", 8)):
        assert tol[name].distribution == "uniform"                            # +- half
        assert 2.0 * tol[name].tolerance == pytest.approx(rows[row])
    assert study.seed == 1 and study.positions == 360


def test_the_documented_command_gives_a_band(tmp_path, cli):
    out = tmp_path / "tp3"
    res = cli("tolerance", str(EXAMPLES / "table1_errors.toml"), "--params",
              str(EXAMPLES / "prototype_3_bearings.toml"), "--out", str(out),
              "--samples", "2", "--workers", "1", "--no-report", "--json")
    assert res.code == 0, res.err
    summary = json.loads(res.out)
    assert summary["reducer"] == "test prototype 3 (bearings)" and summary["torque_nm"] == 200
    assert summary["ok"] + summary["binds"] == 2
    ate = summary["metrics"]["ate_arcmin"]
    assert ate["n"] == summary["ok"] and (not ate["n"] or ate["p5"] <= ate["p95"])


def test_params_that_do_not_load_are_one_line(tmp_path, cli):
    out = tmp_path / "o"
    res = cli("tolerance", str(EXAMPLES / "table1_errors.toml"), "--params",
              str(tmp_path / "missing.toml"), "--out", str(out))
    assert res.code == 2 and res.err.count("\n") == 1 and res.err.startswith("rvsim: error:")
    assert not out.exists()
