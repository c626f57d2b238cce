"""A command that compiles says so once, and keeps the compile time out of its run time (issue
34 item 3, issue 35 item 3).

The one cold test of the suite compiles into a private cache folder (``NUMBA_CACHE_DIR``) with
``rvsim profile``, whose compiled functions are the geometry's curve functions: the folder holds
a copy of the suite's cached curve functions but one (``curvatures``, which ``profile`` calls),
so that the command compiles that one alone (about 0.4 s of CPU; all seven took 4 s); a cold
``ltca`` would compile the whole quasi-static solver
(about 150 s of CPU), which the suite's time cannot afford (issue 30).  That the compile time is
counted apart and kept out of ``wall_s`` is checked on a tiny compiled function
(tests/unit/test_compile_watch.py); here, that a warm command reports ``compile_s`` 0.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import shutil
from pathlib import Path

from rvsim._cache_guard import COMPILING

SRC = str(Path(__file__).resolve().parents[2] / "src")


def _rvsim(*args: str, cache: Path | None = None) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": SRC + os.pathsep + os.environ.get("PYTHONPATH", "")}
    if cache is not None:
        env["NUMBA_CACHE_DIR"] = str(cache)
    return subprocess.run([sys.executable, "-m", "rvsim", *args], capture_output=True,
                          text=True, env=env, check=True)


def _all_curve_functions_but_one(cache: Path, left_out: str = "curvatures") -> None:
    """Copy the cached curve functions (and the cache guard's stamp) from the folder numba
    uses in this process into ``cache`` as numba lays out a NUMBA_CACHE_DIR, but
    ``left_out``'s files."""
    from numba.core.caching import _CacheLocator

    from rvsim.geometry import _curve

    source = Path(_curve.curve_point._cache._cache_path)
    target = cache / _CacheLocator.get_suitable_cache_subpath(_curve.__file__)
    target.mkdir(parents=True)
    for path in source.glob("*"):
        if path.name.startswith(("_curve.", "rvsim__curve")) and \
                not path.name.startswith(f"_curve.{left_out}-"):
            shutil.copy2(path, target / path.name)


def test_a_cold_command_says_it_compiles_once_then_never(tmp_path):
    cache = tmp_path / "numba-cache"
    _all_curve_functions_but_one(cache)
    cold = _rvsim("profile", "--out", str(tmp_path / "cold.dxf"), "--points", "117",
                  cache=cache)
    assert cold.stderr.count(COMPILING) == 1 and cold.stderr.strip() == COMPILING
    assert "compiling" not in cold.stdout
    warm = _rvsim("profile", "--out", str(tmp_path / "warm.dxf"), "--points", "117",
                  cache=cache)
    assert warm.stderr == ""                     # a fresh process, the cache written


def test_a_warm_command_reports_no_compile_time(cli):
    # warm (the suite's warm-up did it already; here in this process, into the same cache)
    assert cli("ltca", "--positions", "81").code == 0
    summary = json.loads(_rvsim("ltca", "--positions", "81", "--json").stdout)
    assert summary["status"] == "ok" and summary["compile_s"] == 0.0
