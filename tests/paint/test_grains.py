"""Grains (thesis §3.3.3a, §5.3.1): exact masks, placement by the centre of gravity, drawn grains,
grain types as JSON, the grain library in the user data folder."""

import doctest
import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from texeditor.paint import grains
from texeditor.recipe.document import Document
from texeditor.errors import FormatError, InputError
from texeditor.paint.grains import GrainLibrary, GrainType, grain_mask
from texeditor.paint.actions import PlaceGrains
from texeditor.userdata import data_dir

ALL = [("square", {}), ("rectangle", {"aspect": 0.5}), ("circle", {}),
       ("circle", {"aspect": 0.6, "angle": 30}), ("diamond", {}), ("hexagon", {}),
       ("polygon", {"sides": 5}), ("polygon", {"sides": 3, "angle": 10}), ("line", {}),
       ("line", {"angle": 30}), ("square", {"angle": 45}),
       ("bitmap", {"bitmap": "0110/1111/0110"})]


def test_doctests():
    assert doctest.testmod(grains, optionflags=doctest.NORMALIZE_WHITESPACE).failed == 0


def as_int(mask):
    return mask.astype(int).tolist()


# -- masks ----------------------------------------------------------------------------------------

def test_small_masks_are_exact():
    assert as_int(grain_mask("square", 2)) == [[1, 1], [1, 1]]
    assert as_int(grain_mask("rectangle", 4, aspect=0.5)) == [[1, 1, 1, 1], [1, 1, 1, 1]]
    assert as_int(grain_mask("rectangle", 4, aspect=0.5, angle=90)) == [[1, 1]] * 4
    assert as_int(grain_mask("circle", 3)) == [[1, 1, 1]] * 3       # corners at √2 < 1.5
    assert as_int(grain_mask("circle", 5)) == [[0, 1, 1, 1, 0]] + [[1] * 5] * 3 + [[0, 1, 1, 1, 0]]
    assert as_int(grain_mask("diamond", 3)) == [[0, 1, 0], [1, 1, 1], [0, 1, 0]]
    assert as_int(grain_mask("hexagon", 8)) == [
        [0, 0, 0, 1, 0, 0, 0],
        [0, 1, 1, 1, 1, 1, 0],
        [1, 1, 1, 1, 1, 1, 1],
        [1, 1, 1, 1, 1, 1, 1],
        [1, 1, 1, 1, 1, 1, 1],
        [1, 1, 1, 1, 1, 1, 1],
        [0, 1, 1, 1, 1, 1, 0],
        [0, 0, 0, 1, 0, 0, 0]]
    assert as_int(grain_mask("polygon", 5, sides=4)) == as_int(grain_mask("diamond", 5))
    assert as_int(grain_mask("line", 4, angle=135)) == [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    assert as_int(grain_mask("square", 3, angle=45)) == [[0, 1, 1, 0], [1, 1, 1, 1],
                                                         [1, 1, 1, 1], [0, 1, 1, 0]]
    assert grain_mask("square", 5, angle=45).sum() == 25


@pytest.mark.parametrize("shape, options", ALL)
def test_masks_are_symmetric_and_sized(shape, options):
    for size in (1, 2, 3, 4, 7, 8, 15):
        mask = grain_mask(shape, size, **options)
        assert mask.dtype == bool and mask.any()
        assert mask.any(axis=0).all() and mask.any(axis=1).all()      # cropped to its box
        assert max(mask.shape) <= size * 1.5 + 1
        if shape != "bitmap" and options.get("angle", 0) % 90 == 0 \
                and shape not in ("hexagon", "polygon"):
            assert (mask == mask[::-1, ::-1]).all()                    # point symmetric


def test_a_quarter_turn_turns_the_mask():
    for shape, options in ALL:
        options = {**options, "angle": options.get("angle", 0)}
        a = grain_mask(shape, 7, **options)
        b = grain_mask(shape, 7, **{**options, "angle": options["angle"] + 90})
        if shape in ("bitmap", "rectangle", "line") or options["angle"] % 90 == 0:
            assert (np.rot90(a) == b).all(), shape


def test_bad_shapes_are_explained():
    for args, kw in ((("star", 3), {}), (("square", 0), {}), (("square", 300), {}),
                     (("polygon", 5), {"sides": 2}), (("circle", 5), {"aspect": 0}),
                     (("circle", 5), {"angle": float("nan")}), (("bitmap", 5), {}),
                     (("square", 2.5), {})):
        with pytest.raises(InputError):
            grain_mask(*args, **kw)


# -- placing by the centre of gravity -----------------------------------------------------------

@pytest.mark.parametrize("shape, options", ALL)
@pytest.mark.parametrize("size", [1, 2, 3, 4, 5, 6, 9, 10])
def test_a_grain_is_placed_with_its_centre_of_gravity_on_the_clicked_cell(shape, size, options):
    doc = Document.new(40, 40, 4)
    doc.apply(PlaceGrains(points=((17, 22),), level=2, shape=shape, size=size, **options))
    rows, cols = np.nonzero(doc.levels)
    cy, cx = rows.mean(), cols.mean()
    assert doc.levels[17, 22] == 2                        # the clicked cell is painted
    d2 = (rows - cy) ** 2 + (cols - cx) ** 2
    nearest = {(r, c) for r, c, d in zip(rows, cols, d2) if d <= d2.min() + 1e-9}
    assert (17, 22) in nearest                            # and it is the nearest to the centre
    assert abs(cy - 17) <= 0.75 and abs(cx - 22) <= 0.75
    if size % 2 and shape in ("square", "circle", "diamond") and not options:
        assert (cy, cx) == (17, 22)                       # odd symmetric grains: exactly


def test_even_grains_sit_above_left_of_the_clicked_cell():
    doc = Document.new(10, 10, 2)
    doc.apply(PlaceGrains(points=((5, 5),), level=1, shape="square", size=4))
    assert (doc.levels[3:7, 3:7] == 1).all() and doc.levels.sum() == 16


def test_stamp_points_clip_or_wrap():
    mask = grain_mask("square", 3)
    rows, cols, keep = grains.stamp_points(mask, (0, 0), (5, 5))
    assert sorted(zip(rows.tolist(), cols.tolist())) == [(0, 0), (0, 1), (1, 0), (1, 1)]
    assert keep.sum() == 4
    rows, cols, keep = grains.stamp_points(mask, (0, 0), (5, 5), wrap=True)
    assert set(zip(rows.tolist(), cols.tolist())) == {(r, c) for r in (4, 0, 1) for c in (4, 0, 1)}


# -- drawn grains ---------------------------------------------------------------------------------

def test_bitmaps_parse_format_scale_and_turn():
    b = grains.parse_bitmap(["0120", "0f00"])
    assert b.tolist() == [[0, 1, 2, 0], [0, 15, 0, 0]]
    assert grains.format_bitmap(b) == "12/f0"                  # cropped to its points
    assert grains.bitmap_levels("12/30", 4).tolist() == [[1, 1, 2, 2], [1, 1, 2, 2],
                                                         [3, 3, 0, 0], [3, 3, 0, 0]]
    assert grains.bitmap_levels("12/30", angle=90).tolist() == [[2, 0], [1, 3]]
    assert grains.bitmap_levels("12/30", angle=-90).tolist() == [[3, 1], [0, 2]]
    turned = grains.bitmap_levels("1111/1111", angle=30)
    assert 6 <= (turned > 0).sum() <= 10
    for bad in ("", "12/3", "0/0", "1g", "1\\2", "1" * 65, 12):
        with pytest.raises(InputError):
            grains.parse_bitmap(bad)


def test_a_multi_level_grain_keeps_its_levels_or_takes_one():
    pebble = GrainType("P", "bitmap", 3, bitmap="010/121/010", own_levels=True)
    assert pebble.values(3)[pebble.mask()].tolist() == [1, 1, 2, 1, 1]
    assert pebble.replace(level=3).values(1)[pebble.mask()].tolist() == [3] * 5
    flat = pebble.replace(own_levels=False)
    assert flat.values(2)[flat.mask()].tolist() == [2] * 5


# -- grain types and the library -----------------------------------------------------------------

def test_grain_types_are_plain_json():
    for g in grains.standard_grains():
        again = GrainType.from_json(json.loads(json.dumps(g.to_json())))
        assert again == g and (again.mask() == g.mask()).all()
    names = [g.name for g in grains.standard_grains()]
    assert len(names) == len(set(names))
    shapes = {g.shape for g in grains.standard_grains()}
    assert set(grains.SHAPES) <= shapes
    for bad in ({"shape": "blob"}, {"size": -1}, {"level": 16}, {"level": True},
                {"name": ""}, {"bitmap": "11"}, {"shape": "bitmap"}, {"angle": "3"},
                {"extra": 1}, {"own_levels": 1}):
        with pytest.raises(InputError):
            GrainType.from_json({"name": "x", **bad})
    with pytest.raises(InputError):
        GrainType.from_json([1, 2])


def test_the_data_folder_follows_the_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path / "d"))
    assert data_dir() == tmp_path / "d"
    monkeypatch.delenv("TEXEDITOR_DATA")
    assert data_dir().name == "texeditor"


