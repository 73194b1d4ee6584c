"""Peano sub-regions (thesis §3.3.3a, Fig. 3.5–3.6): the canvas cut into cells listed along a
Hilbert scan, and the dominance expressions that give those cells their luminosity.

The user types ``6:7(2(1,2(2,3)),6:7(4,5,6:7(6,7),8))``: numbers are sub-regions in scan order
(1 = the first cell of the scan), ``X(...)`` says X is brighter than everything listed inside
(X may be listed too, as the thesis writes ``Lj(L1, …, Lj, …, Ln)``), ``a:b`` says a and b are
equally bright, and groups nest. The expression is also a tree. ``assign_levels`` turns it into
levels that satisfy every relation; the PeanoLevels action writes them into the cells.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from ..errors import InputError

MAX_EXPRESSION = 4000
MAX_CELLS = 2**22

__all__ = ["hilbert_cells", "scan_order", "Node", "DominanceError", "parse_dominance",
           "dominance_ranks", "assign_levels", "cell_grid", "cell_boxes"]


# -- the scan -------------------------------------------------------------------------------------

def hilbert_cells(rows: int, cols: int):
    """Yield every (row, col) of a rows × cols grid once, along a Hilbert curve.

    Any rectangle works (the generalised curve of J. Červený's "gilbert"): consecutive cells
    are neighbours, except for one diagonal step in some grids with odd sides; on a 2^k square
    it is the classical Hilbert curve, starting at the top-left cell.

    >>> list(hilbert_cells(2, 2))
    [(0, 0), (1, 0), (1, 1), (0, 1)]
    """
    for r, c in scan_order(rows, cols):
        yield int(r), int(c)


def scan_order(rows: int, cols: int, limit: int | None = None) -> np.ndarray:
    """The (row, col) of the grid's cells in scan order, as an (n, 2) int array (the first
    ``limit`` only, when given: an expression rarely names more than a few cells)."""
    if rows * cols > MAX_CELLS:
        raise InputError(f"{cols}×{rows} cells are too many for a scan (at most {MAX_CELLS}): "
                         f"choose larger cells")
    if rows < 1 or cols < 1:
        return np.empty((0, 2), np.int64)
    n = rows * cols if limit is None else max(0, min(limit, rows * cols))
    cells = np.empty((n, 2), np.int64)
    frame = (0, 0, cols, 0, 0, rows) if cols >= rows else (0, 0, 0, rows, cols, 0)
    _gilbert(cells, np.array(frame, np.int64))
    return cells


@njit(cache=True)
def _sign(v):
    return (v > 0) - (v < 0)


@njit(cache=True)
def _gilbert(cells, first):
    """Fill ``cells`` along the curve of the rectangle at (x, y) spanned by the major axis
    (ax, ay) and the minor (bx, by) — ``first`` — until it is full. A stack of rectangles
    still to fill stands for the recursion of the published curve, children pushed last
    first so they come off in the curve's order."""
    stack = np.empty((256, 6), np.int64)
    stack[0] = first
    top, k, n = 1, 0, len(cells)
    while top and k < n:
        top -= 1
        x, y, ax, ay, bx, by = stack[top]
        w, h = abs(ax + ay), abs(bx + by)
        dax, day, dbx, dby = _sign(ax), _sign(ay), _sign(bx), _sign(by)
        if h == 1 or w == 1:
            dx, dy, m = (dax, day, w) if h == 1 else (dbx, dby, h)
            for _ in range(m):
                if k == n:
                    break
                cells[k, 0], cells[k, 1] = y, x
                k += 1
                x, y = x + dx, y + dy
            continue
        ax2, ay2, bx2, by2 = ax // 2, ay // 2, bx // 2, by // 2
        w2, h2 = abs(ax2 + ay2), abs(bx2 + by2)
        if 2 * w > 3 * h:                 # a long rectangle: two halves along the major axis
            if w2 % 2 and w > 2:
                ax2, ay2 = ax2 + dax, ay2 + day
            stack[top] = (x + ax2, y + ay2, ax - ax2, ay - ay2, bx, by)
            stack[top + 1] = (x, y, ax2, ay2, bx, by)
            top += 2
        else:                             # up the minor axis, across, and back down
            if h2 % 2 and h > 2:
                bx2, by2 = bx2 + dbx, by2 + dby
            stack[top] = (x + (ax - dax) + (bx2 - dbx), y + (ay - day) + (by2 - dby),
                          -bx2, -by2, -(ax - ax2), -(ay - ay2))
            stack[top + 1] = (x + bx2, y + by2, ax, ay, bx - bx2, by - by2)
            stack[top + 2] = (x, y, bx2, by2, ax2, ay2)
            top += 3


