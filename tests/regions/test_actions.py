"""The region operators as Actions (issue 5): JSON, labels, replay, undo, footprints, errors."""

import json

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support import PROPERTY, REFS, TINY, TINY_DPJS, draw_action
from tests.support.regions import EXAMPLES, T, grid, history_of, same
from texeditor.regions import extractext as regions
from texeditor.regions import transforms
from texeditor.recipe.actions import (REGISTRY, registry, NewCanvas, SetLevels, Synthesize, param_specs)
from texeditor.recipe.codec import action_from_json
from texeditor.recipe.document import dpj_ref
from texeditor.errors import FormatError, InputError, ReplayError
from texeditor.recipe.history import History
from texeditor.recipe.replay import replay
from texeditor.recipe.logopt import optimize
from texeditor.regions.actions import (REGION_ACTIONS, Affinity, ChangeLevel, Copy,
                                      DeleteSelection, Fill, FlipSelection, Identity, Isometry,
                                      RotateSelection, ScaleSelection, ScatterRegions,
                                      Similarity, Translate)


def test_every_region_action_is_registered():
    assert {cls.TYPE for cls in REGION_ACTIONS} <= set(registry())
    assert {type(a) for a in EXAMPLES} == set(REGION_ACTIONS)
    assert all(REGISTRY[cls.TYPE] is cls and cls.EFFECT == "levels" for cls in REGION_ACTIONS)


@pytest.mark.parametrize("action", EXAMPLES, ids=lambda a: a.TYPE)
def test_json_round_trip_and_identical_replay(action):
    obj = json.loads(json.dumps(action.to_json()))
    assert obj["type"] == action.TYPE and obj["version"] == action.VERSION
    again = action_from_json(obj)
    assert again == action and hash(again) == hash(action)
    history = history_of(T)
    before = history.document.levels.copy()
    history.apply(action)
    live = history.document
    replayed = replay([action_from_json(a.to_json()) for a in history.actions], {})
    assert np.array_equal(replayed.levels, live.levels)
    assert replayed.result_hash() == live.result_hash()
    assert history.undo() and np.array_equal(history.document.levels, before)
    assert history.redo() and replayed.result_hash() == history.document.result_hash()


def test_a_whole_log_of_region_actions_replays_bit_for_bit():
    history = history_of(T)
    for action in EXAMPLES:
        history.apply(action)
    assert replay(history.actions, {}).result_hash() == history.document.result_hash()
    assert replay(optimize(history.actions), {}).result_hash() == history.document.result_hash()


def test_labels_are_short_and_human():
    assert Fill(3, 2, 7).label() == "Fill region at (3, 2) with 7"
    assert Fill(3, 2, 7, scope="global").label() == "Fill every point like (3, 2) with 7"
    assert Translate(1, 7, 0, 6).label() == "Translate region at (1, 7) to (0, 6)"
    assert Copy(1, 1, 3, 3, kind="neighbours", connectivity=8).label() == \
        "Copy neighbours at (1, 1), 8-conn. to (3, 3)"
    assert ChangeLevel(1, 1, 2, kind="regions_in_region").label() == \
        "Set regions in region at (1, 1) to level 2"
    assert DeleteSelection(2, 2, kind="partial", scope="global").label() == \
        "Delete partial region of level at (2, 2)"
    assert ScaleSelection(1, 1, 1.5).label() == "Scale region at (1, 1) ×1.5"
    assert RotateSelection(1, 1, 30).label() == "Rotate region at (1, 1) by 30°"
    assert FlipSelection(1, 1).label() == "Flip region at (1, 1) left-right"
    assert Identity(0, 4, 2, 3, row=1, col=1).label() == \
        "Duplicate region at (1, 1) by (0, 4), 2×3 grid"
    assert Isometry(90, 3.5, 3.5).label() == "Rotate texture 90° about (3.5, 3.5)"
    assert Similarity(0.5, -0.5, -0.5).label() == "Zoom texture ×0.5 about (-0.5, -0.5)"
    assert Affinity(1, 0, 1, 1).label() == "Affine map of texture [1 0; 1 1]"
    assert all(0 < len(a.label()) < 60 for a in EXAMPLES)


# -- what each action does to a document ---------------------------------------------------------

def run(action, levels=T, g=4):
    history = history_of(levels, g)
    history.apply(action)
    return history.document.levels


