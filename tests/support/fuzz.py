"""Valid seeds for the fuzz tests: a .dpj and a .texture file as bytes."""

from skimage import data

from texeditor import DPJ, estimate_dpj, quantize
from texeditor.recipe.history import History
from texeditor.recipe.texturefile import texture_bytes


def seed_dpj() -> DPJ:
    q = quantize(data.gravel()[:64, :64], 3)
    return estimate_dpj(q.levels, (2, 2), 3, palette=q.palette)


DPJ_BYTES = seed_dpj().to_bytes()


def seed_texture() -> bytes:
    from texeditor.recipe.actions import SetLevels, SetPalette, Synthesize
    from texeditor.regions.actions import Copy, Fill

    history = History()
    ref = history.add_dpj(seed_dpj())
    for action in (Synthesize(ref, 24, 16, 3), SetLevels(2, 3, 4, 5, 1), Fill(0, 0, 2),
                   Copy(8, 8, 2, 12), SetPalette(((0, 0, 0), (90, 60, 30), (250, 240, 200)))):
        history.apply(action)
    return texture_bytes(history.document, history.applied)[0]


TEXTURE_BYTES = seed_texture()

