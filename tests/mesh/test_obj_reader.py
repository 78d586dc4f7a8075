"""The OBJ reader's two ways of reading 'f' lines: at once (positive indices, the usual form) and one by one
(any form); they must give the same faces, texture corners, warnings and errors."""
import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from geoimg import MeshFileError, load_mesh
from geoimg.mesh import _obj
from geoimg.mesh._mesh import pad_faces

from helpers import BUNDLED


def _one_by_one(rows):
    faces, face_vt, sizes = _obj._corners_one_by_one(rows, [10**6] * len(rows), [10**6] * len(rows))
    return pad_faces(faces), pad_faces(face_vt), sizes


@pytest.mark.parametrize("text", [
    "1 2 3", "1 2 3 4\n5 6 7", "1/1 2/2 3/3", "1/1/1 2/2/2 3/3/3 4/4/4", "1//1 2//2 3//3", "1/4/ 2/5/ 3/6/",
    "1/1 2 3//7\n4/2/9 5 6 7/3", "10 200 3000\n7 8", "1", "12345678901 2 3", "1000000000000000000 2 3",
    "1/2/3 4/5/6 7/8/9\n1/2/3 4/5 6/7/8", "4/7/1 5/8/2 6/9/3 7/10/4",
])
def test_both_ways_read_the_same_corners(text):
    rows = [line.split() for line in text.splitlines()]
    fast = _obj._corners_at_once(rows)
    assert fast is not None
    for got, want in zip(fast, _one_by_one(rows)):
        assert got.dtype == np.int64 and np.array_equal(got, want)


@pytest.mark.parametrize("text", [
    "1 2 -1", "1/1 2/-1 3/3", "0 1 2", "1/0 2/1 3/2", "1/1/1/1 2 3", "1 2 x", "1/x 2 3", "1.0 2 3", "+1 2 3",
    "1 2 99999999999999999999", "١ 2 3", "1/2/x 2 3",
])
def test_other_forms_are_left_to_the_reader_one_by_one(text):
    assert _obj._corners_at_once([line.split() for line in text.splitlines()]) is None


def test_no_face_lines_are_left_to_the_reader_one_by_one():
    assert _obj._corners_at_once([]) is None


def _read_both_ways(path, monkeypatch):
    """(mesh or error, warnings) read at once and read one by one."""
    out = []
    for fast in (True, False):
        with monkeypatch.context() as m:
            if not fast:
                m.setattr(_obj, "_corners_at_once", lambda rows: None)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    got = load_mesh(path)
                except MeshFileError as e:
                    got = str(e)
        out.append((got, [str(w.message) for w in caught]))
    return out


def _same(a, b):
    if isinstance(a, str) or isinstance(b, str):
        return a == b
    fields = ("vertices", "faces", "uv", "face_uv", "colors")
    return all((getattr(a, f) is None and getattr(b, f) is None) or np.array_equal(getattr(a, f), getattr(b, f))
               for f in fields)


@pytest.mark.parametrize("path", sorted(p for folder in BUNDLED for p in folder.rglob("*.obj")), ids=lambda p: p.name)
def test_bundled_files_read_the_same_both_ways(path, monkeypatch):
    (fast, fast_warned), (slow, slow_warned) = _read_both_ways(path, monkeypatch)
    assert _same(fast, slow) and fast_warned == slow_warned


@settings(max_examples=60, deadline=None)
@given(lines=st.lists(st.sampled_from([
    "v 0 0 0", "v 1 0 0", "v 0 1 0 0.5 0.5 0.5", "vt 0 0", "vt 1 1", "f 1 2 3", "f 1/1 2/2 3/1", "f -1 -2 -3",
    "f 1//1 2//1 3//1", "f 1 2", "f 0 1 2", "f 1/1/1 2/2/2 3/2/1 4/1/1", "f 1 2 3 4 5", "  f 2 3 4", "f 1 2 \\",
    " 3", "g part", "f 4/1 5 6/2", "f 9 10 11"]), max_size=14))
def test_any_file_reads_the_same_both_ways(tmp_path_factory, lines):
    path = tmp_path_factory.mktemp("obj") / "m.obj"
    path.write_text("\n".join(lines) + "\n")
    with pytest.MonkeyPatch.context() as monkeypatch:
        (fast, fast_warned), (slow, slow_warned) = _read_both_ways(path, monkeypatch)
    assert _same(fast, slow), (fast, slow)
    assert [w.replace(str(path), "") for w in fast_warned] == [w.replace(str(path), "") for w in slow_warned]
