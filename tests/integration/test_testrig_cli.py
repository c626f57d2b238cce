"""rvsim testrig / rvsim calibrate: output, report, and bad input (one line, exit 2, no file)."""

import json

import numpy as np
import pandas as pd
import pytest

from rvsim.cli import main

EXAMPLE = "docs/examples/testrig"


def _frame(n=4000, revolutions=1.1, ratio=121.0):
    phi = np.linspace(0.0, revolutions * 2 * np.pi, n)
    te = 1e-5 * np.sin(40 * phi)
    return pd.DataFrame({"time_s": np.arange(n) * 0.01, "input_angle_deg": np.degrees(ratio * phi),
                         "output_angle_deg": np.degrees(phi - te)})


def test_example_folder_json_lines_and_report(tmp_path, capsys):
    report = tmp_path / "bench.html"
    assert main(["testrig", EXAMPLE, "--params", "docs/examples/testrig_start.toml",
                 "--json", "--compare", "--report", str(report)]) == 0
    lines = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert len(lines) == 2
    te = next(p for p in lines if p["ate_pp_arcmin"] is not None)
    assert {"te_rms_arcsec", "orders", "efficiency", "forward_backward_offset_arcmin"} <= set(te)
    assert te["simulated"]["status"] == "ok" and "ate_pp_arcmin" in te["difference"]
    loop = next(p for p in lines if p["ate_pp_arcmin"] is None)
    assert loop["lost_motion_arcmin"] > 0 and loop["torsional_rigidity_nm_per_arcmin"] > 0
    assert report.read_text().count("data:image/png;base64") >= 3


def test_semicolon_headerless_counts_and_parquet(tmp_path, capsys):
    frame = _frame()
    counts = frame.copy()
    counts["input_angle_deg"] = np.round(frame["input_angle_deg"] / 360 * 2 ** 20)
    counts.to_csv(tmp_path / "run.csv", sep=";", decimal=",", header=False, index=False)
    assert main(["testrig", str(tmp_path / "run.csv"), "--column", "input_angle=2:counts:1048576",
                 "--json"]) == 0
    first = json.loads(capsys.readouterr().out)
    frame.rename(columns={"output_angle_deg": "out"}).to_parquet(tmp_path / "run.parquet")
    (tmp_path / "map.toml").write_text('[output_angle]\ncolumn = "out"\nunit = "deg"\n')
    assert main(["testrig", str(tmp_path / "run.parquet"), "--map", str(tmp_path / "map.toml"),
                 "--json"]) == 0
    second = json.loads(capsys.readouterr().out)
    # 2^20 counts of the input: 0.01 arcsec of output per count, 0.2 % of this small TE
    assert first["ate_pp_arcmin"] == pytest.approx(second["ate_pp_arcmin"], rel=3e-3)
    assert second["ate_pp_arcmin"] == pytest.approx(2e-5 / (np.pi / 10800), rel=1e-3)


