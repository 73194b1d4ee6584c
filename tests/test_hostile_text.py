"""Integers and text from outside (issue 17, class 3): a clear error, never a traceback."""

import subprocess
import sys

import pytest

from texeditor import peano


def run_cli(*args, timeout=60):
    return subprocess.run([sys.executable, "-m", "texeditor.cli", *args], capture_output=True,
                          timeout=timeout)


@pytest.mark.parametrize("expression", ["1²", "²", "1 > ³", "2⁰"])
def test_a_superscript_digit_in_a_dominance_expression_is_a_dominance_error(expression):
    with pytest.raises(peano.DominanceError):
        peano.parse_dominance(expression)


def test_decimal_digits_int_reads_still_parse():
    assert peano.parse_dominance("١") == peano.parse_dominance("1")      # as before


@pytest.mark.parametrize("args", [["show", str(2**64)], ["render", str(2**63), "-o", "x.png"],
                                  ["search", "--like", str(2**64)], ["export", "-5", "-o", "x"],
                                  ["search", "--limit", str(-2**70)], ["show", "abc"]])
def test_entry_ids_out_of_range_exit_2_in_one_line(args, tmp_path):
    out = run_cli("bank", *args, "--bank", str(tmp_path / "b.db"))
    assert out.returncode == 2, out.stderr
    assert b"Traceback" not in out.stderr and out.stderr.strip().count(b"\n") <= 2


def test_text_that_is_not_utf8_exits_2(tmp_path):
    bank = str(tmp_path / "b.db")
    for args in (["search", b"\xff\xfe"], ["search", "--tag", b"a\xed\xa0\x80"]):
        out = run_cli("bank", *args, "--bank", bank)
        assert out.returncode == 2 and b"UTF-8" in out.stderr and b"Traceback" not in out.stderr


def test_a_texture_whose_file_name_is_not_utf8_is_added(tmp_path):
    from texeditor.resources import ROOT
    dpj = next((ROOT / "dpj").glob("*.dpj"))
    name = tmp_path.as_posix().encode() + b"/x\xff.texture"
    assert run_cli("synth", str(dpj), "--size", "8x8", "-o", name).returncode == 0
    out = run_cli("bank", "add", name, "--bank", str(tmp_path / "b.db"))
    assert out.returncode == 0, out.stderr
    assert "X\ufffd".encode() in out.stdout
