"""Realistic editing sessions, one per tool family, each in a child process (issue 16).

The second Brush stroke once killed the window with a segfault that no single-gesture test met.
Each session here (tests/gui/sessions.py) makes five or more gestures with real input events —
the same tool twice in a row, a click after a stroke, tools switched midway — checks that each
adds one step of the expected Action, then undoes with Ctrl+Z back to the synthesised texture
and redoes with Ctrl+Shift+Z to the final document. A crash fails the test with the child's
stderr instead of ending pytest.
"""

import pytest

from .session_runner import run_child
from .sessions import SESSIONS


@pytest.mark.parametrize("name", sorted(SESSIONS))
def test_a_session_undoes_to_the_synthesis_and_redoes_to_its_end(name, tmp_path):
    report = run_child(["session", name], tmp_path)
    assert report["session"] == name
    assert report["steps"] >= 5 and len(report["gestures"]) == report["steps"]
    assert report["dialogs"] == []                       # no gesture was refused
    assert report["final_hash"] != report["start_hash"]
    assert not (tmp_path / "data").exists() or not any((tmp_path / "data" / "journals").glob("*"))


def test_a_crash_in_the_child_fails_the_test_and_says_so(tmp_path):
    """The runner's own check: a child that dies of a segfault is reported as a crash."""
    with pytest.raises(pytest.fail.Exception, match=r"CRASHED \(signal 11"):
        run_child(["crash"], tmp_path)
