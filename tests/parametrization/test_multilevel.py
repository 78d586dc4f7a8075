"""Sphere maps of large meshes through a decimated copy: the start, the untangling of folds, the fallbacks."""
import numpy as np
import pytest

import geoimg
from geoimg.parametrization import _multilevel as ml
from geoimg.parametrization import _sphere
from geoimg.parametrization._orientation import chord_orientation
from geoimg.parametrization._sphere import MULTILEVEL_STEPS, MULTILEVEL_TRIANGLES, sphere_coords

import meshes


def spiky(height=3.0, width=0.004):
    """A sphere of 20,480 triangles with two long thin spikes (radial, so it stays one genus-0 surface):
    its conformal map squeezes the spikes to a few hundredths of their share."""
    ball = meshes.icosphere(5)
    d = ball.vertices / np.linalg.norm(ball.vertices, axis=1, keepdims=True)
    r = 1.0 + sum(height * np.exp(-(1 - d @ (a / np.linalg.norm(a))) / width)
                  for a in (np.array([0, 0, 1.0]), np.array([1, 1, 0.0])))
    return geoimg.Mesh(d * r[:, None], ball.faces)


@pytest.fixture(scope="module")
def spikes():
    mesh = spiky()
    assert mesh.n_faces >= MULTILEVEL_TRIANGLES
    return mesh


@pytest.mark.slow
def test_a_large_mesh_is_mapped_through_a_coarse_copy(spikes):
    before = spikes.vertices.copy()
    s, info = sphere_coords(spikes)
    assert info["start"] == "multilevel" and info["multilevel"] == "used" and info["stages"] == ["multilevel"]
    # at most MULTILEVEL_STEPS, not swept
    assert info["coarse_triangles"] <= ml.COARSE_TRIANGLES and info["balance_steps"] <= MULTILEVEL_STEPS
    assert info["flipped_triangles"] == 0 and (chord_orientation(s, spikes.faces) > 0).all()
    assert np.allclose(np.linalg.norm(s, axis=1), 1) and np.array_equal(spikes.vertices, before)
    # the same number of fine steps from the conformal map leaves the spikes squeezed (measured: 0.41
    # against 2.03 log-RMS, 0.20 against 0.009 for the most squeezed triangle)
    _, direct = sphere_coords(spikes, steps=MULTILEVEL_STEPS)
    assert direct["start"] in ("conformal", "mean-value")
    assert info["area_log_rms"] < 0.5 * direct["area_log_rms"]
    assert info["area_ratio_min"] > 2 * direct["area_ratio_min"]


def test_explicit_steps_and_small_meshes_map_directly():
    mesh = meshes.icosphere(3, 0.2)
    assert sphere_coords(mesh)[1]["start"] != "multilevel"              # 1,280 triangles
    assert "multilevel" not in sphere_coords(mesh, steps=3)[1]


def test_the_fallback_when_the_coarse_map_folds(monkeypatch):
    mesh = meshes.icosphere(3, 0.2)
    direct, direct_info = sphere_coords(mesh)
    monkeypatch.setattr(_sphere, "MULTILEVEL_TRIANGLES", 1000)             # 1,280 triangles take the coarse path
    monkeypatch.setattr(_sphere, "_decimated_map", lambda beta: (lambda U, G: None))
    heard: list = []
    s, info = sphere_coords(mesh, progress=heard.append)
    assert info["multilevel"] == "the coarse mesh's direct maps fold" and info["start"] in ("conformal", "mean-value")
    assert np.array_equal(s, direct) and info["balance_steps"] == direct_info["balance_steps"]   # the direct path
    # every stage says so (a 100k-face mesh was silent for 20 s between the coarse copy and the balancing)
    assert heard[:3] == ["1280 triangles: mapping a coarse copy first",
                         f"coarse copy of {info['coarse_triangles']} triangles made; mapping it",
                         "no start from the coarse copy (the coarse mesh's direct maps fold): the direct maps"]


