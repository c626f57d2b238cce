"""One name per concept (issue 34 item 5): a renamed keyword of the public API keeps its old
name for a release with a DeprecationWarning naming the new one (``rvsim._keywords.renamed``,
the one helper), and the command line takes the canonical name beside the old one."""

import inspect
import warnings

import pytest

from rvsim._keywords import renamed
from rvsim.cli import build_parser
from rvsim.errors import InputFileError
from rvsim.parameters import RV40E


@renamed(points="positions")
def _count(*, positions: int = 4) -> int:
    return positions


def test_the_old_keyword_works_and_warns_naming_the_new_one():
    with pytest.warns(DeprecationWarning, match="'points' is deprecated, use 'positions'") as got:
        assert _count(points=7) == 7
    assert got[0].filename == __file__            # the caller's line, not the helper's
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert _count(positions=7) == 7 and _count() == 4
    with pytest.raises(TypeError, match="got both 'points' and 'positions'"):
        _count(points=1, positions=2)


def test_a_renamed_function_keeps_its_signature_and_docstring():
    from rvsim.testrig.bench import analyse_path

    assert "positions" in inspect.signature(analyse_path).parameters
    assert "points" not in inspect.signature(analyse_path).parameters
    assert "positions" in analyse_path.__doc__
    with pytest.warns(DeprecationWarning, match="analyse_path\\(\\): the keyword 'points'"):
        with pytest.raises(InputFileError):           # the call goes on with the new name
            analyse_path("no-such-folder", RV40E, points=256)


@pytest.mark.parametrize("old, new", [
    (["efficiency", "--speeds", "500"], ["efficiency", "--speeds-rpm", "500"]),
    (["grid", "--speeds", "500", "--torques", "1", "--out", "g", "--temperatures", "20"],
     ["grid", "--speeds-rpm", "500", "--torques", "1", "--out", "g", "--temperatures-c", "20"]),
    (["life", "--output-speed", "10"], ["life", "--output-speed-rpm", "10"]),
    (["testrig", "x", "--points", "256"], ["testrig", "x", "--positions", "256"]),
])
def test_the_command_line_takes_both_names(old, new):
    parser = build_parser()
    a, b = vars(parser.parse_args(old)), vars(parser.parse_args(new))
    assert {k: v for k, v in a.items() if k != "func"} == \
        {k: v for k, v in b.items() if k != "func"}
