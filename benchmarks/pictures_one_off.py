"""Pictures and numbers of one-off content left out of the fit (issue 22): ``docs/images/fit_one_off.jpg``.

Photos holding one object each (``exemplars.py``): an orange leaf pasted on a 256-pixel crop of
scikit-image's gravel and on its grass, and the lawn of ``camera()`` with the tripod's foot. Per
photo, the fit made twice, ``keep_one_off=True`` (the fit before one-off content was left out) and
the default, and printed: the fit's seconds, the one-off region found
(:func:`spectex.metrics.one_off_repeats`' rarity and box) and its copies in a bake of 8 times the
photo's area at its pixel size (what ``spectex fit`` reports on). The picture: per photo, the photo
and the two bakes, side by side (each bake shown at the photo's height).

Run from the repository root::

    python benchmarks/pictures_one_off.py [--grid docs/images/fit_one_off.jpg]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import exemplars  # noqa: E402
from _machine import cpu_name  # noqa: E402


def photos():
    return {
        "gravel + leaf": exemplars.with_leaf(exemplars.load("gravel")[:256, :256], 150, 100),
        "grass + leaf": exemplars.with_leaf(exemplars.load("grass")[:256, :256], 90, 170, r=24.0),
        "lawn (camera)": exemplars.lawn(),
    }


def label(image, text):
    from PIL import Image, ImageDraw

    out = Image.new("RGB", (image.width, image.height + 20), (255, 255, 255))
    ImageDraw.Draw(out).text((4, 4), text, fill=(0, 0, 0))
    out.paste(image, (0, 20))
    return out


def save_grid(rows, path):
    """Rows of labelled pictures (:func:`label`) side by side, 8 pixels apart, as a JPEG."""
    from PIL import Image

    width = max(sum(p.width for p in row) + 8 * (len(row) - 1) for row in rows)
    grid = Image.new("RGB", (width, sum(row[0].height for row in rows) + 8 * (len(rows) - 1)), (255, 255, 255))
    y = 0
    for row in rows:
        x = 0
        for pic in row:
            grid.paste(pic, (x, y))
            x += pic.width + 8
        y += row[0].height + 8
    grid.save(path, quality=88)
    print(f"wrote {path}")


def picture(image, text, height=256):
    """``image`` (grey or RGB, 0-1) at ``height`` pixels, labelled."""
    from PIL import Image

    rgb = image if image.ndim == 3 else np.repeat(image[:, :, None], 3, axis=2)
    pic = Image.fromarray((np.clip(rgb, 0, 1) * 255).astype(np.uint8))
    pic = pic.resize((round(pic.width * height / pic.height), height), Image.LANCZOS)
    return label(pic, text)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", help="write the picture here (JPEG)")
    args = ap.parse_args(argv)
    from spectex.fitting import fit_result
    from spectex.metrics import one_off_repeats
    from spectex.render import bake

    print(f"CPU: {cpu_name()}")
    rows = []
    for name, photo in photos().items():
        h, w = photo.shape[:2]
        side = int(round(np.sqrt(8.0) * max(h, w)))
        tiles = [photo if photo.ndim == 3 else np.repeat(photo[:, :, None], 3, axis=2)]
        for keep in (True, False):
            t0 = time.perf_counter()
            result = fit_result(photo, rng=0, keep_one_off=keep)
            seconds = time.perf_counter() - t0
            view = bake(result.texture, (side, side), pixel_size=result.pixel_size)
            found = one_off_repeats(view, photo)
            way = "keep_one_off=True" if keep else "default"
            print(f"{name:14s} {way:18s} fit {seconds:5.2f} s; rarity {found.rarity:5.1f}, region {found.box}, "
                  f"copies in 8x its area {found.copies}")
            tiles.append(view)
        row = [picture(image, f"{name}: {text}" if text == "photo" else text)
               for image, text in zip(tiles, ("photo", "keep_one_off=True, 8x the area", "default, 8x the area"))]
        rows.append(row)
    if args.grid:
        save_grid(rows, args.grid)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
