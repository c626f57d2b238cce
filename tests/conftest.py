"""Shared fixtures: the built-in reducer, the paper's reference tables and a CLI runner."""

from __future__ import annotations

import io
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import pandas as pd
import pytest

from rvsim.cli import main
from rvsim.parameters import RV40E

REFERENCE = Path(__file__).parent / "reference" / "data"


@pytest.fixture
def rv40e():
    return RV40E


def reference_table(name: str) -> pd.DataFrame:
    """A table of shared/reference (copied to tests/reference/data; see its README).

    The last column may hold unquoted commas (free-text notes), so each line is split at most
    header-width - 1 times.
    """
    lines = [ln.rstrip("\n") for ln in (REFERENCE / name).read_text().splitlines()
             if ln.strip() and not ln.startswith("#")]
    header = lines[0].split(",")
    rows = [ln.split(",", len(header) - 1) for ln in lines[1:]]
    frame = pd.DataFrame(rows, columns=header)
    for name in frame.columns:
        try:
            frame[name] = pd.to_numeric(frame[name])
        except ValueError:
            pass  # text column
    return frame


class CliResult:
    def __init__(self, code: int, out: str, err: str):
        self.code, self.out, self.err = code, out, err


def run_cli(*args: str) -> CliResult:
    """Run ``rvsim ARGS`` in-process and capture its exit code and streams."""
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        try:
            code = main(list(args))
        except SystemExit as exc:  # --help / --version exit through argparse
            code = int(exc.code or 0)
    return CliResult(code, out.getvalue(), err.getvalue())


@pytest.fixture
def cli():
    return run_cli
