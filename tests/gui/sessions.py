"""The realistic sessions of the session tests, one per tool family, run in a child process by
``session_runner``: at least five gestures, the same tool twice in a row, a click after a stroke,
tools switched midway; every gesture must add exactly one step of the expected kind; then Ctrl+Z
back to the synthesised texture and Ctrl+Shift+Z forward to the final document.
"""

from __future__ import annotations

import sys
import traceback

import numpy as np
from PySide6 import QtCore, QtTest

from app.tools.brush import BrushTool, SprayTool
from app.tools.grain import GrainTool
from app.tools.regions import CopyTool, ExtractTool, FillTool, TranslateTool
from app.tools.spot import SpotTool
from app.tools.zone import ScrambleTool, ZoneTool
from texeditor.regions import actions as ra
from texeditor.recipe.actions import SetPalette
from texeditor.paint.actions import DuplicateZone, PlaceGrains, ScrambleFrontier, Stroke
from texeditor.spots.actions import DeleteSpot, PlaceSpot, ScatterSpots

from .session_runner import Hand, Recorder, close_window, open_window, report, same_document, state

SHIFT = QtCore.Qt.KeyboardModifier.ShiftModifier


def row(y: int, x0: int = 6, x1: int = 54):
    return [(x, y) for x in range(x0, x1 + 1, 8)]


class Session:
    """A hand that checks each gesture on the document: one new step, of the expected Action."""

    def __init__(self, hand: Hand):
        self.hand, self.win = hand, hand.win
        self.gestures: list[str] = []

    def expect(self, kind, gesture, *args, changes: bool = True, **kwargs):
        """Do a gesture; it must add one step of ``kind`` (and change the levels or palette)."""
        before, index = state(self.win), self.win.history.index
        gesture(*args, **kwargs)
        self.hand.wait_idle()
        history = self.win.history
        name = getattr(gesture, "__name__", str(gesture))
        assert history.index == index + 1, \
            f"{name} {kind.__name__}: {history.index - index} new steps instead of one"
        action = history.actions[history.index - 1]
        assert isinstance(action, kind), \
            f"{name}: made {type(action).__name__}, not {kind.__name__}"
        if changes:
            after = state(self.win)
            assert not same_document({**before, "index": 0}, {**after, "index": 0}), \
                f"{name} {kind.__name__}: the document did not change"
        self.gestures.append(type(action).__name__)
        return action

    def other_level(self, cell) -> int:
        """Click the swatch of a level unlike the one at cell (so a fill changes something)."""
        level = (self.hand.level_at(cell) + 1) % self.win.document.num_levels
        self.hand.swatch(level)
        return level


# -- the sessions ----------------------------------------------------------------------------------

def paint(s: Session) -> None:
    """Brush twice, a click with the brush, a Fill click after a stroke, Spray, Grain, Brush."""
    hand, win = s.hand, s.win
    hand.choose(BrushTool)
    hand.swatch(3)
    stroke = s.expect(Stroke, hand.stroke, row(10))
    assert stroke.level == 3 and (win.document.levels[10, 6:55] == 3).all(), "no brush line"
    s.expect(Stroke, hand.stroke, row(30))                     # the second stroke (the crash)
    s.expect(Stroke, hand.click, (40, 20), changes=False)
    hand.choose(FillTool)
    s.other_level((20, 40))
    s.expect(ra.Fill, hand.click, (20, 40))
    hand.choose(SprayTool, by_button=True)
    s.expect(Stroke, hand.stroke, row(38, 10, 50))
    hand.choose(GrainTool)
    hand.swatch(1)
    grain = s.expect(PlaceGrains, hand.click, (12, 24), changes=False)
    assert grain.points == ((24, 12),), "the grain is not where the click was"
    s.expect(PlaceGrains, hand.stroke, row(44, 4, 60), modifiers=SHIFT, changes=False)
    hand.choose(BrushTool, by_button=True)
    hand.swatch(2)
    s.expect(Stroke, hand.stroke, [(5, 5), (20, 12), (35, 5)])
    assert (win.document.levels[10, 6:55] != 0).any()


