import numpy as np
import pytest

import geoimg
from geoimg.cli import main

from helpers import DATA, MOUNTAIN
import meshes
from meshes import l_hexagon, mobius, write


def test_image_mesh_info_pipeline(tmp_path, capsys):
    exr, obj = tmp_path / "m.exr", tmp_path / "m.obj"
    assert main(["image", str(MOUNTAIN), "-o", str(exr), "--res", "64", "--s", "2",
                 "--preview", str(tmp_path / "m.png")]) == 0
    assert main(["mesh", str(exr), "-o", str(obj)]) == 0
    quads = geoimg.load_mesh(obj)
    assert quads.n_faces == 63 * 63 and np.all(quads.face_sizes == 4)
    src = geoimg.load_mesh(MOUNTAIN)
    lo, hi = src.vertices.min(axis=0), src.vertices.max(axis=0)
    qlo, qhi = quads.vertices.min(axis=0), quads.vertices.max(axis=0)
    # the x-z footprint is the terrain's exactly; heights may overshoot a little (a mean of planes
    # is not bound to the vertices' hull), here by under 1% of the height range
    assert np.allclose([qlo[0], qlo[2], qhi[0], qhi[2]], [lo[0], lo[2], hi[0], hi[2]], atol=1e-6 * (hi - lo).max())
    assert np.all(np.abs([qlo[1] - lo[1], qhi[1] - hi[1]]) < 0.01 * (hi[1] - lo[1]))
    assert main(["info", str(exr)]) == 0
    out = capsys.readouterr().out
    assert "64 x 64" in out and "source: mountain.obj" in out
    assert main(["info", str(obj)]) == 0
    out = capsys.readouterr().out
    assert "3969 quad" in out and "open surface with 1 boundary loop (a disk)" in out


def test_errors_exit_2_with_a_message(tmp_path, capsys):
    strip = write(mobius(), tmp_path / "mobius.obj")
    assert main(["image", strip, "-o", str(tmp_path / "b.exr")]) == 2
    assert "not orientable" in capsys.readouterr().err and not (tmp_path / "b.exr").exists()
    assert main(["mesh", str(tmp_path / "none.exr"), "-o", str(tmp_path / "x.obj")]) == 2
    assert "no image file" in capsys.readouterr().err
    (tmp_path / "x.obj").write_text("keep")
    exr = tmp_path / "m.exr"
    main(["image", str(MOUNTAIN), "-o", str(exr), "--res", "16"])
    assert main(["mesh", str(exr), "-o", str(tmp_path / "x.obj")]) == 2
    err = capsys.readouterr().err                     # the command line's words, not the API's
    assert "exists; add --force to replace it" in err and "overwrite=True" not in err
    assert (tmp_path / "x.obj").read_text() == "keep"
    assert main(["mesh", str(exr), "-o", str(tmp_path / "x.obj"), "--force"]) == 0
    with pytest.raises(SystemExit):
        main(["image", str(MOUNTAIN), "-o", str(exr), "--s", "-1"])


@pytest.mark.parametrize("value", ["abc", "0", "-5", "nan", ""])
def test_a_positive_option_says_what_it_expected_for_any_bad_value(tmp_path, capsys, value):
    # argparse names the checking function ("invalid check value") unless the check says it in its own words
    with pytest.raises(SystemExit) as stop:
        main(["compress", str(MOUNTAIN), "-o", str(tmp_path / "m.jp2"), "--bytes", value])
    err = capsys.readouterr().err.strip()
    assert stop.value.code == 2 and f"expected a positive number, got {value}" in err and "check" not in err
    assert not (tmp_path / "m.jp2").exists()


def test_demo_writes_its_files(tmp_path, capsys):
    assert main(["demo", "-o", str(tmp_path), "--res", "48"]) == 0
    out = capsys.readouterr().out
    psnr = float(out.split("quad mesh to input mesh: PSNR ")[1].split(" dB")[0])
    assert psnr > 40                                        # the 48^2 quads of the s = 2 surface are close
    names = {p.name for p in tmp_path.iterdir()}
    assert {"mountain.exr", "mountain_preview.png", "mountain_quads.obj", "mountain_mean_curvature.png"} <= names
    pictures = {"mountain_render.png", "mountain_smoothed_render.png"}
    assert pictures <= names or "pictures skipped" in out      # no headless OpenGL: said, not silent


