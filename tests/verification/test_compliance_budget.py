"""Verification of the compliance budget (issue 32 item 3; docs/model.md section 12,
"Compliance budget"): the stiffened force laws against the laws themselves, a reducer whose
only compliance is the gear mesh against the closed form i^2 rb1^2 (k1 + k2), the budget of
one and of two compliant elements against the series-spring split, and its failures.

Measured (2026-11-28) and the tolerance of each test:

* every stiffened law gives s times its force at the same approach: Palmgren contact with and
  without a series compliance, Johnson's conforming bushing below and beyond the wrap force, a
  roller set with clearance, to 2.2e-16 relative (tolerance 1e-12); factor 1 leaves P bit
  for bit; the bushings stiffened by s are the bushings of ``contact.bushing_stiffness_factor``
  = s (the same j / s, a s of rvsim.bearings.conforming_constants) bit for bit (tolerance
  1e-15);
* the gear mesh 1000 x softer, pins, arm and support bearings 1e4 x stiffer: the rigidity is
  the mesh's closed form i^2 rb1^2 (k1 + k2), averaged over the two directions (2 tooth pairs
  per mesh at negative torque, 1 at positive), within 8.5e-5 (tolerance 2e-4; the rest is
  what the stiffened elements keep);
* that reducer's budget of the mesh alone, 10 x: share 1 - 1/10 within 7.6e-5 (tolerance
  2e-4);
* the cycloid drive's input coupling 1000 x softer, the rest 1e4 x stiffer: rigidity
  i^2 k_input within 1.2e-5 (tolerance 5e-5);
* arm and support bushings compliant, 48 : 52 (mesh and pins 1e4 x): their compliances add
  within 6.0e-4, each share equals its own compliance (the other one stiffened too) over the
  sum within 3.1e-4, residual 6.0e-4 (tolerance 1.5e-3);
* RV-40E, 6 points per branch, 1e4 x: support bushings 44.30 %, arm bushings 41.41 %, pins
  14.25 %, mesh 0.88 %, residual -0.84 %; 100 x: 42.63, 39.86, 14.01, 0.87 %, residual
  2.63 % (pinned to 1e-4); RV-40E-bearings, 100 x: 54.17, 36.74, 7.51, 0.46 % against issue
  32's 54 / 37 / 8 / < 1 (to the issue's rounding).
"""

import math

import numpy as np
import pytest

from rvsim.dynamics.model import build_model
from rvsim.errors import ParameterError
from rvsim.parameters import BUILT_IN_SETS, RV40E, with_values
from rvsim.physics import _layout as L
from rvsim.physics._bearings import conforming_force, roller_set
from rvsim.physics._contact_law import spring_force
from rvsim.physics.stiffening import ELEMENTS, elements_in, stiffen
from rvsim.quasistatic.budget import compliance_budget, rigidity_of
from rvsim.quasistatic.torque_reversal import TEST_OUTPUT_SPEED, hysteresis, sweep_torques
from rvsim.quasistatic.transmission import solve_path

BEARINGS = BUILT_IN_SETS["RV-40E-bearings"]
POINTS = 6                      # points per quarter of the torque reversal (tests/_warmup.py)
#: the cycloid drive's input coupling alone: the closed form within 1.2e-5
INPUT_ALONE = 5e-5
#: two springs in series: the arm and support bushings' compliances add within 6e-4
TWO_SPRINGS = 1.5e-3


def _P(reducer=RV40E):
    return build_model(reducer, 1e-5).P


# --- the stiffened laws ------------------------------------------------------------------

@pytest.mark.parametrize("s", [3.0, 100.0])
def test_palmgren_contact_gives_s_times_the_force(s):
    P = _P(with_values(RV40E, {"flexibility.pin": True, "flexibility.cycloid_disc": True}))
    Ps, _ = stiffen(P, np.zeros((2, 0, 0)), {"pins": s})
    assert P[L.PIN_CB] > 0
    for delta in (1e-7, 3e-6, 2e-5):
        f, _, _ = spring_force(delta, P[L.PIN_C], P[L.PIN_CB], 0.0)
        fs, _, _ = spring_force(delta, Ps[L.PIN_C], Ps[L.PIN_CB], 0.0)
        assert fs == pytest.approx(s * f, rel=1e-12)


