"""The finite-element pin in its groove (rvsim.fe.pin, docs/model.md sections 6 and 17): the
plane-strain solver against the exact solution of a disc squeezed between two strip loads, the
table's symmetry and values, its interpolation, and the engines' use of it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from tests.conftest import HAS_FE, NO_FE

if not HAS_FE:
    pytest.skip(NO_FE, allow_module_level=True)

from rvsim.fe.elasticity import Factor, PlaneStressBody, edge_force
from rvsim.fe.mesh import mesh_plane_region
from rvsim.parameters import RV40E, with_values

E, NU, T, R = 2.0e11, 0.3, 0.015, 0.003


def michell_approach(alpha: float, terms: int = 20000) -> float:
    """Approach [m/N] of two diametrically opposite arcs (half angle ``alpha``) of a solid
    plane-strain disc (radius R, length T) under unit forces along the diameter spread as
    uniform tractions over the arcs, measured as the traction-weighted mean displacement of
    each arc along its force (the finite-element functional).  Exact: Michell's solution,
    Airy function (A r^n + B r^(n+2)) cos n theta per even harmonic n of the boundary
    tractions (Barber, *Elasticity*, 3rd ed., chapter 9), n = 0 uniform pressure."""
    p = 1.0 / (2.0 * alpha * R * T)
    mu = E / (2.0 * (1.0 + NU))
    kappa = 3.0 - 4.0 * NU

    def cos_cos(k):      # integral of cos(k th) cos(th) over |th| < alpha
        return math.sin((k - 1) * alpha) / (k - 1) + math.sin((k + 1) * alpha) / (k + 1)

    def sin_sin(k):      # integral of sin(k th) sin(th) over |th| < alpha
        return math.sin((k - 1) * alpha) / (k - 1) - math.sin((k + 1) * alpha) / (k + 1)

    # n = 0: sigma_rr = a0 (mean radial traction), u_r = (kappa - 1) a0 r / (4 mu)
    a0 = -2.0 * p * math.sin(alpha) / math.pi
    mean_ur_cos = (kappa - 1.0) * a0 * R / (4.0 * mu) * cos_cos(0)
    mean_ut_sin = 0.0
    for n in range(2, terms, 2):
        an = -2.0 * p / math.pi * cos_cos(n)          # sigma_rr = an cos n th at r = R
        bn = 2.0 * p / math.pi * sin_sin(n)           # sigma_rt = bn sin n th
        # a = A R^(n-2), b = B R^n (the stresses at r = R)
        det = n * (1 - n) * n * (n + 1) - (n + 2 - n * n) * n * (n - 1)
        a = (an * n * (n + 1) - (n + 2 - n * n) * bn) / det
        b = (n * (1 - n) * bn - n * (n - 1) * an) / det
        ur = R * (-n * a + (kappa - n - 1) * b) / (2 * mu)
        ut = R * (n * a + (kappa + n + 1) * b) / (2 * mu)
        mean_ur_cos += ur * cos_cos(n)
        mean_ut_sin += ut * sin_sin(n)
    # arc at theta = 0 pushed along -x: its mean displacement along -x, twice (both arcs)
    return 2.0 * -(mean_ur_cos - mean_ut_sin) / (2.0 * alpha)


def fe_approach(n_edges: int, arc_edges: int) -> float:
    """The same with the pin's elements (P2, plane strain) on a disc of ``n_edges`` boundary
    edges, each arc ``arc_edges`` edges; held statically determinately (the loads balance)."""
    theta = 2 * math.pi * np.arange(n_edges) / n_edges
    outline = R * np.column_stack([np.cos(theta), np.sin(theta)])
    mesh = mesh_plane_region(outline, [], 2.0 * R * 2 * math.pi / n_edges)
    body = PlaneStressBody(mesh.points, mesh.triangles, E, NU, T, plane_strain=True)
    nodes = mesh.outline
    half = arc_edges // 2

    def arc(centre):
        return [(int(nodes[k % n_edges]), int(nodes[(k + 1) % n_edges]))
                for k in range(centre - half, centre + half)]

    load = (edge_force(body, arc(0), np.array([-1.0, 0.0]))
            + edge_force(body, arc(n_edges // 2), np.array([1.0, 0.0])))
    top, bottom = body.node_dofs(nodes[[n_edges // 4, 3 * n_edges // 4]]).T
    factor = Factor(body.stiffness, np.array([top[0], top[1], bottom[0]]))
    u = np.zeros(body.n_dofs)
    u[factor.free] = factor.solve(load[factor.free])
    return float(load @ u)


def test_disc_between_two_strips_matches_michell_and_converges():
    """Measured (arcs of +-18 deg, exact 6.507e-10 m/N): errors -0.28 %, -0.078 %, -0.019 %
    with 40, 80, 160 boundary edges (the polygonal boundary: O(h^2)); the series is
    converged to 1e-7."""
    alpha = math.radians(18.0)
    exact = michell_approach(alpha)
    assert exact == pytest.approx(6.5069e-10, rel=1e-4)
    assert michell_approach(alpha, 40000) == pytest.approx(exact, rel=1e-7)
    errors = [fe_approach(n, n // 10) / exact - 1.0 for n in (40, 80, 160)]
    assert -0.0032 < errors[0] < -0.0025
    assert -0.00022 < errors[-1] < 0.0
    rates = [math.log2(errors[i] / errors[i + 1]) for i in range(2)]
    assert all(1.7 < r < 2.2 for r in rates), rates


#: a pin like the RV-40E's (QT500-7, r = 3 mm, 15 mm disc, 1.8 mm load arc)
PIN = {"radius": 0.003, "E": 1.68e11, "nu": 0.24, "length": 0.015, "load_width": 0.0018,
       "steps": 8, "step_deg": 10.0, "version": 1}


@pytest.fixture(scope="module")
def coarse_pin():
    from rvsim.fe.pin import PinModel

    return PinModel(PIN, edges_per_load=8)


@pytest.fixture(scope="module")
def coarse_solves(coarse_pin):
    """(c_pin, contact flags) of the coarse pin at psi = 0, 10 .. 80 deg, each solve started
    from the last one's contact set (as rvsim.fe.pin builds its table)."""
    solves, touching = [], None
    for k in range(9):
        value, touching, _ = coarse_pin.solve(k * math.radians(10.0), touching)
        solves.append((value, touching))
    return solves


