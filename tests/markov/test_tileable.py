"""Tileable synthesis: the Markov process drawn on the torus, so a texture repeats without a seam
(each row closed across the side seam, each column across the bottom one, with the DPJ's own
law; nothing blended)."""

import numpy as np
import pytest
import skimage as ski

from texeditor import DPJ, quantize, synthesize
from texeditor.errors import InputError
from texeditor.markov import multiscale
from texeditor.markov.multiscale import SCALES_CLOSURE, SEAMS, estimate_scales, synthesize_scales
from texeditor.markov.synthesis import CLOSURE
from texeditor.photo import acquire_model
from texeditor.photo.tone import context_codes
from tests.support.torus import off_places, off_the_dpj, photo_dpj, window_codes, window_tv


def random_dpj(seed, g=3):
    """A hand-made 2×2 DPJ over every configuration: a torus always closes."""
    rng = np.random.default_rng(seed)
    configs = np.array(np.meshgrid(*[range(g)] * 4, indexing="ij")).reshape(4, -1).T
    q = rng.random(len(configs)) ** 3 + 1e-3
    return DPJ(configs.reshape(-1, 2, 2).astype(np.uint8), q / q.sum(), g)


@pytest.mark.parametrize("name", ["brick", "grass", "gravel"])
@pytest.mark.parametrize("shape", [(64, 96), (37, 53)])
def test_two_by_two_photo_dpjs_tile_without_a_window_they_lack(name, shape):
    dpj = photo_dpj(name, (2, 2))
    for seed in range(3):
        levels = synthesize(dpj, shape, seed=seed, tileable=True).levels
        assert levels.shape == shape
        assert off_the_dpj(levels, dpj) == 0.0


def test_a_hand_made_dpj_tiles_and_the_same_seed_gives_the_same_texture():
    dpj = random_dpj(1)
    a = synthesize(dpj, (30, 41), seed=5, tileable=True).levels
    assert off_the_dpj(a, dpj) == 0.0
    assert np.array_equal(a, synthesize(dpj, (30, 41), seed=5, tileable=True).levels)
    assert not np.array_equal(a, synthesize(dpj, (30, 41), seed=5).levels)


@pytest.mark.parametrize("name", ["brick", "grass", "gravel"])
def test_three_by_three_photo_dpjs_leave_far_fewer_windows_across_the_seams(name):
    """A plain draw leaves 0.1–0.3 % of its torus windows outside the DPJ (all along its
    seams); a tileable one far fewer (rows or columns whose end found no way back)."""
    dpj = photo_dpj(name, (3, 3))
    plain = off_the_dpj(synthesize(dpj, (256, 256), seed=2).levels, dpj)
    tiled = off_the_dpj(synthesize(dpj, (256, 256), seed=2, tileable=True).levels, dpj)
    assert tiled < plain / 2


@pytest.mark.parametrize("name", ["brick", "grass", "gravel"])
def test_closure_2_keeps_the_issue_target_on_three_by_three_photo_dpjs(name):
    """≤ 0.05 % of the torus windows outside the DPJ over four seeds (closure 1 left 0.06 % on
    brick and 0.12 % on grass: windows an earlier column's redraw broke, and the corner)."""
    dpj = photo_dpj(name, (3, 3))
    shares = [off_the_dpj(synthesize(dpj, (256, 256), seed=s, tileable=True).levels, dpj)
              for s in range(4)]
    assert np.mean(shares) <= 0.0005


def test_closure_2_closes_the_corner_where_closure_1_did_not():
    """Brick's 2×2 DPJ, seed 4 at 256²: closure 1 left two windows across the corner outside
    the DPJ; closure 2 draws the last column given the first ones after it too."""
    dpj = photo_dpj("brick", (2, 2))
    old = synthesize(dpj, (256, 256), seed=4, tileable=True, closure=1).levels
    new = synthesize(dpj, (256, 256), seed=4, tileable=True).levels
    assert off_the_dpj(old, dpj) > 0.0
    assert off_the_dpj(new, dpj) == 0.0


def test_a_hand_made_dpj_without_plain_blocks_closes_both_seams_exactly():
    """2 levels, every 2×2 window but the two of one level: on an odd torus (23×31) closure 1
    left windows across the seams outside it for some seeds, closure 2 for none."""
    configs = [c for c in np.ndindex(2, 2, 2, 2) if len(set(c)) > 1]
    arr = np.array(configs, np.uint8).reshape(-1, 2, 2)
    dpj = DPJ(arr, np.full(len(arr), 1 / len(arr)), 2)
    old = [off_the_dpj(synthesize(dpj, (23, 31), seed=s, tileable=True, closure=1).levels, dpj)
           for s in range(12)]
    new = [off_the_dpj(synthesize(dpj, (23, 31), seed=s, tileable=True).levels, dpj)
           for s in range(12)]
    assert max(old) > 0.0
    assert max(new) == 0.0


def test_closure_1_still_draws_what_it_drew():
    """Recipes that recorded the first closure replay the same: its textures are fixed by their
    hashes (taken before closure 2 existed)."""
    import hashlib
    dpj = photo_dpj("gravel", (3, 3))
    got = hashlib.sha256(synthesize(dpj, (97, 130), seed=1, tileable=True,
                                    closure=1).levels.tobytes()).hexdigest()[:12]
    assert got == "7df813fb00cd"


def seam_jump(picture, axis):
    """Mean grey jump across the seam over the mean jump between neighbours inside."""
    g = picture.astype(float) if picture.ndim == 2 else picture.mean(axis=2)
    inside = np.abs(np.diff(g, axis=axis)).mean()
    across = np.abs(np.take(g, 0, axis=axis) - np.take(g, -1, axis=axis)).mean()
    return across / inside


