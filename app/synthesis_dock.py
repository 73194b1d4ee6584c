"""The synthesis dock: the current DPJ, the size and seed of the next texture, and its button;
for a photo model's scales, how many of them to draw, and whether to show the photo's tone.

Synthesis itself runs in a worker (synthesis_worker.py); this panel only gathers the parameters of
the Synthesize Action the main window will submit.
"""

from __future__ import annotations

from PySide6 import QtCore, QtWidgets

from texeditor.markov.multiscale import MultiScaleDPJ, scales_phrase
from texeditor.markov.scan import ROWS, SCANS
from texeditor.recipe.actions import MAX_CANVAS_SIDE

from .params_form import SeedEdit, dpj_summary
from .widgets import scan_combo, scrolled, tight_vertically

DEFAULT_SIZE = 256
DEFAULT_SEED = 1984


SYNTHESES = ("synthesize", "synthesize_scales")


def synthesis_step(history):
    """The Synthesize (or SynthesizeScales) step that made the current texture (None when the
    last new canvas was not a synthesis, or there is none)."""
    for action in reversed(history.applied):
        if action.EFFECT == "reset":
            return action if action.TYPE in SYNTHESES else None
    return None


def scales_summary(dpjs) -> tuple[str, str]:
    """Two lines for a photo model's scales: its name and number of scales, the finest one."""
    name = dpjs[-1].meta.get("name", "photo model").rpartition(" scale ")[0] or "photo model"
    u, v = dpjs[-1].window
    return (f"{name}: {scales_phrase(len(dpjs))}",
            f"finest {u}×{v}, G = {MultiScaleDPJ(tuple(dpjs)).levels}")


