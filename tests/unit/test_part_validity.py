"""Parts that cannot exist are refused by validation (issue 30; rvsim.geometry.validity).

A hostile test found reducers whose parts cannot exist accepted with status ok numbers or
tracebacks.  Each row is a command line and the words its one-line error must contain (exit
code 2, no file written); validation refuses them before any run, so every command refuses
them alike.
"""

from __future__ import annotations

import pytest

from rvsim.errors import ParameterError
from rvsim.parameters import BUILT_IN_SETS, RV40E, paper_run_values, validate, with_values

from tests.integration.test_bad_inputs import expect_one_line_error, listing

PINS = "'cycloid.pin_radius': neighbouring pins overlap: 40 pins on the 82 mm pin circle are " \
       "12.87 mm apart, not more than the pin diameter 13 mm"
BORE = "'cycloid.disc_bore_radius': the central bore ({} mm) cuts into the crank holes " \
       "(15.5 mm radius on the 44.95 mm crank circle)"
BEARINGS = ["--params", "RV-40E-bearings"]

ROWS = {
    # pins that overlap their neighbours (40 pins on an 82 mm circle: 12.87 mm apart)
    "pins 6.5 params": (["params", "--set", "cycloid.pin_radius=6.5"], PINS),
    "pins 6.5 simulate": (["simulate", "--set", "cycloid.pin_radius=6.5", "--save", "r.npz"],
                          PINS),
    "pins 6.5 ltca": (["ltca", "--set", "cycloid.pin_radius=6.5", "--json"], PINS),
    "pins 6.5 hysteresis": (["hysteresis", "--set", "cycloid.pin_radius=6.5", "--export",
                             "j.json"], PINS),
    "pins 6.5 efficiency": (["efficiency", "--set", "cycloid.pin_radius=6.5"], PINS),
    "pins 6.5 profile": (["profile", "--set", "cycloid.pin_radius=6.5", "--out", "p.dxf"],
                         PINS),
    "pins 6.4 cycloid-drive": (["ltca", "--params", "cycloid-drive", "--set",
                                "cycloid.pin_radius=6.4"],
                               "'cycloid.pin_radius': neighbouring pins overlap: 30 pins on "
                               "the 60 mm pin circle are 12.54 mm apart"),
    # the profile's own check stays first: a pin too large for the teeth is an undercut
    "pins 8 undercut": (["params", "--set", "cycloid.pin_radius=8"],
                        "'cycloid.pin_radius': teeth undercut"),
    # rolling elements that do not fit around their race
    "100 needles": (["hysteresis", *BEARINGS, "--set", "bearings.needle_count=100"],
                    "'bearings.needle_count': 100 needles of 3 mm do not fit around their "
                    "pitch circle of 28 mm diameter: neighbours are 0.8795 mm apart (at most "
                    "29 fit)"),
    "200 support rollers": (["ltca", *BEARINGS, "--set", "bearings.support_roller_count=200"],
                            "'bearings.support_roller_count': 200 support rollers of 5 mm do "
                            "not fit around their pitch circle of 25 mm diameter"),
    "2000 main balls": (["hysteresis", *BEARINGS, "--set", "bearings.main_ball_count=2000",
                         "--export", "j.json"],
                        "'bearings.main_ball_count': 2000 main-bearing balls of 9 mm do not "
                        "fit around their pitch circle of 140 mm diameter: neighbours are "
                        "0.2199 mm apart (at most 48 fit)"),
    "200 mm ball": (["hysteresis", *BEARINGS, "--set", "bearings.main_ball_diameter=200",
                     "--export", "j.json"],
                    "'bearings.main_ball_diameter': a ball of 200 mm cannot run on a pitch "
                    "circle of 140 mm diameter"),
    "main balls of the RV-40E": (["hysteresis", "--set", "bearings.main_ball_count=60",
                                  "--export", "j.json"], "'bearings.main_ball_count': 60 "),
    "needles longer than the disc": (["params", *BEARINGS, "--set",
                                      "bearings.needle_length=16"],
                                     "'bearings.needle_length': 16 mm is longer than the "
                                     "disc's crank hole they run in (disc width 15 mm)"),
    # a central bore that removes the crank holes
    "bore 60": (["ltca", "--set", "cycloid.disc_bore_radius=60"], BORE.format(60)),
    "bore 75": (["simulate", "--set", "cycloid.disc_bore_radius=75"], BORE.format(75)),
    "bore 90 FE disc": (["ltca", "--set", "A=1", "--set", "flexibility.model=fe", "--set",
                         "cycloid.disc_bore_radius=90"], BORE.format(90)),
    "bore 29.5 no ligament": (["params", "--set", "cycloid.disc_bore_radius=29.5"],
                              BORE.format(29.5)),
    # pillar holes (on the crank circle, a quarter turn from the crank holes)
    "pillar into the bore": (["params", "--set", "cycloid.pillar_hole_radius=30"],
                             "'cycloid.pillar_hole_radius': the pillar holes (30 mm) cut into "
                             "the central bore"),
    "pillar through the root": (["params", "--set", "cycloid.pillar_hole_radius=32", "--set",
                                 "cycloid.disc_bore_radius=10"],
                                "'cycloid.pillar_hole_radius': the pillar holes cut through "
                                "the disc's tooth root"),
    "3 pillars": (["params", "--set", "cycloid.pillar_hole_count=3"],
                  "'cycloid.pillar_hole_count': a pillar hole (11 mm) overlaps a crank hole"),
    # the carrier must hold the crank bores; the single-stage flange its output pins
    "carrier 10 FE": (["ltca", "--set", "flexibility.model=fe", "--set",
                       "cycloid.carrier_radius=10"],
                      "'cycloid.carrier_radius': 10 mm cannot hold the crank support bores "
                      "(13 mm radius on the 44.95 mm crank circle)"),
    "carrier 57.9": (["params", "--set", "cycloid.carrier_radius=57.9"],
                     "'cycloid.carrier_radius': 57.9 mm cannot hold"),
    "carrier of the tapered rollers": (["params", *BEARINGS, "--set",
                                        "cycloid.carrier_radius=59"],
                                       "'cycloid.carrier_radius': 59 mm cannot hold the crank "
                                       "support bores (15 mm radius"),
    "flange 40 cycloid-drive": (["params", "--params", "cycloid-drive", "--set",
                                 "cycloid.carrier_radius=40"],
                                "'cycloid.carrier_radius': the output flange (40 mm radius) "
                                "cannot hold the output pins (pin circle + pin radius = 41 "
                                "mm)"),
    # the crank: journal inside the eccentric and through the disc's crank hole
    "journal 13": (["params", "--set", "crank.journal_radius=13"],
                   "'crank.journal_radius': 13 mm is larger than the eccentric radius 12.5 mm"),
    "journal 16 cycloid-drive": (["params", "--params", "cycloid-drive", "--set",
                                  "crank.journal_radius=16"],
                                 "'crank.journal_radius': 16 mm is larger than the eccentric "
                                 "radius 15 mm"),
    "journal through the hole": (["params", "--set", "crank.journal_radius=12.5", "--set",
                                  "crank.arm_bushing_thickness=1"],
                                 "'crank.journal_radius': the disc's crank hole (13.5 mm "
                                 "radius) cannot pass over the journal (12.5 mm) offset by "
                                 "the eccentricity 1.5 mm"),
    # parts along the crank
    "discs overlap": (["params", "--set", "crank.disc2_z=20"],
                      "'crank.disc2_z': the disc 1 (15 mm wide at 13 mm) and the disc 2 (15 mm "
                      "wide at 20 mm) overlap along the crank"),
    "disc into the support": (["params", "--set", "cycloid.disc_width=17"],
                              "'crank.disc1_z': the lower support (10 mm wide at 0 mm) and the "
                              "disc 1 (17 mm wide at 13 mm) overlap"),
    "gear in the support": (["params", "--set", "crank.gear_z=44"],
                            "'crank.gear_z': the upper support (10 mm wide at 42 mm) and the "
                            "planet gear (7 mm wide at 44 mm) overlap"),
    "single disc": (["params", "--params", "cycloid-drive", "--set", "layout.disc_count=1",
                     "--set", "cycloid.disc_width=16"],
                    "'crank.disc1_z': the lower support (10 mm wide at 0 mm) and the disc 1"),
    # gears too narrow to carry the rated torque once
    "face width 1 um params": (["params", "--set", "gears.face_width=0.001"],
                               "'gears.face_width': 0.001 mm cannot carry the rated torque 412 "
                               "N*m: the Lewis tooth-root stress would be 2.5e+05 MPa, above "
                               "the static strength of any gear steel, 2625 MPa (ISO 6336; at "
                               "least 0.095 mm)"),
    "face width 1 um simulate": (["simulate", "--set", "gears.face_width=0.001", "--save",
                                  "r.npz"], "'gears.face_width': 0.001 mm cannot carry"),
}


