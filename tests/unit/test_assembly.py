"""Interference at the assembled pose is a one-line parameter error (issue 8, item 2)."""


import pytest

from rvsim.errors import ParameterError
from rvsim.geometry.assembly import CONTACT_TOLERANCE, assembly_overlaps, check_assembly
from rvsim.geometry.cycloid import nominal_disc_pose
from rvsim.parameters import RV40E, paper_run_values, with_values
from tests.integration.conftest import factors, write_study


def _overlaps(values):
    reducer = with_values(RV40E, values, check=False)
    return {o.parts: o.approach for o in assembly_overlaps(reducer)}


def test_eccentricity_error_alone_overlaps_the_opposite_pin_by_g():
    approach = _overlaps({"G": 0.005})
    assert approach["disc 1 overlaps pin 20 (at 180 deg)"] == pytest.approx(5e-6, abs=1e-12)
    assert approach["disc 2 overlaps pin 0 (at 0 deg)"] == pytest.approx(5e-6, abs=1e-12)
    with pytest.raises(ParameterError) as info:
        with_values(RV40E, {"G": 0.005})
    assert info.value.field == "assembly"
    assert "disc 1 overlaps pin 20 (at 180 deg) by 5.0 um" in info.value.reason
    assert "errors.eccentricity = 0.005 mm" in info.value.reason


def test_large_eccentricity_error_is_one_line_at_the_cli(cli):
    res = cli("simulate", "--set", "G=0.3")
    assert res.code == 2 and res.err.count("\n") == 1
    assert "overlaps pin 20 (at 180 deg) by 300.0 um" in res.err


@pytest.mark.parametrize("closing", [{"errors.rotation_modification": 1.0},
                                     {"errors.disc_runout": 0.014},
                                     {"errors.pin_position_tolerance": 0.005}])
def test_other_closing_errors_need_opening_clearance(closing):
    name = next(iter(closing))
    with pytest.raises(ParameterError, match=name):
        with_values(RV40E, closing)
    with_values(RV40E, {**closing, "I": 0.03})  # the equidistant modification makes room


def test_overlap_within_round_off_is_contact():
    check_assembly(with_values(RV40E, {"G": 0.5 * CONTACT_TOLERANCE * 1e3}, check=False))
    with pytest.raises(ParameterError, match="assembly"):
        check_assembly(with_values(RV40E, {"G": 2.0 * CONTACT_TOLERANCE * 1e3}, check=False))


def test_bushings_and_meshes_start_centred():
    values = {"K": 0.003, "M": 0.004, "L": 0.002, "N": 0.005, "O": 0.001,
              "gears.backlash": 0.01, "G": 0.01, "I": 0.03}
    approach = _overlaps(values)
    arm = [v for k, v in approach.items() if "arm bushing" in k]
    assert arm == pytest.approx([-7e-6] * 4, abs=1e-15)
    lower = [v for k, v in approach.items() if "lower" in k]
    upper = [v for k, v in approach.items() if "upper" in k]
    assert lower == pytest.approx([-3e-6] * 2) and upper == pytest.approx([-6e-6] * 2)
    assert [v for k, v in approach.items() if "sun" in k] == pytest.approx([-5e-6] * 2)


def test_the_checked_pose_is_the_dynamic_models_initial_state():
    from rvsim.physics import _layout as L
    from rvsim.dynamics.model import build_model

    reducer = with_values(RV40E, {"G": 0.01, "I": 0.03})
    q0 = build_model(reducer, 1e-5).q0
    model = build_model(reducer, 1e-5)
    for disc in range(2):
        d = L.DISC0 + L.DISC_STRIDE * disc
        assert q0[d:d + 3] == pytest.approx(nominal_disc_pose(reducer, 0.0, disc), abs=1e-15)
    for crank in range(2):   # both support nodes on the bore centre, eccentric phase 0
        b = L.CRANK0 + L.CRANK_STRIDE * crank
        assert q0[b:b + 5] == pytest.approx([*model.holes[crank], *model.holes[crank], 0.0])
    assert q0[L.CARRIER] == 0.0


def test_every_paper_l36_run_assembles():
    # G is combined with I and J, which open more than G closes: the tightest run (1) keeps
    # 50.1 um at its tightest pin
    smallest = min(-max(o.approach for o in assembly_overlaps(
        with_values(RV40E, paper_run_values(run))) if "pin" in o.parts) for run in range(1, 37))
    assert smallest == pytest.approx(50.13e-6, abs=0.01e-6)


def test_study_with_an_interfering_row_fails_before_any_run(tmp_path, cli):
    path = write_study(tmp_path, factors=factors(G=("G", [0.0, 0.005]), I=("I", [0.0, 0.03]),
                                                 E=("operating.load_torque", [100, 300])))
    out = tmp_path / "out"
    res = cli("study", str(path), "--out", str(out))
    assert res.code == 2 and res.err.count("\n") == 1
    assert "overlaps pin" in res.err and "(study run 3)" in res.err
    assert not (out / "results.sqlite").exists()
