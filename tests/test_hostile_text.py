"""Integers and text from outside (issue 17, class 3): a clear error, never a traceback."""

import subprocess
import sys

import pytest

from texeditor.paint import peano


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


LONE = "moss\udc80"


def test_a_lone_surrogate_given_to_the_python_api_is_an_input_error(tmp_path):
    from texeditor.recipe.actions import NewCanvas
    from texeditor.bank.store import Bank, check_description, check_name, normalize_tags, parse_query
    from texeditor.recipe.document import Document
    from texeditor.errors import InputError
    from texeditor.recipe.texturefile import save_texture
    for call in (lambda: normalize_tags([LONE]), lambda: normalize_tags(LONE + ",stone"),
                 lambda: check_name(LONE), lambda: check_description(LONE),
                 lambda: parse_query(f"tag:{LONE}")):
        with pytest.raises(InputError, match="lone surrogate"):
            call()
    doc = Document()
    doc.apply(NewCanvas(8, 8, 2))
    target = tmp_path / "t.texture"
    with pytest.raises(InputError, match="lone surrogate"):
        save_texture(target, doc, tags=[LONE])
    with pytest.raises(InputError, match="lone surrogate"):
        save_texture(target, doc, description=LONE)
    assert not target.exists()
    bank = Bank(tmp_path / "b.db")
    before = bank.search()
    with pytest.raises(InputError, match="lone surrogate"):
        bank.add(doc, name="moss", tags=[LONE])
    assert bank.search() == before


def test_a_lone_surrogate_escaped_in_a_texture_manifest_is_a_format_error(tmp_path):
    import io
    import json
    import zipfile
    from texeditor.errors import FormatError
    from texeditor.recipe.texturefile import parse_texture
    from texeditor.recipe.actions import NewCanvas
    from texeditor.recipe.document import Document
    from texeditor.recipe.texturefile import texture_bytes
    doc = Document()
    doc.apply(NewCanvas(8, 8, 2))
    data, _ = texture_bytes(doc, doc.actions)
    src = zipfile.ZipFile(io.BytesIO(data))
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as zf:
        for info in src.infolist():
            body = src.read(info)
            if info.filename == "manifest.json":
                manifest = json.loads(body)
                manifest["tags"] = [LONE]
                body = json.dumps(manifest).encode()     # ASCII: "\udc80" as an escape
            zf.writestr(info.filename, body)
    with pytest.raises(FormatError, match="lone surrogate"):
        parse_texture(out.getvalue())
