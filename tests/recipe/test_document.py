"""Document: read-only state, the result hash, copies, DPJ references, the undo atoms."""

import hashlib

import numpy as np
import pytest

from tests.support import TINY_DPJS
from texeditor.recipe.actions import NewCanvas, SetLevels, SetPalette
from texeditor.recipe.document import Document, dpj_ref
from texeditor.errors import InputError


def test_empty_document():
    doc = Document()
    assert doc.shape == (0, 0) and doc.num_levels == 2 and doc.dpj is None
    assert doc.actions == () and doc.dpjs == {}


def test_new_canvas_is_background_and_logged():
    doc = Document.new(5, 3, 4)
    assert doc.shape == (3, 5) and doc.num_levels == 4 and not doc.levels.any()
    assert doc.levels.dtype == np.uint8 and doc.palette.shape == (4, 3)
    assert doc.actions == (NewCanvas(5, 3, 4),)


def test_levels_and_palette_are_read_only():
    doc = Document.new(2, 2, 2)
    with pytest.raises(ValueError):
        doc.levels[0, 0] = 1
    with pytest.raises(ValueError):
        doc.palette[0, 0] = 1


def test_result_hash_covers_levels_shape_and_palette():
    a, b = Document.new(4, 2, 3), Document.new(2, 4, 3)
    assert a.result_hash() != b.result_hash()          # same bytes, other shape
    c = Document.new(4, 2, 3)
    assert a.result_hash() == c.result_hash()
    c.apply(SetPalette(((0, 0, 0), (1, 1, 1), (2, 2, 2))))
    assert a.result_hash() != c.result_hash()
    c = Document.new(4, 2, 3).apply(SetLevels(0, 0, 1, 1, 1))
    assert a.result_hash() != c.result_hash()


def test_copy_is_independent():
    doc = Document.new(3, 3, 3)
    other = doc.copy()
    other.apply(SetLevels(0, 0, 1, 1, 2))
    assert doc.levels[0, 0] == 0 and len(doc.actions) == 1 and len(other.actions) == 2


def test_add_dpj_reference_is_the_sha256_prefix_of_its_file_bytes():
    doc = Document()
    ref = doc.add_dpj(TINY_DPJS[0])
    assert ref == hashlib.sha256(TINY_DPJS[0].to_bytes()).hexdigest()[:16] == dpj_ref(TINY_DPJS[0])
    assert doc.dpjs[ref] is TINY_DPJS[0] and doc.dpj is TINY_DPJS[0]
    with pytest.raises(InputError):
        doc.add_dpj("not a dpj")


def test_writes_record_only_their_footprint():
    doc = Document.new(100, 100, 4)
    mask = np.zeros((100, 100), bool)
    mask[50, 60] = mask[52, 61] = True
    with doc.step(record=[]) as atoms:
        doc.fill(10, 10, 2, 3, 1)
        doc.write_where(mask, 3)
    assert sum(a.nbytes for a in atoms) == 6 + 6           # 2×3 and the mask's 3×2 box
    assert doc.levels[50, 60] == doc.levels[52, 61] == 3 and doc.levels[51, 60] == 0
    for atom in reversed(atoms):
        atom.swap(doc)
    assert not doc.levels.any()


def test_mutators_refuse_levels_beyond_g():
    doc = Document.new(3, 3, 2)
    with doc.step():
        with pytest.raises(InputError, match="level 2"):
            doc.write(0, 0, np.full((2, 2), 2))
        with pytest.raises(InputError, match="outside"):
            doc.write(2, 2, np.zeros((2, 2)))
        with pytest.raises(InputError, match="uses level 5"):
            doc.set_levels(np.full((2, 2), 5, np.uint8))


def test_only_an_action_changes_a_document():
    """The edit interface works inside a step only: the GUI cannot write a document directly."""
    doc = Document.new(3, 3, 2)
    for edit in (lambda: doc.write(0, 0, np.ones((1, 1))), lambda: doc.fill(0, 0, 1, 1, 1),
                 lambda: doc.set_levels(np.ones((2, 2), np.uint8)),
                 lambda: doc.write_where(np.ones((3, 3), bool), 1),
                 lambda: doc.set_palette(((0, 0, 0), (1, 1, 1))),
                 lambda: doc.set_current_dpj(None)):
        with pytest.raises(InputError, match="only through an Action"):
            edit()
    assert not doc.levels.any() and doc.actions == doc.actions[:1]
    with doc.step():
        with pytest.raises(InputError, match="already being applied"):
            with doc.step():
                pass
