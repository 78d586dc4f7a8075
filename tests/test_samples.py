"""Every sample script runs, at a reduced size, and shows what it claims."""
import importlib.util
from pathlib import Path

SAMPLES = Path(__file__).resolve().parents[1] / "samples"


def load_sample(name):
    spec = importlib.util.spec_from_file_location(name, SAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_partial_smoothing_sample(tmp_path):
    stats = load_sample("partial_smoothing").run(tmp_path, res=65)
    assert Path(stats["png"]).is_file()
    surface, image = stats["surface domain, s = 8"], stats["image domain, masked"]
    assert image["far_max"] == 0.0 and image["inside_rms"] > 1e-3            # exact outside the feathered mask
    assert surface["inside_rms"] > 10 * surface["far_max"]                     # a Gaussian reach, not a mask
    assert stats["fitted, s = 2"]["inside_rms"] == 0.0
