"""geoimg batch: a real local Dask cluster (worker processes) over a folder of good, corrupt and refused meshes
with a duplicate file name; the manifest, the outputs, the Zarr store, skipping, interruption, refusals."""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

import geoimg
from geoimg import _commands, batch, cli
from geoimg.batch._task import Job, run_job
from helpers import DATA, data_file
from meshes import mobius, write

pytestmark = pytest.mark.slow           # a page, a sample, a batch, a fuzzing run or a real mesh: the full run

distributed = pytest.importorskip("distributed")
pd = pytest.importorskip("pandas")

RES = 33


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=50) as cluster, distributed.Client(cluster) as c:
        yield c


@pytest.fixture
def inputs(tmp_path):
    """a/sphere.obj, a/cube_no_bottom.obj, b/sphere.obj (the same name in another folder), b/bad.obj (not a
    mesh), b/sub/moebius.off (refused: not orientable), b/notes.txt (not a mesh: not picked up)."""
    root = tmp_path / "in"
    for rel, src in (("a/sphere.obj", "sphere.obj"), ("a/cube_no_bottom.obj", "cube_no_bottom.obj"),
                     ("b/sphere.obj", "sphere.obj")):
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(DATA / src, root / rel)
    (root / "b" / "bad.obj").write_bytes(b"\x00\x01 this is not a mesh \xff")
    (root / "b" / "sub").mkdir()
    write(mobius(), root / "b" / "sub" / "moebius.off")
    (root / "b" / "notes.txt").write_text("hello")
    return root


def _status(table) -> dict:
    return {Path(r.input).relative_to(r.input.split("/in/")[0] + "/in").as_posix(): r.status
            for r in table.itertuples()}


def test_manifest_outputs_and_a_second_run_that_skips_everything(client, inputs, tmp_path):
    out = tmp_path / "out"
    table = batch.convert([inputs], out, client=client, resolution=RES, quads=True)
    assert _status(table) == {"a/cube_no_bottom.obj": "ok", "a/sphere.obj": "ok", "b/bad.obj": "refused",
                              "b/sphere.obj": "ok", "b/sub/moebius.off": "refused"}
    rows = table.set_index("input")
    bad = rows.loc[str(inputs / "b" / "bad.obj")]
    assert "no vertices" in bad.message and pd.isna(bad.outputs)
    assert "orient" in rows.loc[str(inputs / "b" / "sub" / "moebius.off")].message
    for name in ("a/sphere", "b/sphere", "a/cube_no_bottom"):           # equal names kept apart
        assert (out / f"{name}.exr").is_file() and (out / f"{name}_quads.obj").is_file()
    assert sorted(p.name for p in (out / "b").iterdir()) == ["sphere.exr", "sphere_quads.obj"]
    sphere = rows.loc[str(inputs / "a" / "sphere.obj")]
    assert sphere.domain == "octahedral" and sphere.image_size == f"{RES}x{RES}" and sphere.faces == 1280
    assert sphere.topology.startswith("closed surface of genus 0") and sphere.psnr_db > 30
    image = geoimg.load_image(out / "a" / "sphere.exr")                # each piece's map, as its image records it
    assert float(sphere.map_stretch) == image.metadata["map_stretch"] >= 1.0
    assert float(sphere.starved) == image.metadata["starved"]
    assert all(sphere[f"t_{s}"] > 0 for s in ("load", "parametrize", "fit", "sample", "write", "psnr"))
    assert len(set(table.options_hash)) == 1
    # the manifest on disk says the same
    on_disk = batch.read_manifest(out / batch.MANIFEST_NAME)
    assert {k: r["status"] for k, r in on_disk.items()} == dict(zip(table.input, table.status))

    stamps = {p: p.stat().st_mtime_ns for p in out.rglob("*.exr")}
    again = batch.convert([inputs], out, client=client, resolution=RES, quads=True)
    assert again.attrs["summary"]["skipped"] == 5 and list(again.status) == list(table.status)
    assert {k: again.attrs["summary"][k] for k in ("ok", "refused", "failed", "done")} == \
        {"ok": 3, "refused": 2, "failed": 0, "done": 5}
    assert {p: p.stat().st_mtime_ns for p in out.rglob("*.exr")} == stamps      # nothing rewritten

    changed = batch.convert([inputs], out, client=client, resolution=RES, quads=True,
                            weights=geoimg.CoverageWeights(s=2.0))
    assert changed.attrs["summary"]["skipped"] == 0 and set(changed.options_hash) != set(table.options_hash)


