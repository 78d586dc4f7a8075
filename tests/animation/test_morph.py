"""Morphs, glTF morph targets, frame sequences, the renderer and the morph/render commands."""

import numpy as np
import pygltflib as gl
import pytest
from scipy.spatial.transform import Rotation

import geoimg
from geoimg.animation import morph, save_frames, save_glb
from geoimg.cli import main
from geoimg.animation._morph import _octahedral_sampler
from geoimg.parametrization import grid_directions

from checks import check_shared_faces_morph
import meshes
from helpers import MOUNTAIN, data_file, load_data




@pytest.fixture(scope="module")
def spots():
    a = load_data("spot_low_resolution.obj")
    img = geoimg.fit_surface(a, geoimg.parametrize(a, "sphere"), geoimg.GaussianWeights()).sample(33)
    b = meshes.icosphere(3, 0.25)
    img_b = geoimg.fit_surface(b, geoimg.parametrize(b, "sphere"), geoimg.GaussianWeights()).sample(33)
    return img, img_b


@pytest.fixture(scope="module")
def terrain(mountain_surface):
    return mountain_surface.sample(33)


def test_ends_reproduce_the_keys_and_blends_are_affine(spots):
    a, b = spots
    m = morph(a, b, frames=7, easing="linear", align="none", rotate=False)
    frames = list(m.frames())
    assert (
        len(frames) == 7 and np.array_equal(frames[0].pixels, a.pixels) and np.array_equal(frames[-1].pixels, b.pixels)
    )
    p = [f.pixels.astype(np.float64) for f in frames]
    steps = [p[i + 1] - p[i] for i in range(6)]
    assert max(np.abs(s - steps[0]).max() for s in steps) < 1e-5     # equal steps: affine in t
    eased = morph(a, b, frames=7, easing="smoothstep", align="none", rotate=False)
    mid = eased.frame(0.5).pixels
    assert np.allclose(mid, 0.5 * (a.pixels.astype(np.float64) + b.pixels), atol=1e-6)
    assert np.abs(eased.frame(0.25).pixels - m.frame(0.25).pixels).max() > 1e-3   # easing changes the pace


def test_a_morph_of_a_shape_with_itself_is_constant(spots, terrain):
    a, _ = spots
    for img in (a, terrain):
        m = morph(img, img, frames=5)
        assert all(np.array_equal(f.pixels, img.pixels) for f in m.frames())
        assert m.report[1]["scale"] == 1.0 and m.report[1]["translation"] == [0.0, 0.0, 0.0]
    assert morph(a, a, frames=2).report[1]["rotation_deg"] == 0.0


def test_alignment_undoes_a_move_a_scale_and_a_turn_of_the_sphere(spots):
    a, _ = spots
    moved = geoimg.GeometryImage((a.pixels * 2.5 + [3.0, -1.0, 0.5]).astype(np.float32), domain="octahedral")
    m = morph(a, moved, frames=2, rotate=False)
    assert m.report[1]["scale"] == pytest.approx(0.4, rel=1e-6)
    assert np.abs(m.keys[1].pixels - a.pixels).max() < 1e-5
    turn = Rotation.from_rotvec([0.3, -0.5, 0.2])
    q = grid_directions(33).reshape(-1, 3)
    turned = a.domain.average_glued(_octahedral_sampler(a.pixels, a.domain)(turn.apply(q)).reshape(33, 33, 3)).astype(
        np.float32
    )
    m = morph(a, geoimg.GeometryImage(turned, domain="octahedral"), frames=2, align="none")
    rep = m.report[1]
    assert rep["rms_after"] < 0.2 * rep["rms_before"]
    found = Rotation.from_rotvec(np.radians(rep["rotation_deg"]) * np.array(rep["rotation_axis"]))
    assert np.degrees((found * turn).magnitude()) < 3.0          # it found the inverse turn


def test_per_region_timing(terrain):
    b = geoimg.GeometryImage((terrain.pixels + [0, 5, 0]).astype(np.float32), terrain.mask, metadata=terrain.metadata)
    lead = np.zeros(terrain.shape)
    lead[:, :10] = 1.0
    m = morph(terrain, b, frames=5, easing="linear", mask=lead, lag=0.5, align="none")
    frames = list(m.frames())
    assert np.array_equal(frames[0].pixels, terrain.pixels) and np.array_equal(frames[-1].pixels, b.pixels)
    half = m.frame(0.5).pixels[..., 1] - terrain.pixels[..., 1]
    assert half[:, :10].mean() == pytest.approx(5.0, rel=1e-5) and half[:, -10:].mean() == pytest.approx(0.0, abs=1e-5)


