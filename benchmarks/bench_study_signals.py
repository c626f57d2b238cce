"""Measure how a running paper study answers SIGINT (Ctrl-C) and SIGTERM (issue 8, item 3).

Starts ``rvsim study paper-l36`` in a fresh folder, waits until the store holds ``--after``
finished runs, sends the signal, and reports the time from the signal to the process's exit,
its exit code, the rows kept in results.sqlite and the worker processes still alive 2 s later.
Run it with the rvsim to measure first on PYTHONPATH.

Usage:  python benchmarks/bench_study_signals.py [--after 4] [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import signal
import sqlite3
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import psutil


def _rows(path: Path) -> int:
    if not path.exists():
        return 0
    try:
        with sqlite3.connect(f"{path.as_uri()}?mode=ro", uri=True, timeout=5) as db:
            return db.execute("SELECT count(*) FROM runs").fetchone()[0]
    except sqlite3.OperationalError:
        return 0


def measure(signum: int, after: int, workers: int) -> dict:
    with tempfile.TemporaryDirectory() as folder:
        store = Path(folder) / "results.sqlite"
        log = Path(folder) / "stderr.txt"      # not a pipe: orphaned workers would hold it
        proc = subprocess.Popen([sys.executable, "-m", "rvsim", "study", "paper-l36", "--out",
                                 folder, "--workers", str(workers), "--no-progress",
                                 "--no-report"], stdout=subprocess.DEVNULL,
                                stderr=log.open("w"))
        while _rows(store) < after and proc.poll() is None:
            time.sleep(0.02)
        children = psutil.Process(proc.pid).children(recursive=True)
        rows_at_signal = _rows(store)
        start = time.perf_counter()
        proc.send_signal(signum)
        proc.wait()
        exit_s = time.perf_counter() - start
        _, alive = psutil.wait_procs(children, timeout=2)
        survivors = []
        for p in alive:
            try:
                if p.status() != psutil.STATUS_ZOMBIE:
                    survivors.append(p.pid)
                    p.kill()
            except psutil.NoSuchProcess:
                pass
        return {"signal": signal.Signals(signum).name, "exit_code": proc.returncode,
                "seconds_to_exit": round(exit_s, 2), "rows_at_signal": rows_at_signal,
                "rows_kept": _rows(store), "workers_alive_after_2s": len(survivors),
                "stderr_last_line": (log.read_text().strip().splitlines() or [""])[-1]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--after", type=int, default=4)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    for signum in (signal.SIGINT, signal.SIGTERM):
        print(json.dumps(measure(signum, args.after, args.workers)), flush=True)


if __name__ == "__main__":
    main()