def test_photo_models_draw_tiling_scales_and_tone():
    photo = ski.data.brick()
    model = acquire_model(photo)
    jumps = {False: [], True: []}
    for seed in range(3):
        for tileable in (False, True):
            image = model.synthesize((120, 160), seed=seed, tileable=tileable).image
            jumps[tileable].append([seam_jump(image, 0), seam_jump(image, 1)])
    plain, tiled = np.mean(jumps[False], axis=0), np.mean(jumps[True], axis=0)
    assert np.all(tiled < plain) and tiled[0] < plain[0] / 2    # across the rows, the columns
    ms, _ = estimate_scales(photo, scales=3)
    levels = synthesize_scales(ms, (50, 70), seed=1, tileable=True).levels
    assert np.array_equal(levels, synthesize_scales(ms, (50, 70), seed=1, tileable=True).levels)


@pytest.mark.parametrize("name", ["grass", "gravel"])
def test_a_tiling_coarsest_scale_backs_off_to_a_window_that_closes(name):
    """A 5×5 coarsest law from a 64² reduction follows the photo's rows: on a 32² torus its
    seams met dead ends nearly everywhere (about 90 % of the windows outside it). The tileable
    draw backs off to a sub-window law whose torus draw closes."""
    model = acquire_model(getattr(ski.data, name)())
    coarse = model.scales.dpjs[0]
    assert coarse.window == (5, 5)
    shape = multiscale.scale_shapes((256, 256), model.scales.scales)[0]
    full = synthesize(coarse, shape, seed=multiscale.scale_seed(0, 0), tileable=True).levels
    assert off_the_dpj(full, coarse) > 0.3                     # why it backs off
    alone = multiscale.MultiScaleDPJ((coarse,))        # its draw is the coarsest scale's
    for seed in range(3):
        law = multiscale._torus_law(coarse, shape, seed, 2)[0]
        assert law.window[0] < 5 and law.levels == coarse.levels
        assert np.isclose(law.probs.sum(), 1.0)
        drawn = synthesize_scales(alone, shape, seed=seed, tileable=True).levels
        assert off_the_dpj(drawn, law) <= multiscale.TORUS_TOLERANCE
    # a plain draw keeps the full window: nothing to close
    assert off_the_dpj(synthesize_scales(alone, shape, seed=0).levels, coarse, torus=False) < 0.01


def first_law_that_closes(dpj, shape, seed):
    """The back-off one window after another (the rule _torus_law runs two at a time),
    each closed by closure 2."""
    while True:
        drawn = synthesize(dpj, shape, seed=multiscale.scale_seed(seed, 0), tileable=True,
                           closure=2).levels
        if off_the_dpj(drawn, dpj) <= multiscale.TORUS_TOLERANCE or min(dpj.window) <= 2:
            return dpj
        u, v = dpj.window
        dpj = dpj.marginal(rows=slice(0, v - 1), cols=slice(0, u - 1))


@pytest.mark.parametrize("name", ["brick", "moon"])
def test_the_back_off_picks_the_law_one_window_after_another_would(name):
    """The windows are tried two at a time; the law is still the first, widest, that closes
    (here 5×5, 4×4 or 3×3 depending on the seed)."""
    coarse = acquire_model(getattr(ski.data, name)()).scales.dpjs[0]
    windows = set()
    for seed in range(6):
        law = multiscale._torus_law(coarse, (32, 40), seed, 2)[0]
        assert law == first_law_that_closes(coarse, (32, 40), seed)
        windows.add(law.window)
    assert len(windows) >= 2


@pytest.mark.parametrize("name", ["brick", "moon"])
def test_closure_3_stops_failing_coarsest_draws_early_and_picks_the_same_law(name,
                                                                            monkeypatch):
    """Closure 3 judges each coarsest law on a draw stopped once it redraws more than
    TORUS_BUDGET per point: draws that close stay well under it, so the same law comes out as
    from whole draws (closure 2's way: the coarsest scale is closed alike by both)."""
    coarse = acquire_model(getattr(ski.data, name)()).scales.dpjs[0]
    laws = [multiscale._torus_law(coarse, (32, 40), seed, 3)[0] for seed in range(6)]
    assert laws == [multiscale._torus_law(coarse, (32, 40), seed, 2)[0]
                    for seed in range(6)]
    monkeypatch.setattr(multiscale, "TORUS_BUDGET", 10 ** 9)
    assert laws == [multiscale._torus_law(coarse, (32, 40), seed, 3)[0]
                    for seed in range(6)]


@pytest.mark.parametrize("name", ["brick", "moon", "coffee"])
def test_closure_5_stops_failing_coarsest_draws_at_their_back_offs(name, monkeypatch):
    """Closure 5 also stops a trial draw once it backs off at more than TORUS_REPAIRS of its
    points (a back-off leaves about a window off the law; the draws that close back off far
    less), and picks the same law as closure 4 on these photos. Every trial is given that
    budget, and those cut short are rejected."""
    coarse = acquire_model(getattr(ski.data, name)()).scales.dpjs[0]
    shape = (48, 40)
    laws = [multiscale._torus_law(coarse, shape, seed, 4)[0] for seed in range(6)]
    trials = []
    real = multiscale.synthesize

    def spied(dpj, shape, **kw):
        drawn = real(dpj, shape, **kw)
        trials.append((kw["repair_budget"], drawn.repairs))
        return drawn
    monkeypatch.setattr(multiscale, "synthesize", spied)
    chosen = [multiscale._torus_law(coarse, shape, seed, 5) for seed in range(6)]
    assert [law for law, _ in chosen] == laws
    budget = int(multiscale.TORUS_REPAIRS * 48 * 40)
    assert {b for b, _ in trials} == {budget}
    assert all(trial is None or trial.repairs <= budget for _, trial in chosen)
    trials.clear()
    multiscale._torus_law(coarse, shape, 0, 4)
    assert {b for b, _ in trials} == {None}


