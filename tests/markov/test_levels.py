"""Levels & palettes: the two quantisers, the palette and the photo reader's refusals."""

import warnings

import numpy as np
import pytest
from PIL import Image
from skimage import data, io

from texeditor.markov import levels as lv
from texeditor.errors import ImageError, InputError


def mse(grey, q):
    """Mean-square error when each level is rendered by the mean grey of its pixels."""
    err = 0.0
    for k in np.unique(q.levels):
        cell = grey[q.levels == k]
        err += ((cell - cell.mean()) ** 2).sum()
    return err / grey.size


# -- band (the thesis's) ----------------------------------------------------------------------
def test_band_thresholds_cut_the_central_90_percent_into_equal_intervals():
    grey = np.linspace(0, 1, 21).reshape(3, 7)  # 5th percentile 0.05, 95th 0.95
    q = lv.quantize(grey, 3)
    np.testing.assert_allclose(q.thresholds, [0.35, 0.65], atol=1e-12)
    expected = np.array([0] * 7 + [1] * 6 + [2] * 8).reshape(3, 7)  # 0.35 and 0.65 go up
    np.testing.assert_array_equal(q.levels, expected)
    assert q.levels.dtype == np.uint8 and q.levels.max() < 3


def test_band_sends_values_below_and_above_the_band_to_the_extreme_levels():
    grey = np.array([[0.0] + [0.4] * 9 + [0.5] * 9 + [1.0]])
    q = lv.quantize(grey, 4)  # 5th percentile 0.95 * 0.4 = 0.38, 95th 0.5 + 0.05 * 0.5 = 0.525
    np.testing.assert_allclose(q.thresholds, [0.41625, 0.4525, 0.48875], atol=1e-12)
    assert q.levels[0, 0] == 0 and q.levels[0, -1] == 3
    assert set(q.levels[0, 1:10]) == {0} and set(q.levels[0, 10:19]) == {3}


def test_band_falls_back_to_min_max_when_the_band_is_one_grey():
    grey = np.full((10, 10), 0.5)
    grey[0, 0], grey[9, 9] = 0.1, 0.9
    q = lv.quantize(grey, 4)
    np.testing.assert_allclose(q.thresholds, [0.3, 0.5, 0.7], atol=1e-12)
    assert q.levels[0, 0] == 0 and q.levels[9, 9] == 3 and q.levels[5, 5] == 2


def test_grey_palette_is_the_mean_grey_of_each_level_and_empty_levels_get_their_centre():
    grey = np.array([[0.0] * 50 + [1.0] * 50])
    q = lv.quantize(grey, 4)  # band [0, 1], levels 1 and 2 are empty
    np.testing.assert_allclose(q.thresholds, [0.25, 0.5, 0.75])
    np.testing.assert_array_equal(q.palette[:, 0], [0, 96, 159, 255])  # 0.375, 0.625 * 255
    assert (q.palette == q.palette[:, :1]).all() and q.palette.dtype == np.uint8
    q = lv.quantize(np.linspace(0, 1, 21).reshape(3, 7), 3)
    assert q.palette[0, 0] == round(0.15 * 255)  # mean of 0, 0.05, ..., 0.30


# -- Lloyd–Max --------------------------------------------------------------------------------
def test_lloyd_converges_to_the_midpoint_of_the_cell_means():
    grey = np.array([[0.0, 0.1, 0.2, 0.9, 1.0]] * 4)  # band threshold 0.5; means 0.1 and 0.95
    q = lv.quantize(grey, 2, "lloyd")
    np.testing.assert_allclose(q.thresholds, [0.525], atol=1e-12)
    np.testing.assert_array_equal(q.levels[0], [0, 0, 0, 1, 1])
    assert q.levels.dtype == np.uint8


def test_lloyd_puts_the_threshold_between_two_clusters():
    rng = np.random.default_rng(1)
    dark = rng.uniform(0.05, 0.15, 9700)  # 97% dark: the band holds only dark pixels
    light = rng.uniform(0.85, 0.95, 300)
    grey = np.concatenate([dark, light]).reshape(100, 100)
    band = lv.quantize(grey, 2, "band")
    assert band.thresholds[0] < 0.15  # the thesis's quantiser splits the dark cluster
    q = lv.quantize(grey, 2, "lloyd")
    assert 0.45 < q.thresholds[0] < 0.55  # the mid-point of the cluster means, 0.1 and 0.9
    np.testing.assert_array_equal(q.levels.ravel(), np.r_[np.zeros(9700), np.ones(300)])