def test_fill_translate_copy_through_the_document():
    assert same(run(Fill(3, 2, 2))[2:5], """
        . 1 2 2 2 1 . 2
        . 1 2 3 2 1 . .
        . 1 2 2 2 1 . .""")
    assert np.array_equal(run(Translate(1, 7, 0, 6)), regions.translate(T, (1, 7), (0, 6)))
    assert same(run(Translate(7, 0, 7, -1, fill=3))[7], "2 3 . . . . 3 3")
    assert np.array_equal(run(Translate(4, 4, 4, 4)), T)
    assert np.array_equal(run(Copy(1, 1, 3, 3)), regions.copy(T, (1, 1), (3, 3)))


def test_selections_follow_their_recipe():
    assert same(run(ChangeLevel(1, 1, 2, kind="region_in_region"))[2:5, 1:6], """
        1 2 2 2 1
        1 2 3 2 1
        1 2 2 2 1""")
    deleted = run(DeleteSelection(1, 1, kind="regions_in_region", scope="global"))
    assert not deleted[3, 3] and deleted[1, 1] == 1
    moved = run(Translate(1, 1, 1, 4, kind="regions_in_region", fill=1))
    assert np.array_equal(moved, regions.move(T, regions.extract_regions_in_region(T, (1, 1)),
                                              (0, 3), fill=1))
    for action in EXAMPLES:
        if getattr(action, "row", None) is not None:
            mask = regions.select(T, (action.row, action.col), kind=getattr(action, "kind",
                                                                            "region"),
                                  scope=action.scope, connectivity=action.connectivity,
                                  neighbour=getattr(action, "neighbour", None))
            assert np.array_equal(action.selection(T), mask)


def test_local_manipulations_through_the_document():
    line = grid("""
        . . . . .
        . 1 1 1 .
        . . . . .""")
    assert same(run(RotateSelection(1, 2, 90), line), """
        . . 1 . .
        . . 1 . .
        . . 1 . .""")
    assert np.array_equal(run(RotateSelection(1, 2, 45, kind="neighbours", fill=2), line),
                          regions.rotate(line, regions.select(line, (1, 2), kind="neighbours"),
                                         45, fill=2))
    assert same(run(FlipSelection(0, 0, "vertical"), grid("""
        1 1
        1 .""")), """
        1 .
        1 1""")
    assert same(run(ScaleSelection(1, 1, 2, factor_cols=1), grid("""
        . . .
        . 1 .
        . . .""")), """
        . 1 .
        . 1 .
        . . .""")
    assert np.array_equal(run(ScaleSelection(1, 1, 0.5, kind="regions_in_region", fill=3)),
                          regions.scale(T, regions.extract_regions_in_region(T, (1, 1)), 0.5,
                                        fill=3))


def test_global_operators_on_the_whole_texture_and_on_a_selection():
    assert np.array_equal(run(Isometry(90, 3.5, 3.5)), np.rot90(T))
    assert np.array_equal(run(Identity(2, 3, wrap=True)), np.roll(T, (2, 3), axis=(0, 1)))
    assert np.array_equal(run(Similarity(0.5, -0.5, -0.5, wrap=True)),
                          np.tile(T[1::2, 1::2], (2, 2)))
    ring = regions.extractext(T, (1, 1))
    assert np.array_equal(run(Isometry(180, 3, 3, row=1, col=1)),
                          transforms.isometry(T, 180, (3, 3), mask=ring))
    assert np.array_equal(run(Identity(2, -4, 1, 2, 0, -2, row=1, col=7)),
                          transforms.identity(T, (2, -4), mask=regions.extractext(T, (1, 7)),
                                              repeat=(1, 2), step=(0, -2)))
    assert np.array_equal(run(Affinity(1, 0, 1, 1, keep_source=True)),
                          transforms.affinity(T, ((1, 0), (1, 1)), keep_source=True))


def test_an_empty_selection_is_a_no_op_that_costs_nothing():
    history = history_of(T)
    before = history.document.result_hash()
    records = history.memory["undo_records"]
    history.apply(ChangeLevel(7, 7, 1, kind="region_in_region"))    # the corner encloses nothing
    history.apply(RotateSelection(3, 3, 90))                         # one point onto itself
    history.apply(Translate(3, 3, 3, 3))                             # a region onto itself
    assert history.document.result_hash() == before
    assert history.memory["undo_records"] == records
    flat = history_of(np.full((4, 4), 2, np.uint8))
    flat.apply(FlipSelection(0, 0, kind="neighbours"))
    assert (flat.document.levels == 2).all()


def test_the_undo_record_holds_only_what_changed():
    history = History()
    history.apply(NewCanvas(256, 256, 3))
    history.apply(SetLevels(100, 50, 4, 3, 1))
    before = history.memory["undo_records"]
    history.apply(Fill(101, 51, 2))
    assert history.memory["undo_records"] - before == 12               # the 4×3 region
    history.apply(Translate(101, 51, 201, 151))                        # far: two small patches
    assert history.memory["undo_records"] - before == 12 + 2 * 12
    history.apply(Translate(201, 151, 202, 152))                       # near: one box
    assert history.memory["undo_records"] - before == 12 + 2 * 12 + 5 * 4
    for _ in range(3):
        history.undo()
    assert history.document.levels[100, 50] == 1 and history.document.levels.sum() == 12


