"""Every bad input is one line ``rvsim: error: ...`` naming the field, exit code 2, no file.

Each row is what a new user might type: the command line (``{study}`` stands for a study file
written from the row's TOML text, ``{folder}`` for an existing folder, ``{file}`` for an
existing file) and the words the error must contain.  After the command the working folder
must hold exactly what it held before.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest

from rvsim.doe.outputs import write_study_outputs
from rvsim.parameters import paper_l36_scheme

from .conftest import SHORT, factors

H = factors(H=("errors.pin_circle_radius", [0.0, 0.02]))
H_RANGE = factors(H=("H", "range", [0.0, 0.02]))
TWELVE = factors(**{f"F{i}": (name, [0.0, 0.001, 0.002, 0.003, 0.004]) for i, name in enumerate(
    ["errors.pin_radius", "errors.eccentricity", "errors.pin_circle_radius",
     "errors.equidistant_modification", "errors.radial_modification",
     "errors.rotation_modification", "errors.disc_runout", "errors.pin_position_tolerance",
     "clearances.crank_arm_bushing", "clearances.support_flange",
     "clearances.disc_arm_bushing", "clearances.support_carrier"])})


def study(top: str = "", body: str = H, design: str = "L4") -> str:
    return f'name = "bad"\ndesign = "{design}"\n{top}\n{SHORT}\n{body}'


STUDY_ROWS = {
    "parameter = 5": (study(body='[factors.H]\nparameter = 5\nlevels = [0.0, 0.02]\n'),
                      "factors.H.parameter"),
    "set = 5": ('name = "bad"\nset = 5\n' + H, "'set'"),
    "seed = 'abc'": (study('seed = "abc"'), "seed"),
    "seed = -1": (study("seed = -1"), "seed"),
    "samples = '8'": (study('samples = "8"', H_RANGE, "lhs"), "samples"),
    "samples = 8.5": (study("samples = 8.5", H_RANGE, "lhs"), "samples"),
    "samples = 1e9": (study("samples = 1000000000", H_RANGE, "lhs"), "samples"),
    "range = ['a', 0.02]": (study("samples = 8", factors(H=("H", "range", '["a", 0.02]')),
                                  "lhs"), "factors.H.range"),
    "range low > high": (study("samples = 8", factors(H=("H", "range", [0.02, 0.0])), "lhs"),
                         "factors.H.range"),
    "[factors.run]": (study(body=factors(run=("H", [0.0, 0.02]))), "factors.run"),
    "label te_mean_arcmin": (study(body=factors(te_mean_arcmin=("H", [0.0, 0.02]))),
                             "factors.te_mean_arcmin"),
    "label status": (study(body=factors(status=("H", [0.0, 0.02]))), "factors.status"),
    "label key": (study(body=factors(key=("H", [0.0, 0.02]))), "factors.key"),
    "params = 5": (study("params = 5"), "'params'"),
    "name = 5": (study().replace('name = "bad"', "name = 5"), "'name'"),
    "two factors, one parameter": (study(body=H + factors(X=("H", [0.0, 0.01]))),
                                   "which factor H already varies"),
    "[set] value also a factor": (study(body=H).replace(
        "[set]", '[set]\n"H" = 0.01'), "set.errors.pin_circle_radius"),
    "time_step = 1.0": (study("time_step = 1.0"), "time_step"),
    "time_step = 'fast'": (study('time_step = "fast"'), "time_step"),
    "time_step = 0": (study("time_step = 0"), "time_step"),
    "full factorial 5^12": (study(body=TWELVE, design="full"), "design"),
    "repeated level": (study(body=factors(H=("H", [0.0, 0.0]))), "factors.H.levels"),
    "unknown factor key": (study(body=H.replace("levels", "level")), "factors.H"),
}

CLI_ROWS = {
    "--workers -1": (["study", "{study}", "--out", "out", "--workers", "-1"], "--workers"),
    "--workers 0": (["study", "{study}", "--out", "out", "--workers", "0"], "--workers"),
    "study --out ''": (["study", "{study}", "--out", ""], "--out"),
    "study --out FILE": (["study", "{study}", "--out", "{file}"], "--out"),
    "study --alpha 0": (["study", "{study}", "--out", "out", "--alpha", "0"], "--alpha"),
    "study --alpha 1": (["study", "{study}", "--out", "out", "--alpha", "1"], "--alpha"),
    "study --alpha nan": (["study", "{study}", "--out", "out", "--alpha", "nan"], "--alpha"),
    "analyze --alpha 1.5": (["analyze", "{file}", "--alpha", "1.5"], "--alpha"),
    "report --alpha -1": (["report", "{folder}", "--alpha", "-1"], "--alpha"),
    "study file is a folder": (["study", "{folder}.toml", "--out", "out"], "is a folder"),
    "study file is binary": (["study", "{binary}", "--out", "out"], "not a text file"),
    "simulate --save FOLDER": (["simulate", "--save", "{folder}.npz"], "--save"),
    # a hostile test's 100 000 modes crashed the eigensolver after meshing the disc
    "simulate fe_modes 100000": (["simulate", "--set", "flexibility.model=fe", "--set",
                                  "flexibility.fe_modes=100000", "--save", "m.npz"],
                                 "'flexibility.fe_modes': must not exceed 100 (got 100000)"),
    "simulate fe_segments_per_tooth 100000": (
        ["simulate", "--set", "flexibility.model=fe", "--set",
         "flexibility.fe_segments_per_tooth=100000", "--save", "m.npz"],
        "'flexibility.fe_segments_per_tooth': must not exceed 64 (got 100000)"),
    "simulate --report no folder": (["simulate", "--report", "nowhere/r.html"], "--report"),
    "profile --out FOLDER": (["profile", "--out", "{folder}"], "--out"),
    "profile --out ''": (["profile", "--out", ""], "--out"),
    "profile --points 1e12": (["profile", "--out", "p.csv", "--points", "1000000000000"],
                              "--points"),
    # the least is 3 per tooth: the limit in the message is the one that applies
    "profile --points 2": (["profile", "--out", "p.csv", "--points", "2"],
                           "'--points': must be between 117 (3 per tooth of the 39-tooth "
                           "disc) and 1,000,000 (got 2)"),
    # the undercut names what was changed, not the pin radius
    "profile --set I=5": (["profile", "--out", "p.csv", "--set", "I=5"],
                          "'errors.equidistant_modification': teeth undercut"),
    "--scheduler tcp://": (["study", "{study}", "--out", "out", "--scheduler", "tcp://"],
                           "--scheduler"),
    "--scheduler host:port99999": (["study", "{study}", "--out", "out", "--scheduler",
                                    "host:99999"], "--scheduler"),
    "--scheduler foo:bar": (["study", "{study}", "--out", "out", "--scheduler", "foo:bar"],
                            "--scheduler"),
    "--params ''": (["params", "--params", ""], "--params"),
    "simulate --save ''": (["simulate", "--save", ""], "--save"),
    "analyze ''": (["analyze", ""], "table"),
    # an empty list fell back to the default factors; a blank name was "given twice"
    "analyze --factors ''": (["analyze", "{file}", "--factors", ""],
                             "'--factors': '': expected comma-separated column names"),
    "analyze --factors ','": (["analyze", "{file}", "--factors", ","], "'--factors': ','"),
    "analyze a folder": (["analyze", "{folder}"], "a_folder"),
    "--params a folder": (["params", "--params", "{folder}"], "a_folder"),
    "sun_teeth = 1e20": (["params", "--set", "gears.sun_teeth=1e20"], "gears.sun_teeth"),
}
if Path("/dev/zero").exists():   # endless: read until memory ran out (a hostile test)
    CLI_ROWS["--params /dev/zero"] = (["sensitivity", "--params", "/dev/zero"],
                                      "/dev/zero: larger than 16 MiB")
if Path("/proc").is_dir():   # a folder nobody can write in, even root
    CLI_ROWS["study --out unwritable"] = (["study", "{study}", "--out", "/proc/rvsim-out"],
                                          "--out")
    CLI_ROWS["simulate --save unwritable"] = (["simulate", "--save", "/proc/x.npz"], "--save")
    CLI_ROWS["profile --out unwritable"] = (["profile", "--out", "/proc/x.csv"], "--out")


PARAMS_ROWS = {
    "base = []": ("base = []\n", "'base'"),
    "name = []": ("name = []\n", "'name'"),
    "value a list": ("[cycloid]\neccentricity = [1, 2]\n", "cycloid.eccentricity"),
    "unknown table": ("[cycloid.eccentricity]\nx = 1\n", "cycloid.eccentricity.x"),
    "yes/no": ('[operating]\nload_fluctuation = "maybe"\n', "operating.load_fluctuation"),
}


def listing(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def expect_one_line_error(res, words: str) -> None:
    assert res.code == 2, (res.out, res.err)
    assert res.err.startswith("rvsim: error: ") and res.err.count("\n") == 1, res.err
    assert words in res.err, res.err
    assert "Traceback" not in res.err + res.out


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "good.toml").write_text(study())
    (tmp_path / "a_folder").mkdir()
    (tmp_path / "a_folder.toml").mkdir()
    (tmp_path / "a_folder.npz").mkdir()
    (tmp_path / "a_file.csv").write_text("A,B,te_arcmin\n1,1,1\n2,2,2\n1,2,1\n2,1,3\n")
    (tmp_path / "binary.toml").write_bytes(bytes(range(256)))
    return tmp_path


@pytest.mark.parametrize("case", list(STUDY_ROWS))
def test_bad_study_file(workdir, cli, case):
    text, words = STUDY_ROWS[case]
    (workdir / "bad.toml").write_text(text)
    before = listing(workdir)
    expect_one_line_error(cli("study", "bad.toml", "--out", "out", "--no-progress"), words)
    assert listing(workdir) == before


@pytest.mark.parametrize("case", list(CLI_ROWS))
def test_bad_command_line(workdir, cli, case):
    args, words = CLI_ROWS[case]
    names = {"{study}": "good.toml", "{folder}": "a_folder", "{file}": "a_file.csv",
             "{binary}": "binary.toml"}
    for token, value in names.items():
        args = [a.replace(token, value) for a in args]
    before = listing(workdir)
    expect_one_line_error(cli(*args), words)
    assert listing(workdir) == before


@pytest.mark.parametrize("case", list(PARAMS_ROWS))
def test_bad_reducer_file(workdir, cli, case):
    text, words = PARAMS_ROWS[case]
    (workdir / "reducer.toml").write_text(text)
    before = listing(workdir)
    expect_one_line_error(cli("profile", "--params", "reducer.toml", "--out", "p.csv"), words)
    assert listing(workdir) == before


def test_a_letter_alias_and_its_dotted_name_are_one_parameter(workdir, cli):
    text = study(body=factors(H=("H", [0.0, 0.02]), P=("errors.pin_circle_radius", [0, 0.01])))
    (workdir / "bad.toml").write_text(text)
    expect_one_line_error(cli("study", "bad.toml", "--out", "out"), "factors.P")


# --- a damaged study folder given to 'rvsim report' ---------------------------------------

def make_study_folder(folder: Path, failed_runs=()) -> Path:
    """A study folder as 'rvsim study' leaves it (without the store), from the paper's table."""
    folder.mkdir()
    table = paper_l36_scheme().drop(columns=["note"]).rename(
        columns={"te_arcmin": "te_mean_arcmin"}).assign(status="ok", error="", key="k")
    for run in failed_runs:
        table.loc[table["run"] == run, ["status", "error", "te_mean_arcmin"]] = \
            ["diverged", "simulation diverged at step 10", float("nan")]
    write_study_outputs(folder, table, list("ABCDEFGHIJKLMNO"))
    definition = {"name": "paper", "design": "L36", "samples": None, "seed": 0,
                  "time_step": 1e-5, "reducer": "RV-40E", "steady_start": 3.0,
                  # each factor's levels as the table has them (L36: 2 or 3; the study's
                  # answer block reads the optimum's level from them)
                  "factors": [{"label": f, "parameter": f"p.{f}",
                               "levels": sorted(int(v) for v in table[f].unique()),
                               "low": None, "high": None} for f in "ABCDEFGHIJKLMNO"],
                  "fixed": []}
    (folder / "study.json").write_text(json.dumps(definition))
    return folder


