"""Suggested landmarks: the extremities of a shape whose tips are known, the refusals, the command."""
import numpy as np
import pytest

import geoimg
from geoimg.cli import main
from geoimg.errors import InputError, MeshError
from geoimg.mesh import average_geodesic_distance, suggest_landmarks

import meshes
from helpers import data_file

AXES = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)


def star() -> geoimg.Mesh:
    """A sphere with a spike along each of the six axis directions (tips at distance 2.5)."""
    ball = meshes.icosphere(4)
    v = ball.vertices
    near = (v @ AXES.T).max(axis=1)
    radius = 1.0 + 1.5 * np.clip((near - 0.85) / 0.15, 0, 1) ** 1.5
    return geoimg.Mesh(v * radius[:, None], ball.faces)


def test_the_tips_of_a_star_are_its_six_landmarks_and_nothing_else():
    m = star()
    index = suggest_landmarks(m, 10)
    assert len(index) == 6                                 # six extremities, no slope or middle point
    directions = m.vertices[index] / np.linalg.norm(m.vertices[index], axis=1, keepdims=True)
    assert sorted(np.argmax(directions @ AXES.T, axis=1).tolist()) == list(range(6))
    assert np.all(np.linalg.norm(m.vertices[index], axis=1) > 2.4)
    assert len(suggest_landmarks(m, 3)) == 3


def test_a_finger_has_its_two_ends_as_landmarks():
    f = meshes.finger()                         # open at z = 0, its rounded tip at z = 3.25
    d = average_geodesic_distance(f)
    z = f.vertices[:, 2]
    assert np.nanmin(d[(z > 1.4) & (z < 1.9)]) < np.nanmin(d[z > 3.2]) and np.nanmax(d[(z > 1.4) & (z < 1.9)]) < \
        np.nanmax(d[z < 0.01])                  # smallest in the middle, largest at the ends
    ends = sorted(z[suggest_landmarks(f, 2)].tolist())
    assert ends[0] < 0.01 and ends[1] > 3.2


def test_spread_fills_up_with_the_farthest_points_after_the_extremities():
    m = star()
    index = suggest_landmarks(m, 10, spread=True)
    assert len(index) == 10 and len(set(index.tolist())) == 10
    np.testing.assert_array_equal(index[:6], suggest_landmarks(m, 10))      # the six tips first, as they were
    from geoimg.mesh._landmarks import _edge_graph
    from scipy.sparse.csgraph import dijkstra
    d = dijkstra(_edge_graph(m), indices=index)                          # (10, N) edge-path distances
    for k in range(6, 10):       # each further point the farthest from all those before it
        nearest = d[:k].min(axis=0)
        assert nearest[index[k]] == pytest.approx(nearest.max())
    assert len(suggest_landmarks(m, 3, spread=True)) == 3           # enough extremities: spread adds nothing
    tiny = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    assert sorted(suggest_landmarks(tiny, 9, spread=True).tolist()) == [0, 1, 2, 3]     # at most every vertex


def test_several_pieces_and_bad_counts_are_refused():
    two = meshes.three_pieces()
    with pytest.raises(MeshError, match="separate pieces"):
        suggest_landmarks(two)
    for count in (0, -1, 2.5, True):
        with pytest.raises(InputError, match="count"):
            suggest_landmarks(star(), count)
    with pytest.raises(InputError, match="radius"):
        suggest_landmarks(star(), 3, radius=1.5)


def test_the_command_writes_the_points_and_a_picture_or_nothing(tmp_path, capsys):
    pytest.importorskip("moderngl")
    obj = meshes.write(star(), tmp_path / "star.obj")
    csv, png = tmp_path / "p.csv", tmp_path / "p.png"
    assert main(["landmarks", obj, "-o", str(csv), "--picture", str(png), "--width", "80", "--height", "60"]) == 0
    rows = csv.read_text().splitlines()
    assert rows[0] == "index,x,y,z" and len(rows) == 7 and png.is_file()
    assert main(["landmarks", obj, "-o", str(csv), "--count", "9", "--spread", "--force"]) == 0
    assert len(csv.read_text().splitlines()) == 10 and "then spread" in capsys.readouterr().out
    index = int(rows[1].split(",")[0])
    assert np.allclose([float(x) for x in rows[1].split(",")[1:]], geoimg.load_mesh(obj).vertices[index])
    capsys.readouterr()
    assert main(["landmarks", str(data_file("spot.obj")), "-o", str(tmp_path / "x.txt")]) == 2
    assert main(["landmarks", meshes.write(meshes.three_pieces(), tmp_path / "3.obj"), "-o",
                 str(tmp_path / "y.csv")]) == 2
    assert "separate pieces" in capsys.readouterr().err and not (tmp_path / "y.csv").exists()
