"""A command that compiles says so once, and keeps the compile time out of its run time (issue
34 item 3, issue 35 item 3).

The one cold test of the suite: numba compiles the quasi-static solver into an empty, private
cache folder (``NUMBA_CACHE_DIR``), 30-60 s on a quiet 2-core machine (several minutes on a
busy one); ``rvsim ltca --positions 81`` is the cheapest command that compiles.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from rvsim._cache_guard import COMPILING

SRC = str(Path(__file__).resolve().parents[2] / "src")


def _ltca(cache: Path, *extra: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache),
           "PYTHONPATH": SRC + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.run([sys.executable, "-m", "rvsim", "ltca", "--positions", "81", *extra],
                          capture_output=True, text=True, env=env, check=True)


def test_cold_ltca_says_it_compiles_once_then_never(tmp_path):
    cache = tmp_path / "numba-cache"
    cold = _ltca(cache, "--json")
    assert cold.stderr.count(COMPILING) == 1 and cold.stderr.strip() == COMPILING
    summary = json.loads(cold.stdout)           # stdout stays one JSON object
    assert summary["status"] == "ok"
    # the compilation is reported apart, and is not in the solve's wall time (81 positions
    # solve in 0.05-0.4 s; the compilation takes tens of seconds)
    assert summary["compile_s"] > 5.0 and summary["wall_s"] < summary["compile_s"] / 10
    warm = _ltca(cache)                          # a fresh process, the cache written
    assert warm.stderr == ""
    assert "compiling" not in warm.stdout and "status ok" in warm.stdout
