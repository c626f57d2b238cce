"""rvsim testrig / rvsim calibrate: output, report, and bad input (one line, exit 2, no file)."""

import json

import numpy as np
import pandas as pd
import pytest

from rvsim.cli import main
from tests.integration.answer_block import answer

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
    rows = answer(report.read_text())     # the answer first (issue 34 item 2)
    row = next(v for k, v in rows.items() if k.startswith("lost motion ("))
    assert row[0] == f"{loop['lost_motion_arcmin']:.4g} arcmin measured"
    model = loop["simulated"]["lost_motion_arcmin"]
    assert row[1] == f"model {model:.4g} arcmin"


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
    assert main(["calibrate", EXAMPLE, "--fit", "errors.disc_runout", "--positions", "81",
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
    # % beside the fraction, as rvsim efficiency's JSON; the console in % (issue 34)
    assert s["efficiency_pct"] == pytest.approx(85.0, rel=1e-9)
    assert s["simulated"]["efficiency_pct"] == pytest.approx(100 * s["simulated"]["efficiency"])
    assert s["difference"]["efficiency_pct"] == pytest.approx(100 * s["difference"]["efficiency"])
    assert main(["testrig", str(path), "--compare", "--positions", "256", "--params",
                 "RV-40E-bearings"]) == 0
    out = capsys.readouterr().out
    assert "  efficiency 85.00 %" in out
    assert f"efficiency_pct {s['simulated']['efficiency_pct']:.4g} (difference" in out
    assert "efficiency 0." not in out
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


# --- hostile review of the tenth session: each case printed an absurd number as fine, or a
# traceback, or refused a good file for a wrong reason


def _bad(tmp_path, capsys, frame, name="run.csv", **csv):
    frame.to_csv(tmp_path / name, index=False, **csv)
    code = main(["testrig", str(tmp_path / name)])
    return code, capsys.readouterr()


@pytest.mark.parametrize("change, message", [
    # an output encoder counting the other way gave a TE of 720 degrees, exit 0
    (lambda f: f.assign(output_angle_deg=-f.output_angle_deg),
     "the output turns against the ratio's sense (measured ratio -121"),
    # a dead output encoder gave a TE of 360 degrees, exit 0
    (lambda f: f.assign(output_angle_deg=0.0), "the output angle stands still"),
    # a TE of 1e306 overflowed into a 300-digit peak-to-peak
    (lambda f: f.assign(output_angle_deg=f.output_angle_deg.where(f.index != 9, 1e306)),
     "column 'output_angle_deg' data row 10: '1e+306' deg is beyond any bench's output angle"),
    (lambda f: f.assign(output_torque_nm=1e308), "beyond any bench's output torque"),
])
def test_absurd_encoders_and_values_are_refused(tmp_path, capsys, change, message):
    code, out = _bad(tmp_path, capsys, change(_frame().assign(output_torque_nm=300.0)))
    assert code == 2 and out.out == ""
    assert out.err.count("\n") == 1 and message in out.err, out.err


def test_a_ratio_slightly_off_is_noted_and_an_absurd_efficiency_too(tmp_path, capsys):
    frame = _frame().assign(input_torque_nm=300.0 / 121 / 0.85 / 10, output_torque_nm=300.0)
    frame.to_csv(tmp_path / "run.csv", index=False)
    # 121.05 for the recording's exact 121: the TE is a 0.04 % trend (9 arcmin a revolution)
    assert main(["testrig", str(tmp_path / "run.csv"), "--ratio", "121.05", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    trend, efficiency = summary["notes"]
    assert "the measured ratio 121 differs from 121.05 by -0.041" in trend
    assert "a trend of about 8.9" in trend and "arcmin per output revolution" in trend
    assert "the efficiency 8.5 from the torque columns is outside 0 to 1" in efficiency
    # the right ratio: no note, and the text output prints the notes it has
    assert main(["testrig", str(tmp_path / "run.csv")]) == 0
    text = capsys.readouterr().out
    assert text.count("note:") == 1 and "efficiency 8.5" in text
    assert main(["testrig", str(tmp_path / "run.csv"), "--ratio", "inf"]) == 2
    assert "--ratio" in capsys.readouterr().err


def test_coarse_output_encoder_on_a_reversal_is_named_not_a_traceback(tmp_path, capsys):
    frame = pd.read_csv(f"{EXAMPLE}/reversal.csv")
    frame["output_angle_deg"] = (frame["output_angle_deg"] / 0.01).round() * 0.01
    code, out = _bad(tmp_path, capsys, frame)
    assert code == 2 and "a stuck or too coarse angle encoder" in out.err, out.err
    # the loop run backwards (unloading first): named, not as a "rated torque" the user never
    # gave
    frame = pd.read_csv(f"{EXAMPLE}/reversal.csv")
    backwards = frame.drop(columns="time_s")[::-1].reset_index(drop=True)
    code, out = _bad(tmp_path, capsys, backwards.assign(time_s=frame["time_s"]))
    assert code == 2 and "are the rows in time order?" in out.err, out.err


def test_the_reversal_note_reaches_the_text_output(tmp_path, capsys):
    frame = pd.read_csv(f"{EXAMPLE}/reversal.csv")
    frame["output_torque_nm"] *= 0.5
    frame.to_csv(tmp_path / "half.csv", index=False)
    assert main(["testrig", str(tmp_path / "half.csv")]) == 0
    assert "not the rated 412 N*m" in capsys.readouterr().out


def test_manifest_with_bom_and_semicolon_file_zeroed_at_its_start(tmp_path, capsys):
    frame = _frame()
    frame.iloc[:, 1:] -= frame.iloc[0, 1:]          # a first data row of whole numbers
    frame.to_csv(tmp_path / "run.csv", sep=";", decimal=",", index=False)
    (tmp_path / "manifest.csv").write_bytes(b"\xef\xbb\xbffile,torque_nm\nrun.csv,300\n")
    assert main(["testrig", str(tmp_path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["point"]["torque_nm"] == 300.0
    (tmp_path / "manifest.csv").write_text("file,torque_nm\nrun.csv,300\n,200\n")
    assert main(["testrig", str(tmp_path)]) == 2
    assert "row 3: the file cell is empty" in capsys.readouterr().err


def test_one_revolution_te_curve_sampled_periodically(tmp_path, capsys):
    x = np.arange(720) * 0.5
    curve = pd.DataFrame({"output_angle_deg": x, "te_arcsec": 6 * np.sin(np.radians(40 * x)),
                          "direction": 1})
    curve.to_csv(tmp_path / "curve.csv", index=False)
    assert main(["testrig", str(tmp_path / "curve.csv"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["ate_pp_arcmin"] == pytest.approx(0.2, rel=1e-3)
    assert summary["orders"][0]["order"] == 40
    # one sample short of that: refused, and the coverage is not rounded up to "1"
    curve.iloc[:-1].to_csv(tmp_path / "short.csv", index=False)
    assert main(["testrig", str(tmp_path / "short.csv")]) == 2
    assert "covers 0.9972 of a revolution" in capsys.readouterr().err


def test_calibrate_status_says_when_a_parameter_is_not_fitted(tmp_path, capsys):
    # the data do not depend on the carrier's density: it was "status ok", exit 0
    assert main(["calibrate", EXAMPLE, "--params", "docs/examples/testrig_start.toml", "--fit",
                 "materials.carrier.density", "--positions", "81", "--out",
                 str(tmp_path / "a"), "--json"]) == 1
    payload = json.loads(capsys.readouterr().out)
    assert payload["status"] == "not_identifiable"
    assert payload["parameters"]["materials.carrier.density"]["ci95"] == [None, None]
    # a ratio 0.4 % off: the recordings' trend note reaches the calibration, and an interval
    # that reached below zero for a runout is cut at zero, and said so; the trend (RMS 1224.43
    # -> 1224.42 arcsec) is no fit: it was "status ok", exit 0 (issue 30, fifth session)
    assert main(["calibrate", EXAMPLE, "--params", "docs/examples/testrig_start.toml",
                 "--ratio", "121.5", "--fit", "errors.disc_runout", "--positions", "81",
                 "--out", str(tmp_path / "b"), "--json"]) == 1
    payload = json.loads(capsys.readouterr().out)
    assert payload["status"] == "lack_of_fit"
    assert any("8 runs of one sign in 258 residuals, runs test z = -15.2" in n
               for n in payload["notes"])
    low, high = payload["parameters"]["errors.disc_runout"]["ci95"]
    assert low == 0.0 and high > 0.02
    assert any("differs from 121.5" in n for n in payload["notes"])
    assert any("is cut at its bound 0 mm" in n for n in payload["notes"])


def test_an_input_angle_in_radians_labelled_degrees_is_a_unit_error(tmp_path, capsys):
    # it was read as a torque reversal (the input hardly turns, the torque changes sign) and
    # refused for a loop it is not
    frame = pd.read_csv(f"{EXAMPLE}/te_15rpm_300Nm_40C.csv")
    frame["input_angle_deg"] = np.radians(frame["input_angle_deg"])
    code, out = _bad(tmp_path, capsys, frame)
    assert code == 2 and "the measured ratio 2.1116 differs from 121 by -98.3 %" in out.err
    assert "check the angle units" in out.err


def test_a_logger_clock_in_unix_time_is_a_time(tmp_path, capsys):
    # a reviewer's case: the bound on values refused a time column of Unix time (1.76e9 s)
    frame = pd.read_csv(f"{EXAMPLE}/te_15rpm_300Nm_40C.csv")
    assert main(["testrig", f"{EXAMPLE}/te_15rpm_300Nm_40C.csv", "--json"]) == 0
    reference = json.loads(capsys.readouterr().out)
    frame["time_s"] += 1764230400.0
    frame.to_csv(tmp_path / "clock.csv", index=False)
    assert main(["testrig", str(tmp_path / "clock.csv"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["ate_pp_arcmin"] == pytest.approx(reference["ate_pp_arcmin"], rel=1e-9)


def test_a_given_ratio_takes_the_parameter_sets_sense(tmp_path, capsys):
    # a reviewer's case: a cycloid drive's recording (output = -input / 29) with --ratio 29
    # was refused as counting against the ratio's sense
    frame = _frame(ratio=-29.0)
    frame.to_csv(tmp_path / "cycloid.csv", index=False)
    for extra in ([], ["--ratio", "29"]):
        assert main(["testrig", str(tmp_path / "cycloid.csv"), "--params", "cycloid-drive",
                     "--json", *extra]) == 0
        summary = json.loads(capsys.readouterr().out)
        assert summary["ratio_measured"] == pytest.approx(29.0, rel=1e-4)
        assert summary["ate_pp_arcmin"] == pytest.approx(2e-5 / (np.pi / 10800), rel=1e-3)


def test_calibrate_refuses_a_recording_shorter_than_a_revolution(tmp_path, capsys):
    """Issue 33 item 6: a recording too short for a revolution, before any fit or output."""
    path = tmp_path / "short.csv"
    _frame().iloc[:2000].to_csv(path, index=False)
    out = tmp_path / "cal"
    assert main(["calibrate", str(path), "--fit", "errors.pin_radius", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == (f"rvsim: error: {path}: shorter than one output revolution (the longest run "
                   "in one direction covers 0.5498 of a revolution)\n")
    assert not out.exists()
