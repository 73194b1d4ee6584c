"""Composition of textures (thesis §5.4.1): incrustation (a membership mask says which texture shows
at each point, point by point or by blocks, the thesis's "pavés") and mixing,
T3 = not[(a op1 T1) op2 (b op3 T2)] op4 c, or an expression over more textures.

It sits after synthesis and before display: the Compose actions of `texture_actions` call these
pure functions on level matrices; nothing here knows about documents, logs or files.

Mixing is defined on the *grey scale* of each texture, so textures of different G mix sensibly:
a level x of a G-level texture stands for x̂ = x / (G − 1) in [0, 1] (0 the background, 1 the top
level); the weights a, b, c live on the same scale. The operators, for x, y in [0, 1]:

=========  ====================================================================================
and        bitwise AND of the level codes round(x·(G−1)) and round(y·(G−1)) — the raster
           operations of a 1984 frame buffer; for G = 2 the truth table of logic
or         bitwise OR of the codes, clipped to G − 1
xor        bitwise XOR of the codes, clipped to G − 1
min, max   the smaller, the larger
add        x + y clipped to 1
multiply   x · y (so "a multiply T1" takes a proportion a of T1: the thesis's proportions)
replace    y where y > 0, else x: the right operand drawn over the left, its background clear
=========  ====================================================================================

``not`` is 1 − x (for G = 2^k it is the bitwise complement of the code). The result goes back to
the target's G levels by rounding half up: level = floor(T3·(G−1) + 1/2). Codes (for the bitwise
operators) are taken on the target's G. Because every input is one of at most 16 levels, the whole
formula is evaluated once per pair of levels into a lookup table, then indexed: exact and fast.

The formula extends to more than two textures (§5.4.1) as an *expression* (:func:`parse_expression`,
never Python's eval): T1…TN, numbers in [0, 1], the operators above between two operands,
evaluated left to right, ``not``, and brackets ( ) or [ ] to group — the thesis's formula is
``not[(a op1 T1) op2 (b op3 T2)] op4 c``. It is evaluated point by point, a band of
BAND_POINTS points at a time (:func:`evaluate`), so its float64 greys never span the canvas.

Incrustation by blocks ("pavés", §5.4.1): each point of a mask texture stands for a block of
``block × block`` points (:func:`pave`); a mask drawn point by point (the document's levels,
painted points) shows T2 by whole blocks where it holds on at least half a block (:func:`by_blocks`).

>>> import numpy as np
>>> t1 = np.array([[0, 1], [0, 1]]); t2 = np.array([[0, 0], [1, 1]])
>>> mix(t1, t2, levels=2, op2="xor")
array([[0, 1],
       [1, 0]], dtype=uint8)
>>> incrust(np.array([[0, 1], [1, 0]]), [t1, t2])
array([[0, 0],
       [1, 1]], dtype=uint8)
"""

from __future__ import annotations

import re
from functools import partial
from typing import Sequence

import numpy as np

from ..errors import InputError

OPS = ("and", "or", "xor", "min", "max", "add", "multiply", "replace")
MAX_LEVELS = 16


# -- levels on the grey scale ----------------------------------------------------------------------

def to_scale(levels, num_levels: int) -> np.ndarray:
    """Levels 0..G-1 as greys in [0, 1] (x / (G − 1))."""
    return np.asarray(levels, dtype=np.float64) / (num_levels - 1)


def from_scale(values, num_levels: int) -> np.ndarray:
    """Greys in [0, 1] back to levels 0..G-1, rounding half up."""
    return np.floor(np.clip(values, 0.0, 1.0) * (num_levels - 1) + 0.5 + 1e-9).astype(np.uint8)


def convert_levels(levels, from_levels: int, to_levels: int) -> np.ndarray:
    """A texture of G levels expressed in G' levels at the same place on the grey scale
    (so a 4-level texture composed into an 8-level one keeps its greys)."""
    levels = np.asarray(levels)
    if from_levels == to_levels:
        return levels.astype(np.uint8)
    lut = from_scale(to_scale(np.arange(from_levels), from_levels), to_levels)
    return lut[levels]


