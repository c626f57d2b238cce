"""The joint model file (``rvsim hysteresis --export``): schema, round trip, content."""

import json

import numpy as np
import pytest

from rvsim.errors import InputFileError
from rvsim.joint_model import (JOINT_MODEL_SCHEMA, SCHEMA_VERSION, joint_model,
                               load_joint_model, write_joint_model)
from rvsim.parameters import RV40E, with_values
from rvsim.quasistatic.torque_reversal import HysteresisResult
from rvsim.quasistatic.transmission import LtcaResult
from rvsim.units import ARCMIN

#: the known curves the joint model is built from: a linear spring with free play (N*m/rad,
#: rad) and a TE made of three harmonics (order, amplitude [arcmin], phase [rad])
STIFFNESS, FREE_PLAY, RATED = 35.0 / ARCMIN, 0.4 * ARCMIN, 412.0
LINES = ((39.0, 0.05, 0.4), (40.0, 0.02, 0.0), (1.0, 0.01, -1.0))


def known_loop(points: int = 41) -> HysteresisResult:
    """Torque-reversal curve 0 -> -rated -> +rated -> -rated of the spring with free play."""
    grid = np.linspace(-RATED, RATED, points)
    first = np.linspace(0.0, -RATED, points // 2 + 1)
    torque = np.concatenate([first, grid[1:], grid[::-1][1:]])
    came_from = np.concatenate([-np.ones(first.size), -np.ones(points - 1), np.ones(points - 1)])
    side = np.where(torque > 0, 1.0, np.where(torque < 0, -1.0, came_from))
    branch = np.concatenate([-np.ones(first.size), np.ones(points - 1), -np.ones(points - 1)])
    m = torque.size
    return HysteresisResult(torque, torque / STIFFNESS + side * FREE_PLAY / 2, branch, RATED,
                            "ok", 0.0, np.ones(m, bool), np.full(m, STIFFNESS))


def known_te(reducer, n: int = 360) -> LtcaResult:
    """An output revolution whose TE is the wind-up at rated torque plus :data:`LINES`."""
    ratio, zp, zc = reducer.ratio, reducer.cycloid.pin_count, reducer.cycloid.disc_teeth
    out = np.arange(n) * 2 * np.pi / n
    te = RATED / STIFFNESS + FREE_PLAY / 2 + sum(a * ARCMIN * np.cos(k * out + ph)
                                                 for k, a, ph in LINES)
    zeros = np.zeros
    return LtcaResult(out * ratio, out - te, te, RATED, ratio, zp, zc, zeros((n, 2, zp)),
                      zeros((n, 2, zp)), zeros((n, 2, 2)), zeros((n, 2, 2)), zeros((n, 2)),
                      zeros((n, 2)), np.full(n, STIFFNESS), "ok", 0.0, np.ones(n, bool),
                      np.zeros(n, int))


@pytest.fixture
def model():
    reducer = with_values(RV40E, {"I": 0.01})
    loop = known_loop()
    te = known_te(reducer)
    return joint_model(loop, te, reducer), loop, te


def test_round_trip_and_schema(model, tmp_path):
    data, _, _ = model
    path = write_joint_model(tmp_path / "joint.json", data)
    again = load_joint_model(path)
    assert again == json.loads(json.dumps(data))
    assert again["schema_version"] == SCHEMA_VERSION
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.validate(again, JOINT_MODEL_SCHEMA)


def test_content_matches_the_curves(model):
    data, loop, te = model
    summary = loop.summary()
    assert data["backlash_rad"] == pytest.approx(summary["backlash_arcmin"] * ARCMIN, rel=1e-12)
    assert data["stiffness"]["torsional_rigidity_nm_per_rad"] == pytest.approx(
        STIFFNESS, rel=1e-12)
    assert np.allclose(data["stiffness"]["local"]["stiffness_nm_per_rad"], STIFFNESS,
                       rtol=1e-9)
    loading = data["torque_angle"]["loading"]
    assert loading["torque_nm"][0] == -412.0 and loading["torque_nm"][-1] == 412.0
    lines = {h["order"]: h for h in data["transmission_error"]["harmonics"]}
    for order, amplitude, phase in LINES:
        assert lines[order]["amplitude_rad"] == pytest.approx(amplitude * ARCMIN, rel=1e-9)
        assert lines[order]["phase_rad"] == pytest.approx(phase, abs=1e-9)
    # the harmonics rebuild the TE about its mean (what a controller adds to its command)
    theta = te.input_angle / te.ratio
    rebuilt = data["transmission_error"]["mean_rad"] + sum(
        h["amplitude_rad"] * np.cos(h["order"] * theta + h["phase_rad"]) for h in lines.values())
    assert np.max(np.abs(rebuilt - te.te)) < 1e-12 * ARCMIN * 1e3


@pytest.mark.parametrize("text, words", [
    ("not json", "not valid JSON"),
    ('{"schema": "other"}', "not a joint model"),
    ('{"schema": "rvsim-joint-model", "schema_version": 99}', "version 99"),
    ('{"schema": "rvsim-joint-model", "schema_version": 1}', "lacks"),
])
def test_bad_files(tmp_path, text, words):
    path = tmp_path / "j.json"
    path.write_text(text)
    with pytest.raises(InputFileError, match=words):
        load_joint_model(path)
    with pytest.raises(InputFileError, match="not found"):
        load_joint_model(tmp_path / "missing.json")


def test_the_documented_snippet_runs(model, tmp_path, monkeypatch):
    from pathlib import Path

    doc = (Path(__file__).parents[2] / "docs" / "joint_model.md").read_text()
    code = doc.split("```python\n")[1].split("```")[0]
    data, loop, _ = model
    write_joint_model(tmp_path / "joint.json", data)
    monkeypatch.chdir(tmp_path)
    scope = {}
    exec(compile(code, "joint_model.md", "exec"), scope)
    # at 150 N*m on the loading branch: elastic wind-up plus half the free play
    free = loop.summary()["backlash_arcmin"] * ARCMIN
    assert scope["deflection"](150.0) == pytest.approx(150.0 / STIFFNESS + free / 2,
                                                       rel=1e-9)
    assert abs(scope["theta_out"] - 0.7) < 1e-2


def test_main_bearing_stiffness_travels_with_the_joint(model):
    # the robot model needs the carrier's tilting stiffness beside the torsional curve
    from rvsim.bearings import main_bearing_stiffness

    data, _, _ = model
    main = main_bearing_stiffness(with_values(RV40E, {"I": 0.01}))
    assert data["main_bearings"]["tilting_stiffness_nm_per_rad"] == main.tilting
    assert data["main_bearings"]["radial_stiffness_n_per_m"] == main.radial
    assert data["main_bearings"]["axial_stiffness_n_per_m"] == main.axial
