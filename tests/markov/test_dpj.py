"""The sparse DPJ model: codes, marginals, the validation report, restriction, the .dpj file."""

import io
import json
import zipfile

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from texeditor import DPJ, synthesize
from texeditor.markov.dpj import decode, encode
from texeditor.errors import FormatError, InputError
from texeditor.markov.estimation import estimate_dpj


def checkerboard_dpj():
    configs = np.array([[[0, 1], [1, 0]], [[1, 0], [0, 1]]], np.uint8)
    return DPJ(configs, [0.5, 0.5], 2)


@given(st.integers(2, 16), st.integers(1, 3), st.integers(1, 3), st.data())
@settings(max_examples=50, deadline=None)
def test_encode_decode_round_trip(levels, u, v, data):
    n = data.draw(st.integers(1, 20))
    configs = np.array(data.draw(st.lists(st.integers(0, levels - 1), min_size=n * u * v,
                                          max_size=n * u * v)), np.uint8).reshape(n, v, u)
    assert np.array_equal(decode(encode(configs, levels), levels, v, u), configs)


def test_window_too_large_for_63_bits_is_refused():
    with pytest.raises(InputError, match="63 bits"):
        DPJ.empty((4, 4), 16)
    DPJ.empty((3, 5), 16)  # 16^15 = 2^60 fits


@pytest.mark.parametrize("window,levels", [((0, 2), 4), ((7, 1), 4), ((2, 2), 1), ((2, 2), 17)])
def test_out_of_range_windows_and_levels(window, levels):
    with pytest.raises(InputError):
        DPJ.empty(window, levels)


def test_lookup_and_duplicates():
    d = checkerboard_dpj()
    assert d.prob([[0, 1], [1, 0]]) == 0.5
    assert d.prob([[0, 0], [0, 0]]) == 0.0
    with pytest.raises(InputError, match="twice"):
        DPJ(np.zeros((2, 1, 2), np.uint8), [0.5, 0.5], 2)


def test_marginals_sum_over_left_out_rows_and_columns():
    m = np.array([[0, 1, 2], [2, 1, 0], [1, 1, 1]], np.uint8)
    d = estimate_dpj(m, (2, 2), 3)
    assert len(d) == 4 and np.isclose(d.total, 1)
    top = d.marginal(rows=slice(0, 1))
    assert top.window == (2, 1)
    assert top.prob([[0, 1]]) == 0.25 and top.prob([[1, 2]]) == 0.25 and top.prob([[1, 1]]) == 0
    assert np.isclose(top.total, 1)


def test_report_of_a_wrapped_estimate_is_stationary_and_valid():
    rng = np.random.default_rng(0)
    d = estimate_dpj(rng.integers(0, 3, (40, 40)), (3, 2), 3, wrap=True)
    r = d.report()
    assert r.is_valid
    assert r.horizontal_residual < 1e-12 and r.vertical_residual < 1e-12
    assert r.closed_classes == 1 and r.transient_states == 0


def test_report_counts_bad_entries_and_residuals():
    configs = np.array([[[0, 0]], [[0, 1]], [[1, 1]]], np.uint8)
    r = DPJ(configs, [0.5, -0.1, 1.5], 2).report()
    assert r.negative == 1 and r.above_one == 1 and not r.is_valid
    # left marginal {0: 0.4, 1: 1.5}, right {0: 0.5, 1: 1.4}
    assert np.isclose(r.horizontal_residual, 0.2)


@pytest.mark.parametrize("entries", [1, 40])
def test_report_of_a_dpj_whose_probabilities_are_all_zero(entries, tmp_path):
    """A hand-entered DPJ in progress may have every probability at 0 (a file may hold it): its
    report says so (sum 0, not valid, nothing to compare), and dpj-info prints it."""
    from texeditor.cli import main
    rng = np.random.default_rng(entries)
    configs = np.unique(rng.integers(0, 3, (entries, 2, 2)), axis=0).astype(np.uint8)
    dpj = DPJ(configs, np.zeros(len(configs)), 3)
    r = dpj.report()
    assert r.total == 0 and r.entries == len(configs) and not r.is_valid
    assert r.horizontal_residual == 0 and r.vertical_residual == 0
    dpj.save(tmp_path / "zero.dpj")
    assert main(["dpj-info", str(tmp_path / "zero.dpj")]) == 0


