"""Keeps every test away from the user's own texture bank and data folder (libraries, crash
journals), as tests/gui keeps QSettings away."""

import pytest


@pytest.fixture(autouse=True)
def isolated_bank(tmp_path_factory, monkeypatch):
    """A test that opens the bank by default (the GUI's start-up, the CLI) gets a fresh one."""
    monkeypatch.setenv("TEXEDITOR_BANK", str(tmp_path_factory.mktemp("bank") / "bank.sqlite"))
    monkeypatch.setenv("TEXEDITOR_DATA", str(tmp_path_factory.mktemp("data")))
    yield
