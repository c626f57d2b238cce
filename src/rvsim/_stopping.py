"""Stop signals: SIGINT, SIGTERM and SIGHUP raised as exceptions, and remembered.

While :func:`stop_signals` is active, SIGINT raises KeyboardInterrupt and SIGTERM or SIGHUP
:class:`rvsim.errors.Terminated` (a KeyboardInterrupt), so whatever is being written unwinds
and its temporary file is removed.  Each signal is also remembered until the outermost
:func:`stop_signals` ends, because numba's compiler loses such an exception in three ways:
it swallows it in a callback (and the command would go on), it lets it land in a finaliser
(Python prints "Exception ignored in: ..." and a traceback) or it lets another exception out
in its place ("RuntimeError: no compiled object yet").  :func:`check_stop` raises the
remembered stop again: before an output is moved into place, between a simulation's chunks,
while a study waits for its workers, and when any other exception ends a command.  A second
signal within :data:`REPEAT_AFTER` of the first (it is still unwinding) is ignored; a later
one raises the stop again.  A signal the user ignores (``nohup``) stays ignored.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
from typing import Iterator

from .errors import Terminated

__all__ = ["stop_signals", "check_stop", "stop_requested", "request_stop", "signals_blocked",
           "forget_stop", "die_with_parent", "STOP_SIGNALS"]

#: the signals that stop a command
STOP_SIGNALS = tuple(getattr(signal, n) for n in ("SIGINT", "SIGTERM", "SIGHUP")
                     if hasattr(signal, n))
#: a signal this long after the first one raises the stop again (the first was swallowed
#: somewhere and the user asks again); sooner, the first is still unwinding: ignored
REPEAT_AFTER = 1.0

#: the interrupt that a stop signal raised in this process (at most one)
_STOP: list[BaseException] = []
#: nesting of :func:`stop_signals` (the command line's, then a study runner's inside it)
_DEPTH: list[int] = [0]
#: when the remembered stop came (time.monotonic)
_SINCE: list[float] = [0.0]


def request_stop(interrupt: BaseException) -> None:
    """Remember ``interrupt`` until the outermost :func:`stop_signals` ends."""
    _STOP[:] = [interrupt]
    _SINCE[0] = time.monotonic()


def forget_stop() -> None:
    """Forget any remembered stop and the nesting (a forked worker process starts afresh)."""
    _STOP.clear()
    _DEPTH[0] = 0


def stop_requested() -> bool:
    return bool(_STOP)


def check_stop() -> None:
    """Raise the remembered interrupt again, if a signal asked this process to stop."""
    if _STOP:
        raise _STOP[0]


def _stop(signum, frame):
    if _STOP:
        if time.monotonic() - _SINCE[0] < REPEAT_AFTER:
            return                # a second signal while the first unwinds: one is enough
        _SINCE[0] = time.monotonic()
        raise _STOP[0]            # asked again: the first was lost on its way
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
def signals_blocked() -> Iterator[None]:
    """Hold the stop signals back for the ``with`` block (delivered when it ends): a fork, or
    the handlers' own bookkeeping, is not interrupted half-way.  No-op where the platform
    has no signal masks, and outside the main thread."""
    if not hasattr(signal, "pthread_sigmask") or \
            threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


@contextlib.contextmanager
def stop_signals(names: tuple[str, ...] = ("SIGINT", "SIGTERM", "SIGHUP")) -> Iterator[None]:
    """Raise and remember the signals ``names`` (those not ignored) for the ``with`` block.

    Outside the main thread, where Python cannot set handlers, nothing is changed.  The
    previous handlers and unraisable hook are restored afterwards; the remembered stop is
    forgotten when the outermost block ends.  The handlers are installed and restored with
    the signals held back, so a signal cannot leave them half-changed.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {}
    hook = sys.unraisablehook
    with signals_blocked():
        _DEPTH[0] += 1
        for name in names:
            number = getattr(signal, name, None)
            if number is not None and signal.getsignal(number) is not signal.SIG_IGN:
                previous[number] = signal.signal(number, _stop)
        sys.unraisablehook = _quiet(hook)
    try:
        yield
    finally:
        with signals_blocked():
            sys.unraisablehook = hook
            for number, handler in previous.items():
                if handler is not None:      # None: installed from C, cannot be put back
                    signal.signal(number, handler)
            _DEPTH[0] -= 1
            if not _DEPTH[0]:
                _STOP.clear()


def die_with_parent(parent_pid: int) -> None:
    """In a child process (a study's worker, a mesher child): die when the parent
    ``parent_pid`` dies (PR_SET_PDEATHSIG on Linux), or at once if it already has.  Moved from
    ``rvsim.doe._workers`` (issue 31 step 7) so that :mod:`rvsim.fe.mesh` need not import a
    study module."""
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, signal.SIGKILL)          # PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent_pid:                 # the parent died before prctl
        os._exit(1)
