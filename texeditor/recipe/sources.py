"""Recipes as sources: how a step names another texture (a composition source, a spot's fill).

How a log refers to another texture. A composition source, or the texture a spot is filled
with (`spots.actions`), is a *recipe*: the action log that rebuilds it, as the JSON text of a
`.texture`'s actions.json (``{"actions": [...]}``), plus the DPJs it needs, which the document
keeps in its DPJ store (so a saved file carries them, like any DPJ it refers to). A synthesis of
a stored DPJ is the one-step recipe ``[Synthesize(ref, w, h, seed)]``; an opened `.texture` is
its own log; "this document at step k" is its log cut at k; a bank entry is its optimised log,
replayed once when it is chosen and checked against the SHA-256 the bank recorded
(`bank_source`). The step carries the whole recipe, so it replays bit for bit after save and load
even if the bank entry is later changed or deleted. Replaying a recipe gives the same levels on
every machine, and the result is kept in a small memo so a preview and the apply that follows it
synthesise once. A doubling table is a DPJ (`doubling.learn`) in the same store, referred to by
its reference.

Any number of DPJs per recipe, at any depth. A step names the DPJs of each recipe it carries in a
parameter of kind "refs" (a list of references: ``source_dpjs``, ``mask_dpjs``, a spot's
``texture_dpjs``), and that list must be exactly the DPJs the recipe's log names (`check_recipe`),
its own "refs" parameters included. A recipe may itself hold a composition or a texture spot
whose recipe needs DPJs (a bank entry that was a composition, used again): its step names them,
so the outer step names them too, and `recipe.actions.dpj_refs` of any log is every DPJ needed at every
depth without opening a recipe. That list is what a saved file and a bank entry carry, and
replaying a recipe on a scratch document holding just those DPJs gives the same levels after
save and load. Limits, each refused with a message: recipes nest at most MAX_RECIPE_DEPTH deep, a
recipe needs at most MAX_RECIPE_DPJS DPJs, and its text (the recipes nested in it included) is at
most MAX_RECIPE_CHARS characters.

Versions. Mix and Incrust version 1 (and spot placements version 1, see `spot_actions`) named a
recipe's one DPJ, or none, in a "ref" parameter (``source_dpj``, ``mask_dpj``); version 2 lists
them. `Action.upgrade` turns version-1 JSON into version 2 on load (`upgrade_ref`): the same steps,
the same levels.
"
"""

from __future__ import annotations

import dataclasses
import hashlib
import threading
from dataclasses import dataclass

import numpy as np

from ..errors import FormatError, InputError
from .actions import Action, Synthesize, dpj_refs, param
from .cache import Cache
from .codec import log_text, read_log
from .replay import replay

MAX_RECIPE_CHARS = 2**24       # a recipe's text, the recipes nested in it included
MAX_RECIPE_ACTIONS = 100_000
MAX_RECIPE_DEPTH = 8           # a recipe in a recipe in a recipe… at most this many levels
MAX_RECIPE_DPJS = 32           # the DPJs one recipe needs, at every depth together


_RECIPES = Cache(max_items=6, max_bytes=512 * 2**20)   # (levels, G) of recent recipes


# -- recipes: how a composition names another texture ---------------------------------------------

def recipe_of(actions) -> str:
    """The canonical text of a log (compact JSON)."""
    return log_text(actions)


def synthesis_recipe(ref: str, width: int, height: int, seed: int) -> str:
    """The recipe of one synthesis of a stored DPJ."""
    return recipe_of([Synthesize(ref, width, height, seed)])


class _TooDeep(Exception):
    """Recipes nested deeper than MAX_RECIPE_DEPTH: raised where it is found, and turned into one
    InputError by the outermost recipe (not wrapped again by every level in between)."""


_NESTING = threading.local()


def parse_recipe(text: str) -> tuple[Action, ...]:
    """The actions of a recipe, every one checked (InputError says what is wrong). The recipes
    inside it are parsed as its actions are made, one level deeper each: the depth is counted
    here, per thread, so a too deep nesting is refused before it is all read."""
    depth = getattr(_NESTING, "depth", 0) + 1
    if depth > MAX_RECIPE_DEPTH:
        raise _TooDeep
    _NESTING.depth = depth
    try:
        return _parse_recipe(text)
    except _TooDeep:
        if depth > 1:
            raise
        raise InputError(f"texture recipes nest at most {MAX_RECIPE_DEPTH} deep (a source whose "
                         "log composes a source whose log composes…): choose a texture made "
                         "with fewer levels of composition") from None
    finally:
        _NESTING.depth = depth - 1


def _parse_recipe(text: str) -> tuple[Action, ...]:
    if not isinstance(text, str):
        raise InputError("a texture recipe is a JSON text")
    return read_log(text, "the texture recipe", max_actions=MAX_RECIPE_ACTIONS,
                    max_bytes=MAX_RECIPE_CHARS, min_actions=1, error=InputError)


