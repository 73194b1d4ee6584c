"""One exception family for the whole engine.

Every failure a user can cause (a bad file, a bad parameter) is a ``TexeditorError`` whose message
says what to do; the CLI prints it on one line with exit code 2 and the GUI shows it in a dialog.
"""


class TexeditorError(Exception):
    """Base of every error the engine reports to a user."""


class InputError(TexeditorError, ValueError):
    """A parameter is out of range or inconsistent (window larger than the image, G > 16, ...)."""


class ImageError(TexeditorError):
    """An image file cannot be read or cannot be used (unreadable, empty, constant, too large)."""


class FormatError(TexeditorError):
    """A `.dpj`, `.texture` or bank record is malformed, hostile or of an unknown version."""


class ReplayError(TexeditorError):
    """Replaying an action log did not give the recorded result (hash mismatch)."""


class Cancelled(TexeditorError):
    """Long work was cancelled by the user; nothing was changed."""
