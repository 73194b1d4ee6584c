"""Issue 17, class 4: one bad file of the user data folder never stops the application.

Every start runs in a subprocess with a timeout, so a hang (a FIFO read, a modal dialog in
--screenshot mode) fails the test instead of blocking the suite. A bad file is set aside
(renamed ``<name>.bad-<UTC time>``, never deleted) and named in one message."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HUGE_TIME = "1" + "0" * 400           # 10**400: no float holds it

SCREENSHOT = "import sys; from app.main import run; sys.exit(run(sys.argv[1:]))"
RECOVERY = textwrap.dedent("""
    import sys
    from PySide6 import QtWidgets
    app = QtWidgets.QApplication([])
    from app.recovery import RecoveryDialog
    RecoveryDialog.open = lambda self: self.accept()                    # Restore all
    def modal(*a, **k):
        print("MODAL DIALOG", a[1:3], file=sys.stderr)
        sys.exit(3)
    QtWidgets.QMessageBox.critical = QtWidgets.QMessageBox.warning = modal
    from app.main_window import MainWindow
    from app.recovery import offer_recovery
    window = MainWindow()
    window.show()
    offer_recovery(window)
    window.runner.wait(60_000)
    print("restored", 0 if window.history is None else 1)
    print("status", window.statusBar().currentMessage())
    window.journal_discard()
""")


def start(data: Path, code: str, *args: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "QT_QPA_PLATFORM": "offscreen", "TEXEDITOR_DATA": str(data),
           "TEXEDITOR_BANK": str(data / "bank.sqlite")}
    return subprocess.run([sys.executable, "-c", code, *args], env=env, capture_output=True,
                          text=True, timeout=120, cwd=ROOT)


def set_aside(folder: Path, name: str) -> list[Path]:
    return sorted(folder.glob(f"{name}.bad-*"))


def journal(folder: Path, time_field: str, logs: int = 2) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "1234-abcdef123456.journal"
    lines = [f'{{"kind":"start","format":1,"time":{time_field},"source":null}}']
    lines += ['{"kind":"log","keep":0,"append":[]}'] * logs
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("time_field", [HUGE_TIME, "-" + HUGE_TIME, "1e400", "NaN", "Infinity",
                                        "-1", "true", '"yesterday"'])
def test_a_journal_with_an_impossible_time_is_still_offered(tmp_path, time_field):
    journal(tmp_path / "journals", time_field)
    proc = start(tmp_path, RECOVERY)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "restored 1" in proc.stdout
    assert not (tmp_path / "journals" / "1234-abcdef123456.journal").exists()


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_folder_and_a_fifo_named_like_journals_are_set_aside(tmp_path):
    folder = tmp_path / "journals"
    folder.mkdir()
    (folder / "1-aaaaaaaaaaaa.journal").mkdir()
    (folder / "1-aaaaaaaaaaaa.journal" / "inside").write_text("kept")
    os.mkfifo(folder / "2-bbbbbbbbbbbb.journal")
    (folder / "3-cccccccccccc.journal").symlink_to(folder / "nowhere")
    (folder / "4-dddddddddddd.journal").write_bytes(b"\x00garbage\xff")
    proc = start(tmp_path, RECOVERY)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "restored 0" in proc.stdout
    status = proc.stdout.split("status", 1)[1]
    for name in ("1-aaaaaaaaaaaa.journal", "2-bbbbbbbbbbbb.journal", "3-cccccccccccc.journal",
                 "4-dddddddddddd.journal"):
        assert not os.path.lexists(folder / name)
        [moved] = set_aside(folder, name)
        assert name in status and moved.name in status
    [moved] = set_aside(folder, "1-aaaaaaaaaaaa.journal")
    assert (moved / "inside").read_text() == "kept"            # set aside, never deleted
    assert len(status.strip().splitlines()) == 1                 # one message
    proc = start(tmp_path, RECOVERY)                             # and the next start is clean
    assert proc.returncode == 0 and "restored 0" in proc.stdout
    assert proc.stdout.split("status", 1)[1].strip() == ""


def bad_libraries(data: Path) -> dict[str, bytes | None]:
    """A bad grains, brushes and spots library each (None: a FIFO)."""
    deep = b'{"format":"texeditor-brushes","version":1,"items":[' + b"[" * 5000 + b"]" * 5000 \
        + b"]}"
    return {"grains.json": b"garbage, not JSON", "brushes.json": deep, "spots.json": None}


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_screenshot_starts_despite_bad_libraries(tmp_path):
    for name, data in bad_libraries(tmp_path).items():
        if data is None:
            os.mkfifo(tmp_path / name)
        else:
            (tmp_path / name).write_bytes(data)
    out = tmp_path / "out.png"
    proc = start(tmp_path, SCREENSHOT, "--screenshot", str(out), "--size", "640x480")
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    message = [line for line in proc.stderr.splitlines() if "set aside" in line]
    assert len(message) == 1, proc.stderr
    for name in bad_libraries(tmp_path):
        assert not os.path.lexists(tmp_path / name)
        [moved] = set_aside(tmp_path, name)
        assert str(tmp_path / name) in message[0] and moved.name in message[0]


@pytest.mark.parametrize("item", [{"name": 7}, {"name": "x", "size": "1e400"},
                                  {"name": "x", "size": 10**40}, {"shape": []}])
def test_a_library_with_a_bad_item_never_stops_the_screenshot(tmp_path, item):
    for name, kind in (("grains.json", "texeditor-grains"), ("brushes.json", "texeditor-brushes")):
        (tmp_path / name).write_text(json.dumps({"format": kind, "version": 1, "items": [item]}))
    out = tmp_path / "out.png"
    proc = start(tmp_path, SCREENSHOT, "--screenshot", str(out), "--size", "640x480")
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert out.exists()
    assert "Traceback" not in proc.stderr
