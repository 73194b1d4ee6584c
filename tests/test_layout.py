"""The tests folder's own rules (issue 18): no test module imports another test module (shared
material lives in tests/support/ and tests/gui/support.py), and every folder of tests is a
package, so that test modules in different folders may share a name (test_actions.py)."""

import ast
from pathlib import Path

TESTS = Path(__file__).resolve().parent


def module_name(path: Path) -> str:
    return ".".join(("tests",) + path.relative_to(TESTS).with_suffix("").parts)


def imported_modules(source: str, module: str) -> list[tuple[int, str]]:
    """(line, dotted name) of every module an import statement of the module may load, relative
    imports resolved; ``from package import name`` counts package.name too (it may be a module)."""
    package = module.rsplit(".", 1)[0]
    found = []
    for node in ast.walk(ast.parse(source, module)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - (node.level - 1)]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module
            found.append((node.lineno, module))
            found += [(node.lineno, f"{module}.{alias.name}") for alias in node.names]
    return found


def is_test_module(dotted: str) -> bool:
    return dotted.rsplit(".", 1)[-1].startswith("test_")


def test_no_test_module_imports_another_test_module():
    offences = [f"{path.relative_to(TESTS.parent)}:{line} imports {name}"
                for path in sorted(TESTS.rglob("*.py"))
                for line, name in imported_modules(path.read_text(), module_name(path))
                if is_test_module(name)]
    assert not offences, "\n".join(offences)


def test_the_scan_sees_every_form_of_import():
    source = ("import test_bank\nfrom test_history import x\nfrom . import test_attributes\n"
              "from .test_bank import drawn\nfrom tests.support.bank import drawn\n"
              "from .. import support\nimport numpy as np\n")
    names = [name for _, name in imported_modules(source, "tests.bank.test_probe")
             if is_test_module(name)]
    assert names == ["test_bank", "test_history", "tests.bank.test_attributes",
                     "tests.bank.test_bank"]


def test_every_folder_of_tests_is_a_package():
    folders = {path.parent for path in TESTS.rglob("test_*.py")} | {TESTS / "support"}
    assert not [str(f) for f in folders if not (f / "__init__.py").is_file()]
