"""The scan direction (§4.3.2, §5.2.1b) and stationarity enforced at acquisition (§5.2.2).

A scan is a turn of the picture: a DPJ acquired by columns is the row DPJ of the transposed
photo, and a texture drawn by columns is the transposed row texture, bit for bit.
"""

import json

import numpy as np
import pytest

from texeditor import DPJ
from texeditor.cli import main
from texeditor.errors import InputError
from texeditor.markov import scan
from texeditor.markov.dpj_edit import random_dpj
from texeditor.markov.estimation import estimate_dpj
from texeditor.markov.synthesis import synthesize
from texeditor.recipe.actions import Synthesize
from texeditor.recipe.codec import action_from_json
from texeditor.recipe.document import Document


def vertical_stripes(h=40, w=36, seed=0) -> np.ndarray:
    """Stripes two points wide running down, with one point in twenty flipped."""
    rng = np.random.default_rng(seed)
    m = np.tile((np.arange(w) // 2) % 2, (h, 1)).astype(np.uint8)
    return m ^ (rng.random((h, w)) < 0.05).astype(np.uint8)


def test_a_column_scan_counts_windows_down_the_columns():
    # 0 1 0 / 0 1 0 with a 2x1 window: by rows the pairs are 01, 10 (twice each);
    # by columns (each column read top to bottom) they are 00, 11, 00
    m = np.array([[0, 1, 0], [0, 1, 0]], np.uint8)
    rows = estimate_dpj(m, (2, 1), 2)
    assert rows.prob([[0, 1]]) == rows.prob([[1, 0]]) == 0.5
    cols = estimate_dpj(m, (2, 1), 2, scan="columns")
    assert cols.prob([[0, 0]]) == pytest.approx(2 / 3) and cols.prob([[1, 1]]) == pytest.approx(1 / 3)
    assert cols.meta["scan"] == "columns" and "scan" not in rows.meta


@pytest.mark.parametrize("name,turn", [("columns", lambda m: m.T),
                                       ("columns-left", lambda m: m[:, ::-1].T),
                                       ("rows-up", lambda m: m[::-1])])
def test_a_scanned_acquisition_is_the_row_dpj_of_the_turned_photo(name, turn):
    photo = vertical_stripes()
    d = estimate_dpj(photo, (3, 2), 2, scan=name)
    assert d == estimate_dpj(np.ascontiguousarray(turn(photo)), (3, 2), 2)
    assert d.meta["scan"] == name


def test_the_default_scan_keeps_the_former_bytes():
    photo = vertical_stripes()
    assert estimate_dpj(photo, (2, 2), 2).to_bytes() == \
        estimate_dpj(photo, (2, 2), 2, scan="rows").to_bytes()
    assert "scan" not in estimate_dpj(photo, (2, 2), 2).meta


@pytest.mark.parametrize("tileable", [False, True])
def test_synthesis_by_columns_is_the_transposed_synthesis_bit_for_bit(tileable):
    d = estimate_dpj(vertical_stripes(), (3, 2), 2, scan="columns")
    h, w = 24, 40                                    # not square: the shape is turned too
    by_columns = scan.synthesize(d, (h, w), scan="columns", seed=9, tileable=tileable).levels
    assert by_columns.shape == (h, w)
    assert np.array_equal(by_columns, synthesize(d, (w, h), seed=9, tileable=tileable).levels.T)
    left = scan.synthesize(d, (h, w), scan="columns-left", seed=9, tileable=tileable).levels
    assert np.array_equal(left, synthesize(d, (w, h), seed=9, tileable=tileable).levels.T[:, ::-1])
    up = scan.synthesize(d, (h, w), scan="rows-up", seed=9, tileable=tileable).levels
    assert np.array_equal(up, synthesize(d, (h, w), seed=9, tileable=tileable).levels[::-1])


def test_stripes_acquired_and_drawn_by_columns_run_down_the_texture():
    """What the scan is for: the stripes run down the photo, so each column is nearly constant;
    drawn back by columns they run down the texture as well."""
    d = estimate_dpj(vertical_stripes(80, 80), (2, 2), 2, scan="columns")
    out = scan.synthesize(d, (60, 60), scan="columns", seed=1).levels
    same_down = np.mean(out[1:] == out[:-1])
    same_across = np.mean(out[:, 1:] == out[:, :-1])
    assert same_down > 0.85 and same_across < 0.65


def test_the_synthesize_action_draws_in_its_scan_and_keeps_old_logs():
    d = random_dpj((2, 2), 2, seed=3)
    doc = Document()
    ref = doc.store_dpj(d)
    action = Synthesize(ref, 10, 6, 4, scan="columns")
    doc.apply(action)
    assert doc.shape == (6, 10)
    assert np.array_equal(doc.levels, synthesize(d, (10, 6), seed=4).levels.T)
    assert action_from_json(json.loads(json.dumps(action.to_json()))) == action
    assert "scan columns" in action.label()
    old = {"type": "synthesize", "version": 1, "dpj": ref, "width": 10, "height": 6, "seed": 4}
    assert action_from_json(old).scan == "rows"          # a log written before the scan existed
    with pytest.raises(InputError, match="scan must be one of"):
        Synthesize(ref, 10, 6, 4, scan="diagonal")


def test_cli_acquires_and_draws_in_the_recorded_scan(tmp_path, capsys):
    from skimage import io as skio
    photo = tmp_path / "stripes.png"
    skio.imsave(photo, (vertical_stripes() * 255).astype(np.uint8), check_contrast=False)
    out = tmp_path / "s.dpj"
    assert main(["acquire", str(photo), "--levels", "2", "--scan", "columns", "-o", str(out)]) == 0
    d = DPJ.load(out)
    assert d.meta["scan"] == "columns"
    assert main(["synth", str(out), "--size", "30x20", "--seed", "2", "-o",
                 str(tmp_path / "t.npy")]) == 0
    assert "scan columns" in capsys.readouterr().out
    levels = np.load(tmp_path / "t.npy", allow_pickle=False)
    assert np.array_equal(levels, synthesize(d, (30, 20), seed=2).levels.T)
    assert main(["synth", str(out), "--size", "30x20", "--seed", "2", "--scan", "rows", "-o",
                 str(tmp_path / "r.npy")]) == 0
    assert np.array_equal(np.load(tmp_path / "r.npy"), synthesize(d, (20, 30), seed=2).levels)
    assert main(["acquire", str(photo), "--scan", "sideways", "-o", str(out)]) == 2


# -- stationarity enforced when asked (§5.2.2) -----------------------------------------------------

def marginal_gaps(d: DPJ) -> tuple[float, float]:
    """The largest gap between the laws of the left and right (u-1)-column sub-windows, and of
    the top and bottom (v-1)-row ones, summed entry by entry here from the definitions."""
    gaps = []
    for first, second in (((slice(None), slice(0, -1)), (slice(None), slice(1, None))),
                          ((slice(0, -1), slice(None)), (slice(1, None), slice(None)))):
        law: dict = {}
        for config, p in zip(d.configs, d.probs):
            a, b = config[first].tobytes(), config[second].tobytes()
            law[a] = law.get(a, 0.0) + p
            law[b] = law.get(b, 0.0) - p
        gaps.append(max(abs(x) for x in law.values()))
    return gaps[0], gaps[1]


def test_stationary_acquisition_meets_the_condition_and_still_synthesises():
    rng = np.random.default_rng(4)
    m = (rng.random((12, 12)) < 0.4).astype(np.uint8)
    plain = estimate_dpj(m, (2, 2), 2)
    assert max(marginal_gaps(plain)) > 1e-3                 # the photo's borders unbalance it
    d = estimate_dpj(m, (2, 2), 2, stationary=True)
    assert max(marginal_gaps(d)) <= 1e-12 and d.total == pytest.approx(1, abs=1e-12)
    assert d.meta["stationary"] is True and d.report().horizontal_residual <= 1e-12
    assert set(d.codes) <= set(plain.codes)                 # no configuration invented
    out = synthesize(d, (30, 30), seed=1).levels
    assert out.shape == (30, 30) and set(np.unique(out)) <= {0, 1}


def test_stationary_acquisition_in_a_scan():
    d = estimate_dpj(vertical_stripes(20, 16), (3, 2), 2, scan="columns", stationary=True)
    assert max(marginal_gaps(d)) <= 1e-12 and d.meta["scan"] == "columns"


def test_a_photo_no_stationary_law_fits_is_refused_clearly():
    # a ramp 0 1 2 read with a 2x1 window: 0 -> 1 -> 2 and nothing comes back
    with pytest.raises(InputError, match="never comes back"):
        estimate_dpj(np.array([[0, 1, 2]], np.uint8), (2, 1), 3, stationary=True)
