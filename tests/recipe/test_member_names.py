"""Issue 17, class 3: a name ending in a newline never passes a `^…$` pattern (`$` matches
before a final newline): member names and references are matched whole (fullmatch)."""

from texeditor.recipe import texturefile as tf


def test_a_trailing_newline_is_not_a_reference_or_member():
    ref = "0123456789abcdef"[:tf.REF_LENGTH]
    assert tf._OTHER_DPJ.fullmatch(f"dpjs/{ref}.npz")
    assert not tf._OTHER_DPJ.fullmatch(f"dpjs/{ref}.npz\n")
    assert tf._REF.fullmatch(ref) and not tf._REF.fullmatch(ref + "\n")
