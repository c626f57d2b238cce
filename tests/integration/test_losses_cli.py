"""``rvsim efficiency`` with an operating temperature and lip seals, as a user runs it
(issue 32 item 4): the JSON reports the temperature, the viscosity and the seals' drag; a cold
reducer and a sealed one run at a lower efficiency; bad input is one line, exit 2, no file."""

import json

import pytest

from rvsim.physics.losses import seal_torque

POINT = ("--params", "RV-40E-bearings", "--speeds", "500", "--torques", "41.2,412", "--json")


def _run(cli, *extra):
    res = cli("efficiency", *POINT, *extra)
    assert res.code == 0, res.err
    return json.loads(res.out)


def test_temperature_and_seals_in_the_json(cli):
    warm = _run(cli)
    assert warm["temperature_c"] == 40.0 and warm["oil_viscosity_mm2_s"] == 100.0
    assert warm["seal_torque_input_nm"] == 0.0 and warm["seal_torque_output_nm"] == 0.0
    cold = _run(cli, "--set", "operating.temperature=20")
    assert cold["temperature_c"] == 20.0
    assert cold["oil_viscosity_mm2_s"] == pytest.approx(318.38, abs=0.01)
    # thicker oil: more viscous bearing drag, lower efficiency at both torques
    for w, c in zip(warm["efficiency"], cold["efficiency"]):
        assert c["efficiency"] < w["efficiency"]
    assert cold["no_load_running_torque_nm"] > warm["no_load_running_torque_nm"]
    sealed = _run(cli, "--set", "friction.input_seal_count=1", "--set",
                  "friction.input_seal_diameter=25")
    assert sealed["seal_torque_input_nm"] == pytest.approx(seal_torque(0.025), rel=1e-15)
    assert sealed["no_load_running_torque_nm"] == pytest.approx(
        warm["no_load_running_torque_nm"] + seal_torque(0.025), rel=1e-6)


def test_text_output_names_the_lubricant_and_the_seals(cli):
    res = cli("efficiency", "--params", "RV-40E-bearings", "--speeds", "500", "--torques",
              "412", "--set", "operating.temperature=60")
    assert res.code == 0, res.err
    assert "lubricant at 60 degC: 41.44 mm^2/s" in res.out
    assert "lip seals' drag: 0 N*m on the input, 0 N*m on the output" in res.out


@pytest.mark.parametrize("args, message", [
    (("--set", "operating.temperature=-300"),
     "operating.temperature': must be greater than -273.15 degC"),
    (("--params", "RV-40E-bearings", "--set", "operating.temperature=-30"),
     "below the lubricant's cloud point"),
    (("--params", "RV-40E-bearings", "--set", "operating.temperature=500", "--set",
      "friction.oil_max_temperature=1000"), "below the 2 mm^2/s it holds for"),
    (("--set", "operating.temperature=20"), "needs a viscosity-temperature law"),
    (("--set", "friction.input_seal_diameter=-25"),
     "friction.input_seal_diameter': must not be negative"),
    (("--set", "friction.output_seal_count=2"), "friction.output_seal_diameter"),
    (("--set", "friction.output_seal_count=-1"), "friction.output_seal_count"),
])
def test_bad_input_is_one_line(cli, tmp_path, args, message):
    page = tmp_path / "eff.html"
    res = cli("efficiency", *args, "--speeds", "500", "--torques", "412", "--report",
              str(page))
    assert res.code == 2, res.err
    lines = res.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rvsim: error:") and message in lines[0]
    assert not page.exists()


def test_simulate_refuses_a_temperature_without_law(cli, tmp_path):
    saved = tmp_path / "run.npz"
    res = cli("simulate", "--set", "operating.temperature=0", "--save", str(saved))
    assert res.code == 2
    assert res.err.count("\n") == 1 and "operating.temperature" in res.err
    assert not saved.exists()
