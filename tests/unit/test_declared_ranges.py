"""The declared dependency ranges (pyproject.toml) are ranges, and the suite runs inside them.

Found on a fresh machine: CI passed with the pytest the machine already had (9.0.3), while a
fresh virtual environment resolved pytest 9.2.0 and a test failed.  The README's test command
now upgrades to the newest versions the ranges allow, each range's lower bound is the version
the suite was last run with, and this test fails when an installed version lies outside its
declared range (an older package left on the machine) or a range has no upper bound.
"""

from __future__ import annotations

import tomllib
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import pytest
from packaging.requirements import Requirement

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"


def _requirements() -> list[Requirement]:
    project = tomllib.loads(PYPROJECT.read_text())["project"]
    extras = project["optional-dependencies"]
    texts = project["dependencies"] + extras["fe"] + extras["test"] + extras["parquet"]
    return [Requirement(t) for t in texts if not t.startswith("rvsim")]


@pytest.mark.parametrize("requirement", _requirements(), ids=lambda r: r.name)
def test_each_dependency_is_a_bounded_range_that_holds_the_installed_version(requirement):
    operators = {spec.operator for spec in requirement.specifier}
    assert ">=" in operators and "<" in operators, \
        f"{requirement}: a compatible range needs a lower (>=) and an upper (<) bound"
    try:
        installed = version(requirement.name)
    except PackageNotFoundError:
        pytest.skip(f"{requirement.name} is not installed (an extra left out)")
    assert requirement.specifier.contains(installed, prereleases=True), (
        f"{requirement.name} {installed} is installed but the tested range is "
        f"{requirement.specifier}: run the README's test command (pip install --upgrade ...)")
