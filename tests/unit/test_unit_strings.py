"""Values typed with a unit (issue 34 item 6): ``--set operating.input_speed=1000rpm``,
``--set clearances.crank_arm_bushing=5um``; SI inside, the listed unit when none is typed.

Hand conversions: 1000 rpm = 1000 x 360 deg / 60 s = 6000 deg/s; 5 um = 0.005 mm = 5e-6 m;
30 arcmin = 0.5 deg; 206 000 MPa = 206 GPa; 7.85 g/cm^3 = 7850 kg/m^3; 100 cSt = 100 mm^2/s
= 1e-4 m^2/s; 1 h = 3600 s; 2 min = 120 s.
"""

from __future__ import annotations

import json
import math

import pytest

from rvsim.errors import ParameterError
from rvsim.parameters import RV40E, with_values
from rvsim.parameters._io import SPECS, get_value
from rvsim.units import ALIASES, DIMENSION, TO_SI, si_from_text

ACCEPTED = [
    # field, typed, SI value
    ("operating.input_speed", "1000rpm", 1000.0 * 2.0 * math.pi / 60.0),
    ("operating.input_speed", "1000 rpm", 1000.0 * 2.0 * math.pi / 60.0),
    ("operating.input_speed", "2e3 r/min", 2000.0 * 2.0 * math.pi / 60.0),
    ("operating.input_speed", "6000deg/s", 6000.0 * math.pi / 180.0),
    ("operating.input_speed", "10 rad/s", 10.0),
    ("clearances.crank_arm_bushing", "5um", 5e-6),
    ("clearances.crank_arm_bushing", "5 \u00b5m", 5e-6),       # micro sign
    ("clearances.crank_arm_bushing", "5\u03bcm", 5e-6),        # Greek mu
    ("clearances.crank_arm_bushing", "0.005mm", 5e-6),
    ("clearances.crank_arm_bushing", "5e-6 m", 5e-6),
    ("clearances.crank_arm_bushing", "-.5um", -5e-7),
    ("errors.rotation_modification", "0.5 arcmin", 0.5 * math.pi / 180.0 / 60.0),
    ("errors.rotation_modification", "30arcsec", 0.5 * math.pi / 180.0 / 60.0),
    ("gears.pressure_angle", "20deg", 20.0 * math.pi / 180.0),
    ("gears.pressure_angle", "20\u00b0", 20.0 * math.pi / 180.0),
    ("materials.planet_gear.elastic_modulus", "206000MPa", 206e9),
    ("materials.planet_gear.elastic_modulus", "206000 N/mm^2", 206e9),
    ("materials.planet_gear.density", "7.85 g/cm^3", 7850.0),
    ("friction.oil_viscosity", "100cSt", 1e-4),
    ("operating.temperature", "40\u00b0C", 40.0),
    ("operating.temperature", "40 degC", 40.0),
    ("operating.load_torque", "412Nm", 412.0),
    ("operating.load_torque", "412 N*m", 412.0),
    ("operating.duration", "2 min", 120.0),
    ("rating.rated_life", "3600 s", 3600.0),
    ("operating.speed_ramp_time", "100ms", 0.1),
]

REFUSED = [
    # field, typed, words of the one-line reason
    ("operating.input_speed", "5mm", "'5mm' is a length, not an angular speed: give it in "
                                     "deg/s (or rpm, rad/s)"),
    ("operating.input_speed", "5Hz", "is a frequency, not an angular speed"),
    ("operating.input_speed", "5furlongs", "unknown unit 'furlongs'; give an angular speed "
                                           "in deg/s"),
    ("clearances.crank_arm_bushing", "5deg", "is an angle, not a length: give it in mm"),
    ("operating.load_torque", "412 N", "is a force, not a torque: give it in N*m"),
    ("operating.temperature", "313K", "unknown unit 'K'; give a temperature in degC"),
    ("cycloid.pin_count", "40teeth", "takes a plain number, without a unit"),
    ("gears.sun_profile_shift", "0.1mm", "takes a plain number, without a unit"),
    ("clearances.crank_arm_bushing", "1_0um", "'1_0um' is not a number"),
    ("clearances.crank_arm_bushing", "um", "'um' is not a number"),
    ("clearances.crank_arm_bushing", "5 um um", "unknown unit 'um um'"),
    ("clearances.crank_arm_bushing", "1e400um", "'1e400um' is not a finite number"),
    ("clearances.crank_arm_bushing", "inf um", "is not a number"),
]


