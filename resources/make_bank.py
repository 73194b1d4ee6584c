"""Regenerate the built-in bank entries, resources/bank/*.texture (run from the repository root).

A new bank installs these on first run, so a newcomer sees what the product does: textures acquired
from the bundled photos (the 1984 single DPJ, then below each the photo model shown with the
photo's tone), DPJs drawn from a seed (§5.2.2), and edited textures whose logs use the region and
global operators. Each file's stem is the entry's name ("gravel-acquired" → "Gravel
acquired", a leading "NN-" is the entry's place among the built-ins); its tags and description
come from the manifest. Logs are saved optimised, as the bank keeps them. Each entry's texture is
also stored as a picture, bank/pictures/<SHA-256>.npz, and one drawn with a photo's tone as its
tone picture, bank/pictures/tones/<SHA-256>.npz (``--pictures`` writes only these), so a first
start shows and indexes the built-ins, toned, without waiting for the synthesis kernels.

Run whole, it writes every entry with today's action versions; the committed 01–03 and 07–12 are
older files (Synthesize version 1), kept byte for byte as the bank's older-format entries — after
adding an entry, restore them from git and keep only the new files and their pictures.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from texeditor.recipe.actions import NewCanvas, SetLevels, SetPalette, Synthesize  # noqa: E402
from texeditor.markov.dpj import DPJ  # noqa: E402
from texeditor.recipe.history import History  # noqa: E402
from texeditor.recipe.logopt import optimize  # noqa: E402
from texeditor.regions.actions import Copy, Fill, Identity, Isometry, Similarity  # noqa: E402
from texeditor.bank.store import TONES, write_picture, write_tone  # noqa: E402
from texeditor.recipe.texturefile import (render_texture, save_texture,  # noqa: E402
                                          synthesize_scales_texture)
from texeditor.markov.levels import load_image  # noqa: E402
from texeditor.photo import acquire_model, document_tone  # noqa: E402

SIZE = 256
WARM = [(52, 36, 24), (128, 86, 52), (186, 140, 92), (232, 206, 160)]
MOSS = [(24, 36, 20), (58, 86, 40), (104, 140, 64), (170, 196, 110), (226, 234, 190)]


def seeded_dpj(seed: int, levels: int = 3, empty: float = 0.0) -> DPJ:
    """A 2×2 DPJ drawn from a seed (thesis §5.2.2): every configuration gets a small random
    probability (a granular texture); ``empty`` is the share given to the all-background one
    (high: airy, 0: dense)."""
    rng = np.random.default_rng(seed)
    n = levels ** 4
    probs = rng.dirichlet(np.full(n, 0.7))
    probs[0] = 0.0
    probs *= (1.0 - empty) / probs.sum()
    probs[0] = empty
    return DPJ.from_codes(np.arange(n), probs, levels, (2, 2),
                          meta={"name": f"seed-{seed}", "source": f"drawn from seed {seed}"})


def synthesised(dpj: DPJ, seed: int, size: int = SIZE) -> History:
    history = History()
    ref = history.add_dpj(dpj)
    history.apply(Synthesize(ref, size, size, seed))
    return history


def with_tone(photo: str, seed: int, size: int = SIZE) -> History:
    """A multi-scale synthesis from a bundled photo's model, shown with the photo's tone (what
    `texeditor resynth PHOTO -o OUT.texture` writes)."""
    model = acquire_model(load_image(HERE / "images" / f"{photo}.png"))
    return synthesize_scales_texture(model.scales.dpjs, size, size, seed=seed,
                                     tone=model.tone_pictures())


def bundled(name: str) -> DPJ:
    return DPJ.load(HERE / "dpj" / f"{name}.dpj")


def entries() -> dict:
    """stem → (History, tags, description)."""
    out = {}
    gravel, grass, brick = bundled("gravel-3x3-g4"), bundled("grass-2x2-g8"), bundled("brick-2x3-g4")
    out["gravel"] = (synthesised(gravel, 1), ["gravel", "photo", "granular"],
                     "Acquired from scikit-image's gravel photo: 3×3 window, G = 4, Lloyd–Max "
                     "levels; synthesised 256×256, seed 1.")
    out["grass"] = (synthesised(grass, 2), ["grass", "photo", "fine"],
                    "Acquired from scikit-image's grass photo: 2×2 window, G = 8; synthesised.")
    out["brick"] = (synthesised(brick, 3), ["brick", "photo", "oriented"],
                    "Acquired from scikit-image's brick photo: 2×3 window, G = 4; the courses "
                    "run up and down, as in the photo.")
    tone = ("a photo model (multi-scale DPJs: the coarse scales carry the layout) drawn "
            "256×256 and shown with the photo's own greys")
    out["gravel-with-tone"] = (with_tone("gravel", 1), ["gravel", "photo", "granular", "tone"],
                               f"The bundled gravel photo as {tone}, seed 1.")
    out["grass-with-tone"] = (with_tone("grass", 2), ["grass", "photo", "fine", "tone"],
                              f"The bundled grass photo as {tone}, seed 2.")
    out["brick-with-tone"] = (with_tone("brick", 3), ["brick", "photo", "oriented", "tone"],
                              f"The bundled brick photo as {tone}, seed 3.")
    out["granular-airy-seed-5"] = (
        synthesised(seeded_dpj(5, empty=0.35), 5), ["granular", "seed", "airy"],
        "A 2×2 DPJ drawn from seed 5, G = 3, the empty configuration at 0.35: scattered grains.")
    out["granular-dense-seed-8"] = (
        synthesised(seeded_dpj(8, empty=0.0), 8), ["granular", "seed", "dense"],
        "A 2×2 DPJ drawn from seed 8, G = 3, no empty configuration: a dense grain.")

    h = synthesised(gravel, 4)
    h.apply(Fill(SIZE // 2, SIZE // 2, 3, scope="region", connectivity=8))
    h.apply(Copy(SIZE // 2, SIZE // 2, SIZE // 5, SIZE * 4 // 5, kind="region", scope="region",
                 connectivity=8))
    h.apply(SetPalette(WARM))
    out["gravel-filled-and-copied"] = (
        h, ["gravel", "edited", "regions", "colour"],
        "Gravel with the region at the centre filled with the lightest level, copied up to the "
        "right, in warm colours (fill, copy, palette).")

    h = synthesised(brick, 6)
    h.apply(Isometry(90.0, SIZE / 2 - 0.5, SIZE / 2 - 0.5, wrap=True))
    out["brick-turned-a-quarter"] = (
        h, ["brick", "edited", "oriented", "rotated"],
        "Brick turned 90° about its centre (isometry, wrap): the courses now run across.")

    h = synthesised(grass, 7)
    h.apply(Similarity(2.0, SIZE / 2, SIZE / 2, wrap=True))
    h.apply(SetPalette(MOSS + [(240, 244, 220)] * 3))
    out["grass-zoomed-twice"] = (
        h, ["grass", "edited", "coarse", "colour"],
        "Grass zoomed ×2 (similarity): half the grains per area, a coarser texture; moss colours.")

    h = History()
    h.apply(NewCanvas(SIZE, SIZE, 3))
    h.apply(SetLevels(2, 2, 10, 12, 2))
    h.apply(SetLevels(6, 6, 2, 4, 1))
    h.apply(SetLevels(12, 4, 3, 10, 1))
    h.apply(Identity(0, 0, repeat_rows=SIZE // 16, repeat_cols=SIZE // 16, step_rows=16,
                     step_cols=16))
    out["tiled-motif"] = (
        h, ["hand-made", "regular", "periodic", "tiled"],
        "A motif drawn by hand in a 16×16 cell and duplicated on a 16×16 grid (identity): a "
        "perfectly regular texture.")
    return out


def write_pictures(folder: Path = HERE / "bank") -> None:
    """Each built-in's texture as a stored picture, bank/pictures/<SHA-256>.npz: a first start
    shows and indexes the built-ins from these while the synthesis kernels compile. Each one is
    the file's own replay, checked against its recorded hash."""
    pictures = folder / "pictures"
    for old in [*pictures.glob("*.npz"), *(pictures / TONES).glob("*.npz")]:
        old.unlink()
    for path in sorted(folder.glob("*.texture")):
        doc = render_texture(path)                   # replayed, hash checked
        written = write_picture(pictures, doc.levels, doc.palette)
        print(f"{path.name}: picture {written.name[:12]}… ({written.stat().st_size:,} bytes)")
        tone = document_tone(doc)                    # what the window shows, toned
        if tone is not None:
            written = write_tone(pictures, doc.result_hash(), tone)
            print(f"    its tone {written.stat().st_size:,} bytes")


def main() -> None:
    if sys.argv[1:] == ["--pictures"]:               # only the stored pictures
        write_pictures()
        return
    folder = HERE / "bank"
    folder.mkdir(exist_ok=True)
    for old in folder.glob("*.texture"):
        old.unlink()
    for k, (stem, (history, tags, description)) in enumerate(entries().items(), 1):
        doc = history.document
        shorter = optimize(history.applied, doc.dpjs)
        check = History.from_log(shorter, doc.dpjs, exemplars=doc.exemplars)
        assert check.document.result_hash() == doc.result_hash(), stem
        if doc.dpj is not None:      # the current DPJ travels with the file
            check.document.add_dpj(doc.dpj, doc.dpj_ref)
        name = f"{k:02d}-{stem}.texture"
        save_texture(folder / name, check, tags=tags, description=description)
        print(f"{name}: {len(shorter)} actions")
    write_pictures(folder)


if __name__ == "__main__":
    main()
