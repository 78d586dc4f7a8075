"""The landmark warp of the sphere: landmarks meet their targets, no triangle of the carried points turns
over, a rotation alone is undone exactly by the rigid stage, bad landmarks are refused."""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from geoimg.errors import InputError
from geoimg.parametrization._orientation import chord_orientation
from geoimg.animation._warp import best_rotation, warp_sphere

import meshes


@pytest.fixture(scope="module")
def sphere():
    ball = meshes.icosphere(4)
    return ball.vertices / np.linalg.norm(ball.vertices, axis=1, keepdims=True), ball.faces


def _areas(x, t):
    a, b, c = x[t[:, 0]], x[t[:, 1]], x[t[:, 2]]
    return np.linalg.norm(np.cross(b - a, c - a), axis=1)


@pytest.mark.parametrize("seed", [0, 2, 3])
def test_landmarks_meet_their_targets_without_a_fold(sphere, seed):
    d, t = sphere
    rng = np.random.default_rng(seed)
    idx = rng.choice(len(d), 10, replace=False)
    goal = d[idx] @ Rotation.random(random_state=seed).as_matrix().T + rng.normal(0, 0.2, (10, 3))
    goal /= np.linalg.norm(goal, axis=1, keepdims=True)
    out, info = warp_sphere(d, t, d[idx], goal)
    assert info["met"] and info["residual"] < 1e-4 and info["folded"] == 0
    assert np.all(chord_orientation(out, t) > 0)
    for moved in (out[idx], info["landmarks"]):     # landmarks that are points of the set move with it
        assert np.arccos(np.clip((moved * goal).sum(axis=1), -1, 1)).max() < 1e-4
    np.testing.assert_allclose(np.linalg.norm(out, axis=1), 1.0, atol=1e-12)
    ratio = _areas(out, t) / _areas(d @ info["rotation"].T, t)
    assert np.exp(np.abs(np.log(ratio / ratio.mean())).max()) < 50      # smooth: no triangle crushed
    assert info["area_log_rms"] == pytest.approx(np.sqrt(np.average(np.log(ratio) ** 2, weights=_areas(d, t))),
                                                 rel=0.05)


def test_where_no_fold_free_step_is_left_it_stops_and_says_how_far(sphere):
    d, t = sphere
    rng = np.random.default_rng(1)                  # a configuration this flow cannot finish without a fold
    idx = rng.choice(len(d), 10, replace=False)
    goal = d[idx] @ Rotation.random(random_state=1).as_matrix().T + rng.normal(0, 0.2, (10, 3))
    out, info = warp_sphere(d, t, d[idx], goal / np.linalg.norm(goal, axis=1, keepdims=True))
    assert not info["met"] and info["residual"] > 1e-4 and info["folded"] == 0
    assert np.all(chord_orientation(out, t) > 0)


def test_a_rotation_alone_is_undone_by_the_rigid_stage(sphere):
    d, t = sphere
    idx = np.array([0, 5, 17, 40, 99])
    R = Rotation.from_rotvec([0.4, -1.1, 0.7]).as_matrix()
    out, info = warp_sphere(d, t, d[idx], d[idx] @ R.T)
    assert info["steps"] == 0 and np.allclose(info["rotation"], R, atol=1e-12)
    np.testing.assert_allclose(out, d @ R.T, atol=1e-12)
    np.testing.assert_allclose(best_rotation(d[idx], d[idx] @ R.T), R, atol=1e-12)


@pytest.mark.parametrize("sources, targets, message", [
    ([[1, 0, 0], [0, 1, 0]], np.eye(3), "one target per landmark"),
    ([[1, 0, 0], [0, 1, 0]], [[1, 0, 0], [0, 0, 0]], "targets: expected finite non-zero"),
    ([[1, 0, 0], [0, np.nan, 0]], np.eye(2, 3), "sources: expected finite non-zero"),
    ([[1, 0, 0], [2, 0, 0]], np.eye(2, 3), "sources: two landmarks are at the same place"),
    ([[1, 0, 0], [0, 1, 0]], [[1, 0, 0], [2, 0, 0]], "targets: two landmarks are at the same place"),
    (np.zeros((0, 3)), np.zeros((0, 3)), "one target per landmark"),
])
def test_bad_landmarks_are_refused(sphere, sources, targets, message):
    d, t = sphere
    with pytest.raises(InputError, match=message):
        warp_sphere(d, t, sources, targets)


def test_bad_points_are_refused(sphere):
    d, t = sphere
    with pytest.raises(InputError, match="points: expected finite"):
        warp_sphere(d[:, :2], t, d[:2], d[:2])
    with pytest.raises(InputError, match="tris: expected"):
        warp_sphere(d, t + len(d), d[:2], d[:2])
