"""rvsim._files: outputs written whole or not at all."""

import pytest

from rvsim._files import atomic_outputs


def test_outputs_move_into_place_together(tmp_path):
    a, b = tmp_path / "a.npz", tmp_path / "b.html"
    with atomic_outputs(a, None, b) as (ta, none, tb):
        assert none is None and ta.parent == tmp_path and ta.suffix == ".npz"
        ta.write_text("A")
        tb.write_text("B")
        assert not a.exists() and not b.exists()
    assert a.read_text() == "A" and b.read_text() == "B"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.npz", "b.html"]


def test_an_interrupted_pair_leaves_the_old_files_and_no_temporary_one(tmp_path):
    a, b = tmp_path / "a.npz", tmp_path / "b.html"
    a.write_text("old")
    with pytest.raises(KeyboardInterrupt):
        with atomic_outputs(a, b) as (ta, tb):
            ta.write_text("new")
            raise KeyboardInterrupt
    assert a.read_text() == "old" and not b.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["a.npz"]


def test_outputs_get_the_permissions_of_a_plain_open(tmp_path):
    """mkstemp makes 0600 files; a file written straight into the temporary path (calibrate's
    fitted.toml) kept them (a review found it)."""
    import os

    umask = os.umask(0o022)
    try:
        with atomic_outputs(tmp_path / "a.toml") as (tmp,):
            tmp.write_text("x = 1\n")
    finally:
        os.umask(umask)
    assert (tmp_path / "a.toml").stat().st_mode & 0o777 == 0o644
