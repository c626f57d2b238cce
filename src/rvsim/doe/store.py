"""The study's results store: one SQLite file in the study folder.

Rows are keyed by a hash of the complete parameter set (every field of the reducer in SI, the
time step and the model version), so a re-run skips what is finished and a changed parameter
is a new row.  Each result is committed as it arrives (WAL journal): a study killed with SIGKILL
loses only the runs that were in flight.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import sqlite3
import time
from pathlib import Path

from ..parameters import Reducer

__all__ = ["ResultStore", "run_key", "MODEL_VERSION"]

#: bump when a model change makes stored results stale
MODEL_VERSION = "dynamics-2"


def run_key(reducer: Reducer, time_step: float) -> str:
    """Hash of the full parameter set of one run."""
    payload = json.dumps({"reducer": dataclasses.asdict(reducer), "time_step": time_step,
                          "model": MODEL_VERSION}, sort_keys=True, default=str)
    return hashlib.sha256(payload.encode()).hexdigest()


class ResultStore:
    """Finished runs of a study, in ``folder/results.sqlite``."""

    def __init__(self, folder: str | Path):
        self.path = Path(folder) / "results.sqlite"
        self._db = sqlite3.connect(self.path, timeout=30)
        self._db.execute("PRAGMA journal_mode=WAL")
        self._db.execute("""CREATE TABLE IF NOT EXISTS runs (
            key TEXT PRIMARY KEY, status TEXT NOT NULL, error TEXT, metrics TEXT,
            wall_s REAL, finished REAL, history BLOB)""")
        self._db.commit()

    def finished(self) -> dict[str, dict]:
        """Stored rows by key: status, error, metrics (dict)."""
        rows = self._db.execute("SELECT key, status, error, metrics, wall_s FROM runs")
        return {k: {"status": s, "error": e, "metrics": json.loads(m) if m else {},
                    "wall_s": w} for k, s, e, m, w in rows}

    def put(self, key: str, outcome: dict) -> None:
        """Store one run's outcome and commit at once."""
        self._db.execute("INSERT OR REPLACE INTO runs VALUES (?, ?, ?, ?, ?, ?, ?)",
                         (key, outcome["status"], outcome.get("error"),
                          json.dumps(outcome.get("metrics", {})), outcome.get("wall_s"),
                          time.time(), outcome.get("history")))
        self._db.commit()

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