def test_lloyd_has_a_lower_mean_square_error_than_the_band_on_a_photo():
    photo = data.camera()
    grey = lv.to_grey(photo)
    for g in (2, 4, 8, 16):
        band, lloyd = lv.quantize(photo, g, "band"), lv.quantize(photo, g, "lloyd")
        assert mse(grey, lloyd) < mse(grey, band)
        assert lloyd.levels.max() < g and np.all(np.diff(lloyd.thresholds) >= 0)


# -- palettes, dtypes and shapes --------------------------------------------------------------
@pytest.mark.parametrize("method", lv.METHODS)
def test_colour_palette_is_the_mean_colour_of_each_level(method):
    photo = data.astronaut()
    q = lv.quantize(photo, 6, method)
    expected = [np.round(photo[q.levels == k].mean(axis=0)) for k in range(6)]
    np.testing.assert_array_equal(q.palette, np.array(expected, dtype=np.uint8))
    assert len({tuple(c) for c in q.palette}) == 6


def test_alpha_is_ignored_by_the_palette():
    photo = data.astronaut()
    rgba = np.dstack([photo, np.full(photo.shape[:2], 255, np.uint8)])
    np.testing.assert_array_equal(lv.quantize(rgba, 5).palette, lv.quantize(photo, 5).palette)


@pytest.mark.parametrize("method", lv.METHODS)
@pytest.mark.parametrize("photo", [data.camera(), data.astronaut()], ids=["grey", "rgb"])
def test_16_bit_gives_the_same_levels_as_8_bit(photo, method):
    q8 = lv.quantize(photo, 7, method)
    q16 = lv.quantize(photo.astype(np.uint16) * 257, 7, method)
    np.testing.assert_array_equal(q16.levels, q8.levels)
    np.testing.assert_allclose(q16.thresholds, q8.thresholds, atol=1e-6)
    assert np.abs(q16.palette.astype(int) - q8.palette).max() <= 1


def test_every_dtype_and_shape_is_accepted():
    grey8 = (np.arange(64 * 64).reshape(64, 64) % 251).astype(np.uint8)
    reference = lv.quantize(grey8, 4).levels
    variants = [grey8 / 255.0, (grey8 / 255.0).astype(np.float32), grey8[..., None],
                np.dstack([grey8, np.full_like(grey8, 255)]), np.dstack([grey8] * 3),
                np.dstack([grey8] * 3 + [np.full_like(grey8, 255)])]
    for image in variants:
        np.testing.assert_array_equal(lv.quantize(image, 4).levels, reference)
    q = lv.quantize(grey8 > 100, 2)
    np.testing.assert_array_equal(q.levels, grey8 > 100)


def test_to_grey_scales_by_dtype_and_lays_rgba_on_white():
    assert lv.to_grey(np.array([[0, 65535]], np.uint16)).tolist() == [[0.0, 1.0]]
    transparent_black = np.zeros((1, 1, 4), np.uint8)
    assert lv.to_grey(transparent_black)[0, 0] == pytest.approx(1.0)
    assert lv.to_grey(np.array([[[0.2, 0.9]]])).tolist() == [[0.2]]
    grey = lv.to_grey(data.astronaut())
    assert grey.dtype == np.float64 and grey.shape == (512, 512) and 0 <= grey.min() < grey.max() <= 1


@pytest.mark.parametrize("bad", [np.zeros((4, 4, 5)), np.zeros((2, 4, 4, 3)), np.zeros(4),
                                 np.zeros((4, 4), complex), np.array([[np.nan, 0.5]])])
def test_unusable_arrays_raise_image_error(bad):
    with pytest.raises(ImageError):
        lv.quantize(bad, 4)


# -- refusals ---------------------------------------------------------------------------------
@pytest.mark.parametrize("image", [np.full((8, 8), 77, np.uint8), np.zeros((0, 5)),
                                   np.full((3, 3, 3), 0.5)])
def test_constant_or_empty_image_raises_image_error(image):
    with pytest.raises(ImageError, match="constant|empty"):
        lv.quantize(image, 4)