def test_the_library_keeps_user_grains_in_the_data_folder(tmp_path, monkeypatch):
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path / "data"))
    lib = GrainLibrary()
    assert lib.path == tmp_path / "data" / "grains.json"
    assert lib.user() == [] and len(lib.all()) == len(grains.standard_grains())
    mine = GrainType("Seed", "bitmap", 5, bitmap="010/111/010", level=3)
    lib.save(mine)                                                  # creates the folder
    lib.save(GrainType("Flake", "polygon", 9, sides=7, angle=12.5))
    lib.save(mine.replace(size=7))                                  # replaces by name
    again = GrainLibrary(tmp_path / "data")
    assert [g.name for g in again.user()] == ["Flake", "Seed"]
    assert again.get("Seed").size == 7 and again.get("Circle 5").shape == "circle"
    with pytest.raises(InputError):
        lib.save(GrainType("Circle 5", "square", 2))
    with pytest.raises(InputError):
        lib.remove("Hexagon 8")
    with pytest.raises(InputError):
        lib.get("Nothing")
    lib.remove("Flake")
    assert [g.name for g in lib.user()] == ["Seed"]
    assert sorted(p.name for p in lib.path.parent.iterdir()) == ["grains.json"]


@pytest.mark.parametrize("content, message", [
    (b"{not json", "not a texeditor-grains library"),
    (b'{"format": "texeditor-bank", "version": 1, "items": []}', "not a texeditor-grains"),
    (b'{"format": "texeditor-grains", "version": 9, "items": []}', "version 9"),
    (b'{"format": "texeditor-grains", "version": 1, "items": {}}', "at most"),
    (b'{"format": "texeditor-grains", "version": 1, "items": [{"name": "a", "size": 0}]}',
     "grain 1"),
    (b"\xff\xfe", "not a texeditor-grains library"),
])
def test_a_damaged_library_is_a_clear_error(tmp_path, content, message):
    lib = GrainLibrary(tmp_path)
    lib.path.write_bytes(content)
    with pytest.raises(FormatError, match=message):
        lib.user()


def test_an_oversized_library_is_refused_before_reading(tmp_path):
    lib = GrainLibrary(tmp_path)
    lib.path.write_bytes(b" " * (5 * 2**20))
    with pytest.raises(FormatError, match="limit"):
        lib.user()


json_values = st.recursive(st.none() | st.booleans() | st.integers(-10**6, 10**6)
                           | st.floats(allow_nan=True) | st.text(max_size=12),
                           lambda inner: st.lists(inner, max_size=3)
                           | st.dictionaries(st.text(max_size=5), inner, max_size=3),
                           max_leaves=6)
fields = st.sampled_from(["name", "shape", "size", "aspect", "sides", "angle", "level",
                          "own_levels", "bitmap"])


@settings(max_examples=300, deadline=None)
@given(st.dictionaries(fields, json_values, max_size=9))
def test_any_json_object_is_a_grain_or_an_input_error(obj):
    """A library file is the user's: whatever it holds, reading it never crashes."""
    from texeditor.paint.brushes import Brush
    for cls, extra in ((GrainType, {}), (Brush, {"distribution": "cloud"})):
        try:
            cls.from_json({**extra, **{k: v for k, v in obj.items()
                                       if k in {f for f in cls.__dataclass_fields__}}})
        except InputError:
            pass
