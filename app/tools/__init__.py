"""Canvas tools: each turns mouse gestures on the canvas into Actions.

A tool never touches arrays: it builds an Action and calls ``main_window.submit(action)`` (not
``window``: QWidget.window() is a method Qt may call on widgets that carry the name). Gestures
follow napari's pattern: ``drag`` is a generator that does the press's work, then receives each
later cell with ``send`` and ends when the button is released (``close``). Previews (a ghost,
a selection tint) go to the canvas overlay, never into the document.

A tool's settings are data (a frozen dataclass named in ``SETTINGS``, held in ``tool.model``,
see app.tool_settings): its options panel mirrors them, and the tool reads ``tool.settings``.

To add a tool: subclass :class:`Tool` in a module of this package and list it in ``TOOLS`` of
``tool_classes``.
"""

from __future__ import annotations

from typing import Generator

from PySide6 import QtCore, QtWidgets

from ..tool_settings import SettingsModel

Cell = tuple[int, int]   # (x, y): column, row — possibly outside the canvas while dragging


class Tool:
    """The base tool: does nothing on click or drag. Subclasses set NAME, SHORTCUT and TIP."""

    NAME = ""
    LABEL = ""          # the button's short text (default: the first word of NAME)
    SHORTCUT = ""
    TIP = ""
    PANS = False        # a left drag pans the view (the hand tool)
    SETTINGS: type | None = None     # the dataclass of the tool's settings (None: it has none)

    def __init__(self, window):
        self.main_window = window
        self._options: QtWidgets.QWidget | None = None
        self.model = SettingsModel(self.SETTINGS()) if self.SETTINGS is not None else None

    @property
    def settings(self):
        """The tool's settings (a frozen dataclass); assigning one updates the options panel."""
        return self.model.value

    @settings.setter
    def settings(self, value) -> None:
        self.model.value = value

    # -- what the main window asks ----------------------------------------------------------------
    def options(self) -> QtWidgets.QWidget:
        """The tool's options panel (built once)."""
        if self._options is None:
            self._options = self.build_options() or _no_options(self.TIP)
        return self._options

    def build_options(self) -> QtWidgets.QWidget | None:
        return None

    def activate(self) -> None:
        """Called when the tool becomes current."""

    def deactivate(self) -> None:
        self.main_window.canvas.set_overlay(None)
        if getattr(self, "_own_dock", None) is not None:
            self._own_dock.hide()
            self._own_dock = None
            bank = getattr(self.main_window, "bank_dock", None)
            if bank is not None and bank.toggleViewAction().isChecked():
                bank.raise_()                    # the column's first tab comes back, not another

    def show_own_dock(self, name: str) -> None:
        """Show the window's dock ``name`` (the Brushes, the Grain stamps) while this tool is
        current, as Krita and GIMP show presets only with the tools that use them: one the tool
        opened closes when another tool is chosen; one the user had open stays open."""
        dock = getattr(self.main_window, name, None)
        if dock is None:
            return
        if not dock.toggleViewAction().isChecked():
            self._own_dock = dock
        dock.show()
        dock.raise_()

    # -- gestures -----------------------------------------------------------------------------------
    def click(self, cell: Cell, modifiers: QtCore.Qt.KeyboardModifier) -> None:
        """A press and release without moving."""

    def drag(self, cell: Cell, modifiers: QtCore.Qt.KeyboardModifier) -> Generator[None, Cell, None]:
        """A drag from ``cell``: yields once per cell received, returns on release."""
        yield

    def hover(self, cell: Cell | None) -> None:
        """The pointer moved with no button pressed (None: it left the canvas)."""

    # -- helpers for subclasses -----------------------------------------------------------------------
    @property
    def document(self):
        """What the tool paints: the document, or its plates while painting on them."""
        return self.main_window.paint_document

    def inside(self, cell: Cell) -> bool:
        h, w = self.document.shape
        return 0 <= cell[0] < w and 0 <= cell[1] < h


class HandTool(Tool):
    NAME = "Hand"
    SHORTCUT = "H"
    TIP = "Drag to pan the view (the wheel zooms; middle-drag or Space-drag pan with any tool)"
    PANS = True


def _no_options(tip: str) -> QtWidgets.QWidget:
    label = QtWidgets.QLabel(tip or "This tool has no options.")
    label.setWordWrap(True)
    label.setAlignment(QtCore.Qt.AlignmentFlag.AlignTop)
    return label


def tool_classes() -> list[type[Tool]]:
    """Every tool, in toolbar order."""
    from .regions import CopyTool, ExtractTool, FillTool, TranslateTool

    TOOLS: list[type[Tool]] = [HandTool, FillTool, TranslateTool, CopyTool, ExtractTool]
    from .spot import SpotTool
    TOOLS.append(SpotTool)
    from .brush import BrushTool, SprayTool
    from .grain import GrainTool
    from .tree import TreeTool
    from .zone import OrderTool, ScrambleTool, ZoneTool
    TOOLS += [BrushTool, SprayTool, GrainTool, TreeTool, ZoneTool, ScrambleTool, OrderTool]
    return TOOLS