def test_restrict_keeps_the_main_closed_class_and_drops_transients():
    # chain on single points (u = 2, v = 1): 0 -> 1 is transient, {1, 2} is closed, {3} closed
    # but smaller; 0 has no way back.
    configs = np.array([[[0, 1]], [[1, 2]], [[2, 1]], [[3, 3]], [[0, 0]]], np.uint8)
    d = DPJ(configs, [0.1, 0.3, 0.3, 0.2, 0.1], 4)
    r = d.report()
    assert r.closed_classes == 2 and r.transient_states == 1
    kept = d.restrict()
    assert sorted(map(tuple, kept.configs[:, 0])) == [(1, 2), (2, 1)]
    assert np.allclose(kept.probs, 0.5)
    assert kept.report().transient_states == 0


def test_dpj_file_round_trip(tmp_path):
    d = checkerboard_dpj().with_palette([[10, 20, 30], [200, 210, 220]])
    d.meta["source"] = "hand"
    d.save(tmp_path / "c.dpj")
    back = DPJ.load(tmp_path / "c.dpj")
    assert back == d and back.meta["source"] == "hand"
    with np.load(tmp_path / "c.dpj", allow_pickle=False) as z:
        assert z["configs"].shape == (2, 2, 2) and z["configs"].dtype == np.uint8
        assert json.loads(str(z["meta"]))["window"] == [2, 2]


def _npz(**arrays):
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def _meta(levels=2, window=(2, 2)):
    return np.array(json.dumps({"levels": levels, "window": list(window)}))


GOOD = dict(configs=np.zeros((1, 2, 2), np.uint8), probs=np.ones(1), meta=_meta())


@pytest.mark.parametrize("change,message", [
    ({"configs": np.zeros((1, 3, 2), np.uint8)}, "shape"),
    ({"configs": np.zeros((1, 2, 2), np.int64)}, "uint8"),
    ({"probs": np.array([np.nan])}, "NaN"),
    ({"probs": np.array([-0.5])}, "outside"),
    ({"probs": np.ones(2)}, "shape"),
    ({"configs": np.full((1, 2, 2), 2, np.uint8)}, "level 2"),
    ({"meta": np.array("{not json")}, "JSON"),
    ({"meta": _meta(levels=40)}, "out of range"),
    ({"probs": np.array([object()], dtype=object)}, "unsafe"),
])
def test_bad_dpj_files_are_clear_errors(change, message):
    with pytest.raises(FormatError, match=message):
        DPJ.from_bytes(_npz(**{**GOOD, **change}))


def test_foreign_members_and_non_zip_are_refused():
    with pytest.raises(FormatError, match="exactly"):
        DPJ.from_bytes(_npz(**GOOD, extra=np.zeros(1)))
    with pytest.raises(FormatError, match="not a DPJ"):
        DPJ.from_bytes(b"hello")
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("configs.npy", b"x" * 10)
    with pytest.raises(FormatError):
        DPJ.from_bytes(buf.getvalue())


def test_a_header_declaring_terabytes_is_refused_before_allocating():
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        header, {"descr": "|u1", "fortran_order": False, "shape": (10**12, 2, 2)})
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("configs.npy", header.getvalue() + b"\0" * 16)
        for key in ("probs", "meta"):
            member = io.BytesIO()
            np.save(member, GOOD[key])
            z.writestr(f"{key}.npy", member.getvalue())
    with pytest.raises(FormatError, match="declares"):
        DPJ.from_bytes(buf.getvalue())


