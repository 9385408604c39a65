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
