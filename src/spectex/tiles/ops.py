"""Operations on tile images: :func:`emboss` (the paper's alpha), :func:`fit_range`
(back into [0, 1] without breaking a band limit) and :func:`preview` (is it seamless?).
"""

from __future__ import annotations

import math

import numpy as np

from .._parallel import threads_for as _threads_for
from .._validate import check_float, check_image, check_int
from ..color import luma
from .mipmap import mip_chain

__all__ = ["emboss", "fit_range", "preview"]

#: Below this many pixels the emboss gradient runs in NumPy (as ``from_noise.NUMPY_MAX``).
_NUMPY_MAX = 1 << 21


def _gradient_numpy(h, cx, cy, g):
    """``tiles._kernels.gradient`` in NumPy (small images: no numba kernel to load)."""
    g[...] = (cx * (np.roll(h, -1, axis=1) - np.roll(h, 1, axis=1))
              + cy * (np.roll(h, 1, axis=0) - np.roll(h, -1, axis=0)))


def fit_range(values) -> np.ndarray:
    """Map values into [0, 1] by an affine map, only if they leave it.

    ``(v - lo) / (hi - lo)`` with ``lo = min(0, v.min())`` and
    ``hi = max(1, v.max())``: values already in [0, 1] are returned
    unchanged (as float32); otherwise the range is compressed just enough.
    An affine map adds no frequencies (except at zero), so a band-limited
    channel stays band-limited, which clipping would not.
    """
    v = np.asarray(values, dtype=np.float32)
    if v.size == 0:
        return v
    lo, hi = float(v.min()), float(v.max())
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ValueError(f"values must be finite to be fitted into [0, 1], got a range of {lo} to {hi}")
    if lo >= 0.0 and hi <= 1.0:
        return v
    lo, hi = min(lo, 0.0), max(hi, 1.0)
    out = (v - np.float32(lo)) * np.float32(1.0 / (hi - lo))
    np.clip(out, 0.0, 1.0, out=out)  # rounding only
    return out


def emboss(image, *, azimuth: float = 135.0, strength: float = 1.0) -> np.ndarray:
    """Emboss filter: the image lit as a relief from direction ``azimuth``.

    The image (its luma for colour) is taken as a height field ``h``. With
    the light at ``L = (cos a, sin a)`` (``a`` in degrees counter-clockwise
    from the +x axis, y pointing up, so the default 135 lights from the top
    left), the shading of a gently sloping relief is ``g = -(L . grad h)``,
    with the gradient by central differences that wrap around (so a
    seamless image gives a seamless result)::

        d/dx h[i, j] = (h[i, j+1] - h[i, j-1]) / 2
        d/dy h[i, j] = (h[i-1, j] - h[i+1, j]) / 2      (row 0 is the top)

    and ``alpha = 0.5 + 0.5 strength g / max|g|``, clipped to [0, 1]: slopes
    facing the light are above 0.5. With ``strength <= 1`` nothing is
    clipped and the map is linear, so a band-limited image gives a
    band-limited result; ``strength = 1`` reaches 0 or 1 at the steepest
    slope.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        At least 3 x 3.
    azimuth : float
        Direction of the light, degrees.
    strength : float
        Contrast, >= 0 (0 gives a constant 0.5).

    Returns
    -------
    ndarray, shape (H, W), float32 in [0, 1]
    """
    image = check_image("image", image, min_size=3)
    azimuth = check_float("azimuth", azimuth)
    strength = check_float("strength", strength, minimum=0.0, maximum=1e6)
    return _emboss(luma(image), azimuth, strength)


def _emboss(h: np.ndarray, azimuth: float, strength: float) -> np.ndarray:
    a = math.radians(azimuth)
    g = np.empty(h.shape, dtype=np.float32)
    if h.size <= _NUMPY_MAX:
        gradient = _gradient_numpy
    else:
        from ._kernels import gradient
    with _threads_for(h.size):
        gradient(np.ascontiguousarray(h, dtype=np.float32), np.float32(-0.5 * math.cos(a)),
                 np.float32(-0.5 * math.sin(a)), g)
    top = max(float(g.max()), -float(g.min()))
    if top == 0.0 or strength == 0.0:
        return np.full(h.shape, 0.5, dtype=np.float32)
    g *= np.float32(0.5 * strength / top)
    g += np.float32(0.5)
    if strength > 1.0:
        np.clip(g, 0.0, 1.0, out=g)
    return g.astype(np.float32, copy=False)


def preview(tile, *, repeat: int = 3, max_side: int = 1024) -> np.ndarray:
    """A picture that shows whether a tile is seamless.

    The colour repeated ``repeat x repeat`` times, a white gap, and the
    alpha channel (as grey) repeated the same way, side by side. Tiles with
    a side above ``max_side`` are shown by the first level of
    :func:`mip_chain` that fits.

    Parameters
    ----------
    tile : ndarray, shape (H, W, 4), (H, W, 3) or (H, W)
        Without alpha, only the colour part is drawn.
    repeat : int
        Repetitions along each axis, 1 to 8.
    max_side : int
        Largest tile side drawn at full resolution.

    Returns
    -------
    ndarray, float32, shape (repeat h, repeat w [+ gap + repeat w], 3)
    """
    tile = check_image("tile", tile)
    repeat = check_int("repeat", repeat, minimum=1, maximum=8)
    max_side = check_int("max_side", max_side, minimum=1)
    if tile.ndim == 2:
        tile = tile[:, :, None]
    if max(tile.shape[:2]) > max_side:
        tile = next(level for level in mip_chain(tile) if max(level.shape[:2]) <= max_side)
    c = tile.shape[2]
    colour = tile[:, :, :3] if c >= 3 else np.repeat(tile[:, :, :1], 3, axis=2)
    parts = [np.tile(colour, (repeat, repeat, 1))]
    if c in (2, 4):
        gap = np.ones((parts[0].shape[0], max(4, tile.shape[1] // 16), 3), dtype=np.float32)
        parts += [gap, np.repeat(np.tile(tile[:, :, c - 1:c], (repeat, repeat, 1)), 3, axis=2)]
    return np.concatenate(parts, axis=1).astype(np.float32, copy=False)
