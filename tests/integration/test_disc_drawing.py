"""The whole disc in the DXF and SVG drawing (issue 34 item 6): the profile and every hole on
its own layer, read back and checked against the parameters, and the refusals of bad output.

Hand calculation of the RV-40E disc (docs/parameters.md): central bore 20 mm; crank holes of
radius eccentric + arm bushing wall = 12.5 + 3 = 15.5 mm at angles 0 and pi on the crank
circle (the involute stage's centre distance); two pillar holes of 11 mm at pi/2 and 3 pi/2
on the same circle.  Cycloid drive: the eccentric's hole in the centre and 8
output-pin holes of radius r_w + a + clearance = 5 + 1.5 + 0 mm on R_w = 36 mm; the
eccentric's hole there is 15 + 3 = 18 mm (its set's crank), its disc_bore_radius not a part.
"""

from __future__ import annotations

import math
import os
from xml.etree import ElementTree as ET

import ezdxf
import numpy as np
import pytest

import rvsim
from rvsim.geometry import profile_of
from rvsim.geometry.export import export_profile
from rvsim.geometry.involute import gear_geometry
from rvsim.parameters import RV40E

SVG = "{http://www.w3.org/2000/svg}"
POINTS = 3900          # 100 per tooth: fast, and the profile is compared point by point


def _cycloid_drive():
    from rvsim.parameters._io import BUILT_IN_SETS

    return BUILT_IN_SETS["cycloid-drive"]


def rv_expected() -> dict[str, np.ndarray]:
    """The RV-40E disc's holes by hand, rows x, y, radius [mm]."""
    crank = gear_geometry(RV40E).centre_distance * 1e3
    assert crank == pytest.approx(44.954828249, abs=1e-9)      # printed by the SVG, checked
    hole = 12.5 + 3.0
    pillars = [0.5 * math.pi, 1.5 * math.pi]
    return {"BORE": np.array([[0.0, 0.0, 20.0]]),
            "CRANK_HOLES": np.array([[crank, 0.0, hole], [-crank, 0.0, hole]]),
            "PILLAR_HOLES": np.array([[crank * math.cos(a), crank * math.sin(a), 11.0]
                                      for a in pillars])}


def dxf_circles(doc, layer: str) -> np.ndarray:
    return np.array([(c.dxf.center.x, c.dxf.center.y, c.dxf.radius)
                     for c in doc.modelspace().query(f'CIRCLE[layer=="{layer}"]')])


def dxf_profile(doc) -> np.ndarray:
    lines = doc.modelspace().query('LWPOLYLINE[layer=="CYCLOID_PROFILE"]')
    assert len(lines) == 1 and lines[0].closed
    return np.array([(x, y) for x, y, *_ in lines[0].get_points()])


def test_rv_dxf_holds_every_hole_on_its_layer(tmp_path, cli):
    out = tmp_path / "disc.dxf"
    res = cli("profile", "--out", str(out), "--points", str(POINTS))
    assert res.code == 0, res.err
    assert "1 bore, 2 crank holes, 2 pillar holes" in res.out
    doc = ezdxf.readfile(out)
    assert not doc.audit().has_errors
    assert doc.header["$INSUNITS"] == 4
    assert {layer.dxf.name for layer in doc.layers} >= {
        "CYCLOID_PROFILE", "BORE", "CRANK_HOLES", "PILLAR_HOLES", "CONSTRUCTION"}
    for layer, expected in rv_expected().items():
        got = dxf_circles(doc, layer)
        assert got.shape == expected.shape, layer
        assert np.max(np.abs(got - expected)) < 1e-9, layer
    # the construction layer as before: the pin circle (82 mm) and the centre
    assert dxf_circles(doc, "CONSTRUCTION")[:, 2].tolist() == [82.0]
    assert len(doc.modelspace().query("CIRCLE")) == 6
    profile = dxf_profile(doc)
    assert np.max(np.abs(profile - profile_of(RV40E).points(POINTS) * 1e3)) < 1e-9


def test_every_hole_lies_inside_the_profile_and_clear_of_the_others(tmp_path):
    """What a CAD user would check first: the parts of the drawing do not cut each other."""
    from matplotlib.path import Path as Polygon

    out = tmp_path / "disc.dxf"
    export_profile(RV40E, out, points=POINTS)
    doc = ezdxf.readfile(out)
    holes = np.vstack([dxf_circles(doc, layer)
                       for layer in ("BORE", "CRANK_HOLES", "PILLAR_HOLES")])
    outline = Polygon(dxf_profile(doc))
    for x, y, r in holes:
        t = np.linspace(0.0, 2.0 * math.pi, 360)
        assert outline.contains_points(np.column_stack([x + r * np.cos(t),
                                                        y + r * np.sin(t)])).all()
    for i in range(len(holes)):
        for j in range(i + 1, len(holes)):
            gap = math.dist(holes[i, :2], holes[j, :2]) - holes[i, 2] - holes[j, 2]
            assert gap > 0.0