def cell_grid(shape, cell: int, top: int = 0, left: int = 0, down: int | None = None,
              across: int | None = None) -> tuple[int, int]:
    """How many cells (down, across) a cut of ``cell``-point cells starting at (top, left)
    has; by default enough to reach the canvas's bottom and right edges."""
    h, w = shape
    if cell < 1:
        raise InputError(f"a cell is at least 1 point wide, got {cell}")
    if not (0 <= top < h and 0 <= left < w):
        raise InputError(f"the cells start at ({top}, {left}), outside the {w}×{h} canvas")
    down = math.ceil((h - top) / cell) if down is None else down
    across = math.ceil((w - left) / cell) if across is None else across
    if down < 1 or across < 1:
        raise InputError("the cut needs at least one cell down and one across")
    return down, across


def cell_boxes(order: np.ndarray, cell: int, top: int, left: int, shape) -> np.ndarray:
    """(top, left, bottom, right) of each cell of a scan, clipped to the canvas (may be empty)."""
    h, w = shape
    t = top + order[:, 0] * cell
    l_ = left + order[:, 1] * cell
    boxes = np.stack([t, l_, t + cell, l_ + cell], axis=1)
    boxes[:, 0::2] = boxes[:, 0::2].clip(0, h)
    boxes[:, 1::2] = boxes[:, 1::2].clip(0, w)
    return boxes


# -- dominance expressions ------------------------------------------------------------------------

@dataclass
class Node:
    """One group of a dominance expression: its head (sub-regions of equal luminosity, the
    brightest of the group) and the items it dominates; a bare number is a Node without items.
    ``position`` is the head's first character in the text (for error messages and the tree)."""

    head: tuple[int, ...]
    items: list["Node"] = field(default_factory=list)
    position: int = 0

    def __str__(self) -> str:
        head = ":".join(str(i) for i in self.head)
        return head + (f"({','.join(str(n) for n in self.items)})" if self.items else "")

    def walk(self):
        yield self
        for item in self.items:
            yield from item.walk()

    def regions(self) -> set[int]:
        return {i for node in self.walk() for i in node.head}


class DominanceError(InputError):
    """A malformed or contradictory expression; ``position`` points at the offending character."""

    def __init__(self, text: str, position: int, problem: str):
        self.text, self.position, self.problem = text, position, problem
        caret = " " * position + "^"
        super().__init__(f"{problem} (character {position + 1}):\n{text}\n{caret}")


class _Parser:
    """expression := group ; group := head ['(' group {',' group} ')'] ; head := n {':' n}"""

    def __init__(self, text: str):
        self.text, self.pos = text, 0

    def fail(self, problem: str, position: int | None = None):
        raise DominanceError(self.text, self.pos if position is None else position, problem)

    def peek(self) -> str:
        while self.pos < len(self.text) and self.text[self.pos] in " \t":
            self.pos += 1
        return self.text[self.pos] if self.pos < len(self.text) else ""

    def number(self) -> int:
        if not self.peek().isdecimal():     # what int() reads; isdigit() also takes "²"
            what = "the end" if not self.peek() else repr(self.peek())
            self.fail(f"a sub-region number was expected, found {what}")
        start = self.pos
        while self.pos < len(self.text) and self.text[self.pos].isdecimal():
            self.pos += 1
        value = int(self.text[start:self.pos])
        if value < 1:
            self.fail("sub-regions are numbered from 1 along the scan", start)
        if value > MAX_CELLS:
            self.fail(f"sub-region {value} is beyond any scan ({MAX_CELLS} cells at most)", start)
        return value

    def group(self, depth: int = 0) -> Node:
        if depth > 200:
            self.fail("the groups are nested too deeply")
        self.peek()
        start = self.pos
        head = [self.number()]
        while self.peek() == ":":
            self.pos += 1
            head.append(self.number())
        node = Node(tuple(dict.fromkeys(head)), [], start)
        if self.peek() == "(":
            opening = self.pos
            self.pos += 1
            node.items.append(self.group(depth + 1))
            while self.peek() == ",":
                self.pos += 1
                node.items.append(self.group(depth + 1))
            if self.peek() != ")":
                if not self.peek():
                    self.fail(f"')' missing: the '(' at character {opening + 1} is never closed")
                self.fail(f"',' or ')' was expected, found {self.peek()!r}")
            self.pos += 1
        return node

    def parse(self) -> Node:
        if not self.peek():
            self.fail("the expression is empty")
        node = self.group()
        if self.peek():
            problem = "unbalanced ')'" if self.peek() == ")" else \
                f"the expression should end here, found {self.peek()!r}"
            self.fail(problem)
        return node


