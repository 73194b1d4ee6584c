"""A stored texture — a `.texture` file's or a bank entry's recipe — opened the one way.

The log is the texture (thesis §5.4): opening one replays its log on its DPJs and checks that the
result is the one recorded (its SHA-256), so a damaged or forged recipe is never shown. Files and
the bank read their own containers, then hand a `Recipe` to ``open_recipe``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ..errors import ReplayError
from .document import Document
from .history import History
from .replay import Cancel, Progress, replay


@dataclass(frozen=True)
class Recipe:
    """What rebuilds a stored texture: its log, the DPJs it needs (ref → DPJ), the DPJ that was
    current, the SHA-256 of the result recorded (None: not checked), a name for messages and
    the exemplar photos its model steps need (ref → uint8 picture)."""

    actions: tuple
    dpjs: dict = field(default_factory=dict)
    current: str | None = None
    sha256: str | None = None
    name: str = "the texture"
    exemplars: dict = field(default_factory=dict)


def open_recipe(recipe: Recipe, *, history: bool = False, prepared: dict | None = None,
                progress: Progress = None, cancel: Cancel = None, **history_options):
    """Replay a recipe into a Document (or, ``history=True``, a History ready for undo and
    edits) and check its result; any failure is a ReplayError naming the recipe.
    ``prepared``: step → its result given (a stored picture standing for a synthesis)."""
    try:
        if history:
            opened = History.from_log(recipe.actions, recipe.dpjs, current=recipe.current,
                                      prepared=prepared, progress=progress, cancel=cancel,
                                      exemplars=recipe.exemplars, **history_options)
            doc = opened.document
        else:
            opened = doc = replay(recipe.actions, recipe.dpjs, current=recipe.current,
                                  prepared=prepared, progress=progress, cancel=cancel,
                                  exemplars=recipe.exemplars)
    except ReplayError as exc:
        raise ReplayError(f"{recipe.name}: {exc}") from None
    verify(doc, recipe)
    return opened


def verify(doc: Document, recipe: Recipe) -> None:
    """The document is the texture the recipe recorded (nothing to check without a hash)."""
    if recipe.sha256 is None:
        return
    got = doc.result_hash()
    if got != recipe.sha256:
        h, w = doc.shape
        raise ReplayError(f"{recipe.name}: replaying its log gives another texture ({w}x{h}, "
                          f"G = {doc.num_levels}, SHA-256 {got[:12]}…) than the one recorded "
                          f"(SHA-256 {recipe.sha256[:12]}…): it is damaged, and not shown")