@pytest.mark.parametrize("s", [3.0, 100.0])
def test_conforming_bushing_gives_s_times_the_force(s):
    P = _P()
    Ps, _ = stiffen(P, np.zeros((2, 0, 0)), {"arm_bearings": s})
    args = [L.ARM_J1, L.ARM_A1, L.ARM_J2, L.ARM_A2, L.ARM_CB]
    wrap = P[L.ARM_A1] / 16.0
    # below and beyond the wrap force (the law's linear continuation)
    for force in (1e-3 * wrap, 0.5 * wrap, 4.0 * wrap):
        delta = force * (P[L.ARM_J1] + P[L.ARM_J2])
        # the shift given (nan: computed), as the engines call it: their compiled signature
        f, _, _ = conforming_force(delta, *P[args], 0.0, math.nan)
        fs, _, _ = conforming_force(delta, *Ps[args], 0.0, math.nan)
        assert fs == pytest.approx(s * f, rel=1e-12)


def test_roller_set_gives_s_times_the_force():
    P = _P(BEARINGS)
    Ps, _ = stiffen(P, np.zeros((2, 0, 0)), {"support_bearings": 100.0})
    gap = 2e-6
    for rx, ry in ((5e-6, 1e-6), (3e-6, -8e-6)):
        a = roller_set(rx, ry, 0.0, 0.0, P[L.SUP_ROLLERS], 0.3, P[L.SUP_C], gap,
                       P[L.SUP_COS_ALPHA], 0.0, 1.0)
        b = roller_set(rx, ry, 0.0, 0.0, P[L.SUP_ROLLERS], 0.3, Ps[L.SUP_C], gap,
                       P[L.SUP_COS_ALPHA], 0.0, 1.0)
        assert b[0] == pytest.approx(100.0 * a[0], rel=1e-12)
        assert b[1] == pytest.approx(100.0 * a[1], rel=1e-12)


def test_stiffening_touches_its_own_slots_only():
    P = _P(BEARINGS)
    tables = np.zeros((2, 0, 0))
    same, _ = stiffen(P, tables, {name: 1.0 for name in elements_in(P)})
    assert np.array_equal(same, P)                          # factor 1: bit for bit
    mesh, _ = stiffen(P, tables, {"gear_mesh": 7.0})
    assert np.flatnonzero(mesh != P).tolist() == [L.K_MESH] and mesh[L.K_MESH] == 7.0 * P[L.K_MESH]
    assert elements_in(P) == ("gear_mesh", "arm_bearings", "pins", "support_bearings")
    assert set(elements_in(P)) <= set(ELEMENTS)
    with pytest.raises(ValueError, match="no element 'fe_crank'"):
        stiffen(P, tables, {"fe_crank": 2.0})


def test_finite_element_tables_are_divided_and_the_cache_left_alone():
    P = _P()
    P[L.FE_DISC] = 1.0
    P[[L.FE_HOLE_CSS0, L.FE_HOLE_CSS1]] = 2e-9, 3e-9
    P[L.FE_CRANK_XX1:L.FE_CRANK_XX1 + 10] = np.arange(1.0, 11.0) * 1e-9
    P[L.FE_PLATE_XX1:L.FE_PLATE_XX1 + 10] = np.arange(1.0, 11.0) * 1e-10
    tables = np.full((2, 3, 3), 1e-9)
    tables.flags.writeable = False                  # the FE cache hands out read-only arrays
    assert {"fe_disc", "fe_crank", "fe_carrier"} <= set(elements_in(P))
    Ps, ts = stiffen(P, tables, {"fe_disc": 4.0, "fe_crank": 5.0, "fe_carrier": 8.0})
    assert np.array_equal(ts, tables / 4.0) and np.all(tables == 1e-9)
    assert np.array_equal(Ps[[L.FE_HOLE_CSS0, L.FE_HOLE_CSS1]], [0.5e-9, 0.75e-9])
    assert np.array_equal(Ps[L.FE_CRANK_XX1:L.FE_CRANK_XX1 + 10],
                          P[L.FE_CRANK_XX1:L.FE_CRANK_XX1 + 10] / 5.0)
    assert np.array_equal(Ps[L.FE_PLATE_XX1:L.FE_PLATE_XX1 + 10],
                          P[L.FE_PLATE_XX1:L.FE_PLATE_XX1 + 10] / 8.0)
    changed = set(np.flatnonzero(Ps != P))
    assert changed == {L.FE_HOLE_CSS0, L.FE_HOLE_CSS1, *range(L.FE_CRANK_XX1, L.FE_CRANK_XX1 + 10),
                       *range(L.FE_PLATE_XX1, L.FE_PLATE_XX1 + 10)}