def truncate(path: Path, fraction: float) -> None:
    data = path.read_bytes()
    path.write_bytes(data[:int(len(data) * fraction)])


DAMAGE = {
    "bad analysis.json": (lambda f: (f / "analysis.json").write_text("{bad"), "analysis.json"),
    "analysis.json a list": (lambda f: (f / "analysis.json").write_text("[1]"),
                             "analysis.json"),
    "analysis.json of other factors": (
        lambda f: (f / "analysis.json").write_text(json.dumps(
            {"range": {"Z": {}}, "order": "Z", "optimum": {}, "anova": {},
             "prediction": {}})), "analysis.json"),
    "{} study.json": (lambda f: (f / "study.json").write_text("{}"), "study.json"),
    "study.json not UTF-8": (lambda f: (f / "study.json").write_bytes(b"\xff\xfe{"),
                             "study.json"),
    "results.csv cut in a row": (lambda f: truncate(f / "results.csv", 0.5), "results.csv"),
    "results.csv cut in the header": (lambda f: truncate(f / "results.csv", 0.01),
                                      "results.csv"),
    "results.csv empty": (lambda f: (f / "results.csv").write_text(""), "results.csv"),
    "results.csv missing": (lambda f: (f / "results.csv").unlink(), "results.csv"),
    "study.json missing": (lambda f: (f / "study.json").unlink(), "study.json"),
    "results.csv a folder": (lambda f: ((f / "results.csv").unlink(),
                                        (f / "results.csv").mkdir()), "results.csv"),
}


