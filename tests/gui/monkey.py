"""A seeded monkey walk over the whole main window, run in a child process by ``session_runner``.

Hundreds of random user events — every tool by its shortcut or its button, drags and clicks on
the canvas (inside and off its edges), the wheel, the view keys, Space-drag, palette swatches,
the Synthesise button, clicks in the History list, undo and redo, the Extract panel, the spot
modes, the picture copied and pasted as a photo to acquire from, and the non-modal dialogs (global operators, composition, DPJ editor) opened, used and
closed; with ``models``, the Models menu's dialogs too; with ``photo``, a photo model attached
first, so Synthesise draws its scales and tone, tileable or not at random (and every edit draws
the tone again); with ``menus``, the menu bar's entries too (menu_entries). It fails on an exception that reaches Qt, on a crash (the parent sees the signal), or
when Ctrl+Z back to step 1 does not give back the synthesised texture and its palette (and
Ctrl+Shift+Z the document the walk ended on). ``run_start_walk``: the application's own start,
entries of the window chosen while its first texture opens in the worker and after.
"""

from __future__ import annotations

import random
import sys
import traceback

from PySide6 import QtCore, QtTest

from app.tools.regions import ExtractTool
from app.main_window import MENUS
from app.tools.spot import SpotTool

from .session_runner import Hand, Recorder, close_window, open_window, report, same_document, state

Key, Mod = QtCore.Qt.Key, QtCore.Qt.KeyboardModifier
VIEW_KEYS = {"0": Key.Key_0, "1": Key.Key_1, "W": Key.Key_W, "+": Key.Key_Plus,
             "-": Key.Key_Minus, "[": Key.Key_BracketLeft, "]": Key.Key_BracketRight}


