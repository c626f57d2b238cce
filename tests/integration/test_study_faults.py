"""Study faults with real signals and real processes: Ctrl-C, SIGTERM, SIGKILL of the study or
of one worker, a run that kills its worker, a second study into a locked folder, a folder of
another study, a damaged or locked store, a copied store, and the same on a Dask cluster.

Each fault meets a small study (four short runs on two workers); the faults a study should
ride out share one study that meets them all, and the Dask tests share one cluster."""

import os
import shutil
import signal
import sqlite3
import subprocess
import sys
import time

import pandas as pd
import psutil
import pytest

from rvsim.doe import load_study, run, run_key
from rvsim.doe._workers import TEST_KILL_ENV
from rvsim.doe.folder import lock_folder
from rvsim.doe.store import ResultStore
from rvsim.dynamics import DEFAULT_TIME_STEP
from tests.integration.conftest import SRC, default_signals, factors, write_study

HANG = 60  # s: a guard against a hung study, not a performance figure


def _rows(folder, column="status", *, file_alone=False):
    """{key: status} (or another column of the runs) committed in folder/results.sqlite (read
    without disturbing the study).  ``file_alone``: only the rows already checkpointed into
    the file itself (read as immutable, the -wal file ignored), as a copy of the file holds."""
    path = folder / "results.sqlite"
    if not path.exists():
        return {}
    mode = "ro&immutable=1" if file_alone else "ro"
    try:
        with sqlite3.connect(f"{path.as_uri()}?mode={mode}", uri=True, timeout=5) as db:
            return dict(db.execute(f"SELECT key, {column} FROM runs").fetchall())
    except sqlite3.DatabaseError:    # a page caught mid-checkpoint, read as immutable
        return {}


def _study(tmp_path, design="L4"):
    """An L4 study of 0.8 s runs on the implicit-bearings scheme (0.5 s of CPU each, a quarter
    of the explicit scheme's; the faults are the runner's, not the scheme's): long enough to
    interrupt part-way (on two workers, runs 3 and 4 start as runs 1 and 2 are stored).  A test
    that does more than wait between the first row and its signal takes the L8 (its last runs
    never start, so they cost nothing; with four runs, a slow second command let all four end
    before the signal, seen once on 2026-11-28)."""
    folder = tmp_path / "definition"
    folder.mkdir()
    path = write_study(folder, design=design, extra='scheme = "implicit-bearings"',
                       factors=factors(H=("H", [0.0, 0.02]), I=("I", [0.0, 0.032]),
                                       E=("E", [100, 300])))
    text = path.read_text().replace('"operating.duration" = 0.4', '"operating.duration" = 0.8')
    path.write_text(text.replace('"operating.steady_start" = 0.3',
                                 '"operating.steady_start" = 0.5'))
    return path