@pytest.mark.parametrize("case", list(ROWS))
def test_a_part_that_cannot_exist_is_refused(empty_workdir, cli, case):
    args, words = ROWS[case]
    expect_one_line_error(cli(*args), words)
    assert listing(empty_workdir) == []


#: with_values (Python) refuses the same reducers, naming the same field
PYTHON_ROWS = {
    "pins": ({"cycloid.pin_radius": 6.5}, "cycloid.pin_radius"),
    "bore": ({"cycloid.disc_bore_radius": 60}, "cycloid.disc_bore_radius"),
    "carrier": ({"cycloid.carrier_radius": 10}, "cycloid.carrier_radius"),
    "journal": ({"crank.journal_radius": 13}, "crank.journal_radius"),
    "face width": ({"gears.face_width": 0.001}, "gears.face_width"),
    "main balls": ({"bearings.main_ball_count": 2000}, "bearings.main_ball_count"),
}


@pytest.mark.parametrize("case", list(PYTHON_ROWS))
def test_with_values_refuses_them_too(case):
    values, field = PYTHON_ROWS[case]
    with pytest.raises(ParameterError) as info:
        with_values(RV40E, values)
    assert info.value.field == field and "\n" not in str(info.value)
    # a tolerance study's reducers skip the assembly check, not this one
    with pytest.raises(ParameterError):
        validate(with_values(RV40E, values, check=False), assembly=False)


