"""The chains inside a DPJ (§4.5, Massaloux): dead ends pruned, classes, restriction, period.

The hand-made chains' answers are worked out in each test's comment from the definitions: a
state is a (u-1)-column (or (v-1)-row) sub-window, a configuration the transition from its left
(top) one to its right (bottom) one; a dead end is a state no configuration leaves.
"""

import numpy as np
import pytest

from texeditor import DPJ, resources
from texeditor.cli import main
from texeditor.errors import InputError
from texeditor.markov.chain import DEAD_END, MAIN, MINOR_CLOSED, TRANSIENT, analyse, period
from texeditor.markov.estimation import estimate_dpj
from texeditor.markov.levels import load_image, quantize


def points(transitions: dict, levels: int) -> DPJ:
    """A u = 2, v = 1 DPJ: one entry per transition (a, b) of the chain on single points."""
    return DPJ(np.array([[[a, b]] for a, b in transitions], np.uint8),
               list(transitions.values()), levels)


def roles_of(d: DPJ) -> dict:
    return {tuple(map(tuple, c)): int(r) for c, r in zip(d.configs, analyse(d).roles)}


def test_a_dead_end_tail_is_pruned_and_the_closed_class_found():
    # {1, 2} cycles (1 -> 1, 1 -> 2, 2 -> 1); 0 leads in; 2 -> 3 -> 4 and 4 goes nowhere:
    # 4 is a dead end, so 3 -> 4 goes; then 3 is one, so 2 -> 3 goes. Without the pruning
    # {1, 2} leaks into the tail and no class is closed.
    d = points({(0, 1): .1, (1, 1): .1, (1, 2): .3, (2, 1): .3, (2, 3): .1, (3, 4): .1}, 5)
    roles = {k[0]: r for k, r in roles_of(d).items()}
    assert roles == {(0, 1): TRANSIENT, (1, 1): MAIN, (1, 2): MAIN, (2, 1): MAIN,
                     (2, 3): DEAD_END, (3, 4): DEAD_END}
    r = d.report()
    assert (r.states, r.closed_classes, r.transient_states, r.dead_ends) == (5, 1, 3, 2)
    kept = d.restrict()
    assert sorted(map(tuple, kept.configs[:, 0])) == [(1, 1), (1, 2), (2, 1)]
    assert np.allclose(kept.probs, np.array([.1, .3, .3]) / .7) and kept.total == pytest.approx(1)
    k = kept.report()
    assert (k.closed_classes, k.transient_states, k.dead_ends) == (1, 0, 0)


def test_a_vertical_dead_end_prunes_and_then_a_horizontal_one_follows():
    # 2x2 windows of G = 2, rows top/bottom. A 00/00, B 01/01, C 10/10 make the horizontal
    # class {col 0/0, col 1/1} (A: 0/0 -> 0/0, B: 0/0 -> 1/1, C: 1/1 -> 0/0).
    # D 01/11: its bottom row 11 is no configuration's top row -> a vertical dead end.
    # E 00/01: column 0/0 -> column 0/1, which only D leaves: once D goes, E is a dead end.
    a, b, c = [[0, 0], [0, 0]], [[0, 1], [0, 1]], [[1, 0], [1, 0]]
    dd, e = [[0, 1], [1, 1]], [[0, 0], [0, 1]]
    d = DPJ(np.array([a, b, c, dd, e], np.uint8), [.3, .25, .25, .1, .1], 2)
    roles = roles_of(d)
    key = lambda m: tuple(map(tuple, m))       # noqa: E731
    assert [roles[key(m)] for m in (a, b, c, dd, e)] == [MAIN, MAIN, MAIN, DEAD_END, DEAD_END]
    kept = d.restrict()
    assert len(kept) == 3 and kept.prob(dd) == 0 and kept.prob(e) == 0
    assert kept.prob(a) == pytest.approx(.3 / .8) and kept.prob(b) == pytest.approx(.25 / .8)


def test_a_column_window_prunes_the_vertical_chain_alone():
    # u = 1: the horizontal chain is one state that always goes on. Vertical chain on points:
    # 0 -> 0, 0 -> 1, 1 -> 0 and 0 -> 2, where 2 starts nothing: a dead end.
    d = DPJ(np.array([[[0], [0]], [[0], [1]], [[1], [0]], [[0], [2]]], np.uint8),
            [.4, .25, .25, .1], 3)
    r = d.report()
    assert (r.states, r.closed_classes, r.dead_ends, r.period) == (1, 1, 1, 1)
    kept = d.restrict()
    assert len(kept) == 3 and kept.prob([[0], [2]]) == 0
    assert kept.prob([[0], [0]]) == pytest.approx(.4 / .9)


def test_small_closed_classes_and_transients_keep_their_roles():
    # {1, 2} (mass .6) and {3} (mass .15) are closed; 0 -> 1 is transient
    d = points({(0, 1): .1, (1, 2): .3, (2, 1): .3, (1, 1): .15, (3, 3): .15}, 4)
    roles = {k[0]: r for k, r in roles_of(d).items()}
    assert roles[(3, 3)] == MINOR_CLOSED and roles[(0, 1)] == TRANSIENT
    assert d.report().closed_classes == 2


