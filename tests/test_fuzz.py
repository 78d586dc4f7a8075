"""The readers under coverage-guided fuzzing (tests/fuzz/fuzz_readers.py, atheris): a short run of every
format in one process (the first byte of an input choosing its format) finds nothing but clean GeoimgErrors;
and every input an earlier run found (tests/data/fuzz) is read or refused in one GeoimgError, with no
library's log. The long runs, ten minutes a format, are benchmarks/bench_fuzz.py's."""
import logging
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

import geoimg

sys.path.insert(0, str(Path(__file__).parent / "fuzz"))
from fuzz_readers import FORMATS, IMAGES, MIXED, make_target, write_seeds  # noqa: E402

pytestmark = pytest.mark.slow           # a page, a sample, a batch, a fuzzing run or a real mesh: the full run

HARNESS = Path(__file__).parent / "fuzz" / "fuzz_readers.py"
FINDINGS = sorted((Path(__file__).parent / "data" / "fuzz").iterdir())
SECONDS = 8


def test_a_short_fuzzing_run_of_every_format_finds_nothing(tmp_path):
    pytest.importorskip("atheris")
    corpus = tmp_path / "corpus"
    seeds = write_seeds(MIXED, corpus)                # here: one process fewer than the harness would start
    assert {p.name.split("-")[0] for p in seeds} == set(FORMATS)
    done = subprocess.run([sys.executable, str(HARNESS), MIXED, f"-max_total_time={SECONDS}", "-rss_limit_mb=3072",
                           "-timeout=30", str(corpus)], cwd=tmp_path, capture_output=True, text=True,
                          errors="replace", timeout=600)
    found = sorted(p.name for p in tmp_path.iterdir() if p.name.split("-")[0] in ("crash", "timeout", "oom"))
    assert done.returncode == 0 and found == [], (found, done.stderr[-3000:])
    assert "Done " in done.stderr and len(list(corpus.iterdir())) >= len(seeds)


def test_the_mixed_target_reads_each_input_as_the_format_its_first_byte_chooses(monkeypatch):
    seen = []

    def record(path):
        seen.append((Path(path).suffix[1:], Path(path).read_bytes()))

    monkeypatch.setattr(geoimg, "load_mesh", record)
    monkeypatch.setattr(geoimg, "load_image", record)
    target = make_target(MIXED)
    target(b"")                                                        # nothing to choose by: nothing read
    for k in range(len(FORMATS) + 2):                                  # the byte counts round the formats
        target(bytes([k]) + b"body")
    assert seen == [(FORMATS[k % len(FORMATS)], b"body") for k in range(len(FORMATS) + 2)]


@pytest.mark.parametrize("finding", FINDINGS, ids=[p.name for p in FINDINGS])
def test_every_earlier_finding_is_read_or_refused_cleanly(finding):
    fmt = finding.suffix[1:]
    assert fmt in FORMATS
    before = logging.lastResort
    try:
        make_target(fmt)(finding.read_bytes())       # raises on anything but a clean GeoimgError or a read
    finally:
        logging.lastResort = before
    read = geoimg.load_image if fmt in IMAGES else geoimg.load_mesh
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(geoimg.GeoimgError):
            read(finding)
