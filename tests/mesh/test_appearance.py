"""Colours, texture coordinates and textures of meshes: read, checked, carried through repairs, written."""
import warnings

import numpy as np
import pygltflib
import pytest
import trimesh

import geoimg
from geoimg.errors import MeshError
from geoimg.mesh import load_mesh, save_mesh, split_components, orient_faces
from geoimg.mesh._appearance import split_corners

from helpers import textured_spot

SQUARE = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]


def coloured_square(**kw):
    return geoimg.Mesh(SQUARE, [[0, 1, 2], [0, 2, 3]], colors=[[1, 0, 0], [0, 1, 0], [0, 0, 1], [0.5, 0.5, 0.5]], **kw)


@pytest.mark.parametrize("ext, tol", [(".obj", 1e-6), (".ply", 0.5 / 255)])
def test_vertex_colours_round_trip(tmp_path, ext, tol):
    m = coloured_square()
    back = load_mesh(save_mesh(m, tmp_path / f"c{ext}"))
    assert back.colors is not None and np.abs(back.colors - m.colors).max() <= tol
    assert np.array_equal(back.faces, m.faces)


def test_obj_colours_0_255_are_scaled_and_mixed_lines_refused(tmp_path):
    p = tmp_path / "a.obj"
    p.write_text("v 0 0 0 255 0 0\nv 1 0 0 0 255 0\nv 0 1 0 0 0 255\nf 1 2 3\n")
    assert load_mesh(p).colors.tolist() == np.eye(3).tolist()
    p.write_text("v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.warns(UserWarning, match="some 'v' lines have colours"):
        assert load_mesh(p).colors is None


def test_ascii_ply_colours_are_read(tmp_path):
    p = tmp_path / "a.ply"
    p.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n"
                 "property list uchar int vertex_indices\nend_header\n0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n"
                 "3 0 1 2\n")
    assert load_mesh(p).colors.tolist() == np.eye(3).tolist()


def test_textured_obj_is_read_with_seamed_uvs(tmp_path):
    m = load_mesh(textured_spot(tmp_path))
    assert m.texture.shape == (1024, 1024, 3) and m.texture.dtype == np.uint8
    assert m.face_uv.shape == (m.n_faces, 3, 2) and m.uv is None         # spot's UVs have seams
    source, uv, faces = split_corners(m)
    assert len(source) > m.n_vertices                                    # split at the seams
    assert np.allclose(uv[faces], m.face_uv) and np.array_equal(source[faces], m.faces)


def test_missing_or_several_textures_warn_and_read_none(tmp_path):
    obj = textured_spot(tmp_path)
    (tmp_path / "spot_texture.png").unlink()
    with pytest.warns(UserWarning, match="texture spot_texture.png not found"):
        assert load_mesh(obj).texture is None
    lines = obj.read_text().splitlines()
    half = 2 + len(lines) // 2
    obj.write_text("\n".join(lines[:half] + ["usemtl other"] + lines[half:]))
    (tmp_path / "spot.mtl").write_text("newmtl spot\nmap_Kd a.png\nnewmtl other\nmap_Kd b.png\n")
    with pytest.warns(UserWarning, match="use 2 textures"):
        assert load_mesh(obj).texture is None


@pytest.mark.parametrize("kw, match", [
    (dict(colors=[[2, 0, 0]] * 4), "colors: expected values in"),
    (dict(colors=np.zeros((4, 2))), "colors: expected shape"),
    (dict(colors=[[np.nan, 0, 0]] * 4), "colors: expected values in"),
    (dict(face_uv=np.zeros((2, 2, 2))), "face_uv: expected shape"),
    (dict(face_uv=np.full((2, 3, 2), np.inf)), "face_uv: contains NaN"),
    (dict(texture=np.zeros((4, 4, 3), np.uint8)), "a texture needs face_uv"),
    (dict(face_uv=np.zeros((2, 3, 2)), texture=np.zeros((4, 4, 3))), "texture: expected an 8-bit"),
])
def test_bad_appearance_is_refused(kw, match):
    with pytest.raises(MeshError, match=match):
        geoimg.Mesh(SQUARE, [[0, 1, 2], [0, 2, 3]], **kw)