@pytest.mark.parametrize("field,typed,si", ACCEPTED)
def test_a_value_with_a_unit_is_converted_to_si(field, typed, si):
    reducer = with_values(RV40E, {field: typed}, check=False)
    assert get_value(reducer, field, user_units=False) == pytest.approx(si, rel=1e-15)


@pytest.mark.parametrize("field,typed,words", REFUSED)
def test_a_wrong_unit_is_refused_naming_the_field(field, typed, words):
    with pytest.raises(ParameterError) as info:
        with_values(RV40E, {field: typed}, check=False)
    assert info.value.field == field and words in str(info.value)


@pytest.mark.parametrize("field,typed,plain", [
    ("clearances.crank_arm_bushing", "0.1mm", "0.1"), ("operating.input_speed", "6000deg/s",
                                                       "6000"),
    ("errors.rotation_modification", "0.7arcmin", "0.7"), ("H", "0.013 mm", "0.013")])
def test_the_listed_unit_typed_is_the_plain_number_to_the_last_bit(field, typed, plain):
    one = with_values(RV40E, {field: typed}, check=False)
    two = with_values(RV40E, {field: plain}, check=False)
    assert one == two


def test_another_unit_is_rounded_once():
    """5 um is the double nearest 5e-6 m (5 * 1e-6 is one unit in the last place below it),
    so it lists as 0.005 mm."""
    assert si_from_text("5um", "mm") == 5e-6
    assert get_value(with_values(RV40E, {"clearances.crank_arm_bushing": "5um"}),
                     "clearances.crank_arm_bushing") == 0.005


def test_the_unit_table_is_whole():
    assert set(DIMENSION) == set(TO_SI)
    assert all(target in TO_SI for target in ALIASES.values())
    assert {spec.unit for spec in SPECS.values()} <= set(DIMENSION)
    assert si_from_text("12.5", "mm") is None and si_from_text("abc", "mm") is None


def test_set_on_the_command_line(cli):
    res = cli("params", "--set", "operating.input_speed=1000rpm", "--set",
              "clearances.crank_arm_bushing=5um", "--json")
    assert res.code == 0, res.err
    rows = {row["name"]: row for row in json.loads(res.out)["parameters"]}
    assert rows["operating.input_speed"]["value"] == 6000.0
    assert rows["operating.input_speed"]["unit"] == "deg/s"
    assert rows["clearances.crank_arm_bushing"]["value"] == 0.005


@pytest.mark.parametrize("assignment,words", [
    ("operating.input_speed=5mm", "parameter 'operating.input_speed': '5mm' is a length, not "
                                  "an angular speed: give it in deg/s"),
    ("clearances.crank_arm_bushing=5kg", "'5kg' is a mass, not a length: give it in mm"),
])
def test_a_wrong_unit_on_the_command_line_is_one_line(cli, assignment, words):
    res = cli("params", "--set", assignment)
    assert res.code == 2 and res.out == ""
    assert res.err.count("\n") == 1 and res.err.startswith("rvsim: error: ") and words in res.err


def test_a_parameter_file_may_give_units(tmp_path, cli):
    path = tmp_path / "mine.toml"
    path.write_text('[operating]\ninput_speed = "1500 rpm"\n[clearances]\n'
                    'crank_arm_bushing = "8um"\n')
    res = cli("params", "--params", str(path), "--json")
    assert res.code == 0, res.err
    rows = {row["name"]: row["value"] for row in json.loads(res.out)["parameters"]}
    assert rows["operating.input_speed"] == 9000.0
    assert rows["clearances.crank_arm_bushing"] == 0.008
