"""Dominance trees placed on screen (thesis §3.3.3a, Fig. 3.6): vertices pointed anywhere on the
canvas, each carrying a grain, joined into a tree whose every vertex is brighter than the
vertices under it.

This is the tree form of a dominance expression (`peano`): the expression names vertices
(numbered from 1 in the order they were placed) instead of Peano sub-regions, ``1(2(4),3)`` for a
root 1 with children 2 and 3, and 4 under 2. The levels come from `peano.assign_levels`, and the
grains are drawn dominated first, so where grains overlap the brighter one lies on top. Several
trees are several DominanceTree actions, placed anywhere and mixed on one canvas.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .brushes import last_wins
from .grains import GrainType, stamp_points
from .peano import Node, assign_levels, dominance_ranks, parse_dominance

MAX_VERTICES = 4096
MAX_DEPTH = 200                  # the deepest nesting a dominance expression may have

__all__ = ["MAX_VERTICES", "tree_expression", "vertex_tree", "vertex_levels", "draw_tree"]


def tree_expression(parents) -> str:
    """The dominance expression of a tree given by each vertex's parent (-1 for the root), the
    vertices numbered from 1 in the order given; a parent comes before its children.

    >>> tree_expression([-1, 0, 0, 1])
    '1(2(4),3)'
    """
    parents = [int(p) for p in parents]
    if not parents or parents[0] != -1 or -1 in parents[1:]:
        raise InputError("a tree has one root, its first vertex")
    children: list[list[int]] = [[] for _ in parents]
    depth = [0] * len(parents)
    for i, p in enumerate(parents[1:], start=1):
        if not 0 <= p < i:
            raise InputError(f"vertex {i + 1}'s parent must be a vertex placed before it")
        children[p].append(i)
        depth[i] = depth[p] + 1
    if max(depth) > MAX_DEPTH:
        raise InputError(f"a tree is at most {MAX_DEPTH} vertices deep")

    def text(i: int) -> str:
        inside = ",".join(text(k) for k in children[i])
        return f"{i + 1}({inside})" if inside else str(i + 1)
    return text(0)


def vertex_tree(expression: str, count: int) -> Node:
    """The tree of an expression over ``count`` vertices, which must name each of 1..count once
    (a vertex is one place on screen: it cannot be under itself or in two groups)."""
    tree = parse_dominance(expression)
    named = sorted(i for node in tree.walk() for i in node.head)
    if named != list(range(1, count + 1)):
        raise InputError(f"the tree must name each of its {count} vertices (1..{count}) once, "
                         f"got {expression[:60]!r}")
    return tree


def vertex_levels(expression: str, count: int, low: int, high: int):
    """Each vertex's level (from ``low``, the dimmest, to ``high``) and rank (0: it dominates
    nothing), in vertex order.

    >>> vertex_levels("1(2(4),3)", 4, 1, 3)
    ([3, 2, 1, 1], [2, 1, 0, 0])
    """
    ranks = dominance_ranks(vertex_tree(expression, count), expression)
    levels = assign_levels(expression, low, high)
    return [levels[i] for i in sorted(ranks)], [ranks[i] for i in sorted(ranks)]


def draw_tree(canvas_shape, points, grains: list[GrainType], levels, ranks, *,
              wrap: bool = False):
    """(rows, cols, values) of a tree's grains on the canvas, each point once: every grain
    placed by its centre of gravity at its vertex with its vertex's level, the dominated ones
    first so that a dominant grain covers those it overlaps (equal ranks: later vertices on top).
    """
    drawn = sorted(range(len(points)), key=lambda i: (ranks[i], i))
    rows, cols, values = [], [], []
    for i in drawn:
        r, c, _ = stamp_points(grains[i].mask(), points[i], canvas_shape, wrap=wrap)
        rows.append(r)
        cols.append(c)
        values.append(np.full(len(r), levels[i], np.uint8))
    return last_wins(np.concatenate(rows), np.concatenate(cols), np.concatenate(values),
                     canvas_shape)
