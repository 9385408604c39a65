"""Pixel-grid reductions shared by the fit, its report and the command line (a leaf: NumPy only)."""

from __future__ import annotations

import numpy as np


def box_halved(image) -> np.ndarray:
    """``image`` at half its size, each pixel the mean of a 2 x 2 block (float64; an odd last row or column
    dropped). Any trailing axes (channels) are kept."""
    img = np.asarray(image, dtype=np.float64)
    h, w = img.shape[0] // 2, img.shape[1] // 2
    return img[: 2 * h, : 2 * w].reshape(h, 2, w, 2, *img.shape[2:]).mean(axis=(1, 3))
