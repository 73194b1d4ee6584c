"""Level shares kept on course while a field is drawn: its law tilted band by band.

A field drawn from a DPJ comes out with level shares off the DPJ's, the same way seed after
seed: a coarse scale's wide window over a small photo reduction settles on shares of its own
(coffee's coarsest at 512²: 0.07–0.12 off), and a scale drawn given synthetic parents favours
some levels over the photo's law given the same parents (chelsea: 0.03–0.05 off; coins, at
1024²: 0.09–0.10). Drafts (markov.particles) only choose among draws, and moving region borders
afterwards (markov.balance) costs a second at 2048². Here the rows are drawn in bands of about
BAND_POINTS points; after each band the share of every level among the points over each parent
level is compared with its aim, and the next band is drawn from the law tilted by
exp(λ[parent, level]) on each window's last point (a window's weight: the rows' law given the
rows above stays exact for the tilted law, and no window leaves the DPJ). λ moves slowly (GAIN,
and at most STEP a band): a field whose levels come and go over long stretches (coffee's dark
patches) is otherwise chased into horizontal stripes, its tilt swinging from band to band.

The aim of a level given its parent is the photo's (the DPJ's share of the level over that
parent) times a factor per level, the same for every parent, chosen so the aims over this
field's parents add up to the DPJ's level shares: the parents' own drift is made up too.

A field of BAND_POINTS points or fewer is one band, never tilted: it relies on the drafts. Small
fields steered closely (16 bands each aimed at what the rows left must hold, λ 3× as fast) did
keep photos of large regions at their shares (a logo, a retina: 0.06–0.11 off → 0.01–0.02 at
512²), but drew scene photos in horizontal bands (the spread of level shares over blocks of rows
against blocks of columns, 23 photos: 0.90 → 1.19; a rocket 0.41 → 1.29), and a constant tilt
fitted on a trial draw flips such fields from one level to another: neither was kept. More
drafts of small scales do it without bands (markov.particles.drafts_for).
"""

from __future__ import annotations

import numpy as np

BAND_POINTS = 8192   # a steered field is drawn in bands of about this many points, and of at
BAND_ROWS = 8        # least this many rows (each band is a call of the kernels, which costs
                     # a 2048-wide band about 0.1 ms: 4-row bands made its draw 10 % slower)
GAIN = 0.1           # λ moves by this times the log ratio of aim to the band's share ...
STEP = 0.03          # ... by at most this a band ...
REACH = 3.0          # ... and stays within ±REACH
PRIOR = 2            # a band's share of a level over a parent: with this many points at its aim
HALF_WEIGHT = 300    # a parent level over this many points of a band moves λ half as far as
                     # one over many
FLOOR = 0.005        # shares compared in logs from this floor (a level absent under a parent
                     # is not pushed without end)
FIT_ROUNDS = 200     # rounds fitting the factor per level (the aims' sum)


def band_rows(width: int) -> int:
    """The rows of a band of a steered field this wide."""
    return max(BAND_ROWS, -(-BAND_POINTS // width))


class Steering:
    """The tilt of one field's law, moved band by band towards the aims (see the module)."""

    def __init__(self, entry_parent: np.ndarray, entry_level: np.ndarray, aims: np.ndarray,
                 seen: np.ndarray):
        self.entry = entry_parent * aims.shape[1] + entry_level   # each entry's place in tilt
        self.aims = aims                  # (parent levels, G): each level's aim over a parent
        self.seen = seen                  # (parent levels,): the DPJ has points over it
        self.tilt = np.zeros_like(aims)

    def tilted(self, fent: np.ndarray) -> np.ndarray:
        """The kernels' entry weights (q, m) with every entry's last point tilted."""
        return fent * np.exp(self.tilt).ravel().take(self.entry)

    def update(self, composite: np.ndarray) -> None:
        """Move the tilt after a band of rows (``composite``: parent · G + level)."""
        counts = np.bincount(composite.ravel(), minlength=self.aims.size)[: self.aims.size]
        counts = counts.reshape(self.aims.shape).astype(float)
        points = counts.sum(axis=1, keepdims=True)
        share = (counts + PRIOR * self.aims) / (points + PRIOR)
        weight = points / (points + HALF_WEIGHT) * self.seen[:, None]
        step = GAIN * weight * (np.log(self.aims + FLOOR) - np.log(share + FLOOR))
        self.tilt = np.clip(self.tilt + np.clip(step, -STEP, STEP), -REACH, REACH)


def steering(tables, shares, parents: np.ndarray | None) -> Steering:
    """A Steering for a field drawn from kernel ``tables`` (markov.synthesis) towards the level
    ``shares``; ``parents``: the field's parent levels (None: a field without parents)."""
    gp, gx = tables.gp, tables.gx
    code, start, end = tables.ctx
    entry_parent = np.repeat(code % gp, end - start)     # a context ends with the bottom row's
    entry_level = tables.ient[2] % gx                     # parents, the last point's last
    shares = np.asarray(shares, float)
    if gp == 1:
        return Steering(entry_parent, entry_level, shares[None, :], np.ones(1))
    joint = np.bincount(tables.first_configs[:, -1, -1], weights=tables.first_q,
                        minlength=gp * gx)[: gp * gx].reshape(gp, gx)
    seen = joint.sum(axis=1) > 0
    law = np.where(seen[:, None], joint, 1.0)
    law = law / law.sum(axis=1, keepdims=True)
    field = np.bincount(parents.ravel(), minlength=gp)[:gp] / parents.size
    return Steering(entry_parent, entry_level, _fitted(law, field, shares), seen)


def _fitted(law: np.ndarray, field: np.ndarray, shares: np.ndarray) -> np.ndarray:
    """law(level | parent) times a factor per level, so that over the ``field``'s parent shares
    the levels' shares are ``shares`` (as near as the law allows)."""
    factor = np.zeros(len(shares))
    for _ in range(FIT_ROUNDS):
        aims = law * np.exp(factor)
        aims /= aims.sum(axis=1, keepdims=True)
        step = np.log(shares + 1e-9) - np.log(field @ aims + 1e-9)
        if np.abs(step).max() < 1e-4:
            break
        factor = np.clip(factor + step, -10.0, 10.0)
    return aims
