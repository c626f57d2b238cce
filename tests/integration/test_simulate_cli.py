"""``rvsim simulate`` as a new user runs it: JSON keys, paper runs, saved histories, errors."""

import json

import numpy as np
import pandas as pd
import pytest

from .test_run_report import SHORT

#: the short schedule (0.4 s, same physics) as --set options
SHORT_ARGS = tuple(a for name, value in SHORT.items() for a in ("--set", f"{name}={value}"))
KEYS = {"te_mean_arcmin", "te_pp_arcmin", "te_rms_arcmin", "speed_ratio", "sim_time_s", "steps",
        "wall_s", "status"}


def test_paper_run_2_json(cli):
    res = cli("simulate", "--paper-run", "2", "--json")
    assert res.code == 0, res.err
    data = json.loads(res.out)
    assert KEYS <= set(data)
    assert data["status"] == "ok" and data["sim_time_s"] == pytest.approx(4.0)
    assert data["speed_ratio"] == pytest.approx(121.0, abs=0.01)
    assert data["te_mean_arcmin"] > 0


def test_default_run_and_saved_histories(tmp_path, cli):
    path = tmp_path / "run.npz"
    res = cli("simulate", *SHORT_ARGS, "--save", str(path), "--json")
    assert res.code == 0, res.err
    data = np.load(path)
    assert {"time", "theta_in", "theta_out", "te_rad", "pin_forces"} <= set(data.files)
    frame = pd.DataFrame({k: data[k] for k in ("time", "te_rad")})
    assert frame["time"].iloc[-1] == pytest.approx(0.4)
    assert json.loads(str(data["summary"]))["status"] == "ok"


def test_text_output_names_the_largest_pin_force(tmp_path, cli):
    # the text lines carry what the JSON does, the largest pin force (every step's) included
    path = tmp_path / "run.npz"
    args = ("simulate", "--paper-run", "3", *SHORT_ARGS, "--save", str(path))
    text = cli(*args)
    assert text.code == 0, text.err
    data = json.loads(str(np.load(path)["summary"]))
    assert f"largest pin force {data['max_pin_force_n']:.1f} N" in text.out
    assert data["max_pin_force_n"] >= np.load(path)["pin_f_max"][-100:].max() > 0


@pytest.mark.parametrize("args, words", [
    (("--paper-run", "0"), "1 to 36"),
    (("--paper-run", "37"), "1 to 36"),
    (("--paper-run", "x"), "invalid int value"),
    (("--save", "run.csv"), ".npz"),
    (("--report", "run.pdf"), ".html"),
    (("--set", "E=-5"), "operating.load_torque"),
    (("--time-step", "0.1"), "time_step"),
    # a negative value in exponent form is the value, not an option ("expected one argument")
    (("--time-step", "-1e-5"), "'time_step': must be in (0, 0.001] s (got -1e-05)"),
    (("--duration", "-.5"), "(got -0.5 s)"),
    (("--duration", "0"), "duration"),
    # a step so small that the run's step count overflowed the kernel's integer (exit 1 with
    # numba's message), or would take hours
    (("--time-step", "1e-300"), "'time_step': 4 s at 1e-300 s per step is 4e+300 steps, more "
     "than the 1e+09 a run may take (at least 4e-09 s per step for this duration)"),
    (("--time-step", "1e-9"), "is 4000000000 steps, more than the 1e+09"),
    # just above the limit: the count and the least step show it (not "1e+09 ... 4e-09")
    (("--time-step", "4e-9", "--duration", "4.0000001"), "4.0000001 s at 4e-09 s per step is "
     "1000000025 steps, more than the 1e+09 a run may take (at least 4.0000001e-09 s per step"),
    (("--time-step", "-inf"), "'time_step': must be in (0, 0.001] s (got -inf)"),
])
def test_simulate_errors(cli, args, words):
    res = cli("simulate", *args)
    assert res.code == 2 and words in res.err and res.err.count("\n") == 1


def test_failed_simulation_reports_status(cli):
    res = cli("simulate", "--duration", "1.6", "--time-step", "0.0002", "--json")
    assert res.code == 1
    assert json.loads(res.out)["status"] in ("diverged", "runaway_penetration")
    assert "simulation failed" in res.err


def test_implicit_bearings_scheme(cli):
    """Issue 14: the scheme that takes the bearings implicitly, at its own 2e-5 s step."""
    res = cli("simulate", *SHORT_ARGS, "--scheme", "implicit-bearings", "--json")
    assert res.code == 0, res.err
    data = json.loads(res.out)
    assert data["status"] == "ok" and data["steps"] == 20_000          # 0.4 s / 2e-5 s
    assert data["implicit_fallbacks"] == 0 and data["implicit_factorisations"] > 0


@pytest.mark.parametrize("args, words", [
    (("--scheme", "implicit"), "invalid choice"),
    (("--scheme", "implicit-bearings", "--set", "flexibility.model=fe", "--set", "A=true"),
     "'scheme'"),
    (("--scheme", "implicit-bearings", "--params", "cycloid-drive"), "'scheme'"),
])
def test_scheme_errors(cli, args, words):
    res = cli("simulate", "--duration", "1.6", *args)
    assert res.code == 2 and words in res.err and res.err.count("\n") == 1


def test_an_interrupted_report_leaves_neither_file(tmp_path, cli, monkeypatch):
    """--save and --report are one output: Ctrl-C or SIGTERM between them (here: in the
    report) leaves no histories without their report."""
    import rvsim.report

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(rvsim.report, "write_run_report", interrupted)
    res = cli("simulate", *SHORT_ARGS, "--save", str(tmp_path / "r.npz"),
              "--report", str(tmp_path / "r.html"))
    assert res.code == 130 and res.err == "rvsim: interrupted\n"
    assert list(tmp_path.iterdir()) == []
