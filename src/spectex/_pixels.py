"""Pixel-grid reductions shared by the fit, its report and the command line (a leaf: NumPy only)."""

from __future__ import annotations

import numpy as np


def principal_axis(values, sample: int = 65536) -> np.ndarray:
    """The first principal axis of ``values`` (..., C): the colours' main direction, their mean removed, read
    from every k-th value so that at most about ``sample`` are (a unit vector of C; its sign is SVD's)."""
    flat = np.asarray(values).reshape(-1, np.shape(values)[-1])
    centred = flat - flat.mean(axis=0)
    return np.linalg.svd(centred[:: max(1, centred.shape[0] // sample)], full_matrices=False)[2][0]


def box_halved(image) -> np.ndarray:
    """``image`` at half its size, each pixel the mean of a 2 x 2 block (float64; an odd last row or column
    dropped). Any trailing axes (channels) are kept."""
    img = np.asarray(image, dtype=np.float64)
    h, w = img.shape[0] // 2, img.shape[1] // 2
    return img[: 2 * h, : 2 * w].reshape(h, 2, w, 2, *img.shape[2:]).mean(axis=(1, 3))
