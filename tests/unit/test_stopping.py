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
