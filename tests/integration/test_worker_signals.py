"""The study's worker pool and stop signals (a hostile test, seventh session): a signal that
reached the parent while it forked a worker used to live on in the worker (its remembered
stop, its handlers), so every run it was given died with the worker ("worker_died" rows),
and the parent, whose own exception had been lost in an after-fork callback, went on."""

import json
import multiprocessing
import signal
import sys

import pytest

import rvsim.doe.runner

from rvsim import _stopping
from rvsim.doe import load_study
from rvsim.doe._workers import run_workers
from rvsim.errors import Terminated
from tests.integration.conftest import write_study

pytestmark = pytest.mark.skipif(sys.platform == "win32" or
                                multiprocessing.get_start_method() != "fork",
                                reason="POSIX signals, forked workers")


def _task(tmp_path):
    reducer = load_study(write_study(tmp_path)).reducers()[0]
    return (reducer, 1e-5, "dynamic", False, 360, "explicit")


def test_a_stop_lost_before_the_workers_start_stops_the_pool(tmp_path):
    results = {}
    with _stopping.stop_signals():
        _stopping.request_stop(Terminated("SIGTERM"))     # its exception lost on its way
        with pytest.raises(Terminated):
            run_workers({"a": _task(tmp_path), "b": _task(tmp_path), "c": _task(tmp_path)},
                        2, results.__setitem__, task=rvsim.doe.runner.evaluate_task)
    assert results == {}            # no run stored, least of all as "worker_died"


def test_a_worker_starts_with_its_own_signal_state(tmp_path, monkeypatch):
    """What a worker sees of the parent's stop machinery: nothing (no remembered stop, the
    default unraisable hook, no signal held back, SIGINT ignored, SIGTERM at its default)."""
    import rvsim.doe.runner

    seen = tmp_path / "seen.json"

    def probe(*args):
        seen.write_text(json.dumps({
            "stop": _stopping.stop_requested(),
            "default_hook": sys.unraisablehook is sys.__unraisablehook__,
            "blocked": sorted(int(s) for s in signal.pthread_sigmask(signal.SIG_BLOCK, [])
                              if s in _stopping.STOP_SIGNALS),
            "sigint_ignored": signal.getsignal(signal.SIGINT) is signal.SIG_IGN,
            "sigterm_default": signal.getsignal(signal.SIGTERM) is signal.SIG_DFL}))
        return {"status": "ok", "metrics": {}}

    monkeypatch.setattr(rvsim.doe.runner, "evaluate", probe)
    results = {}
    with _stopping.stop_signals():
        with _stopping.signals_blocked():       # as during a fork
            _stopping.request_stop(Terminated("SIGTERM"))
            with pytest.raises(Terminated):
                run_workers({"a": _task(tmp_path)}, 1, results.__setitem__,
                            task=rvsim.doe.runner.evaluate_task)
    assert json.loads(seen.read_text()) == {"stop": False, "default_hook": True, "blocked": [],
                                            "sigint_ignored": True, "sigterm_default": True}
    assert results == {}