@pytest.mark.parametrize("call, message", [
    (lambda a, t: morph(a), "at least two shapes"),
    (lambda a, t: morph(a, t), "cannot morph between domains"),
    (lambda a, t: morph(t, geoimg.GeometryImage(np.zeros((17, 17, 3), np.float32))), "pass resample=True"),
    (lambda a, t: morph(a, a, frames=1), "frames"),
    (lambda a, t: morph(a, a, easing="bounce"), "easing"),
    (lambda a, t: morph(a, a, align="affine"), "align"),
    (lambda a, t: morph(a, a, mask=np.ones((3, 3))), "mask: expected shape"),
    (lambda a, t: morph(a, a, mask=np.ones((33, 33)), lag=1.0), "lag"),
    (lambda a, t: morph(a, "b.obj"), "geoimg.Mesh or GeometryImage"),
    (lambda a, t: morph(a, a, frames=3).frame(1.5), "t: expected a time"),
])
def test_mismatches_and_bad_settings_are_refused(spots, terrain, call, message):
    with pytest.raises((ValueError, TypeError), match=message):
        call(spots[0], terrain)


def test_resample_brings_keys_to_one_size(terrain, mountain_surface):
    big = mountain_surface.sample(65)
    m = morph(terrain, big, frames=3, resample=True, align="none")
    assert m.keys[1].shape == (33, 33)
    assert np.abs(m.keys[1].pixels - terrain.pixels).max() < 0.01 * np.ptp(terrain.pixels)


def test_shared_faces_share_the_parametrization_and_match_vertex_interpolation():
    check_shared_faces_morph(load_data("spot_low_resolution.obj"))


def _read_accessor(g, index):
    acc = g.accessors[index]
    view = g.bufferViews[acc.bufferView]
    blob = g.binary_blob()
    dtype = {gl.FLOAT: np.float32, gl.UNSIGNED_INT: np.uint32}[acc.componentType]
    width = {gl.SCALAR: 1, gl.VEC2: 2, gl.VEC3: 3}[acc.type]
    data = np.frombuffer(blob[view.byteOffset:view.byteOffset + view.byteLength], dtype)
    return data.reshape(acc.count, width) if width > 1 else data


@pytest.mark.parametrize("timing", [False, True])
def test_glb_reads_back_with_its_targets_and_frames(spots, tmp_path, timing):
    a, b = spots
    lead = np.zeros(a.shape)
    lead[:, :12] = 1.0
    m = morph(a, b, a, frames=9, easing="ease-in-out", mask=lead if timing else None)
    path = save_glb(m, tmp_path / "m.glb")
    g = gl.GLTF2().load(str(path))
    prim = g.meshes[0].primitives[0]
    n_targets = 9 if timing else 2
    assert len(prim.targets) == n_targets and len(g.animations) == 1
    sampler = g.animations[0].samplers[0]
    assert sampler.interpolation == ("STEP" if timing else "LINEAR")
    times, weights = _read_accessor(g, sampler.input), _read_accessor(g, sampler.output).reshape(9, n_targets)
    assert len(times) == 9 and times[-1] == pytest.approx(8 / 24)
    base = _read_accessor(g, prim.attributes.POSITION)
    deltas = [_read_accessor(g, t["POSITION"] if isinstance(t, dict) else t.POSITION) for t in prim.targets]
    for i, frame in enumerate(m.frames()):     # base + weights . targets is every frame's quad mesh
        pos = base + sum(w * d for w, d in zip(weights[i], deltas))
        assert np.abs(pos - frame.to_mesh().vertices).max() < 1e-5
    idx = _read_accessor(g, prim.indices)
    assert idx.max() == len(base) - 1 and len(idx) % 3 == 0