def test_outputs_equal_geoimg_image_on_the_same_input(client, inputs, tmp_path):
    out = tmp_path / "out"
    batch.convert([inputs / "a"], out, client=client, resolution=RES, steps=[("mean", [3])])
    for name in ("sphere", "cube_no_bottom"):
        single = tmp_path / f"{name}.exr"
        assert cli.main(["image", str(inputs / "a" / f"{name}.obj"), "-o", str(single), "--res", str(RES), "-q"]) == 0
        assert cli.main(["filter", str(single), "-o", str(single), "--mean", "3", "--force", "-q"]) == 0
        a, b = geoimg.load_image(out / f"{name}.exr"), geoimg.load_image(single)
        np.testing.assert_array_equal(a.pixels, b.pixels)
        np.testing.assert_array_equal(a.valid, b.valid)
        np.testing.assert_array_equal(a.normals, b.normals)
        assert a.domain == b.domain and a.metadata["filters"] == b.metadata["filters"]


def test_zarr_store_shapes_records_and_items(client, inputs, tmp_path):
    store = tmp_path / "data.zarr"
    table = batch.convert([inputs], tmp_path / "out", client=client, zarr=store, resolution=RES)
    zarr = pytest.importorskip("zarr")
    group = zarr.open_group(str(store), mode="r")
    assert group["positions"].shape == (5, RES, RES, 3) and group["positions"].dtype == np.float32
    assert group["mask"].shape == (5, RES, RES) and group["normals"].shape == (5, RES, RES, 3)
    records = batch.store_records(store)
    for i, row in enumerate(table.itertuples()):
        assert (records[i] is not None) == (row.status == "ok")
        if row.status == "ok":
            assert records[i]["source"] == row.input and records[i]["psnr_db"] == pytest.approx(row.psnr_db)
            item = batch.read_item(store, i)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")                     # the cube's UV seams, said in the manifest
                ref = geoimg.mesh_to_images(row.input, RES, component="largest")[0]
            np.testing.assert_array_equal(item.pixels[item.valid], ref.pixels[ref.valid].astype(np.float32))
            assert item.domain == ref.domain
        else:
            assert not group["mask"][i].any()
            with pytest.raises(geoimg.InputError, match="not written"):
                batch.read_item(store, i)
    assert not list((tmp_path / "out").rglob("*.exr"))                 # the images went into the store
    again = batch.convert([inputs], tmp_path / "out", client=client, zarr=store, resolution=RES)
    assert again.attrs["summary"]["skipped"] == 5
    with pytest.raises(geoimg.InputError, match="another batch"):      # same store, other options
        batch.convert([inputs], tmp_path / "out", client=client, zarr=store, resolution=RES,
                      weights=geoimg.CoverageWeights(s=2.0))


def test_a_scheduler_that_cannot_be_reached_leaves_nothing(inputs, tmp_path, monkeypatch):
    from geoimg.batch import _engine
    monkeypatch.setattr(_engine, "CONNECT_TIMEOUT", 2)               # not the 30 s a real network gets
    distributed_ = pytest.importorskip("distributed")
    with distributed_.LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster:
        address = cluster.scheduler_address
    with pytest.raises(OSError):                                   # the scheduler is gone: refused to connect
        batch.convert([inputs / "a"], tmp_path / "out", scheduler=address, resolution=RES, zarr=tmp_path / "z.zarr")
    assert not (tmp_path / "out").exists() and not (tmp_path / "z.zarr").exists()