@pytest.mark.parametrize("closure", [2, 3, 5])
def test_the_trial_draw_that_chose_the_coarsest_law_is_its_first_try(closure, monkeypatch):
    """A tileable multi-scale draw does not draw the coarsest scale's first try again: the
    trial draw that showed its law closes is that try (same law, seed and redraws). The
    texture is the one drawn without reusing it."""
    model = acquire_model(ski.data.brick()).scales
    shape = (96, 80)
    coarsest = multiscale.scale_shapes(shape, model.scales)[0]
    calls = []
    real = multiscale.synthesize

    def counted(dpj, shape, **kw):
        calls.append((dpj, shape, kw["seed"]))
        return real(dpj, shape, **kw)
    monkeypatch.setattr(multiscale, "synthesize", counted)
    laws = set()
    for seed in range(4):
        calls.clear()
        now = synthesize_scales(model, shape, seed=seed, tileable=True, closure=closure).levels
        first = (coarsest, multiscale.scale_seed(seed, 0))
        drawn = [dpj for dpj, *call in calls if tuple(call) == first]
        law, _ = multiscale._torus_law(model.dpjs[0], coarsest, seed, closure,
                                       (multiscale.COARSE_REDRAWS, multiscale.COARSE_ROW_REDRAWS))
        laws.add(law.window)
        assert sum(dpj is law for dpj in drawn) == 1       # tried once, not drawn again
        with monkeypatch.context() as m:
            m.setattr(multiscale, "_torus_law", lambda *a: (law, None))
            again = synthesize_scales(model, shape, seed=seed, tileable=True,
                                      closure=closure).levels
        assert np.array_equal(now, again)
    assert len(laws) >= 2          # the full law and a sub-window's



@pytest.mark.parametrize("kind, share", [("redraw", "TORUS_BUDGET"), ("repair", "TORUS_REPAIRS")])
def test_a_budget_stops_a_draw_that_meets_dead_ends_everywhere(kind, share):
    """A draw given a budget of redraws (or of back-offs, ``repairs``) stops once past it; a
    draw that stays within it is the draw made without one. (Seam closure 5: closure 6 meets
    fewer dead ends on this law, 2032 redraws.)"""
    coarse = acquire_model(ski.data.brick()).scales.dpjs[0]
    budget = int(getattr(multiscale, share) * 64 * 64)
    spent = lambda drawn: getattr(drawn, kind + "s")
    full = synthesize(coarse, (64, 64), seed=0, tileable=True, closure=5)
    assert spent(full) > 2 * budget                    # its 5×5 law does not close at 64²
    cut = synthesize(coarse, (64, 64), seed=0, tileable=True, closure=5,
                     **{kind + "_budget": budget})
    assert budget < spent(cut) < spent(full) / 2
    three = coarse.marginal(rows=slice(0, 3), cols=slice(0, 3))     # its 3×3 law closes
    closing = synthesize(three, (64, 64), seed=0, tileable=True, **{kind + "_budget": budget})
    assert spent(closing) <= budget and off_the_dpj(closing.levels, three) < 0.01
    assert np.array_equal(closing.levels, synthesize(three, (64, 64), seed=0, tileable=True).levels)


def test_closure_3_draws_a_photo_model_that_tiles_with_fewer_tries():
    """Multi-scale textures recorded with closure 3 differ from closure 2's (a new way, so a
    new step version) but tile as well: seams no more visible, the same seed the same texture."""
    model = acquire_model(ski.data.gravel())
    jumps = {2: [], 3: []}
    for seed in range(3):
        for closure in (2, 3):
            image = model.synthesize((96, 128), seed=seed, tileable=True,
                                     closure=closure).image
            jumps[closure].append([seam_jump(image, 0), seam_jump(image, 1)])
    assert np.all(np.mean(jumps[3], axis=0) < 1.3 * np.mean(jumps[2], axis=0))
    a = model.synthesize((96, 128), seed=1, tileable=True)
    assert np.array_equal(a.image, model.synthesize((96, 128), seed=1, tileable=True).image)
    assert not np.array_equal(a.levels, model.synthesize((96, 128), seed=1, tileable=True,
                                                         closure=2).levels)
    with pytest.raises(InputError):
        synthesize_scales(model.scales, (96, 128), tileable=True,
                          closure=multiscale.SCALES_CLOSURE + 1)


def test_tone_contexts_read_across_the_seams_when_the_levels_tile():
    levels = np.random.default_rng(0).integers(0, 3, (5, 7)).astype(np.uint8)
    nine, five, own = context_codes(levels, 3, wrap=True)
    padded = np.pad(levels, 1, mode="wrap")
    i, j = 0, 6                                        # a corner: its context wraps both ways
    block = padded[i:i + 3, j:j + 3].ravel()
    assert nine[i * 7 + j] == int("".join(map(str, block)), 3)
    cross = [padded[i, j + 1], padded[i + 1, j], padded[i + 1, j + 1], padded[i + 1, j + 2],
             padded[i + 2, j + 1]]
    assert five[i * 7 + j] == int("".join(map(str, cross)), 3)
    assert own[i * 7 + j] == levels[i, j]