@pytest.fixture(scope="module")
def intact_study(tmp_path_factory):
    return make_study_folder(tmp_path_factory.mktemp("intact") / "s")


def test_an_intact_study_folder_gets_its_report(tmp_path, cli, intact_study):
    folder = Path(shutil.copytree(intact_study, tmp_path / "s"))
    res = cli("report", str(folder))
    assert res.code == 0, res.err
    assert (folder / "report.html").is_file()


def test_a_study_with_a_failed_run_is_analysed_with_a_note(tmp_path, cli):
    folder = make_study_folder(tmp_path / "s", failed_runs=(18,))
    analysis = json.loads((folder / "analysis.json").read_text())
    assert analysis["runs_ok"] == 35 and "error" not in analysis
    assert any("unbalanced" in note for note in analysis["notes"])
    res = cli("report", str(folder))
    assert res.code == 0, res.err
    page = (folder / "report.html").read_text()
    assert "unbalanced table" in page and "Failed runs" in page


@pytest.mark.parametrize("case", list(DAMAGE))
def test_report_of_a_damaged_study_folder(tmp_path, cli, case, intact_study):
    damage, words = DAMAGE[case]
    folder = Path(shutil.copytree(intact_study, tmp_path / "s"))
    damage(folder)
    before = listing(tmp_path)
    expect_one_line_error(cli("report", str(folder)), words)
    assert listing(tmp_path) == before          # no report.html, no results.sqlite


