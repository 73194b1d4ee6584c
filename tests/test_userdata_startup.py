"""Issue 17, class 4 (engine side): bad libraries and journals are set aside, never deleted."""

import json
import os
import re

import pytest

from texeditor.recipe.journal import orphans, recover
from texeditor.libraries import check_libraries
from texeditor.userdata import set_aside


def test_good_libraries_are_left_alone(tmp_path):
    (tmp_path / "grains.json").write_text(
        json.dumps({"format": "texeditor-grains", "version": 1, "items": []}))
    assert check_libraries(tmp_path) == []
    assert check_libraries(tmp_path / "missing") == []
    assert (tmp_path / "grains.json").exists()


@pytest.mark.parametrize("name", ["grains.json", "brushes.json", "spots.json"])
@pytest.mark.parametrize("content", [b"garbage", b"[" * 100000, b"\xff\xfe", b'{"format": 1}',
                                     b'{"format":"x"}' + b" " * (5 * 2**20), "folder", "fifo"])
def test_a_bad_library_is_set_aside_and_named(tmp_path, name, content):
    path = tmp_path / name
    if content == "folder":
        path.mkdir()
    elif content == "fifo":
        os.mkfifo(path)
    else:
        path.write_bytes(content)
    [line] = check_libraries(tmp_path)
    assert not os.path.lexists(path)
    [moved] = list(tmp_path.glob(f"{name}.bad-*"))
    assert re.fullmatch(re.escape(name) + r"\.bad-\d{8}T\d{6}Z", moved.name)
    assert str(path) in line and moved.name in line
    if isinstance(content, bytes):
        assert moved.read_bytes() == content                   # kept as it was
    assert check_libraries(tmp_path) == []


def test_set_aside_never_overwrites(tmp_path):
    names = []
    for k in range(3):
        (tmp_path / "grains.json").write_text(str(k))
        names.append(set_aside(tmp_path / "grains.json").name)
    assert len(set(names)) == 3
    assert sorted((tmp_path / n).read_text() for n in names) == ["0", "1", "2"]


@pytest.mark.parametrize("time_field", ["1" + "0" * 400, "1e400", "NaN", "-Infinity", "-5",
                                        "1e300", "null", "[]"])
def test_an_impossible_journal_time_reads_as_unknown(tmp_path, time_field):
    path = tmp_path / "1-abc.journal"
    path.write_text(f'{{"kind":"start","format":1,"time":{time_field}}}\n'
                    '{"kind":"log","keep":0,"append":[]}\n')
    assert recover(path).started == 0.0


def test_orphans_lists_what_is_named_like_a_journal_without_failing(tmp_path):
    (tmp_path / "1-a.journal").mkdir()
    (tmp_path / "2-b.journal").symlink_to(tmp_path / "nowhere")
    (tmp_path / "3-c.journal").write_text("")
    assert {p.name for p in orphans(tmp_path)} == {"1-a.journal", "2-b.journal", "3-c.journal"}
