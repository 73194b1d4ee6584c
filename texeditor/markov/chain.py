"""The Markov chains inside a DPJ (thesis §4.4–4.5, Massaloux): dead ends, classes, period.

It sits between the DPJ and everything that judges or restricts one (its report, the DPJ
editor's Chain column, ``dpj-info``, Restrict). The horizontal chain's states are the (u-1)-column
sub-windows, each configuration a transition from its left one to its right one; the vertical
chain's are the (v-1)-row sub-windows, top to bottom. A DPJ estimated without wrap has *dead
ends*: a right (or bottom) sub-window seen only at the photo's border, which no configuration
continues. They are pruned first, repeatedly (pruning one may make another), so that the
horizontal chain keeps its closed classes; Massaloux's restriction then keeps the main one.

A small chain on single points (u = 2, v = 1): {1, 2} cycles, 0 leads into it, 3 is a dead end.

>>> from texeditor.markov.dpj import DPJ
>>> d = DPJ(np.array([[[0, 1]], [[1, 2]], [[2, 1]], [[2, 3]]], np.uint8), [.1, .4, .4, .1], 4)
>>> c = analyse(d)
>>> [ROLE_NAMES[r] for r in c.roles]
['transient', 'main class', 'main class', 'dead end']
>>> c.states, c.closed_classes, c.transient_states, c.period
(4, 1, 2, 2)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy        # scipy.sparse loads on first use, not at start-up

# the role of an entry in the horizontal chain
MAIN, TRANSIENT, MINOR_CLOSED, DEAD_END = 0, 1, 2, 3
ROLE_NAMES = {MAIN: "main class", TRANSIENT: "transient", MINOR_CLOSED: "small closed class",
              DEAD_END: "dead end"}


@dataclass(frozen=True)
class Chain:
    """The horizontal chain of a DPJ once its dead ends are pruned.

    ``roles``: each entry's role — MAIN (kept by the restriction), DEAD_END (pruned: it leads, to
    the right or below, where no configuration continues), TRANSIENT (its left sub-window is in
    no closed class) or MINOR_CLOSED (in a closed class carrying less probability than the main
    one). ``period``: the main class's period (1: aperiodic, 0: no closed class); the thesis asks
    for one irreducible aperiodic class (§4.5).
    """

    states: int
    closed_classes: int
    transient_states: int
    roles: np.ndarray
    period: int

    @property
    def dead_ends(self) -> int:
        return int(np.count_nonzero(self.roles == DEAD_END))

    @property
    def kept(self) -> np.ndarray:
        """The entries Massaloux's restriction keeps: the main closed class."""
        return self.roles == MAIN


def analyse(dpj) -> Chain:
    """The horizontal chain's classes after the dead ends of both chains are pruned."""
    n = len(dpj)
    if not n:
        return Chain(0, 0, 0, np.zeros(0, np.int8), 0)
    (left, right), (top, bottom) = dpj.horizontal_states(), dpj.vertical_states()
    live = prune_dead_ends(np.ones(n, bool), [(left, right), (top, bottom)])
    states, ids = np.unique(np.concatenate([left, right]), return_inverse=True)
    ids = ids.ravel()
    li, ri = ids[:n], ids[n:]
    label, closed = _closed_classes(li[live], ri[live], len(states))
    roles = np.full(n, DEAD_END, np.int8)
    if not len(closed):
        return Chain(len(states), 0, len(states), roles, 0)
    mass = np.bincount(label[li[live]], weights=dpj.probs[live], minlength=label.max() + 1)
    main = closed[np.argmax(mass[closed])]
    in_closed = np.isin(label[li], closed)
    roles[live & ~in_closed] = TRANSIENT
    roles[live & in_closed] = MINOR_CLOSED
    roles[live & (label[li] == main)] = MAIN
    inside = roles == MAIN
    return Chain(len(states), len(closed), int(np.count_nonzero(~np.isin(label, closed))),
                 roles, period(li[inside], ri[inside]))


def prune_dead_ends(keep: np.ndarray, chains) -> np.ndarray:
    """``keep`` without the entries that lead to a dead end of any of the ``chains`` ((from, to)
    codes per entry): entries after which every path of kept entries ends. Pruning one chain can
    leave the other a new dead end, so the chains take turns until neither changes."""
    keep = keep.copy()
    changed = True
    while changed and keep.any():
        changed = False
        for a, b in chains:
            endless = _endless(a[keep], b[keep])
            if not endless.all():
                keep[np.flatnonzero(keep)[~endless]] = False
                changed = True
    return keep


def _endless(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """For each transition a → b, whether a path can go on from b for ever: b reaches a cycle.
    One pass (linear in the transitions), however long the tails that end: the states on a cycle
    are those of a strongly connected class with a transition inside, and the states that reach
    them are found by one breadth-first search backwards from a node joined to all of them."""
    if not len(a):
        return np.zeros(0, bool)
    states, ids = np.unique(np.concatenate([a, b]), return_inverse=True)
    ids = ids.ravel()
    k, m = len(a), len(states)
    ai, bi = ids[:k], ids[k:]
    label, _ = _closed_classes(ai, bi, m)
    cyclic = np.zeros(label.max() + 1, bool)
    cyclic[label[ai][label[ai] == label[bi]]] = True
    roots = np.flatnonzero(cyclic[label])
    back = scipy.sparse.coo_matrix(                  # b → a, and the extra node m → every root
        (np.ones(k + len(roots)), (np.r_[bi, np.full(len(roots), m)], np.r_[ai, roots])),
        shape=(m + 1, m + 1)).tocsr()
    reach = np.zeros(m + 1, bool)
    reach[scipy.sparse.csgraph.breadth_first_order(back, m, return_predecessors=False)] = True
    return reach[bi]


def _closed_classes(li: np.ndarray, ri: np.ndarray, m: int) -> tuple[np.ndarray, np.ndarray]:
    """Strongly connected class of each of ``m`` states, and the ids of the closed ones: at least
    one transition inside, none leaving."""
    graph = scipy.sparse.coo_matrix((np.ones(len(li)), (li, ri)), shape=(m, m)).tocsr()
    _, label = scipy.sparse.csgraph.connected_components(graph, directed=True, connection="strong")
    leaves = label[li] != label[ri]
    k = label.max() + 1
    inside = np.bincount(label[li][~leaves], minlength=k) > 0
    leaking = np.bincount(label[li][leaves], minlength=k) > 0
    return label, np.flatnonzero(inside & ~leaking)


def period(li: np.ndarray, ri: np.ndarray) -> int:
    """The period of an irreducible chain given as its transitions (from, to state ids): the gcd
    of its cycle lengths, found as the gcd of depth(a) + 1 - depth(b) over its transitions a → b,
    depths being breadth-first levels from any state. 0 for a chain without transitions.

    >>> period(np.array([0, 1, 2]), np.array([1, 2, 0])), period(np.array([0, 1, 1]), np.array([1, 0, 1]))
    (3, 1)
    """
    if not len(li):
        return 0
    states, ids = np.unique(np.concatenate([li, ri]), return_inverse=True)
    ids = ids.ravel()
    a, b = ids[:len(li)], ids[len(li):]
    m = len(states)
    graph = scipy.sparse.coo_matrix((np.ones(len(a)), (a, b)), shape=(m, m)).tocsr()
    depth = scipy.sparse.csgraph.shortest_path(graph, unweighted=True, indices=int(a[0]))
    return int(np.gcd.reduce(np.abs(depth[a] + 1 - depth[b]).astype(np.int64)))
