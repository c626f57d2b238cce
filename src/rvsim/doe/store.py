"""The study's results store: one SQLite file in the study folder.

Rows are keyed by a hash of the complete parameter set (every field of the reducer in SI, the
time step) and the fingerprint of the model's source code (:mod:`rvsim._fingerprint`), so a
re-run skips what is finished, a changed parameter is a new row and a changed model is a new
row.  Each result is committed as it arrives (WAL journal) and checkpointed into
``results.sqlite`` at once: a study killed with SIGKILL loses only the runs that were in
flight.  ``results.sqlite`` alone (copied without its -wal file, or read as immutable) holds
every row checkpointed; a kill in the few ms between a commit and its checkpoint leaves that
row in the -wal file only, and the next opening of the store for writing (a re-run) recovers
it.  A store that another process keeps locked is waited for: a finished run is never dropped
for a lock timeout.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import sqlite3
import sys
import time
from pathlib import Path

from .._fingerprint import model_fingerprint
from ..errors import InputFileError
from ..parameters import Reducer

__all__ = ["ResultStore", "run_key"]

#: seconds SQLite waits for another process's lock before one attempt fails
_BUSY_TIMEOUT = 1.0
#: seconds a study waits at start for a store another process keeps locked
_OPEN_TIMEOUT = 5.0


def run_key(reducer: Reducer, time_step: float) -> str:
    """Hash of the full parameter set of one run and of the model's source code."""
    payload = json.dumps({"reducer": dataclasses.asdict(reducer), "time_step": time_step,
                          "model": model_fingerprint()}, sort_keys=True, default=str)
    return hashlib.sha256(payload.encode()).hexdigest()


def _is_locked(exc: sqlite3.Error) -> bool:
    return isinstance(exc, sqlite3.OperationalError) and (
        "locked" in str(exc) or "busy" in str(exc))


class ResultStore:
    """Finished runs of a study, in ``folder/results.sqlite``.

    ``readonly=True`` opens an existing store without writing to it (InputFileError if absent).
    A damaged file or one locked by another process is an InputFileError with one line.
    """

    def __init__(self, folder: str | Path, *, readonly: bool = False):
        self.path = Path(folder) / "results.sqlite"
        self._warned = False
        if readonly and not self.path.is_file():
            raise InputFileError(f"{self.path}: not found")
        try:
            if readonly:
                # immutable: a reader creates no -wal / -shm file beside the store (the WAL is
                # checkpointed after every commit, so the main file holds every finished run
                # but one committed in the last few ms before a kill, until a re-run opens it)
                self._db = sqlite3.connect(f"{self.path.resolve().as_uri()}?mode=ro&immutable=1",
                                           uri=True, timeout=_OPEN_TIMEOUT)
            else:
                self._db = sqlite3.connect(self.path, timeout=_OPEN_TIMEOUT)
        except sqlite3.Error as exc:
            raise InputFileError(f"{self.path}: cannot open ({exc})") from None
        try:
            self._open(readonly)
        except sqlite3.Error as exc:
            self._db.close()
            if _is_locked(exc):
                raise InputFileError(f"{self.path}: locked by another process (close the "
                                     "program that holds it and run again)") from None
            if "readonly" in str(exc) or "read-only" in str(exc):
                raise InputFileError(f"{self.path}: cannot be written ({exc})") from None
            said = " ".join(str(exc).split())
            said = said if len(said) <= 120 else said[:117] + "..."
            raise InputFileError(f"{self.path}: damaged ({said}); move it away to start the "
                                 "study afresh, or use a new folder") from None
        self._db.execute(f"PRAGMA busy_timeout = {int(_BUSY_TIMEOUT * 1000)}")

    def _open(self, readonly: bool) -> None:
        check = self._db.execute("PRAGMA quick_check").fetchone()[0]
        if check != "ok":
            raise sqlite3.DatabaseError(check)
        if readonly:
            self._db.execute("SELECT key, status, error, metrics, wall_s, finished, history "
                             "FROM runs LIMIT 0")
            return
        self._db.execute("PRAGMA journal_mode=WAL")
        self._db.execute("BEGIN IMMEDIATE")         # fails at once if another writer holds it
        self._db.execute("""CREATE TABLE IF NOT EXISTS runs (
            key TEXT PRIMARY KEY, status TEXT NOT NULL, error TEXT, metrics TEXT,
            wall_s REAL, finished REAL, history BLOB)""")
        self._db.commit()

    def finished(self) -> dict[str, dict]:
        """Stored rows by key: status, error, metrics (dict)."""
        rows = self._db.execute("SELECT key, status, error, metrics, wall_s FROM runs")
        return {k: {"status": s, "error": e, "metrics": json.loads(m) if m else {},
                    "wall_s": w} for k, s, e, m, w in rows}

    def get_many(self, keys: list[str]) -> dict[str, dict]:
        """Stored rows of ``keys`` (those finished), as :meth:`finished` gives them."""
        out = {}
        for start in range(0, len(keys), 500):
            part = keys[start:start + 500]
            rows = self._db.execute("SELECT key, status, error, metrics, wall_s FROM runs WHERE "
                                    f"key IN ({','.join('?' * len(part))})", part)
            out.update({k: {"status": s, "error": e, "metrics": json.loads(m) if m else {},
                            "wall_s": w} for k, s, e, m, w in rows})
        return out

    def put(self, key: str, outcome: dict) -> None:
        """Store one run's outcome, commit and checkpoint; wait out other processes' locks."""
        row = (key, outcome["status"], outcome.get("error"),
               json.dumps(outcome.get("metrics", {})), outcome.get("wall_s"), time.time(),
               outcome.get("history"))
        while True:
            try:
                with self._db:
                    self._db.execute("INSERT OR REPLACE INTO runs VALUES (?, ?, ?, ?, ?, ?, ?)",
                                     row)
                break
            except sqlite3.OperationalError as exc:
                if not _is_locked(exc):
                    raise
                if not self._warned:
                    print(f"rvsim: {self.path} is locked by another process; waiting to store "
                          "finished runs", file=sys.stderr)
                    self._warned = True
                time.sleep(0.2)
        self._checkpoint()

    def _checkpoint(self, attempts: int = 20) -> None:
        """Copy the WAL into results.sqlite, so that the file alone holds every commit.

        A reader of an older snapshot holds part of the WAL back for a moment: retry briefly;
        after that the next commit (or closing the store) completes the copy.
        """
        for _ in range(attempts):
            try:
                _, logged, copied = self._db.execute("PRAGMA wal_checkpoint(PASSIVE)").fetchone()
            except sqlite3.OperationalError:
                logged, copied = 1, 0
            if copied >= logged:
                return
            time.sleep(0.01)

    def history(self, key: str):
        """Stored compact history of one run (dict of arrays) or None."""
        import io

        import numpy as np

        row = self._db.execute("SELECT history FROM runs WHERE key = ?", (key,)).fetchone()
        if not row or row[0] is None:
            return None
        with np.load(io.BytesIO(row[0])) as data:
            return {name: data[name] for name in data.files}

    def close(self) -> None:
        self._db.close()
