"""The headless command line: acquire, synth, dpj-info; bad input exits 2 on one line."""

import io
import os
import json
import pickle  # only to build a hostile file; the program itself never unpickles
import subprocess
import sys

import numpy as np
import pytest
from skimage import data, io as skio

from texeditor import DPJ
from texeditor.cli import main


@pytest.fixture
def photo(tmp_path):
    path = tmp_path / "gravel.png"
    skio.imsave(path, data.gravel()[:128, :128], check_contrast=False)
    return path


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_acquire_synth_and_info(tmp_path, photo, capsys):
    dpj_path = tmp_path / "g.dpj"
    code, out, _ = run(capsys, "acquire", photo, "--window", "3x2", "--levels", "4",
                       "--quantizer", "lloyd", "--wrap", "-o", dpj_path)
    assert code == 0 and "non-zero configurations" in out
    dpj = DPJ.load(dpj_path)
    assert dpj.window == (3, 2) and dpj.levels == 4 and dpj.meta["quantizer"] == "lloyd"

    code, out, _ = run(capsys, "synth", dpj_path, "--size", "64x48", "--seed", "3",
                       "-o", tmp_path / "t.npy")
    assert code == 0 and "repairs" in out
    levels = np.load(tmp_path / "t.npy", allow_pickle=False)
    assert levels.shape == (48, 64) and levels.dtype == np.uint8 and levels.max() < 4

    code, _, _ = run(capsys, "synth", dpj_path, "--size", "64x48", "--seed", "3",
                     "-o", tmp_path / "t.png")
    picture = skio.imread(tmp_path / "t.png")
    assert code == 0 and picture.shape[:2] == (48, 64)
    # the PNG shows each level in the photo's palette grey
    assert np.array_equal(picture, dpj.palette[levels][:, :, 0])

    code, out, _ = run(capsys, "dpj-info", dpj_path, "--json")
    report = json.loads(out)
    assert code == 0 and report["is_valid"] and report["horizontal_residual"] < 1e-12


def _hostile_dpjs(tmp_path):
    good = {"levels": 2, "window": [2, 2]}

    def npz(name, **arrays):
        buf = io.BytesIO()
        np.savez(buf, **arrays)
        (tmp_path / name).write_bytes(buf.getvalue())
        return tmp_path / name

    meta = np.array(json.dumps(good))
    yield npz("shape.dpj", configs=np.zeros((2, 2, 3), np.uint8), probs=np.ones(2) / 2, meta=meta)
    yield npz("nan.dpj", configs=np.zeros((1, 2, 2), np.uint8), probs=np.array([np.nan]), meta=meta)
    yield npz("neg.dpj", configs=np.zeros((1, 2, 2), np.uint8), probs=np.array([-1.0]), meta=meta)
    yield npz("level.dpj", configs=np.full((1, 2, 2), 5, np.uint8), probs=np.ones(1), meta=meta)
    yield npz("pickle.dpj", configs=np.zeros((1, 2, 2), np.uint8),
              probs=np.array([{"x": 1}], dtype=object), meta=meta)
    raw = tmp_path / "raw.dpj"
    raw.write_bytes(pickle.dumps({"configs": [1, 2, 3]}))
    yield raw


def test_bad_dpj_files_exit_2_on_one_line_without_output(tmp_path, capsys):
    for path in _hostile_dpjs(tmp_path):
        out = tmp_path / f"{path.stem}.png"
        code, _, err = run(capsys, "synth", path, "--size", "8x8", "-o", out)
        assert code == 2, path
        assert err.count("\n") == 1 and err.startswith("texeditor: error:") and path.name in err
        assert not out.exists()


