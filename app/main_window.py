"""The main window: the canvas in the centre, docks for synthesis, palette and history, menus.

It is the only place where user intent becomes Actions submitted to the History; long work goes to
the TaskRunner and comes back as an Action applied here, on the GUI thread.

Its docks are declared in DOCKS and its menus in MENUS; menus are found by objectName, never by
their (translatable) text, and a dock offers its menu entries (``menu_entries``) for the window to
add: no dock sets attributes of the window.
"""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass

from PySide6 import QtCore, QtGui, QtWidgets

from texeditor import warmup
from texeditor.wording import counted
from texeditor.markov.multiscale import scales_phrase
from texeditor.recipe.actions import SetPalette, Synthesize, SynthesizeScales
from texeditor.errors import TexeditorError
from texeditor.recipe.history import EVERYTHING, History
from texeditor.recipe.journal import THUMB_CROP

from . import dpj_editor, resources
from .acquire_dialog import AcquireDialog, pasted_photo
from .bank_dock import BankDock
from .brush_dock import BrushDock
from .canvas import CanvasView
from .files import FileOps
from .grain_rendering_dock import GrainRenderingDock
from .grain_stamps_dock import GrainStampsDock
from .history_dock import HistoryDock
from .models_menu import add_model_entries
from .palette_dock import PaletteDock
from .photo_ops import PhotoOps
from .relief_dock import ReliefDock
from .plate_ops import PlateOps
from .plates_dock import PlatesDock
from .synthesis_dock import SynthesisDock
from .synthesis_worker import TaskRunner, render_synthesis
from .tool_dock import ToolOptionsDock
from .tools import tool_classes

APP_NAME = "texeditor"
THUMB_PAUSE_MS = 1000      # the journal's thumbnail is taken once the edits pause this long
LEFT = QtCore.Qt.DockWidgetArea.LeftDockWidgetArea
RIGHT = QtCore.Qt.DockWidgetArea.RightDockWidgetArea


@dataclass(frozen=True)
class DockSpec:
    """A dock of the main window, made as ``cls(window)`` and kept as ``window.<attr>``."""

    attr: str
    cls: type
    object_name: str           # Qt objectName: saved window layouts name docks by it
    area: QtCore.Qt.DockWidgetArea
    tab_with: str = ""         # tabified behind this dock (attr), in one column
    hidden: bool = False       # shown on demand: by the tool that uses it, or View
    fills_menu: str = ""       # objectName of a menu the dock fills (``fill_menu``) on opening


# In View menu order; the Brushes and Grain stamps docks show with their tools (Tool.show_own_dock).
DOCKS = (
    DockSpec("tool_dock", ToolOptionsDock, "ToolOptionsDock", LEFT),
    DockSpec("synthesis_dock", SynthesisDock, "SynthesisDock", RIGHT),
    DockSpec("palette_dock", PaletteDock, "PaletteDock", RIGHT),
    DockSpec("history_dock", HistoryDock, "HistoryDock", RIGHT),
    DockSpec("bank_dock", BankDock, "BankDock", LEFT),         # opens in start_default
    DockSpec("brush_dock", BrushDock, "BrushDock", LEFT, tab_with="bank_dock", hidden=True),
    DockSpec("grain_dock", GrainStampsDock, "GrainDock", LEFT, tab_with="brush_dock",
             hidden=True, fills_menu="GrainStampsMenu"),
    DockSpec("density_dock", GrainRenderingDock, "GrainDensityDock", LEFT,
             tab_with="grain_dock"),
    DockSpec("relief_dock", ReliefDock, "ReliefDock", LEFT, tab_with="density_dock",
             hidden=True),
    DockSpec("plates_dock", PlatesDock, "PlatesDock", RIGHT, tab_with="synthesis_dock",
             hidden=True),
)

# (objectName, title), in menu bar order
MENUS = (("FileMenu", "&File"), ("EditMenu", "&Edit"), ("ImageMenu", "&Image"),
         ("ModelsMenu", "&Models"), ("ViewMenu", "&View"), ("ToolsMenu", "&Tools"), ("GrainStampsMenu", "Grain &stamps"))


