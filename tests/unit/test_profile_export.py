"""Profile export: DXF written by ezdxf and read back, CSV points in millimetres."""

import ezdxf
import numpy as np
import pytest

from rvsim.geometry import profile_of
from rvsim.geometry.export import export_profile
from rvsim.parameters import RV40E


def test_dxf_reads_back_as_the_profile(tmp_path, cli):
    out = tmp_path / "disc.dxf"
    res = cli("profile", "--out", str(out), "--points", "7200", "--set", "I=0.016")
    assert res.code == 0, res.err
    doc = ezdxf.readfile(out)
    assert doc.header["$INSUNITS"] == 4
    polylines = doc.modelspace().query('LWPOLYLINE[layer=="CYCLOID_PROFILE"]')
    assert len(polylines) == 1 and polylines[0].closed
    pts = np.array([(x, y) for x, y, *_ in polylines[0].get_points()])
    assert len(pts) == 7200
    expected = profile_of(__import__("rvsim").with_values(RV40E, {"I": 0.016})).points(7200) * 1e3
    assert np.max(np.abs(pts - expected)) < 1e-9


def test_csv_export(tmp_path):
    out = tmp_path / "disc.csv"
    summary = export_profile(RV40E, out, points=3900)
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape == (3900, 2)
    assert out.read_text().startswith("x_mm,y_mm")
    assert np.hypot(data[:, 0], data[:, 1]).max() == pytest.approx(82 + 1.5 - 3, abs=1e-6)
    assert summary["chordal_deviation_mm"] < 0.05


def test_chordal_deviation_falls_with_points():
    from rvsim.geometry.export import chordal_deviation

    assert chordal_deviation(RV40E, 36000) < chordal_deviation(RV40E, 3600) / 50