@pytest.mark.parametrize("image", [np.full((8, 8, 3), (200, 10, 10), np.uint8),
                                   np.dstack([np.arange(108, dtype=np.uint8).reshape(6, 6, 3),
                                              np.zeros((6, 6), np.uint8)])])
def test_a_one_colour_photo_is_refused_as_flat_by_the_colour_quantiser(image):
    """Not "choose G ≤ 1 colour classes", which no G obeys: the photo has nothing to
    quantise (a transparent one is laid on white, so it is one colour too)."""
    with pytest.raises(ImageError, match="one flat colour"):
        lv.quantize(image, 4, "lab")


@pytest.mark.parametrize("g", [1, 17, 0, -3, 2.5, "8", True])
def test_levels_out_of_range_raise_input_error(g):
    with pytest.raises(InputError):
        lv.quantize(data.camera(), g)


def test_unknown_method_raises_input_error():
    with pytest.raises(InputError, match="band, lloyd"):
        lv.quantize(data.camera(), 4, "kmeans")


# -- load_image -------------------------------------------------------------------------------
def test_load_image_reads_back_what_was_written(tmp_path):
    rgb = data.astronaut()[::8, ::8]
    io.imsave(tmp_path / "a.png", rgb)
    np.testing.assert_array_equal(lv.load_image(tmp_path / "a.png"), rgb)
    deep = (np.arange(40 * 30).reshape(30, 40) * 50).astype(np.uint16)
    io.imsave(tmp_path / "deep.png", deep, check_contrast=False)
    back = lv.load_image(str(tmp_path / "deep.png"))
    assert back.dtype == np.uint16
    np.testing.assert_array_equal(back, deep)


def test_load_image_expands_palette_images_and_takes_the_first_page(tmp_path):
    grey = (np.arange(32 * 32).reshape(32, 32) % 256).astype(np.uint8)
    Image.fromarray(np.dstack([grey] * 3)).convert("P").save(tmp_path / "p.png")
    assert lv.load_image(tmp_path / "p.png").shape == (32, 32, 3)
    pages = [Image.fromarray(grey), Image.fromarray(255 - grey)]
    for name in ("pages.tif", "anim.gif"):
        pages[0].save(tmp_path / name, save_all=True, append_images=pages[1:])
        np.testing.assert_array_equal(lv.load_image(tmp_path / name), grey)


def _png_bytes(tmp_path):
    io.imsave(tmp_path / "good.png", data.camera()[:64, :64], check_contrast=False)
    return (tmp_path / "good.png").read_bytes()


@pytest.mark.parametrize("case", ["text", "truncated", "empty", "missing", "folder"])
def test_load_image_refuses_bad_files_with_image_error(tmp_path, case):
    path = tmp_path / "bad.png"
    if case == "text":
        path.write_text("this is not a picture\n")
    elif case == "truncated":
        path.write_bytes(_png_bytes(tmp_path)[:300])
    elif case == "empty":
        path.write_bytes(b"")
    elif case == "folder":
        path.mkdir()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(ImageError) as info:
            lv.load_image(path)
    assert "bad.png" in str(info.value) and "\n" not in str(info.value)
    assert not [w for w in caught if not issubclass(w.category, ResourceWarning)]


def test_load_image_refuses_too_many_pixels_before_decoding(tmp_path, monkeypatch):
    _png_bytes(tmp_path)
    monkeypatch.setattr(lv, "MAX_PIXELS", 64 * 63)
    with pytest.raises(ImageError, match="megapixels"):
        lv.load_image(tmp_path / "good.png")


def test_decompression_bomb_becomes_image_error_without_warnings(tmp_path, monkeypatch):
    _png_bytes(tmp_path)
    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", 1000)  # 4096 pixels: Pillow warns
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(ImageError, match="too large"):
            lv.load_image(tmp_path / "good.png")
    assert not [w for w in caught if issubclass(w.category, Image.DecompressionBombWarning)]
    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", 1000 // 4)  # more than twice: Pillow errors
    with pytest.raises(ImageError, match="too large"):
        lv.load_image(tmp_path / "good.png")