def test_bad_images_exit_2(tmp_path, photo, capsys):
    text = tmp_path / "notes.png"
    text.write_text("not a picture")
    empty = tmp_path / "empty.png"
    empty.write_bytes(b"")
    flat = tmp_path / "flat.png"
    skio.imsave(flat, np.full((20, 20), 77, np.uint8), check_contrast=False)
    tiny = tmp_path / "tiny.png"
    skio.imsave(tiny, np.arange(4, dtype=np.uint8).reshape(2, 2) * 60, check_contrast=False)
    cases = [
        [text], [empty], [tmp_path / "missing.png"], [flat],
        [tiny, "--window", "3x3"],
        [photo, "--levels", "17"], [photo, "--levels", "1"],
        [photo, "--window", "3by3"], [photo, "--quantizer", "median"],
    ]
    for extra in cases:
        out = tmp_path / "out.dpj"
        code, _, err = run(capsys, "acquire", *extra, "-o", out)
        assert code == 2, extra
        assert err.count("\n") == 1 and "Traceback" not in err, (extra, err)
        assert not out.exists()


def test_bad_synth_parameters_exit_2(tmp_path, photo, capsys):
    dpj_path = tmp_path / "g.dpj"
    assert run(capsys, "acquire", photo, "--window", "2x2", "-o", dpj_path)[0] == 0
    for extra in (["--size", "1x1"], ["--size", "big"], ["--seed", "-4"],
                  ["--seed", str(2**64)]):
        code, _, err = run(capsys, "synth", dpj_path, *extra, "-o", tmp_path / "x.png")
        assert code == 2 and err.count("\n") == 1, extra
    code, _, err = run(capsys, "synth", dpj_path, "-o", tmp_path / "x.jpg")
    assert code == 2 and ".png" in err
    code, _, err = run(capsys, "synth", dpj_path, "-o", dpj_path / "x.png")   # under a file
    assert code == 2 and "is not a folder" in err
    code, _, err = run(capsys, "synth", dpj_path, "-o", tmp_path / "none" / "x.png")
    assert code == 2 and "does not exist" in err