def _start(path, out, *extra, env=None, session=False, ignored=()):
    """``rvsim study`` as a subprocess (``session``: in its own process group; ``ignored``:
    signals ignored in it, as ``nohup`` does)."""
    return subprocess.Popen([sys.executable, "-m", "rvsim", "study", str(path), "--out",
                             str(out), "--workers", "2", "--no-progress", "--no-report", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env={**os.environ, **(env or {})}, start_new_session=session,
                            preexec_fn=default_signals(ignored))


def _wait_rows(proc, out, count, *, file_alone=False):
    deadline = time.time() + HANG
    while (len(_rows(out, file_alone=file_alone)) < count and proc.poll() is None
           and time.time() < deadline):
        time.sleep(0.02)
    assert proc.poll() is None, "the study ended before it could be interrupted"
    return psutil.Process(proc.pid).children(recursive=True)


def _gone(processes):
    """Wait (bounded) for processes to end; return those still running."""
    _, alive = psutil.wait_procs(processes, timeout=10)
    return [p for p in alive if _running(p)]


def _running(process):
    try:
        return process.status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


@pytest.mark.parametrize("signum, group, code, word", [
    (signal.SIGINT, False, 130, "interrupted"),
    (signal.SIGINT, True, 130, "interrupted"),    # Ctrl-C in a terminal: the whole group
    (signal.SIGTERM, False, 143, "terminated")])
def test_signal_stops_the_study_keeps_rows_and_leaves_no_worker(tmp_path, cli, signum, group,
                                                                 code, word):
    path = _study(tmp_path, "L8")
    out = tmp_path / "out"
    proc = _start(path, out, session=group)
    workers = _wait_rows(proc, out, 1)
    assert len(workers) == 2
    # while it runs, the folder is locked against a second study
    res = cli("study", str(path), "--out", str(out))
    assert res.code == 2 and "another rvsim study is running" in res.err
    assert res.err.count("\n") == 1
    before = _rows(out)
    if group:
        os.killpg(proc.pid, signum)
    else:
        proc.send_signal(signum)
    _, err = proc.communicate(timeout=HANG)
    assert proc.returncode == code
    assert err.count("\n") == 1 and word in err and "Traceback" not in err
    assert not _gone(workers)
    kept = _rows(out)
    assert 1 <= len(kept) < 8 and set(before) <= set(kept)
    with lock_folder(out):     # the folder is free (a re-run: the SIGKILL test below)
        pass


@pytest.fixture(scope="module")
def disturbed(tmp_path_factory):
    """One study that meets three faults it should ride out: run as under ``nohup`` (SIGHUP
    ignored) in a session of its own, it gets the terminal's SIGHUP (to the whole group) once
    its first run is stored; then one of its workers is SIGKILLed; then another process takes
    the store's lock until the next finished run says that it waits for it.  The lock holder
    is started beforehand and takes the lock on demand, within milliseconds of the worker's
    kill (under load, all four runs were once stored before a holder started only then could
    take it, 2026-11-28)."""
    tmp_path = tmp_path_factory.mktemp("disturbed")
    path = _study(tmp_path)
    out = tmp_path / "out"
    proc = _start(path, out, session=True, ignored=(signal.SIGHUP,))
    waiting = _lock_holder(out / "results.sqlite")
    try:
        workers = _wait_rows(proc, out, 1)
        os.killpg(proc.pid, signal.SIGHUP)
        workers[0].kill()
        holder = _take_lock(waiting)
        notice = proc.stderr.readline()           # the next finished run waits for the lock
        holder.communicate("release\n", timeout=HANG)
        _, err = proc.communicate(timeout=HANG)
    finally:
        if waiting.poll() is None:
            waiting.kill()
            waiting.wait()
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return {"code": proc.returncode, "notice": notice, "err": err, "rows": _rows(out),
            "left": _gone(workers)}


def test_a_study_under_nohup_survives_the_hangup(disturbed):
    """`nohup rvsim study ...`: the terminal's SIGHUP (to the whole process group) used to
    stop the study (143), its runner replacing the ignored signal with its own handler, and
    its workers set SIGHUP back to its default.  Study and workers now carry on (the one line
    on stderr is the lock's notice, tested below)."""
    assert (disturbed["code"], disturbed["err"]) == (0, ""), disturbed
    assert not disturbed["left"]                  # no worker outlives the study
    assert list(disturbed["rows"].values()) == ["ok"] * 4


def test_a_killed_worker_is_replaced_and_its_run_retried(disturbed):
    assert disturbed["code"] == 0, disturbed["err"]
    rows = disturbed["rows"]
    assert len(rows) == 4 and set(rows.values()) == {"ok"}


def test_finished_runs_wait_out_a_lock_taken_mid_study(disturbed):
    assert "is locked by another process; waiting" in disturbed["notice"], disturbed
    assert disturbed["code"] == 0, disturbed["err"]
    assert len(disturbed["rows"]) == 4 and set(disturbed["rows"].values()) == {"ok"}


SWALLOWED_CTRL_C = """
import importlib, os, signal, sys
from rvsim.cli import run

simulate = importlib.import_module("rvsim.dynamics.simulate")
checked = simulate.check_run_options
sent = []

class Finalised:                     # Ctrl-C lands in a finaliser (llvmlite's, numba compiling)
    def __del__(self):
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(1000):        # the handler runs here; its exception cannot leave
            pass

def check(*args, **kwargs):          # the runner's checks before any run
    if not sent:
        sent.append(Finalised())
        sent.clear()
    return checked(*args, **kwargs)

simulate.check_run_options = check
sys.argv = ["rvsim", "study", sys.argv[1], "--out", sys.argv[2], "--no-progress"]
run()
"""


def test_a_ctrl_c_swallowed_before_the_runs_stops_the_study(tmp_path):
    """Cold numba cache, Ctrl-C 2.5 s after the start of `rvsim study paper-l36`: Python
    printed "Exception ignored on calling ctypes callback function" with a traceback, and the
    study ran all 36 runs and exited 0.  The stop is now remembered in a study's process too:
    one line, 130, no run."""
    path = _study(tmp_path)
    out = tmp_path / "out"
    res = subprocess.run([sys.executable, "-c", SWALLOWED_CTRL_C, str(path), str(out)],
                         capture_output=True, text=True, timeout=HANG, stdin=subprocess.DEVNULL,
                         env={**os.environ, "PYTHONPATH": SRC}, preexec_fn=default_signals())
    assert (res.returncode, res.stdout, res.stderr) == (130, "", "rvsim: interrupted\n")
    assert _rows(out) == {}


def test_sigkill_of_the_study_ends_its_workers_and_loses_only_runs_in_flight(tmp_path):
    """kill -9 of the study: its workers end, the store file alone (without -wal / -shm) holds
    every run checkpointed before the kill, the store with its -wal holds those and any run
    committed in the last few ms before it, and a re-run keeps them all (not run again) and
    completes the study.

    The kill lands once two rows are in the file itself: a row is committed to the WAL and
    checkpointed a few ms later, so a kill in between leaves that row in the -wal file alone
    (CI, 2026-11-28: the test then waited for rows seen through the WAL and one of the two
    was not yet in the file).  The re-run, opening the store with its -wal, recovers it."""
    path = _study(tmp_path)
    out = tmp_path / "out"
    proc = _start(path, out)
    workers = _wait_rows(proc, out, 2, file_alone=True)
    seen = _rows(out, file_alone=True)
    proc.kill()
    proc.communicate(timeout=HANG)
    assert not _gone(workers), workers
    copy = tmp_path / "copy"
    copy.mkdir()
    shutil.copy(out / "results.sqlite", copy / "results.sqlite")   # without -wal / -shm
    copied, original = _rows(copy), _rows(out)
    assert 2 <= len(seen) and seen.items() <= copied.items(), (seen, copied)
    assert copied.items() <= original.items() and len(original) < 4, (copied, original)
    before = _rows(out, "finished")
    results = run(load_study(path), out, workers=2, progress=False)
    after = _rows(out, "finished")
    assert len(after) == 4 and (results["status"] == "ok").all()
    assert all(after[k] == v for k, v in before.items())   # finished rows kept, not re-run


@pytest.fixture(scope="module")
def doomed_run(tmp_path_factory):
    """The small study on two local workers, its second run SIGKILLing every worker that
    starts it: (study, the run's key, the folder, the results)."""
    folder = tmp_path_factory.mktemp("doomed")
    study = load_study(write_study(folder))
    doomed = run_key(study.reducers()[1], study.time_step or DEFAULT_TIME_STEP)
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv(TEST_KILL_ENV, doomed[:16])
        results = run(study, folder / "out", workers=2, progress=False)
    return study, doomed, folder / "out", results


def test_a_run_that_kills_its_worker_twice_is_stored_as_failed(doomed_run, monkeypatch):
    study, doomed, out, results = doomed_run
    assert list(results["status"]) == ["ok", "worker_died", "ok", "ok"]
    assert results.loc[1, "error"] == "worker process died twice (signal 9)"
    # resumed without the fault: the worker_died row is run again, the others are kept
    monkeypatch.delenv(TEST_KILL_ENV, raising=False)    # (the Dask cluster's, if it is up)
    before = _rows(out)
    results = run(study, out, workers=2, progress=False)
    assert list(results["status"]) == ["ok", "ok", "ok", "ok"]
    after = _rows(out)
    assert {k: v for k, v in after.items() if k != doomed} == \
        {k: v for k, v in before.items() if k != doomed}


def test_a_worker_that_cannot_be_started_is_one_line_and_keeps_finished_runs(
        tmp_path, monkeypatch, capsys):
    """The first worker starts (a real process); every later fork fails as under a process
    limit: the study stops with one line and exit 1, the runs that finished are stored."""
    import multiprocessing.process

    real_start = multiprocessing.process.BaseProcess.start
    started = []

    def start(self):
        if started:
            raise BlockingIOError(11, "Resource temporarily unavailable")
        started.append(self)
        return real_start(self)

    monkeypatch.setattr(multiprocessing.process.BaseProcess, "start", start)
    study = load_study(write_study(tmp_path))
    doomed = run_key(study.reducers()[1], study.time_step or DEFAULT_TIME_STEP)
    monkeypatch.setenv(TEST_KILL_ENV, doomed[:16])   # run 2 kills the one worker
    from rvsim.cli import main

    code = main(["study", str(tmp_path / "study.toml"), "--out", str(tmp_path / "out"),
                 "--workers", "1", "--no-progress"])
    assert code == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("rvsim: error: study: cannot start a worker "
                                               "process (BlockingIOError: ")
    assert "3 run(s) not evaluated; finished runs are kept in" in err[0]
    rows = _rows(tmp_path / "out")
    assert list(rows.values()) == ["ok"]          # run 1 finished before the worker died


def test_a_folder_of_another_study_is_refused(tmp_path, small_study, cli):
    out = tmp_path / "out"
    out.mkdir()
    (out / "study.json").write_text('{"name": "other"}')
    store = ResultStore(out)
    store.put("k", {"status": "ok", "metrics": {}})
    store.close()
    res = cli("study", str(small_study), "--out", str(out))
    assert res.code == 2 and res.err.count("\n") == 1
    assert "holds the results of study 'other'" in res.err and "new --out folder" in res.err


def test_a_users_own_results_are_not_overwritten(tmp_path, small_study, cli):
    # found by a hostile review: a folder rvsim did not make, with the user's results.csv,
    # took the study and lost the file
    out = tmp_path / "mine"
    out.mkdir()
    (out / "results.csv").write_text("mydata\n")
    res = cli("study", str(small_study), "--out", str(out))
    assert res.code == 2 and res.err == (
        f"rvsim: error: {out}: holds results.csv but no study.json, so no study wrote them, "
        "and this one would replace them; give a new --out folder\n")
    assert sorted(p.name for p in out.iterdir()) == ["results.csv"]
    assert (out / "results.csv").read_text() == "mydata\n"


def _valid_store(folder):
    store = ResultStore(folder)
    for i in range(50):
        store.put(f"k{i}", {"status": "ok", "metrics": {"x": i}, "history": os.urandom(3000)})
    store.close()


@pytest.mark.parametrize("damage", ["junk", "truncated", "pages"])
def test_a_damaged_store_is_one_line(tmp_path, small_study, cli, damage):
    out = tmp_path / "out"
    out.mkdir()
    path = out / "results.sqlite"
    if damage == "junk":
        path.write_bytes(b"this is not a database" * 100)
    elif damage == "truncated":
        _valid_store(out)
        path.write_bytes(path.read_bytes()[:path.stat().st_size // 2])
    else:               # pages overwritten: SQLite's integrity report ran over 2-5 lines
        _valid_store(out)
        data = bytearray(path.read_bytes())
        for i in range(8192, len(data), 997):
            data[i] = 0x5A
        path.write_bytes(bytes(data))
    res = cli("study", str(small_study), "--out", str(out))
    assert res.code == 2 and res.err.count("\n") == 1, res.err
    assert "results.sqlite: damaged" in res.err


_HOLD_LOCK = """
import sqlite3, sys, time
if len(sys.argv) > 2:                # on demand: started beforehand, locks when told
    print("ready", flush=True)
    sys.stdin.readline()
db = sqlite3.connect(sys.argv[1], isolation_level=None)
db.execute("BEGIN EXCLUSIVE")
print("locked", flush=True)
sys.stdin.readline()
db.execute("COMMIT")
"""


def _hold_lock(path):
    """A process holding an exclusive lock on the store until a line is written to its stdin."""
    holder = subprocess.Popen([sys.executable, "-c", _HOLD_LOCK, str(path)],
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    assert holder.stdout.readline().strip() == "locked"
    return holder


def _lock_holder(path):
    """A process started (and its Python loaded) beforehand, that locks the store on demand
    (:func:`_take_lock`) within milliseconds."""
    holder = subprocess.Popen([sys.executable, "-c", _HOLD_LOCK, str(path), "on-demand"],
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    assert holder.stdout.readline().strip() == "ready"
    return holder


def _take_lock(holder):
    holder.stdin.write("lock\n")
    holder.stdin.flush()
    assert holder.stdout.readline().strip() == "locked"
    return holder


def test_a_store_locked_by_another_process_is_one_line(tmp_path, small_study, cli,
                                                        monkeypatch):
    out = tmp_path / "out"
    out.mkdir()
    ResultStore(out).close()
    holder = _hold_lock(out / "results.sqlite")
    try:
        monkeypatch.setattr("rvsim.doe.store._OPEN_TIMEOUT", 0.2)
        res = cli("study", str(small_study), "--out", str(out))
    finally:
        holder.kill()
        holder.wait()
    assert res.code == 2 and res.err.count("\n") == 1
    assert "locked by another process" in res.err


@pytest.fixture(scope="module")
def dask_cluster(tmp_path_factory):
    """Two Dask worker processes; a worker that starts the doomed run SIGKILLs itself."""
    distributed = pytest.importorskip("distributed")
    import dask

    folder = tmp_path_factory.mktemp("dask")
    study = load_study(write_study(folder))
    doomed = run_key(study.reducers()[1], study.time_step or DEFAULT_TIME_STEP)[:16]
    # as the local runner: a run may kill a worker once; one task per worker at a time, so a
    # dying worker takes no other run with it (with no failure allowed, a run sent to the
    # dying worker just before it died was lost with it: measured)
    with pytest.MonkeyPatch.context() as patch, dask.config.set(
            {"distributed.scheduler.allowed-failures": 1,
             "distributed.scheduler.worker-saturation": 1.0,
             # worker processes forked from this one, which has imported rvsim: a spawned
             # worker imported it again (2-3 s of CPU for each of the four workers)
             "distributed.worker.multiprocessing-method": "fork"}):
        patch.setenv(TEST_KILL_ENV, doomed)     # inherited by the worker processes
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                      host="127.0.0.1", dashboard_address=None) as cluster:
            yield cluster, study


def test_dask_a_killed_worker_is_a_failed_run_with_the_reason(tmp_path, dask_cluster,
                                                               doomed_run):
    """On two Dask worker processes: the doomed run is a failed row with Dask's reason, and
    the others give the local pool's numbers."""
    cluster, study = dask_cluster
    assert len(cluster.workers) == 2
    results = run(study, tmp_path / "out", scheduler=cluster.scheduler_address,
                  progress=False)
    assert list(results["status"]) == ["ok", "worker_died", "ok", "ok"]
    assert results.loc[1, "error"].startswith("Dask KilledWorker: ")
    local = doomed_run[3]
    assert list(results["key"]) == list(local["key"])
    ok = results["status"] == "ok"
    pd.testing.assert_series_equal(results.loc[ok, "te_mean_arcmin"],
                                   local.loc[ok, "te_mean_arcmin"])


def test_dask_ctrl_c_cancels_the_queued_runs(tmp_path, dask_cluster):
    cluster, _ = dask_cluster
    path = _study(tmp_path, "L8")
    out = tmp_path / "out"
    proc = _start(path, out, "--scheduler", cluster.scheduler_address)
    _wait_rows(proc, out, 1)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=HANG)
    assert proc.returncode == 130 and err.count("\n") == 1 and "interrupted" in err
    assert 1 <= len(_rows(out)) < 8
    deadline = time.time() + HANG
    while cluster.scheduler.tasks and time.time() < deadline:
        time.sleep(0.05)
    assert not cluster.scheduler.tasks     # nothing left queued or running on the cluster


def test_on_idle_runs_once_when_a_core_is_free_and_no_run_waits(monkeypatch):
    """Two workers, runs of 0.1, 0.8 and 0.1 s: the worker that ends the last short run finds
    nothing left while the other still works; the parent's preparation then runs, once, before
    the long run's result, and every result still arrives."""
    import multiprocessing

    import rvsim.doe.runner
    from rvsim.doe._workers import run_workers

    if multiprocessing.get_start_method() != "fork":
        pytest.skip("the stand-in evaluation reaches the workers by fork")

    def stand_in(seconds, *args):
        time.sleep(seconds)
        return {"status": "ok", "metrics": {"s": seconds}}

    monkeypatch.setattr(rvsim.doe.runner, "evaluate", stand_in)
    log = []
    run_workers({"short1": (0.1, 0.0), "long": (0.8, 0.0), "short2": (0.1, 0.0)}, 2,
                lambda key, outcome: log.append(key), on_idle=lambda: log.append("idle"),
                task=rvsim.doe.runner.evaluate_task)
    assert log == ["short1", "short2", "idle", "long"]
