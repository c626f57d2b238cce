"""The command line starts fast because heavy libraries load only inside the commands
(issue 8, item 8).  Times are measured by benchmarks/bench_startup.py; this test checks the
structure that makes them small: what ``rvsim --help`` and ``import rvsim`` load."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = ("numba", "pandas", "scipy", "pyDOE3", "matplotlib", "distributed", "statsmodels")


def _loaded_after(code: str) -> set[str]:
    probe = (f"import sys\n{code}\nimport json\n"
             f"print(json.dumps([m for m in {list(HEAVY)!r} if m in sys.modules]))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stdout
    return set(json.loads(out.strip().splitlines()[-1]))


@pytest.mark.parametrize("code", [
    "import rvsim",
    "from rvsim.cli import build_parser; build_parser().format_help()",
    "import rvsim.dynamics, rvsim.doe",
    "import rvsim.analysis.catalogue",   # on the quasi-static engine's first-call path
])
def test_no_heavy_library_at_start_up(code):
    assert _loaded_after(code) == set()


def test_lazy_names_resolve():
    import rvsim
    import rvsim.doe
    import rvsim.dynamics

    assert callable(rvsim.simulate) and callable(rvsim.dynamics.simulate)
    assert rvsim.dynamics.DEFAULT_TIME_STEP == 5e-6
    assert callable(rvsim.doe.paper_l36)
    assert set(rvsim.__all__) <= set(dir(rvsim))
