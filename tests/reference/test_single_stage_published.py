"""Reference: the cycloid stage of a published reducer against its published FEM result.

Source (docs/validation.md, "Single-stage drive against a published result"): Wang, Liu, Yu,
Mao, He (SIAT) and Du (CUHK), "Analysis of meshing characteristics of pins and pin housing
integral structure in cycloidal planetary drive": zc = 39, zp = 40, R_z = 100 mm, A = 1 mm,
r_z = 2 mm, E = 208 GPa, nu = 0.295, output load 167 N*m.  Their FEM of the disc and the pin
housing finds 20 pins in contact and a maximum contact stress of 45.96 MPa.  The disc width is
not published: docs/validation_data/siat_nonpin_cycloid_stage.toml keeps the base set's 10 mm.

Measured 2026-11-24 (40 positions over an output revolution, 167 N*m) and pinned here:

* rigid bearings (bushing stiffness x 1e5): 20 pins in contact at every position, as published;
  largest pin force 218.149 N; largest Hertz pressure 649.891 MPa (14.1 x the published 45.96
  MPa; it would take a 2.0 m wide disc to bring the Hertz pressure down to it);
* the set's own bushings: 24 pins in contact, 263.299 N, 753.006 MPa.

The stress is reported, not tuned: the disagreement is documented, not asserted away.
"""

from pathlib import Path

import numpy as np
import pytest

from rvsim.parameters import load_toml, with_values
from rvsim.quasistatic import ltca

SET = Path(__file__).parents[2] / "docs" / "validation_data" / "siat_nonpin_cycloid_stage.toml"
TORQUE = 167.0                  # N*m, the paper's output load
PUBLISHED_PINS_IN_CONTACT = 20
PUBLISHED_MAX_CONTACT_STRESS_MPA = 45.96


@pytest.fixture(scope="module")
def stage():
    return load_toml(SET)


def test_published_dimensions_load(stage):
    c = stage.cycloid
    assert (c.disc_teeth, c.pin_count) == (39, 40)
    assert c.pin_circle_radius == pytest.approx(0.100)
    assert c.eccentricity == pytest.approx(0.001)
    assert c.pin_radius == pytest.approx(0.002)
    for material in (stage.materials.cycloid_disc, stage.materials.pin):
        assert material.elastic_modulus == pytest.approx(208e9)
        assert material.poisson_ratio == pytest.approx(0.295)
    assert stage.operating.load_torque == pytest.approx(TORQUE)
    assert stage.layout.stages == 1 and stage.ratio == -39


def test_rigid_bearings_against_the_published_fem(stage):
    result = ltca(with_values(stage, {"contact.bushing_stiffness_factor": 1e5}),
                  torque=TORQUE, positions=40, allow_aliasing=True)
    assert result.status == "ok"
    assert np.all(result.pins_in_contact == PUBLISHED_PINS_IN_CONTACT)
    summary = result.summary()
    assert summary["max_pin_force_n"] == pytest.approx(218.149, rel=1e-5)
    stress = summary["max_contact_stress_mpa"]
    assert stress == pytest.approx(649.891, rel=1e-5)
    # the disagreement, as measured: 14.1 x the published FEM value
    assert stress / PUBLISHED_MAX_CONTACT_STRESS_MPA == pytest.approx(14.14, abs=0.01)


def test_own_bushings(stage):
    summary = ltca(stage, torque=TORQUE, positions=40, allow_aliasing=True).summary()
    assert summary["status"] == "ok"
    assert summary["pins_in_contact_min"] == summary["pins_in_contact_max"] == 24
    assert summary["max_pin_force_n"] == pytest.approx(263.299, rel=1e-5)
    assert summary["max_contact_stress_mpa"] == pytest.approx(753.006, rel=1e-5)