def fit(levels, shape: tuple[int, int]) -> np.ndarray:
    """A texture brought to ``shape``: repeated (tiled from the top-left) if smaller, cropped if
    larger — textures are stationary, so a repeat is the natural way to cover more ground."""
    levels = np.asarray(levels)
    h, w = shape
    if levels.shape == (h, w):
        return levels
    reps = (-(-h // levels.shape[0]), -(-w // levels.shape[1]))
    return np.tile(levels, reps)[:h, :w]


# -- the operators ---------------------------------------------------------------------------------

def apply_op(op: str, x, y, num_levels: int) -> np.ndarray:
    """``x op y`` on the grey scale of a G-level target (see the module's table)."""
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    top = num_levels - 1
    if op in ("and", "or", "xor"):
        cx, cy = _codes(x, top), _codes(y, top)
        bits = {"and": np.bitwise_and, "or": np.bitwise_or, "xor": np.bitwise_xor}[op](cx, cy)
        return np.minimum(bits, top) / top
    if op == "min":
        return np.minimum(x, y)
    if op == "max":
        return np.maximum(x, y)
    if op == "add":
        return np.minimum(x + y, 1.0)
    if op == "multiply":
        return x * y
    if op == "replace":
        return np.where(y > 0, y, x)
    raise InputError(f"unknown operator {op!r}: choose one of {', '.join(OPS)}")


def _codes(values: np.ndarray, top: int) -> np.ndarray:
    return np.floor(np.clip(values, 0.0, 1.0) * top + 0.5 + 1e-9).astype(np.int64)


def check_op(op: str) -> str:
    if op not in OPS:
        raise InputError(f"unknown operator {op!r}: choose one of {', '.join(OPS)}")
    return op


def mix_table(levels1: int, levels2: int, levels: int, *, a: float = 1.0, op1: str = "multiply",
              op2: str = "max", b: float = 1.0, op3: str = "multiply", negate: bool = False,
              op4: str = "max", c: float = 0.0) -> np.ndarray:
    """The (G1, G2) table of T3's level for each pair of levels (t1, t2)."""
    for op in (op1, op2, op3, op4):
        check_op(op)
    for name, w in (("a", a), ("b", b), ("c", c)):
        if not 0.0 <= w <= 1.0:
            raise InputError(f"weight {name} = {w} must lie in 0..1 (a proportion of the grey "
                             "scale: 0 the background, 1 the top level)")
    t1 = to_scale(np.arange(levels1), levels1)[:, None]
    t2 = to_scale(np.arange(levels2), levels2)[None, :]
    inner = apply_op(op2, apply_op(op1, a, t1, levels), apply_op(op3, b, t2, levels), levels)
    if negate:
        inner = 1.0 - inner
    inner = np.broadcast_to(inner, (levels1, levels2))
    return from_scale(apply_op(op4, inner, c, levels), levels)


def mix(t1, t2, *, levels: int, levels1: int | None = None, levels2: int | None = None,
        **ops) -> np.ndarray:
    """T3 = not[(a op1 T1) op2 (b op3 T2)] op4 c, point by point, as a G-level matrix.

    ``levels1``/``levels2`` are the G of each source (default: the target's ``levels``); ``ops``
    are a, op1, op2, b, op3, negate, op4, c of :func:`mix_table`. T1 and T2 must have one shape.
    """
    t1, t2 = np.asarray(t1), np.asarray(t2)
    if t1.shape != t2.shape:
        raise InputError(f"T1 {t1.shape} and T2 {t2.shape} must have the same shape")
    g1, g2 = levels1 or levels, levels2 or levels
    _check_levels(t1, g1, "T1")
    _check_levels(t2, g2, "T2")
    return mix_table(g1, g2, levels, **ops)[t1, t2]


def incrust(membership, sources: Sequence) -> np.ndarray:
    """Incrustation: at each point, the level of ``sources[membership]``.

    A membership of 0..N−1 says which of N textures shows there; a boolean one picks
    ``sources[1]`` where True, so the thesis's T3 = if bool then T1 else T2 is
    ``incrust(bool, [T2, T1])``. All arrays have one shape.
    """
    membership = np.asarray(membership)
    if membership.dtype == bool:
        membership = membership.astype(np.uint8)
    if membership.dtype.kind not in "ui" or membership.ndim != 2:
        raise InputError("the membership must be a 2-D matrix of integers or booleans")
    if not len(sources):
        raise InputError("incrustation needs at least one texture")
    stack = np.stack([np.asarray(s, dtype=np.uint8) for s in sources]) \
        if all(np.shape(s) == membership.shape for s in sources) else None
    if stack is None:
        raise InputError(f"every texture must have the membership's shape {membership.shape}")
    if membership.size and (membership.min() < 0 or membership.max() >= len(sources)):
        raise InputError(f"the membership uses texture {int(membership.max())} but only "
                         f"{len(sources)} are given (0..{len(sources) - 1})")
    return np.take_along_axis(stack, membership[None].astype(np.intp), axis=0)[0]


def parse_level_set(text: str, num_levels: int = MAX_LEVELS) -> frozenset[int]:
    """"1,3-5" → {1, 3, 4, 5}: the levels of a mask texture that select a texture."""
    chosen: set[int] = set()
    for part in str(text).replace(" ", "").split(","):
        if not part:
            continue
        lo, dash, hi = part.partition("-")
        try:
            lo_i, hi_i = int(lo), int(hi if dash else lo)
        except ValueError:
            raise InputError(f"levels {text!r}: write numbers and ranges like 1,3-5") from None
        if not 0 <= lo_i <= hi_i < num_levels:
            raise InputError(f"levels {text!r}: {part} is outside 0..{num_levels - 1}")
        chosen.update(range(lo_i, hi_i + 1))
    return frozenset(chosen)


def membership_from_levels(levels, chosen) -> np.ndarray:
    """True where the mask texture's level is one of ``chosen`` (a third texture's levels)."""
    table = np.zeros(256, dtype=bool)
    table[list(chosen)] = True
    return table[np.asarray(levels, dtype=np.uint8)]


def membership_from_points(points, shape: tuple[int, int]) -> np.ndarray:
    """True at the listed (row, col) points (a painted mask, or a selection's points); points
    outside the canvas are ignored, so a mask painted on a larger canvas still applies."""
    mask = np.zeros(shape, dtype=bool)
    if len(points):
        p = np.asarray(points, dtype=np.int64).reshape(-1, 2)
        keep = (p[:, 0] >= 0) & (p[:, 0] < shape[0]) & (p[:, 1] >= 0) & (p[:, 1] < shape[1])
        mask[p[keep, 0], p[keep, 1]] = True
    return mask


def _check_levels(levels: np.ndarray, num_levels: int, name: str) -> None:
    if not 2 <= num_levels <= MAX_LEVELS:
        raise InputError(f"{name}: G = {num_levels} is outside 2..{MAX_LEVELS}")
    if levels.dtype.kind not in "ui":
        raise InputError(f"{name} must hold integer levels, got {levels.dtype}")
    if levels.size and (levels.min() < 0 or levels.max() >= num_levels):
        raise InputError(f"{name} holds levels outside 0..{num_levels - 1}")


# -- incrustation by blocks ("pavés") --------------------------------------------------------------

def pave(levels, block: int, shape: tuple[int, int]) -> np.ndarray:
    """A mask texture read at block scale: each of its points a ``block × block`` block, the
    whole repeated to cover ``shape`` (the thesis's pavés: a point of a synthesis window says
    which texture a block shows).

    >>> pave(np.array([[1, 0]]), 2, (3, 6))
    array([[1, 1, 0, 0, 1, 1],
           [1, 1, 0, 0, 1, 1],
           [1, 1, 0, 0, 1, 1]])
    """
    block = _block(block)
    h, w = shape
    coarse = fit(levels, (-(-h // block), -(-w // block)))
    return np.repeat(np.repeat(coarse, block, axis=0), block, axis=1)[:h, :w]


def by_blocks(membership, block: int) -> np.ndarray:
    """A point-by-point mask made of whole blocks: a ``block × block`` block (counted from the
    top-left; those at the right and bottom edges may be cut) holds where at least half of its
    points hold.

    >>> by_blocks(np.array([[1, 1, 0, 0], [0, 0, 0, 1], [0, 0, 0, 0]], bool), 2).astype(int)
    array([[1, 1, 0, 0],
           [1, 1, 0, 0],
           [0, 0, 0, 0]])
    """
    block = _block(block)
    membership = np.asarray(membership, dtype=bool)
    h, w = membership.shape
    rows, cols = -(-h // block), -(-w // block)
    padded = np.zeros((rows * block, cols * block), np.int64)
    padded[:h, :w] = membership
    inside = np.zeros_like(padded)
    inside[:h, :w] = 1
    count = padded.reshape(rows, block, cols, block).sum(axis=(1, 3))
    size = inside.reshape(rows, block, cols, block).sum(axis=(1, 3))
    held = 2 * count >= size
    return np.repeat(np.repeat(held, block, axis=0), block, axis=1)[:h, :w]


def _block(block) -> int:
    if isinstance(block, bool) or not isinstance(block, (int, np.integer)) or block < 1:
        raise InputError(f"a block (pavé) is a whole number of points ≥ 1, got {block!r}")
    return int(block)


# -- an expression over N textures -----------------------------------------------------------------

MAX_EXPRESSION = 1000          # characters
MAX_DEPTH = 32                 # brackets and nots nested
_TOKEN = re.compile(r"\s*(?:(?P<number>\d+(?:\.\d*)?|\.\d+)|(?P<texture>T\d+)|(?P<word>[a-z]+)"
                    r"|(?P<open>[(\[])|(?P<close>[)\]]))", re.IGNORECASE)


def parse_expression(text: str, textures: int) -> tuple:
    """The tree of an expression over T1…T``textures`` (InputError says what is wrong): a number
    ``("number", x)``, a texture ``("T", k)``, ``("not", e)`` or ``(op, left, right)``. Every
    texture must be used; operators chain left to right (brackets group).

    >>> parse_expression("not[(0.5 multiply T1) max T2] min 1", 2)
    ('min', ('not', ('max', ('multiply', ('number', 0.5), ('T', 1)), ('T', 2))), ('number', 1.0))
    """
    if not isinstance(text, str) or not text.strip():
        raise InputError("the expression is empty: write one over T1, T2…, like T1 max T2")
    if len(text) > MAX_EXPRESSION:
        raise InputError(f"the expression is longer than {MAX_EXPRESSION} characters")
    tokens = _tokens(text)
    tree, end = _chain(tokens, 0, 0, textures)
    if end < len(tokens):
        raise InputError(f"the expression goes on after its end, at {tokens[end][1]!r}: "
                         "an operator is missing, or a bracket is not opened")
    unused = sorted(set(range(1, textures + 1)) - _used(tree))
    if unused:
        raise InputError(f"the expression does not use {', '.join(f'T{k}' for k in unused)}")
    return tree


def _tokens(text: str) -> list[tuple[str, str]]:
    tokens, at = [], 0
    while text[at:].strip():
        m = _TOKEN.match(text, at)
        if m is None:
            raise InputError(f"the expression has {text[at:].strip()[:12]!r}, which is neither "
                             f"a texture T1…, a number, an operator ({', '.join(OPS)}), not, "
                             "nor a bracket")
        kind = m.lastgroup
        tokens.append((kind, m.group(kind)))
        at = m.end()
    return tokens


def _chain(tokens, i, depth, textures):
    """operand {operator operand}: left to right."""
    tree, i = _operand(tokens, i, depth, textures)
    while i < len(tokens) and tokens[i][0] == "word" and tokens[i][1].lower() != "not":
        op = tokens[i][1].lower()
        check_op(op)
        right, i = _operand(tokens, i + 1, depth, textures)
        tree = (op, tree, right)
    return tree, i


def _operand(tokens, i, depth, textures):
    if depth > MAX_DEPTH:
        raise InputError(f"the expression nests more than {MAX_DEPTH} brackets deep")
    if i >= len(tokens):
        raise InputError("the expression ends where a texture, a number or a bracket is due")
    kind, text = tokens[i]
    if kind == "number":
        value = float(text)
        if value > 1:
            raise InputError(f"the number {text} is outside 0..1 (the grey scale: 0 the "
                             "background, 1 the top level)")
        return ("number", value), i + 1
    if kind == "texture":
        k = int(text[1:])
        if not 1 <= k <= textures:
            raise InputError(f"the expression names {text.upper()}, but there are T1…T{textures}")
        return ("T", k), i + 1
    if kind == "word" and text.lower() == "not":
        inner, i = _operand(tokens, i + 1, depth + 1, textures)
        return ("not", inner), i
    if kind == "open":
        inner, i = _chain(tokens, i + 1, depth + 1, textures)
        closing = ")" if text == "(" else "]"
        if i >= len(tokens) or tokens[i][1] != closing:
            raise InputError(f"a bracket {text} is not closed by {closing}")
        return inner, i + 1
    raise InputError(f"the expression has {text!r} where a texture, a number or a bracket "
                     "is due")


def _used(tree) -> set[int]:
    if tree[0] == "T":
        return {tree[1]}
    if tree[0] == "number":
        return set()
    return set().union(*(_used(t) for t in tree[1:]))


def evaluate(text: str, textures: Sequence[tuple[np.ndarray, int]], levels: int) -> np.ndarray:
    """T = the expression, point by point, as a ``levels``-level matrix: ``textures`` are
    (levels, G) of T1…TN, of one shape, each on its own grey scale.

    Every operator works point by point, so the matrix is made a band of rows at a time
    (BAND_POINTS points): the same bits as on the whole canvas at once, without a float64 copy
    of each texture (eight textures of 2^26 points took 4 GiB before the operators' own).

    >>> t = [(np.array([[0, 1, 1, 0]]), 2), (np.array([[0, 1, 0, 1]]), 2),
    ...      (np.array([[1, 1, 0, 0]]), 2)]
    >>> evaluate("T1 xor T2 xor T3", t, 2)
    array([[1, 1, 1, 1]], dtype=uint8)
    """
    tree = parse_expression(text, len(textures))
    shape = np.shape(textures[0][0])
    sources = []
    for k, (t, g) in enumerate(textures, start=1):
        t = np.asarray(t)
        if t.shape != shape:
            raise InputError(f"T{k} {t.shape} and T1 {shape} must have the same shape")
        _check_levels(t, g, f"T{k}")
        sources.append((t.__getitem__, g))
    _check_levels(np.zeros(0, np.uint8), levels, "the result")
    return _evaluate(tree, sources, shape, levels)


def evaluate_fitted(text: str, textures: Sequence[tuple[np.ndarray, int]], levels: int,
                    shape: tuple[int, int]) -> np.ndarray:
    """`evaluate` of the textures each brought to ``shape`` by `fit` (repeated or cropped),
    without making those copies: each band takes the rows of each texture it needs. The same
    matrix, and the same errors, as ``evaluate(text, [(fit(t, shape), g), …], levels)``.

    >>> evaluate_fitted("T1 max T2", [(np.array([[0, 1, 0]]), 2), (np.array([[1]]), 2)], 2,
    ...                 (2, 3))
    array([[1, 1, 1],
           [1, 1, 1]], dtype=uint8)
    """
    shape = tuple(shape)
    arrays = [np.asarray(t) for t, _ in textures]
    if len(shape) != 2 or any(t.ndim != 2 or not t.size for t in arrays):   # odd: fit them
        return evaluate(text, [(fit(t, shape), g) for t, (_, g) in zip(arrays, textures)],
                        levels)
    tree = parse_expression(text, len(textures))
    sources = []
    for k, (t, (_, g)) in enumerate(zip(arrays, textures), start=1):
        _check_levels(t[:shape[0], :shape[1]], g, f"T{k}")     # the points fit() keeps
        sources.append((partial(_fitted_rows, t, shape), g))
    _check_levels(np.zeros(0, np.uint8), levels, "the result")
    return _evaluate(tree, sources, shape, levels)


BAND_POINTS = 2**18     # points an expression is evaluated on at once (2 MiB of greys a texture)


def _evaluate(tree, sources, shape, levels) -> np.ndarray:
    """The expression's matrix of ``shape``, band by band; ``sources`` give each texture's
    points of a band (an index of the first axis) and its G."""
    out = np.empty(shape, np.uint8)
    if len(shape) == 0:
        bands = [...]
    else:
        step = max(1, BAND_POINTS // max(1, int(np.prod(shape[1:]))))
        bands = [slice(top, top + step) for top in range(0, shape[0], step)]
    for band in bands:
        greys = [to_scale(rows(band), g) for rows, g in sources]
        value = np.broadcast_to(_value(tree, greys, levels), out[band].shape)
        out[band] = from_scale(value, levels)
    return out


def _fitted_rows(levels: np.ndarray, shape: tuple[int, int], rows: slice) -> np.ndarray:
    """``fit(levels, shape)[rows]``: point (i, j) is levels[i mod h, j mod w]."""
    (h, w), (height, width) = levels.shape, shape
    top, bottom = rows.start, min(rows.stop, height)
    band = levels[top:bottom] if bottom <= h else levels[np.arange(top, bottom) % h]
    return band[:, :width] if w >= width else np.tile(band, (1, -(-width // w)))[:, :width]


def _value(tree, greys, levels):
    if tree[0] == "number":
        return np.float64(tree[1])
    if tree[0] == "T":
        return greys[tree[1] - 1]
    if tree[0] == "not":
        return 1.0 - _value(tree[1], greys, levels)
    return apply_op(tree[0], _value(tree[1], greys, levels), _value(tree[2], greys, levels),
                    levels)
