"""Charts of the DPJ being edited (pyqtgraph): the probabilities sorted on a log scale, the law of
single levels, and the horizontal chain's transition matrix as a heat map.

They only read the DPJ (the numbers come from texeditor.markov.dpj_edit); a hidden tab is redrawn when
it is shown, so editing a large DPJ does not pay for charts nobody looks at.
"""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6 import QtCore, QtWidgets

from texeditor.markov import dpj_edit

from .table import config_text

MAX_BARS = 300           # above this many entries the sorted law is drawn as a filled curve
CURVE_POINTS = 2000      # ranks drawn on that curve
HEAT_STATES = 48         # most probable states shown in the transition matrix
LABELLED_STATES = 16     # up to this many, the heat map's axes name the states


def _plot(title: str, left: str, bottom: str) -> pg.PlotWidget:
    w = pg.PlotWidget(background="w")
    item = w.getPlotItem()
    item.setTitle(title, color="#333", size="10pt")
    item.setLabel("left", left)
    item.setLabel("bottom", bottom)
    item.showGrid(x=False, y=True, alpha=0.25)
    item.setMenuEnabled(False)
    for name in ("left", "bottom"):
        item.getAxis(name).setTextPen("#333")
        item.getAxis(name).setPen("#888")
        item.getAxis(name).enableAutoSIPrefix(False)
    return w


class ChartsPanel(QtWidgets.QTabWidget):
    def __init__(self, parent=None):
        super().__init__(parent)
        self.dpj = None
        self._drawn: set[int] = set()
        self.sorted_plot = _plot("Probabilities, largest first", "probability (log)", "rank")
        self.sorted_plot.getPlotItem().getAxis("left").setLogMode(False, True)
        self.levels_plot = _plot("Law of single points", "probability", "level")
        self.heat_plot = _plot("Horizontal chain m(L → R)", "from state L", "to state R")
        self.heat_plot.getPlotItem().invertY(True)
        self.heat_plot.getPlotItem().showGrid(x=False, y=False)
        self.heat_image = pg.ImageItem(axisOrder="row-major")
        self.heat_plot.addItem(self.heat_image)
        self.colour_bar = pg.ColorBarItem(values=(0, 1), colorMap=pg.colormap.get("viridis"),
                                          interactive=False, width=12)
        self.colour_bar.setImageItem(self.heat_image, insert_in=self.heat_plot.getPlotItem())
        self.addTab(self.sorted_plot, "Probabilities")
        self.addTab(self.levels_plot, "Levels")
        self.addTab(self.heat_plot, "Transitions")
        self.currentChanged.connect(lambda _i: self._draw_current())

    def set_dpj(self, dpj) -> None:
        self.dpj = dpj
        self._drawn.clear()
        self._draw_current()

    def draw_all(self) -> None:
        for k in range(self.count()):
            self._draw(k)

    def _draw_current(self) -> None:
        if self.dpj is not None and self.currentIndex() not in self._drawn:
            self._draw(self.currentIndex())

    def _draw(self, k: int) -> None:
        (self._draw_sorted, self._draw_levels, self._draw_heat)[k](self.dpj)
        self._drawn.add(k)

    # -- the three charts --------------------------------------------------------------------------
    def _draw_sorted(self, dpj) -> None:
        plot = self.sorted_plot.getPlotItem()
        plot.clear()
        p = np.sort(dpj.probs[dpj.probs > 0])[::-1]
        if not len(p):
            return
        logp = np.log10(p)
        floor = np.floor(logp.min()) - 0.5
        rank = np.arange(1, len(p) + 1)
        brush = pg.mkBrush(70, 110, 170)
        if len(p) <= MAX_BARS:
            plot.addItem(pg.BarGraphItem(x=rank, height=logp - floor, y0=floor, width=0.8,
                                         brush=brush, pen=pg.mkPen(40, 70, 120)))
        else:                      # monotone: a few thousand ranks draw the same curve
            keep = np.unique(np.linspace(0, len(p) - 1, CURVE_POINTS).astype(int))
            plot.plot(rank[keep], logp[keep], pen=pg.mkPen(40, 70, 120), fillLevel=floor,
                      brush=brush)
        plot.setXRange(0.5, len(p) + 0.5, padding=0.02)
        plot.setYRange(floor, max(0.0, logp.max()) + 0.1, padding=0)

    def _draw_levels(self, dpj) -> None:
        plot = self.levels_plot.getPlotItem()
        plot.clear()
        marginal = dpj_edit.level_marginal(dpj)
        brushes = [pg.mkBrush(*(int(c) for c in rgb)) for rgb in dpj.palette]
        plot.addItem(pg.BarGraphItem(x=np.arange(dpj.levels), height=marginal, width=0.8,
                                     brushes=brushes, pen=pg.mkPen("#555")))
        plot.getAxis("bottom").setTicks([[(k, str(k)) for k in range(dpj.levels)]])
        plot.setXRange(-0.6, dpj.levels - 0.4, padding=0)
        plot.setYRange(0, max(float(marginal.max()) * 1.1, 1e-3), padding=0)

    def _draw_heat(self, dpj) -> None:
        plot = self.heat_plot.getPlotItem()
        states, matrix, total = dpj_edit.transition_matrix(dpj, HEAT_STATES)
        k = len(matrix)
        shown = f"{k} most probable of {total:,} states" if k < total else f"{total} states"
        plot.setTitle(f"Horizontal chain m(L → R): {shown}" if k else
                      "Horizontal chain: none (u = 1 or no entries)", color="#333", size="10pt")
        if not k:
            self.heat_image.clear()
            return
        self.heat_image.setImage(matrix, levels=(0, 1))
        self.heat_image.setRect(QtCore.QRectF(-0.5, -0.5, k, k))
        if k <= LABELLED_STATES:
            ticks = [[(i, config_text(s)) for i, s in enumerate(states)]]
        else:
            ticks = None
        for name in ("left", "bottom"):
            plot.getAxis(name).setTicks(ticks)
        plot.setXRange(-0.5, k - 0.5, padding=0)
        plot.setYRange(-0.5, k - 0.5, padding=0)