def test_load_image_refuses_more_than_four_channels(tmp_path):
    import tifffile
    tifffile.imwrite(tmp_path / "five.tif", np.zeros((8, 8, 5), np.uint8), photometric="minisblack",
                     planarconfig="contig")
    with pytest.raises(ImageError, match="five.tif"):
        lv.load_image(tmp_path / "five.tif")


def test_a_cmyk_jpeg_is_read_as_its_rgb_colours(tmp_path):
    rgb = data.astronaut()
    Image.fromarray(rgb).convert("CMYK").save(tmp_path / "print.jpg", quality=95)
    image = lv.load_image(tmp_path / "print.jpg")
    assert image.shape == rgb.shape
    assert np.abs(image.astype(int) - rgb).mean() < 12     # JPEG loss, not CMYK read as RGBA
    assert lv.quantize(image, 4).levels.max() == 3


def test_a_one_pixel_high_strip_quantises(tmp_path):
    strip = np.random.default_rng(0).integers(0, 256, (1, 100_000)).astype(np.uint8)
    io.imsave(tmp_path / "strip.png", strip, check_contrast=False)
    q = lv.quantize(lv.load_image(tmp_path / "strip.png"), 4)
    assert q.levels.shape == (1, 100_000) and set(np.unique(q.levels)) == {0, 1, 2, 3}


# -- colour classes in CIELAB ("lab") ------------------------------------------------------------
def _patches():
    """Red, green and blue patches of 6, 10 and 4 columns (5 rows); the red one in two shades."""
    image = np.zeros((5, 20, 3), np.uint8)
    image[:, :6] = (250, 0, 0)
    image[:2, :6] = (200, 30, 10)
    image[:, 6:16] = (0, 200, 0)
    image[:, 16:] = (0, 0, 255)
    return image


def test_lab_finds_the_three_patches_ordered_by_lightness_with_their_mean_colours():
    q = lv.quantize(_patches(), 3, "lab")
    # L*: blue (0, 0, 255) 32.3 < red 53 < green (0, 200, 0) 71: level 0 is the darkest
    expected = np.zeros((5, 20), np.uint8)
    expected[:, :6], expected[:, 6:16] = 1, 2
    np.testing.assert_array_equal(q.levels, expected)
    red = (3 * np.array([250, 0, 0]) + 2 * np.array([200, 30, 10])) / 5     # 230, 12, 4
    np.testing.assert_array_equal(q.palette, [[0, 0, 255], np.round(red), [0, 200, 0]])
    assert q.levels.dtype == np.uint8 and q.palette.dtype == np.uint8 and q.thresholds.size == 0


def test_lab_tells_apart_colours_of_one_grey_that_the_grey_quantisers_merge():
    image = np.zeros((4, 8, 3), np.uint8)
    image[:, :4] = (200, 60, 60)          # a red and a green of nearly the same grey
    image[:, 4:] = (40, 110, 40)
    image[0, 0] = (0, 0, 0)               # and one black point: a grey quantiser's contrast
    grey = lv.to_grey(image)
    assert abs(grey[1, 0] - grey[1, 4]) < 0.01
    assert len(np.unique(lv.quantize(image, 2, "lloyd").levels[1:])) == 1
    q = lv.quantize(image, 3, "lab")
    assert q.levels[0, 0] == 0 and set(q.levels[1:, :4].ravel()) != set(q.levels[1:, 4:].ravel())
    assert len(np.unique(q.levels[1:])) == 2


def test_lab_is_deterministic_and_reads_16_bit_photos_like_8_bit_ones():
    rng = np.random.default_rng(5)
    image = rng.integers(0, 256, (40, 50, 3), dtype=np.uint8)
    first, again = lv.quantize(image, 6, "lab"), lv.quantize(image.copy(), 6, "lab")
    np.testing.assert_array_equal(first.levels, again.levels)
    np.testing.assert_array_equal(first.palette, again.palette)
    wide = lv.quantize(image.astype(np.uint16) * 257, 6, "lab")
    np.testing.assert_array_equal(wide.levels, first.levels)
    lightness = ski_lab(first.palette)[:, 0]
    assert np.all(np.diff(lightness) > 0)             # level 0 the darkest


def ski_lab(palette):
    from skimage.color import rgb2lab
    return rgb2lab(np.asarray(palette, np.float64)[None] / 255)[0]