def test_quiet_prints_nothing(tmp_path, capsys):
    assert main(["image", str(MOUNTAIN), "-o", str(tmp_path / "q.exr"), "--res", "16", "--quiet"]) == 0
    assert main(["mesh", str(tmp_path / "q.exr"), "-o", str(tmp_path / "q.ply"), "-q"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""


def test_boundary_option_for_disk_meshes(tmp_path, capsys):
    v = [[0, 0, 0], [2, 0, 0], [3, 1, 0], [2, 2, 0], [0, 2, 0], [1.2, 1, 0]]     # a convex pentagon fan
    pentagon = geoimg.save_mesh(geoimg.Mesh(v, [[0, 1, 5], [1, 2, 5], [2, 3, 5], [3, 4, 5], [4, 0, 5]]),
                                tmp_path / "p.obj")
    for flag, shape in (("keep", (22, 33)), ("square", (33, 33))):
        out = tmp_path / f"{flag}.exr"
        assert main(["image", str(pentagon), "-o", str(out), "--method", "disk", "--boundary", flag,
                     "--res", "33", "-q"]) == 0
        assert geoimg.load_image(out).shape == shape     # kept: the pentagon's 3 x 2 proportions
    capsys.readouterr()
    ell = write(l_hexagon(), tmp_path / "L.off")
    assert main(["image", str(ell), "-o", str(tmp_path / "l.exr"), "--method", "disk", "--boundary", "keep"]) == 2
    assert "reflex" in capsys.readouterr().err


@pytest.mark.slow
def test_balance_option_for_disk_meshes(tmp_path, capsys):
    finger = write(meshes.finger(), tmp_path / "finger.obj")
    flags = ("area", "slim", "none")
    for flag in flags:      # a disk asked for: unbalanced, this one starves, and auto would take charts
        assert main(["image", finger, "-o", str(tmp_path / f"{flag}.exr"), "--method", "disk", "--balance", flag,
                     "--res", "33", "-q"]) == 0
    assert main(["image", finger, "-o", str(tmp_path / "default.exr"), "--res", "33", "-q"]) == 0
    images = {flag: geoimg.load_image(tmp_path / f"{flag}.exr") for flag in flags + ("default",)}
    assert {im.metadata["parametrization"] for im in images.values()} == {"disk"}
    for i, f1 in enumerate(flags):
        for f2 in flags[i + 1:]:
            assert not np.array_equal(images[f1].pixels, images[f2].pixels), (f1, f2)
    np.testing.assert_array_equal(images["default"].pixels, images["area"].pixels)     # area is the default
    with pytest.raises(SystemExit) as e:
        main(["image", finger, "-o", str(tmp_path / "x.exr"), "--balance", "stretch"])
    err = capsys.readouterr().err
    assert e.value.code == 2 and "invalid choice: 'stretch'" in err and not (tmp_path / "x.exr").exists()
    assert len(err.strip().splitlines()) == 1                       # one line, as every geoimg error
    for bad in ([], ["", "AREA"]):                                   # missing, empty, another case
        for value in bad or [None]:
            with pytest.raises(SystemExit) as e:
                main(["image", finger, "-o", str(tmp_path / "x.exr"), "--balance"] + ([] if value is None else [value]))
            err = capsys.readouterr().err
            assert e.value.code == 2 and len(err.strip().splitlines()) == 1 and "--balance" in err
            assert not (tmp_path / "x.exr").exists()


@pytest.mark.slow
def test_os_errors_are_one_line_and_a_closed_pipe_is_quiet(tmp_path, capsys, monkeypatch):
    folder = tmp_path / "a_folder.exr"
    folder.mkdir()
    assert main(["image", str(MOUNTAIN), "-o", str(folder), "--res", "9", "--force"]) == 2
    assert "error:" in capsys.readouterr().err
    under_a_file = tmp_path / "file.txt"
    under_a_file.write_text("x")
    assert main(["image", str(MOUNTAIN), "-o", str(under_a_file / "x.exr"), "--res", "9"]) == 2
    assert "error:" in capsys.readouterr().err
    exr = tmp_path / "m.exr"
    assert main(["image", str(MOUNTAIN), "-o", str(exr), "--res", "9", "-q"]) == 0

    class ClosedPipe:
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def flush(self):
            pass

    monkeypatch.setattr("sys.stdout", ClosedPipe())
    assert main(["info", str(exr)]) == 0
    assert capsys.readouterr().err == ""


def test_outputs_are_all_or_none_and_checked_before_the_work(tmp_path, capsys):
    exr = tmp_path / "m.exr"
    assert main(["image", str(MOUNTAIN), "-o", str(exr), "--res", "9", "-q"]) == 0
    (tmp_path / "c_mean.png").write_text("mine")                      # the 4th of 5 curvature outputs
    assert main(["curvature", str(exr), "-o", str(tmp_path / "c")]) == 2
    assert "c_mean.png exists" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c_mean.png", "m.exr"]   # nothing else, no temp
    (tmp_path / "m.png").write_text("mine")
    assert main(["image", str(MOUNTAIN), "-o", str(tmp_path / "n.exr"), "--preview", str(tmp_path / "m.png"),
                 "--res", "9"]) == 2
    assert not (tmp_path / "n.exr").exists() and (tmp_path / "m.png").read_text() == "mine"
    (tmp_path / "x.glb").write_text("mine")
    assert main(["morph", str(exr), str(exr), "-o", str(tmp_path / "x.glb"), "--frames", "2"]) == 2
    assert "x.glb exists" in capsys.readouterr().err


def test_the_demo_writes_only_into_its_own_folder(tmp_path, capsys):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("keep")
    assert main(["demo", "-o", str(mine), "--res", "9", "-q"]) == 2
    assert "not written by geoimg demo" in capsys.readouterr().err and sorted(p.name for p in mine.iterdir()) == [
        "notes.txt"
    ]
    assert main(["demo", "-o", str(tmp_path / "d"), "--res", "9", "-q"]) == 0
    assert main(["demo", "-o", str(tmp_path / "d"), "--res", "9", "-q"]) == 0      # again: its own folder


def test_sigterm_removes_the_file_being_written(tmp_path):
    import os
    import signal
    from geoimg._atomic import atomic_path
    from geoimg.cli import _terminated
    previous = signal.signal(signal.SIGTERM, _terminated)
    try:
        with pytest.raises(SystemExit):
            with atomic_path(tmp_path / "half.exr") as tmp:
                tmp.write_bytes(b"half")
                os.kill(os.getpid(), signal.SIGTERM)
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert list(tmp_path.iterdir()) == []


def test_version_module_entry_and_one_line_warnings(tmp_path, capsys):
    import subprocess
    import sys
    with pytest.raises(SystemExit):
        main(["--version"])
    assert capsys.readouterr().out.strip() == f"geoimg {geoimg.__version__}"
    run = subprocess.run([sys.executable, "-m", "geoimg", "--version"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0 and run.stdout.strip() == f"geoimg {geoimg.__version__}"
    seams = tmp_path / "mixed.obj"                  # colours on one 'v' line only give a warning
    seams.write_text("v 0 0 0 1 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\nf 1 2 3 4\n")
    seams = str(seams)
    assert main(["image", seams, "-o", str(tmp_path / "s.exr"), "--res", "9"]) == 0
    err = capsys.readouterr().err
    assert err.startswith("geoimg image: warning: ") and "some 'v' lines have colours" in err and ".py:" not in err
    assert main(["image", seams, "-o", str(tmp_path / "t.exr"), "--res", "9", "-q"]) == 0
    assert capsys.readouterr().err == ""


def test_reprs_are_short():
    m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3], [0, 1, 2, -1]])
    assert repr(m) == "Mesh(4 vertices, 2 faces: 1 triangles, 1 quads)"
    img = geoimg.GeometryImage(np.zeros((300, 400, 3), np.float32), metadata={"s": 1.0})
    assert repr(img) == ("GeometryImage(400 x 300 float32, PlanarDomain(orientation=1, extent=(1.0, 1.0)), "
                         "metadata keys ['s'])")


def test_the_demo_is_quiet_when_asked(tmp_path, capsys):
    assert main(["demo", "-o", str(tmp_path / "d"), "--res", "9", "-q"]) == 0
    assert capsys.readouterr().out == ""


def test_every_option_has_help_and_shows_its_default():
    import argparse
    from geoimg.cli import build_parser
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    missing = []
    for command, parser in sub.choices.items():
        for action in parser._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            if not action.help:
                missing.append(f"{command} {action.option_strings or action.dest}: no help")
            elif action.option_strings and action.default not in (None, False) \
                    and "default" not in action.help:
                missing.append(f"{command} {action.option_strings}: default {action.default!r} not shown")
    assert not missing, "\n".join(missing)


@pytest.mark.parametrize("argv, message", [
    (["image", "M", "-o", "out.txt"], "out.txt: the geometry image must be named *.exr or *.npz"),
    (["image", "M", "-o", "out.exr", "--preview", "p.jpg"], "p.jpg: the preview must be named *.png"),
    (["image", "M", "-o", "nowhere/out.exr"], "folder nowhere does not exist"),
    (["mesh", "I", "-o", "q.xyz"], "q.xyz: the quad mesh must be named"),
    (["filter", "I", "-o", "f.png", "--mean", "3"], "f.png: the geometry image must be named"),
    (["filter", "I", "-o", "f.exr", "--mean", "3", "--mesh", "f.xyz"], "f.xyz: the quad mesh must be named"),
    (["render", "I", "-o", "r.jpg"], "r.jpg: the picture must be named *.png"),
    (["morph", "I", "I", "-o", "m.gltf"], "m.gltf: the glTF morph must be named *.glb"),
    (["morph", "I", "I", "--gif", "m.png"], "m.png: the GIF must be named *.gif"),
])
def test_outputs_are_checked_before_any_work(tmp_path, monkeypatch, capsys, argv, message):
    import geoimg._commands as commands
    import geoimg._convert as convert
    import geoimg.animation as animation

    def no_work(*args, **kwargs):
        raise AssertionError("work started before the outputs were checked")
    for module, name in ((convert, "mesh_to_images"), (commands, "load_image"), (commands, "load_mesh"),
                         (animation, "morph")):
        monkeypatch.setattr(module, name, no_work)
    monkeypatch.chdir(tmp_path)
    argv = [str(MOUNTAIN) if a == "M" else "in.exr" if a == "I" else a for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and ".tmp" not in err and len(err.strip().splitlines()) == 1


@pytest.mark.slow
def test_progress_off_a_terminal_only_when_asked(tmp_path, capsys):
    out = tmp_path / "m.exr"
    assert main(["image", str(MOUNTAIN), "-o", str(out), "--res", "16"]) == 0
    assert capsys.readouterr().err == ""                          # a pipe or a log: quiet by default
    assert main(["image", str(MOUNTAIN), "-o", str(out), "--res", "16", "--force", "--progress"]) == 0
    err = capsys.readouterr().err
    assert "parametrizing" in err and "sampling 16 pixels" in err and err.startswith("[")
    assert main(["image", str(MOUNTAIN), "-o", str(out), "--res", "16", "--force", "--progress", "-q"]) == 0
    assert capsys.readouterr().err == ""                          # quiet wins
    frames = tmp_path / "frames"
    assert main(["morph", str(out), str(out), "--frames", "20", "--frames-dir", str(frames), "--progress", "-q"]) == 0
    assert capsys.readouterr().err == ""
    assert main(["morph", str(out), str(out), "--frames", "20", "--frames-dir", str(frames), "--progress",
                 "--force"]) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "obj frames" in line]
    assert lines == [f"{k}/20 obj frames" for k in (1, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20)]   # each tenth


def test_colours_travel_from_a_textured_obj_to_a_textured_quad_mesh(tmp_path, capsys):
    from helpers import textured_spot
    obj = str(textured_spot(tmp_path))
    exr, plain = tmp_path / "s.exr", tmp_path / "p.exr"
    assert main(["image", obj, "-o", str(exr), "--res", "17"]) == 0
    assert main(["image", obj, "-o", str(plain), "--res", "17", "--no-colors"]) == 0
    assert geoimg.load_image(exr).colors.shape == (17, 17, 3) and geoimg.load_image(plain).colors is None
    capsys.readouterr()
    assert main(["info", str(exr)]) == 0 and "colours yes" in capsys.readouterr().out
    assert main(["info", obj]) == 0 and "1024 x 1024 texture" in capsys.readouterr().out
    assert main(["mesh", str(exr), "-o", str(tmp_path / "q.obj")]) == 0
    assert "texture q.png beside it" in capsys.readouterr().out
    q = geoimg.load_mesh(tmp_path / "q.obj")
    assert q.texture.shape == (17, 17, 3) and q.colors is not None
    (tmp_path / "r.mtl").write_text("someone else's")               # a file in the way: nothing written
    assert main(["mesh", str(exr), "-o", str(tmp_path / "r.obj")]) == 2
    assert "r.mtl exists" in capsys.readouterr().err and not (tmp_path / "r.obj").exists()


@pytest.mark.parametrize("step, message", [(["--median", "4"], "odd"), (["--tv", "-1"], "weight"),
                                           (["--nlmeans", "0"], "h"), (["--tv", "much"], "expected float")])
def test_denoising_steps_refuse_bad_values_in_one_line(tmp_path, capsys, step, message):
    exr = tmp_path / "m.exr"
    assert main(["image", str(MOUNTAIN), "-o", str(exr), "--res", "9", "-q"]) == 0
    code = None
    try:
        code = main(["filter", str(exr), "-o", str(tmp_path / "f.exr"), *step])
    except SystemExit as e:          # argparse's own refusal of a non-number
        code = e.code
    assert code == 2 and message in capsys.readouterr().err and not (tmp_path / "f.exr").exists()


def test_denoising_steps_run_from_the_command_line(tmp_path):
    exr = tmp_path / "m.exr"
    assert main(["image", str(MOUNTAIN), "-o", str(exr), "--res", "17", "-q"]) == 0
    assert main(["filter", str(exr), "-o", str(tmp_path / "f.exr"), "--median", "3", "--tv", "0.5", "--nlmeans",
                 "0.5", "-q"]) == 0
    out = geoimg.load_image(tmp_path / "f.exr")
    assert [f.split("(")[0] for f in out.metadata["filters"]] == ["median_filter", "denoise_tv", "denoise_nl_means"]


def test_every_command_shows_examples_that_parse():
    import shlex
    from geoimg.cli import EXAMPLES, build_parser
    parser = build_parser()
    commands = [a for a in parser._actions if isinstance(a, __import__("argparse")._SubParsersAction)][0].choices
    assert sorted(commands) == sorted(EXAMPLES)
    for name, examples in EXAMPLES.items():
        assert "examples:" in commands[name].format_help() and len(examples) >= 1
        for example in examples:
            argv = shlex.split(example.split("#")[0])
            assert argv[0] == "geoimg" and argv[1] == name
            parser.parse_args(argv[1:])                 # exits (fails the test) on an option that does not exist


def test_curvature_into_a_folder_takes_the_inputs_name(tmp_path, capsys, monkeypatch):
    exr = tmp_path / "terrain.exr"
    assert main(["image", str(MOUNTAIN), "-o", str(exr), "--res", "17", "-q"]) == 0
    (tmp_path / "maps").mkdir()
    monkeypatch.chdir(tmp_path / "maps")
    assert main(["curvature", str(exr), "-o", ".", "-q"]) == 0          # was a traceback: '.' has an empty name
    assert main(["curvature", str(exr), "-o", str(tmp_path / "maps") + "/", "-q", "--force"]) == 0
    assert sorted(p.name for p in (tmp_path / "maps").iterdir()) == [
        "terrain_gaussian.exr", "terrain_gaussian.png", "terrain_mean.exr", "terrain_mean.png", "terrain_normals.png"]


def test_an_axis_with_a_method_that_takes_none_is_refused(tmp_path, capsys):
    sphere = str(DATA / "sphere.obj")
    for argv in (["image", sphere, "-o", str(tmp_path / "s.exr"), "--axis", "z", "--method", "sphere"],
                 ["batch", sphere, "-o", str(tmp_path / "out"), "--axis", "z", "--method", "disk"]):
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert "axis: the up axis of a height field" in err and len(err.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(geoimg.ParametrizationError, match="method 'uv' takes none"):
        geoimg.parametrize(geoimg.load_mesh(MOUNTAIN), "uv", axis="y")


def test_a_misspelled_option_points_to_its_commands_help(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["image", str(MOUNTAIN), "-o", "x.exr", "--rez", "33"])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.strip() == ("geoimg image: error: unrecognized arguments: --rez 33; did you mean --res? "
                           "(see geoimg image --help)")


def test_help_lists_every_image_format(capsys):
    with pytest.raises(SystemExit):
        main(["image", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "output geometry image (.exr, .npz, .tif, .npy" in text


def test_a_resolution_the_domain_cannot_have_is_rounded_with_a_note(tmp_path, capsys, monkeypatch):
    """``--res 256`` for a closed mesh: an octahedral image needs an odd side. It was refused after the
    parametrization's work; now the image is 257 and a warning says why. A resolution that is no size at all
    is refused before any work."""
    sphere = str(DATA / "sphere.obj")
    assert main(["image", sphere, "-o", str(tmp_path / "s.exr"), "--res", "32"]) == 0
    err = capsys.readouterr().err
    assert "resolution 32: an octahedral image has an odd side" in err and "sampled at 33" in err
    assert geoimg.load_image(tmp_path / "s.exr").shape == (33, 33)
    import geoimg._convert as convert

    def no_work(*args, **kwargs):
        raise AssertionError("work started before the resolution was checked")
    monkeypatch.setattr(convert, "parametrize", no_work)
    for bad in (1, 2.5, "64", True):
        with pytest.raises(geoimg.InputError, match="resolution: expected a whole number"):
            geoimg.mesh_to_image(sphere, bad)


def test_openimageio_errors_are_one_line(tmp_path, capsys):
    header_only = tmp_path / "h.exr"
    header_only.write_bytes(b"\x76\x2f\x31\x01\x02\x00\x00\x00")
    assert main(["info", str(header_only)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "cannot be read as an image" in err and "EXR Error" not in err
