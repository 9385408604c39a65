"""Mip-map chains of tiles: :func:`mip_chain`, averaged as stored or in linear light.

References
----------
L. Williams, "Pyramidal parametrics", SIGGRAPH 1983 (mip-maps).
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import check_choice, check_image
from ..color import linear_to_srgb, srgb_to_linear

__all__ = ["gl_level_shapes", "mip_chain", "quantize"]


def _reduce_matrix(n: int) -> np.ndarray:
    """(floor(n/2) or 1) x n area weights: output texel i averages [i r, (i+1) r)."""
    m = max(1, n // 2)
    r = n / m
    a = np.zeros((m, n))
    for i in range(m):
        lo, hi = i * r, (i + 1) * r
        for k in range(int(math.floor(lo)), min(n, int(math.ceil(hi)))):
            a[i, k] = (min(hi, k + 1) - max(lo, k)) / r
    return a


def _reduce(level: np.ndarray) -> np.ndarray:
    """One mip reduction of an (h, w, C) float32 level."""
    h, w, c = level.shape
    if h % 2 == 0 and w % 2 == 0:
        out = np.empty((h // 2, w // 2, c), dtype=np.float32)
        step = max(1, (1 << 22) // max(1, w * c))  # output rows per block: bounded float64 work space
        for r0 in range(0, h // 2, step):
            r1 = min(h // 2, r0 + step)
            x = level[2 * r0:2 * r1].reshape(r1 - r0, 2, w // 2, 2, c).astype(np.float64)
            out[r0:r1] = (x[:, 0, :, 0] + x[:, 0, :, 1] + x[:, 1, :, 0] + x[:, 1, :, 1]) * 0.25
        return out
    x = level.astype(np.float64)
    # the area weights as matrix products (BLAS; einsum's loops took 2.9 of a 9 s fit of a cut tile)
    if h > 1:
        x = np.tensordot(_reduce_matrix(h), x, axes=(1, 0))
    if w > 1:
        x = np.moveaxis(np.tensordot(x, _reduce_matrix(w), axes=(1, 1)), 2, 1)
    return np.ascontiguousarray(x, dtype=np.float32)


def mip_chain(tile, *, space: str = "stored") -> list[np.ndarray]:
    """The mip-map chain of a tile: box reductions down to 1 x 1.

    Level 0 is the tile itself (as float32); level ``k + 1`` has
    ``max(1, floor(n / 2))`` texels along each side of ``n`` texels
    (OpenGL's rule for the sizes of mip levels), and is computed from level
    ``k`` (not from the tile), as ``glGenerateMipmap`` does.

    Filtering. For even sides, each texel of the next level is the mean of a
    2 x 2 block (exactly). For an odd side ``n``, texel ``i`` of the next
    level averages the interval ``[i r, (i + 1) r)`` of the level, with
    ``r = n / floor(n / 2)``, weighting the texels it covers partly by the
    part covered: the footprints of a level's texels partition one period
    of the tile exactly, so every level tiles with the same world period and
    keeps the tile's mean (no row or column is dropped, as a plain 2 x 2 box
    on an odd side would drop one; OpenGL leaves the filter for
    non-power-of-two sides to the implementation, so the renderer uploads
    these levels rather than calling ``glGenerateMipmap``). Because the
    footprints never cross the wrap edge, the chain is exact for a
    repeating texture: a texel straddling the edge would mix the last and
    the first texels, which is the same thing for a seamless tile.

    Averaging space. ``'stored'`` (default) averages the stored values, as
    ``glGenerateMipmap`` does for non-sRGB formats such as ``GL_RGBA8``: use
    it when the tile is uploaded as a plain (linear-format) texture, so that
    these levels are exactly what the GPU would make. ``'linear'`` decodes
    the colour channels from sRGB, averages in linear light and encodes
    again, as GL does for ``GL_SRGB8_ALPHA8`` textures; use it with sRGB
    textures. Alpha is always averaged as stored. Averaging in linear light
    keeps the perceived brightness of fine contrast at a distance (a
    black-and-white checkerboard becomes sRGB 0.735, not 0.5); averaging
    stored values darkens high-contrast detail in the distance but matches
    the plain-texture pipeline.

    Parameters
    ----------
    tile : ndarray, shape (H, W) or (H, W, C)
    space : {'stored', 'linear'}
        Averaging space (see above). ``'linear'`` treats channels 0-2 of an
        RGB(A) tile, or channel 0 of a grey(+alpha) tile, as sRGB.

    Returns
    -------
    list of ndarray, each float32 of shape (h_k, w_k, C)
        ``1 + floor(log2(max(H, W)))`` levels, the last 1 x 1. A 2-D tile
        gives levels of shape (h_k, w_k, 1).
    """
    tile = check_image("tile", tile)
    space = check_choice("space", space, ("stored", "linear"))
    level = tile[:, :, None] if tile.ndim == 2 else tile
    c = level.shape[2]
    colour = slice(0, 3) if c >= 3 else slice(0, 1)
    chain = [level]
    while level.shape[0] > 1 or level.shape[1] > 1:
        if space == "linear":
            lin = level.copy()
            lin[:, :, colour] = srgb_to_linear(level[:, :, colour])
            nxt = _reduce(lin)
            nxt[:, :, colour] = linear_to_srgb(nxt[:, :, colour])
        else:
            nxt = _reduce(level)
        chain.append(nxt)
        level = nxt
    return chain


def gl_level_shapes(height: int, width: int) -> list[tuple[int, int]]:
    """The mip level shapes OpenGL allocates for a base level of ``height x width``.

    Each level halves both sides, rounding down, never below 1, down to 1 x 1.
    """
    shapes = [(int(height), int(width))]
    while shapes[-1] != (1, 1):
        h, w = shapes[-1]
        shapes.append((max(1, h // 2), max(1, w // 2)))
    return shapes


def quantize(image: np.ndarray, bits: int | None) -> np.ndarray:
    """Quantise ``image`` in [0, 1] to ``bits`` per channel, as a UNORM texture stores it.

    ``round(clip(v, 0, 1) * (2**bits - 1)) / (2**bits - 1)``; ``None`` returns
    a float32 copy unchanged.
    """
    image = np.asarray(image, dtype=np.float32)
    if bits is None:
        return image.copy()
    top = np.float32(2 ** bits - 1)
    return (np.floor(np.clip(image, 0.0, 1.0) * top + np.float32(0.5)) / top).astype(np.float32)