def test_pin_in_groove_converges_under_refinement(coarse_solves):
    """c_pin(0) with 4, 8, 16 boundary edges per load arc (44, 84, 168 around): 5.6331,
    5.6408, 5.6434 e-10 m/N (32 per arc: 5.6442): steps shrinking 2.9 times (the 8-edge
    model is the module's)."""
    from rvsim.fe.pin import PinModel

    values = [PinModel(PIN, edges_per_load=4).solve(0.0)[0], coarse_solves[0][0],
              PinModel(PIN, edges_per_load=16).solve(0.0)[0]]
    assert values == pytest.approx([5.6331e-10, 5.6408e-10, 5.6434e-10], rel=2e-4)
    assert (values[1] - values[0]) > 2.5 * (values[2] - values[1]) > 0.0


def test_pin_contact_set_and_symmetry(coarse_pin, coarse_solves):
    """Pressed straight into its groove the pin touches all of it; turned by psi it lifts off
    the groove's far end; the groove is symmetric, so is c_pin (measured 5e-5 and 1.4e-4 at
    20 and 40 deg: the inside of the mesh is not symmetric).  The solves at 0, 20 and 40 deg
    are the table's (coarse_solves); the one at 0 deg started from the whole groove."""
    c0, touching = coarse_solves[0]
    assert touching.all()
    c40, touching = coarse_solves[4]
    held = coarse_pin.groove_angles[touching]
    assert held.max() == pytest.approx(math.pi / 2)
    # measured -45 deg: the contact spans about 90 deg either side of the force (Persson)
    assert math.radians(-50.0) < held.min() < math.radians(-40.0)
    assert c40 > c0
    for degrees, plus in ((20.0, coarse_solves[2][0]), (40.0, c40)):
        minus = coarse_pin.solve(math.radians(-degrees))[0]
        assert plus == pytest.approx(minus, rel=3e-4)