def check_recipe(text: str, refs: tuple, what: str) -> None:
    """A valid recipe whose DPJs are exactly ``refs``: every DPJ its log names, the DPJs of the
    recipes nested in it included (their steps name them in turn), so a log's `dpj_refs` is
    all a saved file or a bank entry must carry. Order does not matter."""
    used = dpj_refs(parse_recipe(text))
    if len(used) > MAX_RECIPE_DPJS:
        raise InputError(f"{what} is made from {len(used)} DPJs; a texture used as a source may "
                         f"use at most {MAX_RECIPE_DPJS}")
    missing = [r for r in used if r not in refs]
    if missing:
        raise InputError(f"{what} uses DPJ {', '.join(missing)}, which the step does not name "
                         f"(it names {', '.join(refs) or 'none'})")
    extra = [r for r in refs if r not in used]
    if extra:
        raise InputError(f"{what} does not use DPJ {', '.join(extra)}, which the step names")


def render_recipe(text: str, dpjs: dict, progress=None, cancel=None) -> tuple[np.ndarray, int]:
    """(levels, G) of a recipe replayed on an empty document with ``dpjs`` (reference → DPJ, a
    reference naming its DPJ's content); memoised."""
    wrong = sorted(r for r, d in dpjs.items() if not d.has_ref(r))
    if wrong:      # the memo is keyed by references: each must name its DPJ
        raise InputError(f"DPJ {', '.join(wrong)} of a texture recipe is another DPJ's content")
    hit = _RECIPES.get(_recipe_key(text, dpjs))
    if hit is not None:
        return hit
    doc = replay(parse_recipe(text), dpjs, progress=progress, cancel=cancel)
    if not doc.levels.size:
        raise InputError("the texture recipe gives an empty canvas")
    return _remember(text, dpjs, doc)


def _recipe_key(text: str, dpjs: dict) -> tuple:
    return (hashlib.sha256(text.encode("utf-8")).hexdigest(), tuple(sorted(dpjs)))


def _remember(text: str, dpjs: dict, doc) -> tuple[np.ndarray, int]:
    levels = doc.levels.copy()
    levels.flags.writeable = False
    result = (levels, doc.num_levels)
    _RECIPES.put(_recipe_key(text, dpjs), result)
    return result


def recipe_field(doc: str, optional: bool = False):
    return param("str", hi=MAX_RECIPE_CHARS, default=None if optional else dataclasses.MISSING,
                 optional=optional, doc=doc)


def refs_field(doc: str):
    """The DPJs a recipe needs, at every depth (see `check_recipe`)."""
    return param("refs", hi=MAX_RECIPE_DPJS, default=(), doc=doc)


def source_levels(doc, text: str, refs: tuple, progress=None, cancel=None):
    """(levels, G) of a recipe whose DPJs ``refs`` are in the document's store."""
    missing = [r for r in refs if r not in doc.dpjs]
    if missing:
        raise InputError(f"DPJ {', '.join(missing)} of a texture recipe is not part of this "
                         "document")
    return render_recipe(text, {r: doc.dpjs[r] for r in refs}, progress, cancel)


def upgrade_ref(params: dict, old: str, new: str) -> dict:
    """Version-1 JSON named a recipe's one DPJ (or none) in ``old``; now ``new`` lists them."""
    if new in params:
        raise FormatError(f"version 1 has no parameter {new!r} (it names one DPJ in {old!r})")
    params = dict(params)
    ref = params.pop(old, None)
    params[new] = [] if ref is None else [ref]
    return params


@dataclass(frozen=True)
class TextureSource:
    """A texture ready to be named by a step: its recipe, the DPJs it needs at every depth (their
    references, and the DPJs themselves for the document's store), its number of levels G, a
    name."""

    recipe: str
    refs: tuple
    dpjs: dict
    levels: int
    name: str

    def store(self, doc) -> None:
        """Keep the recipe's DPJs in ``doc`` (before a step that names them is made)."""
        for dpj in self.dpjs.values():
            doc.store_dpj(dpj)


def bank_source(bank, entry_id: int, progress=None, cancel=None) -> TextureSource:
    """A bank entry (of a `bank.Bank`) as a recipe: its log and every DPJ it needs.

    The entry is replayed here and must give the texture the bank recorded (its SHA-256), so a
    damaged entry is refused before a step names it; the levels stay in the memo for the preview
    or the apply that follows. Slow: call it in a worker."""
    entry, recipe = bank.get(entry_id), bank.recipe(entry_id)
    refs = tuple(dpj_refs(recipe.actions))
    text = recipe_of(recipe.actions)
    check_recipe(text, refs, f"bank entry {entry.id} “{entry.name}”")
    doc = bank.render(entry_id, progress=progress, cancel=cancel)     # hash checked
    dpjs = {r: recipe.dpjs[r] for r in refs}
    _remember(text, dpjs, doc)
    return TextureSource(text, refs, dpjs, doc.num_levels, entry.name)
