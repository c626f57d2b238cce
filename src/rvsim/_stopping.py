"""Stop signals: SIGINT, SIGTERM and SIGHUP raised as exceptions, and remembered.

While :func:`stop_signals` is active, SIGINT raises KeyboardInterrupt and SIGTERM or SIGHUP
:class:`rvsim.errors.Terminated` (a KeyboardInterrupt), so whatever is being written unwinds
and its temporary file is removed.  Each signal is also remembered until the outermost
:func:`stop_signals` ends, because numba's compiler loses such an exception in three ways:
it swallows it in a callback (and the command would go on), it lets it land in a finaliser
(Python prints "Exception ignored in: ..." and a traceback) or it lets another exception out
in its place ("RuntimeError: no compiled object yet").  :func:`check_stop` raises the
remembered stop again: before an output is moved into place, between a simulation's chunks,
and when any other exception ends a command.  A second signal while the first unwinds is
ignored; a signal the user ignores (``nohup``) stays ignored.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from typing import Iterator

from .errors import Terminated

__all__ = ["stop_signals", "check_stop", "stop_requested", "request_stop"]

#: the interrupt that a stop signal raised in this process (at most one)
_STOP: list[BaseException] = []
#: nesting of :func:`stop_signals` (the command line's, then a study runner's inside it)
_DEPTH: list[int] = [0]


def request_stop(interrupt: BaseException) -> None:
    """Remember ``interrupt`` until the outermost :func:`stop_signals` ends."""
    _STOP[:] = [interrupt]


def stop_requested() -> bool:
    return bool(_STOP)


def check_stop() -> None:
    """Raise the remembered interrupt again, if a signal asked this process to stop."""
    if _STOP:
        raise _STOP[0]


def _stop(signum, frame):
    if _STOP:                     # a second signal while the first unwinds: one is enough
        return
    interrupt = (KeyboardInterrupt() if signum == signal.SIGINT
                 else Terminated(signal.Signals(signum).name))
    request_stop(interrupt)
    raise interrupt


def _quiet(then):
    """A :data:`sys.unraisablehook` that says nothing of the remembered interrupt (it is
    raised again at the next :func:`check_stop`); anything else goes on to ``then``."""
    def hook(unraisable) -> None:
        if not (_STOP and unraisable.exc_value is _STOP[0]):
            then(unraisable)
    return hook


@contextlib.contextmanager
def stop_signals(names: tuple[str, ...] = ("SIGINT", "SIGTERM", "SIGHUP")) -> Iterator[None]:
    """Raise and remember the signals ``names`` (those not ignored) for the ``with`` block.

    Outside the main thread, where Python cannot set handlers, nothing is changed.  The
    previous handlers and unraisable hook are restored afterwards; the remembered stop is
    forgotten when the outermost block ends.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {}
    hook = sys.unraisablehook
    _DEPTH[0] += 1
    try:
        for name in names:
            number = getattr(signal, name, None)
            if number is not None and signal.getsignal(number) is not signal.SIG_IGN:
                previous[number] = signal.signal(number, _stop)
        sys.unraisablehook = _quiet(hook)
        yield
    finally:
        sys.unraisablehook = hook
        for number, handler in previous.items():
            if handler is not None:      # None: installed from C, cannot be put back
                signal.signal(number, handler)
        _DEPTH[0] -= 1
        if not _DEPTH[0]:
            _STOP.clear()
