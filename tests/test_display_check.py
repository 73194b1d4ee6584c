"""The check before Qt starts: a missing display or X11 library is a clear message, not an abort."""

from __future__ import annotations

import pytest

from app import display_check
from app.main import run

LDD = """\tlinux-vdso.so.1 (0x00007ffd)
\tlibxcb-icccm.so.4 => not found
\tlibxcb.so.1 => /lib/x86_64-linux-gnu/libxcb.so.1 (0x00007f)
\tlibxkbcommon-x11.so.0 => not found
\tlibxcb-icccm.so.4 => not found
\tlibX11-xcb.so.1 => not found
"""


def test_ldd_output_gives_each_missing_library_once():
    assert display_check.not_found(LDD) == ["libxcb-icccm.so.4", "libxkbcommon-x11.so.0",
                                            "libX11-xcb.so.1"]
    assert display_check.not_found("\tlibc.so.6 => /lib/libc.so.6 (0x1)\n") == []


@pytest.mark.parametrize("soname, package", [
    ("libxcb-icccm.so.4", "libxcb-icccm4"), ("libxcb-cursor.so.0", "libxcb-cursor0"),
    ("libxkbcommon-x11.so.0", "libxkbcommon-x11-0"), ("libX11-xcb.so.1", "libx11-xcb1"),
    ("libxcb-render-util.so.0", "libxcb-render-util0"), ("weird", "weird")])
def test_debian_package_names(soname, package):
    assert display_check.debian_package(soname) == package


@pytest.fixture
def linux_x11(monkeypatch):
    monkeypatch.setattr(display_check.sys, "platform", "linux")
    for name in ("QT_QPA_PLATFORM", "WAYLAND_DISPLAY"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("DISPLAY", ":0")


def test_no_display_is_said_and_the_exit_code_is_2(linux_x11, monkeypatch, capsys):
    monkeypatch.delenv("DISPLAY")
    assert run([]) == 2
    err = capsys.readouterr().err
    assert "no display" in err and "--screenshot" in err


def test_missing_x11_libraries_are_named_with_the_packages(linux_x11, monkeypatch, capsys):
    monkeypatch.setattr(display_check, "missing_libraries",
                        lambda path: display_check.not_found(LDD))
    assert run([]) == 2
    err = capsys.readouterr().err
    assert "libxkbcommon-x11.so.0" in err
    assert "sudo apt-get install libxcb-icccm4 libxkbcommon-x11-0 libx11-xcb1" in err


def test_a_chosen_platform_or_wayland_is_left_to_qt(linux_x11, monkeypatch):
    monkeypatch.setattr(display_check, "missing_libraries", lambda path: ["libxcb.so.1"])
    assert display_check.problem() is not None
    monkeypatch.setenv("QT_QPA_PLATFORM", "offscreen")
    assert display_check.problem() is None
    monkeypatch.delenv("QT_QPA_PLATFORM")
    monkeypatch.setenv("WAYLAND_DISPLAY", "wayland-0")
    assert display_check.problem() is None


def test_this_machine_s_plugin_is_checked_with_ldd(linux_x11):
    """The real ldd on the real plugin: every name it reports is a library, never a crash."""
    plugin = display_check._xcb_plugin()
    assert plugin is not None and plugin.name == "libqxcb.so"      # where PySide6 keeps it
    assert all(".so" in name for name in display_check.missing_libraries(plugin))