def test_frame_sequences(terrain, tmp_path):
    b = geoimg.GeometryImage((terrain.pixels * 1.1).astype(np.float32), terrain.mask, metadata=terrain.metadata)
    m = morph(terrain, b, frames=4, align="none")
    objs = save_frames(m, tmp_path / "obj", "obj")
    exrs = save_frames(m, tmp_path / "exr", "exr")
    assert [p.name for p in objs] == [f"frame_{i:04d}.obj" for i in range(4)]
    assert np.array_equal(geoimg.load_image(exrs[2]).pixels, m.frame(float(m.times[2])).pixels)
    assert geoimg.load_mesh(objs[3]).n_vertices == m.frame(1.0).to_mesh().n_vertices
    with pytest.raises(ValueError, match="fmt"):
        save_frames(m, tmp_path / "x", "stl")


# --- pictures ---------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def renderer():
    from geoimg.animation import Renderer, RenderError
    try:
        r = Renderer(96, 72)
    except RenderError as e:
        pytest.skip(f"no headless OpenGL here: {e}")
    yield r
    r.release()


def test_renderer_draws_the_shape_from_the_camera(renderer, spots):
    a, _ = spots
    front = renderer.render(a, renderer.camera_for(a, azimuth=0))
    side = renderer.render(a, renderer.camera_for(a, azimuth=90))
    shape = (front != 255).any(axis=2)
    assert front.shape == (72, 96, 3) and 0.05 < shape.mean() < 0.9
    assert not shape[0].any() and not shape[-1].any()              # framed: the edges are background
    assert np.abs(front.astype(int) - side).mean() > 5              # another view, another picture
    grey = front[shape].astype(int)
    assert grey.std() > 5                                           # shaded, not flat


def test_render_and_morph_commands(tmp_path, capsys, renderer):
    png = tmp_path / "m.png"
    assert main(["render", str(MOUNTAIN), "-o", str(png), "--width", "80", "--height", "60"]) == 0
    import imageio.v3 as iio
    assert iio.imread(png).shape == (60, 80, 3)
    a, b = str(data_file("spot_low_resolution.obj")), str(data_file("sphere.obj"))
    out = tmp_path / "m.glb"
    assert main(["morph", a, b, "--frames", "4", "--res", "33", "-o", str(out), "--gif", str(tmp_path / "m.gif"),
                 "--width", "64", "--height", "48", "--frames-dir", str(tmp_path / "f")]) == 0
    assert len(gl.GLTF2().load(str(out)).meshes[0].primitives[0].targets) == 1
    assert iio.imread(tmp_path / "m.gif").shape == (4, 48, 64, 3)
    assert len(list((tmp_path / "f").glob("frame_*.obj"))) == 4
    text = capsys.readouterr().out
    assert "sphere turned" in text and "wrote" in text
    assert main(["morph", a, b]) == 2
    assert "nothing to write" in capsys.readouterr().err
    assert main(["morph", a, str(MOUNTAIN), "-o", str(tmp_path / "x.glb")]) == 2
    assert "cannot morph between domains" in capsys.readouterr().err


def test_frame_files_are_written_all_or_none(tmp_path):
    a = geoimg.GeometryImage(np.zeros((3, 3, 3), np.float32))
    m = morph(a, geoimg.GeometryImage(np.ones((3, 3, 3), np.float32)), frames=4, align="none")
    (tmp_path / "frame_0002.obj").write_text("mine")
    with pytest.raises(FileExistsError, match="frame_0002.obj exists"):
        save_frames(m, tmp_path, "obj")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["frame_0002.obj"]
    assert len(save_frames(m, tmp_path / "f", "ply")) == 4
    with pytest.raises(geoimg.InputError, match="frames: expected an integer from 2 to 100000"):
        morph(a, a, frames=100_000_000)


