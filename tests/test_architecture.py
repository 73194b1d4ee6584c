"""The shape of the code (issue 18): the engine's imports form no cycle and never reach the GUI,
the console script runs headless commands without Qt, and no module reaches into another's
private members — in particular nothing but `recipe/document.py` touches a Document's."""

import ast
import subprocess
import sys

from tests.support import ROOT
from texeditor.recipe.document import Document

ENGINE = ROOT / "texeditor"
GUI_MODULES = ("app", "PySide6", "pyqtgraph", "shiboken6")


def module_name(path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(path) -> list[tuple[str, str | None]]:
    """(module, name) of every import in a file, function-level (lazy) ones included, resolved
    to absolute module names; ``name`` is the imported name of a ``from`` import."""
    package = module_name(path) if path.name == "__init__.py" else \
        module_name(path).rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found += [(alias.name, None) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                parts = parts[:len(parts) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            found += [(base, alias.name) for alias in node.names]
    return found


def engine_graph() -> dict[str, set[str]]:
    """Module → the engine modules it imports (``from pkg import mod`` counts as ``pkg.mod``)."""
    files = {module_name(p): p for p in ENGINE.rglob("*.py")}
    graph = {}
    for name, path in files.items():
        edges = set()
        for module, imported in imports(path):
            if f"{module}.{imported}" in files:
                edges.add(f"{module}.{imported}")
            elif module in files:
                edges.add(module)
        graph[name] = edges - {name}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every strongly connected set of more than one module (Tarjan)."""
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                found.append(sorted(group))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_the_engine_has_no_import_cycle():
    graph = engine_graph()
    assert len(graph) > 40 and graph["texeditor.recipe.history"]      # the scan sees the engine
    assert cycles(graph) == []


def test_the_cycle_finder_finds_a_cycle():
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_the_engine_never_imports_the_gui():
    wrong = [(module_name(p), module) for p in ENGINE.rglob("*.py")
             for module, _ in imports(p) if module.split(".")[0] in GUI_MODULES]
    assert wrong == []


def test_each_idea_is_one_package_one_level_deep():
    packages = {p.parent.name for p in ENGINE.glob("*/__init__.py")}
    assert packages == {"markov", "regions", "paint", "spots", "texture", "photo", "relief",
                        "recipe", "bank", "spectral", "pyramid", "fractal", "flow"}
    assert not list(ENGINE.glob("*/*/__init__.py"))


def test_headless_commands_of_the_console_script_never_import_qt(tmp_path):
    dpj = ROOT / "resources" / "dpj" / "brick-2x3-g4.dpj"
    code = ("import sys; from app.main import main; "
            f"code = main(['synth', {str(dpj)!r}, '--size', '16x12', '-o', {str(tmp_path / 'o.png')!r}]); "
            "qt = sorted(m for m in sys.modules if m.split('.')[0] in ('PySide6', 'pyqtgraph')); "
            "print(code, qt)")
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip().endswith("0 []") and (tmp_path / "o.png").exists()


# -- private members ---------------------------------------------------------------------------

def own_members(tree) -> set[str]:
    """The private names a module defines for its own classes: methods, attributes it assigns
    on self or cls, class-level names and slots."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            names.add(node.name)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store) \
                and isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"):
            names.add(node.attr)
        elif isinstance(node, ast.ClassDef):
            for item in node.body:
                targets = item.targets if isinstance(item, ast.Assign) else (
                    [item.target] if isinstance(item, ast.AnnAssign) else [])
                for target in targets:
                    if isinstance(target, ast.Name):
                        names.add(target.id)
                        if target.id == "__slots__":
                            names.update(ast.literal_eval(item.value))
    return {n for n in names if n.startswith("_")}


def foreign_private_uses(path, allowed=frozenset()) -> list[str]:
    """``x._name`` (x not self, cls or super()) where the module defines no ``_name`` of its
    own, and ``from engine_module import _name``."""
    tree = ast.parse(path.read_text())
    mine = own_members(tree) | allowed
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr.startswith("_") \
                and not node.attr.startswith("__") and node.attr not in mine:
            base = node.value
            if isinstance(base, ast.Name) and base.id in ("self", "cls"):
                continue
            if isinstance(base, ast.Call) and ast.unparse(base.func) == "super":
                continue
            found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {ast.unparse(node)}")
        elif isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith(
                ("texeditor", "app"))):
            found += [f"{path.relative_to(ROOT)}:{node.lineno}: import of {a.name}"
                      for a in node.names if a.name.startswith("_") and a.name != "__version__"]
    return found


def test_no_module_uses_another_modules_private_members():
    pyqtgraph_internals = frozenset({"_renderRequired"})
    files = list(ENGINE.rglob("*.py")) + list((ROOT / "app").rglob("*.py"))
    assert len(files) > 80
    wrong = [line for path in files for line in foreign_private_uses(path, pyqtgraph_internals)]
    assert wrong == []


def document_private_names() -> set[str]:
    doc = Document()
    return {n for n in set(vars(Document)) | set(vars(doc))
            if n.startswith("_") and not n.startswith("__")}


def test_nothing_but_the_document_touches_its_private_members():
    """Actions, History, files, the bank, the GUI, benchmarks and tests use the public edit
    interface (``doc._write`` and the like are refused anywhere else)."""
    private = document_private_names()
    assert {"_levels", "_palette", "_log", "_recorder"} <= private
    folders = ("texeditor", "app", "tests", "benchmarks", "docs", "resources")
    wrong = []
    for path in (p for folder in folders for p in (ROOT / folder).rglob("*.py")):
        if path == ENGINE / "recipe" / "document.py":
            continue
        tree = ast.parse(path.read_text())
        mine = own_members(tree)
        wrong += [f"{path.relative_to(ROOT)}:{node.lineno}: {ast.unparse(node)}"
                  for node in ast.walk(tree)
                  if isinstance(node, ast.Attribute) and node.attr in private - mine
                  and not (isinstance(node.value, ast.Name) and node.value.id == "self")]
    assert wrong == []


def test_the_private_access_scan_sees_a_violation(tmp_path):
    bad = ROOT / "tests" / "_probe_private.py"
    try:
        bad.write_text("def f(doc):\n    doc._write(0, 0, 1)\n    return doc.levels\n")
        assert foreign_private_uses(bad) == ["tests/_probe_private.py:2: doc._write"]
    finally:
        bad.unlink()
