"""Either sign of F, H, I and J (issue 9, item 5): the exact gaps and the assembly check decide."""

import textwrap

import numpy as np
import pytest

from rvsim.errors import ParameterError
from rvsim.geometry.cycloid import pin_centres, pin_gaps, profile_of
from rvsim.parameters import RV40E, with_values

UM = 1e-6


@pytest.mark.parametrize("letter, parameter", [
    ("F", "errors.pin_radius"), ("H", "errors.pin_circle_radius"),
    ("I", "errors.equidistant_modification"), ("J", "errors.radial_modification")])
def test_negative_alone_is_interference(letter, parameter):
    # each alone closes the clearance by 10 um at some pin; the assembly check names it
    with pytest.raises(ParameterError, match=rf"overlaps pin .* by 10\.0 um .*{parameter} = -0\.01"):
        with_values(RV40E, {letter: -0.01})


def test_negative_values_reach_the_geometry():
    r = with_values(RV40E, {"I": -0.01, "J": 0.015})
    prof = profile_of(r)
    assert prof.offset == pytest.approx(3e-3 - 10 * UM, abs=1e-15)
    assert prof.generating_radius == pytest.approx(82e-3 - 15 * UM, abs=1e-15)
    r = with_values(RV40E, {"J": -0.01, "I": 0.02})
    assert profile_of(r).generating_radius == pytest.approx(82e-3 + 10 * UM, abs=1e-15)
    r = with_values(RV40E, {"H": -0.01, "I": 0.02})
    assert np.hypot(*pin_centres(r).T) == pytest.approx(82e-3 - 10 * UM, abs=1e-15)
    # a pin 10 um bigger with a 10 um larger pin circle: the gap at the pin on the
    # eccentric's side changes by -F + H = 0 (both along the normal there)
    r = with_values(RV40E, {"F": -0.01, "I": 0.01})
    assert np.min(pin_gaps(r, 0.0)) == pytest.approx(0.0, abs=1e-12)


def test_negative_equidistant_with_larger_radial_moving_nearly_cancels():
    # -10 um equidistant and +15 um radial-moving: the working flank keeps a gap under
    # 0.3 um (measured 0.232 um), the tooth tips and roots get 5 um; it assembles
    r = with_values(RV40E, {"I": -0.01, "J": 0.015})
    gaps = pin_gaps(r, 0.0)
    assert 0.0 < gaps.min() < 0.3 * UM
    assert gaps.max() == pytest.approx(5 * UM, rel=1e-6)
    # with a radial-moving modification too small to compensate, it does not
    with pytest.raises(ParameterError, match=r"disc 1 overlaps pin .* by 3\.2 um"):
        with_values(RV40E, {"I": -0.01, "J": 0.01})


def test_rotation_modification_is_a_study_factor(tmp_path):
    from rvsim.doe import load_study

    path = tmp_path / "rot.toml"
    path.write_text(textwrap.dedent("""
        design = "L9"
        [set]
        I = 0.03
        [factors.R]
        parameter = "errors.rotation_modification"
        levels = [-1.0, 0.0, 1.0]
        [factors.J]
        parameter = "J"
        levels = [-0.01, 0.0, 0.01]
    """))
    study = load_study(path)
    reducers = study.reducers()
    rotations = sorted({r.errors.rotation_modification for r in reducers})
    assert rotations == pytest.approx(np.array([-1.0, 0.0, 1.0]) * np.pi / 10800)
    assert min(r.errors.radial_modification for r in reducers) == pytest.approx(-10 * UM)