def test_a_scheduler_address_runs_the_same_tasks(client, inputs, tmp_path):
    table = batch.convert([inputs / "a" / "sphere.obj"], tmp_path / "out", scheduler=client.scheduler.address,
                          resolution=RES)
    assert list(table.status) == ["ok"] and (tmp_path / "out" / "sphere.exr").is_file()


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(zarr="x.zarr"), geoimg.InputError, "resolution"),
    (dict(zarr="x.zarr", resolution=33, component="all"), geoimg.InputError, "one image per input"),
    (dict(s=0.0), geoimg.InputError, "s: expected"),
    (dict(s="soft"), geoimg.InputError, "s: coverage weights take one number"),      # deprecated, still checked
    (dict(weights="soft"), geoimg.InputError, "weights: expected one of"),
    (dict(weights=geoimg.GaussianWeights(s=np.ones(3))), geoimg.InputTypeError, "a batch takes one number"),
    (dict(method="magic"), geoimg.InputError, "method"),
    (dict(resolution=1), geoimg.InputError, "resolution"),
    (dict(steps=[("blur", [3])]), geoimg.InputError, "unknown filter step"),
    (dict(steps=[("mean", [])]), geoimg.InputError, "takes 1 value"),
    (dict(quads_format="stl"), geoimg.InputError, "quads_format"),
    (dict(colour="red"), geoimg.InputTypeError, "colour"),
    (dict(memory_limit="lots"), geoimg.InputError, "memory_limit: expected a size"),
    (dict(harmonics=0), geoimg.InputError, "lmax"),
    (dict(harmonics=4, method="heightfield", axis="z"), geoimg.InputError, "harmonics: the spectrum"),
    (dict(harmonics=4, zarr="s.zarr", resolution=33), geoimg.InputError, "Zarr"),
])
def test_bad_options_are_refused_before_any_work(inputs, tmp_path, kwargs, error, match):
    with pytest.raises(error, match=match):
        batch.convert([inputs], tmp_path / "out", client=object(), **kwargs)    # no client is ever asked
    assert not (tmp_path / "out").exists()


def test_bad_paths_are_refused_before_any_work(inputs, tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file or folder"):
        batch.convert([tmp_path / "nowhere"], tmp_path / "out", client=object())
    (tmp_path / "empty").mkdir()
    with pytest.raises(geoimg.InputError, match="no mesh files"):
        batch.convert([tmp_path / "empty"], tmp_path / "out", client=object())
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "thesis.tex").write_text("precious")
    with pytest.raises(FileExistsError, match="no geoimg batch wrote"):
        batch.convert([inputs], foreign, client=object())
    with pytest.raises(geoimg.InputError, match="inside the input folder"):
        batch.convert([inputs], inputs / "a" / "images", client=object())
    shutil.copy(inputs / "a" / "sphere.obj", inputs / "a" / "sphere_quads.obj")
    with pytest.raises(FileExistsError, match="would replace an input"):
        batch.convert([inputs / "a" / "sphere.obj", inputs / "a" / "sphere_quads.obj"], inputs / "a", client=object(),
                      quads=True, force=True)
    (tmp_path / "file").write_text("")
    with pytest.raises(FileExistsError, match="is a file"):
        batch.convert([inputs], tmp_path / "file", client=object())
    assert (foreign / "thesis.tex").read_text() == "precious"


def test_globs_and_output_names(inputs):
    found = batch.find_inputs([str(inputs / "**" / "*.obj"), inputs / "a" / "sphere.obj"])
    assert [p.relative_to(inputs).as_posix() for p in found] == [
        "a/cube_no_bottom.obj", "a/sphere.obj", "b/bad.obj", "b/sphere.obj"]
    assert [s.as_posix() for s in batch.output_stems(found)] == ["a/cube_no_bottom", "a/sphere", "b/bad", "b/sphere"]


def test_a_job_that_cannot_write_is_failed_not_raised(tmp_path):
    src = str(DATA / "sphere.obj")
    st = os.stat(src)
    opts = batch.ConvertOptions(resolution=17, psnr=False)
    (tmp_path / "a_file").write_text("")
    row = run_job(Job(src, str(tmp_path / "a_file" / "sphere"), opts, "h", st.st_size, st.st_mtime_ns))
    assert row["status"] == "failed" and row["message"].startswith("FileExistsError")
    assert row["t_parametrize"] > 0 and row["faces"] == 1280