def test_lab_classes_are_a_local_optimum_of_the_colour_error():
    """Lloyd's fixed point: every colour is nearest (in CIELAB) to its own class's mean."""
    from skimage.color import rgb2lab
    image = data.astronaut()[::4, ::4]
    q = lv.quantize(image, 5, "lab")
    lab = rgb2lab(image)
    centres = np.array([lab[q.levels == k].mean(axis=0) for k in range(5)])
    nearest = ((lab[:, :, None, :] - centres) ** 2).sum(-1).argmin(-1)
    assert np.mean(nearest == q.levels) > 0.99       # bins of 5 bits: a few border colours


def test_lab_on_a_grey_photo_is_exactly_lloyd():
    grey = data.camera()[::4, ::4]
    rgb = np.repeat(grey[:, :, None], 3, axis=2)
    for image in (grey, rgb, np.dstack([rgb, np.full(grey.shape, 255, np.uint8)])):
        lab, lloyd = lv.quantize(image, 4, "lab"), lv.quantize(image, 4, "lloyd")
        np.testing.assert_array_equal(lab.levels, lloyd.levels)
        np.testing.assert_array_equal(lab.palette, lloyd.palette)
        np.testing.assert_array_equal(lab.thresholds, lloyd.thresholds)


def test_lab_lays_rgba_on_white_and_refuses_fewer_colours_than_classes():
    image = np.zeros((2, 4, 4), np.uint8)
    image[:, :2] = (255, 0, 0, 255)
    image[:, 2:] = (0, 0, 255, 0)          # transparent blue: white, as to_grey sees it
    q = lv.quantize(image, 2, "lab")
    np.testing.assert_array_equal(q.levels, [[0, 0, 1, 1]] * 2)
    with pytest.raises(ImageError, match="only 2 colours"):
        lv.quantize(image, 3, "lab")


@pytest.mark.parametrize("pixels", [1, 2, 4097, lv.COUNTED_COLOURS - 1, lv.COUNTED_COLOURS + 3])
@pytest.mark.parametrize("colours", [7, 5000, 1 << 24])
def test_a_photos_colours_are_found_as_np_unique_finds_them(colours, pixels):
    """Below COUNTED_COLOURS pixels the 24-bit codes are radix-sorted, from it on counted: the
    same colours, places and counts as np.unique either way."""
    rng = np.random.default_rng(colours)
    codes = rng.integers(0, colours, pixels).astype(np.uint32)
    expected = np.unique(codes, return_inverse=True, return_counts=True)
    found = lv._unique_colours(codes)
    for a, b in zip(expected, found):
        assert np.array_equal(a, b)
    assert found[0].dtype == expected[0].dtype


def test_an_8_bit_photos_colour_codes_are_those_of_the_same_photo_as_floats():
    """8-bit RGB is coded straight from its bytes: the codes the float path gives every value."""
    rng = np.random.default_rng(3)
    photo = np.stack([np.arange(256, dtype=np.uint8)] * 3, axis=-1)[None].repeat(300, axis=0)
    photo[:, :, 1] = rng.permutation(256).astype(np.uint8)
    for other in (photo / 255.0, photo.astype(np.uint16) * 257):
        assert np.array_equal(lv._colour_codes(photo), lv._colour_codes(other))
    assert lv._colour_codes(photo)[0, 7] == (7 << 16) | (int(photo[0, 7, 1]) << 8) | 7


def test_a_large_colour_photo_gets_the_classes_sorting_would_give(monkeypatch):
    photo = np.repeat(np.repeat(data.astronaut(), 3, axis=0), 3, axis=1)[:1400, :1600]
    assert photo.shape[0] * photo.shape[1] >= lv.COUNTED_COLOURS
    counted = lv.quantize(photo, 4, "lab")
    monkeypatch.setattr(lv, "COUNTED_COLOURS", photo.size)      # np.unique, as before
    sorted_ = lv.quantize(photo, 4, "lab")
    assert np.array_equal(counted.levels, sorted_.levels)
    assert np.array_equal(counted.palette, sorted_.palette)