def test_every_path_to_a_dead_end_is_said_not_hidden():
    d = points({(0, 1): .5, (1, 2): .5}, 3)
    r = d.report()
    assert r.closed_classes == 0 and r.dead_ends == 2 and r.period == 0
    assert "none" in "\n".join(r.lines())
    with pytest.raises(InputError, match="dead end"):
        d.restrict()


def de_bruijn(k: int, n: int) -> list[int]:
    """A de Bruijn sequence B(k, n) (every n-word over k symbols once, cyclically)."""
    a, seq = [0] * k * n, []

    def db(t, p):
        if t > n:
            if n % p == 0:
                seq.extend(a[1:p + 1])
        else:
            a[t] = a[t - p]
            db(t + 1, p)
            for j in range(a[t - p] + 1, k):
                a[t] = j
                db(t + 1, t)
    db(1, 1)
    return seq


def test_a_long_path_that_ends_is_pruned_whole():
    # B(16, 3) read once, not round: 4,096 distinct triples, each visited once, so its 4,095
    # windows of four points are a path of the horizontal chain with no cycle: all dead ends
    seq = de_bruijn(16, 3)
    seq = np.array(seq + seq[:2], np.uint8)
    d = estimate_dpj(seq[None], (4, 1), 16)
    assert len(d) == 4095
    r = d.report()
    assert (r.states, r.closed_classes, r.dead_ends, r.period) == (4096, 0, 4095, 0)
    # closed into a ring (wrap), it is one cycle of length 4,096: closed, period 4,096
    ring = estimate_dpj(seq[None, :-2], (4, 1), 16, wrap=True).report()
    assert (ring.closed_classes, ring.dead_ends, ring.period) == (1, 0, 4096)


@pytest.mark.parametrize("transitions,expected", [
    ({(0, 1): .5, (1, 0): .5}, 2),                                   # one cycle of length 2
    ({(0, 1): .4, (1, 0): .4, (0, 0): .2}, 1),                       # a loop of length 1 too
    ({(0, 1): 1 / 3, (1, 2): 1 / 3, (2, 0): 1 / 3}, 3),              # one cycle of length 3
    # 0 -> 1 -> 0 (length 2) and 0 -> 1 -> 2 -> 3 -> 0 (length 4): gcd 2
    ({(0, 1): .3, (1, 0): .2, (1, 2): .1, (2, 3): .2, (3, 0): .2}, 2),
    # lengths 2 and 3 (0 -> 1 -> 0, 0 -> 1 -> 2 -> 0): gcd 1, aperiodic without a loop
    ({(0, 1): .4, (1, 0): .2, (1, 2): .2, (2, 0): .2}, 1),
])
def test_the_period_of_the_main_class(transitions, expected):
    d = points(transitions, 4)
    r = d.report()
    assert r.period == expected and r.closed_classes == 1
    text = "\n".join(r.lines())
    assert ("PERIODIC, period 2" in text) == (expected == 2)
    assert ("aperiodic" in text) == (expected == 1)


def test_period_of_transitions_directly():
    assert period(np.array([0, 1, 2, 3]), np.array([1, 2, 3, 0])) == 4
    assert period(np.array([]), np.array([])) == 0


def test_dpj_info_flags_a_periodic_chain(tmp_path, capsys):
    path = tmp_path / "beat.dpj"
    points({(0, 1): .5, (1, 0): .5}, 2).save(path)
    assert main(["dpj-info", str(path)]) == 0
    assert "PERIODIC, period 2" in capsys.readouterr().out
    assert main(["dpj-info", str(path), "--json"]) == 0
    out = capsys.readouterr().out
    assert '"period": 2' in out and '"dead_ends": 0' in out


@pytest.mark.parametrize("levels", [4, 8])
@pytest.mark.parametrize("method", ["band", "lloyd"])
@pytest.mark.parametrize("photo", resources.sample_images(), ids=lambda p: p.stem)
def test_a_bundled_photo_without_wrap_has_one_closed_class_holding_the_mass(photo, method,
                                                                            levels):
    """Issue 21.1: the right and bottom borders' dead ends made every state transient. One
    restriction keeps the main closed class (>= 99 % of the mass); it may uncover a few dead
    ends below (rows whose continuation was in what it dropped), which restricting again
    removes, until nothing changes."""
    q = quantize(load_image(photo), levels, method)
    d = estimate_dpj(q.levels, (3, 3), levels, wrap=False)
    r = d.report()
    assert r.closed_classes == 1 and r.period == 1
    kept = d.restrict()
    assert d.probs[np.isin(d.codes, kept.codes)].sum() >= 0.99
    k = kept.report()
    assert k.closed_classes == 1 and k.dead_ends <= len(kept) // 500
    for _ in range(5):
        again = kept.restrict()
        if len(again) == len(kept):
            break
        kept = again
    k = kept.report()
    assert (k.closed_classes, k.transient_states, k.dead_ends, k.period) == (1, 0, 0, 1)
    assert np.array_equal(kept.restrict().codes, kept.codes)
    assert d.probs[np.isin(d.codes, kept.codes)].sum() >= 0.985