def test_repairs_carry_colours_and_corner_uvs():
    uv = np.random.default_rng(0).random((2, 3, 2))
    m = geoimg.Mesh(SQUARE + [[5, 0, 0], [6, 0, 0], [5, 1, 0]], [[0, 1, 2], [3, 4, 5]],
                    colors=np.linspace(0, 1, 21).reshape(7, 3), face_uv=uv)
    pieces = split_components(m)
    for piece, used in pieces:
        assert np.array_equal(piece.colors, m.colors[used])
    assert {tuple(p.face_uv.ravel()) for p, _ in pieces} == {tuple(u.ravel()) for u in uv}
    turned, count = orient_faces(geoimg.Mesh(SQUARE, [[0, 1, 2], [0, 3, 2]], face_uv=uv))
    assert count == 1
    f = 1 if turned.faces[1].tolist() == [2, 3, 0] else 0     # the face turned over
    pairs = {(int(v), tuple(t)) for v, t in zip(turned.faces[f], turned.face_uv[f])}
    assert pairs == {(int(v), tuple(t)) for v, t in zip([0, 3, 2] if f == 1 else [0, 1, 2], uv[f])}


def test_textured_obj_is_written_with_its_material_all_or_nothing(tmp_path):
    m = load_mesh(textured_spot(tmp_path))
    out = save_mesh(m, tmp_path / "copy.obj")
    assert (tmp_path / "copy.mtl").read_text().endswith("map_Kd copy.png\n")
    back = load_mesh(out)
    assert np.array_equal(back.texture, m.texture) and np.allclose(back.face_uv, m.face_uv)
    (tmp_path / "again.png").write_text("in the way")
    with pytest.raises(FileExistsError):
        save_mesh(m, tmp_path / "again.obj")
    assert not (tmp_path / "again.obj").exists() and not (tmp_path / "again.mtl").exists()


def test_glb_carries_texture_or_colours(tmp_path):
    m = load_mesh(textured_spot(tmp_path))
    g = pygltflib.GLTF2().load(str(save_mesh(m, tmp_path / "t.glb")))
    prim = g.meshes[0].primitives[0]
    assert prim.attributes.TEXCOORD_0 is not None and g.images and g.textures
    assert g.materials[prim.material].pbrMetallicRoughness.baseColorTexture is not None
    back = trimesh.load(tmp_path / "t.glb", force="mesh", process=False)
    assert back.visual.uv.shape == (len(back.vertices), 2)
    g = pygltflib.GLTF2().load(str(save_mesh(coloured_square(), tmp_path / "c.glb")))
    assert g.meshes[0].primitives[0].attributes.COLOR_0 is not None


def test_formats_without_colours_say_so(tmp_path):
    with pytest.warns(UserWarning, match="STL keeps no colours"):
        save_mesh(coloured_square(), tmp_path / "c.stl")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        save_mesh(coloured_square(), tmp_path / "c.ply")


def test_glb_reads_back_its_texture_and_colours(tmp_path):
    m = load_mesh(textured_spot(tmp_path))
    back = load_mesh(save_mesh(m, tmp_path / "t.glb"))
    assert np.array_equal(back.texture, m.texture)

    def corners(mesh):
        return np.hstack([mesh.vertices[mesh.faces].reshape(-1, 3), mesh.face_uv.reshape(-1, 2)])

    from scipy.spatial import cKDTree          # float32 in the file: every corner within rounding of one
    a, b = corners(back), corners(m)
    assert cKDTree(b).query(a)[0].max() < 1e-6 and cKDTree(a).query(b)[0].max() < 1e-6
    c = coloured_square()
    assert np.abs(load_mesh(save_mesh(c, tmp_path / "c.glb")).colors - c.colors).max() <= 0.5 / 255


def test_obj_w_coordinates_are_not_colours(tmp_path):
    p = tmp_path / "w.obj"
    p.write_text("v 0 0 0 1\nv 1 0 0 1\nv 0 1 0\nf 1 2 3\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert load_mesh(p).colors is None
