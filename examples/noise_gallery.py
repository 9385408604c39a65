"""Gallery of procedural textures (seed 002): one strip, one texture per kind.

Run: ``python examples/noise_gallery.py [OUT] [--tile N]``; writes
``docs/images/noise_gallery.jpg`` by default.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from spectex import io, procedural

TEST_ARGS = ["--tile", "32"]

PANELS = [
    ("perlin", "grey", {"scale": 6}),
    ("fbm", "earth", {"scale": 3, "octaves": 8}),
    ("turbulence", "fire", {"scale": 3, "octaves": 7}),
    ("marble", "marble", {"scale": 3}),
    ("wood", "wood", {}),
    ("clouds", "clouds", {}),
    ("stripes", "ocean", {"scale": 4}),
    ("value", "moss", {"scale": 8}),
]


def gallery(tile: int = 256, seed: int = 7) -> np.ndarray:
    """The strip: ``(tile, tile * len(PANELS), 3)`` float32."""
    images = []
    for kind, cmap, params in PANELS:
        field = procedural.texture(kind, (tile, tile), seed=seed, **params)
        images.append(procedural.colorize(field, cmap, kind=kind))
    return np.concatenate(images, axis=1)


def main(argv=None) -> Path:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="docs/images/noise_gallery.jpg")
    parser.add_argument("--tile", type=int, default=256)
    args = parser.parse_args(argv)
    return io.write_image(args.out, gallery(args.tile))


if __name__ == "__main__":
    print(main())
