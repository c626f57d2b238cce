"""Parameter sets: SI storage, user units at the edges, TOML, overrides, validation."""

import dataclasses
import math

import pytest

from rvsim.errors import InputFileError, ParameterError
from rvsim.parameters import (RV40E, SPECS, TABLE2_FACTORS, get_value, load_toml,
                              parameter_table, with_values)


def test_rv40e_is_the_paper_set():
    c = RV40E.cycloid
    assert RV40E.ratio == pytest.approx(121.0)
    assert c.eccentricity == pytest.approx(1.5e-3)
    assert c.pin_circle_radius == pytest.approx(82e-3)
    assert (c.disc_teeth, c.pin_count) == (39, 40)
    assert RV40E.curtate_ratio == pytest.approx(1.5 * 40 / 82)
    assert RV40E.materials.pin.elastic_modulus == pytest.approx(1.68e11)
    assert RV40E.operating.load_torque == 300.0
    assert "Rotate Vector" in RV40E.citation
    assert dataclasses.is_dataclass(RV40E) and RV40E.__dataclass_params__.frozen


def test_errors_default_to_zero():
    for name in SPECS:
        if name.startswith(("errors.", "clearances.")):
            assert get_value(RV40E, name) == 0.0


def test_user_units_convert_to_si():
    r = with_values(RV40E, {"errors.pin_circle_radius": 0.02, "operating.input_speed": 3600,
                            "materials.pin.elastic_modulus": 200})
    assert r.errors.pin_circle_radius == pytest.approx(2e-5)
    assert r.operating.input_speed == pytest.approx(2 * math.pi * 10)
    assert r.materials.pin.elastic_modulus == pytest.approx(2e11)
    assert get_value(r, "errors.pin_circle_radius") == pytest.approx(0.02)


def test_factor_letters_are_aliases():
    r = with_values(RV40E, {"H": 0.03, "A": "yes", "E": 400})
    assert r.errors.pin_circle_radius == pytest.approx(3e-5)
    assert r.flexibility.cycloid_disc is True
    assert r.operating.load_torque == 400
    assert set(TABLE2_FACTORS) == set("ABCDEFGHIJKLMNO")


def test_parameter_table_lists_every_field_with_unit():
    rows = parameter_table(RV40E)
    assert len(rows) == len(SPECS) > 60
    assert all(row["unit"] for row in rows)


def test_a_seed_is_no_count():
    # a reviewer's case: the count ceiling refused a seed of 123456
    seeded = with_values(RV40E, {"errors.pin_position_seed": 20261127})
    assert seeded.errors.pin_position_seed == 20261127
    with pytest.raises(ParameterError, match="123456 is beyond any reducer"):
        with_values(RV40E, {"cycloid.pillar_hole_count": 123456})


@pytest.mark.parametrize("values, field, words", [
    ({"nonsense.key": 1}, "nonsense.key", "unknown parameter"),
    ({"cycloid.eccentricity": "abc"}, "cycloid.eccentricity", "not a number"),
    ({"cycloid.eccentricity": "nan"}, "cycloid.eccentricity", "finite"),
    ({"cycloid.pin_radius": -3}, "cycloid.pin_radius", "greater than 0"),
    ({"clearances.support_carrier": -0.01}, "clearances.support_carrier", "negative"),
    ({"cycloid.pin_count": 41}, "cycloid.pin_count", "disc_teeth + 1"),
    ({"cycloid.pin_count": 40.5}, "cycloid.pin_count", "whole number"),
    ({"cycloid.eccentricity": 2.1}, "cycloid.eccentricity", "K1"),
    ({"cycloid.pin_radius": 8}, "cycloid.pin_radius", "undercut"),
    ({"flexibility.pin": "maybe"}, "flexibility.pin", "yes/no"),
    ({"errors.eccentricity": 1.6}, "errors.eccentricity", "smaller than"),
    ({"operating.steady_start": 5}, "operating.steady_start", "earlier"),
    # found by a hostile review: an OverflowError traceback, an inf TE printed with exit 0,
    # and counts of 1e308 accepted
    ({"gears.module": 1e308}, "gears.module", "1e+308 mm is beyond any reducer (at most "
                                              "1e+18 mm)"),
    ({"H": 1e308}, "errors.pin_circle_radius", "beyond any reducer"),
    ({"cycloid.pillar_hole_count": 1e308}, "cycloid.pillar_hole_count", "1e+308 is beyond "
                                                                        "any reducer (at most "
                                                                        "100000)"),
])
def test_bad_values_name_field_and_reason(values, field, words):
    with pytest.raises(ParameterError) as info:
        with_values(RV40E, values)
    assert info.value.field == field
    assert words in str(info.value)
    assert "\n" not in str(info.value)


def test_toml_round_trip(tmp_path, cli):
    text = cli("params", "--toml", "--set", "H=0.02").out
    path = tmp_path / "mine.toml"
    path.write_text(text)
    r = load_toml(path)
    assert r.errors.pin_circle_radius == pytest.approx(2e-5)
    assert r == with_values(RV40E, {"H": 0.02})


def test_toml_partial_file_keeps_base_values(tmp_path):
    path = tmp_path / "r.toml"
    path.write_text('name = "my RV"\n[cycloid]\neccentricity = 1.4\n[flexibility]\npin = true\n')
    r = load_toml(path)
    assert r.name == "my RV"
    assert r.cycloid.eccentricity == pytest.approx(1.4e-3)
    assert r.flexibility.pin is True
    assert r.cycloid.pin_radius == RV40E.cycloid.pin_radius


@pytest.mark.parametrize("content, words", [
    ("[cycloid]\nfoo = 1\n", "unknown parameter"),
    ("[cycloid]\neccentricity = 'x'\n", "not a number"),
    ("[cycloid\n", "not valid TOML"),
    ('base = "RV-999"\n', "unknown parameter set"),
    ("[flexibility]\npin = 3\n", "yes/no"),
])
def test_bad_toml(tmp_path, content, words):
    path = tmp_path / "bad.toml"
    path.write_text(content)
    with pytest.raises((ParameterError, InputFileError), match=words):
        load_toml(path)


def test_missing_toml_file(tmp_path):
    with pytest.raises(InputFileError, match="not found"):
        load_toml(tmp_path / "absent.toml")


@pytest.mark.parametrize("name", ['my "RV" \\ test', "tab\there", "new\nline", "bell\x07 del\x7f",
                                  "unicode: \u00e9\u4e2d", "'single' \"\"\"triple\"\"\""])
def test_toml_string_round_trips(name):
    import tomllib

    from rvsim.parameters._io import toml_string

    assert tomllib.loads(f"name = {toml_string(name)}")["name"] == name


def test_absurd_tooth_count_blames_the_tooth_count(rv40e):
    for field in ("gears.sun_teeth", "gears.planet_teeth"):
        with pytest.raises(ParameterError) as info:
            with_values(rv40e, {field: "1e20"})
        assert info.value.field == field