def _batch_command(*args):
    return [sys.executable, "-m", "geoimg", "batch", *map(str, args)]


def test_cli_exit_status_summary_and_usage_errors(inputs, tmp_path, capsys):
    out = tmp_path / "out"
    run = subprocess.run(_batch_command(inputs / "a", "-o", out, "--res", RES, "--workers", 1),
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "2 inputs: 2 converted (0 of them poor), 0 refused, 0 failed" in run.stdout
    run = subprocess.run(_batch_command(inputs, "-o", out, "--res", RES, "--workers", 1, "--force"),
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 1
    assert "2 of 5 inputs were not converted" in run.stderr and "bad.obj: refused:" in run.stderr
    # a rerun skips every input and reports what the manifest says: the refusals stay refusals, exit 1
    run = subprocess.run(_batch_command(inputs, "-o", out, "--res", RES, "--workers", 1),
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 1, run.stdout
    assert "5 inputs: 3 converted (0 of them poor), 2 refused, 0 failed (5 of these finished by an earlier run)" \
        in run.stdout
    assert "2 of 5 inputs were not converted" in run.stderr and "bad.obj: refused:" in run.stderr
    for args in (["--zarr", tmp_path / "z.zarr"], ["--quads", "stl"], ["--workers", "0"], ["--mean", "x"]):
        try:                                     # in this process: the function the program calls
            status = cli.main(["batch", str(inputs), "-o", str(tmp_path / "o2"), *map(str, args)])
        except SystemExit as e:                  # argparse's own usage errors
            status = e.code
        err = capsys.readouterr().err
        assert status == 2 and "Traceback" not in err and "error" in err and not (tmp_path / "o2").exists()


@pytest.mark.parametrize("how", ["SIGTERM to the batch", "Ctrl-C to every process"])
def test_an_interrupted_run_leaves_nothing_partial_and_resumes(tmp_path, how):
    root = tmp_path / "in"
    root.mkdir()
    copies = 4                  # enough to interrupt the run after its first row, before its last
    for k in range(copies):
        shutil.copy(data_file("spot_low_resolution.obj"), root / f"spot{k}.obj")   # 1.3 s a row (Spot: 2.4)
    out = tmp_path / "out"
    proc = subprocess.Popen(_batch_command(root, "-o", out, "--res", 129, "--workers", 1, "--quads", "-q"),
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, start_new_session=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))   # as in a terminal
    manifest = out / batch.MANIFEST_NAME
    deadline = time.time() + 240
    while time.time() < deadline and proc.poll() is None:
        if manifest.is_file() and len(batch.read_manifest(manifest)) >= 1:
            break
        time.sleep(0.05)
    assert proc.poll() is None, "the batch ended before it could be interrupted"
    if how.startswith("SIGTERM"):
        proc.send_signal(signal.SIGTERM)
    else:
        os.killpg(proc.pid, signal.SIGINT)        # a terminal's Ctrl-C reaches the workers too
    assert proc.wait(timeout=120) == 128 + (signal.SIGTERM if how.startswith("SIGTERM") else signal.SIGINT)
    err = proc.stderr.read()
    assert "Traceback" not in err and (how.startswith("SIGTERM") or err.strip() == "geoimg batch: interrupted")
    assert not [p for p in out.rglob("*") if ".tmp" in p.name or p.name.endswith(".partial")]
    rows = batch.read_manifest(manifest)
    assert 1 <= len(rows) < copies and all(r["status"] == "ok" for r in rows.values())
    for r in rows.values():
        for f in r["outputs"].split(";"):
            assert Path(f).is_file()
        geoimg.load_image(r["outputs"].split(";")[0])
    for exr in out.glob("*.exr"):                          # every image there is whole
        geoimg.load_image(exr)
    run = subprocess.run(_batch_command(root, "-o", out, "--res", 129, "--workers", 1, "--quads"),
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert f"({len(rows)} of these finished by an earlier run)" in run.stdout
    assert len(batch.read_manifest(manifest)) == copies and len(list(out.glob("*.exr"))) == copies


class _Stream:
    def __init__(self, tty):
        self.tty, self.text = tty, ""

    def isatty(self):
        return self.tty

    def write(self, s):
        self.text += s

    def flush(self):
        pass


def _counts(done, elapsed, total=10):
    return {
        "done": done,
        "ok": done,
        "poor": 0,
        "refused": 0,
        "failed": 0,
        "skipped": 0,
        "total": total,
        "elapsed": elapsed,
        "per_minute": 60 * done / elapsed if elapsed else 0.0,
        "eta": (total - done) * elapsed / done if done else None,
    }


def test_progress_lines_off_a_terminal_a_bar_on_one_and_nothing_when_quiet():
    logs = _Stream(tty=False)
    p = _commands.BatchProgress(every=5.0, stream=logs)
    for done, t in ((0, 0.0), (1, 1.0), (2, 4.0), (3, 5.5), (4, 7.0), (10, 12.0)):
        p(_counts(done, t))
    lines = logs.text.splitlines()
    assert [line.split("]")[0] for line in lines] == ["[0s", "[6s", "[12s"]       # every 5 s, and the end
    assert lines[1].endswith("3/10 done, 0 poor, 0 refused, 0 failed, 32.7/min, 13s left")
    assert lines[-1].startswith("[12s] 10/10 done") and "left" not in lines[-1]
    term = _Stream(tty=True)
    p = _commands.BatchProgress(stream=term)
    p(_counts(5, 10.0))
    p(_counts(10, 20.0))
    assert term.text.startswith("\r[###############...............] 5/10") and term.text.endswith("\n")
    quiet = _Stream(tty=True)
    _commands.BatchProgress(quiet=True, stream=quiet)(_counts(5, 1.0))
    assert quiet.text == ""


def test_zarr_items_keep_their_colours(tmp_path):
    from geoimg.batch._store import open_store, write_item
    pixels = np.random.default_rng(0).random((5, 5, 3)).astype(np.float32)
    coloured = geoimg.GeometryImage(pixels, colors=np.full((5, 5, 3), 0.25, np.float32))
    store = tmp_path / "s.zarr"
    open_store(store, ["a", "b"], 5, False, "h", colors=True)
    write_item(store, 0, coloured)
    write_item(store, 1, geoimg.GeometryImage(pixels))
    batch._store.write_records(store, {i: {"shape": [5, 5], "domain": "planar", "metadata": {}, "colors": i == 0}
                                        for i in range(2)})
    assert np.array_equal(batch.read_item(store, 0).colors, coloured.colors)
    assert batch.read_item(store, 1).colors is None


def test_an_image_far_from_its_input_is_marked_poor_and_counted(inputs, tmp_path):
    """With a PSNR bar no image can reach the converted inputs are 'poor': written, but counted apart, listed
    with the reason, exit 1; a rerun keeps them poor. Bad bars are refused before any work."""
    out = tmp_path / "out"
    run = subprocess.run(_batch_command(inputs / "a", "-o", out, "--res", RES, "--workers", 1, "--min-psnr", 500),
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 1, run.stderr
    assert "2 inputs: 2 converted (2 of them poor), 0 refused, 0 failed" in run.stdout
    assert "poor: far from the input: PSNR" in run.stderr and "< 500" in run.stderr
    rows = batch.read_manifest(out / batch.MANIFEST_NAME)
    assert {r["status"] for r in rows.values()} == {"poor"} and all((out / "a").glob("*.exr"))
    run = subprocess.run(_batch_command(inputs / "a", "-o", out, "--res", RES, "--workers", 1, "--min-psnr", 500),
                         capture_output=True, text=True, timeout=300)
    assert (
        run.returncode == 1
        and "(2 of them poor)" in run.stdout
        and "2 of these finished by an earlier run" in run.stdout
    )
    for bad in (["--min-psnr", "nan"], ["--max-hausdorff", "0"], ["--max-hausdorff", "x"]):
        run = subprocess.run(_batch_command(inputs / "a", "-o", tmp_path / "o2", *bad), capture_output=True,
                             text=True, timeout=60)
        assert run.returncode == 2 and "Traceback" not in run.stderr and not (tmp_path / "o2").exists()


def test_a_row_names_every_pieces_domain_and_keeps_its_warnings_short(tmp_path):
    from geoimg.batch._task import WARNINGS_CELL
    # a closed sphere and many loose triangles far from it: pieces of two domains, a long list of warnings
    sphere = geoimg.load_mesh(DATA / "sphere.obj")
    tri = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.2]]) * 0.1
    loose = [tri + [3 + k, 0, 0] for k in range(40)]
    v = np.vstack([sphere.vertices] + loose)
    n = sphere.n_vertices
    f = np.vstack([sphere.faces] + [np.array([[0, 1, 2]]) + n + 3 * k for k in range(40)])
    src = write(geoimg.Mesh(v, f), tmp_path / "many.ply")
    st = os.stat(src)
    opts = batch.ConvertOptions(resolution=17, psnr=False)
    row = run_job(Job(str(src), str(tmp_path / "out" / "many"), opts, "h", st.st_size, st.st_mtime_ns))
    assert row["status"] == "ok" and row["pieces"] == 41
    domains = row["domain"].split()
    assert len(domains) == 41 and domains[0] == "octahedral" and set(domains[1:]) == {"planar"}
    assert len(row["warnings"]) <= WARNINGS_CELL and "41 separate pieces" in row["warnings"]
    assert "and 29 more" in row["warnings"]


def test_numpy_scalars_are_taken_as_the_numbers_they_hold():
    from geoimg.batch import BatchOptions
    given = BatchOptions(resolution=np.int64(65), weights=geoimg.GaussianWeights(s=np.float32(2.0), n=np.int32(12)),
                         nsr=np.float32(0.01), min_psnr=np.float32(40), max_hausdorff=np.float64(0.05))
    plain = BatchOptions(resolution=65, weights=geoimg.GaussianWeights(s=2.0, n=12), nsr=float(np.float32(0.01)),
                         min_psnr=40.0, max_hausdorff=0.05)
    assert given == plain and given.digest() == plain.digest() and type(given.nsr) is float


def test_harmonics_table_rows_are_the_normalized_coefficient_files(client, tmp_path):
    from geoimg.spectrum import coefficient_columns, harmonics_from_row, load_harmonics
    root = tmp_path / "in"
    root.mkdir()
    for name in ("spot_low_resolution.obj", "torus.obj", "sphere.obj"):
        shutil.copy(data_file(name), root / name)
    out = tmp_path / "out"
    table = batch.convert([root], out, client=client, resolution=RES, harmonics=4, psnr=False)
    status = dict(zip(table["input"].map(lambda p: Path(p).name), table["status"]))
    assert status == {"sphere.obj": "ok", "spot_low_resolution.obj": "ok", "torus.obj": "refused"}
    assert "genus-0" in table.loc[table["input"].str.endswith("torus.obj"), "message"].item()
    assert not (out / "torus_sh.npz").exists() and not (out / "torus.exr").exists()   # refused before converting
    for kind in ("csv", "parquet"):
        coeffs = pd.read_csv(out / "harmonics.csv") if kind == "csv" else pd.read_parquet(
            out / "harmonics.parquet")
        assert list(coeffs.columns) == ["input", "lmax", "psnr_db"] + coefficient_columns(4)
        assert [Path(p).name for p in coeffs["input"]] == ["sphere.obj", "spot_low_resolution.obj"]
        for row in coeffs.to_dict("records"):
            stem = Path(row["input"]).stem
            stored = load_harmonics(out / f"{stem}_sh.npz")
            assert stored.metadata["source"] == f"{stem}.obj"
            expected = stored.normalized().coeffs
            assert np.allclose(harmonics_from_row(row).coeffs, expected, rtol=0, atol=1e-12)
    first = (out / "harmonics.csv").read_bytes()
    again = batch.convert([root], out, client=client, resolution=RES, harmonics=4, psnr=False)
    assert again.attrs["summary"]["skipped"] == 3 and (out / "harmonics.csv").read_bytes() == first