def test_console_script_reports_one_line_and_exit_code(tmp_path):
    bad = tmp_path / "bad.dpj"
    bad.write_text("garbage")
    proc = subprocess.run([sys.executable, "-m", "texeditor.cli", "dpj-info", str(bad)],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0 and "not a DPJ file" in proc.stderr


def test_texture_synth_render_log_and_optimize(tmp_path, capsys):
    from texeditor import synthesize
    from texeditor.resources import bundled_dpj

    dpj_path = bundled_dpj("grass-2x2-g8")
    tex = tmp_path / "a.texture"
    assert run(capsys, "synth", dpj_path, "--size", "40x30", "--seed", "8", "-o", tex)[0] == 0
    code, out, _ = run(capsys, "log", tex)
    assert code == 0 and out.strip() == "1. Synthesise 40×30, seed 8"
    assert run(capsys, "render", tex, "-o", tmp_path / "a.npy")[0] == 0
    expected = synthesize(DPJ.load(dpj_path), (30, 40), seed=8).levels
    assert np.array_equal(np.load(tmp_path / "a.npy", allow_pickle=False), expected)
    assert run(capsys, "render", tex, "--scale", "3", "-o", tmp_path / "a.png")[0] == 0
    assert skio.imread(tmp_path / "a.png").shape[:2] == (90, 120)
    code, out, _ = run(capsys, "log", tex, "--optimize", "-o", tmp_path / "b.texture")
    assert code == 0 and "same result" in out and "(nothing to do)" in out


def test_log_optimise_says_what_it_moves_and_merges(tmp_path, capsys):
    from texeditor.recipe.actions import CropCanvas, NewCanvas, SetLevels
    from texeditor.recipe.history import History
    from texeditor.recipe.texturefile import read_texture, save_texture

    history = History()
    for action in (NewCanvas(8, 8, 3), CropCanvas(1, 1, 7, 7), SetLevels(1, 1, 1, 1, 2),
                   CropCanvas(0, 0, 4, 4)):
        history.apply(action)
    tex, short = tmp_path / "crops.texture", tmp_path / "short.texture"
    save_texture(tex, history)
    notes = ["  moved step 4 (Crop to 4×4 at (0, 0)) before step 3 so it merges with step 2",
             "  merged step 2 (Crop to 7×7 at (1, 1)) and step 4 (Crop to 4×4 at (0, 0)) into "
             "one step: Crop to 4×4 at (1, 1)"]
    code, out, _ = run(capsys, "log", tex, "--optimise")          # says what it would do
    assert code == 0 and out.splitlines() == [
        "4 actions would be optimised to 3 (-o NEW.texture writes them)", *notes]
    assert not short.exists()
    code, out, _ = run(capsys, "log", tex, "--optimise", "-o", short)
    assert code == 0 and out.splitlines() == [
        f"{short}: 4 actions optimised to 3, same result", *notes]
    assert read_texture(short).actions == (NewCanvas(8, 8, 3), CropCanvas(1, 1, 4, 4),
                                           SetLevels(1, 1, 1, 1, 2))


def test_render_refuses_a_texture_whose_hash_does_not_match(tmp_path, capsys):
    import zipfile

    from texeditor.resources import bundled_dpj

    tex, bad = tmp_path / "a.texture", tmp_path / "bad.texture"
    assert run(capsys, "synth", bundled_dpj("grass-2x2-g8"), "--size", "20x20", "-o", tex)[0] == 0
    with zipfile.ZipFile(tex) as src, zipfile.ZipFile(bad, "w") as dst:
        for info in src.infolist():
            data = src.read(info)
            if info.filename == "manifest.json":
                manifest = json.loads(data)
                manifest["result_sha256"] = "0" * 64
                data = json.dumps(manifest).encode()
            dst.writestr(info, data)
    out = tmp_path / "x.png"
    code, _, err = run(capsys, "render", bad, "-o", out)
    assert code == 2 and err.count("\n") == 1 and "SHA-256" in err
    assert not out.exists()


def test_resynth_and_photo_models_end_to_end(tmp_path, photo, capsys):
    """resynth in one command; acquire --scales saves a model that synth draws as a picture,
    as levels and as a .texture that replays the same levels; dpj-info reports each scale."""
    from skimage import io as iio
    code, out, _ = run(capsys, "resynth", photo, "--size", "96x64", "--seed", "2",
                       "-o", tmp_path / "r.png")
    assert code == 0 and "2 scales" in out and "photographic tone" in out
    picture = iio.imread(tmp_path / "r.png")
    assert picture.shape == (64, 96) and len(np.unique(picture)) > 16

    model = tmp_path / "m.dpj"
    code, out, _ = run(capsys, "acquire", photo, "--scales", "2", "-o", model)
    assert code == 0 and "photo model, 2 scales" in out
    run(capsys, "synth", model, "--size", "80x60", "--seed", "5", "-o", tmp_path / "a.npy")
    run(capsys, "synth", model, "--size", "80x60", "--seed", "5", "-o", tmp_path / "a.texture")
    code, _, _ = run(capsys, "render", tmp_path / "a.texture", "-o", tmp_path / "b.npy")
    assert code == 0
    assert np.array_equal(np.load(tmp_path / "a.npy"), np.load(tmp_path / "b.npy"))
    code, out, _ = run(capsys, "synth", model, "--no-tone", "--size", "80x60", "-o",
                       tmp_path / "flat.png")
    assert code == 0 and len(np.unique(iio.imread(tmp_path / "flat.png"))) <= 4
    code, out, _ = run(capsys, "dpj-info", model)
    assert code == 0 and "scale 1 of 2" in out
    code, _, err = run(capsys, "resynth", photo, "--scales", "9", "-o", tmp_path / "x.png")
    assert code == 2 and "1..6" in err and not (tmp_path / "x.png").exists()
    code, out, _ = run(capsys, "resynth", photo, "--scales", "1", "--size", "40x30", "-o",
                       tmp_path / "one.png")
    assert code == 0 and "1 scale," in out


def test_resynth_names_what_a_too_small_photo_lacks(tmp_path, capsys):
    """A photo under 8 points a side: one line, without a reduction it would not have."""
    path = tmp_path / "tiny.png"
    skio.imsave(path, (np.arange(9).reshape(3, 3) * 25).astype(np.uint8), check_contrast=False)
    code, _, err = run(capsys, "resynth", path, "--size", "40x30", "-o", tmp_path / "x.png")
    assert code == 2 and err.count("\n") == 1
    assert "3x3 photo is too small: a photo has at least 8 points a side" in err
    code, _, err = run(capsys, "resynth", path, "--scales", "2", "-o", tmp_path / "x.png")
    assert code == 2 and "too small for 2 scales (its coarsest reduction" in err
    assert not (tmp_path / "x.png").exists()


def test_a_reader_that_leaves_early_is_no_error(tmp_path):
    """`texeditor bank list | head -1`: the pipe closes before the listing is written; the
    command ends quietly (no "error: Broken pipe", no traceback), as Unix tools do."""
    env = {**os.environ, "TEXEDITOR_BANK": str(tmp_path / "bank.sqlite")}
    for argv in (["bank", "list"], ["--help"]):
        proc = subprocess.Popen([sys.executable, "-m", "texeditor.cli", *argv], env=env,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        proc.stdout.close()                       # gone before the program writes
        err = proc.stderr.read().decode()
        assert proc.wait(timeout=120) in (0, 1)
        assert "rror" not in err and "Traceback" not in err, err


def test_version_and_counts_in_words(tmp_path, capsys):
    """`texeditor --version` names the release (the console script sends it to the headless
    CLI, not to the window); a one-step texture is "1 action", not "1 actions"."""
    from app.main import main as console
    import texeditor
    for entry in (main, console):
        with pytest.raises(SystemExit) as stop:
            entry(["--version"])
        assert stop.value.code == 0
        assert capsys.readouterr().out.strip() == f"texeditor {texeditor.__version__}"
    dpj = tmp_path / "d.dpj"
    DPJ.from_codes(np.arange(16), np.full(16, 1 / 16), 2, (2, 2)).save(dpj)
    code, _, _ = run(capsys, "synth", dpj, "--size", "16x16", "-o", tmp_path / "t.texture")
    code, out, _ = run(capsys, "render", tmp_path / "t.texture", "-o", tmp_path / "t.png")
    assert code == 0 and ", 1 action replayed, hash verified" in out


def test_a_first_run_at_a_terminal_says_it_prepares_the_engine(monkeypatch, capsys):
    """A fresh install compiles the kernels for up to a minute: a person at a terminal is told
    once why the command is silent; a cached kernel, a pipe or a log hear nothing."""
    import types
    import numba
    from texeditor import cli

    def compiles(args):
        return numba.njit(lambda x: x + 1)(1) - numba.njit(lambda x: x * 2)(1)  # new kernels

    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    assert cli._run(types.SimpleNamespace(func=compiles)) == 0
    assert capsys.readouterr().err == cli.COMPILING_NOTE + "\n"          # once for both kernels
    assert cli._run(types.SimpleNamespace(func=lambda args: 0)) == 0
    assert capsys.readouterr().err == ""                                 # nothing compiled
    compiles(None)                                                       # outside a command
    assert capsys.readouterr().err == ""
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False)
    assert cli._run(types.SimpleNamespace(func=compiles)) == 0
    assert capsys.readouterr().err == ""                                 # not a terminal


def test_resynth_auto_scales_fit_a_small_texture(tmp_path, capsys):
    """"auto" gives a small texture the scales it can hold (a 256² photo has 3, whose coarsest
    5×5 window needs at least 17×17): a 32×16 tile comes out on 2 scales, 8×4 on one; the
    same size with the photo's own 3 scales asked for is refused, naming a size and fewer
    scales; a texture too small for one scale names the smallest."""
    path = tmp_path / "gravel.png"
    skio.imsave(path, data.gravel()[:256, :256], check_contrast=False)
    sizes = {"64x64": "3 scales,", "32x16": "2 scales,", "8x4": "1 scale,"}
    for size, scales in sizes.items():
        out_path = tmp_path / f"{size}.npy"
        code, out, _ = run(capsys, "resynth", path, "--size", size, "-o", out_path)
        assert code == 0 and scales in out
        w, h = map(int, size.split("x"))
        assert np.load(out_path).shape == (h, w)
    code, _, err = run(capsys, "resynth", path, "--size", "32x16", "--scales", "3", "-o",
                       tmp_path / "x.png")
    assert code == 2 and "too small for 3 scales" in err
    assert "choose at least 17x17, or fewer scales" in err
    code, _, err = run(capsys, "resynth", path, "--size", "2x1", "-o", tmp_path / "x.png")
    assert code == 2 and "a 2x1 texture is too small for 1 scale " in err
    assert "choose at least 3x2\n" in err and not (tmp_path / "x.png").exists()


def test_resynth_says_when_it_rebalanced_the_level_shares(tmp_path, capsys):
    """A crop of chelsea whose finest level shares come out off at this seed: the texture comes
    out within 0.03 of the model's, and the command says it moved border points."""
    from texeditor.photo import acquire_model
    crop = data.chelsea()[100:292, 200:392]
    path = tmp_path / "cat.png"
    skio.imsave(path, crop, check_contrast=False)
    code, out, _ = run(capsys, "resynth", path, "--scales", "3", "--size", "140x100", "--seed",
                       "3", "-o", tmp_path / "r.npy")
    assert code == 0 and "level shares rebalanced" in out
    levels = np.load(tmp_path / "r.npy")
    shares = np.bincount(levels.ravel(), minlength=4) / levels.size
    assert np.abs(shares - acquire_model(crop, scales=3).frequencies()).max() <= 0.03


def test_acquire_with_colour_classes_keeps_the_photo_colours(tmp_path, capsys):
    path = tmp_path / "coffee.png"
    skio.imsave(path, data.coffee()[::4, ::4], check_contrast=False)
    out = tmp_path / "coffee.dpj"
    code, _, _ = run(capsys, "acquire", path, "--levels", "4", "--quantizer", "lab", "-o", out)
    assert code == 0
    dpj = DPJ.load(out)
    from texeditor.markov.levels import quantize
    np.testing.assert_array_equal(dpj.palette, quantize(data.coffee()[::4, ::4], 4, "lab").palette)
    assert dpj.meta["quantizer"] == "lab"
    assert np.ptp(dpj.palette.astype(int), axis=1).max() > 40     # colours, not greys


def test_render_writes_the_texture_laid_on_its_plates_as_rgb(tmp_path, capsys):
    from texeditor.recipe.actions import NewCanvas, SetLevels
    from texeditor.recipe.history import History
    from texeditor.recipe.texturefile import save_texture
    from texeditor.texture.plate_actions import AddPlates, OnPlates

    history = History()
    history.apply(NewCanvas(4, 2, 2))                       # greys 0 and 255
    history.apply(SetLevels(0, 0, 1, 4, 1))                 # top row 255: mean grey 127.5
    history.apply(AddPlates(((100, 50, 200), (240, 120, 0))))
    history.apply(OnPlates.of(SetLevels(0, 2, 2, 2, 1)))    # right half on plate 1
    tex = tmp_path / "plates.texture"
    save_texture(tex, history)
    code, out, _ = run(capsys, "render", tex, "--scale", "2", "-o", tmp_path / "rgb.png")
    assert code == 0 and "colour plates" in out
    rgb = skio.imread(tmp_path / "rgb.png")
    plate = np.array([[[100, 50, 200]] * 2 + [[240, 120, 0]] * 2] * 2, float)
    offset = np.array([[127.5], [-127.5]])[..., None]       # grey − mean grey, row by row
    expected = np.clip(np.rint(plate + offset), 0, 255).astype(np.uint8)
    np.testing.assert_array_equal(rgb, np.repeat(np.repeat(expected, 2, 0), 2, 1))
    assert run(capsys, "render", tex, "--no-plates", "-o", tmp_path / "grey.png")[0] == 0
    np.testing.assert_array_equal(skio.imread(tmp_path / "grey.png"), [[255] * 4, [0] * 4])