def test_coloured_keys_morph_their_colours_and_the_glb_carries_them(spots, tmp_path):
    a, b = spots
    ca = np.clip(0.5 + 0.4 * a.pixels / np.abs(a.pixels).max(), 0, 1)
    a = geoimg.GeometryImage(a.pixels, domain=a.domain, metadata=dict(a.metadata, source="cow.obj"), colors=ca)
    b = geoimg.GeometryImage(b.pixels, domain=b.domain, metadata=dict(b.metadata, source="ball.obj"),
                             colors=np.broadcast_to(np.float32([0.9, 0.1, 0.1]), b.pixels.shape))
    m = morph(a, b, frames=3, easing="linear")
    assert np.allclose(m.frame(0.5).colors, 0.5 * (m.keys[0].colors + m.keys[1].colors), atol=1e-6)
    assert m.keys[1].colors is not None                         # turned with the sphere, still in [0, 1]
    g = gl.GLTF2().load(str(save_glb(m, tmp_path / "c.glb")))
    prim = g.meshes[0].primitives[0]
    assert g.meshes[0].extras["targetNames"] == ["ball.obj"]
    assert g.materials[prim.material].pbrMetallicRoughness.baseColorFactor == [1.0, 1.0, 1.0, 1.0]
    uv = _read_accessor(g, prim.attributes.TEXCOORD_0)
    base, col = _read_accessor(g, prim.attributes.POSITION), _read_accessor(g, prim.attributes.COLOR_0)
    assert uv.min() > 0 and uv.max() < 1 and len(uv) == len(base) == len(col)
    t = prim.targets[0]
    dp = _read_accessor(g, t["POSITION"] if isinstance(t, dict) else t.POSITION)
    dc = _read_accessor(g, t["COLOR_0"] if isinstance(t, dict) else t.COLOR_0)
    end = m.frame(1.0).to_mesh()
    # split vertices (seams of the octahedral image) hold their welded vertex's position and colour
    src = _split_source(m.frame(1.0))
    assert len(src) > end.n_vertices
    assert np.abs(base + dp - end.vertices[src]).max() < 1e-5
    assert np.abs(col + dc - end.colors[src]).max() < 1e-5


def _split_source(image):
    from geoimg.mesh._appearance import split_corners
    return split_corners(image.to_mesh())[0]


def test_pictures_use_colours_frame_tightly_read_the_up_axis_and_can_be_transparent(renderer, spots, terrain,
                                                                                    tmp_path, capsys):
    from geoimg.animation import Renderer, up_axis
    a, _ = spots
    red = geoimg.GeometryImage(a.pixels, domain=a.domain, colors=np.broadcast_to(np.float32([1, 0, 0]), a.pixels.shape))
    pic = renderer.render(red, renderer.camera_for(red))
    shape = (pic != 255).any(axis=2)
    assert (pic[shape][:, 0].astype(int) - pic[shape][:, 1:].max(axis=1)).mean() > 60      # drawn red
    rows, cols = np.flatnonzero(shape.any(axis=1)), np.flatnonzero(shape.any(axis=0))
    # tight: the picture's longer side nearly filled, and the shape centred
    assert max((rows[-1] - rows[0] + 1) / 72, (cols[-1] - cols[0] + 1) / 96) > 0.85
    assert abs((rows[0] + rows[-1]) / 2 - 35.5) < 4 and abs((cols[0] + cols[-1]) / 2 - 47.5) < 4
    assert up_axis(terrain) == "y" and terrain.metadata.get("up") is None       # a plain sample: no record
    zup = geoimg.GeometryImage(terrain.pixels, terrain.mask, metadata={"up": "z"})
    assert up_axis(zup) == "z" and renderer.camera_for(zup).up.tolist() == [0, 0, 1]
    with Renderer(48, 36, background=None) as clear:
        rgba = clear.render(a, clear.camera_for(a))
    assert rgba.shape == (36, 48, 4) and rgba[0, 0, 3] == 0 and rgba[18, 24, 3] == 255
    png = tmp_path / "t.png"
    assert main(["render", str(MOUNTAIN), "-o", str(png), "--width", "40", "--height", "30", "--transparent"]) == 0
    import imageio.v3 as iio
    assert iio.imread(png).shape == (30, 40, 4)


def test_a_terrain_image_records_its_up_axis(mountain):
    img = geoimg.mesh_to_image(mountain, 17, method="heightfield")
    assert img.metadata["up"] == "y"


def test_a_renderer_still_draws_after_another_is_released(renderer, spots):
    from geoimg.animation import Renderer
    a, _ = spots
    before = renderer.render(a, renderer.camera_for(a))
    with Renderer(32, 24) as other:
        other.render(a)
    assert np.array_equal(renderer.render(a, renderer.camera_for(a)), before)


def _pixel_of(direction, n):
    from geoimg.parametrization import sphere_to_square
    uv = sphere_to_square(np.asarray(direction, float)[None])[0]
    return int(round(uv[1] * (n - 1))), int(round(uv[0] * (n - 1)))


