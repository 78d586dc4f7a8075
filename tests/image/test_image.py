import numpy as np
import pytest

import geoimg
from geoimg import GeometryImage, ImageFileError, load_image, save_image


def plane_image(H=5, W=6, dtype=np.float32):
    u, v = np.meshgrid(np.linspace(0, 1, W), np.linspace(0, 1, H))
    return np.stack([u, v, u * v], axis=-1).astype(dtype)


def test_to_mesh_full_mask_gives_all_quads_oriented_up():
    img = GeometryImage(plane_image())
    m = img.to_mesh()
    assert m.n_vertices == 30 and m.n_faces == 4 * 5 and np.all(m.face_sizes == 4)
    q = m.faces[0]
    n = np.cross(m.vertices[q[1]] - m.vertices[q[0]], m.vertices[q[2]] - m.vertices[q[0]])
    assert n[2] > 0 and np.all(m.normals[:, 2] > 0)       # grid normals agree with quad orientation
    assert np.allclose(m.uv[-1], [1, 1])


def test_to_mesh_orientation_flag_reverses_quads():
    m = GeometryImage(plane_image(), metadata={"orientation": -1}).to_mesh()
    q = m.faces[0]
    n = np.cross(m.vertices[q[1]] - m.vertices[q[0]], m.vertices[q[2]] - m.vertices[q[0]])
    assert n[2] < 0 and np.all(m.normals[:, 2] < 0)


def test_to_mesh_drops_quads_touching_masked_pixels():
    mask = np.ones((5, 6), bool)
    mask[2, 3] = False
    mask[0, 0] = False
    m = GeometryImage(plane_image(), mask).to_mesh()
    assert m.n_faces == 20 - 4 - 1
    assert m.n_vertices == 30 - 2   # both masked pixels gone, no unreferenced vertex
    assert m.referenced_vertices().all()
    with pytest.raises(geoimg.GeoimgError, match="no 2 x 2 block"):
        GeometryImage(plane_image(), np.eye(5, 6, dtype=bool)).to_mesh()


def test_surface_image_to_mesh_matches_source_orientation(mountain_surface, mountain):
    m = mountain_surface.sample(32).to_mesh()
    assert m.n_faces == 31 * 31
    q = m.faces[:, :3]
    n = np.cross(m.vertices[q[:, 1]] - m.vertices[q[:, 0]], m.vertices[q[:, 2]] - m.vertices[q[:, 0]])
    assert np.mean(n[:, 1] > 0) > 0.99      # y-up terrain: quads face up, like the source triangles
    assert np.mean(np.sum(n * m.normals[q[:, 0]], axis=1) > 0) > 0.99


def test_exr_round_trip_is_bit_exact_with_mask_normals_metadata(tmp_path, mountain_surface):
    img = mountain_surface.sample(40)
    img.metadata["source"] = "mountain.obj"
    back = load_image(save_image(img, tmp_path / "m.exr"))
    assert back.pixels.dtype == np.float32 and np.array_equal(back.pixels, img.pixels)
    assert np.array_equal(back.mask, img.mask) and np.array_equal(back.normals, img.normals)
    assert back.metadata == img.metadata and back.domain == img.domain and back.domain.kind == "planar"
    # the mesh from the file equals the mesh from memory
    assert np.array_equal(back.to_mesh().vertices, img.to_mesh().vertices)


def test_preview_is_16_bit(tmp_path):
    import OpenImageIO as oiio

    mask = np.ones((5, 6), bool)
    mask[0, 0] = False
    p = GeometryImage(plane_image(), mask).preview(tmp_path / "p.png")
    buf = oiio.ImageBuf(str(p))
    assert buf.spec().format == oiio.UINT16 and buf.spec().nchannels == 3
    px = buf.get_pixels(oiio.UINT16)
    assert px[0, 0].tolist() == [0, 0, 0] and px[-1, -1].tolist() == [65535, 65535, 65535]


def test_file_errors(tmp_path):
    img = GeometryImage(plane_image())
    save_image(img, tmp_path / "a.exr")
    with pytest.raises(FileExistsError):
        save_image(img, tmp_path / "a.exr")
    save_image(img, tmp_path / "a.exr", overwrite=True)
    with pytest.raises(ImageFileError, match="saved as .exr, .npz, .tif, .tiff, .npy"):
        save_image(img, tmp_path / "a.jpg")
    with pytest.raises(ImageFileError, match="PNG"):
        img.preview(tmp_path / "a.jpg")
    with pytest.raises(TypeError, match="GeometryImage"):
        save_image(plane_image(), tmp_path / "b.exr")
    with pytest.raises(FileNotFoundError):
        load_image(tmp_path / "missing.exr")
    (tmp_path / "junk.exr").write_bytes(b"not an exr at all")
    with pytest.raises(ImageFileError, match="cannot be read"):
        load_image(tmp_path / "junk.exr")
    assert sorted(f.name for f in tmp_path.iterdir()) == ["a.exr", "junk.exr"]


@pytest.mark.parametrize("kwargs, error, message", [
    (dict(pixels=np.zeros((4, 4))), ValueError, "expected shape"),
    (dict(pixels=np.zeros((4, 4, 3), int)), TypeError, "float32 or float64"),
    (dict(pixels=np.full((4, 4, 3), np.nan)), ValueError, "NaN"),
    (dict(pixels=np.zeros((4, 4, 3)), mask=np.ones((4, 5), bool)), ValueError, r"mask: expected shape \(4, 4\)"),
    (dict(pixels=np.zeros((4, 4, 3)), mask=np.ones((4, 4))), TypeError, "boolean"),
    (dict(pixels=np.zeros((4, 4, 3)), domain="torus"), ValueError, "domain"),
])
def test_bad_images_are_refused(kwargs, error, message):
    with pytest.raises(error, match=message):
        GeometryImage(**kwargs)


def test_image_copies_its_inputs():
    p = plane_image()
    img = GeometryImage(p)
    p[0, 0, 0] = 42
    assert img.pixels[0, 0, 0] == 0