def test_bushings_stiffened_are_the_bushing_stiffness_factor():
    # one convention with contact.bushing_stiffness_factor (rvsim.bearings.conforming_constants)
    s = 4.0
    P = _P()
    Ps, _ = stiffen(P, np.zeros((2, 0, 0)), {"arm_bearings": s, "support_bearings": s})
    Pf = _P(with_values(RV40E, {"contact.bushing_stiffness_factor": s}))
    for slot in (L.ARM_J1, L.ARM_A1, L.ARM_J2, L.ARM_A2, L.SUP_J1, L.SUP_A1, L.SUP_J2,
                 L.SUP_A2_L, L.SUP_A2_U, L.ARM_SHIFT, L.SUP_SHIFT_L, L.SUP_SHIFT_U):
        assert Ps[slot] == pytest.approx(Pf[slot], rel=1e-15, abs=0.0), L.PARAM_NAMES[slot]


# --- budgets with a known answer ----------------------------------------------------------

#: the gear mesh 1000 x softer, the rest 1e4 x stiffer: the mesh is the reducer's compliance
#: (the others keep 1e-4 of it)
ONLY_MESH = {"gear_mesh": 1e-3, "pins": 1e4, "arm_bearings": 1e4, "support_bearings": 1e4}


def test_mesh_alone_is_the_closed_form():
    """Input locked: a carrier turn theta is the arc i rb1 theta on each mesh's line of action
    (i the ratio, rb1 the sun's base radius), each mesh carries k_j i rb1 theta and the input
    torque T / i = rb1 (F1 + F2): K = i^2 rb1^2 (k1 + k2), per direction with its tooth
    pairs (the catalogue rigidity averages the two directions)."""
    run = hysteresis(RV40E, points_per_branch=POINTS, stiffen=ONLY_MESH)
    rigidity, status = rigidity_of(run)
    torque, branch = sweep_torques(412.0, POINTS)
    path = solve_path(RV40E, np.zeros(len(torque)), -torque,
                      carrier_rate=TEST_OUTPUT_SPEED * branch, stiffen=ONLY_MESH)
    k = path.mesh_state[:, :, 0].sum(axis=1)
    P = _P()
    hand = [RV40E.ratio ** 2 * P[L.RB1] ** 2 * np.unique(k[torque > 0.4 * 412.0]).item(),
            RV40E.ratio ** 2 * P[L.RB1] ** 2 * np.unique(k[torque < -0.4 * 412.0]).item()]
    assert hand[1] == pytest.approx(2.0 * hand[0], rel=1e-12)       # 2 pairs against 1
    assert hand[0] == pytest.approx(RV40E.ratio ** 2 * P[L.RB1] ** 2 * 2e-3 * P[L.K_MESH],
                                    rel=1e-12)                       # one pair per mesh
    assert status == "ok" and rigidity == pytest.approx(np.mean(hand), rel=2e-4)


def test_single_stage_input_coupling_alone_is_the_closed_form():
    """Cycloid drive, input locked: the input coupling twists by i theta_out and carries the
    input torque T / i: K = i^2 k_input."""
    drive = BUILT_IN_SETS["cycloid-drive"]
    P = _P(drive)
    assert elements_in(P) == ("input_coupling", "arm_bearings", "pins", "support_bearings",
                              "output_pins")
    only = {"input_coupling": 1e-3, "arm_bearings": 1e4, "pins": 1e4, "support_bearings": 1e4,
            "output_pins": 1e4}
    rigidity, status = rigidity_of(hysteresis(drive, points_per_branch=POINTS, stiffen=only))
    assert status == "ok"
    assert rigidity == pytest.approx(drive.ratio ** 2 * 1e-3 * P[L.K_INPUT], rel=INPUT_ALONE)


def test_budget_of_the_one_compliant_element_is_one_less_one_over_s():
    budget = compliance_budget(RV40E, points_per_branch=POINTS, factor=100.0, base=ONLY_MESH,
                               elements=("gear_mesh",))
    assert budget.status == "ok" and budget.elements == ("gear_mesh",)
    assert budget.shares[0] == pytest.approx(0.99, abs=2e-4)


def test_two_elements_in_series_split_as_their_compliances():
    # arm and support bushings, nearly equal springs in series; mesh and pins rigid
    two = {"gear_mesh": 1e4, "pins": 1e4}
    budget = compliance_budget(RV40E, points_per_branch=POINTS, base=two,
                               elements=("arm_bearings", "support_bearings"))
    assert budget.status == "ok"
    # each element's compliance alone (the other one made rigid as well)
    alone = {}
    for name, other in (("arm_bearings", "support_bearings"),
                        ("support_bearings", "arm_bearings")):
        alone[name] = 1.0 / rigidity_of(hysteresis(RV40E, points_per_branch=POINTS,
                                                   stiffen={**two, other: 1e4}))[0]
    total = sum(alone.values())
    assert 0.4 < alone["arm_bearings"] / total < 0.6                  # comparable springs
    assert 1.0 / budget.rigidity == pytest.approx(total, rel=TWO_SPRINGS)
    for i, name in enumerate(budget.elements):
        assert budget.shares[i] == pytest.approx(alone[name] / total, abs=TWO_SPRINGS), name
    assert budget.residual == pytest.approx(0.0, abs=TWO_SPRINGS)