def test_changed_boxes_cut_along_empty_bands():
    from texeditor.regions.actions import changed_boxes
    changed = np.zeros((40, 40), bool)
    assert changed_boxes(changed) == []
    changed[0, 0] = changed[30, 35] = changed[2, 37] = True
    assert sorted(changed_boxes(changed)) == [(0, 0, 1, 1), (2, 37, 3, 38), (30, 35, 31, 36)]
    changed[::2, ::2] = True                                            # scattered: one box
    assert changed_boxes(changed) == [(0, 0, 39, 39)]
    dots = np.zeros((400, 400), bool)
    dots[::10, ::10] = True                                             # many: at most 16
    boxes = changed_boxes(dots)
    assert len(boxes) <= 16 and sum((b - t) * (r - l) for t, l, b, r in boxes) >= 1600
    covered = np.zeros_like(dots)
    for t, l, b, r in boxes:
        covered[t:b, l:r] = True
    assert not (dots & ~covered).any()


# -- errors --------------------------------------------------------------------------------------

@pytest.mark.parametrize("make, message", [
    (lambda: Fill(0, 0, 16), "value = 16"),
    (lambda: Fill(-1, 0, 1), "row = -1"),
    (lambda: Fill(0, 0, 1, scope="local"), "scope must be"),
    (lambda: Fill(0, 0, 1, connectivity=6), "connectivity must be 4 or 8"),
    (lambda: Copy(0, 0, 1, 1, kind="lasso"), "kind must be one of"),
    (lambda: FlipSelection(0, 0, "diagonal"), "axis must be"),
    (lambda: Identity(0, 1, row=3), "both row and col"),
    (lambda: Identity(0, 1, step_rows=3), "both grid steps"),
    (lambda: Identity(0, 1, repeat_rows=0), "repeat_rows = 0"),
    (lambda: Affinity(1, 2, 2, 4), "singular"),
    (lambda: Similarity(0, 0, 0), "factor = 0.0"),
    (lambda: ScaleSelection(0, 0, 100), "factor = 100.0"),
    (lambda: Isometry(float("nan"), 0, 0), "angle"),
])
def test_bad_parameters_are_input_errors(make, message):
    with pytest.raises(InputError, match=message):
        make()


def test_malformed_json_is_a_format_error():
    with pytest.raises(FormatError, match="kind must be one of"):
        action_from_json({"type": "copy", "version": 1, "row": 0, "col": 0, "to_row": 1,
                          "to_col": 1, "kind": "everything"})
    with pytest.raises(FormatError, match="lacks parameters"):
        action_from_json({"type": "fill", "version": 1, "row": 0, "col": 0})


def test_points_outside_the_canvas_and_missing_levels_fail_cleanly():
    history = history_of(T)
    before = history.document.result_hash()
    with pytest.raises(InputError, match=r"point \(8, 0\) is outside the 8×8 canvas"):
        history.apply(Fill(8, 0, 1))
    with pytest.raises(InputError, match="level 5 does not exist"):
        history.apply(Translate(1, 1, 2, 2, fill=5))
    with pytest.raises(InputError, match="level 9 does not exist"):
        history.apply(ChangeLevel(7, 7, 9, kind="region_in_region"))   # even when selecting none
    assert history.document.result_hash() == before and len(history.actions) == len(T[T > 0]) + 1
    with pytest.raises(ReplayError, match="step 2 .*Fill region at \\(9, 9\\)"):
        replay([NewCanvas(4, 4, 2), Fill(9, 9, 1)], {})


def test_param_specs_drive_the_edit_forms():
    specs = {s.name: s for s in param_specs(Isometry)}
    assert specs["angle"].kind == "float" and specs["row"].optional and specs["row"].value is None
    assert specs["connectivity"].value == 4 and specs["kind"].value == "region"


# -- properties ----------------------------------------------------------------------------------

KIND_SCOPE = st.tuples(st.sampled_from(regions.KINDS), st.sampled_from(regions.SCOPES),
                       st.sampled_from(regions.CONNECTIVITIES))