#: parts the model does not have are not checked; the limits are the geometric ones
ACCEPTED = {
    "needles not fitted": ("RV-40E", {"bearings.needle_count": 100}),
    "rollers not fitted": ("RV-40E", {"bearings.support_roller_count": 200}),
    "no main bearings in the single-stage drive": ("cycloid-drive",
                                                   {"bearings.main_ball_count": 2000}),
    "no gears in the single-stage drive": ("cycloid-drive", {"gears.face_width": 0.001}),
    "pins 6.4 leave 0.07 mm of housing": ("RV-40E", {"cycloid.pin_radius": 6.4}),
    "bore 29.4 leaves 0.05 mm": ("RV-40E", {"cycloid.disc_bore_radius": 29.4}),
    "15 rollers: the most that fit": ("RV-40E-bearings", {}),
    "face width 0.1 mm": ("RV-40E", {"gears.face_width": 0.1}),
    "discs touching": ("RV-40E", {"crank.disc2_z": 28}),
}


@pytest.mark.parametrize("case", list(ACCEPTED))
def test_what_can_exist_is_accepted(case):
    name, values = ACCEPTED[case]
    with_values(BUILT_IN_SETS[name], values)


@pytest.mark.parametrize("name", list(BUILT_IN_SETS))
def test_built_in_sets_and_the_paper_runs_validate(name):
    validate(BUILT_IN_SETS[name])
    if name != "cycloid-drive":       # the paper's L36 sets the RV's support clearances
        for run in range(1, 37):
            with_values(BUILT_IN_SETS[name], paper_run_values(run))