def regions(s: Session) -> None:
    """Fill twice, Translate, Copy, Extract with every panel button, a Fill after a stroke."""
    hand, win = s.hand, s.win
    hand.choose(FillTool)
    level = s.other_level((5, 5))
    s.expect(ra.Fill, hand.click, (5, 5))
    assert win.document.levels[5, 5] == level
    s.other_level((40, 30))
    s.expect(ra.Fill, hand.click, (40, 30))
    hand.choose(TranslateTool)
    s.expect(ra.Translate, hand.stroke, [(20, 20), (24, 23), (28, 26)])
    hand.choose(CopyTool, by_button=True)
    s.expect(ra.Copy, hand.stroke, [(10, 30), (20, 25), (40, 12)])
    hand.choose(ExtractTool)
    tool = win.tool
    hand.click((30, 20))
    assert tool.selection is not None and tool.panel.isEnabled(), "nothing selected"
    panel = tool.panel
    s.expect(ra.FlipSelection, hand.button, panel.flip_h, changes=False)
    s.expect(ra.RotateSelection, hand.button, panel.rotate, changes=False)
    s.expect(ra.ScaleSelection, hand.button, panel.scale_button, changes=False)
    s.expect(ra.Identity, hand.button, panel.duplicate, changes=False)
    s.other_level((tool.selection["col"], tool.selection["row"]))
    s.expect(ra.ChangeLevel, hand.button, panel.recolour)
    s.expect(ra.DeleteSelection, hand.button, panel.delete)
    assert tool.selection is None
    hand.choose(BrushTool)
    hand.swatch(1)
    s.expect(Stroke, hand.stroke, row(40))
    hand.choose(FillTool)
    s.other_level((30, 40))
    s.expect(ra.Fill, hand.click, (30, 40))                     # a click after a stroke
    hand.choose(ExtractTool, by_button=True)
    hand.click((30, 40))
    s.expect(ra.FlipSelection, hand.button, win.tool.panel.flip_v, changes=False)


def spots(s: Session) -> None:
    """Place twice, place by a drag, a brush stroke, scatter, then delete a placed spot."""
    hand, win = s.hand, s.win
    hand.choose(SpotTool)
    tool = win.tool
    QtTest.QTest.qWait(300)                       # the spot editor's dock takes its place
    tool.editor.load(tool.editor.library.get("Ellipse"))
    tool.opts.scale_box.setValue(0.4)
    hand.swatch(3)
    first = s.expect(PlaceSpot, hand.click, (20, 15))
    assert (first.row, first.col) == (15, 20) and win.document.levels[15, 20] == 3
    s.expect(PlaceSpot, hand.click, (44, 30))
    s.expect(PlaceSpot, hand.stroke, [(30, 10), (34, 12), (38, 14)])
    hand.choose(BrushTool)
    hand.swatch(1)
    s.expect(Stroke, hand.stroke, row(40))
    hand.choose(SpotTool, by_button=True)
    s.expect(PlaceSpot, hand.click, (10, 40))                     # a click after a stroke
    tool.opts.mode.setCurrentIndex(tool.opts.mode.findData("scatter"))
    tool.opts.count.setValue(8)
    tool.opts.scale_max.setValue(0.5)
    s.expect(ScatterSpots, hand.stroke, [(2, 2), (20, 12), (30, 20)])
    tool.opts.mode.setCurrentIndex(tool.opts.mode.findData("delete"))
    s.expect(DeleteSpot, hand.click, (44, 30))


