"""No attribute of an app/ class hides a method of its Qt (or pyqtgraph) base.

``self.shape = (h, w)`` on a QGraphicsItem once crashed the window on the second brush stroke:
pyqtgraph called ``item.shape()`` on every item under the pointer, met a tuple, and shiboken died
reporting the TypeError from inside a Qt virtual call. Two checks, for the class of defect:
every ``self.name = …`` written in a method of a Qt subclass of app/ (read from the source, so
classes that are hard to build are covered too), and the instance attributes of every widget and
graphics item of a live main window with its docks, tools and dialogs built.
"""

import ast
import importlib
import inspect
import pkgutil
import textwrap

import pytest
from PySide6 import QtCore, QtWidgets

import app


def app_modules():
    for info in pkgutil.walk_packages(app.__path__, "app."):
        if info.name.endswith("__main__"):
            continue
        yield importlib.import_module(info.name)


def foreign_bases(cls):
    """The classes of cls's MRO that are not app/'s own (Qt's, pyqtgraph's)."""
    return [b for b in cls.__mro__[1:] if not b.__module__.startswith("app") and b is not object]


def is_qt(cls) -> bool:
    return any(b.__module__.startswith(("PySide6", "pyqtgraph", "shiboken6")) for b in cls.__mro__)


def shadowed(cls, names) -> list[str]:
    """The names among ``names`` that a foreign base of cls defines as something callable."""
    hits = []
    for name in names:
        for base in foreign_bases(cls):
            if callable(base.__dict__.get(name)):
                hits.append(f"{cls.__module__}.{cls.__qualname__}.{name} hides "
                            f"{base.__module__}.{base.__qualname__}.{name}()")
                break
    return hits


def assigned_names(cls) -> set[str]:
    """Every ``self.X = …`` (also augmented and tuple targets) in the methods of cls's body."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(cls)))
    names = set()
    for node in ast.walk(tree):
        targets = []
        if isinstance(node, ast.Assign):
            targets = node.targets
        elif isinstance(node, (ast.AugAssign, ast.AnnAssign)):
            targets = [node.target]
        for target in targets:
            for t in ast.walk(target):
                if (isinstance(t, ast.Attribute) and isinstance(t.value, ast.Name)
                        and t.value.id == "self"):
                    names.add(t.attr)
    return names


def qt_classes():
    seen = set()
    for module in app_modules():
        for _name, cls in inspect.getmembers(module, inspect.isclass):
            if cls.__module__ == module.__name__ and is_qt(cls) and cls not in seen:
                seen.add(cls)
                yield cls


def test_the_source_check_finds_the_crash_it_is_for():
    """The check itself: a QGraphicsObject that stores ``self.shape`` is caught."""
    class Bad(QtWidgets.QGraphicsObject):
        def __init__(self):
            super().__init__()
            self.shape = (2, 2)
            self.rows = 2
    names = assigned_names(Bad)
    assert names == {"shape", "rows"}
    assert shadowed(Bad, names) == [
        f"{__name__}.test_the_source_check_finds_the_crash_it_is_for.<locals>.Bad.shape hides "
        "PySide6.QtWidgets.QGraphicsItem.shape()"]


def test_no_app_class_assigns_an_attribute_named_like_a_qt_method():
    classes = list(qt_classes())
    assert len(classes) > 40          # the walk really reached app/'s widgets and items
    hits = [hit for cls in classes for hit in shadowed(cls, assigned_names(cls))]
    assert hits == []


def live_objects(win) -> list:
    """Every QObject of the window and its dialogs, and every item of its graphics scenes."""
    objs = list(QtWidgets.QApplication.allWidgets()) + win.findChildren(QtCore.QObject)
    for view in [w for w in objs if isinstance(w, QtWidgets.QGraphicsView)]:
        if view.scene() is not None:
            objs += view.scene().items()
    return objs


@pytest.fixture
def user_data(tmp_path, monkeypatch):
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path / "data"))


def test_no_live_widget_or_item_of_a_session_hides_a_qt_method(window, qtbot, user_data):
    """The main window with every tool's options built and the dialogs of the menus opened."""
    for tool in window.tools:
        window.set_tool(tool)
    window.global_operators()
    dialog = window.acquire()
    objs = live_objects(window)
    hits = set()
    for obj in objs:
        cls = type(obj)
        if cls.__module__.startswith("app"):
            own = [k for k, v in vars(obj).items()     # PySide caches bound signals there
                   if not k.startswith("__") and not isinstance(v, QtCore.SignalInstance)]
            hits.update(shadowed(cls, own))
    dialog.reject()
    assert len([o for o in objs if type(o).__module__.startswith("app")]) > 20
    assert sorted(hits) == []
