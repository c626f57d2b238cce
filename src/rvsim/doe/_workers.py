"""Local worker processes of a study, each with its own pipe, faults contained.

The parent starts N long-lived workers (numba's kernel is loaded once per worker), sends each
one run at a time and waits on the result pipes and the process sentinels together, so it
knows which run a dead worker held.  A run whose worker dies is sent again to a fresh worker;
a run that kills its worker twice is returned as failed with the reason.  Workers ignore
SIGINT (the parent decides), die with the parent (PR_SET_PDEATHSIG on Linux; elsewhere when
their pipe closes) and are terminated when the parent stops for any reason.
"""

from __future__ import annotations

import collections
import multiprocessing
import os
import signal
import sys
from multiprocessing.connection import wait
from typing import Callable

from .._stopping import STOP_SIGNALS, check_stop, die_with_parent, forget_stop, signals_blocked
from ..errors import RvsimError

__all__ = ["run_workers", "TEST_KILL_ENV", "MAX_ATTEMPTS", "WorkerStartError"]

#: test-only hook: a worker given a run whose key starts with this value SIGKILLs itself
TEST_KILL_ENV = "RVSIM_TEST_KILL_RUN"
#: worker deaths a run may cause before it is stored as failed
MAX_ATTEMPTS = 2


class WorkerStartError(RvsimError):
    """No worker process could be started (fork / spawn failed: process or memory limit) while
    runs were still waiting; the finished ones are stored."""


def _worker_main(conn, parent_pid: int, inherited_fds: list[int], task: Callable) -> None:
    # started with the stop signals held back (run_workers' spawn): the parent's handlers, its
    # remembered stop and its unraisable hook are replaced before a signal can reach them
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for name in ("SIGTERM", "SIGHUP"):   # an ignored one (nohup) stays ignored
        number = getattr(signal, name, None)
        if number is not None and signal.getsignal(number) is not signal.SIG_IGN:
            signal.signal(number, signal.SIG_DFL)
    forget_stop()
    sys.unraisablehook = sys.__unraisablehook__
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)
    die_with_parent(parent_pid)
    for fd in inherited_fds:       # the parent's folder lock must die with the parent
        try:
            os.close(fd)
        except OSError:
            pass
    while True:
        try:
            job = conn.recv()
        except (EOFError, OSError):
            break
        if job is None:
            break
        try:
            conn.send(task(*job))
        except OSError:
            break


class _Worker:
    def __init__(self, context, inherited_fds: list[int], task: Callable):
        self.conn, child = context.Pipe()
        self.process = context.Process(target=_worker_main, daemon=True,
                                       args=(child, os.getpid(), inherited_fds, task))
        self.process.start()
        child.close()
        self.task: tuple | None = None

    def stop(self) -> None:
        if self.process.is_alive():
            self.process.terminate()

    def reap(self) -> None:
        self.process.join(2.0)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()
        self.conn.close()


def _death(code: int | None) -> str:
    if code is not None and code < 0:
        return f"signal {-code}"
    return f"exit code {code}"


def run_workers(tasks: dict[str, tuple], workers: int, on_result: Callable[[str, dict], None],
                inherited_fds: list[int] = (), on_idle: Callable[[], None] | None = None,
                *, task: Callable[..., tuple[str, dict]], first_alone: bool = False) -> None:
    """Evaluate ``tasks`` in ``workers`` processes: each worker calls ``task(key, *tasks[key])``,
    which returns ``(key, outcome)`` (:func:`rvsim.doe.runner.evaluate_task`; a module-level
    function, so that a spawned worker can unpickle it).

    ``on_result(key, outcome)`` is called in this process as each run finishes.  ``on_idle()``
    is called once, the first time a worker finds no run left while another still works: a
    core is then free for this process's own preparations (the study's analysis imports), and
    no worker waits on them.

    ``first_alone``: start one worker and the others only once its first run has come back
    (or the worker died): with a cold numba cache that worker compiles the kernel and caches
    it, and the others load it instead of compiling the same kernel at once.
    """
    context = multiprocessing.get_context()
    fds = list(inherited_fds) if context.get_start_method() == "fork" else []
    queue = collections.deque(tasks)
    attempts: collections.Counter = collections.Counter()
    pool: list[_Worker] = []
    start_failure: list[str] = []

    def spawn() -> _Worker | None:
        """A new worker, or None when the system refuses one (the study carries on with the
        workers it has; with none left, :class:`WorkerStartError`)."""
        # a stop signal during the fork would run the parent's handler in the child (or in
        # the parent's after-fork callbacks, where its exception is lost): held back until
        # the child has its own handlers, and in the parent until the worker is in the pool
        with signals_blocked():
            try:
                worker = _Worker(context, fds, task)
            except OSError as exc:
                start_failure.append(f"{type(exc).__name__}: {exc}")
                return None
            pool.append(worker)
        return worker

    def give_up_if_stuck() -> None:
        if queue and not any(w.task is not None for w in pool) and start_failure:
            raise WorkerStartError(f"study: cannot start a worker process ({start_failure[-1]})"
                                   f"; {len(queue)} run(s) not evaluated")

    def dispatch(worker: _Worker) -> None:
        while queue:
            key = queue.popleft()
            try:
                worker.conn.send((key, *tasks[key]))
            except OSError:             # died idle: not the run's fault
                queue.appendleft(key)
                replace(worker, None)
                return
            worker.task = key
            return

    def replace(worker: _Worker, held: str | None) -> None:
        worker.stop()
        worker.reap()
        pool.remove(worker)
        if held is not None:
            attempts[held] += 1
            if attempts[held] >= MAX_ATTEMPTS:
                reason = _death(worker.process.exitcode)
                times = "twice" if MAX_ATTEMPTS == 2 else f"{MAX_ATTEMPTS} times"
                on_result(held, {"status": "worker_died", "metrics": {},
                                 "error": f"worker process died {times} ({reason})"})
            else:
                queue.appendleft(held)
        if queue:
            fresh = spawn()
            if fresh is not None:
                dispatch(fresh)
            else:
                give_up_if_stuck()

    def grow() -> None:
        """Start the workers held back by ``first_alone``, each with a run."""
        for _ in range(min(workers - len(pool), len(queue))):
            fresh = spawn()
            if fresh is None:
                break
            dispatch(fresh)

    try:
        for _ in range(min(1 if first_alone else workers, len(queue))):
            if spawn() is None:
                break
        for worker in list(pool):
            dispatch(worker)
        give_up_if_stuck()
        while busy := [w for w in pool if w.task is not None]:
            ready = set(wait([w.conn for w in busy] + [w.process.sentinel for w in busy]))
            check_stop()        # a stop signal whose exception was lost on its way
            if first_alone and ready:       # the first run is back, or its worker died
                first_alone = False
                grow_now = True
            else:
                grow_now = False
            for worker in busy:
                if worker.conn in ready:
                    try:
                        key, outcome = worker.conn.recv()
                    except (EOFError, OSError):
                        replace(worker, worker.task)
                        continue
                    worker.task = None
                    on_result(key, outcome)
                    dispatch(worker)
                    if on_idle is not None and worker.task is None and not queue and \
                            any(w.task is not None for w in pool):
                        idle, on_idle = on_idle, None
                        try:
                            idle()
                        except Exception:  # noqa: BLE001 - a preparation only: whatever
                            pass           # failed here fails again, reported, after the runs
                elif worker.process.sentinel in ready:
                    replace(worker, worker.task)
            if grow_now:
                grow()
        give_up_if_stuck()
    finally:
        for worker in pool:
            worker.stop()
        for worker in pool:
            worker.reap()
