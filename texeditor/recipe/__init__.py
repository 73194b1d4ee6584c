"""The recipe (thesis §5.4): a texture is the log of Actions that made it.

`Action` and its parameters, the `Document` Actions change, the `History` that undoes and edits
them, the log codec, the one replay loop, stored recipes opened and verified, log optimisation,
the crash journal and `.texture` files.
"""

from .actions import Action, param, register, registry
from .codec import action_from_json, log_text, read_log
from .document import Document
from .history import Change, History
from .replay import replay
from .stored import Recipe, open_recipe
from .texturefile import load_texture, read_texture, render_texture, save_texture

__all__ = ["Action", "param", "register", "registry", "action_from_json", "log_text",
           "read_log", "Document", "Change", "History", "replay", "Recipe", "open_recipe",
           "load_texture", "read_texture", "render_texture", "save_texture"]