class MainWindow(FileOps, PhotoOps, PlateOps, QtWidgets.QMainWindow):
    def __init__(self, history: History | None = None, path=None):
        super().__init__()
        self.setWindowTitle(APP_NAME)
        self.resize(1280, 800)
        self.history: History | None = None
        self.path = None
        self._name: str | None = None      # the title of a document without a file
        self._clean_log: tuple = ()
        self._unsubscribe = None
        self._journal = None       # this window's crash journal (None: not yet; False: failed)
        self._broken_journal = None   # the one that failed, kept locked (see _journal_failed)
        self._thumb_timer = QtCore.QTimer(self)     # its thumbnail, once the edits pause
        self._thumb_timer.setSingleShot(True)
        self._thumb_timer.setInterval(THUMB_PAUSE_MS)
        self._thumb_timer.timeout.connect(self.journal_thumbnail)
        self.runner = TaskRunner(self)
        self._replaying = None     # the PendingEdit of a past step replayed in the worker
        self.closing = False       # closeEvent accepted: a task cancelled now is not replaced
        self.headless = False      # --screenshot: errors go to stderr, never a modal dialog
        self.paint_zone = None     # the zone the two zone tools share (app.tools.zone)
        self.peano_dialog = None          # non-modal dialogs, kept to be shown again
        self.composition_dialog = None
        self.doubling_dialog = None
        self.photo_model = None    # the photo model acquired or opened last (app.photo_ops)
        self._tone_cache = None    # (model, key, tone.Rendered) of the last tone rendering
        self._stored_tone = None   # (levels, picture): a bank entry's stored tone (first start)
        self._tone_drawing = False   # a tone is being drawn on a thread (app.photo_ops)
        self._tone_arrival = None    # its ToneArrival, made on first use
        self._step_model = None    # (synthesis step, the photo model its tone names)
        self.tone_seconds = 0.0    # how long the last tone rendering took

        self.canvas = CanvasView()
        self.canvas.setAcceptDrops(False)      # files dropped on it go to the window (dropEvent)
        self.setCentralWidget(self.canvas)
        self.setAcceptDrops(True)
        self.tools = [cls(self) for cls in tool_classes()]     # before the docks that show them
        self._build_docks()
        self._docks_sized = False

        self._build_status_bar()
        self._build_actions()
        self._build_menus()
        add_model_entries(self)
        self._build_tools()
        self._add_dock_entries()
        self._connect()
        if history is not None:
            self.set_history(history, path)

    # -- construction -------------------------------------------------------------------------------
    def _build_docks(self) -> None:
        """The docks of DOCKS, each in its area, tabbed behind its neighbour, hidden if asked;
        the first dock of each tabbed column stays in front."""
        fronts = []
        for spec in DOCKS:
            dock = spec.cls(self)
            dock.setObjectName(spec.object_name)
            setattr(self, spec.attr, dock)
            self.addDockWidget(spec.area, dock)
            if spec.tab_with:
                self.tabifyDockWidget(getattr(self, spec.tab_with), dock)
                if not any(s.attr == spec.tab_with and s.tab_with for s in DOCKS):
                    fronts.append(spec.tab_with)
            if spec.hidden:
                dock.hide()
        for attr in fronts:
            getattr(self, attr).raise_()

    def docks(self) -> list[QtWidgets.QDockWidget]:
        """The declared docks, in DOCKS order."""
        return [getattr(self, spec.attr) for spec in DOCKS]

    def menu(self, name: str) -> QtWidgets.QMenu:
        """A menu of the menu bar (or a submenu) by its objectName."""
        menu = self.menuBar().findChild(QtWidgets.QMenu, name)
        if menu is None:
            raise KeyError(f"no menu named {name!r}")
        return menu

    def _add_dock_entries(self) -> None:
        """What each dock offers: entries for the window's menus (their shortcuts work with the
        dock hidden), and a menu it fills each time it opens."""
        for spec in DOCKS:
            dock = getattr(self, spec.attr)
            for name, action in getattr(dock, "menu_entries", lambda: [])():
                if action is None:
                    self.menu(name).addSeparator()
                else:
                    self.addAction(action)
                    self.menu(name).addAction(action)
            if spec.fills_menu:
                menu = self.menu(spec.fills_menu)
                menu.aboutToShow.connect(lambda d=dock, m=menu: d.fill_menu(m))
                dock.fill_menu(menu)

    def _build_status_bar(self) -> None:
        bar = self.statusBar()
        self.progress = QtWidgets.QProgressBar()
        self.progress.setRange(0, 1000)
        self.progress.setFixedWidth(180)
        self.progress.setTextVisible(False)
        self.cancel_button = QtWidgets.QToolButton()
        self.cancel_button.setText("Cancel")
        self.cancel_button.setToolTip("Stop this work (Esc); the document stays as it was")
        self.cancel_button.clicked.connect(self.runner.cancel)
        self.task_label = QtWidgets.QLabel()
        self.cursor_label = QtWidgets.QLabel()
        self.level_label = QtWidgets.QLabel()
        self.zoom_label = QtWidgets.QLabel("zoom –")
        self.repairs_label = QtWidgets.QLabel()
        self.retargeted_label = QtWidgets.QLabel()
        self.retargeted_label.setToolTip("Steps after an edited one whose Fill, Translate, Copy or "
                                         "Extract now acts on a different region (marked ⚠ in "
                                         "the History)")
        self.journal_label = QtWidgets.QLabel("⚠ Crash protection off")
        self.journal_label.setToolTip("The crash journal cannot be written (a full disk?): the "
                                      "work since the last save would be lost in a crash. "
                                      "Saving starts a new journal.")
        for w in (self.task_label, self.progress, self.cancel_button, self.journal_label):
            bar.addPermanentWidget(w)
            w.hide()
        for w, chars in ((self.retargeted_label, 0), (self.repairs_label, 0),
                         (self.cursor_label, 14),
                         (self.level_label, 9), (self.zoom_label, 11)):
            if chars:
                w.setMinimumWidth(QtGui.QFontMetrics(w.font()).horizontalAdvance("0" * chars))
            bar.addPermanentWidget(w)
        self._show_hover(None)

    def _action(self, text, slot, shortcut=None, tip=None, checkable=False) -> QtGui.QAction:
        action = QtGui.QAction(text, self)
        if shortcut is not None:
            keys = shortcut if isinstance(shortcut, list) else [shortcut]
            action.setShortcuts([QtGui.QKeySequence(k) for k in keys])
        if tip:
            action.setStatusTip(tip)
            action.setToolTip(tip)
        action.setCheckable(checkable)
        action.triggered.connect(slot if checkable else self._once_opened(slot))
        self.addAction(action)    # shortcuts work even with menus hidden (offscreen, full screen)
        return action

    def _once_opened(self, slot):
        """``slot``, but while the window has no texture yet (its first one still opening in
        the worker, or a crash's journals being read) the status bar says to wait: Undo,
        Synthesise, an export… there read a document that is not there yet. New, Quit and
        Cancel (Esc: the opening itself may be cancelled) need none."""
        def guarded(*_args):
            if slot in self._without_texture() or not self.still_opening():
                slot()
        return guarded

    def still_opening(self) -> bool:
        """True, and the status bar says to wait, while the window has no texture yet (the
        one place that says so: the window's actions, the Models entries, the grain editor
        and the relief's exports ask here)."""
        if self.history is not None:
            return False
        self.statusBar().showMessage("The texture is still opening: a moment, please.", 5000)
        return True

    def _without_texture(self) -> tuple:
        return (self.new_document, self.quit_all, self.runner.cancel)

    def _build_actions(self) -> None:
        K = QtGui.QKeySequence.StandardKey
        a = self._action
        self.act_new = a("&New…", self.new_document, K.New, "A blank canvas")
        self.act_open = a("&Open…", lambda: self.open_file(), K.Open, "Open a .texture file")
        self.act_save = a("&Save", self.save, K.Save, "Save the texture (DPJ + actions)")
        self.act_save_as = a("Save &As…", self.save_as, K.SaveAs)
        self.act_export = a("&PNG picture…", self.export_png, "Ctrl+E",
                            "Write the texture as an image, optionally enlarged")
        self.act_acquire = a("&Acquire DPJ from image…", lambda: self.acquire(), "Ctrl+I",
                             "Estimate a DPJ from a photo (thesis §5.2)")
        self.act_open_dpj = a("Open DPJ or photo &model…", lambda: self.open_dpj(),
                              "Ctrl+Shift+O", "Open a .dpj file: a DPJ, or a photo model whose "
                              "scales are added to the texture")
        self.act_new_dpj = a("New &DPJ…", lambda: dpj_editor.open_editor(self, new=True),
                             "Ctrl+Shift+N", "Enter a DPJ by hand: window, G, then paint "
                             "configurations and give them probabilities (thesis §5.2.2)")
        self.act_edit_dpj = a("Edit D&PJ…", lambda: dpj_editor.open_editor(self), "Ctrl+J",
                              "Open the current DPJ in the DPJ editor")
        self.act_quit = a("&Quit", self.quit_all, K.Quit, "Close every texeditor window, "
                          "asking about unsaved work")
        self.act_copy_picture = a("&Copy picture", self.copy_picture, K.Copy,
                                  "Copy the picture on show to the clipboard")
        self.act_paste_photo = a("&Paste as photo…", self.paste_photo, "Ctrl+Shift+V",
                                 "Acquire a DPJ from the picture on the clipboard")
        self.act_undo = a("&Undo", self.undo, "Ctrl+Z")
        self.act_redo = a("&Redo", self.redo, ["Ctrl+Shift+Z", "Ctrl+Y"])
        for act in (self.act_undo, self.act_redo):     # nothing to undo before a texture
            act.setEnabled(False)
        self.act_synth = a("&Synthesise", self.synthesise_from_dock, "Ctrl+R",
                           "Draw a texture from the current DPJ")
        self.act_global = a("&Global operators…", self.global_operators, "Ctrl+G",
                            "Rotate, zoom, shear or tile the texture or the selection (§3.4.3)")
        self.act_peano = a("&Peano sub-regions…", self.open_peano, None,
                           "Cut the canvas into cells along a Hilbert scan and give them levels "
                           "from a dominance expression (thesis §3.3.3a)")
        self.act_compose = a("&Composition…", self.open_composition, "Ctrl+Shift+K",
                             "Incrust or mix another texture into this one (thesis §5.4.1)")
        self.act_double = a("&Double the levels…", self.open_doubling, None,
                            "Turn a G-level texture into 2G levels, learnt from a photo "
                            "(thesis §4.5)")
        self.act_plates_dock = a("Colour &plates…", self.show_plates_dock, None,
                                 "Lay the texture on coloured plates: add them, take them from a "
                                 "photo, paint them (thesis §1.2.3)")
        self.act_cancel = a("&Cancel work", self.runner.cancel, "Esc")
        self.act_cancel.setEnabled(False)
        self.act_zoom_in = a("Zoom &in", self.canvas.zoom_in, ["+", "=", "Ctrl++"])
        self.act_zoom_out = a("Zoom &out", self.canvas.zoom_out, ["-", "Ctrl+-"])
        self.act_fit = a("&Fit in window", self.canvas.fit, "0")
        self.act_actual = a("&Actual pixels (100 %)", self.canvas.actual_pixels, "1")
        self.act_tiled = a("&Tiled preview (3×3)", self.canvas.set_tiled, "W",
                           "Repeat the texture 3×3 to judge its seams", checkable=True)
        self.act_tiled.setIconText("Tiled")
        self.act_tone = a("Photographic &tone", lambda _=False: None, "T",
                          "Show the texture with the photo's own greys and colours (a photo "
                          "model's tone) instead of the palette", checkable=True)
        self.act_tone.setChecked(True)
        self.act_tone.setEnabled(False)
        self.act_tone.toggled.connect(self._tone_toggled)     # also when the dock's box toggles
        self.act_plates = a("Show &plates", lambda _=False: None, None,
                            "Lay the texture on its colour plates (thesis §1.2.3), on the canvas "
                            "and in exports", checkable=True)
        self.act_plates.setChecked(True)
        self.act_plates.setEnabled(False)
        self.act_plates.toggled.connect(self._plates_toggled)
        self.act_paint_plates = a("Paint on the &plates", lambda _=False: None, "Shift+P",
                                  "The tools and the palette work on the colour plates instead "
                                  "of the texture's levels", checkable=True)
        self.act_paint_plates.setEnabled(False)
        self.act_paint_plates.toggled.connect(self._paint_target_changed)

    def _build_menus(self) -> None:
        for name, title in MENUS:
            self.menuBar().addMenu(title).setObjectName(name)
        menu = self.menu("FileMenu")
        menu.addActions([self.act_new, self.act_open])
        self.recent_menu = menu.addMenu("Open &Recent")
        self.recent_menu.setObjectName("RecentMenu")
        self.recent_menu.aboutToShow.connect(self._fill_recent_menu)
        menu.addSeparator()
        menu.addActions([self.act_save, self.act_save_as])
        export = menu.addMenu("&Export")
        export.setObjectName("ExportMenu")      # the Relief dock adds its maps
        export.addAction(self.act_export)
        menu.addAction(self.bank_dock.act_save)
        menu.addSeparator()
        menu.addActions([self.act_acquire, self.act_open_dpj])
        menu.addActions([self.act_new_dpj, self.act_edit_dpj])
        menu.addSeparator()
        menu.addAction(self.act_quit)
        menu = self.menu("EditMenu")
        menu.addActions([self.act_undo, self.act_redo])
        menu.addSeparator()
        menu.addActions([self.act_copy_picture, self.act_paste_photo])
        menu = self.menu("ImageMenu")
        menu.addActions([self.act_synth, self.act_cancel])
        menu.addSeparator()
        menu.addActions([self.act_global, self.act_peano])
        menu.addSeparator()
        menu.addActions([self.act_compose, self.act_double, self.act_plates_dock])
        menu = self.menu("ViewMenu")
        menu.addActions([self.act_zoom_in, self.act_zoom_out, self.act_fit, self.act_actual])
        menu.addSeparator()
        menu.addActions([self.act_tiled, self.act_tone, self.act_plates])
        menu.addSeparator()
        menu.addActions([dock.toggleViewAction() for dock in self.docks()])
        for dock in self.docks():          # a dock opened from View comes to the front of its
            dock.toggleViewAction().triggered.connect(    # tabs, not a tab behind the others
                lambda shown, d=dock: d.raise_() if shown else None)

        bar = self.addToolBar("Main")
        bar.setObjectName("MainToolBar")
        bar.setToolButtonStyle(QtCore.Qt.ToolButtonStyle.ToolButtonTextOnly)
        bar.addActions([self.act_new, self.act_open, self.act_save])
        bar.addSeparator()
        bar.addActions([self.act_acquire, self.act_synth])
        bar.addSeparator()
        bar.addActions([self.act_undo, self.act_redo])
        bar.addSeparator()
        bar.addActions([self.act_fit, self.act_tiled])

    def _build_tools(self) -> None:
        """One checkable action per tool, with its shortcut: in the Tools menu and as a grid of
        buttons above the tool options (as GIMP does: a column of text buttons beside the docks
        took a tenth of a 1280-pixel window from the canvas)."""
        group = QtGui.QActionGroup(self)
        menu = self.menu("ToolsMenu")
        for tool in self.tools:
            tip = f"{tool.TIP} ({tool.SHORTCUT})" if tool.SHORTCUT else tool.TIP
            tool.qaction = self._action(tool.NAME, lambda _=False, t=tool: self.set_tool(t),
                                        tool.SHORTCUT or None, tip, checkable=True)
            tool.qaction.setIconText(tool.LABEL or tool.NAME.split()[0])   # the button's label
            group.addAction(tool.qaction)
            menu.addAction(tool.qaction)
        menu.addSeparator()
        menu.addAction(self.act_paint_plates)
        self.tool_dock.set_tools(self.tools)
        self.set_tool(self.tools[0])

    def set_tool(self, tool) -> None:
        """Make ``tool`` current: its button checked, its options shown."""
        if self.canvas.tool is not None and self.canvas.tool is not tool and \
                self.history is not None:       # without a texture no tool was activated
            self.canvas.tool.deactivate()
        self.canvas.tool = tool
        if hasattr(tool, "qaction"):
            tool.qaction.setChecked(True)
        self.tool_dock.show_tool(tool)
        if self.history is not None:    # else once the first texture is there (set_history):
            tool.activate()             # a tool may follow the document's history

    @property
    def tool(self):
        return self.canvas.tool

    @property
    def current_level(self) -> int:
        """The level tools paint with: the palette's selected swatch."""
        return self.palette_dock.swatches.current

    def open_peano(self):
        """Show the (non-modal) Peano sub-regions dialog."""
        from .peano_dialog import open_peano
        self.peano_dialog = open_peano(self, self.peano_dialog)
        return self.peano_dialog

    def open_composition(self):
        """Show the (non-modal) composition dialog (a new one for another document)."""
        from .composition_dialog import open_composition
        self.composition_dialog = open_composition(self, self.composition_dialog)
        return self.composition_dialog

    def open_doubling(self):
        """Open the level-doubling dialog (window-modal); none for an empty canvas."""
        from .doubling_dialog import open_doubling
        dialog = open_doubling(self)
        if dialog is not None:
            self.doubling_dialog = dialog
        return dialog

    def global_operators(self):
        """Show the (non-modal) global operators dialog."""
        from .global_dialog import GlobalOperatorsDialog

        if getattr(self, "_global_dialog", None) is None:
            self._global_dialog = GlobalOperatorsDialog(self)
        self._global_dialog.show()
        self._global_dialog.raise_()
        return self._global_dialog

    def _connect(self) -> None:
        self.canvas.hovered.connect(self._show_hover)
        self.canvas.zoomChanged.connect(self._show_zoom)
        self.synthesis_dock.requested.connect(self.synthesise)
        self.synthesis_dock.tone_box.toggled.connect(self.act_tone.setChecked)
        self.act_tone.toggled.connect(self.synthesis_dock.tone_box.setChecked)
        self.palette_dock.committed.connect(self._palette_committed)
        self.palette_dock.preview.connect(self._preview_palette)
        self.plates_dock.paint_box.toggled.connect(self.act_paint_plates.setChecked)
        self.act_paint_plates.toggled.connect(self.plates_dock.paint_box.setChecked)
        self.plates_dock.add_requested.connect(self.add_plates)
        self.plates_dock.photo_requested.connect(self.plates_from_photo)
        self.plates_dock.paste_requested.connect(self.plates_from_clipboard)
        self.plates_dock.remove_requested.connect(self.remove_plates)
        self.plates_dock.show_box.toggled.connect(self.act_plates.setChecked)
        self.act_plates.toggled.connect(self.plates_dock.show_box.setChecked)
        self.history_dock.stepClicked.connect(self.goto_step)
        self.history_dock.editRequested.connect(self.edit_step)
        self.history_dock.optimiseRequested.connect(self.optimise_log)
        self.runner.started.connect(self._task_started)
        self.runner.progress.connect(self._task_progress)
        self.runner.finished.connect(self._task_finished)

    def showEvent(self, ev) -> None:
        super().showEvent(ev)
        if not self._docks_sized:
            self._docks_sized = True
            QtCore.QTimer.singleShot(0, self, self._size_docks)   # once the layout has settled

    def childEvent(self, ev) -> None:
        """The tab bars Qt makes for tabbed docks show whole titles and scroll, as Krita's do:
        four docks in the left column would otherwise read "Texture …", "Bru…", "G…"."""
        super().childEvent(ev)
        child = ev.child()
        if ev.type() == QtCore.QEvent.Type.ChildPolished and isinstance(child, QtWidgets.QTabBar):
            child.setElideMode(QtCore.Qt.TextElideMode.ElideNone)
            child.setUsesScrollButtons(True)

    def closeEvent(self, ev) -> None:
        """The DPJ editors' unsaved changes are asked about first (Cancel keeps the window
        open), then the texture's (FileOps)."""
        if not dpj_editor.confirm_close(self):
            ev.ignore()
            return
        super().closeEvent(ev)

    def resizeEvent(self, ev) -> None:
        super().resizeEvent(ev)
        if self._docks_sized and ev.size().height() > ev.oldSize().height() >= 0:
            QtCore.QTimer.singleShot(0, self, self._regrow_docks)    # once laid out anew

    def _regrow_docks(self) -> None:
        """The window grew: the synthesis and palette docks a smaller window squeezed (their
        Synthesise button, their sliders scrolled out of sight) get their natural height back
        from the history; docks at their height or taller are left as the user made them."""
        docks = (self.synthesis_dock, self.palette_dock)
        heights = self._natural_heights()
        if any(d.isVisible() and d.height() < h for d, h in zip(docks, heights)):
            self._size_column([max(d.height(), h) for d, h in zip(docks, heights)])

    def _size_docks(self) -> None:
        """Synthesis (and the Plates dock, its tab, when open: the taller, and their tab bar)
        and palette at their natural height; the history takes the rest."""
        self._size_column(self._natural_heights())
        self.resizeDocks([self.history_dock, self.tool_dock], [340, 190],
                         QtCore.Qt.Orientation.Horizontal)

    def _size_column(self, heights) -> None:
        docks = [self.synthesis_dock, self.palette_dock, self.history_dock]
        rest = max(200, sum(d.height() for d in docks) - sum(heights))
        self.resizeDocks(docks, heights + [rest], QtCore.Qt.Orientation.Vertical)

    def _natural_heights(self) -> list[int]:
        """The heights the synthesis (or its Plates tab) and palette docks show all of their
        content at."""

        def natural(d):     # the content, its scroll area's frame and the dock's title bar
            area = d.widget()
            return (area.widget().sizeHint().height() + 2 * area.frameWidth()
                    + d.sizeHint().height() - area.sizeHint().height())
        plates = not self.plates_dock.isHidden()     # closed, it has no tab nor a size to read
        tabs = [bar.sizeHint().height() for bar in self.findChildren(QtWidgets.QTabBar)
                if plates and bar.isVisible() and self.plates_dock.windowTitle() in
                [bar.tabText(i) for i in range(bar.count())]]
        return [max([natural(self.synthesis_dock)] + [natural(self.plates_dock)] * plates)
                + sum(tabs[:1]), natural(self.palette_dock)]

    # -- the document -------------------------------------------------------------------------------
    @property
    def document(self):
        return self.history.document

    def set_history(self, history: History, path=None, name: str | None = None) -> None:
        """Show another document (new, opened, or the start-up one); it starts unmodified.
        ``name`` titles a document without a file (a bank entry's name)."""
        self.canvas.end_gesture()       # a drag left open belongs to the document it began on
        if self._unsubscribe is not None:
            self._unsubscribe()
        tool, first = self.canvas.tool, self.history is None
        if tool is not None and not first:
            tool.deactivate()       # a tool that follows the history (Extract, Spot, Tree)
        self.history, self.path, self._name = history, path, name     # follows the new one
        self.keep_model_for(history)
        self._unsubscribe = history.subscribe(self._history_changed)
        if tool is not None:
            tool.activate()         # (or, chosen before the first texture, now starts to)
        self.history_dock.set_history(history)
        self.mark_clean()
        self._history_changed()

    def _history_changed(self, change=None) -> None:
        """Show what a History change (a `Change`; None: everything) changed, and only that:
        the canvas redraws the box a step touched, each dock refreshes on the kinds it shows."""
        what = EVERYTHING if change is None else change.what
        doc = self.history.document
        if what & {"levels", "palette", "plates"}:
            self._show_document(doc, change)
        if what & {"palette", "plates"}:
            self._refresh_plates()
            self.palette_dock.set_palette(self.paint_palette())
        if "levels" in what or "palette" in what:
            self.relief_dock.document_changed()
        if what & {"log", "dpj"}:
            self.history_dock.refresh()
            refs = self.scale_refs()
            self.synthesis_dock.refresh(self.history, [doc.dpjs[r] for r in refs])
            self.density_dock.refresh()
            if self._docks_sized:         # a photo model's rows may need more height
                QtCore.QTimer.singleShot(0, self, self._regrow_docks)
        self.act_undo.setEnabled(self.can_undo())
        self.act_redo.setEnabled(self.history.can_redo)
        self.act_tone.setEnabled(self.tone_available())
        self.synthesis_dock.set_tone_available(self.tone_available())
        moved = len(self.history.retargeted)
        self.retargeted_label.setText(f"⚠ {moved} step(s) re-targeted" if moved else "")
        self._update_title()
        self.journal_sync()

    def _show_document(self, doc, change) -> None:
        """Redraw the canvas as little as the change allows: a box of cells, a recolouring,
        or (a new matrix, a replay) the whole picture."""
        picture = self.display_picture(wait=False) if doc.levels.size else None
        if not doc.levels.size:
            self.canvas.image.clear()
        elif picture is not None:       # tone, plates: the whole picture is drawn again
            self.canvas.set_image(doc.levels, doc.palette, picture)
        elif self.canvas.picture is not None:        # tone was shown: back to the palette
            self.canvas.set_image(doc.levels, doc.palette)
        elif change is not None and change.what & {"levels", "palette"} == {"palette"} \
                and self.canvas.levels is not None and self.canvas.levels.shape == doc.shape:
            self.canvas.set_palette(doc.palette)
        elif (change is None or "palette" in change.what or change.box is None
              or not self.canvas.update_box(doc.levels, change.box)):
            self.canvas.set_image(doc.levels, doc.palette)

    # -- crash journal ------------------------------------------------------------------------------
    def journal_sync(self, *, reset: bool = False) -> None:
        """Append the log's change to this window's crash journal (reset: after open or save).
        A journal that cannot be written is given up with a warning, never an error; the next
        open or save (the disk took a file again) starts a new one."""
        if self.history is None or (self._journal is False and not reset):
            return
        from texeditor.recipe.journal import Journal
        try:
            if not self._journal:
                self._forget_broken_journal()
                self._journal = Journal()
                reset = True
            doc = self.history.document
            if reset:
                self._journal.reset(self.history.applied, doc.dpjs, source=self.path,
                                    exemplars=doc.exemplars, current=doc.dpj_ref)
            else:
                self._journal.sync(self.history.applied, doc.dpjs, doc.exemplars, doc.dpj_ref)
        except OSError as exc:
            self._journal_failed(exc)
            return
        self.journal_label.hide()
        self._thumb_timer.start()

    def journal_thumbnail(self) -> None:
        """Record in the journal what the canvas shows (the recovery dialog's picture of the
        work): once the edits pause, so a brush stroke does not write one per dab."""
        crop = self.canvas.shown_crop(THUMB_CROP) if self._journal else None
        if crop is None:
            return
        try:
            self._journal.thumbnail(crop)
        except OSError as exc:
            self._journal_failed(exc)

    def _journal_failed(self, exc: OSError) -> None:
        """Crash protection off until the next open or save. The journal that failed stays
        open and locked, so no other window offers it as a crashed one while this one lives;
        if this one dies, what it holds is offered back."""
        if self._journal:
            self._broken_journal = self._journal
        self._journal = False
        self._thumb_timer.stop()
        self.journal_label.show()
        self.statusBar().showMessage(f"Crash protection is off until the next save: cannot write "
                                     f"the journal ({exc.strerror or exc}).", 10000)

    def _forget_broken_journal(self) -> None:
        if self._broken_journal is not None:
            try:
                self._broken_journal.discard()
            except OSError:
                pass             # offered at the next start, as any journal left behind
            self._broken_journal = None

    def journal_discard(self) -> None:
        self._thumb_timer.stop()
        if self._journal:
            self._journal.discard()
        self._forget_broken_journal()
        self._journal = None

    def submit(self, action, prepared=None) -> bool:
        """Apply an Action; a refused one is explained in a dialog and changes nothing. One that
        would change nothing (a fill with the region's own level) adds no step, and says so.
        ``prepared``: the step's slow part, done in the worker (a synthesis's levels)."""
        if self.edits_locked():
            return False
        try:
            action = self.on_target(action)
        except TexeditorError as exc:
            self.show_error("This change cannot be made on the plates", exc)
            return False
        if (prepared is None and warmup.pending()
                and warmup.needs_kernels(action, self.history.document)):
            return self._after_warm_up(action)
        try:
            added = self.history.apply(action, if_changed=True, prepared=prepared)
        except TexeditorError as exc:
            self.show_error("This change cannot be made", exc)
            return False
        if not added:
            self.statusBar().showMessage(f"{action.label()}: this changes nothing, so no step "
                                         "was added.", 5000)
        return True

    def submit_computed(self, compute, label: str, error_title: str = "This change cannot be "
                        "made") -> bool:
        """Apply the step ``compute(copy of the document)`` returns as (action, prepared), its
        slow part done in the worker (status bar, Esc): a step that takes seconds on a large
        texture. The window stays live; if the texture changes meanwhile the step is not
        applied, and the status bar says to apply it again. False when it could not start."""
        if self.edits_locked() or self.busy_note():
            return False
        history, log = self.history, self.history.applied
        scratch = history.document.copy()

        def computed(result) -> None:
            action, prepared = result
            if self.history is not history or history.applied != log:
                self.statusBar().showMessage(f"{action.label()}: the texture changed "
                                             "meanwhile, so it was not applied; apply it "
                                             "again.", 8000)
                return
            self.submit(action, prepared=prepared)
        self.runner.run(label, lambda _progress, _cancel: compute(scratch), computed,
                        on_error=lambda exc: self.show_error(error_title, exc))
        return True

    def busy_note(self) -> bool:
        """True while a task runs in the worker, and the status bar then says to wait: a
        command that needs the worker is never dropped without a word."""
        if self.runner.busy:
            self.statusBar().showMessage("Busy: wait for the current work or cancel it (Esc).",
                                         5000)
        return self.runner.busy

    def _after_warm_up(self, action) -> bool:
        """A step that needs the kernels while a first start compiles them waits in the worker
        (busy bar, Esc cancels it) and is applied when they are ready: the GUI never freezes.
        False: not applied yet."""
        if self.busy_note():
            return False
        history = self.history
        self.runner.run("Preparing the synthesis engine… (first start only)",
                        lambda progress, cancel: warmup.wait(cancel=cancel),
                        lambda _: history is self.history and self.submit(action),
                        on_cancel=lambda: self.statusBar().showMessage(
                            "Cancelled: the change was not made.", 5000))
        return False

    def _palette_committed(self, palette) -> None:
        """A palette the document refused (while a replay runs, say) is not left on show."""
        if not self.submit(SetPalette(palette)):
            self.palette_dock.set_palette(self.paint_palette())
            self._show_document(self.history.document, None)

    def undo(self) -> None:
        if self._replaying is not None:
            self.runner.cancel()       # undo the edit being replayed: as Krita cancels a stroke
            return
        self._settle_pending()
        if self.can_undo():
            self._guarded(self.history.undo)
            if self.history.redoes_edit:
                self.statusBar().showMessage("Edit undone: the step's old parameters and the "
                                             "later steps are back.", 5000)

    def can_undo(self) -> bool:
        """The first step is the base texture, as in GIMP; an edit of it can be undone."""
        return self.history.index > 1 or self.history.undoes_edit

    def redo(self) -> None:
        if not self.edits_locked():
            self._guarded(self.history.redo)

    def goto_step(self, steps: int) -> None:
        if not self.edits_locked():
            if steps < self.history.index:      # back: as undo (forward: as redo, no flush)
                self._settle_pending()
            self._guarded(lambda: self.history.goto(max(1, steps)))

    def _settle_pending(self) -> None:
        """Before the history goes back: a grey-scale key step just made lands first (and is
        undone); grain settings still waiting for their pause are dropped."""
        self.palette_dock.flush()
        self.density_dock.drop_pending()

    def _guarded(self, fn) -> None:
        try:
            fn()
        except TexeditorError as exc:
            self.show_error("Cannot go to this step", exc)

    def show_error(self, title: str, exc: Exception) -> None:
        """Errors are dialogs; the document is left as it was."""
        self.statusBar().showMessage(f"{title}: {exc}", 8000)
        if self.headless:
            print(f"texeditor: {title}: {exc}", file=sys.stderr)
            return
        QtWidgets.QMessageBox.critical(self, title, str(exc))

    # -- synthesis ----------------------------------------------------------------------------------
    def synthesise_from_dock(self) -> None:
        self.synthesise(*self.synthesis_dock.values())

    def synthesise(self, width: int, height: int, seed: int, scales: int | None = None) -> None:
        """Synthesise from the current DPJ in the worker, then apply a Synthesize action; when
        the current DPJ is a scale of a photo model, from its first ``scales`` scales (None:
        the Synthesis dock's number) with a SynthesizeScales action."""
        doc = self.history.document
        refs = self.scale_refs()
        if refs:
            n = self.synthesis_dock.scale_count() if scales is None else scales
            self._synthesise_scales(refs[:max(1, min(n, len(refs)))], width, height, seed)
            return
        if doc.dpj is None:
            QtWidgets.QMessageBox.information(self, "No DPJ", "Acquire a DPJ from an image first "
                                              "(File ▸ Acquire DPJ from image…).")
            return
        if self.busy_note():
            return
        try:
            action = Synthesize(doc.dpj_ref, width, height, seed, self.synthesis_dock.tileable(),
                                self.synthesis_dock.scan())
        except TexeditorError as exc:
            self.show_error("Cannot synthesise", exc)
            return
        self._run_synthesis(action, doc.dpj, f"Synthesising {width}×{height}…")

    def _synthesise_scales(self, refs, width: int, height: int, seed: int) -> None:
        """The same path for a multi-scale synthesis: the scales' DPJs drawn in the worker, the
        levels applied here by SynthesizeScales."""
        if self.busy_note():
            return
        try:
            photo, levels = self.tone_refs(refs)
            action = SynthesizeScales(tuple(refs), width, height, seed,
                                      self.synthesis_dock.tileable(), tone_photo=photo,
                                      tone_levels=levels)
        except TexeditorError as exc:
            self.show_error("Cannot synthesise", exc)
            return
        dpjs = [self.history.document.dpjs[r] for r in refs]
        self._run_synthesis(action, dpjs,
                            f"Synthesising {width}×{height} on {scales_phrase(len(refs))}…")

    def _run_synthesis(self, action, source, label: str) -> None:
        """Draw ``action``'s levels from ``source`` (its DPJ or DPJs) in the worker, with
        progress and Cancel; the levels are applied on this thread when done."""
        start, history = time.perf_counter(), self.history
        log = history.applied
        self.runner.run(label,
                        lambda progress, cancel: render_synthesis(action, source, progress, cancel),
                        lambda result: self._synthesis_done(history, log, action, result, start),
                        on_cancel=lambda: self.statusBar().showMessage(
                            "Synthesis cancelled: the document is unchanged.", 8000),
                        on_error=lambda exc: self.show_error("Synthesis failed", exc))

    def _synthesis_done(self, history, log, action, result, start) -> None:
        if history is not self.history:
            return       # another document was opened meanwhile
        if history.applied != log:     # an undo, a step chosen in the History, a stroke: applied
            self.statusBar().showMessage(  # now, it would drop the steps undone meanwhile
                f"{action.label()}: the texture changed while it was drawn, so it was not "
                "applied (the history is as you left it); synthesise again.", 10000)
            return
        levels, repairs = result
        steps = self.history.index
        if not self.submit(action, prepared=levels) or self.history.index == steps:
            return                 # refused, or the same texture again (submit said so)
        seconds = time.perf_counter() - start
        self.repairs_label.setText(f"repairs {repairs:,}")
        self.repairs_label.setToolTip("Window positions drawn from a backed-off context (dead "
                                      "ends of the DPJ) in the last synthesis")
        self.statusBar().showMessage(
            f"Synthesised {action.width}×{action.height}, seed {action.seed}, in {seconds:.2f} s "
            f"— {repairs:,} repairs", 10000)

    def edit_step(self, i: int, action) -> None:
        """Replace step i and replay every later step in the worker, on a scratch copy: the
        window stays live, the new document is swapped in only at the end, and Cancel (Esc,
        Ctrl+Z) leaves the document and its history exactly as they were."""
        self._replay_edit(lambda history: history.pending_replace(i, action, to_end=True),
                          f"Replaying from step {i + 1}…", "Cannot apply this edit",
                          self._replayed)

    def optimise_log(self, actions) -> None:
        """Replace the applied steps by the log optimiser's shorter log (the History dock's
        Optimise…), replayed in the worker as an edit is: one change, undone by Ctrl+Z."""
        self._replay_edit(lambda history: history.pending_rewrite(actions),
                          "Replaying the optimised log…", "Cannot optimise the log",
                          self._optimised)

    def _replay_edit(self, make, what: str, failure: str, done) -> None:
        """Run ``make(history)``'s PendingEdit in the worker, then ``done(history, pending)``."""
        if self.busy_note():
            return
        history = self.history
        try:
            pending = make(history)
        except TexeditorError as exc:
            self.show_error(failure, exc)
            return
        self._set_replaying(pending)

        def failed(exc):
            self._replay_ended()
            self.show_error(failure, exc)

        self.runner.run(what, pending.run, lambda _pending: done(history, pending),
                        on_cancel=lambda: self._replay_ended("Edit cancelled: the history is "
                                                             "unchanged."),
                        on_error=failed)

    def _commit_replay(self, history, pending, failure: str) -> bool:
        """Swap the replayed document in (unless another document was opened meanwhile)."""
        self._set_replaying(None)
        if history is not self.history:
            return False
        try:
            history.commit(pending)
        except TexeditorError as exc:
            self.show_error(failure, exc)
            return False
        return True

    def _replayed(self, history, pending) -> None:
        if not self._commit_replay(history, pending, "Cannot apply this edit"):
            return
        later = pending.new_index - pending.i - 1
        moved = len(history.retargeted)
        note = (f" {moved} later step(s) now act on a different region (marked ⚠ in the "
                "History)." if moved else "")
        self.statusBar().showMessage(f"Step {pending.i + 1} edited and the {later} later "
                                     f"step(s) replayed.{note} Ctrl+Z undoes the edit.", 12000)

    def _optimised(self, history, pending) -> None:
        before = history.index
        if self._commit_replay(history, pending, "Cannot optimise the log"):
            self.statusBar().showMessage(f"Log optimised: {counted(before, 'step')} became "
                                         f"{history.index}, the same texture. Ctrl+Z undoes it.",
                                         12000)

    def _set_replaying(self, pending) -> None:
        """While a replay runs the history dock is locked and Ctrl+Z cancels it."""
        self._replaying = pending
        self.history_dock.set_replaying(pending is not None)
        self.act_undo.setEnabled(pending is not None or self.can_undo())

    def _replay_ended(self, message: str = "") -> None:
        """Nothing was swapped in; the history dock keeps the edited values (to try again)."""
        self._set_replaying(None)
        if message:
            self.statusBar().showMessage(message, 8000)

    def edits_locked(self) -> bool:
        """True (with a word in the status bar) while a past step's edit is replayed: the
        document is about to be replaced, so a change made now would be lost. Like Krita while
        its image is busy, the change is refused rather than queued on a picture that is
        going away; Esc or Ctrl+Z cancels the replay."""
        if self._replaying is None:
            return False
        self.statusBar().showMessage("The history is being replayed: wait for it to finish, "
                                     "or press Esc to cancel it.", 5000)
        QtWidgets.QApplication.beep()
        return True

    def acquire(self, photo=None) -> AcquireDialog | None:
        """Open the acquisition dialog (window-modal, without a nested event loop), on ``photo``
        (a path, a pasted picture or an array) or else the first bundled photo."""
        if self.edits_locked():       # its DPJ would be added to a document about to be replaced
            return None
        dialog = AcquireDialog(resources.sample_images(), self, photo)
        dialog.accepted.connect(lambda: self.use_acquired(dialog))
        dialog.finished.connect(dialog.deleteLater)
        self.acquire_dialog = dialog
        dialog.open()
        return dialog

    def paste_photo(self) -> AcquireDialog | None:
        """Edit ▸ Paste as photo: acquire from the clipboard's picture (a screenshot, a picture
        copied in a painting program or a browser) or the image file copied in a file manager,
        as GIMP's File ▸ Create ▸ From Clipboard."""
        photo = self.clipboard_photo("Cannot paste this picture", "acquire from")
        return None if photo is None else self.acquire(photo)

    def clipboard_photo(self, error_title: str, purpose: str):
        """The clipboard's picture (an images.PastedPicture, read in the worker) or the image
        file copied in a file manager (a Path); None once it has said why not (a picture that
        cannot be used: a dialog; nothing on the clipboard: the status bar, "no picture to
        ``purpose``")."""
        try:
            photo = pasted_photo(QtWidgets.QApplication.clipboard().mimeData())
        except TexeditorError as exc:
            self.show_error(error_title, exc)
            return None
        if photo is None:
            self.statusBar().showMessage(f"The clipboard holds no picture to {purpose}.", 5000)
            QtWidgets.QApplication.beep()
        return photo

    def use_acquired(self, dialog: AcquireDialog) -> None:
        """The acquired DPJ becomes the current one (and is synthesised if asked); a photo
        model's scales are all added, the finest current, and the model attached."""
        dpj = dialog.dpj
        if dialog.model is not None:
            self.attach_model(dialog.model)
            self.statusBar().showMessage(f"Acquired a photo model of {dialog.model.scales.scales} "
                                         f"scales with G = {dialog.model.levels} from "
                                         f"{dialog.path.name}.", 10000)
        else:
            self.history.add_dpj(dpj)
            u, v = dpj.window
            self.statusBar().showMessage(f"Acquired a {u}×{v} DPJ with G = {dpj.levels} from "
                                         f"{dialog.path.name}: {len(dpj):,} configurations.",
                                         10000)
        if dialog.synthesise_now.isChecked():
            self.synthesise_from_dock()

    def start_default(self) -> None:
        """Open the texture bank on a built-in entry; without a bank, a fresh synthesis from a
        bundled DPJ."""
        if self.bank_dock.start():
            return
        history = History()
        try:
            history.add_dpj(resources.default_dpj())
        except TexeditorError as exc:
            self.show_error("No start-up texture", exc)
        self.set_history(history)
        if history.document.dpj is not None:
            self.synthesise_from_dock()

    # -- status bar ---------------------------------------------------------------------------------
    def _show_hover(self, info) -> None:
        if info is None:
            self.cursor_label.setText("x –, y –")
            self.level_label.setText("level –")
        else:
            x, y, level = info
            self.cursor_label.setText(f"x {x}, y {y}")
            self.level_label.setText(f"level {level}")

    def _show_zoom(self, zoom: float) -> None:
        """The zoom of the texture; none before there is one (an empty view's 61800 % says nothing)."""
        shown = self.canvas.levels is not None and self.canvas.levels.size > 0
        self.zoom_label.setText(f"zoom {zoom * 100:.0f} %" if shown else "zoom –")

    def _task_started(self, label: str) -> None:
        """The task's label, Cancel, and a busy bar until the task reports its first progress
        (a first start compiles the kernels for a while before any)."""
        self.task_label.setText(label)
        self.progress.setRange(0, 0)
        for w in (self.task_label, self.progress, self.cancel_button):
            w.show()
        self.act_cancel.setEnabled(True)
        self.synthesis_dock.set_busy(True)

    def _task_progress(self, fraction: float) -> None:
        if self.progress.maximum() == 0:
            self.progress.setRange(0, 1000)
        self.progress.setValue(int(fraction * 1000))

    def _task_finished(self) -> None:
        for w in (self.task_label, self.progress, self.cancel_button):
            w.hide()
        self.act_cancel.setEnabled(False)
        self.synthesis_dock.set_busy(False)

    def _update_title(self) -> None:
        name = self.path.name if self.path is not None else (self._name or "Untitled")
        h, w = self.history.document.shape
        size = f" ({w}×{h}, G = {self.history.document.num_levels})" if h else ""
        self.setWindowTitle(f"{name}{'*' if self.is_modified() else ''}{size} — {APP_NAME}")
