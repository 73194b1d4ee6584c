"""`texeditor export X.texture --height H.png --normal N.png`: the .texture replayed, its relief
maps written and read back; bad input exits 2 on one line and writes nothing."""

import imageio.v3 as iio
import numpy as np
import pytest

from texeditor.cli import main
from texeditor.recipe.history import History
from texeditor.recipe.texturefile import save_texture
from texeditor.relief import encode_normals, heights, normal_map
from texeditor.resources import bundled_dpj


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def texture(tmp_path, capsys):
    """A 40×30 synthesis from a bundled DPJ, as a .texture; and its levels as replayed."""
    tex = tmp_path / "grass.texture"
    assert run(capsys, "synth", bundled_dpj("grass-2x2-g8"), "--size", "40x30", "--seed", "3",
               "-o", tex)[0] == 0
    assert run(capsys, "render", tex, "-o", tmp_path / "levels.npy")[0] == 0
    return tex, np.load(tmp_path / "levels.npy", allow_pickle=False)


def palette_of(path):
    from texeditor.recipe.texturefile import render_texture
    return render_texture(path).palette


def test_export_writes_both_maps(tmp_path, capsys, texture):
    tex, levels = texture
    palette = palette_of(tex)
    code, out, err = run(capsys, "export", tex, "--height", tmp_path / "h.png",
                         "--normal", tmp_path / "n.png", "--strength", "2.5")
    assert code == 0 and err == "" and "height map" in out and "OpenGL" in out
    height = iio.imread(tmp_path / "h.png")
    assert height.dtype == np.uint16 and height.shape == (30, 40)
    assert np.array_equal(height, palette[levels, 0].astype(np.uint16) * 257)     # grey palette
    normal = iio.imread(tmp_path / "n.png")
    assert normal.shape == (30, 40, 3) and normal.dtype == np.uint8
    assert np.array_equal(normal, encode_normals(normal_map(heights(levels, palette, 2.5))))


def test_directx_no_wrap_and_one_map_alone(tmp_path, capsys, texture):
    tex, levels = texture
    assert run(capsys, "export", tex, "--normal", tmp_path / "gl.png")[0] == 0
    code, out, _ = run(capsys, "export", tex, "--normal", tmp_path / "dx.png", "--directx")
    assert code == 0 and "DirectX" in out and not (tmp_path / "h.png").exists()
    gl, dx = iio.imread(tmp_path / "gl.png"), iio.imread(tmp_path / "dx.png")
    assert np.array_equal(dx[..., 1], 255 - gl[..., 1])
    assert np.array_equal(dx[..., [0, 2]], gl[..., [0, 2]])
    assert run(capsys, "export", tex, "--normal", tmp_path / "edge.png", "--no-wrap")[0] == 0
    edge = iio.imread(tmp_path / "edge.png")
    assert np.array_equal(edge[1:-1, 1:-1], gl[1:-1, 1:-1])          # the inside is the same
    assert not np.array_equal(edge, gl)                               # the border is one-sided
    # the default strength is 4
    palette = palette_of(tex)
    assert np.array_equal(gl, encode_normals(normal_map(heights(levels, palette, 4.0))))


def test_bad_exports_exit_2_on_one_line_and_write_nothing(tmp_path, capsys, texture):
    tex, _ = texture
    junk = tmp_path / "junk.texture"
    junk.write_bytes(b"not a zip")
    empty = tmp_path / "empty.texture"
    save_texture(empty, History())
    out = tmp_path / "out.png"
    cases = [([tex], "--height"),
             ([tex, "--height", tmp_path / "h.jpg"], ".png"),
             ([tex, "--normal", tmp_path / "nowhere" / "n.png"], "does not exist"),
             ([tex, "--height", out, "--normal", out], "same file"),
             ([tex, "--normal", out, "--strength", "-1"], "strength"),
             ([tex, "--normal", out, "--strength", "nan"], "strength"),
             ([tex, "--normal", out, "--strength", "lots"], "strength"),
             ([tmp_path / "missing.texture", "--normal", out], "no such file"),
             ([junk, "--normal", out], "junk.texture"),
             ([empty, "--height", out], "no texture")]
    for argv, words in cases:
        code, stdout, err = run(capsys, "export", *argv)
        assert code == 2 and err.count("\n") == 1 and words in err, (argv, err)
        assert "Traceback" not in err and stdout == ""
        assert not out.exists() and not (tmp_path / "h.jpg").exists()