class Walk:
    """The random walk: each event is one user gesture, logged so a failure can be read."""

    def __init__(self, hand: Hand, seed: int, models: bool = False, photo: bool = False,
                 menus: bool = False):
        self.hand, self.win, self.models, self.photo = hand, hand.win, models, photo
        self.menus = menus
        self.rng = random.Random(seed)
        self.log: list[str] = []
        self.made = 0              # events that added a step

    def cell(self, margin: int = 4):
        """A random cell, sometimes just off the canvas (drags leave it, clicks miss it)."""
        h, w = self.win.document.shape
        return (self.rng.randrange(-margin, w + margin), self.rng.randrange(-margin, h + margin))

    def path(self):
        return [self.cell() for _ in range(self.rng.randint(2, 5))]

    # -- the events --------------------------------------------------------------------------------
    def tool(self):
        tool = self.rng.choice(self.win.tools)
        by_button = self.rng.random() < 0.3
        self.hand.choose(type(tool), by_button=by_button)
        return f"tool {tool.NAME} by {'button' if by_button else 'shortcut'}"

    def drag(self):
        cells = self.path()
        shift = self.rng.random() < 0.15
        self.hand.stroke(cells, Mod.ShiftModifier if shift else None, move_ms=12)
        return f"drag {'shift ' if shift else ''}{cells}"

    def middle_drag(self):
        cells = self.path()
        self.hand.stroke(cells, button=QtCore.Qt.MouseButton.MiddleButton, move_ms=12)
        return f"middle-drag {cells}"

    def space_drag(self):
        canvas, cells = self.win.canvas, self.path()
        QtTest.QTest.keyPress(canvas, Key.Key_Space)
        self.hand.stroke(cells, move_ms=12)
        QtTest.QTest.keyRelease(canvas, Key.Key_Space)
        return f"space-drag {cells}"

    def click(self):
        cell = self.cell()
        ctrl = self.rng.random() < 0.1
        self.hand.click(cell, Mod.ControlModifier if ctrl else None)
        return f"click {'ctrl ' if ctrl else ''}{cell}"

    def wheel(self):
        cell, notches = self.cell(0), self.rng.choice([-2, -1, 1, 2])
        self.hand.wheel(cell, notches)
        return f"wheel {notches} at {cell}"

    def view_key(self):
        name = self.rng.choice(sorted(VIEW_KEYS))
        self.hand.key(VIEW_KEYS[name])
        return f"key {name}"

    def swatch(self):
        level = self.rng.randrange(self.win.document.num_levels)
        self.hand.swatch(level)
        return f"swatch {level}"

    def undo(self):
        self.hand.undo()
        return "Ctrl+Z"

    def redo(self):
        self.hand.redo()
        return "Ctrl+Shift+Z"

    def history_row(self):
        step = self.rng.randrange(len(self.win.history.actions))
        self.hand.history_row(step)
        return f"history row {step + 1}"

    def synthesise(self):
        dock = self.win.synthesis_dock
        seed = self.rng.randrange(1000)
        dock.seed.set_value(seed)
        tiles = ""
        if self.photo:                       # a photo model's texture, tileable or not
            if self.rng.random() < 0.5:
                self.hand.button(dock.tileable_box)
            tiles = ", tileable" if dock.tileable() else ""
        self.hand.button(dock.button)
        self.hand.wait_idle()
        return f"Synthesise (seed {seed}{tiles})"

    def panel(self):
        """A button of the Extract tool's selection panel (when it has a selection)."""
        tool = self.win.tool
        if not isinstance(tool, ExtractTool) or not tool.panel.isEnabled():
            return self.click()
        p = tool.panel
        button = self.rng.choice([p.recolour, p.delete, p.flip_h, p.flip_v, p.rotate,
                                  p.scale_button, p.duplicate])
        self.hand.button(button)
        return f"selection panel {button.text()}"

    def spot_mode(self):
        tool = self.win.tool
        if not isinstance(tool, SpotTool):
            return self.tool()
        mode = self.rng.randrange(tool.opts.mode.count())
        tool.opts.mode.setCurrentIndex(mode)
        tool.opts.scale_box.setValue(self.rng.choice([0.2, 0.4, 0.8]))
        tool.opts.count.setValue(self.rng.randint(1, 12))
        return f"spot mode {tool.opts.mode.currentData()}"

    def global_dialog(self):
        """Ctrl+G, an operator, Apply; sometimes Close."""
        self.hand.shortcut("Ctrl+G")
        dialog = self.win._global_dialog
        op = self.rng.randrange(dialog.operator.count())
        dialog.operator.setCurrentIndex(op)
        self.hand.button(dialog.apply_button)
        closed = self.rng.random() < 0.5
        if closed:
            dialog.close()
        closing = ", Close" if closed else ""
        return f"global operators {dialog.operator.currentData()} Apply{closing}"

    def composition(self):
        self.hand.shortcut("Ctrl+Shift+K")
        dialog = self.win.composition_dialog
        QtTest.QTest.qWait(20)
        assert dialog.isVisible(), "Ctrl+Shift+K showed no composition dialog"
        dialog.close()
        return "composition open, close"

    def dpj_editor(self):
        self.hand.shortcut("Ctrl+J")
        editor = self.win.dpj_editor
        QtTest.QTest.qWait(20)
        assert editor.isVisible(), "Ctrl+J showed no DPJ editor"
        editor.close()
        return "Edit DPJ open, close"

    def model(self):
        """Models ▸ a random entry: a setting changed (the seed, where it has one), the
        background preview waited for, then OK or Cancel — or Cancel while it computes."""
        from app.step_dialog import StepDialog
        entries = [a for a in self.win.menu("ModelsMenu").actions() if a.isEnabled()]
        entry = self.rng.choice(entries)
        entry.trigger()
        QtTest.QTest.qWait(20)
        dialogs = [d for d in self.win.findChildren(StepDialog) if d.isVisible()]
        if not dialogs:                     # an entry that needs something the window lacks
            return f"model {entry.objectName()}: no dialog"
        dialog = dialogs[-1]
        if hasattr(dialog, "seed"):
            dialog.seed.set_value(self.rng.randrange(1000))
        if self.rng.random() < 0.2:
            dialog.reject()
            return f"model {entry.objectName()}: Cancel at once"
        assert dialog.wait(120_000), f"{entry.objectName()}: no preview in 120 s"
        ok = dialog.ok.isEnabled() and self.rng.random() < 0.7
        if ok:
            self.hand.button(dialog.ok)
        else:
            dialog.reject()
        QtTest.QTest.qWait(20)
        return f"model {entry.objectName()}: {'OK' if ok else 'Cancel'}"

    def paste_photo(self):
        """Ctrl+C (the picture on show), Ctrl+Shift+V: the acquisition dialog on it, its result
        waited for, then Acquire (a new DPJ, synthesised) or Cancel."""
        before = getattr(self.win, "acquire_dialog", None)     # deleted once it was closed
        self.hand.shortcut("Ctrl+C")
        self.hand.shortcut("Ctrl+Shift+V")
        dialog = getattr(self.win, "acquire_dialog", None)
        QtTest.QTest.qWait(20)
        if dialog is before:                              # a replay running: refused, said so
            return "Ctrl+C, Ctrl+Shift+V: no dialog"
        assert dialog.wait(120_000), "the pasted picture was not acquired in 120 s"
        ok = dialog.ok_button.isEnabled() and self.rng.random() < 0.5
        if ok:
            self.hand.button(dialog.ok_button)
        else:
            dialog.reject()
        QtTest.QTest.qWait(20)
        return f"Ctrl+C, Ctrl+Shift+V: {'Acquire' if ok else 'Cancel'}"

    def menu(self):
        """An entry of the menu bar (but the Models menu, the --models walks', and those that
        end the document: New, Open Recent, Quit), then every window it opened closed (or a
        dialog's OK pressed) and every dock shown again (a View entry may hide one)."""
        from PySide6 import QtWidgets
        entries = [a for a in menu_entries(self.win) if a.isEnabled()]
        entry = self.rng.choice(entries)
        before = set(QtWidgets.QApplication.topLevelWidgets())
        entry.trigger()
        self.hand.wait_idle()
        QtTest.QTest.qWait(20)
        opened = [w for w in QtWidgets.QApplication.topLevelWidgets()
                  if w not in before and w.isVisible() and w is not self.win]
        how = []
        for w in opened:
            ok = isinstance(w, QtWidgets.QDialog) and self.rng.random() < 0.3
            if ok and hasattr(w, "wait"):            # its result computed in a worker first
                assert w.wait(120_000), f"{type(w).__name__} computed nothing in 120 s"
            if ok:
                w.accept()                           # refused while it has nothing to give
                ok = not w.isVisible()
            how.append(f"{type(w).__name__} {'accepted' if ok else 'closed'}")
            if not ok:
                w.close()
            self.hand.wait_idle()
        for dock in self.win.docks():
            dock.show()
        text = entry.text().replace("&", "")
        return f"menu {text}" + (f" ({', '.join(how)})" if how else "")

    def slider(self):
        dock = self.win.palette_dock
        slider = self.rng.choice([dock.darkest, dock.lightest, dock.contrast])
        key = self.rng.choice([Key.Key_PageUp, Key.Key_PageDown, Key.Key_Up])
        self.hand.key(key, widget=slider)
        return f"grey-scale slider {key.name}"

    def step(self) -> None:
        events, weights = (EVENTS + [Walk.model], WEIGHTS + [MODEL_WEIGHT]) if self.models \
            else (EVENTS, WEIGHTS)
        if self.photo:
            events, weights = events + [Walk.synthesise], weights + [PHOTO_SYNTHESIS_WEIGHT]
        if self.menus:
            events, weights = events + [Walk.menu], weights + [MENU_WEIGHT]
        event = self.rng.choices(events, weights)[0]
        before = self.win.history.index
        self.log.append(event(self))
        self.hand.wait_idle()
        self.made += self.win.history.index > before


