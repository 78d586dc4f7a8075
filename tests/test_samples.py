"""Every sample script runs, at a reduced size, and shows what it claims."""
import importlib.util
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow           # a page, a sample, a batch, a fuzzing run or a real mesh: the full run

SAMPLES = Path(__file__).resolve().parents[1] / "samples"


@pytest.fixture(scope="module")
def renderer_or_skip():
    from geoimg.animation import Renderer, RenderError
    try:
        Renderer(16, 16).release()
    except RenderError as e:
        pytest.skip(f"no headless OpenGL here: {e}")


def load_sample(name):
    import sys
    if str(SAMPLES) not in sys.path:
        sys.path.insert(0, str(SAMPLES))      # the samples import their _common helpers
    spec = importlib.util.spec_from_file_location(name, SAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_partial_smoothing_sample(tmp_path):
    stats = load_sample("partial_smoothing").run(tmp_path, res=65)
    assert Path(stats["png"]).is_file()
    surface, image = stats["surface domain, s = 8"], stats["image domain, masked"]
    assert image["far_max"] == 0.0 and image["inside_rms"] > 1e-3            # exact outside the feathered mask
    assert stats["fitted, s = 2"]["inside_rms"] == 0.0
    rest_surface, rest_image = stats["surface domain, all but the region"], stats["image domain, all but the region"]
    assert rest_image["inside_rms"] == 0.0 and rest_image["far_max"] > 1e-3      # the region kept bit for bit
    assert rest_surface["inside_rms"] < 1e-9 and rest_surface["far_max"] > 1e-3   # s(u, v) keeps it exactly
    assert surface["inside_rms"] > 1e-3 and surface["far_max"] < 1e-9


def test_fig2_terrain_sample(tmp_path):
    stats = load_sample("fig2_terrain").run(tmp_path, res=33, step=8)
    assert Path(stats["png"]).is_file()
    # smoother surfaces bend less: the Gaussian curvature's range shrinks as s grows
    spans = [stats[s]["K_range"][1] - stats[s]["K_range"][0] for s in (2.0, 4.0, 8.0)]
    assert spans[0] > spans[1] > spans[2]


def test_fig3_small_meshes_sample(tmp_path, renderer_or_skip):
    stats = load_sample("fig3_small_meshes").run(tmp_path, res=17, size=(80, 60))
    assert Path(stats["png"]).is_file()
    assert stats["triangles, quads, pentagons"]["sizes"] == [3, 4, 5]


def test_fig4_filtering_sample(tmp_path, renderer_or_skip):
    stats = load_sample("fig4_filtering").run(tmp_path, res=33, size=(80, 60))
    assert stats["geometry image"] == 0.0 and stats["mean filter 5x5, twice"] > 0.01
    assert 0 < stats["head smoothed only"] < stats["mean filter 5x5, twice"]


def test_fig5_morph_sample(tmp_path):
    stats = load_sample("fig5_morph").run(tmp_path, res=65, step=4)
    assert Path(stats["png"]).is_file()
    assert min(stats[k] for k in ("2004-10-04", "3:1", "1:1", "1:3", "2007-07-05")) > 50   # dB vs per-vertex blend


def test_fig9_multires_sample(tmp_path, renderer_or_skip):
    stats = load_sample("fig9_multires").run(tmp_path, finest=49, size=(80, 60))
    assert [stats[s] for s in (8.0, 4.0, 2.0, 1.0, 0.5)] == sorted(stats[s] for s in (8.0, 4.0, 2.0, 1.0, 0.5))


def test_fig11_weights_sample(tmp_path):
    stats = load_sample("fig11_weights").run(tmp_path, res=33)
    assert Path(stats["png"]).is_file() and len(stats) == 7


def test_cut_open_sample(tmp_path, renderer_or_skip):
    stats = load_sample("cut_open").run(tmp_path, res=129, size=(80, 60))
    assert Path(stats["png"]).is_file() and stats["domain"] == "cut"
    assert stats["genus in"] == stats["genus out"] == 1 and stats["closed out"] and stats["psnr_db"] > 45


def test_balanced_disk_sample(tmp_path, renderer_or_skip):
    stats = load_sample("balanced_disk").run(tmp_path, res=65, size=(80, 60))
    plain = stats["none"]
    for balanced in (stats["slim"], stats["area"]):
        assert plain["folds"] == balanced["folds"] == 0
        assert plain["area_log_rms"] > 5 and balanced["area_log_rms"] < 1.5
        assert balanced["psnr_db"] > plain["psnr_db"] + 10 and balanced["hausdorff"] < plain["hausdorff"] / 3


def test_textured_sample(tmp_path, renderer_or_skip):
    stats = load_sample("textured").run(tmp_path, res=65, size=(80, 60))
    assert Path(stats["png"]).is_file() and stats["colours_kept"] and stats["texture"] == [65, 65, 3]


def test_denoise_sample(tmp_path, renderer_or_skip):
    stats = load_sample("denoise").run(tmp_path, res=65, size=(80, 60))
    assert Path(stats["png"]).is_file()
    assert stats["image_nlmeans"] < stats["noisy"] and stats["mesh_taubin"] < stats["noisy"]