def test_analysis_json_of_a_study_is_strict_json(intact_study):
    folder = intact_study

    def refuse(name):
        raise AssertionError(f"bare {name}")

    data = json.loads((folder / "analysis.json").read_text(), parse_constant=refuse)
    assert data["anova"]["Error"]["p"] is None


def test_params_toml_round_trips_quotes_and_backslashes(tmp_path, cli):
    name = 'my "RV" \\ test\ttab'
    source = tmp_path / "in.toml"
    source.write_text('name = "my \\"RV\\" \\\\ test\\ttab"\n')
    res = cli("params", "--params", str(source), "--toml")
    assert res.code == 0, res.err
    (tmp_path / "out.toml").write_text(res.out)
    again = json.loads(cli("params", "--params", str(tmp_path / "out.toml"), "--json").out)
    assert again["name"] == name


def test_output_files_are_written_atomically(tmp_path):
    from rvsim.plots import figure_to_png, main_effects_plot
    from rvsim.analysis import range_analysis

    table = paper_l36_scheme().drop(columns=["note"])
    png = tmp_path / "effects.png"
    data = figure_to_png(main_effects_plot(range_analysis(table, "te_arcmin")), png)
    assert png.read_bytes() == data and data[:4] == b"\x89PNG"
    assert os.listdir(tmp_path) == ["effects.png"]     # no temporary file left beside it


def test_names_and_numbers_a_hostile_review_found(tmp_path, cli, monkeypatch):
    monkeypatch.chdir(tmp_path)
    # Python's float() reads "1_0" as 10
    res = cli("params", "--set", "H=1_0")
    assert res.code == 2 and "'1_0' is not a number" in res.err
    # "need inf GB"
    res = cli("simulate", "--duration", "1e308")
    assert res.code == 2 and "need more memory than any machine has" in res.err
    # a name that is only its ending: "unsupported profile format ''"
    res = cli("profile", "--out", ".dxf", "--points", "117")
    assert res.code == 0, res.err
    assert (tmp_path / ".dxf").read_text().startswith("  0\nSECTION")
    # upper-case .NPZ was refused by the save, naming its temporary file
    from .test_simulate_cli import SHORT_ARGS

    res = cli("simulate", *SHORT_ARGS, "--scheme", "implicit-bearings", "--save", "RUN.NPZ")
    assert res.code == 0, res.err
    assert sorted(p.name for p in tmp_path.iterdir()) == [".dxf", "RUN.NPZ"]


@pytest.mark.parametrize("args", [("ltca", "--torque", "1_0"), ("simulate", "--time-step", "1_0"),
                                  ("analyze", "x.csv", "--alpha", "0_1")])
def test_digit_groups_are_no_numbers_on_the_command_line(cli, args):
    # Python reads "1_0" as 10: --set and parameter files refused it, the options did not
    res = cli(*args)
    assert res.code == 2 and "is not a number" in res.err and res.err.count("\n") == 1