EVENT_WEIGHTS = {
    Walk.tool: 12, Walk.drag: 24, Walk.click: 20, Walk.middle_drag: 2, Walk.space_drag: 2,
    Walk.wheel: 4, Walk.view_key: 6, Walk.swatch: 6, Walk.undo: 5, Walk.redo: 3,
    Walk.history_row: 2, Walk.synthesise: 1, Walk.panel: 6, Walk.spot_mode: 2,
    Walk.global_dialog: 2, Walk.composition: 1, Walk.dpj_editor: 1, Walk.slider: 2,
    Walk.paste_photo: 1,
}
EVENTS, WEIGHTS = list(EVENT_WEIGHTS), list(EVENT_WEIGHTS.values())
MODEL_WEIGHT = 3            # --models walks: the Models dialogs too (other seeds' walks unchanged)
PHOTO_SYNTHESIS_WEIGHT = 5  # --photo walks: Synthesise more often (a photo model's textures)
MENU_WEIGHT = 12            # --menus walks: the menu bar's entries too
NOT_WALKED = {"New…", "Quit", "Open Recent"}   # they end the document the walk checks


def menu_entries(win) -> list:
    """The menu bar's entries, submenus included, but the Models menu's and NOT_WALKED."""
    found = []

    def walk(menu):
        for action in menu.actions():
            if action.menu() is not None:
                if action.menu().title().replace("&", "") not in NOT_WALKED:
                    walk(action.menu())
            elif not action.isSeparator() \
                    and action.text().replace("&", "") not in NOT_WALKED:
                found.append(action)
    for name, _title in MENUS:
        if name != "ModelsMenu":
            walk(win.menu(name))
    return found