def test_multilevel_start_says_why_it_found_no_map(monkeypatch):
    ball = meshes.icosphere(3, 0.2)
    tris = np.asarray(ball.faces, np.int64)
    monkeypatch.setattr(ml, "decimate", lambda x, t, n: None)
    s, info = ml.multilevel_start(ball.vertices, tris, lambda U, G: U)
    assert s is None and info == {"multilevel": "decimation failed"}
    monkeypatch.undo()
    s, info = ml.multilevel_start(ball.vertices, tris, lambda U, G: None, coarse_triangles=300)
    assert s is None and info["multilevel"] == "the coarse mesh's direct maps fold" and info["coarse_triangles"] <= 300

    def mirrored(U, G):                               # every triangle inside out: nothing local opens that
        return U / np.linalg.norm(U, axis=1, keepdims=True) * [-1.0, 1.0, 1.0]
    s, info = ml.multilevel_start(ball.vertices, tris, mirrored, coarse_triangles=300)
    assert s is None and info["transfer_folds"] == len(tris) and "did not open" in info["multilevel"]


def _exact_ball(level=3):
    ball = meshes.icosphere(level)
    return ball.vertices / np.linalg.norm(ball.vertices, axis=1, keepdims=True), np.asarray(ball.faces, np.int64)


def test_untangle_opens_a_fold_and_moves_only_its_neighbourhood():
    s, tris = _exact_ball()
    a, b = tris[0, 0], tris[0, 1]
    folded = s.copy()
    folded[[a, b]] = s[[b, a]]                                   # two neighbours swapped: their triangles fold
    assert (chord_orientation(folded, tris) <= 0).any()
    out, steps, opened = ml.untangle(folded, tris, rings=2)
    assert opened and 0 < steps < ml.UNTANGLE_STEPS
    det = chord_orientation(out, tris)
    assert det.min() > ml.OPEN_SHARE * ml.UNTANGLE_TARGET * np.median(chord_orientation(s, tris)) * 0.5
    near = ml._rings(tris, np.array([a, b]), len(s), 2 + 1)
    assert np.array_equal(out[~near], folded[~near])          # the rest of the map stays bit for bit
    assert np.allclose(np.linalg.norm(out, axis=1), 1)
    same, steps, opened = ml.untangle(s, tris)                 # nothing folded: nothing to do
    assert opened and steps == 0 and same is s


def test_untangle_reports_what_it_cannot_open():
    s, tris = _exact_ball(2)
    out, steps, opened = ml.untangle(s * [-1.0, 1.0, 1.0], tris, rings=1, steps=5)   # the whole map inside out
    assert not opened and steps == 5


def test_transfer_reproduces_a_map_on_the_coarse_mesh_itself():
    s, tris = _exact_ball(3)
    U, G = ml.decimate(s, tris, 200)
    assert len(G) <= 200 and len(U) - len(G) / 2 == 2                 # closed, genus 0: V - E + F = 2
    coarse = U / np.linalg.norm(U, axis=1, keepdims=True)
    assert np.allclose(ml.transfer(U, U, G, coarse), coarse, atol=1e-12)   # its own vertices
    fine = ml.transfer(s, U, G, coarse)
    assert np.allclose(np.linalg.norm(fine, axis=1), 1) and np.abs(fine - s).max() < 0.2


def test_every_map_says_which_stages_ran():
    assert sphere_coords(meshes.icosphere(3, 0.2))[1]["stages"] == ["conformal"]


def test_folds_that_every_start_leaves_are_opened_last_or_said_to_stay():
    s, tris = _exact_ball()
    a, b = tris[0, 0], tris[0, 1]
    folded = s.copy()
    folded[[a, b]] = s[[b, a]]
    n = int(np.sum(chord_orientation(folded, tris) <= 0))
    out, said = _sphere._open_folds(folded, tris)
    assert (chord_orientation(out, tris) > 0).all() and said == f"untangled ({n} folded)"
    assert _sphere._open_folds(s, tris) == (s, None)
    inside_out = s * [-1.0, 1.0, 1.0]                                   # nothing local opens this
    out, said = _sphere._open_folds(inside_out, tris)
    assert out is inside_out and said == f"untangle failed ({len(tris)} folded)"
