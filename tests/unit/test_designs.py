"""Designs: orthogonal arrays are strength-2 balanced; the paper's L36 assignment; samplers."""

import numpy as np
import pytest

from rvsim.doe import (assign_columns, full_factorial, is_strength2_balanced, latin_hypercube,
                       orthogonal_array, paper_l36, sobol)
from rvsim.errors import ParameterError
from rvsim.parameters import paper_l36_scheme

ARRAYS = ["L4", "L8", "L9", "L12", "L16", "L18", "L27", "L36"]


@pytest.mark.parametrize("name", ARRAYS)
def test_every_array_is_strength_2_balanced(name):
    array = orthogonal_array(name)
    assert array.min() == 1
    assert is_strength2_balanced(array)


def test_balance_check_detects_an_unbalanced_array():
    array = orthogonal_array("L9").copy()
    array[0, 0] = 2
    assert not is_strength2_balanced(array)


def test_pydoe3_l36_is_l36_2_11_3_12():
    array = orthogonal_array("L36")
    levels = [len(np.unique(array[:, j])) for j in range(array.shape[1])]
    assert levels.count(2) == 11 and levels.count(3) == 12


def test_paper_assignment_reproduces_table3_scheme():
    table = paper_l36().table()
    letters = list("ABCDEFGHIJKLMNO")
    np.testing.assert_array_equal(table[letters].to_numpy(),
                                  paper_l36_scheme()[letters].to_numpy())


def test_assign_columns_refuses_missing_level_count():
    with pytest.raises(ParameterError, match="no free 3-level column"):
        assign_columns(orthogonal_array("L4"), [2, 3], "L4")


def test_full_factorial_and_samplers():
    ff = full_factorial([2, 3])
    assert ff.shape == (6, 2) and len({tuple(r) for r in ff}) == 6
    lhs = latin_hypercube(10, 3, seed=1)
    assert lhs.shape == (10, 3)
    # Latin property: each of the 10 strata holds one point per dimension
    for j in range(3):
        assert sorted(np.floor(lhs[:, j] * 10).astype(int)) == list(range(10))
    assert sobol(16, 2).shape == (16, 2)
    with pytest.raises(ParameterError, match="power of two"):
        sobol(10, 2)


def test_study_objects_refuse_contradictions_and_oversized_designs():
    from rvsim.doe.study import MAX_RUNS, Study, StudyFactor

    h = StudyFactor("H", "errors.pin_circle_radius", (0.0, 0.02))
    with pytest.raises(ParameterError, match="time_step"):
        Study("s", (h,), design="L4", time_step=0.0)      # was silently the default step
    with pytest.raises(ParameterError, match="already varies"):
        Study("s", (h, StudyFactor("X", "errors.pin_circle_radius", (0.0, 0.01))), "L4")
    with pytest.raises(ParameterError, match="also varied"):
        Study("s", (h,), "L4", fixed=(("errors.pin_circle_radius", 0.01),))
    with pytest.raises(ParameterError, match="results.csv"):
        Study("s", (StudyFactor("status", "errors.pin_circle_radius", (0.0, 0.02)),), "L4")
    many = tuple(StudyFactor(f"F{i}", name, tuple(range(5))) for i, name in enumerate(
        ["errors.pin_radius", "errors.eccentricity", "errors.pin_circle_radius",
         "errors.equidistant_modification", "errors.radial_modification",
         "errors.rotation_modification", "errors.disc_runout", "clearances.crank_arm_bushing"]))
    assert 5 ** 8 > MAX_RUNS
    with pytest.raises(ParameterError, match="full factorial"):
        Study("s", many, design="full")
    with pytest.raises(ParameterError, match="samples"):
        Study("s", (StudyFactor("H", "errors.pin_circle_radius", low=0.0, high=0.02),),
              design="lhs", samples=MAX_RUNS + 1)


def test_reserved_labels_cover_every_metric_column():
    # a factor label must never overwrite a metric column of results.csv
    from rvsim.doe.study import RESULT_COLUMNS
    from rvsim.dynamics.result import te_metrics

    t = np.linspace(0.0, 1.0, 11)
    keys = te_metrics(t, 1e-4 * t, np.ones_like(t), np.ones_like(t), 0.5)
    assert all(k in RESULT_COLUMNS or k.startswith("te_") for k in keys)
