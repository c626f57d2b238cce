"""The study store's key (model source fingerprint), a run stopped at step 0, scheduler
addresses, and the store opened read-only."""

import numpy as np
import pytest

import rvsim._fingerprint as fp
from rvsim.doe import ResultStore, load_study, run, run_key
from rvsim.doe.runner import evaluate
from rvsim.dynamics import Result
from rvsim.physics import _layout as L
from rvsim.errors import InputFileError
from rvsim.parameters import RV40E
from tests.integration.conftest import write_study


def test_model_fingerprint_is_stable_and_covers_the_model_sources():
    files = fp.model_source_files()
    names = {f.relative_to(fp._ROOT).as_posix() for f in files}
    assert {"_jit.py", "physics/_layout.py", "physics/compliance.py", "dynamics/_kernel.py", "geometry/_curve.py",
            "parameters/rv40e.py", "units.py", "bearings.py", "friction.py",
            # the quasi-static engine's studies and tolerance samples were stored without
            # their engine's source in the key (found 2026-11-26)
            "quasistatic/transmission.py", "quasistatic/_solver.py", "analysis/catalogue.py",
            "doe/engines.py", "tolerance/engine.py"} <= names
    assert fp.fingerprint_files(files) == fp.model_fingerprint() == fp.model_fingerprint()


def test_changing_a_model_source_changes_the_fingerprint(tmp_path):
    root = tmp_path / "rvsim"
    (root / "dynamics").mkdir(parents=True)
    kernel = root / "dynamics" / "_kernel.py"
    kernel.write_text("STIFFNESS = 1.0\n")
    (root / "units.py").write_text("MM = 1e-3\n")
    files = lambda: fp.model_source_files(root)  # noqa: E731
    before = fp.fingerprint_files(files(), root)
    assert fp.fingerprint_files(files(), root) == before
    kernel.write_text("STIFFNESS = 2.0\n")
    assert fp.fingerprint_files(files(), root) != before
    kernel.write_text("STIFFNESS = 1.0\n")
    (root / "dynamics" / "extra.py").write_text("")
    assert fp.fingerprint_files(files(), root) != before


def test_the_run_key_follows_the_model_fingerprint(monkeypatch):
    key = run_key(RV40E, 1e-5)
    assert run_key(RV40E, 1e-5) == key and run_key(RV40E, 2e-5) != key
    monkeypatch.setattr("rvsim.doe.store.model_fingerprint", lambda: "another model")
    assert run_key(RV40E, 1e-5) != key


@pytest.mark.parametrize("samples", [0, 1])
def test_a_run_stopped_at_step_0_keeps_its_status(monkeypatch, samples):
    def stopped(reducer, **kwargs):
        return Result(time=np.zeros(samples), channels=np.zeros((samples, len(L.CHANNEL_NAMES))),
                      pin_forces=np.zeros((samples, 2, 40)), ratio=121.0, steady_start=1.5,
                      status="runaway_penetration", steps=0, wall_s=0.01, energy={})

    monkeypatch.setattr("rvsim.dynamics.simulate", stopped)
    outcome = evaluate(RV40E, 1e-5)
    assert outcome["status"] == "runaway_penetration"
    assert outcome["error"] == "simulation runaway penetration at step 0"


@pytest.mark.parametrize("address", ["tcp://", "tcp://host:notaport", "::::", "udp://h:1",
                                     "tcp://host:99999"])
def test_a_malformed_scheduler_address_is_one_line(tmp_path, cli, address):
    path = write_study(tmp_path)
    out = tmp_path / "out"
    res = cli("study", str(path), "--out", str(out), "--scheduler", address)
    assert res.code == 2 and res.err.count("\n") == 1 and "--scheduler" in res.err
    assert not out.exists()
    with pytest.raises(InputFileError, match="--scheduler: .* is not a scheduler address"):
        run(load_study(path), out, scheduler=address, progress=False)
    assert not out.exists()


def test_a_store_opened_read_only_writes_nothing(tmp_path):
    with pytest.raises(InputFileError, match="not found"):
        ResultStore(tmp_path, readonly=True)
    assert not (tmp_path / "results.sqlite").exists()
    store = ResultStore(tmp_path)
    store.put("k", {"status": "ok", "metrics": {"te": 1.0}})
    store.close()
    store = ResultStore(tmp_path, readonly=True)
    assert store.finished()["k"]["metrics"] == {"te": 1.0}
    store.close()


@pytest.mark.parametrize("workers", [0, -1])
def test_run_refuses_fewer_than_one_worker(tmp_path, workers):
    study = load_study(write_study(tmp_path))
    with pytest.raises(InputFileError, match="workers: must be at least 1"):
        run(study, tmp_path / "out", workers=workers, progress=False)
    assert not (tmp_path / "out").exists()