def test_a_version_1_tileable_step_replays_with_the_first_closure():
    """A log written before closure 2 (Synthesize version 1, no ``closure``) replays to the
    texture it made; a new step records closure 2 and draws the new way."""
    import hashlib
    from texeditor.recipe.codec import action_from_json
    from texeditor.recipe.document import Document
    from texeditor.recipe.actions import Synthesize
    dpj = photo_dpj("gravel", (3, 3))
    doc = Document()
    ref = doc.add_dpj(dpj)
    old = {"type": "synthesize", "version": 1, "dpj": ref, "width": 130, "height": 97,
           "seed": 1, "tileable": True}
    doc.apply(action_from_json(old))
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest()[:12] == "7df813fb00cd"
    new = Synthesize(ref, 130, 97, seed=1, tileable=True)
    assert new.to_json()["closure"] == CLOSURE and new.to_json()["version"] == Synthesize.VERSION
    doc.apply(new)
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest()[:12] != "7df813fb00cd"


@pytest.mark.parametrize("name", ["grass", "brick"])
def test_closing_the_bottom_seam_redraws_only_near_it(name):
    """Each column's redraw keeps the windows of the columns after it whole (up to where their
    own closure redraws), so one long redraw does not spread to every later column. Without
    that, seeds of grass redrew a third of the texture column by column."""
    from texeditor.markov import synthesis as S
    dpj = photo_dpj(name, (3, 3))
    rows, columns = S._tables(dpj), S._tables(S._transposed(dpj))
    h = w = 256
    for seed in range(10):
        state = np.random.SeedSequence(seed).generate_state(1, np.uint64)
        torus = np.pad(np.zeros((h, w), np.uint8), ((0, 2), (0, 2)), mode="wrap")
        S._sample_rows(torus, 0, h, rows, state, 64, np.int64(S.NO_BUDGET), np.int64(h),
                       np.int64(w), np.int64(2),
                       np.int64(S.NO_BUDGET), np.int64(S.NO_BUDGET), S.NO_PULL)
        across = np.ascontiguousarray(torus.T)
        before = across.copy()
        S._close_columns(across, columns, state, np.int64(w), np.int64(h), np.int64(2))
        changed = across[:w, :h] != before[:w, :h]
        assert changed.mean() < 0.06, seed
        assert off_the_dpj(np.ascontiguousarray(across[:w, :h].T), dpj) < 0.0005


def replayed_fixture(folder: str, name: str):
    """A tileable texture of tests/data/``folder`` opened with today's code, its levels (and
    tone) checked against the hashes written with it: the document, its step, the record."""
    import hashlib
    import json
    from tests.support import DATA
    from texeditor.photo import document_tone
    from texeditor.recipe.texturefile import render_texture
    expected = json.loads((DATA / folder / "expected.json").read_text())[name]
    doc = render_texture(DATA / folder / f"{name}.texture")
    step = doc.actions[-1]
    assert step.closure == expected["closure"] and step.tileable
    assert hashlib.sha256(doc.levels.tobytes()).hexdigest() == expected["levels_sha256"]
    if "tone_sha256" in expected:
        assert hashlib.sha256(document_tone(doc).tobytes()).hexdigest() == \
            expected["tone_sha256"]
    return doc, step, expected


@pytest.mark.parametrize("name", ["scales-tileable", "synthesize-tileable"])
def test_tileable_textures_of_the_previous_closures_replay_as_they_did(name):
    """Files written before closure 4 (tests/data/closure-3: SynthesizeScales version 4 with
    closure 3, Synthesize version 2 with closure 2) come out bit-identical, levels and tone. A
    new step of the same texture records closure 4, whose seams redraw shorter stretches: the
    same seed draws another torus, whose windows are still the DPJ's."""
    import dataclasses
    doc, step, expected = replayed_fixture("closure-3", name)
    new = dataclasses.replace(step, closure=4)
    assert type(step).VERSION > expected["version"]
    assert new.to_json()["closure"] == 4
    redrawn = new.prepare(doc)
    assert not np.array_equal(redrawn, doc.levels)
    if name == "synthesize-tileable":
        assert off_the_dpj(redrawn, doc.dpj) <= 0.0005


@pytest.mark.parametrize("name", ["scales-tileable", "synthesize-tileable"])
def test_tileable_textures_of_closure_4_replay_as_they_did(name):
    """Files written before seam closure 5 (tests/data/closure-4: Synthesize version 3 with
    closure 4; SynthesizeScales version 10 with closure 5, whose scales are closed by seam
    closure 4 and still are) come out bit-identical, levels and tone. A new synthesis step
    names closure 5 and draws another torus (this seed's last column was redrawn far up)."""
    import dataclasses
    doc, step, expected = replayed_fixture("closure-4", name)
    if name == "scales-tileable":
        assert step.closure == 5 and SEAMS[step.closure - 1] == 4
        assert expected["version"] == 10 and not step.tone_finish     # shown as it was drawn
        return
    new = dataclasses.replace(step, closure=5)
    assert new.to_json()["version"] == type(step).VERSION > expected["version"]
    redrawn = new.prepare(doc)
    assert not np.array_equal(redrawn, doc.levels)
    assert off_the_dpj(redrawn, doc.dpj) <= off_the_dpj(doc.levels, doc.dpj)


def test_tileable_textures_of_closure_5_replay_as_they_did():
    """A file written before seam closure 6 (tests/data/closure-5: Synthesize version 4 with
    closure 5) comes out bit-identical. A new step names closure 6 and draws another torus,
    whose windows are still the DPJ's. (Photo models of closure 5: tests/data/scales-v16.)"""
    import dataclasses
    doc, step, expected = replayed_fixture("closure-5", "synthesize-tileable")
    assert expected["version"] == 4 < type(step).VERSION and step.closure == 5
    new = dataclasses.replace(step, closure=CLOSURE)
    assert CLOSURE == 8 and new.to_json()["closure"] == 8
    redrawn = new.prepare(doc)
    assert not np.array_equal(redrawn, doc.levels)
    assert off_the_dpj(redrawn, doc.dpj) <= 0.0005


