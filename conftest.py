"""`python3 -m pytest` also runs the engine's docstring examples (the grids of the operators, the
DPJ codes…): every module of texeditor/ is collected as a doctest module, as --doctest-modules
would do, without collecting the test helpers (tests/gui's session runner…) as doctest modules."""

from pathlib import Path

from _pytest.doctest import DoctestModule

ENGINE = Path(__file__).resolve().parent / "texeditor"


def pytest_collect_file(file_path: Path, parent):
    if (file_path.suffix == ".py" and ENGINE in file_path.parents
            and file_path.name != "__main__.py"
            and not parent.config.option.doctestmodules):     # --doctest-modules collects them
        return DoctestModule.from_parent(parent, path=file_path)
    return None
