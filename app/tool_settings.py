"""A tool's settings as data: a frozen dataclass held by a :class:`SettingsModel`, mirrored by
the option widgets bound to its fields.

Tools read their parameters from ``model.value`` (never from a spin box), so a tool keeps its
settings whether its options panel exists, is shown or not, and tests and sessions can set them
without going through widgets. A widget change replaces the value; assigning a value writes the
bound widgets, whose signals are then ignored here (no feedback loop) but still reach other
listeners (a preview that follows the settings).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Callable

from PySide6 import QtCore, QtWidgets


class SettingsModel(QtCore.QObject):
    """One tool's settings (a frozen dataclass) and the widgets that show them."""

    changed = QtCore.Signal(str)        # the field a widget changed ("" when set as a whole)

    def __init__(self, value):
        super().__init__()
        self._value = value
        self._fields: dict[str, list[tuple[Callable[[], Any], Callable[[Any], None]]]] = {}
        self._loading = False

    @property
    def value(self):
        return self._value

    @value.setter
    def value(self, value) -> None:
        self._value = value
        self._write(list(self._fields))
        self.changed.emit("")

    def update(self, **fields) -> None:
        """Replace some fields (as if set as a whole): the widgets follow."""
        self._value = dataclasses.replace(self._value, **fields)
        self._write(list(fields))
        self.changed.emit("")

    def has(self, name: str) -> bool:
        return name in {f.name for f in dataclasses.fields(self._value)}

    def bind(self, name: str, widget: QtWidgets.QWidget, *, scale: float = 1,
             get: Callable[[], Any] | None = None, put: Callable[[Any], None] | None = None,
             signal=None) -> None:
        """Mirror field ``name`` in ``widget`` (a combo box's item data, a check box, a spin
        box or a slider ×``scale``, a line edit; or ``get``/``put``/``signal`` given). A field
        the dataclass lacks is not bound (a widget shared by tools with different settings)."""
        if not self.has(name):
            return
        default_get, default_put, default_signal = _adapter(widget, scale)
        get, put = get or default_get, put or default_put
        signal = default_signal if signal is None else signal
        self._fields.setdefault(name, []).append((get, put))
        self._write([name])
        if signal is not False and get is not None:
            signal.connect(lambda *_: self._read(name, get))

    def _read(self, name: str, get) -> None:
        if self._loading:
            return
        self._value = dataclasses.replace(self._value, **{name: get()})
        self.changed.emit(name)

    def _write(self, names) -> None:
        """Show the fields in their widgets; the value then takes what the widgets hold (a
        spin box's rounding and range), so data and widgets never disagree."""
        self._loading = True
        try:
            for name in names:
                for get, put in self._fields.get(name, ()):
                    put(getattr(self._value, name))
                    if get is not None:
                        self._value = dataclasses.replace(self._value, **{name: get()})
        finally:
            self._loading = False


def _adapter(widget, scale: float):
    """(get, put, signal) for the common widgets."""
    if isinstance(widget, QtWidgets.QComboBox):
        return (widget.currentData,
                lambda v: widget.setCurrentIndex(max(0, widget.findData(v))),
                widget.currentIndexChanged)
    if isinstance(widget, QtWidgets.QAbstractButton):
        return widget.isChecked, widget.setChecked, widget.toggled
    if isinstance(widget, QtWidgets.QLineEdit):
        return widget.text, widget.setText, widget.textChanged
    if isinstance(widget, (QtWidgets.QSpinBox, QtWidgets.QAbstractSlider)):
        if scale == 1:
            return widget.value, lambda v: widget.setValue(round(v)), widget.valueChanged
        return (lambda: widget.value() / scale, lambda v: widget.setValue(round(v * scale)),
                widget.valueChanged)
    if isinstance(widget, QtWidgets.QDoubleSpinBox):
        return widget.value, widget.setValue, widget.valueChanged
    if isinstance(widget, QtWidgets.QLabel):
        return None, lambda v: widget.setText(str(v)), False
    raise TypeError(f"no settings adapter for {type(widget).__name__}")
