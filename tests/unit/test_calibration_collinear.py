"""Two checks of a calibration on inputs built by hand: set-wise identifiability (the condition
index of the Jacobian with unit-length columns; Belsley, Kuh & Welsch 1980) and an estimate
left on its bound (scipy's active_mask)."""

import numpy as np

from rvsim.testrig import calibration as C
from rvsim.testrig.calibration import CONDITION_LIMIT, _collinear

NAMES = ["a", "b", "c"]


def _jacobian(mix):
    """Three sensitivity columns over 101 samples; the third is a + b plus ``mix`` of a
    column of its own (a smaller ``mix``: a flatter combination)."""
    t = np.linspace(-1.0, 1.0, 101)
    a, b, own = np.sin(3 * t), t ** 2, np.cos(7 * t)
    return np.column_stack([a, b, a + b + mix * own])


def _index(J):
    sv = np.linalg.svd(J / np.linalg.norm(J, axis=0), compute_uv=False)
    return sv[0] / sv[-1]


def test_a_flat_combination_is_not_identifiable_though_no_pair_is():
    J = _jacobian(0.02)
    corr = np.corrcoef(J.T)
    assert np.max(np.abs(corr[np.triu_indices(3, 1)])) < 0.999       # the pairwise rule passes
    notes = []
    assert _collinear(J, NAMES, {}, notes) == {0, 1, 2}
    assert _index(J) > CONDITION_LIMIT
    assert notes == [f"the data fix a combination of a, b, c, not each (condition index "
                     f"{_index(J):.0f} of the scaled Jacobian, above 30: Belsley, Kuh & Welsch "
                     "1980): fix all but one of them, or add a test that separates them"]


def test_a_well_conditioned_fit_is_left_alone():
    J = _jacobian(1.0)
    notes = []
    assert _index(J) < CONDITION_LIMIT
    assert _collinear(J, NAMES, {}, notes) == set() and notes == []


def test_a_blocked_column_is_left_out():
    J = _jacobian(0.02)
    J[:, 2] = 0.0                   # the model failed on both sides of c: no column
    assert _collinear(J, NAMES, {2: "fails"}, []) == set()


def test_an_estimate_the_data_push_onto_its_bound_is_no_fit():
    """scipy's active_mask (-1: lower bound active): efficiency points of RV-40E fitted with
    RV-40E-bearings gave a pin friction of 1.8e-15, status ok before (hostile5); at_bound now."""
    from types import SimpleNamespace

    from rvsim.testrig.calibration import _on_bound

    specs = [SimpleNamespace(unit="-"), SimpleNamespace(unit="mm")]
    names = ["contact.friction_coefficient", "clearances.crank_arm_bushing"]
    notes = []
    assert _on_bound(np.array([-1, 0]), np.array([1.8e-15, 0.004]), names, specs, set(), {},
                     notes)
    assert notes == ["contact.friction_coefficient stopped on its lower bound (1.8e-15 -): the "
                     "data push it beyond its range, so the value is the bound, not a fit "
                     "(check the recording's units and columns and the parameter set it is "
                     "fitted from)"]
    assert not _on_bound(np.array([0, 0]), np.array([0.03, 0.004]), names, specs, set(), {}, [])
    # a parameter already not identifiable (or blocked) is said so, not twice
    assert not _on_bound(np.array([-1, 0]), np.array([0.0, 0.004]), names, specs, {0}, {}, [])


def test_lack_of_fit_is_residuals_of_one_sign_for_long_runs():
    """The runs test of the fitted residuals (issue 30, fifth session): noise keeps its status,
    a misfit (a smooth curve: few runs of one sign) is lack_of_fit, a curve at the model's
    numerical resolution (a noise-free fit of the model's own curve) is not judged."""
    rng = np.random.default_rng(1)
    noise = rng.normal(0.0, 0.1, 101)
    notes = []
    assert not C._systematic(noise, 40.0, notes) and notes == []
    misfit = np.sin(np.linspace(0.0, 4.0 * np.pi, 101)) + noise      # 5 half waves
    assert C._systematic(misfit, 40.0, notes)
    assert len(notes) == 1 and "runs test z = " in notes[0]
    assert not C._systematic(misfit * 1e-8, 40.0, [])           # below 1e-6 of the data's RMS
    assert not C._systematic(np.array([np.nan, 1.0, 2.0]), 40.0, [])