def chain_dpj(stay=0.98):
    """The 3×1 windows of a two-level Markov chain that seldom changes level: its rows are
    independent chains, so a row drawn on its ring changes level across the seam as often as
    anywhere else."""
    change = np.array([[stay, 1 - stay], [1 - stay, stay]])
    configs = np.array(np.meshgrid(*[range(2)] * 3, indexing="ij")).reshape(3, -1).T
    probs = np.array([0.5 * change[a, b] * change[b, c] for a, b, c in configs])
    return DPJ(configs.reshape(-1, 1, 3).astype(np.uint8), probs, 2)


def side_changes(fields):
    """How often a row's last and first points differ, over how often two neighbours do."""
    x = np.asarray(fields)
    return np.mean(x[:, :, -1] != x[:, :, 0]) / np.mean(x[:, :, 1:] != x[:, :, :-1])


def test_closure_6_draws_each_row_on_its_ring():
    """Closure 5 redrew a row's end from a stretch of one window given both sides, so a chain
    that seldom changes level had to change within that stretch: 5.8 times as often across
    the seam as inside. Closure 6 draws the row on its ring (its first points, then the rest
    given them at both ends): as often as inside."""
    dpj = chain_dpj()
    drawn = {c: [synthesize(dpj, (64, 128), seed=s, tileable=True, closure=c).levels
                 for s in range(8)] for c in (5, 6)}
    assert side_changes(drawn[5]) > 3
    assert 0.5 < side_changes(drawn[6]) < 1.5


def test_closure_6_closes_a_photo_dpjs_side_seam_as_its_inside():
    """A 3×3 DPJ of brick, 128², 8 seeds: its rows change level across the side seam 1.49
    times as often as inside with closure 5, 1.00 with closure 6; the torus's windows are
    still the DPJ's, and the same seed draws the same texture."""
    dpj = photo_dpj("brick", (3, 3))
    drawn = {c: [synthesize(dpj, (128, 128), seed=s, tileable=True, closure=c).levels
                 for s in range(8)] for c in (5, 6)}
    assert side_changes(drawn[6]) < 1.2 < side_changes(drawn[5]) - 0.2
    assert max(off_the_dpj(x, dpj) for x in drawn[6]) <= 0.001
    assert np.array_equal(drawn[6][3],
                          synthesize(dpj, (128, 128), seed=3, tileable=True, closure=6).levels)


def bottom_changes(fields):
    """How often a column's last and first points differ, over how often two neighbours do."""
    x = np.asarray(fields)
    return np.mean(x[:, -1] != x[:, 0]) / np.mean(x[:, 1:] != x[:, :-1])


def test_closure_7_pulls_the_last_rows_towards_the_first():
    """The bottom seam: closure 6 closes it by the columns' law over one window, between rows
    drawn apart (camera 3×3, 128², 8 seeds: 2.04 times as many level changes across it as
    inside); closure 7 weighs the last 16 rows towards the first row's levels (_pull): 1.24.
    The side seam and the windows stay as they were."""
    from texeditor.markov import synthesis as S
    dpj = photo_dpj("camera", (3, 3))
    drawn = {c: [synthesize(dpj, (128, 128), seed=s, tileable=True, closure=c).levels
                 for s in range(8)] for c in (6, 7)}
    assert bottom_changes(drawn[7]) < 1.5 < bottom_changes(drawn[6]) - 0.3
    assert abs(side_changes(drawn[7]) - side_changes(drawn[6])) < 0.2
    assert max(off_the_dpj(x, dpj) for x in drawn[7]) <= 0.001
    assert len(S._pull(dpj, 128)) == 16 and len(S._pull(dpj, 1024)) == S.PULL_ROWS
    factors = S._pull(dpj, 1024)          # towards the first row's level, less with distance
    assert np.all(factors[0].argmax(axis=0) == np.arange(dpj.levels))
    assert np.all(np.diagonal(factors[0]) > np.diagonal(factors[31]))


def test_tileable_textures_of_closure_7_replay_as_they_did():
    """A file written before seam closure 8 (tests/data/closure-7: Synthesize version 5 with
    closure 7, brick 3×3, 112×136) comes out bit-identical. A new step names closure 8 and
    Synthesize version 6, and draws another torus whose windows are still the DPJ's."""
    import dataclasses
    doc, step, expected = replayed_fixture("closure-7", "synthesize-tileable")
    assert expected["version"] == 5 < type(step).VERSION == 6 and step.closure == 7
    new = dataclasses.replace(step, closure=CLOSURE)
    assert new.to_json()["closure"] == 8 and new.to_json()["version"] == 6
    redrawn = new.prepare(doc)
    assert not np.array_equal(redrawn, doc.levels)
    assert off_the_dpj(redrawn, doc.dpj) <= 0.0005


