"""One-off content left out of the fit: a leaf on gravel, a tripod's foot on a lawn.

A texture made of pieces of a photo shows every piece once per photo area; a
piece that looks like no other (found by :func:`spectex.metrics.one_off_repeats`'s
rarity) is then the first thing a viewer sees, the same object at random
places. :func:`remove_one_off` fills its region from elsewhere in the photo
before the fit cuts its tile: the window around the region (the region and a
ring of its surroundings) is matched against every window of the photo that
holds none of it, by the squared difference over the ring, and the best
window's content is pasted in, cut along four minimum-error paths through the
ring (Efros and Freeman 2001), so that the seam runs where the two agree.

References
----------
A. A. Efros, W. T. Freeman, "Image quilting for texture synthesis and
transfer", SIGGRAPH 2001.
"""

from __future__ import annotations

import numpy as np

__all__ = ["remove_one_off"]

#: The ring around the region, as a fraction of its larger side (at least :data:`MIN_RING` pixels).
RING = 0.5
MIN_RING = 6
#: The window (region and ring) may cover at most this fraction of the photo: a larger region is
#: not one object in a texture, and too little of the photo would be left to fill it from.
MAX_WINDOW_SHARE = 0.25


def fill_window(box, shape):
    """The region's window: the box grown by the ring on every side, inside the photo."""
    y0, x0, y1, x1 = box
    ring = max(MIN_RING, int(round(RING * max(y1 - y0, x1 - x0))))
    return (max(0, y0 - ring), max(0, x0 - ring), min(shape[0], y1 + ring), min(shape[1], x1 + ring))


def _ring_costs(photo, window, box):
    """Squared difference over the window's ring between the window and the photo's window at every
    place (top-left corners; +inf where the photo's window would hold any of the region's window)."""
    import scipy.fft as sfft

    wy0, wx0, wy1, wx1 = window
    y0, x0, y1, x1 = box
    th, tw = wy1 - wy0, wx1 - wx0
    h, w = photo.shape[:2]
    ring = np.ones((th, tw))
    ring[y0 - wy0:y1 - wy0, x0 - wx0:x1 - wx0] = 0.0
    shape = (h + th, w + tw)
    fr = np.conj(sfft.rfft2(ring, s=shape))
    cost = np.zeros((h - th + 1, w - tw + 1))
    for c in range(photo.shape[2]):
        img = photo[:, :, c].astype(np.float64)
        t = img[wy0:wy1, wx0:wx1] * ring
        fi = sfft.rfft2(img, s=shape)
        sq = sfft.irfft2(sfft.rfft2(img * img, s=shape) * fr, s=shape)[:h - th + 1, :w - tw + 1]
        cross = sfft.irfft2(fi * np.conj(sfft.rfft2(t, s=shape)), s=shape)[:h - th + 1, :w - tw + 1]
        cost += sq - 2.0 * cross + float(np.sum(t * t))
    # no source window overlapping the region's own window (it would copy the object, or itself)
    ys, xs = np.arange(cost.shape[0])[:, None], np.arange(cost.shape[1])[None, :]
    overlap = (ys < wy1) & (ys + th > wy0) & (xs < wx1) & (xs + tw > wx0)
    return np.where(overlap, np.inf, cost)


def _cut_mask(err, inner):
    """Where the window takes the source: inside four minimum-error paths through the ring, one per side
    (the top one across the rows above ``inner``, and so on), each running the window's whole length."""
    from .._seams import min_cut_path

    th, tw = err.shape
    iy0, ix0, iy1, ix1 = inner
    mask = np.ones((th, tw), bool)
    rows, cols = np.arange(th)[:, None], np.arange(tw)[None, :]
    if iy0 > 0:  # top: a left-to-right path through rows 0 .. iy0 - 1; the source below it
        path = min_cut_path(np.ascontiguousarray(err[:iy0].T))
        mask &= rows >= path[None, :]
    if iy1 < th:  # bottom: through rows iy1 .. th - 1; the source above it
        path = min_cut_path(np.ascontiguousarray(err[iy1:].T)) + iy1
        mask &= rows <= path[None, :]
    if ix0 > 0:  # left
        path = min_cut_path(np.ascontiguousarray(err[:, :ix0]))
        mask &= cols >= path[:, None]
    if ix1 < tw:  # right
        path = min_cut_path(np.ascontiguousarray(err[:, ix1:])) + ix1
        mask &= cols <= path[:, None]
    mask[iy0:iy1, ix0:ix1] = True
    return mask


def remove_one_off(photo: np.ndarray, box):
    """Fill the region ``box`` (``(y0, x0, y1, x1)``, photo pixels) of an RGB float photo from the rest of it.

    Returns ``(filled, source)``: a new array, equal to the photo outside the region's window, and the
    top-left corner of the window it was filled from; ``(photo, None)`` where the window would cover over
    :data:`MAX_WINDOW_SHARE` of the photo or no window of the photo holds none of it.
    """
    h, w = photo.shape[:2]
    window = fill_window(box, (h, w))
    wy0, wx0, wy1, wx1 = window
    if (wy1 - wy0) * (wx1 - wx0) > MAX_WINDOW_SHARE * h * w:
        return photo, None
    cost = _ring_costs(photo, window, box)
    if not np.isfinite(cost).any():
        return photo, None
    sy, sx = (int(v) for v in np.unravel_index(int(np.argmin(cost)), cost.shape))
    th, tw = wy1 - wy0, wx1 - wx0
    target = photo[wy0:wy1, wx0:wx1]
    source = photo[sy:sy + th, sx:sx + tw]
    err = np.sum((source.astype(np.float64) - target) ** 2, axis=2)
    y0, x0, y1, x1 = box
    mask = _cut_mask(err, (y0 - wy0, x0 - wx0, y1 - wy0, x1 - wx0))
    filled = photo.copy()
    filled[wy0:wy1, wx0:wx1][mask] = source[mask]
    return filled, (sy, sx)
