"""Where the bundled sample photos and DPJs live (the repository's `resources/` folder).

The application starts on a bundled DPJ until the bank exists; tests acquire from the photos.
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent / "resources"
DEFAULT_DPJ = "gravel-3x3-g4"


def sample_images() -> list[Path]:
    return sorted((ROOT / "images").glob("*.png"))


def bundled_dpjs() -> list[Path]:
    return sorted((ROOT / "dpj").glob("*.dpj"))


def bundled_dpj(name: str = DEFAULT_DPJ) -> Path:
    return ROOT / "dpj" / f"{name}.dpj"