CONFIGS = np.array([[[0, 0], [0, 1]], [[0, 1], [1, 0]], [[1, 0], [0, 1]]])


@pytest.mark.parametrize("make, message", [
    (lambda: DPJ(CONFIGS + 0.5, [0.2, 0.3, 0.5], 2), "whole levels"),
    (lambda: DPJ(CONFIGS.astype(str), [0.2, 0.3, 0.5], 2), "configurations"),
    (lambda: DPJ([[[0, 0], [0]], [[1, 1], [1, 1]]], [0.5, 0.5], 2), "configurations"),
    (lambda: DPJ(CONFIGS, [0.2, 0.3, 0.5], 2.5), "whole number"),
    (lambda: DPJ(CONFIGS, [0.2, 0.3, 0.5], "2"), "whole number"),
    (lambda: DPJ(CONFIGS, ["a", "b", "c"], 2), "probabilities"),
    (lambda: DPJ(CONFIGS, [0.2, 0.3, 0.5j], 2), "probabilities"),
    (lambda: DPJ(CONFIGS, [0.2, 0.3, 0.5], 2, meta=[1]), "meta"),
    (lambda: DPJ.from_codes([99], [1.0], 2, (2, 2)), "codes"),
    (lambda: DPJ.from_codes([-1], [1.0], 2, (2, 2)), "codes"),
    (lambda: DPJ.from_codes([2**70], [1.0], 2, (2, 2)), "codes"),
    (lambda: estimate_dpj(np.full((9, 9), np.nan), (2, 2), 2), "integers"),
    (lambda: estimate_dpj(np.zeros((9, 9), int), (2.5, 2), 2), "whole number"),
    (lambda: estimate_dpj(np.zeros((9, 9), int), (2, 2), 4.5), "whole number"),
    (lambda: estimate_dpj(np.zeros((9, 9), int), (2, 2), 2, meta=[1, 2]), "meta"),
    (lambda: synthesize(estimate_dpj(np.eye(9, dtype=int), (2, 2), 2), (float("inf"), 8)),
     "size"),
    (lambda: DPJ(CONFIGS, [1e308] * 3, 2).normalized(), "sum to inf"),
    (lambda: synthesize(estimate_dpj(np.eye(9, dtype=int), (2, 2), 2), (8, 8), seed=2**64),
     "seed"),                        # drawn, it could not be kept in a recipe (63 bits)
])
def test_the_python_calls_refuse_what_is_not_a_dpj_by_name(make, message):
    """What the Python calls are given is checked as a file is: 2.5 levels, "2", a fraction in
    a configuration or a code past G^(u·v) were truncated, read or wrapped into another
    configuration without a word, and strings, ragged lists, NaN or infinity escaped as raw
    numpy errors (ValueError, OverflowError, UFuncTypeError)."""
    with pytest.raises(InputError, match=message):
        make()
    assert DPJ(CONFIGS.astype(float), [0.2, 0.3, 0.5], 2).configs.dtype == np.uint8   # 1.0: fine
    assert len(DPJ(CONFIGS, [np.nan, -1.0, 0.5], 2).report().lines()) > 0   # hand entry, checked


def test_a_file_of_deflated_zeros_declaring_too_many_entries_is_refused_unread(monkeypatch):
    """A few hundred KB of deflated zeros declaring 40 million entries took 612 MB before
    "more than 4000000 entries": the count is read from the header, before numpy inflates."""
    import texeditor.markov.dpj as dpj_module
    big = DPJ.from_codes(np.arange(200), np.full(200, 1 / 200), 2, (3, 3))
    monkeypatch.setattr(dpj_module, "MAX_ENTRIES", 100)
    monkeypatch.setattr(np, "load", lambda *a, **k: pytest.fail("inflated before refused"))
    with pytest.raises(FormatError, match="at most 100 entries"):
        DPJ.from_bytes(big.to_bytes())
