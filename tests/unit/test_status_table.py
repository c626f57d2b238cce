"""The one table of status codes of both engines (rvsim.physics._status; issue 31 step 10)."""
from __future__ import annotations

from rvsim.physics import _status


def test_every_code_and_every_name_is_defined_once():
    codes = [code for code, _, _ in _status.STATUSES]
    names = [name for _, name, _ in _status.STATUSES]
    assert len(set(codes)) == len(codes)
    assert len(set(names)) == len(names)
    # every STATUS_* constant is a row of the table, and every row has its constant
    constants = {value for key, value in vars(_status).items()
                 if key.startswith("STATUS_") and isinstance(value, int)}
    assert constants == set(codes)


def test_the_public_status_strings_are_those_of_before_the_table():
    # the strings results, JSON and CSV files carry (dynamic runs, quasi-static points)
    assert _status.STATUS_TEXT == {0: "ok", 1: "diverged", 2: "runaway_penetration",
                                   3: "energy_imbalance", 4: "speed_ratio_off",
                                   5: "not_converged", 6: "singular_stiffness"}
    assert all(_status.STATUS_MESSAGE[code] == name.replace("_", " ")
               for code, name in _status.STATUS_TEXT.items())
