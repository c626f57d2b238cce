"""The compile notice and the compile time (issue 34 item 3, issue 35 item 3), without compiling
rvsim's kernels: a tiny numba function, compiled in a private cache folder, stands for them
(rvsim._cache_guard: numba's "numba:compile" event)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
import types
from pathlib import Path

import pytest

from rvsim import _cache_guard
from rvsim._cache_guard import COMPILING, _CompileWatch
from rvsim.doe._workers import run_workers

SRC = Path(__file__).resolve().parents[2] / "src"

#: two cached functions, one calling the other, and a process that registers the listener,
#: then compiles (or loads) them and a foreign function; prints what the watch saw as JSON
KERNELS = '''
import numba


@numba.njit(cache=True)
def inner(x):
    return x + 1


@numba.njit(cache=True)
def outer(x):
    return inner(x) * 2
'''

PROBE = '''
import json
import numba
from rvsim import _cache_guard
from rvsim._cache_guard import RunClock, compile_seconds, compiled_or_cached, watch_compiles

watch_compiles()
watch_compiles()            # once per process, however often it is asked
_cache_guard._WATCH.packages = ("rvsim.", "probe_kernels")     # stands for rvsim's kernels
from probe_kernels import outer


@numba.njit
def foreign(x):
    return x - 1


cached_before = compiled_or_cached(outer)
foreign(1)                  # not rvsim's: no notice, not counted
after_foreign = compile_seconds()
clock = RunClock()
outer(1)
outer(2)                    # compiled once
run, compiled = clock.split()
print(json.dumps({"cached_before": cached_before, "after_foreign": after_foreign,
                  "compiled": compiled, "total": compile_seconds(), "run": run,
                  "cached_after": compiled_or_cached(outer)}))
'''


def _probe(tmp_path) -> tuple[dict, str]:
    script = tmp_path / "probe.py"
    script.write_text(PROBE)
    (tmp_path / "probe_kernels.py").write_text(KERNELS)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
           "PYTHONPATH": str(SRC) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          env=env, cwd=tmp_path, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1]), done.stderr


def test_notice_once_when_compiling_and_never_from_a_warm_cache(tmp_path):
    cold, err = _probe(tmp_path)
    assert err.count(COMPILING) == 1 and err.strip() == COMPILING
    assert not cold["cached_before"] and cold["cached_after"]
    assert cold["after_foreign"] == 0.0          # a foreign function is not rvsim's compile
    # the nested function compiles inside the outer one's event: counted once, all in the clock
    assert cold["compiled"] > 0 and cold["compiled"] == cold["total"]
    warm, err = _probe(tmp_path)                  # a fresh process, the cache written
    assert err == ""
    assert warm["cached_before"] and warm["compiled"] == warm["total"] == 0.0


class _Dispatcher:
    def __init__(self, module):
        self.py_func = lambda: None
        self.py_func.__module__ = module


def test_watch_counts_outermost_rvsim_compilations(monkeypatch, caplog):
    clock = iter([10.0, 12.5, 20.0, 21.0])
    monkeypatch.setattr(_cache_guard, "time", types.SimpleNamespace(
        perf_counter=lambda: next(clock)))
    watch = _CompileWatch()
    with caplog.at_level("WARNING", logger="rvsim.compile"):
        watch.start(_Dispatcher("rvsim.dynamics._kernel"))     # 10.0
        watch.start(_Dispatcher("rvsim.physics._contact_law"))  # nested: no clock
        watch.end()
        watch.end()                                             # 12.5
        watch.start(_Dispatcher("numpy_user_code"))             # foreign: not timed
        watch.end()
        watch.start(_Dispatcher("rvsim.quasistatic._solver"))   # 20.0
        watch.end()                                             # 21.0
    assert watch.seconds == pytest.approx(3.5, abs=1e-12)
    assert [r.getMessage() for r in caplog.records] == [COMPILING]     # said once


def _stamp(key, delay):
    start = time.time()
    time.sleep(delay)
    return key, {"pid": os.getpid(), "start": start, "end": time.time()}


def test_first_alone_holds_the_other_workers_until_the_first_run_is_back():
    outcomes = {}
    run_workers({f"r{i}": (0.2,) for i in range(4)}, 2,
                lambda key, outcome: outcomes.__setitem__(key, outcome), task=_stamp,
                first_alone=True)
    first = min(outcomes.values(), key=lambda o: o["start"])
    others = [o for o in outcomes.values() if o["pid"] != first["pid"]]
    assert others, "the second worker never started"
    assert all(o["start"] >= first["end"] for o in others)


def test_cli_compile_figures(monkeypatch):
    from rvsim.cli import _common

    monkeypatch.setattr(_cache_guard._WATCH, "seconds", 0.0)
    assert _common.compile_time_text() == ""
    assert _common.with_compile_time({"wall_s": 0.2}) == {"wall_s": 0.2, "compile_s": 0.0}
    monkeypatch.setattr(_cache_guard._WATCH, "seconds", 51.6)
    assert _common.compile_time_text() == ", + 52 s compiling"
    assert _common.with_compile_time({"wall_s": 0.2})["compile_s"] == 51.6