def test_a_uint8_colour_photos_palette_is_the_mean_np_bincount_gives():
    """The palette of an 8-bit colour photo is summed by a kernel (no float64 copy of the photo):
    the same means as bincount over img_as_float, to the last bit."""
    photo = data.coffee()
    for g in (2, 5):
        q = lv.quantize(photo, g, "lab")
        flat = q.levels.ravel()
        counts = np.bincount(flat, minlength=g)
        means = np.stack([np.bincount(flat, weights=lv._as_unit_float(photo[..., c]).ravel(),
                                      minlength=g) for c in range(3)], axis=1)
        expected = np.round(means / counts[:, None] * 255).astype(np.uint8)
        assert np.all(counts > 0) and np.array_equal(q.palette, expected)


@pytest.mark.parametrize("dtype, low, high", [(np.float32, 0, 1000), (np.float64, -3, 2),
                                              (np.int32, 0, 1000), (np.int16, -500, 500)])
def test_load_image_scales_samples_without_a_usual_white_by_their_own_range(tmp_path, dtype,
                                                                             low, high):
    """A height map saved as floats in metres, a 32-bit integer TIFF or a signed one with
    negative samples: scaled by their own range (min → 0, max → 1), so their levels are those
    of the same picture in 0..1 — not one clipped grey, nor "constant"."""
    import tifffile
    rng = np.random.default_rng(3)
    samples = (rng.random((40, 50)) * (high - low) + low).astype(dtype)
    samples[0, 0], samples[0, 1] = low, high
    tifffile.imwrite(tmp_path / "h.tif", samples)
    image = lv.load_image(tmp_path / "h.tif")
    assert image.dtype == np.float32 and image.min() == 0 and image.max() == 1
    unit = (samples.astype(np.float64) - low) / (high - low)
    assert np.allclose(image, unit, atol=1e-6)
    shares = np.bincount(lv.quantize(image, 4, "band").levels.ravel(), minlength=4) / samples.size
    assert shares.min() > 0.15


def test_load_image_keeps_pictures_within_their_usual_range_as_stored(tmp_path):
    """Floats in 0..1 and 8/16-bit pictures come back as they were written; a float RGBA whose
    colour is in 0..255 has its colour scaled and its 0..1 alpha kept."""
    import tifffile
    rng = np.random.default_rng(4)
    for name, stored in (("f.tif", rng.random((20, 30)).astype(np.float32)),
                       ("u16.tif", rng.integers(0, 65536, (20, 30)).astype(np.uint16)),
                       ("u8.tif", rng.integers(0, 256, (20, 30, 3)).astype(np.uint8))):
        tifffile.imwrite(tmp_path / name, stored)
        image = lv.load_image(tmp_path / name)
        assert image.dtype == stored.dtype and np.array_equal(image, stored)
    rgba = np.concatenate([rng.random((20, 30, 3)) * 255, rng.random((20, 30, 1))], axis=2)
    tifffile.imwrite(tmp_path / "rgba.tif", rgba.astype(np.float32), photometric="rgb",
                     extrasamples=["unassalpha"])
    image = lv.load_image(tmp_path / "rgba.tif")
    colour = rgba[..., :3]
    assert np.allclose(image[..., :3], (colour - colour.min()) / np.ptp(colour), atol=1e-6)
    assert np.allclose(image[..., 3], rgba[..., 3], atol=1e-6)


@pytest.mark.parametrize("scale, message", [(255.0, "reach 255"), (-3.0, "go down to -3")])
def test_float_pixels_on_another_scale_are_refused_not_clipped(scale, message):
    """A photo given as floats in 0..255 (an ``.astype(float)``, a mean of channels) would be
    clipped to 0..1, almost black and white, and drawn without a word: it is refused, saying
    how to bring it to 0..1; a little outside 0..1 is still clipped, as scikit-image reads it."""
    import texeditor
    photo = np.linspace(0, 1, 48 * 40).reshape(48, 40)
    for call in (lambda p: lv.quantize(p, 4, "lloyd"), lambda p: lv.to_rgb(np.dstack([p] * 3)),
                 lambda p: texeditor.resynthesize(p, (24, 24), seed=1)):
        with pytest.raises(lv.ImageError, match=message):
            call(photo * scale)
    slightly = lv.quantize(np.clip(photo * 1.2 - 0.1, -0.1, 1.1), 4, "lloyd")
    assert set(np.unique(slightly.levels)) == {0, 1, 2, 3}