def test_holes_are_where_the_fe_disc_meshes_them():
    """Two codes place the holes (the FE disc's own expressions and the layout functions the
    drawing uses): they must agree to the last bit of a millimetre's billionth."""
    pytest.importorskip("skfem")
    from rvsim.fe.disc import disc_geometry
    from rvsim.geometry.layout import disc_holes

    g = disc_geometry(RV40E, 0)
    holes = disc_holes(RV40E)
    assert np.max(np.abs(np.array(g["crank_holes"]) - holes["crank_holes"])) < 1e-12
    assert np.max(np.abs(np.array(g["pillars"]) - holes["pillar_holes"])) < 1e-12
    assert holes["bore"].tolist() == [[0.0, 0.0, g["bore"]]]


def test_disc_two_is_cut_half_a_pitch_turned(tmp_path):
    """Disc 2's teeth have the phase -pi/zc (geometry.cycloid); its holes are disc 1's.  With
    39 teeth and 2 pillar holes it is disc 1 turned half a turn."""
    one, two = tmp_path / "one.dxf", tmp_path / "two.dxf"
    s1 = export_profile(RV40E, one, points=POINTS)
    s2 = export_profile(RV40E, two, points=POINTS, disc=1)
    assert (s1["disc"], s2["disc"]) == (1, 2)
    d1, d2 = ezdxf.readfile(one), ezdxf.readfile(two)
    for layer in ("BORE", "CRANK_HOLES", "PILLAR_HOLES"):
        assert np.array_equal(dxf_circles(d1, layer), dxf_circles(d2, layer))
    turn = -math.pi / 39
    rot = np.array([[math.cos(turn), math.sin(turn)], [-math.sin(turn), math.cos(turn)]])
    p1, p2 = dxf_profile(d1), dxf_profile(d2)
    assert np.max(np.abs(p2 - p1 @ rot)) < 1e-9
    # disc 1 turned half a turn (39 teeth: pi = -pi/39 + 20 pitches) is disc 2 as a curve:
    # each vertex of disc 2 on the (dense) curve of disc 1 turned (measured 6e-14 mm: the
    # vertices coincide); disc 1 unturned is 3.0 mm out, a tooth tip where a gap is
    dense = profile_of(RV40E).points(8 * POINTS, math.pi) * 1e3
    assert distance_to_curve(p2, dense) < 1e-9
    assert distance_to_curve(p1, dense) == pytest.approx(3.0, abs=1e-3)


def distance_to_curve(points: np.ndarray, curve: np.ndarray) -> float:
    """Largest distance from ``points`` to the closed polyline ``curve`` (its segments at
    each point's nearest vertex)."""
    from scipy.spatial import cKDTree

    nearest = cKDTree(curve).query(points)[1]
    worst = 0.0
    for step in (-1, 1):
        a, b = curve[nearest], curve[(nearest + step) % len(curve)]
        d = b - a
        t = np.clip(np.einsum("ij,ij->i", points - a, d) / np.einsum("ij,ij->i", d, d), 0, 1)
        gap = np.linalg.norm(points - (a + t[:, None] * d), axis=1)
        worst = gap if step == -1 else np.minimum(worst, gap)
    return float(np.max(worst))


def test_cycloid_drive_draws_its_own_holes(tmp_path, cli):
    out = tmp_path / "drive.dxf"
    res = cli("profile", "--params", "cycloid-drive", "--out", str(out),
              "--points", str(29 * 100))
    assert res.code == 0, res.err
    doc = ezdxf.readfile(out)
    assert not dxf_circles(doc, "CRANK_HOLES").size and not dxf_circles(doc, "PILLAR_HOLES").size
    assert dxf_circles(doc, "BORE").tolist() == [[0.0, 0.0, 18.0]]
    pins = dxf_circles(doc, "OUTPUT_PIN_HOLES")
    angles = 2.0 * math.pi * np.arange(8) / 8
    expected = np.column_stack([36.0 * np.cos(angles), 36.0 * np.sin(angles),
                                np.full(8, 5.0 + 1.5)])
    assert pins.shape == (8, 3) and np.max(np.abs(pins - expected)) < 1e-9


@pytest.mark.parametrize("count", [0, 3])
def test_pillar_holes_as_many_as_the_set_has(tmp_path, count):
    """No pillar holes: no layer; three: evenly spaced from a quarter turn (pillar_angles)."""
    reducer = rvsim.with_values(RV40E, {"cycloid.pillar_hole_count": count,
                                        "cycloid.pillar_hole_radius": 6.0})
    out = tmp_path / "disc.dxf"
    summary = export_profile(reducer, out, points=POINTS)
    doc = ezdxf.readfile(out)
    layers = {layer.dxf.name for layer in doc.layers}
    assert ("PILLAR_HOLES" in layers) == (count > 0) and summary["holes"].get(
        "PILLAR_HOLES", 0) == count
    crank = gear_geometry(RV40E).centre_distance * 1e3
    angles = 0.5 * math.pi + 2.0 * math.pi * np.arange(count) / 3
    expected = np.column_stack([crank * np.cos(angles), crank * np.sin(angles),
                                np.full(count, 6.0)])
    got = dxf_circles(doc, "PILLAR_HOLES").reshape(-1, 3)
    assert got.shape == expected.shape and np.all(np.abs(got - expected) < 1e-9)


