"""The checks of a hand-entered DPJ (thesis §5.2.2, §4.5), always in view, each with its remedy.

It reads the DPJ's report (range, sum, stationarity residuals, classes of the horizontal chain)
and offers Normalise, Make stationary and Restrict as buttons the editor turns into DPJ edits.
"""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets

STATIONARY = 1e-9        # residuals at or below this count as stationary
OK, WARN, BAD = "ok", "warn", "bad"
MARKS = {OK: ("✓", "#2e8b57"), WARN: ("!", "#d08000"), BAD: ("✗", "#c0392b")}


class CheckRow:
    """A mark (✓ / ! / ✗), a sentence, and an optional button with the remedy."""

    def __init__(self, grid: QtWidgets.QGridLayout, row: int, title: str, button: str | None,
                 tip: str = ""):
        self.mark = QtWidgets.QLabel()
        self.mark.setFixedWidth(18)
        self.mark.setAlignment(QtCore.Qt.AlignmentFlag.AlignCenter)
        self.title = QtWidgets.QLabel(f"<b>{title}</b>")
        self.text = QtWidgets.QLabel()
        self.text.setWordWrap(True)
        self.text.setTextInteractionFlags(QtCore.Qt.TextInteractionFlag.TextSelectableByMouse)
        grid.addWidget(self.mark, row, 0, QtCore.Qt.AlignmentFlag.AlignTop)
        grid.addWidget(self.title, row, 1, QtCore.Qt.AlignmentFlag.AlignTop)
        grid.addWidget(self.text, row, 2)
        self.button = None
        if button:
            self.button = QtWidgets.QPushButton(button)
            self.button.setToolTip(tip)
            grid.addWidget(self.button, row, 3, QtCore.Qt.AlignmentFlag.AlignTop)

    def show(self, state: str, text: str, remedy: bool = False) -> None:
        symbol, colour = MARKS[state]
        self.state = state
        self.mark.setText(f"<span style='color:{colour}; font-weight:bold'>{symbol}</span>")
        self.text.setText(text)
        if self.button is not None:
            self.button.setEnabled(remedy)


def chain_is_regular(r) -> bool:
    """The thesis's regular chain (§4.5): one closed class, aperiodic, nothing else."""
    return r.closed_classes == 1 and r.transient_states == 0 and r.period == 1


def chain_text(r, unreachable: int) -> str:
    """The Chain row's sentence: classes, dead ends, the period, the entries marked."""
    text = (f"{r.states:,} states, {r.closed_classes} closed class"
            f"{'es' if r.closed_classes != 1 else ''}, {r.transient_states:,} transient")
    if r.dead_ends:
        text += f", {r.dead_ends:,} dead end{'s' if r.dead_ends > 1 else ''}"
    if r.period > 1:
        text += (f" — periodic, period {r.period}: along a row the patterns cycle through "
                 f"{r.period} families")
    if unreachable:
        text += f" — {unreachable:,} unreachable, marked in red"
    return text


class ChecksPanel(QtWidgets.QWidget):
    """Signals: ``normaliseRequested``, ``stationaryRequested``, ``restrictRequested``."""

    normaliseRequested = QtCore.Signal()
    stationaryRequested = QtCore.Signal()
    restrictRequested = QtCore.Signal()

    def __init__(self, parent=None):
        super().__init__(parent)
        grid = QtWidgets.QGridLayout(self)
        grid.setColumnStretch(2, 1)
        grid.setHorizontalSpacing(8)
        self.range = CheckRow(grid, 0, "Range", None)
        self.sum = CheckRow(grid, 1, "Sum", "Normalise",
                            "Divide every probability by the sum")
        self.stationarity = CheckRow(
            grid, 2, "Stationarity", "Make stationary",
            "The closest DPJ (in Kullback–Leibler divergence) whose left/right and top/bottom "
            "sub-windows have equal laws, on the same configurations")
        self.chain = CheckRow(grid, 3, "Chain", "Restrict",
                              "Keep only the main closed class of the horizontal chain "
                              "(Massaloux): drops dead ends, transient states and small "
                              "closed classes")
        self.verdict = QtWidgets.QLabel()
        grid.addWidget(self.verdict, 4, 0, 1, 4)
        self.sum.button.clicked.connect(self.normaliseRequested)
        self.stationarity.button.clicked.connect(self.stationaryRequested)
        self.chain.button.clicked.connect(self.restrictRequested)

    def show_pending(self) -> None:
        """A large DPJ is being checked in the background."""
        for row in (self.range, self.sum, self.stationarity, self.chain):
            row.mark.setText("…")
            if row.button is not None:
                row.button.setEnabled(False)
        self.verdict.setText("Checking…")

    def show_report(self, report, unreachable: int) -> None:
        """Show the DPJ's report; ``unreachable`` is the number of marked entries."""
        r = report
        bad = r.negative + r.above_one + r.nonfinite
        self.range.show(OK if not bad else BAD,
                        "every probability is in [0, 1]" if not bad else
                        f"{r.negative} negative, {r.above_one} above 1, {r.nonfinite} not a number")
        if not r.entries:
            self.sum.show(BAD, "0: paint a configuration and give it a probability")
        else:
            off = abs(r.total - 1.0) >= 1e-9
            self.sum.show(BAD if off else OK, f"{r.total:.10g}" + (" — must be 1" if off else ""),
                          remedy=off and r.total > 0)
        h, v = r.horizontal_residual, r.vertical_residual
        still = h <= STATIONARY and v <= STATIONARY
        self.stationarity.show(OK if still else WARN,
                               f"left/right {h:.3g}, top/bottom {v:.3g}" +
                               ("" if still else " (0 when stationary)"),
                               remedy=not still and r.entries > 0 and r.total > 0)
        if not r.entries:
            self.chain.show(OK, "no configurations yet")
        else:
            self.chain.show(OK if chain_is_regular(r) and not unreachable else WARN,
                            chain_text(r, unreachable), remedy=bool(unreachable))
        ready = r.is_valid
        colour = MARKS[OK if ready else BAD][1]
        self.verdict.setText(f"<span style='color:{colour}'>" +
                             ("Ready to synthesise." if ready else
                              "Not ready: probabilities in [0, 1] summing to 1 are needed.")
                             + "</span>")