def test_pin_table_interpolation(coarse_pin, coarse_solves):
    """The kernel's Catmull-Rom reading of the 10-deg table against the model solved at the
    angle: within 1.5e-4 up to 45 deg, 4e-4 at 55 deg (measured)."""
    from rvsim.physics._pin_compliance import table_value

    step = math.radians(10.0)
    table = np.array([value for value, _ in coarse_solves])
    assert np.all(np.diff(table) > 0.0)
    assert table[0] == pytest.approx(5.6408e-10, rel=1e-4)
    assert table[4] == pytest.approx(6.0315e-10, rel=1e-4)
    for degrees, tol in ((5, 3e-4), (15, 3e-4), (25, 3e-4), (35, 3e-4), (45, 3e-4), (55, 8e-4)):
        psi = math.radians(degrees)
        direct = coarse_pin.solve(psi)[0]
        assert table_value(table, step, math.cos(psi)) == pytest.approx(direct, rel=tol)
    # even in psi, held beyond the table's end
    assert table_value(table, step, math.cos(-0.3)) == table_value(table, step, math.cos(0.3))
    assert table_value(table, step, -1.0) == table[-1]


# --- both engines read the table at each contact's angle --------------------------------

def _coarse(values):
    """A coarse FE disc (when A), the crank and the plates rigid: the pins are what is tested."""
    return with_values(RV40E, {"flexibility.fe_element_size": 4.0,        # mm
                               "flexibility.fe_segments_per_tooth": 2,
                               "flexibility.fe_crank": False, "flexibility.fe_carrier": False,
                               **values})


def test_a_constant_table_is_the_closed_form_pin(monkeypatch):
    """A table holding Roark's constant gives the closed-form model's TE exactly: the table
    replaces P[PIN_CB]'s pin term and nothing else."""
    import rvsim.fe.pin as fe_pin
    from rvsim.physics import _layout as L
    from rvsim.dynamics.model import build_model
    from rvsim.quasistatic import ltca

    closed = _coarse({"B": 1})
    roark = build_model(closed, 1e-5).P[L.PIN_CB]
    assert roark == pytest.approx(2.1056e-9, rel=1e-4)
    table = fe_pin.PinTable(np.radians(10.0) * np.arange(9), np.full(9, roark), 0, 0, 0.0, True)
    monkeypatch.setattr(fe_pin, "pin_table", lambda reducer: table)
    fe = _coarse({"B": 1, "flexibility.model": "fe"})
    assert build_model(fe, 1e-5).P[L.PIN_CB] == 0.0
    a = ltca(closed, torque=300.0, positions=12, allow_aliasing=True)
    b = ltca(fe, torque=300.0, positions=12, allow_aliasing=True)
    assert np.max(np.abs(a.te - b.te)) < 1e-12 * np.max(np.abs(a.te))


@pytest.mark.parametrize("disc", [0, 1])
def test_quasi_static_te_equals_dynamic_mean_with_fe_pins(disc):
    """Low speed, constant load (as tests/verification/test_quasistatic.py, on the shorter
    schedule of tests/verification/_fe_runs.py), FE pins with the rigid disc (independent
    contacts; measured +5.8e-6, -3.0e-6 on the full low_speed schedule) and with the coarse FE
    disc (coupled contacts, the dynamic engine's one-step lag; measured +2.0e-6, -1.8e-5 on
    the full schedule: over windows of 0.3 .. 2 s the difference wanders within 2e-5)."""
    from tests.verification._fe_runs import quick_low_speed
    from tests.verification.test_quasistatic import engines_mean_te

    static, dynamic = engines_mean_te(quick_low_speed(_coarse({"B": 1, "A": disc,
                                                               "flexibility.model": "fe"})))
    assert static == pytest.approx(dynamic, rel=1e-5)


def test_the_pin_table_fills_its_block_of_p():
    """fe.pin states its table size as a literal (it sits below the physics layer, issue 31):
    the table's values are the kernel's P block of the pin table."""
    import rvsim.fe.pin as fe_pin
    from rvsim.physics import _layout as L

    assert fe_pin.TABLE_STEPS + 1 == L.PIN_FE_N
