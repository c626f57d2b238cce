"""CLI of the foundation: help, version, params, profile, sensitivity and their error paths."""

import json
import subprocess
import sys

import pytest

import rvsim


def test_help_and_version(cli):
    res = cli("--help")
    assert res.code == 0 and "params" in res.out and "examples" in res.out
    res = cli("--version")
    assert res.code == 0 and rvsim.__version__ in res.out
    for command in ("params", "profile", "sensitivity"):
        res = cli(command, "--help")
        assert res.code == 0 and "examples" in res.out


def test_every_command_prints_its_help(cli):
    """Every subcommand's --help prints and exits 0 (a '%' in a help text, which argparse
    formats, made `rvsim simulate --help` raise; found by a hostile test)."""
    from rvsim.cli import build_parser

    parser = build_parser()
    commands = next(a for a in parser._actions if a.dest == "command").choices
    assert len(commands) >= 14
    for command in commands:
        res = cli(command, "--help")
        assert res.code == 0 and res.err == "", (command, res.err[-300:])
        assert f"usage: rvsim {command}" in res.out


def test_params_json(cli):
    res = cli("params", "--json")
    data = json.loads(res.out)
    names = {p["name"]: p for p in data["parameters"]}
    assert names["cycloid.eccentricity"]["unit"] == "mm"
    assert names["cycloid.eccentricity"]["value"] == pytest.approx(1.5)


def test_sensitivity_json_shape(cli):
    data = json.loads(cli("sensitivity", "--json").out)
    assert set(data) >= {"K1", "terms"}
    assert len(data["terms"]) == 9
    for term in data["terms"]:
        assert {"symbol", "coefficient", "sensitivity_index", "te_arcmin"} <= set(term)


@pytest.mark.parametrize("args, words", [
    (("params", "--set", "bogus=1"), "unknown parameter"),
    (("params", "--set", "cycloid.eccentricity=abc"), "not a number"),
    (("params", "--set", "cycloid.pin_radius=-1"), "greater than 0"),
    (("params", "--set", "cycloid.pin_count=41"), "disc_teeth + 1"),
    (("params", "--set", "cycloid.eccentricity=2.2"), "K1"),
    (("params", "--set", "cycloid.pin_radius=8"), "undercut"),
    (("params", "--set", "novalue"), "expected name=value"),
    (("params", "--params", "/nonexistent/r.toml"), "not found"),
    (("profile", "--out", "x.txt"), "unsupported profile format"),
    (("profile",), "--out"),
    (("profile", "--out", "/nonexistent/dir/p.dxf"), "does not exist"),
    (("sensitivity", "--set", "G=9"), "errors.eccentricity"),
    (("frobnicate",), "invalid choice"),
])
def test_error_paths_one_line_exit_2(cli, args, words):
    res = cli(*args)
    assert res.code == 2
    assert words in res.err
    assert res.err.count("\n") == 1 and "Traceback" not in res.err


def test_console_script_error_has_no_traceback(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "rvsim.cli", "params", "--set",
                           "cycloid.pin_count=41"], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.startswith("rvsim: error: parameter 'cycloid.pin_count'")
    assert "Traceback" not in proc.stderr


def test_failed_profile_export_leaves_no_file(tmp_path, cli):
    out = tmp_path / "p.dxf"
    res = cli("profile", "--out", str(out), "--points", "10")
    assert res.code == 2 and not out.exists()
    assert list(tmp_path.iterdir()) == []


def test_set_values_win_over_a_paper_run():
    import argparse

    from rvsim.cli._common import reducer_from_args

    args = argparse.Namespace(params=None, assignments=["H=0.05"], paper_run=2)
    reducer = reducer_from_args(args)
    assert reducer.errors.pin_circle_radius == pytest.approx(5e-5)       # from --set
    assert reducer.errors.equidistant_modification == pytest.approx(3.2e-5)  # from run 2
