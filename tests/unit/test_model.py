"""Model assembly: compliances, mass properties and switches map to the documented values."""

import math

import pytest

from rvsim.physics import _layout as L
from rvsim.physics.compliance import (effective_modulus, palmgren_coefficient,
                                      pin_compliance, ring_compliance, tooth_compliance)
from rvsim.dynamics.model import build_model, mass_properties
from rvsim.parameters import RV40E, Material, with_values

STEEL = Material("bearing steel", 2.075e11, 7850.0, 0.3)


def test_palmgren_law_for_steel_matches_the_published_constant():
    # delta [mm] = 3.84e-5 Q^0.9 / l^0.8 for a 15 mm roller
    c = palmgren_coefficient(15e-3, STEEL, STEEL)
    q = 1000.0
    assert c * q ** 0.9 == pytest.approx(3.84e-5 * q ** 0.9 / 15 ** 0.8 * 1e-3)


def test_softer_pin_material_is_more_compliant():
    pin = RV40E.materials.pin
    disc = RV40E.materials.cycloid_disc
    ratio = palmgren_coefficient(15e-3, disc, pin) / palmgren_coefficient(15e-3, STEEL, STEEL)
    assert ratio == pytest.approx(effective_modulus(STEEL, STEEL) / effective_modulus(disc, pin))
    assert ratio > 1.0


def test_body_compliances_have_the_documented_magnitudes():
    c = RV40E.cycloid
    tooth = tooth_compliance(2 * c.eccentricity, 2 * math.pi * 77.5e-3 / 39, c.disc_width,
                             RV40E.materials.cycloid_disc)
    # by hand: bending 3e-3^3 / (3 E I) = 1.79e-11, shear 1.2 * 3e-3 / (G A) = 2.33e-10 m/N
    assert tooth == pytest.approx(2.507e-10, rel=1e-3)
    # Roark by hand: q = 3521 N / 15 mm, b = 1.6 sqrt(q D 2(1-nu^2)/E) = 0.201 mm,
    # 4 (1-nu^2) / (pi E l) (1/3 + ln(2D/b)) = 4.761e-10 * 4.422 = 2.105e-9 m/N
    pin = pin_compliance(3e-3, 15e-3, 412 / (2 * 1.5e-3 * 39), RV40E.materials.pin)
    assert pin == pytest.approx(2.105e-9, rel=1e-3)
    ring = ring_compliance(3e-3, 14e-3, 15e-3, RV40E.materials.bushing)
    assert 1 / ring == pytest.approx(2.19e11 * 14e-3 * 15e-3 / 3e-3)


@pytest.mark.parametrize("letter, index", [("A", L.PIN_CB), ("B", L.PIN_CB), ("C", L.ARM_CB)])
def test_flexibility_switches_add_series_compliance(letter, index):
    rigid = build_model(RV40E, 1e-5).P[index]
    flexible = build_model(with_values(RV40E, {letter: True}), 1e-5).P[index]
    assert rigid == 0.0 and flexible > 0.0


def test_clearances_combine_in_series_and_supports_differ():
    r = with_values(RV40E, {"K": 0.003, "M": 0.004, "O": 0.001, "N": 0.005, "L": 0.002})
    P = build_model(r, 1e-5).P
    assert P[L.ARM_CLEAR] == pytest.approx(7e-6)
    assert P[L.SUP_CLEAR_U] == pytest.approx(6e-6)
    assert P[L.SUP_CLEAR_L] == pytest.approx(3e-6)


def test_errors_enter_where_documented():
    r = with_values(RV40E, {"F": 0.01, "G": 0.005, "H": 0.02, "I": 0.016, "J": 0.026})
    m = build_model(r, 1e-5)
    assert m.P[L.PIN_RADIUS] == pytest.approx(2.99e-3)
    assert m.P[L.ECC] == pytest.approx(1.495e-3)
    assert m.P[L.A_GEN] == pytest.approx(1.5e-3)
    assert m.P[L.RG] == pytest.approx(82e-3 - 0.026e-3)
    assert m.P[L.PROFILE_OFFSET] == pytest.approx(3.016e-3)
    assert math.hypot(*m.pins[0]) == pytest.approx(82.02e-3)


def test_mass_properties_are_plausible():
    mp = mass_properties(RV40E)
    # the figures docs/model.md section 7 states
    assert mp.disc_mass == pytest.approx(1.90, rel=0.005)
    assert mp.disc_inertia == pytest.approx(6.6e-3, rel=0.01)
    assert mp.crank_mass == pytest.approx(0.36, rel=0.01)
    assert mp.crank_inertia == pytest.approx(1.2e-4, rel=0.02)
    # the node mass matrix of the rigid crank reproduces its total translating mass
    assert mp.crank_node_mass.sum() == pytest.approx(mp.crank_mass, rel=1e-9)


def test_bushing_stiffness_factor_scales_compliance():
    a = build_model(RV40E, 1e-5).P[L.ARM_C]
    b = build_model(with_values(RV40E, {"contact.bushing_stiffness_factor": 10}), 1e-5).P[L.ARM_C]
    assert b == pytest.approx(a * 10 ** -0.9)


def test_rated_torque_is_a_parameter_of_the_reducer():
    # the pin body compliance is linearised at the pin load that carries the rated torque
    flexible = with_values(RV40E, {"B": True})
    assert flexible.rating.rated_torque == pytest.approx(412.0)
    c = RV40E.cycloid
    expected = pin_compliance(c.pin_radius, c.disc_width, 412.0 / (2 * c.eccentricity * 39),
                              RV40E.materials.pin)
    assert build_model(flexible, 1e-5).P[L.PIN_CB] == pytest.approx(expected, rel=1e-12)
    doubled = with_values(flexible, {"rating.rated_torque": 824})
    assert build_model(doubled, 1e-5).P[L.PIN_CB] < expected


def test_load_inertia_turns_with_the_carrier():
    carrier = mass_properties(RV40E).carrier_inertia
    assert carrier == pytest.approx(0.0152, rel=0.01)
    assert build_model(RV40E, 1e-5).P[L.J_CARRIER] == pytest.approx(carrier + 0.3)
    bare = with_values(RV40E, {"operating.load_inertia": 0})
    assert build_model(bare, 1e-5).P[L.J_CARRIER] == pytest.approx(carrier)