def draw_region_action(data, doc):
    """A random region action on the document as it stands (points inside the canvas)."""
    h, w = doc.shape
    g = doc.num_levels
    r, c = data.draw(st.integers(0, h - 1)), data.draw(st.integers(0, w - 1))
    kind, scope, conn = data.draw(KIND_SCOPE)
    neighbour = data.draw(st.none() | st.integers(1, 3)) if kind == "neighbours" else None
    sel = dict(kind=kind, scope=scope, connectivity=conn, neighbour=neighbour)
    level = st.integers(0, g - 1)
    to = (data.draw(st.integers(-3, h + 2)), data.draw(st.integers(-3, w + 2)))
    which = data.draw(st.integers(0, 12))
    centre = (data.draw(st.floats(-2, h + 2)), data.draw(st.floats(-2, w + 2)))
    whole = data.draw(st.booleans())
    target = dict(row=None, col=None) if whole else dict(row=r, col=c)
    wrap = data.draw(st.booleans())
    return [
        lambda: Fill(r, c, data.draw(level), scope=scope, connectivity=conn),
        lambda: Translate(r, c, *to, fill=data.draw(level), wrap=wrap, **sel),
        lambda: Copy(r, c, *to, wrap=wrap, **sel),
        lambda: ChangeLevel(r, c, data.draw(level), **sel),
        lambda: DeleteSelection(r, c, **sel),
        lambda: ScaleSelection(r, c, data.draw(st.floats(0.25, 3)), wrap=wrap, **sel),
        lambda: RotateSelection(r, c, data.draw(st.floats(-360, 360)), wrap=wrap, **sel),
        lambda: FlipSelection(r, c, data.draw(st.sampled_from(["horizontal", "vertical"])),
                              **sel),
        lambda: Identity(to[0], to[1], data.draw(st.integers(1, 3)), data.draw(st.integers(1, 3)),
                         wrap=wrap, **target, **sel),
        lambda: Isometry(data.draw(st.floats(-360, 360)), *centre, wrap=wrap,
                         keep_source=data.draw(st.booleans()), **target, **sel),
        lambda: Similarity(data.draw(st.floats(0.3, 3)), *centre, wrap=wrap, **target, **sel),
        lambda: Affinity(1, data.draw(st.floats(-1, 1)), data.draw(st.floats(-1, 1)), 1.5, *centre,
                         wrap=wrap, **target, **sel),
        lambda: ScatterRegions(data.draw(st.integers(0, 9)), radius=data.draw(st.floats(0, 4)),
                               rotation=data.draw(st.sampled_from(["none", "quarter", "any"])),
                               scale_min=0.5, scale_max=data.draw(st.floats(0.5, 2)),
                               fill=data.draw(level), wrap=wrap, **target, **sel),
    ][which]()


def mixed_history(data, steps: int = 10) -> History:
    """A synthesised texture, then random region actions mixed with the other actions."""
    history = History(snapshot_every=4)
    for d in TINY_DPJS:
        history.document.add_dpj(d, dpj_ref(d))
    history.apply(Synthesize(data.draw(st.sampled_from(REFS)), data.draw(st.integers(2, 9)),
                             data.draw(st.integers(2, 9)), data.draw(st.integers(0, 3))))
    for _ in range(data.draw(st.integers(1, steps))):
        doc = history.document
        try:
            if data.draw(st.integers(0, 3)) or doc.shape[0] == 0:
                history.apply(draw_region_action(data, doc))
            else:
                history.apply(draw_action(data, doc))
        except InputError:
            pass
    return history


@PROPERTY
@given(st.data())
def test_copy_then_undo_restores(data):
    history = mixed_history(data, steps=4)
    doc = history.document
    before = doc.levels.copy(), doc.result_hash()
    h, w = doc.shape
    history.apply(Copy(data.draw(st.integers(0, h - 1)), data.draw(st.integers(0, w - 1)),
                       data.draw(st.integers(-h, 2 * h)), data.draw(st.integers(-w, 2 * w)),
                       kind=data.draw(st.sampled_from(regions.KINDS)),
                       wrap=data.draw(st.booleans())))
    assert history.undo()
    assert np.array_equal(history.document.levels, before[0])
    assert history.document.result_hash() == before[1]


@PROPERTY
@given(st.data())
def test_mixed_logs_replay_optimise_undo_and_redo_identically(data):
    history = mixed_history(data)
    final = history.document.result_hash()
    again = replay([action_from_json(json.loads(json.dumps(a.to_json())))
                    for a in history.actions], TINY)
    assert again.result_hash() == final
    assert replay(optimize(history.actions, TINY), TINY).result_hash() == final
    k = data.draw(st.integers(0, history.index))
    for _ in range(k):
        history.undo()
    assert history.document.result_hash() == replay(history.actions[:history.index],
                                                    TINY).result_hash()
    for _ in range(k):
        history.redo()
    assert history.document.result_hash() == final
