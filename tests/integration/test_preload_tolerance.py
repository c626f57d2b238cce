"""A tolerance run keeps a drawn reducer whose crank hole interferes with needles without
clearance: assembled with elastic preload (issue 32 item 2), not dropped as ``binds``.

`RV-40E-bearings` (needles and tapered rollers without clearance, K = M = 0) with the crank
holes in the discs drawn within +-3 um: every reducer of such a run was dropped before
(docs/validation.md, issue 32); both reducers drawn here interfere (crank 2's needles in
disc 1 by 3.44 um, 1198 MPa; crank 1's in disc 2 by 3.41 um) and are analysed, the median
rigidity pinned (measured 2026-11-28: 561.45 N*m/arcmin).
"""

import json

import pytest

STUDY = """
name = "needles without clearance"
params = "RV-40E-bearings"
samples = 2
seed = 1
positions = 81
[set]
"operating.load_torque" = 412
"errors.equidistant_modification" = 0.010
[tolerances.disc_holes]
tolerance = 0.003
"""


def test_tolerance_run_keeps_a_reducer_with_a_small_interference(tmp_path, cli):
    from rvsim.bearings import roller_preloads
    from rvsim.tolerance.spec import load_tolerance_study

    path = tmp_path / "needles.toml"
    path.write_text(STUDY)
    study = load_tolerance_study(path)
    drawn = study.realise(study.unit_sample(0), None, study.nominal)
    worst = max(roller_preloads(drawn), key=lambda p: p.interference)
    assert worst.interference == pytest.approx(PINNED["interference"], abs=1e-13)
    res = cli("tolerance", str(path), "--out", str(tmp_path / "o"), "--workers", "1",
              "--json", "--no-report", "--no-progress")
    assert res.code == 0, res.err
    summary = json.loads(res.out)
    assert summary["ok"] == 2 and summary["binds"] == 0 and summary["failed"] == 0
    rigidity = summary["metrics"]["torsional_rigidity_nm_per_arcmin"]["p50"]
    assert rigidity == pytest.approx(PINNED["rigidity"], rel=1e-6)


PINNED = {"interference": 3.4357988e-06, "rigidity": 561.45480}