@pytest.mark.slow
def test_landmarks_make_features_meet_and_do_better_than_the_rigid_turn():
    from scipy.spatial import cKDTree
    from geoimg.mesh import suggest_landmarks
    a, b = load_data("spot_low_resolution.obj"), geoimg.load_mesh(data_file("spot.obj"))
    la = suggest_landmarks(a, 8)
    lb = cKDTree(b.vertices).query(a.vertices[la])[1]          # the same cow: its features by position
    b = geoimg.Mesh(b.vertices @ Rotation.from_rotvec([np.pi / 2, 0, 0]).as_matrix().T, b.faces)   # lying down
    marked = morph(a, b, frames=3, resolution=65, align="none", landmarks=list(zip(la, lb)))
    rigid = morph(a, b, frames=3, resolution=65, align="none")
    report = marked.report[1]["landmarks"]
    assert report["met"] and report["folded"] == 0 and report["residual_rad"] < 1e-4
    directions = geoimg.parametrize(a).coords[la]
    diag = b.bounding_box_diagonal()
    errors = {}
    for name, m in (("landmarks", marked), ("rigid", rigid)):
        px = [m.keys[1].pixels[_pixel_of(d, 65)] for d in directions]
        errors[name] = np.linalg.norm(np.array(px) - b.vertices[lb], axis=1) / diag
    assert errors["landmarks"].max() < 0.05                     # key 1's feature where key 0's is
    assert errors["rigid"].mean() > 0.2       # the best turn of the sphere matches the shapes in space, not features


@pytest.mark.parametrize("landmarks, message", [
    ([(0, 99999)], "vertex 99999 of shape 1 does not exist"),
    ([(0, 1), (0, 2)], "two landmarks of shape 0 coincide"),
    ([(0, 1, 2)], "one tuple of 2 vertex indices or 3-D points"),
    ([], "one tuple of 2"),
    ([5], "one tuple of 2"),
    ("0,1", "vertex-index tuples or 'auto'"),
    ([("a", "b")], "shape 0's landmark 'a' is neither a vertex index nor a 3-D point"),
    ([(True, 1)], "neither a vertex index nor a 3-D point"),
    ([(0, (1.0, 2.0))], "shape 1's landmark .* neither"),
    ([(0, (np.nan, 0.0, 0.0))], "neither a vertex index nor a 3-D point"),
    ([(0, ("x", "y", "z"))], "neither a vertex index nor a 3-D point"),
])
def test_bad_landmarks_are_refused(landmarks, message):
    a = load_data("spot_low_resolution.obj")
    with pytest.raises(geoimg.InputError, match=message):
        morph(a, a, frames=2, resolution=17, landmarks=landmarks)


def test_landmark_points_are_snapped_to_the_nearest_vertex():
    a, b = load_data("spot_low_resolution.obj"), geoimg.load_mesh(data_file("spot.obj"))
    from scipy.spatial import cKDTree
    ia = np.array([12, 300, 700, 501])
    pairs = list(zip(ia.tolist(), cKDTree(b.vertices).query(a.vertices[ia])[1].tolist()))   # the same places
    by_index = morph(a, b, frames=2, resolution=33, align="none", landmarks=pairs)
    near = [(i, tuple(b.vertices[j] + 1e-4)) for i, j in pairs]           # points just off key 1's vertices
    by_point = morph(a, b, frames=2, resolution=33, align="none", landmarks=near)
    np.testing.assert_array_equal(by_point.keys[1].pixels, by_index.keys[1].pixels)
    assert by_point.report[1]["landmarks"] == by_index.report[1]["landmarks"]
    assert by_index.report[1]["landmarks"]["met"]


def test_landmarks_need_meshes_on_the_sphere(spots, mountain):
    with pytest.raises(geoimg.InputError, match="geometry image without its mesh"):
        morph(spots[0], load_data("spot_low_resolution.obj"), landmarks=[(0, 0)])
    with pytest.raises(geoimg.InputError, match="closed genus-0 meshes"):
        morph(mountain, mountain, frames=2, resolution=17, landmarks=[(0, 1)])