def svg_layers(path) -> dict[str, ET.Element]:
    root = ET.parse(path).getroot()
    assert root.tag == f"{SVG}svg"
    return {g.get("id"): g for g in root.iter(f"{SVG}g") if g.get("id")}


def test_svg_holds_the_same_disc(tmp_path, cli):
    out = tmp_path / "disc.svg"
    res = cli("profile", "--out", str(out), "--points", str(POINTS))
    assert res.code == 0, res.err
    root = ET.parse(out).getroot()
    assert root.get("width").endswith("mm") and root.get("height").endswith("mm")
    x0, y0, w, h = map(float, root.get("viewBox").split())
    assert w == pytest.approx(float(root.get("width")[:-2]), abs=1e-6)   # 1 unit = 1 mm
    layers = svg_layers(out)
    assert list(layers) == ["CYCLOID_PROFILE", "BORE", "CRANK_HOLES", "PILLAR_HOLES"]
    paths = layers["CYCLOID_PROFILE"].findall(f"{SVG}path")
    assert len(paths) == 1
    d = paths[0].get("d").split()
    assert d[0] == "M" and d[-1] == "Z"                                  # closed
    xy = np.array([[float(v) for v in p.split(",")] for p in d[1:-1]])
    assert np.max(np.abs(xy - profile_of(RV40E).points(POINTS) * 1e3)) < 1e-9
    for layer, expected in rv_expected().items():
        circles = np.array([[float(c.get(k)) for k in ("cx", "cy", "r")]
                            for c in layers[layer].findall(f"{SVG}circle")])
        assert circles.shape == expected.shape
        assert np.max(np.abs(circles - expected)) < 1e-9
    # the whole disc fits the view (1 mm margin)
    assert -x0 == pytest.approx(np.max(np.abs(xy)) + 1.0, abs=1e-6) and x0 == y0 and w == h


def test_svg_of_the_cycloid_drive(tmp_path):
    out = tmp_path / "drive.svg"
    summary = export_profile(_cycloid_drive(), out, points=2900, disc=1)
    assert summary["holes"] == {"BORE": 1, "OUTPUT_PIN_HOLES": 8}
    layers = svg_layers(out)
    assert len(layers["OUTPUT_PIN_HOLES"].findall(f"{SVG}circle")) == 8
    assert "CRANK_HOLES" not in layers


@pytest.mark.parametrize("name,words", [
    ("disc.png", "unsupported profile format '.png'"),
    ("disc.svgz", "unsupported profile format '.svgz'"),
    ("missing/disc.svg", "does not exist"),
    ("sub", "is a folder"),
])
def test_bad_output_is_one_line_and_no_file(tmp_path, cli, name, words):
    (tmp_path / "sub").mkdir()
    res = cli("profile", "--out", str(tmp_path / name), "--points", str(POINTS))
    assert res.code == 2
    assert res.err.count("\n") == 1 and res.err.startswith("rvsim: error: ")
    assert words in res.err
    assert sorted(os.listdir(tmp_path)) == ["sub"] and not os.listdir(tmp_path / "sub")


@pytest.mark.parametrize("args,words", [
    (("--disc", "3"), "invalid choice: 3"),
    (("--disc", "2", "--params", "cycloid-drive", "--set", "layout.disc_count=1"),
     "'--disc': the reducer has 1 disc"),
])
def test_a_disc_that_is_not_there_is_refused(tmp_path, cli, args, words):
    res = cli("profile", "--out", str(tmp_path / "d.svg"), *args)
    assert res.code == 2 and res.err.count("\n") == 1 and words in res.err
    assert not os.listdir(tmp_path)


def test_a_failed_write_leaves_no_file(tmp_path, monkeypatch):
    """The atomic writer: a drawing that fails half-written leaves the folder as it was."""
    from rvsim.geometry import export

    def half(tmp, layers):
        tmp.write_text("<svg")
        raise OSError("disk full")

    monkeypatch.setattr(export, "_write_svg", half)
    with pytest.raises(OSError, match="disk full"):
        export_profile(RV40E, tmp_path / "disc.svg", points=POINTS)
    assert not os.listdir(tmp_path)


def test_disc_index_is_checked():
    with pytest.raises(rvsim.errors.ParameterError, match="must be 0 or 1"):
        export_profile(RV40E, "x.svg", points=POINTS, disc=2)
