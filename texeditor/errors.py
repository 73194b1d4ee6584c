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


def check_unicode(text: str, what: str) -> str:
    """``text`` if it can be written as UTF-8; a lone surrogate (a file name or an argument that
    was not UTF-8, passed on) is an InputError naming ``what``, not a UnicodeEncodeError later."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        shown = text.encode("utf-8", "replace").decode("utf-8")
        raise InputError(f"{what} is not valid Unicode text (it holds a lone surrogate): "
                         f"{shown!r:.80}") from None
    return text