def test_morph_command_reads_a_landmarks_file(tmp_path, capsys):
    a, b = str(data_file("spot_low_resolution.obj")), str(data_file("sphere.obj"))
    pairs = tmp_path / "pairs.csv"
    pairs.write_text("cow,ball\n0,0\n100,50\n300,120\n")
    assert main(["morph", a, b, "--landmarks", str(pairs), "--frames", "2", "--res", "17",
                 "-o", str(tmp_path / "m.glb")]) == 0
    assert "landmarks warped onto shape 0's" in capsys.readouterr().out
    for text, message in (("0,1,2\n", "rows of 2 vertex indices"), ("0,x\n", "whole vertex indices"),
                          ("0,999999\n", "vertex 999999 of shape 1 does not exist")):
        pairs.write_text(text)
        assert main(["morph", a, b, "--landmarks", str(pairs), "-o", str(tmp_path / "n.glb")]) == 2
        assert message in capsys.readouterr().err and not (tmp_path / "n.glb").exists()


@pytest.mark.slow
def test_auto_landmarks_pair_the_same_features_and_say_which(tmp_path, capsys):
    a, b = load_data("spot_low_resolution.obj"), geoimg.load_mesh(data_file("spot.obj"))
    m = morph(a, b, frames=2, resolution=65, align="none", landmarks="auto")
    pairs = np.array(m.report[0]["auto_landmarks"])
    assert len(pairs) >= 6 and m.report[1]["landmarks"]["met"]
    # the same cow in the same pose: partners are the same feature, close in space
    assert np.linalg.norm(a.vertices[pairs[:, 0]] - b.vertices[pairs[:, 1]], axis=1).max() < 0.05 * \
        b.bounding_box_diagonal()
    with pytest.raises(geoimg.InputError, match="every key must be a mesh"):
        morph(m.keys[0], b, landmarks="auto")
    with pytest.raises(geoimg.InputError, match="or 'auto'"):
        morph(a, b, landmarks="some")
    assert main(["morph", str(data_file("spot_low_resolution.obj")), str(data_file("spot.obj")), "--landmarks",
                 "auto", "--frames", "2", "--res", "33", "-o", str(tmp_path / "a.glb")]) == 0
    assert "auto landmarks:" in capsys.readouterr().out


def test_landmarks_with_three_keys_a_timing_mask_and_the_files_downstream(tmp_path):
    from scipy.spatial import cKDTree
    a, b = load_data("spot_low_resolution.obj"), geoimg.load_mesh(data_file("spot.obj"))
    c = geoimg.Mesh(a.vertices * [1.0, 1.3, 1.0], a.faces)            # a taller Spot, the same faces as a
    ia = np.array([12, 300, 700, 501])
    ib = cKDTree(b.vertices).query(a.vertices[ia])[1]
    weights = np.zeros((33, 33))
    weights[:16] = 1.0
    m = morph(a, b, c, frames=5, resolution=33, align="none", landmarks=list(zip(ia, ib, ia)), mask=weights)
    for k in (1, 2):
        assert m.report[k]["landmarks"]["met"] and m.report[k]["landmarks"]["folded"] == 0
    assert np.array_equal(m.frame(2.0).pixels, m.keys[2].pixels)
    half = m.frame(1.5).pixels                      # the mask's rows lead: nearer key 2 than the others
    lead, lag = np.abs(half - m.keys[2].pixels)[:16].mean(), np.abs(half - m.keys[2].pixels)[17:].mean()
    assert lead < lag
    g = gl.GLTF2().load(str(save_glb(m, tmp_path / "m.glb")))
    assert len(g.meshes[0].primitives[0].targets) >= 2 and len(g.animations) == 1
    files = save_frames(m, tmp_path / "frames", "ply")
    assert len(files) == 5 and all(f.is_file() for f in files)


def test_gif_frames_share_one_palette_and_read_back_close(tmp_path):
    """Smooth shading and a flat background through 256 shared colours: every frame within a few levels on
    average, the background exact, the timing and the loop kept; bad inputs refused, nothing written."""
    import imageio.v3 as iio
    from PIL import Image
    from geoimg.animation import save_animation
    yy, xx = np.mgrid[0:60, 0:80]
    frames = []
    for k in range(6):
        f = np.full((60, 80, 3), 255, np.uint8)
        disk = (xx - 20 - 6 * k) ** 2 + (yy - 30) ** 2 < 300
        shade = (80 + 2 * xx + yy + 10 * k) % 256
        f[disk] = np.stack([shade, 0.9 * shade, 0.8 * shade], -1)[disk].astype(np.uint8)
        frames.append(f)
    path = save_animation(frames, tmp_path / "a.gif", fps=20)
    back = iio.imread(path)[..., :3].astype(float)
    assert back.shape == (6, 60, 80, 3)
    assert np.abs(back - np.array(frames, float)).mean(axis=(1, 2, 3)).max() < 3.0
    assert (back[:, 0, 0] == 255).all()                                   # the background
    with Image.open(path) as im:
        assert im.n_frames == 6 and im.info["duration"] == 50 and im.info["loop"] == 0
    for bad, message in ((dict(frames=[], path=tmp_path / "b.gif"), "nothing to write"),
                         (dict(frames=frames, path=tmp_path / "b.gif", fps=0), "fps")):
        with pytest.raises(geoimg.InputError, match=message):
            save_animation(**bad)
    assert not (tmp_path / "b.gif").exists()