@pytest.mark.parametrize("change, message", [
    (lambda f: f.drop(columns="output_angle_deg"), "missing column 'output_angle_deg'"),
    (lambda f: f.assign(time_s=f.time_s[::-1].to_numpy()), "time does not increase"),
    (lambda f: f.iloc[:2000], "shorter than one output revolution"),
    (lambda f: f.assign(output_angle_deg=f.output_angle_deg.where(f.index % 500 != 7)),
     "NaN gap at data row 8"),
    (lambda f: f.assign(input_angle_deg=f.input_angle_deg * 1.02), "measured ratio"),
])
def test_bad_recordings(tmp_path, capsys, change, message):
    path = tmp_path / "bad.csv"
    change(_frame()).to_csv(path, index=False)
    report = tmp_path / "r.html"
    assert main(["testrig", str(path), "--report", str(report)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"rvsim: error: {path}: ") and message in err
    assert len(err.strip().splitlines()) == 1
    assert not report.exists()


@pytest.mark.parametrize("column", ["input_angle=nope", "input_angle=input_angle_deg:deg",
                                    "oil_temperature=temp_c"])
def test_a_mapped_column_the_file_lacks_is_named(tmp_path, capsys, column):
    """A typo in --column used to fall through to another reading of the file ("read as a
    torque reversal recording: ... no increasing branch")."""
    path = tmp_path / "run.csv"
    _frame().to_csv(path, index=False)
    code = main(["testrig", str(path), "--column", column, "--json"])
    err = capsys.readouterr().err
    if column.endswith(":deg"):                                # present: read as mapped
        assert code == 0, err
        return
    name, quantity = column.split("=")[1], column.split("=")[0]
    assert code == 2 and err.count("\n") == 1
    assert err.startswith(f"rvsim: error: {path}: no column '{name}' (mapped to {quantity}); "
                          "the file has 'time_s', "), err


def test_a_folder_may_lack_a_mapped_optional_column_in_some_files(tmp_path, capsys):
    """One map for a folder: a column some files have (the oil temperature of some runs) is
    fine; one that no file has is named; a file that fails while lacking one is named."""
    import shutil

    folder = tmp_path / "bench"
    shutil.copytree(EXAMPLE, folder)      # the TE file has oil_temperature_c, reversal.csv not
    assert "oil_temperature_c" not in (folder / "reversal.csv").read_text().splitlines()[0]
    code = main(["testrig", str(folder), "--column", "oil_temperature=oil_temperature_c",
                 "--json"])
    out = capsys.readouterr()
    assert code == 0, out.err
    assert main(["testrig", str(folder), "--column", "oil_temperature=temp_c"]) == 2
    assert capsys.readouterr().err == (f"rvsim: error: {folder}: no file has column 'temp_c' "
                                       "(mapped to oil_temperature)\n")
    assert main(["testrig", str(folder), "--column", "input_angle=nope"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"rvsim: error: {folder / 'te_15rpm_300Nm_40C.csv'}: no column "
                          "'nope' (mapped to input_angle)"), err


def test_calibrate_writes_params_the_other_commands_accept(tmp_path, capsys):
    # the example's other uncertain values at their true ones: the stiffness factor alone is
    # then found (0.809 at 128 positions; with the clearance free too the two are correlated
    # +0.997 and only the full-resolution fit of the user guide recovers both)
    start = tmp_path / "start.toml"
    start.write_text('base = "RV-40E"\nname = "bench start"\n[errors]\n'
                     'equidistant_modification = 0.01\ndisc_runout = 0.006\n'
                     '[clearances]\ncrank_arm_bushing = 0.004\n')
    out = tmp_path / "fit"
    assert main(["calibrate", EXAMPLE, "--params", str(start),
                 "--fit", "contact.bushing_stiffness_factor", "--positions", "128",
                 "--out", str(out), "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    estimate = payload["parameters"]["contact.bushing_stiffness_factor"]["estimate"]
    assert 0.7 < estimate < 0.9
    assert main(["params", "--params", str(out / "fitted.toml"), "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["name"] == "bench start, calibrated to testrig"
    rows = shown["parameters"]
    value = next(r["value"] for r in rows if r["name"] == "contact.bushing_stiffness_factor")
    assert value == pytest.approx(estimate, rel=1e-9)


def test_compare_refuses_a_file_ratio_that_is_not_the_models(tmp_path, capsys):
    path = tmp_path / "r81.csv"
    _frame(ratio=81.0).to_csv(path, index=False)
    assert main(["testrig", str(path), "--ratio", "81", "--json"]) == 0      # analysis: fine
    capsys.readouterr()
    assert main(["testrig", str(path), "--ratio", "81", "--compare"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"rvsim: error: {path}: its ratio 81 differs from the parameter "
                          "set's 121")


def test_calibrate_says_when_the_model_fails_next_to_the_start(tmp_path, capsys):
    # the RV-40E's teeth do not assemble with any disc runout: starting at zero, the fit must
    # say so (scipy's relative step, 1e-3 of |x|, stayed at 1e-15 m and claimed an interval)
    out = tmp_path / "fit"
    assert main(["calibrate", EXAMPLE, "--fit", "errors.disc_runout", "--positions", "64",
                 "--out", str(out), "--json"]) == 1
    payload = json.loads(capsys.readouterr().out)
    assert payload["status"] == "model_fails"
    assert payload["parameters"]["errors.disc_runout"]["ci95"] == [None, None]
    assert any("fails on both sides" in n and "overlaps" in n for n in payload["notes"])


def test_compare_without_a_torque_says_the_model_ran_at_zero(tmp_path, capsys):
    path = tmp_path / "free.csv"
    _frame().to_csv(path, index=False)
    assert main(["testrig", str(path), "--compare", "--points", "256"]) == 0
    assert "the model ran at 0 N*m" in capsys.readouterr().out
    assert main(["testrig", str(path), "--compare", "--points", "256", "--json"]) == 0
    assert "0 N*m" in json.loads(capsys.readouterr().out)["simulated"]["note"]


def test_compare_gives_the_model_efficiency_when_the_set_has_friction(tmp_path, capsys):
    path = tmp_path / "run_15rpm_300Nm.csv"
    _frame().assign(input_torque_nm=300 / 121 / 0.85, output_torque_nm=300.0).to_csv(
        path, index=False)
    assert main(["testrig", str(path), "--compare", "--points", "256", "--json",
                 "--params", "RV-40E-bearings"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["efficiency"] == pytest.approx(0.85, rel=1e-9)
    # the efficiency engine at 15 rpm, 300 N*m (0.903 measured when written)
    assert 0.8 < s["simulated"]["efficiency"] < 0.99
    assert s["difference"]["efficiency"] == pytest.approx(0.85 - s["simulated"]["efficiency"])
    assert main(["testrig", str(path), "--compare", "--points", "256", "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert "efficiency" not in s["simulated"] and "no friction" in s["simulated"]["note"]


@pytest.mark.parametrize("name, what", [("gears.sun_teeth", "a whole number"),
                                        ("flexibility.cycloid_disc", "a yes/no switch"),
                                        ("flexibility.model", "a choice")])
def test_calibrate_refuses_what_is_not_continuous(tmp_path, capsys, name, what):
    assert main(["calibrate", EXAMPLE, "--fit", name, "--out", str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err
    assert err == (f"rvsim: error: parameter '{name}': cannot be fitted ({what}; only "
                   "continuous quantities can be)\n")
    assert not (tmp_path / "c").exists()