def zones(s: Session) -> None:
    """Draw a zone, duplicate it twice, scramble its frontier twice, a stroke, scramble again."""
    hand, win = s.hand, s.win
    hand.choose(ZoneTool)
    hand.stroke([(2, 3), (6, 6), (11, 10)])                 # draws the zone: no step
    assert win.tool.zone is not None and win.history.index == 1
    s.expect(DuplicateZone, hand.stroke, [(5, 5), (15, 10), (25, 15)])
    s.expect(DuplicateZone, hand.stroke, [(25, 15), (35, 20), (45, 30)])
    hand.choose(ScrambleTool)
    win.tool.opts.density.setValue(60)
    s.expect(ScrambleFrontier, hand.click, (45, 30))
    s.expect(ScrambleFrontier, hand.click, (45, 30))
    hand.choose(BrushTool, by_button=True)
    s.expect(Stroke, hand.stroke, row(42))
    hand.choose(ScrambleTool, by_button=True)
    s.expect(ScrambleFrontier, hand.click, (45, 30))
    hand.choose(ZoneTool)
    s.expect(DuplicateZone, hand.stroke, [(45, 30), (30, 20), (10, 20)])


def palette(s: Session) -> None:
    """Swatches choose the level of strokes and fills; the grey-scale sliders and Reset make
    palette steps between them."""
    hand, win = s.hand, s.win
    dock = win.palette_dock
    hand.choose(BrushTool)
    for level, y in ((1, 8), (3, 16), (2, 24)):
        hand.swatch(level)
        stroke = s.expect(Stroke, hand.stroke, row(y))
        assert stroke.level == level and (win.document.levels[y, 6:55] == level).all()
    s.expect(SetPalette, _slider_steps, hand, dock.darkest, QtCore.Qt.Key.Key_PageUp, 2)
    s.expect(SetPalette, _slider_steps, hand, dock.contrast, QtCore.Qt.Key.Key_PageDown, 3)
    hand.choose(FillTool)
    s.other_level((40, 34))
    s.expect(ra.Fill, hand.click, (40, 34))
    s.expect(SetPalette, hand.button, dock.reset_button)
    before = state(win)
    hand.key(QtCore.Qt.Key.Key_PageUp, widget=dock.darkest)
    hand.undo()                  # at once: the key step is undone, never landed after the undo
    QtTest.QTest.qWait(600)
    assert same_document(state(win), before) and win.history.can_redo, \
        "a grey-scale key step then Ctrl+Z: the edit landed after the undo and dropped redo"
    hand.swatch(0)
    hand.choose(BrushTool)
    s.expect(Stroke, hand.stroke, row(40))


def _slider_steps(hand: Hand, slider, key, times: int) -> None:
    """Keyboard steps on a grey-scale slider; the dock commits them once they settle."""
    slider.setFocus()
    for _ in range(times):
        hand.key(key, widget=slider)
    QtTest.QTest.qWait(600)


def global_ops(s: Session) -> None:
    """Image ▸ Global operators… (Ctrl+G): rotate, zoom twice, a stroke, a selection zoomed,
    a grid of copies; the dialog stays open and is closed at the end."""
    hand, win = s.hand, s.win
    hand.shortcut("Ctrl+G")
    dialog = win._global_dialog
    assert dialog.isVisible(), "Ctrl+G showed no dialog"
    ops = dialog.operator
    s.expect(ra.Isometry, hand.button, dialog.apply_button)
    ops.setCurrentIndex(ops.findData("similarity"))
    s.expect(ra.Similarity, hand.button, dialog.apply_button)
    s.expect(ra.Similarity, hand.button, dialog.apply_button)
    hand.choose(BrushTool)
    hand.swatch(3)
    s.expect(Stroke, hand.stroke, row(24))
    hand.choose(ExtractTool)
    hand.click((30, 24))
    dialog.factor.setValue(1.5)
    action = s.expect(ra.Similarity, hand.button, dialog.apply_button, changes=False)
    assert (action.row, action.col) == (24, 30), "the dialog ignored the selection"
    ops.setCurrentIndex(ops.findData("affinity"))
    s.expect(ra.Affinity, hand.button, dialog.apply_button, changes=False)
    hand.click((-5, -5))                                     # outside: no selection
    ops.setCurrentIndex(ops.findData("identity"))
    s.expect(ra.Identity, hand.button, dialog.apply_button)
    dialog.close()


