"""Stop signals raised and remembered (rvsim._stopping), with real signals to this process."""

import os
import signal
import sys
import types

import pytest

from rvsim import _stopping
from rvsim._stopping import check_stop, stop_requested, stop_signals
from rvsim.errors import Terminated

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")


def _signal_self(number):
    os.kill(os.getpid(), number)
    for _ in range(1000):          # the handler runs between bytecodes
        pass


def test_a_signal_raises_is_remembered_and_forgotten_by_the_outermost_block():
    before = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Terminated, match="SIGTERM"):
        with stop_signals():
            with stop_signals(("SIGTERM",)):     # a study runner inside the command line
                try:
                    _signal_self(signal.SIGTERM)
                except Terminated:
                    pass                          # swallowed on its way ...
            assert stop_requested()               # ... the inner block ends, still known
            check_stop()                          # ... and raised again
    assert not stop_requested()
    assert signal.getsignal(signal.SIGTERM) is before


def test_a_second_signal_while_the_first_unwinds_is_ignored():
    with pytest.raises(KeyboardInterrupt):
        with stop_signals():
            try:
                _signal_self(signal.SIGINT)
            except KeyboardInterrupt:
                _signal_self(signal.SIGINT)       # no second exception here
                raise


def test_an_ignored_signal_stays_ignored():
    previous = signal.signal(signal.SIGHUP, signal.SIG_IGN)
    try:
        with stop_signals():
            assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
            _signal_self(signal.SIGHUP)
        assert not stop_requested()
    finally:
        signal.signal(signal.SIGHUP, previous)


def test_the_unraisable_hook_drops_only_the_remembered_stop():
    seen = []
    stop = Terminated("SIGTERM")
    hook = _stopping._quiet(seen.append)
    other = types.SimpleNamespace(exc_value=ValueError("a finaliser's own error"))
    hook(other)                                   # no stop requested: passed on
    _stopping.request_stop(stop)
    try:
        hook(types.SimpleNamespace(exc_value=stop))
        hook(other)
    finally:
        _stopping._STOP.clear()
    assert seen == [other, other]


def test_a_signal_asked_again_later_raises_again():
    """A stop swallowed by numba's compiler (cold cache) was acted on 52 s later, and every
    signal in between was ignored as 'still unwinding'.  After REPEAT_AFTER it raises."""
    with pytest.raises(Terminated):
        with stop_signals():
            _stopping.request_stop(Terminated("SIGTERM"))            # lost on its way
            _stopping._SINCE[0] -= _stopping.REPEAT_AFTER + 0.5
            _signal_self(signal.SIGINT)                               # the user asks again
            pytest.fail("the second signal was ignored")


def test_the_handlers_change_with_the_signals_held_back(monkeypatch):
    """A signal between the restored hook and the restored handlers raised out of the block's
    end and left the nesting count, the remembered stop and the handler behind (a hostile
    test: within 10 s of random signals); every change is now made with them held back."""
    masks = []
    real = signal.signal

    def recording(number, handler):
        masks.append(set(signal.pthread_sigmask(signal.SIG_BLOCK, [])))
        return real(number, handler)

    monkeypatch.setattr(_stopping.signal, "signal", recording)
    with stop_signals():
        pass
    assert len(masks) == 6
    assert all(set(_stopping.STOP_SIGNALS) <= mask for mask in masks)
    assert not set(_stopping.STOP_SIGNALS) & set(signal.pthread_sigmask(signal.SIG_BLOCK, []))