class SynthesisDock(QtWidgets.QDockWidget):
    """``requested(width, height, seed)`` when the user asks for a synthesis."""

    requested = QtCore.Signal(int, int, int)

    def __init__(self, parent=None):
        super().__init__("Synthesis", parent)
        self.setObjectName("SynthesisDock")
        body = QtWidgets.QWidget()
        form = QtWidgets.QFormLayout(body)
        tight_vertically(form)
        self.dpj_label = QtWidgets.QLabel()
        self.dpj_label.setWordWrap(True)     # a long name or description wraps: the dock never
                                             # scrolls sideways to show it
        self.width_box = self._side()
        self.height_box = self._side()
        size_row = QtWidgets.QHBoxLayout()
        size_row.addWidget(self.width_box, 1)
        size_row.addWidget(QtWidgets.QLabel("×"))
        size_row.addWidget(self.height_box, 1)
        self.seed = SeedEdit(DEFAULT_SEED)
        self.scales_box = QtWidgets.QSpinBox()
        self.scales_box.setRange(1, 1)
        self.scales_box.setToolTip("How many scales of the photo model to draw, coarsest first "
                                   "(all of them: the photo's size of structure); only for a "
                                   "photo model's DPJ")
        self.tone_box = QtWidgets.QCheckBox("Photographic tone")
        self.tone_box.setChecked(True)
        self.tone_box.setToolTip("Show the texture with the photo's own greys and colours instead "
                                 "of the palette (View ▸ Photographic tone, T)")
        scales_page = QtWidgets.QWidget()
        scales_row = QtWidgets.QHBoxLayout(scales_page)
        scales_row.setContentsMargins(0, 0, 0, 0)
        scales_row.addWidget(self.scales_box)
        scales_row.addWidget(self.tone_box, 1)
        self.tileable_box = QtWidgets.QCheckBox("Tileable")
        self.tileable_box.setToolTip("Draw the texture on the torus: it repeats without a seam "
                                     "(its last columns and rows are drawn given its first ones)")
        seed_row = QtWidgets.QHBoxLayout()
        seed_row.addWidget(self.seed, 1)
        seed_row.addWidget(self.tileable_box)
        self.scan_box = scan_combo("The order the texture is drawn in (thesis §5.2.1b): the "
                                   "DPJ's rows run along it. A DPJ acquired in a scan proposes "
                                   "that scan; another one turns the texture.")
        self.button = QtWidgets.QPushButton("Synthesise")
        self.button.setToolTip("Draw a new texture from the current DPJ (Ctrl+R)")
        self.button.clicked.connect(self._request)
        form.addRow("DPJ", self.dpj_label)
        form.addRow("Size", size_row)
        # one DPJ is drawn in a scan, a photo model's scales in rows: the row shows what applies
        self.scan_or_scales = QtWidgets.QStackedWidget()
        self.scan_or_scales.addWidget(self.scan_box)
        self.scan_or_scales.addWidget(scales_page)
        form.addRow("Seed", seed_row)
        form.addRow("Scan", self.scan_or_scales)
        self.scan_or_scales_label = form.labelForField(self.scan_or_scales)
        form.addRow(self.button)
        self.setWidget(scrolled(body))
        self.scale_dpjs: list = []
        self._proposed_for = None        # the DPJ whose recorded scan the box last proposed
        self.set_dpj(None)
        self.set_scales([])
        self.set_tone_available(False)

    def _side(self) -> QtWidgets.QSpinBox:
        box = QtWidgets.QSpinBox()
        box.setRange(1, MAX_CANVAS_SIDE)
        box.setValue(DEFAULT_SIZE)
        box.setSuffix(" px")
        return box

    def set_dpj(self, dpj) -> None:
        self.has_dpj = dpj is not None
        if dpj is None:        # always two lines, so the dock keeps its height
            self.dpj_label.setText("none yet\nFile ▸ Acquire DPJ from image…")
        else:
            name, _, details = dpj_summary(dpj).partition(": ")
            self.dpj_label.setText(f"{name}\n{details}")
        self.dpj_label.setToolTip(dpj_summary(dpj) if dpj is not None else "")
        self.button.setEnabled(self.has_dpj and not getattr(self, "busy", False))
        self._propose_scan(dpj)

    def _propose_scan(self, dpj) -> None:
        """A new current DPJ proposes the scan it was acquired in (rows when it says none);
        the same DPJ keeps the scan the user chose."""
        ref = dpj.ref if dpj is not None else None
        if ref != self._proposed_for:
            self._proposed_for = ref
            recorded = dpj.meta.get("scan", ROWS) if dpj is not None else ROWS
            self.set_scan(recorded if recorded in SCANS else ROWS)

    def set_scan(self, scan: str) -> None:
        self.scan_box.setCurrentIndex(self.scan_box.findData(scan))

    def scan(self) -> str:
        """The scan of the next synthesis (a photo model's scales are drawn in rows)."""
        return ROWS if self.scale_dpjs else self.scan_box.currentData()

    def set_scales(self, dpjs) -> None:
        """The scales (DPJs, coarsest first) the current DPJ belongs to, or none: a new set
        offers all its scales, the same set keeps the number chosen."""
        dpjs = list(dpjs)
        same = [d.ref for d in dpjs] == [d.ref for d in self.scale_dpjs]
        self.scale_dpjs = dpjs
        n = max(1, len(dpjs))
        self.scales_box.setRange(1, n)
        if not same:
            self.scales_box.setValue(n)
        self.scales_box.setEnabled(len(dpjs) > 1)
        self.scan_or_scales.setCurrentIndex(1 if dpjs else 0)
        self.scan_or_scales_label.setText("Scales" if dpjs else "Scan")
        if dpjs:
            first, second = scales_summary(dpjs)
            self.dpj_label.setText(f"{first}\n{second}")
            self.dpj_label.setToolTip("\n".join(dpj_summary(d) for d in dpjs))

    def set_tone_available(self, available: bool) -> None:
        self.tone_box.setEnabled(available)

    def scale_count(self) -> int:
        return self.scales_box.value()

    def refresh(self, history, scale_dpjs=()) -> None:
        """Follow the document after any change (undo, redo, replay, open): its DPJ (and the
        scales it belongs to), and the size, seed and scales of the synthesis that made the
        current texture. Those are shown when that step changes, so values typed for the next
        synthesis survive unrelated edits (a stroke)."""
        doc = history.document
        self.set_dpj(doc.dpj)
        self.set_scales(scale_dpjs)
        step = synthesis_step(history)
        if step is not None and step != getattr(self, "_shown_step", None):
            self.show_step(step)
        self._shown_step = step

    def show_step(self, action) -> None:
        """Show a Synthesize step's size, seed and scan (a SynthesizeScales step's scales)."""
        self.width_box.setValue(action.width)
        self.height_box.setValue(action.height)
        self.seed.set_value(action.seed)
        self.tileable_box.setChecked(action.tileable)
        if action.TYPE == "synthesize":
            self.set_scan(action.scan)
        else:
            self.scales_box.setValue(len(action.dpjs))

    def set_busy(self, busy: bool) -> None:
        self.busy = busy
        self.button.setEnabled(self.has_dpj and not busy)

    def values(self) -> tuple[int, int, int]:
        return self.width_box.value(), self.height_box.value(), self.seed.value()

    def tileable(self) -> bool:
        return self.tileable_box.isChecked()

    def _request(self) -> None:
        self.requested.emit(*self.values())