def mixed(s: Session) -> None:
    """Every family in one session, with an undo midway and new gestures on top of it."""
    hand, win = s.hand, s.win
    hand.choose(BrushTool)
    hand.swatch(3)
    s.expect(Stroke, hand.stroke, row(6))
    s.expect(Stroke, hand.stroke, row(12))
    hand.choose(FillTool)
    s.other_level((30, 30))
    s.expect(ra.Fill, hand.click, (30, 30))
    hand.undo()
    hand.undo()                                   # the second stroke and the fill are gone
    s.gestures[-2:] = []
    hand.choose(SpotTool)
    QtTest.QTest.qWait(300)
    win.tool.editor.load(win.tool.editor.library.get("Ellipse"))
    s.expect(PlaceSpot, hand.click, (40, 20))     # the redo steps are dropped
    assert not win.history.can_redo
    hand.choose(ZoneTool)
    hand.stroke([(4, 30), (8, 34), (14, 40)])
    s.expect(DuplicateZone, hand.stroke, [(6, 35), (20, 35), (40, 35)])
    hand.choose(GrainTool)
    s.expect(PlaceGrains, hand.click, (50, 10), changes=False)
    hand.shortcut("Ctrl+G")
    s.expect(ra.Isometry, hand.button, win._global_dialog.apply_button)
    win._global_dialog.close()
    hand.choose(ExtractTool)
    hand.click((20, 20))
    s.expect(ra.FlipSelection, hand.button, win.tool.panel.flip_h, changes=False)


SESSIONS = {f.__name__: f for f in (paint, regions, spots, zones, palette, global_ops, mixed)}


# -- running one -----------------------------------------------------------------------------------

def undo_redo(hand: Hand, start: dict, final: dict, steps: int) -> None:
    """Ctrl+Z back to the synthesised texture, Ctrl+Shift+Z forward to the final document."""
    win = hand.win
    for _ in range(steps):
        hand.undo()
    now = state(win)
    assert now["index"] == start["index"], f"undo stopped at step {now['index']}"
    assert np.array_equal(now["levels"], start["levels"]), \
        f"undo to the start left {int((now['levels'] != start['levels']).sum())} points changed"
    assert np.array_equal(now["palette"], start["palette"]), "undo to the start: another palette"
    assert np.array_equal(win.canvas.levels, start["levels"]), "the canvas shows another picture"
    hand.undo()                                   # the synthesis itself is not undone
    assert win.history.index == start["index"]
    for _ in range(steps):
        hand.redo()
    assert same_document(state(win), final), "redo to the end did not give the final document"
    assert np.array_equal(win.canvas.levels, final["levels"]), "the canvas is not the document"


def run_session(name: str) -> int:
    recorder = Recorder()
    win = open_window(recorder)
    hand = Hand(win)
    session = Session(hand)
    start = state(win)
    try:
        SESSIONS[name](session)
        final = state(win)
        steps = final["index"] - start["index"]
        assert steps >= 5 and steps == len(session.gestures), \
            f"{steps} steps for {len(session.gestures)} gestures"
        undo_redo(hand, start, final, steps)
        close_window(win)
    except AssertionError as exc:
        traceback.print_exc()
        print(f"session {name}: {exc}", file=sys.stderr)
        _print_recorded(recorder)
        return 1
    if recorder.exceptions:
        _print_recorded(recorder)
        return 1
    report(session=name, gestures=session.gestures, steps=steps,
           dialogs=[text for _kind, text in recorder.dialogs],
           start_hash=_digest(start), final_hash=_digest(final))
    return 0


def _digest(doc: dict) -> str:
    import hashlib
    return hashlib.sha1(doc["levels"].tobytes() + doc["palette"].tobytes()).hexdigest()[:12]


def _print_recorded(recorder: Recorder) -> None:
    for text in recorder.exceptions:
        print(f"EXCEPTION that reached Qt:\n{text}", file=sys.stderr)
    for kind, text in recorder.dialogs:
        print(f"{kind} dialog: {text}", file=sys.stderr)
