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
