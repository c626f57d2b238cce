"""Verification of the cycloid geometry against analytic limits.

* the unmodified profile is conjugate: every pin touches (gap 0 +- 1e-6 mm, no overlap) at every
  crank angle of a full turn, for both discs;
* Table 2 modifications open clearance at every pin;
* the backlash found geometrically (disc turned to first contact, crank held) agrees with
  Eq. (6) within 1 % (measured: 0.02 % to 0.5 %; Eq. (6) takes the pin of longest lever arm);
* the profile is closed and has 39 lobes.
"""

import math

import numpy as np
import pytest

from rvsim.geometry import geometric_backlash, pin_gaps, profile_of
from rvsim.geometry.cycloid import profile_offset
from rvsim.parameters import RV40E, with_values

CRANK_ANGLES = np.linspace(0.0, 2.0 * np.pi, 181)


@pytest.mark.parametrize("disc", [0, 1])
def test_unmodified_profile_touches_every_pin(disc):
    worst = 0.0
    for beta in CRANK_ANGLES:
        gaps = pin_gaps(RV40E, beta, disc=disc)
        worst = max(worst, float(np.max(np.abs(gaps))))
    assert worst < 1e-9  # metres: 1e-6 mm


@pytest.mark.parametrize("levels", [dict(I=0.016, J=0.026), dict(I=0.048, J=0.078),
                                    dict(F=0.01), dict(H=0.03), dict(I=0.032)])
def test_modifications_open_clearance_everywhere(levels):
    reducer = with_values(RV40E, levels)
    for beta in CRANK_ANGLES[::10]:
        assert np.min(pin_gaps(reducer, beta)) > 0.0


@pytest.mark.parametrize("equidistant, radial", [(0.016, 0.0), (0.0, 0.026), (0.016, 0.026),
                                                 (0.032, 0.052), (0.048, 0.078)])
def test_backlash_agrees_with_eq6(equidistant, radial):
    reducer = with_values(RV40E, {"I": equidistant, "J": radial})
    k1 = reducer.curtate_ratio
    # Eq. (6) with the radial-moving amount removing material (Delta r_p = -J)
    eq6 = 2.0 / (1.5 * 39) * (equidistant + radial * math.sqrt(1.0 - k1 * k1))
    for beta in np.linspace(0.0, 2.0 * np.pi / 40, 4):
        forward, backward = geometric_backlash(reducer, beta)
        assert forward + backward == pytest.approx(eq6, rel=0.01)
        assert forward == pytest.approx(backward, rel=0.02)


def test_profile_is_closed_with_39_lobes():
    prof = profile_of(with_values(RV40E, {"I": 0.016, "J": 0.026}))
    pts = prof.points(39 * 200)
    radius = np.hypot(pts[:, 0], pts[:, 1])
    peaks = (radius > np.roll(radius, 1)) & (radius >= np.roll(radius, -1))
    assert int(peaks.sum()) == 39
    step = np.linalg.norm(np.diff(np.vstack([pts, pts[:1]]), axis=0), axis=1)
    assert step.max() < 5 * step.mean()  # no jump: last point joins the first
    c = RV40E.cycloid
    assert radius.max() == pytest.approx(c.pin_circle_radius + c.eccentricity - c.pin_radius
                                         - 0.016e-3 - 0.026e-3, abs=1e-9)


def test_pin_position_errors_are_bounded_and_reproducible():
    from rvsim.geometry import pin_centres

    values = {"errors.pin_position_tolerance": 0.005, "errors.pin_position_seed": 7}
    # pin errors alone make the pins overlap the disc (no check): only the centres matter here
    a = pin_centres(with_values(RV40E, values, check=False))
    b = pin_centres(with_values(RV40E, values, check=False))
    nominal = pin_centres(RV40E)
    np.testing.assert_array_equal(a, b)
    radial = np.hypot(a[:, 0], a[:, 1]) - 82e-3
    assert np.abs(radial).max() <= 5e-6 and np.abs(radial).max() > 1e-6
    assert np.linalg.norm(a - nominal, axis=1).max() <= 5e-6 * math.sqrt(2) + 1e-12
    other = pin_centres(with_values(RV40E, {**values, "errors.pin_position_seed": 8},
                                    check=False))
    assert not np.allclose(a, other)


def test_runout_moves_the_profile_by_half_of_it():
    # runout alone overlaps pins at assembly (validation rejects it); the geometry is tested here
    reducer = with_values(RV40E, {"errors.disc_runout": 0.02}, check=False)
    gaps = pin_gaps(reducer, 0.0)
    # shifting the profile centre by 0.01 mm changes gaps by at most 0.01 mm, both signs
    assert np.abs(gaps).max() == pytest.approx(1e-5, rel=0.05)
    assert gaps.min() < 0 < gaps.max()


def test_runout_phase_turns_the_profile_offset():
    base = with_values(RV40E, {"errors.equidistant_modification": 0.01,
                               "errors.disc_runout": 0.006})
    turned = with_values(base, {"errors.disc_runout_phase": 90.0})
    for disc in (0, 1):
        x0, y0 = profile_offset(base, disc)
        x1, y1 = profile_offset(turned, disc)
        assert math.hypot(x1, y1) == pytest.approx(3e-6, rel=1e-12)
        # turned a quarter turn counter-clockwise in the profile's axes
        assert (x1, y1) == pytest.approx((-y0, x0), abs=1e-18)