#: measured shares of the paper's RV-40E (which stays as it is), 6 points per branch: the
#: default factor (1e4) and issue 32's 100
BUILT_IN = [
    ("RV-40E", 1e4, {"support_bearings": 0.4430, "arm_bearings": 0.4141, "pins": 0.1425,
                     "gear_mesh": 0.0088}, -0.0084),
    ("RV-40E", 100.0, {"support_bearings": 0.4263, "arm_bearings": 0.3986, "pins": 0.1401,
                       "gear_mesh": 0.0087}, 0.0263)]


def test_rolling_bearings_set_is_issue_32s_budget():
    """Issue 32 quoted, from a 100 x stiffen method on RV-40E-bearings: tapered support
    rollers 54 %, needles 37 %, pins 8 %, gear mesh under 1 % (measured here 54.17, 36.74,
    7.51, 0.46 %; residual 1.1 %).  Checked to the issue's rounding (this set is the one
    issue 32 item 1 may replace: then this test is to be re-measured, not widened)."""
    budget = compliance_budget(BEARINGS, points_per_branch=POINTS, factor=100.0)
    shares = dict(zip(budget.elements, budget.shares))
    assert budget.status == "ok"
    assert shares == pytest.approx({"support_bearings": 0.54, "arm_bearings": 0.37,
                                    "pins": 0.08, "gear_mesh": 0.005}, abs=0.005)
    assert budget.labels[budget.order()[0]] == "crank support bearings (tapered rollers)"


@pytest.mark.parametrize("name, factor, expected, residual", BUILT_IN,
                         ids=[f"{n}-{f:g}" for n, f, _, _ in BUILT_IN])
def test_built_in_sets(name, factor, expected, residual):
    budget = compliance_budget(BUILT_IN_SETS[name], points_per_branch=POINTS, factor=factor)
    assert budget.status == "ok"
    shares = dict(zip(budget.elements, budget.shares))
    assert shares == pytest.approx(expected, abs=1e-4)
    assert budget.residual == pytest.approx(1.0 - sum(shares.values()), abs=1e-15)
    assert budget.residual == pytest.approx(residual, abs=1e-4)
    order = [budget.elements[i] for i in budget.order()]
    assert order == sorted(expected, key=expected.get, reverse=True)   # softest first
    summary = budget.summary()
    assert [row["element"] for row in summary["elements"]] == order
    assert summary["rigidity_nm_per_arcmin"] == pytest.approx(
        hysteresis(BUILT_IN_SETS[name], points_per_branch=POINTS).summary()[
            "torsional_rigidity_nm_per_arcmin"], rel=1e-12)


# --- bad input and failures ---------------------------------------------------------------

@pytest.mark.parametrize("kwargs, field", [
    ({"factor": 1.0}, "factor"), ({"factor": math.nan}, "factor"), ({"factor": True}, "factor"),
    ({"base": {"fe_crank": 2.0}}, "base"), ({"base": {"pins": -1.0}}, "base"),
    ({"elements": ("output_pins",)}, "elements"), ({"elements": ()}, "elements")])
def test_bad_arguments_name_their_field(kwargs, field):
    with pytest.raises(ParameterError) as info:
        compliance_budget(RV40E, points_per_branch=POINTS, **kwargs)
    assert info.value.field == field


@pytest.mark.parametrize("factor, element, status", [
    (1e7, "arm_bearings", "not_converged"), (1e8, "pins", "singular_stiffness")])
def test_a_failed_stiffened_test_is_a_status_naming_the_element(factor, element, status):
    # arm bushings 1e7 x stiffer: the solver's tolerance is below the round-off of forces that
    # stiff, even by continuation in the factor (pins converge there: share 14.25 % at 1e4 to
    # 1e7 x); pins 1e8 x: the condensed stiffness cannot be inverted
    budget = compliance_budget(RV40E, points_per_branch=POINTS, factor=factor,
                               elements=(element,))
    assert budget.status == f"{status} ({element} stiffened)"
    assert np.isnan(budget.shares[0])
    assert budget.summary()["elements"][0]["share"] is None


def test_a_failed_reference_test_fails_the_whole_budget():
    budget = compliance_budget(RV40E, points_per_branch=POINTS,
                               base={"arm_bearings": 1e8})
    assert budget.status == "not_converged (reference test)"
    assert np.all(np.isnan(budget.shares)) and math.isnan(budget.rigidity)