def attach_photo_model(win) -> None:
    """Gravel's photo model (2 scales, from the photo's top-left 128²) in the window, as
    Models ▸ Open photo model would attach it."""
    from texeditor.markov.levels import load_image
    from texeditor.photo import acquire_model
    from texeditor.resources import ROOT
    photo = load_image(ROOT / "images" / "gravel.png")[:128, :128]
    win.attach_model(acquire_model(photo, scales=2))


def shows_its_tone(win) -> str | None:
    """The canvas shows the document drawn with its synthesis's tone (as the step says it
    tiles), when the document has one."""
    import numpy as np
    from texeditor.photo import document_tone
    want = document_tone(win.document)
    if want is None or not win.act_tone.isChecked():
        return None
    shown = win.canvas.picture
    if not np.array_equal(shown[..., 0] if want.ndim == 2 else shown, want):
        return "the canvas does not show the document's tone"
    return None


def undo_all_redo_all(hand: Hand, start: dict) -> str | None:
    """Ctrl+Z back to step 1 must give the starting document; Ctrl+Shift+Z the final one."""
    win = hand.win
    final = state(win)
    for _ in range(len(win.history.actions) + 2):
        hand.undo()
    hand.wait_idle()
    if not same_document(state(win), start):
        now = state(win)
        palette = "another" if (now["palette"] != start["palette"]).any() else "the same"
        return (f"undo back to step 1 stopped at step {now['index']} with "
                f"{int((now['levels'] != start['levels']).sum())} points changed and {palette} "
                "palette")
    for _ in range(final["index"] - 1):
        hand.redo()
    if not same_document(state(win), final):
        return "redo to the end did not give back the document the walk ended on"
    return None


