"""Per-part errors (issue 11 item 1): their effect on the exact pin gaps and both engines."""

import dataclasses
import math

import numpy as np
import pytest

from rvsim.errors import ParameterError
from rvsim.geometry import pin_gaps
from rvsim.geometry.assembly import check_assembly
from rvsim.geometry.cycloid import pin_centres
from rvsim.geometry.deviations import pin_table
from rvsim.parameters import RV40E, PartErrors, validate, with_values

#: bushing clearances opened (built unchecked: a check at collection would call compiled
#: functions while the warm-up compiles them; the values are the valid ones of paper run levels)
OPEN = with_values(RV40E, {"I": 0.02, "K": 0.01}, check=False)
ZP, ZC = RV40E.cycloid.pin_count, RV40E.cycloid.disc_teeth


def parts(r, **kw):
    return dataclasses.replace(r, parts=PartErrors(**kw))


def test_no_part_errors_leave_the_pins_and_gaps_unchanged():
    table = pin_table(OPEN)
    assert table.shape == (ZP, 3)
    np.testing.assert_array_equal(table[:, :2], pin_centres(OPEN))
    assert not table[:, 2].any()


def test_a_larger_pin_closes_its_own_gap_by_its_radius_deviation():
    d = np.zeros(ZP)
    d[7] = 3e-6
    before = pin_gaps(OPEN, 0.3)
    after = pin_gaps(parts(OPEN, pin_radius=tuple(d)), 0.3)
    np.testing.assert_allclose(before - after, d, atol=1e-13)


def test_pin_hole_clearance_opens_every_gap_by_half_of_it():
    after = pin_gaps(with_values(OPEN, {"errors.pin_hole_clearance": 0.004}), 0.3)
    np.testing.assert_allclose(after - pin_gaps(OPEN, 0.3), 2e-6, atol=1e-13)


def test_every_pin_moved_outwards_equals_the_pin_circle_error():
    a = pin_gaps(parts(OPEN, pin_radial=(5e-6,) * ZP), 0.2)
    b = pin_gaps(with_values(OPEN, {"H": 0.005}), 0.2)
    np.testing.assert_allclose(a, b, atol=1e-13)


def test_a_disc_phase_equals_the_disc_turned_by_it():
    delta = 2e-6                                   # rad: 0.16 um at the pin circle
    a = pin_gaps(parts(OPEN, disc_phase=(delta, 0.0)), 0.2)
    b = pin_gaps(OPEN, 0.2, extra_rotation=delta)
    moved = pin_gaps(OPEN, 0.2) - b
    # first-order model of the turned flank: agrees to its second-order term (the gap's
    # curvature in the rotation, ~30 m/rad^2: 6e-11 m here), 0.1 % of the change
    assert np.max(np.abs(a - b)) < 1e-3 * np.max(np.abs(moved))


def test_a_constant_profile_deviation_equals_a_negative_equidistant_modification():
    a = pin_gaps(parts(OPEN, profile_harmonics=((0, 0, 4e-6, 0.0),)), 0.2)
    b = pin_gaps(with_values(OPEN, {"I": 0.016}), 0.2)
    np.testing.assert_allclose(a, b, atol=1e-12)
    # disc 2 is untouched
    np.testing.assert_allclose(pin_gaps(parts(OPEN, profile_harmonics=((0, 0, 4e-6, 0.0),)),
                                        0.2, disc=1), pin_gaps(OPEN, 0.2, disc=1), atol=1e-13)


def test_measured_profile_points_are_interpolated_periodically():
    u = np.linspace(0.0, 2.0 * math.pi, 200, endpoint=False)
    points = tuple((float(x), 3e-6) for x in u)
    a = pin_gaps(parts(OPEN, profile_points=(points, ())), 0.2)
    b = pin_gaps(with_values(OPEN, {"I": 0.017}), 0.2)
    np.testing.assert_allclose(a, b, atol=1e-12)


def test_assembly_check_covers_part_errors():
    with pytest.raises(ParameterError, match="arm bushing"):
        validate(parts(OPEN, disc_holes=((12e-6, 0.0, 0.0, 0.0), (0.0,) * 4)))
    validate(parts(OPEN, disc_holes=((8e-6, 0.0, 0.0, 0.0), (0.0,) * 4)))
    with pytest.raises(ParameterError, match="overlaps pin"):
        check_assembly(parts(OPEN, pin_radius=(25e-6,) + (0.0,) * (ZP - 1)))
    with pytest.raises(ParameterError, match="arm bushing"):
        validate(parts(OPEN, eccentricity=(11e-6, 0.0, 0.0, 0.0)))


def test_wrong_lengths_name_the_field():
    with pytest.raises(ParameterError, match="parts.pin_radius"):
        validate(parts(OPEN, pin_radius=(1e-6,) * 3))
    with pytest.raises(ParameterError, match="parts.disc_pitch"):
        validate(parts(OPEN, disc_pitch=((0.0,) * ZC,)))


def test_quasi_static_engine_sees_each_eccentric():
    from rvsim.quasistatic import ltca

    # every eccentric 2 um smaller equals the uniform eccentricity error G = 2 um
    a = ltca(parts(OPEN, eccentricity=(-2e-6,) * 4), positions=12,
             allow_aliasing=True)
    b = ltca(with_values(OPEN, {"G": 0.002}), positions=12, allow_aliasing=True)
    np.testing.assert_allclose(a.te, b.te, atol=1e-9)


def test_dynamic_engine_runs_with_every_part_error():
    from rvsim.dynamics import simulate

    rng = np.random.default_rng(0)
    r = with_values(OPEN, {"operating.duration": 0.4, "operating.speed_ramp_time": 0.1,
                           "operating.load_start": 0.1, "operating.load_ramp_end": 0.2,
                           "operating.steady_start": 0.3})
    drawn = parts(r, pin_radial=tuple(rng.uniform(-2e-6, 2e-6, ZP)),
                  pin_radius=tuple(rng.uniform(-1e-6, 1e-6, ZP)),
                  disc_pitch=(tuple(rng.uniform(-3e-6, 3e-6, ZC)), (0.0,) * ZC),
                  eccentricity=(1e-6, 0.0, 0.0, -1e-6), eccentric_phase=(1e-4, 0, 0, 0),
                  disc_holes=((1e-6, 0, 0, 1e-6), (0.0,) * 4), carrier_holes=(2e-6, 0, 0, 0))
    a, b = simulate(drawn), simulate(r)
    assert a.status == "ok" and b.status == "ok"
    assert a.summary()["te_mean_arcmin"] != b.summary()["te_mean_arcmin"]