def parse_dominance(text: str) -> Node:
    """The tree of a dominance expression; a malformed one is a DominanceError whose message
    points at the offending character.

    >>> str(parse_dominance("6 : 7 (2 (1, 2(2,3)), 8)"))
    '6:7(2(1,2(2,3)),8)'
    """
    if not isinstance(text, str):
        raise InputError("a dominance expression is a text")
    if len(text) > MAX_EXPRESSION:
        raise DominanceError(text[:60], 60, f"the expression is longer than {MAX_EXPRESSION} "
                                            f"characters")
    return _Parser(text).parse()


def dominance_ranks(tree: Node, text: str = "") -> dict[int, int]:
    """Each sub-region's rank: 0 for those that dominate nothing, else one more than the
    highest rank they dominate (the lowest ranks satisfying every relation).

    Equal heads (``a:b``) share a rank; a head listed inside its own group (``2(2,3)``) is not
    below itself; a contradiction (``1(2(1))``, ``1:2(3(2))``) is a DominanceError.

    >>> dominance_ranks(parse_dominance("6:7(2(1,2(2,3)),6:7(4,5,6:7(6,7),8))"))
    {1: 0, 2: 1, 3: 0, 4: 0, 5: 0, 6: 2, 7: 2, 8: 0}
    """
    text = text or str(tree)
    parent = {i: i for i in tree.regions()}

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for node in tree.walk():                         # a:b, and a head listed in its own group
        for i in node.head[1:]:
            parent[find(i)] = find(node.head[0])
    below: dict[int, set[int]] = {}
    where: dict[tuple[int, int], int] = {}
    for node in tree.walk():
        top = find(node.head[0])
        for item in node.items:
            if find(item.head[0]) == top:
                continue                             # the group's head listed among its items
            for sub in item.walk():
                for i in sub.head:
                    below.setdefault(top, set()).add(find(i))
                    where.setdefault((top, find(i)), sub.position)
    for (a, b), pos in where.items():
        if a == b:
            raise DominanceError(text, pos, f"sub-region {b} is listed inside a group it heads "
                                            f"(or equals): it cannot be brighter than itself")
    ranks: dict[int, int] = {}
    for c in sorted({find(i) for i in parent}):
        if c not in ranks:
            _rank(c, below, where, ranks, text)
    return {i: ranks[find(i)] for i in sorted(parent)}


def _rank(start: int, below: dict, where: dict, ranks: dict, text: str) -> None:
    """Depth-first ranks of the classes under ``start`` (iterative: chains may be long)."""
    visiting = {start}
    stack = [(start, iter(sorted(below.get(start, ()))))]
    while stack:
        node, children = stack[-1]
        for child in children:
            if child in visiting:
                raise DominanceError(text, where[(node, child)],
                                     "these relations contradict each other: a sub-region "
                                     "would be brighter than itself")
            if child not in ranks:
                visiting.add(child)
                stack.append((child, iter(sorted(below.get(child, ())))))
                break
        else:
            stack.pop()
            visiting.discard(node)
            ranks[node] = 1 + max((ranks[k] for k in below.get(node, ())), default=-1)


def assign_levels(tree: Node | str, low: int = 1, high: int = 7) -> dict[int, int]:
    """Sub-region → level, spreading the ranks evenly from ``low`` (the dimmest) to ``high``
    (the brightest), so every relation of the expression holds with as much contrast as the
    levels allow.

    >>> assign_levels("6:7(2(1,2(2,3)),6:7(4,5,6:7(6,7),8))", 1, 3)
    {1: 1, 2: 2, 3: 1, 4: 1, 5: 1, 6: 3, 7: 3, 8: 1}
    """
    text = tree if isinstance(tree, str) else ""
    tree = parse_dominance(tree) if isinstance(tree, str) else tree
    if not 0 <= low <= high:
        raise InputError(f"the levels run from low to high: got low {low}, high {high}")
    ranks = dominance_ranks(tree, text)
    top = max(ranks.values())
    if top > high - low:
        raise InputError(f"the expression has {top + 1} degrees of luminosity but levels "
                         f"{low}..{high} give only {high - low + 1}: use more levels")
    if top == 0:
        return {i: high for i in ranks}
    return {i: low + math.floor(r * (high - low) / top + 0.5) for i, r in ranks.items()}