def _turned_and_moved(mesh, degrees=(40.0, -25.0, 70.0), shift=(0.3, -0.2, 0.5)):
    turn = Rotation.from_euler("xyz", degrees, degrees=True)
    return geoimg.Mesh(turn.apply(np.array(mesh.vertices)) + np.asarray(shift), mesh.faces)


def test_spectral_morph_matches_spheres_by_the_ellipsoids_and_leaves_shapes_in_place():
    from geoimg.mesh import surface_distance
    from geoimg.spectrum import harmonics, synthesize
    a = load_data("spot_low_resolution.obj")
    h = harmonics(a, 8)
    own = h.to_image(65)
    # the same shape with its sphere turned: as image keys they do not correspond; through the ellipsoids they do
    turn = Rotation.from_euler("xyz", (40.0, -25.0, 70.0), degrees=True).as_matrix()
    d = own.domain.directions(65).reshape(-1, 3)
    turned = geoimg.GeometryImage(synthesize(h.coeffs, d @ turn.T).reshape(65, 65, 3).astype(np.float32), None,
                                  own.domain)
    m = morph(own, turned, frames=3, easing="linear", spectral=8, resolution=65, align="none")
    first, mid, last = (f.pixels.astype(np.float64) for f in m.frames())
    radius = np.linalg.norm(first - first.reshape(-1, 3).mean(axis=0), axis=2).mean()
    assert np.abs(last - first).max() < 0.01 * radius                  # one shape: the morph stands still
    assert np.allclose(mid, 0.5 * (first + last), atol=1e-5)          # blending images = blending coefficients
    assert abs(m.report[1]["sphere_turn_deg"] - m.report[0]["sphere_turn_deg"]) > 1.0
    plain = morph(own, turned, frames=3, easing="linear", resolution=65, align="none", rotate=False)
    assert np.abs(plain.frame(1.0).pixels - plain.frame(0.0).pixels).max() > 0.3 * radius
    # a mesh turned and moved stays where it is (the ellipsoids match the spheres, not the objects)
    b = _turned_and_moved(a)
    m = morph(a, b, frames=2, spectral=8, resolution=65, align="none")
    for key, frame in ((a, m.frame(0.0)), (b, m.frame(1.0))):
        assert surface_distance(key, frame.to_mesh(), n=20000)["psnr_db"] > 35      # degree 8 of spot: ~41 dB
    assert m.report[1]["harmonics_lmax"] == 8


def test_spectral_morph_needs_spheres_and_no_landmarks(spots, terrain):
    a = load_data("spot_low_resolution.obj")
    with pytest.raises(ValueError, match="lmax"):
        morph(a, a, spectral=0)
    with pytest.raises(ValueError, match="landmarks"):
        morph(a, a, spectral=4, landmarks=[(0, 0), (1, 1), (2, 2)])
    with pytest.raises(ValueError, match="octahedral"):
        morph(spots[0], terrain, spectral=4)
    with pytest.raises(ValueError, match="genus-0"):
        morph(a, load_data("torus.obj"), spectral=4)


def test_morph_command_spectral(tmp_path, capsys):
    a = data_file("spot_low_resolution.obj")
    out = tmp_path / "frames"
    assert main(["morph", str(a), str(a), "--spectral", "4", "--frames", "3", "--frames-dir", str(out),
                 "--res", "33"]) == 0
    assert len(list(out.glob("frame_*.obj"))) == 3 and "ellipsoid" in capsys.readouterr().out
    for bad in (["--spectral", "0"], ["--spectral", "4", "--landmarks", "auto"]):
        assert main(["morph", str(a), str(a), "--frames-dir", str(tmp_path / "no"), *bad]) == 2
        assert not (tmp_path / "no").exists()