# -- what load_image decodes: only what its header allows ----------------------------------------
def _tiff_decodes(monkeypatch):
    """Every array tifffile decodes, by shape; read through imageio or directly."""
    import tifffile
    decoded, real = [], tifffile.TiffFile.asarray

    def spy(self, *args, **kwargs):
        array = real(self, *args, **kwargs)
        decoded.append(array.shape)
        return array
    monkeypatch.setattr(tifffile.TiffFile, "asarray", spy)
    return decoded


def test_a_tiff_stack_decodes_its_first_page_only(tmp_path):
    """A TIFF stack gives its first page (as the docs say) and decodes that page only: a 6 MB
    stack of 400 pages of 2048² took 1.85 GB, every page decoded and one kept."""
    import tifffile
    import tracemalloc
    stack = np.random.default_rng(0).integers(0, 256, (16, 512, 512), dtype=np.uint8)
    tifffile.imwrite(tmp_path / "stack.tif", stack, photometric="minisblack")
    tracemalloc.start()
    try:
        image = lv.load_image(tmp_path / "stack.tif")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert np.array_equal(image, stack[0])
    assert peak < stack.nbytes / 4


@pytest.mark.parametrize("stored, limit, says", [
    (np.zeros((64, 64)), "MAX_IMAGE_BYTES", "64-bit floats: 0 MiB decoded, more than 0 MiB"),
    (np.zeros((64, 64), np.float16), "MAX_PIXELS", "64x64, more than 0 megapixels"),
    (np.zeros((64, 64), np.uint64), "MAX_PIXELS", "64x64, more than 0 megapixels"),
    (np.zeros((64, 64, 5), np.float32), None, r"shape \(64, 64, 5\) is not supported")])
