"""The picture grids of the ``pictures_*`` benchmarks: labelled panels, rows of them saved as one JPEG."""

from __future__ import annotations

import numpy as np


def label(image, text):
    """A PIL ``image`` with ``text`` in a grey band of 20 pixels above it."""
    from PIL import Image, ImageDraw

    out = Image.new("RGB", (image.width, image.height + 20), (128, 128, 128))
    ImageDraw.Draw(out).text((4, 4), text, fill=(0, 0, 0))
    out.paste(image, (0, 20))
    return out


def panel(rgb, text, crop):
    """The top-left ``crop x crop`` of an image (float in [0, 1], or 8-bit; grey or RGB(A)), labelled."""
    from PIL import Image

    rgb = np.asarray(rgb, dtype=np.float64)
    if rgb.max() > 1.0:
        rgb = rgb / 255.0
    if rgb.ndim == 2:
        rgb = np.stack([rgb] * 3, axis=2)
    rgb = np.clip(rgb[:crop, :crop, :3], 0.0, 1.0)
    return label(Image.fromarray((rgb * 255 + 0.5).astype(np.uint8)), text)


def save_grid(rows, path):
    """Rows of equal panels, 8 pixels apart across, saved as a JPEG at ``path``."""
    from PIL import Image

    w, h = rows[0][0].width, rows[0][0].height
    cols = max(len(row) for row in rows)
    grid = Image.new("RGB", (cols * w + (cols - 1) * 8, len(rows) * h), (128, 128, 128))
    for r, row in enumerate(rows):
        for c, img in enumerate(row):
            grid.paste(img, (c * (w + 8), r * h))
    grid.save(path, quality=90)


def wall_photos(description, argv=None):
    """The ``pictures_*`` wall benchmarks' command line: ``--photo PATH`` (repeatable, fitted beside
    ``exemplars.py``'s ``ashlar``) and ``--grid PATH`` (the picture, JPEG; its folder checked before minutes of
    fits). Returns ``(args, photos)``, ``photos`` by name, RGB float32; a missing or unreadable photo or folder
    is one line of error and exit status 2."""
    import argparse
    from pathlib import Path

    import exemplars

    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--photo", action="append", default=[], help="a photo of your own to fit beside (repeatable)")
    ap.add_argument("--grid", help="write the picture here (JPEG)")
    args = ap.parse_args(argv)
    if args.grid and not Path(args.grid).resolve().parent.is_dir():
        ap.error(f"--grid: the folder of {args.grid!r} does not exist")
    photos = {"ashlar (exemplars.py)": exemplars.load("ashlar")}
    for path in args.photo:
        try:
            photos[Path(path).stem] = exemplars.load(path)
        except (OSError, ValueError) as exc:
            ap.error(f"--photo: {exc}")
    for name, photo in photos.items():
        photo = np.asarray(photo, np.float32)
        photos[name] = np.repeat(photo[:, :, None], 3, axis=2) if photo.ndim == 2 else photo[:, :, :3]
    return args, photos
