"""The File menu of the main window: New, Open (in the worker), Save, Save As, Export PNG, Recent.

A mixin of MainWindow. A `.texture` holds the DPJs and the action log; opening one replays the log,
so it runs off the GUI thread. Every failure is a dialog and the open document stays as it was.
"""

from __future__ import annotations

from pathlib import Path

from PySide6 import QtCore, QtWidgets

from texeditor.export import to_rgb, write_picture, write_png
from texeditor.wording import counted
from texeditor.recipe.actions import NewCanvas
from texeditor.errors import Cancelled, TexeditorError
from texeditor.recipe.history import History
from texeditor.recipe.texturefile import load_texture, save_texture

from .acquire_dialog import pasted_photo
from .images import photo_rgb, qimage_from_rgb
from .new_dialog import NewDialog

TEXTURE_FILTER = "Textures (*.texture);;All files (*)"
BACKGROUND_EXPORT = 2**20     # output pixels from which an export is written in the worker
PNG_FILTER = "PNG images (*.png)"
MAX_RECENT = 8


def settings() -> QtCore.QSettings:
    """The user's settings (the default format, so tests can redirect them to a temporary file)."""
    return QtCore.QSettings(QtCore.QSettings.defaultFormat(), QtCore.QSettings.Scope.UserScope,
                            "texeditor", "texeditor")


def recent_files() -> list[str]:
    value = settings().value("recentFiles", [])
    return [value] if isinstance(value, str) else list(value or [])


def remember_recent(path) -> None:
    path = str(Path(path).resolve())
    files = [path] + [p for p in recent_files() if p != path]
    settings().setValue("recentFiles", files[:MAX_RECENT])