def test_closure_8_draws_the_last_rows_as_the_inside():
    """Closure 7 redraws every column's last points given the columns before it but not those
    after: on brick (3×3, 192², 8 seeds) the windows of the last five rows were 0.36 TV from
    the inside's, five rows in the middle 0.14. Closure 8 pulls the last rows at full strength
    and redraws only the columns whose windows across the seam leave the DPJ: 0.14, as the
    middle's. Its torus windows are the DPJ's, and the same seed draws the same texture."""
    dpj = photo_dpj("brick", (3, 3))
    n = 192
    last, middle = {}, {}
    for closure in (7, 8):
        codes = np.stack([window_codes(synthesize(dpj, (n, n), seed=s, tileable=True,
                                                  closure=closure).levels, (3, 3), 4)
                          for s in range(8)])
        inside = codes[:, 16:n // 2 - 8].ravel()
        last[closure] = window_tv(codes[:, n - 5:].ravel(), inside)
        middle[closure] = window_tv(codes[:, n // 2:n // 2 + 5].ravel(), inside)
    assert middle[7] == middle[8]                # the rows' pass is the same
    assert last[7] > middle[8] + 0.15
    assert last[8] < middle[8] + 0.05
    drawn = [synthesize(dpj, (n, n), seed=s, tileable=True).levels for s in (2, 5)]
    assert max(off_the_dpj(x, dpj) for x in drawn) <= 0.0005
    assert np.array_equal(drawn[1], synthesize(dpj, (n, n), seed=5, tileable=True).levels)


def test_closure_8_redraws_the_columns_near_a_window_the_dpj_lacks():
    """The bottom seam of a torus whose rows were pulled (closure 8): a column whose windows
    across it are the DPJ's is kept as drawn, unless one of the next two is not; a point
    spoiled at the seam is redrawn with its neighbours, and the windows it spoiled close."""
    from texeditor.markov import synthesis as S
    dpj = photo_dpj("gravel", (3, 3))
    rows, columns = S._tables(dpj), S._tables(S._transposed(dpj))
    h = w = 96
    pull = S._pull(dpj, h, 8)
    kept = []
    for seed in range(6):
        state = np.random.SeedSequence(seed).generate_state(1, np.uint64)
        torus = np.pad(np.zeros((h, w), np.uint8), ((0, 2), (0, 2)), mode="wrap")
        S._sample_rows(torus, 0, h, rows, state, 16, np.int64(S.NO_BUDGET), np.int64(h),
                       np.int64(w), np.int64(8), np.int64(S.NO_BUDGET),
                       np.int64(S.NO_BUDGET), pull)
        drawn = off_places(torus[:h, :w], dpj, torus=True)
        spoiled = 40 + seed
        torus[h - 1, spoiled] = (torus[h - 1, spoiled] + 2) % 4
        before = torus[:h, :w].copy()
        spoilt = off_places(before, dpj, torus=True) & ~drawn
        across = np.ascontiguousarray(torus.T)
        S._close_columns(across, columns, state, np.int64(w), np.int64(h), np.int64(8))
        after = np.ascontiguousarray(across[:w, :h].T)
        changed = np.nonzero((after != before).any(axis=0))[0]
        assert spoilt.any() and spoiled in changed
        assert not (spoilt & off_places(after, dpj, torus=True)).any()
        assert off_the_dpj(after, dpj) <= 0.0005
        kept.append(1 - len(changed) / w)
    assert np.mean(kept) > 0.6          # most columns closed by the pull alone


def test_closure_8_pulls_by_the_chain_itself():
    """Closure 7 weighs a point d + 1 rows above the first row by P^(d+1)^0.25; closure 8 by
    P^(d+1) (PULL_POWER_8: a column's own h-transform), floored at 1e-3 as closure 7's."""
    from texeditor.markov import synthesis as S
    from texeditor.markov.dpj import decode
    dpj = photo_dpj("camera", (3, 3))
    windows = decode(dpj.codes, dpj.levels, 3, 3)
    chain = np.zeros((4, 4))
    np.add.at(chain, (windows[:, 0, 0], windows[:, 1, 0]), dpj.probs)
    chain /= chain.sum(axis=1, keepdims=True)
    for d in (0, 5, 31):
        step = np.linalg.matrix_power(chain, d + 1)
        assert np.allclose(S._pull(dpj, 1024, 8)[d], np.maximum(step, 1e-3))
        assert np.allclose(S._pull(dpj, 1024, 7)[d], np.maximum(step, 1e-3) ** 0.25)
    assert len(S._pull(dpj, 128, 8)) == 16


@pytest.mark.parametrize("width", range(3, 9))   # narrower: smaller than a window
def test_closure_6_on_a_torus_too_narrow_for_a_ring(width):
    """A torus narrower than two windows has no room for a ring's start: its rows are drawn
    and closed as closure 5 does; every width gives a field of the asked shape, the same
    from the same seed."""
    dpj = photo_dpj("gravel", (3, 3))
    for shape in ((24, width), (width, 24)):
        first = synthesize(dpj, shape, seed=width, tileable=True).levels
        assert first.shape == shape and first.max() < dpj.levels
        assert np.array_equal(first, synthesize(dpj, shape, seed=width, tileable=True).levels)


def test_a_photo_model_closes_its_scales_by_seam_closure_7_but_its_coarsest(monkeypatch):
    """Seam closure 5 leaves a row's failed side closure as it is; a photo model's scales fail
    more (2 tries a seam) and their tone jumped more across the side seam with it, so closure
    5 of the scales closes every scale, the trial draws of its coarsest law too, by seam
    closure 4. Closure 6 of the scales draws their rows on their ring, by seam closure 6.
    Closure 7 pulls the last rows of the scales drawn given their parents too (seam closure 7),
    not the coarsest (COARSEST_SEAM); closure 8 (the current one) closes them by seam closure
    8, the coarsest still by 6."""
    assert len(SEAMS) == SCALES_CLOSURE and SEAMS[4] == 4 and SEAMS[5] == 6
    assert SCALES_CLOSURE == CLOSURE == 8 and multiscale.COARSEST_SEAM == 6
    asked = {"coarsest": [], "given": []}

    def spy(draw, key):
        def wrapped(*args, **kwargs):
            asked[key].append(kwargs.get("closure"))
            return draw(*args, **kwargs)
        return wrapped
    monkeypatch.setattr(multiscale, "synthesize", spy(multiscale.synthesize, "coarsest"))
    monkeypatch.setattr(multiscale, "synthesize_given",
                        spy(multiscale.synthesize_given, "given"))
    model = acquire_model(ski.data.gravel()[:128, :128], scales=3)
    for closure, coarsest, given in ((None, 6, 8), (7, 6, 7), (6, 6, 6), (5, 4, 4)):
        for key in asked:
            asked[key].clear()
        synthesize_scales(model.scales, (48, 56), seed=3, tileable=True,
                          **({} if closure is None else {"closure": closure}))
        assert asked["coarsest"] and set(asked["coarsest"]) == {coarsest}
        assert len(asked["given"]) >= 2 and set(asked["given"]) == {given}


def test_the_pull_given_parents_is_the_chance_to_reach_the_first_row_through_them():
    """Closure 7 of a scale drawn given its parents weighs the last rows of a column by the
    chance, under the law of its own levels given both points' parents, of reaching the first
    row's level through that column's parents (h_d = P_d h_(d-1) from the seam up, the top
    level 1, ** PULL_POWER_GIVEN): against the product of the chain's matrices. Random parents
    make the first level unreachable at times: no level is then preferred."""
    from texeditor.markov import synthesis as S
    model = acquire_model(ski.data.gravel()[:128, :128], scales=3)
    dpj, gp = model.scales.dpjs[2], multiscale.parent_levels(model.scales.dpjs, 2)
    gx = dpj.levels // gp
    chain = S._pull_given(dpj, gp, 64)
    assert chain.shape == (gp * gp, gx, gx) and np.allclose(chain.sum(axis=2), 1.0)
    assert S._pull_given(dpj, gp, 7) is S.NO_PULL          # too short a torus to pull
    rng = np.random.default_rng(4)
    h, w = 64, 20
    out = (rng.integers(0, gp, (h + 1, w + 2)) * gx + rng.integers(0, gx, (h + 1, w + 2)))
    t = S._tables(dpj, gp)
    rows = S._pulled_rows(chain, t, h)
    assert rows == h // S.PULL_SHARE == 8
    along = np.zeros((rows, w + 2, gx))
    S._pull_along(out.astype(np.uint8), h, chain, t, along)
    unreachable = 0
    for c in range(w + 2):
        reach = np.eye(gx)[out[0, c] % gx]
        for d in range(rows):
            r = h - 1 - d
            reach = chain[out[r, c] // gx * gp + out[(r + 1) % h, c] // gx] @ reach
            if reach.max() == 0:                      # unreachable: no level preferred
                reach, unreachable = np.ones(gx), unreachable + 1
            reach = reach / reach.max()
            assert np.allclose(along[d, c], np.maximum(reach, 1e-3) ** S.PULL_POWER_GIVEN)
    assert 0 < unreachable < rows * (w + 2) / 2


def test_closure_7_of_a_photo_model_pulls_its_finer_scales_towards_the_first_row():
    """A photo model's finest levels changed across the bottom seam twice as often as inside
    with closure 6 (camera crop, 128², 12 seeds: 2.12); closure 7 pulls the last rows of its
    scales drawn given their parents towards the first row: 1.33. Its windows and level
    shares stay the model's."""
    model = acquire_model(ski.data.camera()[:256, :256])
    drawn = {c: [model.synthesize((128, 128), seed=s, tileable=True, closure=c,
                                  tone=False).levels for s in range(12)] for c in (6, 7)}
    assert bottom_changes(drawn[7]) < 1.6 < bottom_changes(drawn[6]) - 0.3
    for levels in drawn[7]:
        shares = np.bincount(levels.ravel(), minlength=model.levels) / levels.size
        assert np.abs(shares - model.frequencies()).max() <= 0.03


def test_closure_8_of_a_photo_model_closes_its_finer_scales_by_the_pull():
    """Closure 8 of the scales pulls the last rows of the scales drawn given their parents at
    full strength and redraws their bottom seam only near the columns the pull did not close
    (seam closure 8): a gravel crop's finest levels (128², 12 seeds) change across the bottom
    seam 1.53 times as often as inside with closure 7, 1.12 with closure 8. The side seam and
    the level shares stay as they were."""
    model = acquire_model(ski.data.gravel()[:256, :256])
    drawn = {c: [model.synthesize((128, 128), seed=s, tileable=True, closure=c,
                                  tone=False).levels for s in range(12)] for c in (7, 8)}
    assert bottom_changes(drawn[8]) < 1.3 < bottom_changes(drawn[7]) - 0.1
    assert abs(side_changes(drawn[8]) - side_changes(drawn[7])) < 0.2
    for levels in drawn[8]:
        shares = np.bincount(levels.ravel(), minlength=model.levels) / levels.size
        assert np.abs(shares - model.frequencies()).max() <= 0.03


def test_closure_5_reads_the_last_column_as_the_others():
    """The last column of a torus: closure 4 redrew it from any window across the side seam a
    row's closure had left outside the DPJ, however far up (and that long redraw, given the
    first columns whole, seldom closed: it backed off over most of the column); closure 5 only
    mends what the columns before it changed near the bottom seam. The rows are drawn alike,
    so both leave the same windows outside the DPJ far up the side seam, closure 5 no more in
    all, and its last column changes only near the bottom."""
    from texeditor.markov import synthesis as S
    dpj = photo_dpj("grass", (3, 3))
    rows, columns = S._tables(dpj), S._tables(S._transposed(dpj))
    h = w = 256
    far = {4: 0, 5: 0}
    outside = {4: 0.0, 5: 0.0}
    for seed in range(8):
        for closure in (4, 5):
            state = np.random.SeedSequence(seed).generate_state(1, np.uint64)
            torus = np.pad(np.zeros((h, w), np.uint8), ((0, 2), (0, 2)), mode="wrap")
            S._sample_rows(torus, 0, h, rows, state, 16, np.int64(S.NO_BUDGET), np.int64(h),
                           np.int64(w),
                           np.int64(closure), np.int64(S.NO_BUDGET), np.int64(S.NO_BUDGET),
                           S.NO_PULL)
            across = np.ascontiguousarray(torus.T)
            before = across.copy()
            S._close_columns(across, columns, state, np.int64(w), np.int64(h),
                             np.int64(closure))
            last = np.flatnonzero(across[w - 1, :h] != before[w - 1, :h])
            far[closure] += bool(len(last)) and last.min() < h - 16
            outside[closure] += off_the_dpj(np.ascontiguousarray(across[:w, :h].T), dpj)
    assert far[5] == 0 < far[4]
    assert outside[5] <= outside[4]


@pytest.mark.parametrize("shape", [(1, 1), (2, 5), (7, 3), (16, 16)])
def test_the_torus_a_tileable_draw_fills_repeats_its_first_rows_and_columns(shape):
    """The padded copy a tileable draw works in is np.pad's wrap, also when the window's
    overlap is larger than the texture."""
    from texeditor.markov.synthesis import _torus
    levels = np.random.default_rng(sum(shape)).integers(0, 5, shape).astype(np.uint8)
    for rows in range(4):
        for columns in range(4):
            assert np.array_equal(_torus(levels, rows, columns),
                                  np.pad(levels, ((0, rows), (0, columns)), mode="wrap"))


class WindowLaw:
    """m of a window straight from a DPJ, as the sampler's tables mean it: the rows above read
    without their parents (a row is drawn given the levels above it and its own parents), the
    horizontal transition of column states, P(window) over P(its first u-1 columns); 0 where
    the DPJ lacks the window."""

    def __init__(self, dpj, gp):
        self.gx = dpj.levels // gp
        self.p, self.left = {}, {}
        for config, p in zip(self._above_stripped(dpj.configs), dpj.probs):
            self.p[config.tobytes()] = self.p.get(config.tobytes(), 0.0) + p
            head = config[:, :-1].tobytes()
            self.left[head] = self.left.get(head, 0.0) + p

    def _above_stripped(self, configs):
        configs = np.array(configs, np.int64)
        configs[..., :-1, :] %= self.gx
        return configs

    def m(self, window):
        window = self._above_stripped(window)
        p = self.p.get(window.tobytes(), 0.0)
        return p / self.left[window[:, :-1].tobytes()] if p > 0.0 else 0.0


@pytest.mark.parametrize("kind", ["photo", "given parents"])
def test_the_rows_below_weigh_each_entry_by_the_windows_they_end(kind):
    """A seam closure weighs a stretch's entries by the fixed rows under it (_keep_below): the
    product of the transitions m of the windows ending in them — here read from the DPJ
    itself, window by window — 0 where the DPJ lacks one. _window_m (what _first_bad reads)
    is that m too."""
    from texeditor.markov import synthesis as S
    if kind == "photo":
        dpj, gp = photo_dpj("brick", (3, 3)), 1
        q = quantize(ski.data.brick(), 4, "lloyd").levels
    else:
        model, levels = estimate_scales(ski.data.gravel()[:128, :128], scales=2)
        dpj = model.dpjs[1]
        gp = multiscale.parent_levels(model.dpjs, 1)
        q = levels[1] + dpj.levels // gp * multiscale.codes_for(dpj, levels[0], levels[1].shape)
    t = S._tables(dpj, gp)
    law = WindowLaw(dpj, gp)
    u, v, gx = t.u, t.v, t.gx
    rng = np.random.default_rng(3)
    bcode, start, end = t.ient[S.BCODE], t.ctx[S.START], t.ctx[S.END]
    checked = kept = 0
    for _ in range(300):
        if rng.random() < 0.7:        # mostly the photo's windows, which the DPJ has
            y, x = rng.integers(0, q.shape[0] - 8), rng.integers(0, q.shape[1] - 9)
            out = q[y:y + 8, x:x + 9].astype(np.uint8)
        else:
            out = (rng.integers(0, gp, (8, 9)) * gx
                   + rng.integers(0, gx, (8, 9))).astype(np.uint8)
        r, n, below = 3, int(rng.integers(0, 9 - u + 1)), v - 1
        ci = int(rng.integers(t.lvl[S.LEN, 0]))
        lo, hi = int(start[ci]), int(end[ci])
        tb = rng.random(hi - lo + 5)
        tb[rng.random(len(tb)) < 0.2] = 0.0
        expected = tb.copy()
        for e in range(lo, hi):
            drawn = out.copy()          # row r as the entry would draw it (its parents stay)
            digits = [bcode[e] // gx ** (u - 1 - j) % gx for j in range(u)]
            drawn[r, n:n + u] = drawn[r, n:n + u] // gx * gx + digits
            for k in range(1, below + 1):
                m = law.m(drawn[r + k - v + 1:r + k + 1, n:n + u])
                assert S._window_m(out, r + k, n, r, bcode[e], t) == pytest.approx(m, rel=1e-9)
                expected[2 + e - lo] *= m
        total = S._keep_below(out, r, n, below, tb, 2, lo, hi, bcode, t)
        assert np.array_equal(tb == 0.0, expected == 0.0)
        assert tb == pytest.approx(expected, rel=1e-9)
        assert total == pytest.approx(expected[2:2 + hi - lo].sum(), rel=1e-9)
        checked += hi - lo
        kept += np.count_nonzero(expected[2:2 + hi - lo])
    assert checked > 1000 and 0 < kept < checked
