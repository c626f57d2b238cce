"""Issue 31 steps 4-8: what moved keeps its behaviour, and the import test catches a return.

* step 4: the value checks stay in ``parameters`` (:func:`check_values`), the checks that need
  geometry are :func:`rvsim.geometry.checks.check_geometry`; ``parameters.validate`` runs both,
  in the old order;
* step 5: :mod:`rvsim.html` holds the report building blocks (the old private names are the
  same objects);
* step 6: the analysis figures live in :mod:`rvsim.analysis.figures`, matplotlib's set-up in
  :mod:`rvsim._matplotlib`;
* step 7: one evaluator protocol with a registry (``rvsim.doe.engines.EVALUATORS``), public
  executors in ``doe.runner``, one reader of study files;
* step 8: ``geometry.deviations`` owns the pin centres (``doe._workers <-> doe.runner`` stays,
  see docs/decisions.md);
* the import test fails when an upward import or a circle comes back.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from pathlib import Path

import pytest

from rvsim.errors import InputFileError, ParameterError
from rvsim.parameters import RV40E, validate, with_values

sys.path.insert(0, str(Path(__file__).resolve().parent))
import test_import_layers as layers  # noqa: E402  (the import test's own graph functions)


# --- step 4 ---------------------------------------------------------------------------------

def test_value_checks_need_no_geometry():
    from rvsim.parameters._io import check_values

    assert check_values(RV40E) is RV40E
    # the pin hole clearance is a value, the profile that does not fit the pins is geometry:
    # check_values passes a reducer whose only fault is geometric, check_geometry refuses it
    bad = dataclasses.replace(RV40E, crank=dataclasses.replace(RV40E.crank,
                                                               eccentric_radius=0.05))
    assert check_values(bad) is bad
    from rvsim.geometry.checks import check_geometry

    with pytest.raises(ParameterError) as geometric:
        check_geometry(bad)
    with pytest.raises(ParameterError) as public:
        validate(bad)
    assert (public.value.field, public.value.reason) == (geometric.value.field,
                                                         geometric.value.reason)


def test_a_value_fault_is_reported_before_a_geometric_one():
    bad = dataclasses.replace(RV40E, crank=dataclasses.replace(RV40E.crank,
                                                               eccentric_radius=0.05),
                              operating=dataclasses.replace(RV40E.operating,
                                                            duration=-1.0))
    with pytest.raises(ParameterError, match="operating.duration"):
        validate(bad)


def test_assembly_false_leaves_out_the_assembly_check_only(monkeypatch):
    import rvsim.geometry.checks as checks

    calls = []
    monkeypatch.setattr(checks, "check_assembly", lambda r: calls.append(r))
    validate(RV40E, assembly=False)
    assert calls == []
    validate(RV40E)
    assert calls == [RV40E]


def test_moved_names_keep_their_values():
    from rvsim.bearings import roller_pitch_diameter as public
    from rvsim.geometry.checks import MAX_PRELOAD
    from rvsim.geometry.layout import roller_pitch_diameter
    from rvsim.parameters.fe_sizes import DISC_COARSEST, DISC_FINEST

    assert public is roller_pitch_diameter
    assert roller_pitch_diameter(0.01, 0.003) == 0.023          # 2 r + d, exactly
    assert MAX_PRELOAD == 0.02e-3
    assert (DISC_FINEST, DISC_COARSEST) == (0.25, 8.0)


def test_too_much_preload_is_still_refused_by_validate():
    bad = with_values(RV40E, {"bearings.arm_needles": True}, check=False)
    bad = dataclasses.replace(bad, bearings=dataclasses.replace(bad.bearings,
                                                                needle_clearance=-0.03e-3))
    with pytest.raises(ParameterError, match="bearings.needle_clearance"):
        validate(bad)


# --- step 5 and 6 ---------------------------------------------------------------------------

def test_html_building_blocks():
    import pandas as pd

    from rvsim import html, report

    assert report._page is html.page and report._table is html.table
    frame = pd.DataFrame({"x": [1.23456789, math.nan], "name": ["<a>", "b"]},
                         index=pd.Index(["r1", "r2"], name="row"))
    text = html.table(frame, highlight={"r2"})
    assert "<td>1.235</td>" in text                  # 4 significant digits
    assert "&lt;a&gt;" in text and "<a>" not in text  # escaped
    assert '<tr class="sig"><td class="l">r2</td><td></td>' in text   # NaN empty, marked
    page = html.page("a & b", ["<p>x</p>"])
    assert page.startswith("<!DOCTYPE html>") and "<title>a &amp; b</title>" in page
    assert html.CSS in page


def test_a_report_into_a_missing_folder_is_refused(tmp_path):
    from rvsim.html import target

    assert target(tmp_path / "r.html") == tmp_path / "r.html"
    with pytest.raises(InputFileError, match="does not exist"):
        target(tmp_path / "missing" / "r.html")


def test_figure_names_are_one_object_each():
    from rvsim import _matplotlib, plots
    from rvsim.analysis import figures, interactions

    assert plots.pyplot is plots._pyplot is _matplotlib.pyplot
    assert plots.plain is _matplotlib.plain
    assert plots.main_effects_plot is figures.main_effects_plot
    assert interactions.interaction_plots is figures.interaction_plots
    assert _matplotlib.plain("x$_$") == r"x\$_\$"


# --- step 7 ---------------------------------------------------------------------------------

def _stand_in(reducer, *, time_step, hysteresis, positions, scheme):
    return {"status": "ok", "metrics": {"args": [reducer.name, time_step, hysteresis,
                                                  positions, scheme]}}


def test_an_evaluator_gets_every_option():
    from rvsim.doe.runner import evaluate

    outcome = evaluate(RV40E, 2e-5, _stand_in, True, 90, "implicit-bearings")
    assert outcome["metrics"]["args"] == [RV40E.name, 2e-5, True, 90, "implicit-bearings"]


def test_registered_evaluators_and_an_unknown_name(monkeypatch):
    from rvsim.doe import engines
    from rvsim.doe.runner import evaluate

    import rvsim.tolerance.engine as tolerance_engine      # registers "tolerance"

    assert engines.EVALUATORS["dynamic"] is engines.evaluate_dynamic
    assert engines.EVALUATORS["tolerance"] is tolerance_engine.evaluate_run
    outcome = evaluate(RV40E, 2e-5, engine="quasistatic")
    assert outcome == {"status": "error", "metrics": {}, "error": "ParameterError: unknown "
                       "engine 'quasistatic' (dynamic, quasi-static or tolerance)"}
    monkeypatch.setitem(engines.EVALUATORS, "stand-in", _stand_in)
    assert evaluate(RV40E, 1e-5, "stand-in")["metrics"]["args"][1] == 1e-5


def test_the_quasi_static_evaluator_forwards_hysteresis(monkeypatch):
    from rvsim.doe import engines

    seen = []
    monkeypatch.setattr(engines, "evaluate_quasi_static",
                        lambda r, *, hysteresis=False, positions=360:
                        seen.append((hysteresis, positions)) or {})
    engines.EVALUATORS["quasi-static"](RV40E, time_step=1.0, hysteresis=True, positions=7,
                                       scheme="explicit")
    assert seen == [(True, 7)]


def test_tolerance_evaluator_is_picklable_by_reference():
    import pickle

    from rvsim.tolerance.engine import evaluate_run

    assert pickle.loads(pickle.dumps(evaluate_run)) is evaluate_run


def test_study_files_are_read_by_one_reader(tmp_path):
    from rvsim._files import read_study_toml
    from rvsim.doe.study import load_study
    from rvsim.tolerance.spec import load_tolerance_study

    bad = tmp_path / "s.toml"
    bad.mkdir()                       # a folder: the message names what was expected
    messages = []
    for reader in (read_study_toml, load_study, load_tolerance_study):
        with pytest.raises(InputFileError) as info:
            reader(bad)
        messages.append(str(info.value))
    assert set(messages) == {f"{bad}: is a folder, not a TOML study file"}


def test_executors_are_public():
    from rvsim.doe import runner

    for name in ("run_local", "run_dask", "check_scheduler"):
        assert name in runner.__all__ and callable(getattr(runner, name))
    with pytest.raises(InputFileError, match="is not a scheduler address"):
        runner.check_scheduler("http://host/path")


# --- step 8 ---------------------------------------------------------------------------------

def test_pin_centres_have_one_home():
    from rvsim import geometry
    from rvsim.geometry import cycloid, deviations

    assert cycloid.pin_centres is deviations.pin_centres is geometry.pin_centres


# --- the import test catches a return -------------------------------------------------------

@pytest.fixture(scope="module")
def imports():
    """The import graph of src/rvsim, read once (each test edits its own copy)."""
    graph = layers.read_imports()
    return lambda: dict(graph)


@pytest.mark.parametrize("edge", [
    ("rvsim.parameters._io", "rvsim.geometry.cycloid"),    # step 4
    ("rvsim.testrig.report", "rvsim.report"),              # step 5
    ("rvsim.analysis.interactions", "rvsim.plots"),        # step 6
    ("rvsim.fe.mesh", "rvsim.doe._workers"),               # step 7
])
def test_an_upward_import_coming_back_fails(edge, imports):
    graph = imports()
    assert edge not in layers.upward_imports(graph)
    graph[edge[0]] = graph[edge[0]] | {edge[1]}
    assert edge in layers.upward_imports(graph) - layers.ALLOWED_UPWARD


@pytest.mark.parametrize("edge", [
    ("rvsim.doe.runner", "rvsim.tolerance.engine"),        # step 7
    ("rvsim.geometry.deviations", "rvsim.geometry.cycloid"),   # step 8
])
def test_a_circle_coming_back_fails(edge, imports):
    graph = imports()
    assert not _circles(graph)
    graph[edge[0]] = graph[edge[0]] | {edge[1]}
    assert _circles(graph)


def _circles(graph) -> list:
    """The module circles and the package circles the import test looks for."""
    kept = layers._without_allowed(graph)
    packages: dict[str, set[str]] = {}
    for a, targets in kept.items():
        for b in targets:
            if layers.unit(a) != layers.unit(b) and "rvsim" not in (layers.unit(a),
                                                                   layers.unit(b)):
                packages.setdefault(layers.unit(a), set()).add(layers.unit(b))
    return layers.cycles(kept) + layers.cycles(packages)


def test_the_allow_lists_hold_the_one_documented_exception():
    assert layers.ALLOWED_UPWARD == {("rvsim.parameters._io", "rvsim.geometry.checks")}
    assert layers.ALLOWED_CYCLE == set()
