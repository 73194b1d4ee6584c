"""The DPJ editor (thesis §5.2.2): a DPJ entered by hand with a probability palette, checked,
generated, previewed live, and handed to the main window as its current DPJ."""

from .window import DPJEditor, NewDPJDialog, confirm_close, hand_made, open_editor

__all__ = ["DPJEditor", "NewDPJDialog", "confirm_close", "hand_made", "open_editor"]