def run_monkey(seed: int, events: int, models: bool = False, photo: bool = False,
               menus: bool = False) -> int:
    recorder = Recorder()
    win = open_window(recorder)
    hand = Hand(win)
    if photo:
        attach_photo_model(win)
    start = state(win)
    walk = Walk(hand, seed, models, photo, menus)
    problem = None
    try:
        for _ in range(events):
            walk.step()
            if recorder.exceptions:
                break
        lost = [text for _kind, text in recorder.dialogs if text.startswith("Cannot go to")]
        if lost:                                  # the History refused a step it listed
            problem = f"history navigation failed: {lost}"
        elif photo and not recorder.exceptions:
            problem = shows_its_tone(win)
        if not problem and not recorder.exceptions:
            problem = undo_all_redo_all(hand, start)
        close_window(win)
    except Exception as exc:              # an assertion, or an error raised in the walk itself
        problem = f"{exc!r}\n{traceback.format_exc()}"
    if recorder.exceptions or problem:
        print(f"monkey seed {seed}: {problem or 'an exception reached Qt'}", file=sys.stderr)
        for text in recorder.exceptions:
            print(f"EXCEPTION that reached Qt:\n{text}", file=sys.stderr)
        print("last events:\n  " + "\n  ".join(walk.log[-25:]), file=sys.stderr)
        return 1
    report(seed=seed, events=len(walk.log), made=walk.made, steps=len(win.history.actions),
           kinds=sorted({line.split()[0] for line in walk.log}),
           dialogs=[text for _kind, text in recorder.dialogs],
           tileable=sum(line.startswith("Synthesise") and "tileable" in line for line in walk.log),
           plain=sum(line.startswith("Synthesise") and "tileable" not in line
                     for line in walk.log),
           pasted=[line.split(": ")[-1] for line in walk.log if "Ctrl+Shift+V" in line],
           menus=sorted({line[5:] for line in walk.log if line.startswith("menu ")}))
    return 0


EARLY_EVENTS = 10      # a start walk's first entries come one after another, without a pause


def window_entries(win) -> list:
    """Every entry of the window a user may choose: the menu bar's (the Models menu too) and
    the tool bars', but NOT_WALKED."""
    from PySide6 import QtGui
    return [a for a in win.findChildren(QtGui.QAction)
            if a.text() and a.menu() is None and not a.isSeparator()
            and a.text().replace("&", "") not in NOT_WALKED | {"Export…", "Export..."}]


def run_start_walk(seed: int, events: int) -> int:
    """The application's own start (``texeditor`` alone: the bank's first entry opening in the
    worker) with ``events`` entries of the window (window_entries) chosen at once and at random
    short pauses, while the texture opens and after, every window they open closed. Fails on an
    exception that reaches Qt, or when no texture is open once the worker is done."""
    from PySide6 import QtWidgets

    from app.main_window import MainWindow
    QtWidgets.QApplication.instance() or QtWidgets.QApplication(["texeditor-start"])
    recorder = Recorder()
    recorder.install()
    win = MainWindow()
    win.resize(1280, 800)
    win.show()
    win.start_default()
    rng = random.Random(seed)
    entries = window_entries(win)
    log, early = [], 0
    for _ in range(events):
        entry = rng.choice(entries)
        early += win.history is None
        log.append(entry.text().replace("&", "") + (" (opening)" if win.history is None else ""))
        entry.trigger()
        QtWidgets.QApplication.processEvents()
        if len(log) > EARLY_EVENTS:           # the first ones at once, while it opens
            QtCore.QThread.msleep(rng.choice((0, 5, 20)))
        for w in QtWidgets.QApplication.topLevelWidgets():
            if w is not win and w.isVisible() and w.isWindow():
                w.close()
        if recorder.exceptions:
            break
    Hand(win).wait_idle()
    QtTest.QTest.qWait(100)
    problem = None
    if not recorder.exceptions and (win.history is None or not win.document.levels.size):
        problem = "no texture opened"
    close_window(win)
    if recorder.exceptions or problem:
        print(f"start walk seed {seed}: {problem or 'an exception reached Qt'}", file=sys.stderr)
        for text in recorder.exceptions:
            print(f"EXCEPTION that reached Qt:\n{text}", file=sys.stderr)
        print("last entries:\n  " + "\n  ".join(log[-25:]), file=sys.stderr)
        return 1
    report(seed=seed, events=len(log), early=early, entries=len(set(log)),
           dialogs=[text for _kind, text in recorder.dialogs])
    return 0