class FileOps:
    """New, open, save, export and the unsaved-changes prompt (needs history, runner, path)."""

    # -- modified state -----------------------------------------------------------------------------
    def mark_clean(self) -> None:
        self._clean_log = self.history.applied if self.history is not None else ()
        self._update_title()
        self.journal_sync(reset=True)      # nothing unsaved to recover from here on

    def mark_unsaved(self) -> None:
        """Call the whole log unsaved work (a restored crash journal: nothing of it is on disk)."""
        self._clean_log = ()
        self._update_title()

    def is_modified(self) -> bool:
        return self.history is not None and self.history.applied != self._clean_log

    def maybe_save(self) -> bool:
        """True when the current work may be dropped (saved, discarded, or unmodified)."""
        if not self.is_modified():
            return True
        answer = QtWidgets.QMessageBox.question(
            self, "Unsaved changes",
            "The texture has changes that are not saved. Save them first?",
            QtWidgets.QMessageBox.StandardButton.Save
            | QtWidgets.QMessageBox.StandardButton.Discard
            | QtWidgets.QMessageBox.StandardButton.Cancel,
            QtWidgets.QMessageBox.StandardButton.Save)
        if answer == QtWidgets.QMessageBox.StandardButton.Save:
            return self.save()
        return answer == QtWidgets.QMessageBox.StandardButton.Discard

    def quit_all(self) -> bool:
        """File ▸ Quit: close every texeditor window (a crash can leave several restored), this
        one first, each asking about its own unsaved work; a Cancel stops the quit there."""
        others = [w for w in QtWidgets.QApplication.topLevelWidgets()
                  if isinstance(w, type(self)) and w is not self and w.isVisible()]
        return all(w.close() for w in [self, *others])

    def closeEvent(self, ev) -> None:
        if not self.maybe_save():
            ev.ignore()
            return
        self.closing = True                # a task cancelled now starts nothing in its place
        self.runner.cancel()
        self.runner.wait(10_000)
        self.journal_discard()
        ev.accept()

    # -- drops ----------------------------------------------------------------------------------------
    def dragEnterEvent(self, ev) -> None:
        """Files and pictures dragged from a file manager or a browser may be dropped."""
        mime = ev.mimeData()
        if mime.hasImage() or any(url.isLocalFile() for url in mime.urls()):
            ev.acceptProposedAction()

    def dropEvent(self, ev) -> None:
        """A dropped .texture opens, a .dpj is opened as File ▸ Open DPJ does, and any other
        file or a picture is a photo to acquire from (the acquisition dialog opens on it)."""
        ev.acceptProposedAction()
        try:
            dropped = pasted_photo(ev.mimeData())
        except TexeditorError as exc:
            self.show_error("Cannot use the dropped picture", exc)
            return
        suffix = dropped.suffix.lower() if isinstance(dropped, Path) else None
        if suffix == ".texture":
            self.open_file(dropped)
        elif suffix == ".dpj":
            self.open_dpj(dropped)
        elif dropped is not None:
            self.acquire(dropped)

    # -- new and open -------------------------------------------------------------------------------
    def new_document(self) -> NewDialog:
        """Ask for size and G (window-modal, without a nested event loop), then create."""
        doc = self.history.document if self.history is not None else None
        h, w = doc.shape if doc is not None and doc.levels.size else (256, 256)
        dialog = NewDialog(w, h, doc.num_levels if doc is not None else 4, self)
        dialog.accepted.connect(lambda: self.create_document(*dialog.values()))
        dialog.finished.connect(dialog.deleteLater)
        self.new_dialog = dialog
        dialog.open()
        return dialog

    def create_document(self, width: int, height: int, levels: int) -> bool:
        """A new History on a blank canvas; the current DPJ is kept so Synthesise still works."""
        if not self.maybe_save():
            return False
        history = History()
        if self.photo_model is not None:       # its scales stay at hand for a synthesis
            for dpj in self.photo_model.scales.dpjs:
                history.add_dpj(dpj)
        old = self.history.document.dpj if self.history is not None else None
        if old is not None and old.levels == levels:
            history.add_dpj(old)
        try:
            history.apply(NewCanvas(width, height, levels))
        except TexeditorError as exc:
            self.show_error("Cannot create this canvas", exc)
            return False
        self.set_history(history)
        return True

    def open_file(self, path=None) -> None:
        if self.busy_note():
            return
        if path is None:
            path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Open a texture", self._folder(),
                                                            TEXTURE_FILTER)
            if not path:
                return
        if self.busy_note() or not self.maybe_save():
            return
        path = Path(path)
        self.runner.run(f"Opening {path.name}…",
                        lambda progress, cancel: load_texture(path, progress=progress,
                                                              cancel=cancel),
                        lambda result: self._opened(path, result[0]),
                        on_cancel=lambda: self.statusBar().showMessage("Opening cancelled.", 5000),
                        on_error=lambda exc: self.show_error(f"Cannot open {path.name}", exc))

    def _opened(self, path: Path, history: History) -> None:
        self.set_history(history, path)
        remember_recent(path)
        self.statusBar().showMessage(f"Opened {path} ({counted(len(history.actions), 'step')}).",
                                     8000)

    def _fill_recent_menu(self) -> None:
        self.recent_menu.clear()
        files = recent_files()
        for path in files:
            action = self.recent_menu.addAction(Path(path).name)
            action.setToolTip(path)
            action.setStatusTip(path)
            action.triggered.connect(lambda _checked=False, p=path: self.open_file(p))
        if not files:
            self.recent_menu.addAction("No recent files").setEnabled(False)

    # -- save and export ----------------------------------------------------------------------------
    def save(self) -> bool:
        if self.path is None:
            return self.save_as()
        return self.save_to(self.path)

    def save_as(self) -> bool:
        start = str(self.path) if self.path is not None else str(Path(self._folder(), "untitled.texture"))
        path, _ = QtWidgets.QFileDialog.getSaveFileName(self, "Save the texture", start,
                                                        TEXTURE_FILTER)
        if not path:
            return False
        path = Path(path)
        if path.suffix.lower() != ".texture":
            path = path.with_name(path.name + ".texture")
        return self.save_to(path)

    def save_to(self, path) -> bool:
        """Write a `.texture` (atomically, by the engine); errors leave the document as it was."""
        path = Path(path)
        try:
            save_texture(path, self.history)
        except (TexeditorError, OSError) as exc:
            self.show_error(f"Cannot save {path.name}", exc)
            return False
        self.path = path
        remember_recent(path)
        self.mark_clean()
        self.statusBar().showMessage(f"Saved {path}.", 5000)
        return True

    def export_png(self) -> None:
        doc = self.history.document
        if not doc.levels.size:
            return
        start = str(Path(self._folder(), (self.path.stem if self.path else "texture") + ".png"))
        path, _ = QtWidgets.QFileDialog.getSaveFileName(self, "Export as PNG", start, PNG_FILTER)
        if not path:
            return
        h, w = doc.shape
        scale, ok = QtWidgets.QInputDialog.getInt(
            self, "Export scale", f"Draw each point as N×N pixels ({w}×{h} points):", 1, 1, 16)
        if ok:
            self.export_to(path, scale)

    def export_to(self, path, scale: int = 1) -> bool:
        """Write the picture on show (tone, plates, if they are; else the levels in their
        palette), each point as scale×scale pixels. False when it was refused or failed."""
        path = Path(path)
        if path.suffix.lower() != ".png":
            path = path.with_name(path.name + ".png")
        doc = self.history.document
        picture = self.display_picture()     # the picture on show: tone, plates, if they are
        h, w = doc.shape
        if picture is not None:
            write = lambda: write_picture(path, picture, scale)             # noqa: E731
        else:
            levels, palette = doc.levels.copy(), doc.palette.copy()        # edits may follow
            write = lambda: write_png(path, levels, palette, scale)         # noqa: E731
        return self.write_export(h * w * scale * scale, path, write, "Cannot export",
                                 f"Exported {path} ({w * scale}×{h * scale} pixels).")

    def write_export(self, pixels: int, path: Path, write, error_title: str, done: str) -> bool:
        """``write()`` a file (atomically: no half-written file), saying ``done`` in the status
        bar or the error in a dialog. From BACKGROUND_EXPORT output pixels on (a 2048² export
        takes a second or more) it is written in the worker, the window live, with progress
        and Esc, which stops it before the write begins (once begun, it ends; the status bar
        says which). False when it failed, or could not start while other work runs."""
        if pixels < BACKGROUND_EXPORT:
            try:
                write()
            except (TexeditorError, OSError) as exc:
                self.show_error(error_title, exc)
                return False
            self.statusBar().showMessage(done, 8000)
            return True
        if self.busy_note():
            return False
        written = []

        def work(_progress, cancel):
            if cancel():
                raise Cancelled("export cancelled")
            write()
            written.append(path)

        def cancelled():
            self.statusBar().showMessage(done if written else f"Export cancelled: {path.name} "
                                         "was not written.", 8000)
        self.runner.run(f"Writing {path.name}…", work,
                        lambda _r: self.statusBar().showMessage(done, 8000),
                        on_cancel=cancelled,
                        on_error=lambda exc: self.show_error(error_title, exc))
        return True

    def copy_picture(self) -> bool:
        """Edit ▸ Copy picture: the picture on show (tone, plates, else the levels in their
        palette) to the clipboard, to paste into a painting program."""
        doc = self.history.document if self.history is not None else None
        if doc is None or not doc.levels.size:
            return False
        picture = self.display_picture()
        rgb = to_rgb(doc.levels, doc.palette) if picture is None else photo_rgb(picture)
        QtWidgets.QApplication.clipboard().setImage(qimage_from_rgb(rgb))
        h, w = doc.shape
        self.statusBar().showMessage(f"Copied the picture ({w}×{h} pixels) to the clipboard.",
                                     5000)
        return True

    def _folder(self) -> str:
        return str(self.path.parent) if self.path is not None else str(Path.home())