def test_a_tiff_pillow_cannot_open_is_checked_from_its_header_before_decoding(
        tmp_path, monkeypatch, stored, limit, says):
    """Pillow reads no float64, float16, 64-bit or 5-channel TIFF, so imageio decoded them
    unchecked (a 1.6 MB float64 TIFF of 14000² took 1.7 GB before it was refused): tifffile's
    header is checked first, and nothing is decoded."""
    import tifffile
    tifffile.imwrite(tmp_path / "x.tif", stored, photometric="minisblack", planarconfig="contig")
    if limit:
        monkeypatch.setattr(lv, limit, stored.size // 2)
    decoded = _tiff_decodes(monkeypatch)
    with pytest.raises(ImageError, match=says):
        lv.load_image(tmp_path / "x.tif")
    assert decoded == []


def test_a_tiff_strip_that_inflates_past_its_size_is_refused(tmp_path):
    """A page's size says what its strips hold; a deflated strip may inflate to far more (a
    1 MB TIFF of a 64x64 page took 2.2 GB): it is refused, inflated a bounded piece at a time."""
    import struct
    import tifffile
    import zlib
    path = tmp_path / "strip.tif"
    tifffile.imwrite(path, np.zeros((64, 64), np.uint8), compression="zlib", rowsperstrip=64)
    with tifffile.TiffFile(path) as tif:
        tags, order = tif.pages[0].tags, tif.byteorder
        places = tags["StripOffsets"].valueoffset, tags["StripByteCounts"].valueoffset
    data = bytearray(path.read_bytes())
    bomb = zlib.compress(bytes(4 * 2**20))          # 4 MiB of zeros for a strip of 4 KiB
    for place, value in zip(places, (len(data), len(bomb))):
        struct.pack_into(order + "I", data, place, value)
    path.write_bytes(bytes(data) + bomb)
    with pytest.raises(ImageError, match="strip.tif: a strip or tile of the TIFF inflates past "
                                         "its declared 4096 bytes"):
        lv.load_image(path)


def test_a_tiff_of_too_many_pages_is_refused_before_they_are_walked(tmp_path, monkeypatch):
    """Pillow and tifffile read every page's header (4096 pages took 3 s, 100,000 minutes):
    past MAX_TIFF_PAGES the file is refused; a chain of pages that loops is one page."""
    import struct
    import tifffile
    monkeypatch.setattr(lv, "MAX_TIFF_PAGES", 3)
    pages = np.arange(4 * 6 * 5, dtype=np.uint8).reshape(4, 6, 5)
    tifffile.imwrite(tmp_path / "three.tif", pages[:3], photometric="minisblack")
    tifffile.imwrite(tmp_path / "four.tif", pages, photometric="minisblack", bigtiff=True)
    assert np.array_equal(lv.load_image(tmp_path / "three.tif"), pages[0])
    with pytest.raises(ImageError, match="four.tif: the TIFF has more than 3 pages"):
        lv.load_image(tmp_path / "four.tif")
    data = bytearray((tmp_path / "three.tif").read_bytes())
    first = struct.unpack_from("<I", data, 4)[0]
    entries = struct.unpack_from("<H", data, first)[0]
    struct.pack_into("<I", data, first + 2 + 12 * entries, first)    # page 1 is page 0 again
    (tmp_path / "loop.tif").write_bytes(bytes(data))
    assert np.array_equal(lv.load_image(tmp_path / "loop.tif"), pages[0])


@pytest.mark.parametrize("name", ["a.npz", "a.png"])
def test_an_npz_is_not_a_picture(tmp_path, monkeypatch, name):
    """imageio's NPZ reader decoded an .npz's array whatever its size (a 1.5 MB file took
    1.7 GB): a file neither Pillow nor tifffile reads is refused, nothing decoded."""
    with open(tmp_path / name, "wb") as f:
        np.savez(f, np.arange(64 * 64, dtype=np.uint8).reshape(64, 64))
    monkeypatch.setattr(lv.iio, "imread", lambda *a, **k: pytest.fail("decoded"))
    with pytest.raises(ImageError, match=f"{name}: cannot read it as an image"):
        lv.load_image(tmp_path / name)


def test_a_stacks_planar_first_page_is_read_interleaved(tmp_path):
    """The first page of a stack of planar RGB pages is (H, W, 3), as a planar file of one page
    is (it was refused as a 4-D image, or read as its red plane)."""
    import tifffile
    pages = np.random.default_rng(1).integers(0, 256, (2, 3, 20, 30), dtype=np.uint8)
    tifffile.imwrite(tmp_path / "p.tif", pages, planarconfig="separate", photometric="rgb")
    assert np.array_equal(lv.load_image(tmp_path / "p.tif"), np.moveaxis(pages[0], 0, -1))


# -- arrays read as the file reader reads the same samples ----------------------------------------
@pytest.mark.parametrize("dtype", [np.int64, np.int32, np.uint32])
@pytest.mark.parametrize("photo", [data.camera()[::4, ::4], data.astronaut()[::4, ::4]],
                         ids=["grey", "rgb"])
def test_wide_integer_photos_quantise_as_the_8_bit_photo(photo, dtype):
    """``np.array(picture, dtype=int)`` is int64, numpy's default: read on int64's scale it
    was ~0, "constant: a single grey (0)"; it is read by its own range, as load_image reads
    such samples, so a 0..255 photo gives the levels and palette of the uint8 one."""
    photo = photo.copy()
    photo[0, 0], photo[0, 1] = 0, 255       # 0..255: its own range is uint8's
    wide = photo.astype(dtype)
    for method in lv.METHODS:
        q8, q = lv.quantize(photo, 4, method), lv.quantize(wide, 4, method)
        assert np.array_equal(q.levels, q8.levels) and np.array_equal(q.palette, q8.palette)
    assert np.allclose(lv.to_grey(wide), lv.to_grey(photo), atol=1e-7)
    assert np.allclose(lv.to_rgb(wide), lv.to_rgb(photo), atol=1e-7)


@pytest.mark.parametrize("samples", [np.arange(-600, 600, dtype=np.int16),
                                     np.arange(1000, 2200, dtype=np.int64) * 10**9])
def test_an_array_reads_as_a_tiff_of_the_same_samples(tmp_path, samples):
    """Signed samples below 0 and 64-bit ones: the API reads the array as load_image reads a
    TIFF holding it (by its own range), levels and greys alike."""
    import tifffile
    image = samples.reshape(30, 40)
    tifffile.imwrite(tmp_path / "s.tif", image)
    read = lv.load_image(tmp_path / "s.tif")
    assert np.array_equal(lv.quantize(image, 4).levels, lv.quantize(read, 4).levels)
    assert np.allclose(lv.to_grey(image), lv.to_grey(read), atol=1e-7)
