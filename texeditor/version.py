"""The release number, in one place (files record it; the package re-exports it)."""

__version__ = "0.1.0"
