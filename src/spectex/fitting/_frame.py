"""A flat frame around a photo: borders, letterboxing, the wedges a rotated photo leaves.

Such a frame is not the ground's texture: left in, the finest tile holds a line or a wedge of one
colour at its edge, and every patch of the texture repeats it (black bars across gravel, one per
patch). :func:`frame_box` finds it; :func:`spectex.fitting.prepare_exemplar` crops it away and says
so. What counts as a frame: a connected region of one colour (every 3 x 3 neighbourhood within
:data:`FLAT_TOL` in each channel, the whole within :data:`COLOUR_TOL`) that runs along the photo's
edge for at least :data:`MIN_EDGE_SHARE` of a side and holds at most one hole (a border holds the photo; a bar or a
wedge none). A grout network is flat too, but holds a hole per tile; a clipped highlight touches the
edge over a few pixels only.
"""

from __future__ import annotations

import numpy as np

#: Most per-channel range within a 3 x 3 neighbourhood of a frame pixel: under one 8-bit step (a
#: frame is one exact colour, and so is a JPEG's away from its edge; a photo's smoothest parts,
#: scikit-image's brick or moon, vary by one to three steps).
FLAT_TOL = 0.5 / 255.0
#: Most spread (1st to 99th percentile, per channel) of a frame region's colour: one colour, where a
#: smooth photo's flat-looking patches drift (scikit-image's brick: half its pixels are locally flat).
COLOUR_TOL = 1.0 / 255.0
#: Least share of one side of the photo a frame region runs along.
MIN_EDGE_SHARE = 0.25
#: Most rows or columns of JPEG ringing cropped beyond the frame's exact part (one block), and how
#: near its colour (per channel) half of such a line must stay.
RING_WIDTH = 8
RING_TOL = 24.0 / 255.0
#: Pixels cropped beyond the frame on each side it touched (the blur or ringing where it meets
#: the photo).
FRAME_MARGIN = 2


def _flat(rgb: np.ndarray) -> np.ndarray:
    """Pixels whose 3 x 3 neighbourhood is within :data:`FLAT_TOL` in every channel (bool)."""
    from scipy import ndimage

    flat = np.ones(rgb.shape[:2], dtype=bool)
    for c in range(rgb.shape[2]):
        ch = rgb[:, :, c]
        flat &= (ndimage.maximum_filter(ch, 3, mode="nearest") - ndimage.minimum_filter(ch, 3, mode="nearest")
                 <= FLAT_TOL)
    return flat


def _frame_mask(rgb: np.ndarray) -> np.ndarray:
    """The frame's pixels (bool, ``rgb``'s height x width)."""
    from scipy import ndimage

    h, w = rgb.shape[:2]
    # most photos have no flat run along any side: their edge rows and columns say so at once
    if max(_flat(rgb[:2])[0].mean(), _flat(rgb[-2:])[-1].mean(), _flat(rgb[:, :2])[:, 0].mean(),
           _flat(rgb[:, -2:])[:, -1].mean()) < MIN_EDGE_SHARE:
        return np.zeros((h, w), dtype=bool)
    labels, n = ndimage.label(_flat(rgb))
    if n == 0:
        return np.zeros((h, w), dtype=bool)
    # how far each region runs along each side (its pixels on the edge rows and columns)
    along = np.zeros(n + 1)
    for line, side in ((labels[0], w), (labels[-1], w), (labels[:, 0], h), (labels[:, -1], h)):
        along = np.maximum(along, np.bincount(line, minlength=n + 1) / side)
    frame = np.zeros((h, w), dtype=bool)
    for k in np.flatnonzero(along >= MIN_EDGE_SHARE):
        if k == 0:
            continue
        region = labels == k
        spread = np.percentile(rgb[region], [1.0, 99.0], axis=0)
        if float(np.max(spread[1] - spread[0])) > COLOUR_TOL:
            continue
        # a frame holds one photo (a border: one hole) or none (a bar, a wedge); a grout network
        # holds a hole per tile
        inside, m = ndimage.label(~region)
        edge = np.unique(np.concatenate([inside[0], inside[-1], inside[:, 0], inside[:, -1]]))
        if m - np.count_nonzero(edge) <= 1:
            frame |= region
    # the 3 x 3 test leaves out the frame's last pixel before the photo: grown back by one
    return ndimage.binary_dilation(frame)


def frame_box(rgb):
    """The box of the photo inside a flat frame, or None where it has none.

    ``rgb``: an (H, W, C) float image in [0, 1]. The frame's pixels (see the module) are cropped
    away greedily, one edge row or column at a time, always the edge holding the largest share of
    frame, until no edge holds any; then up to :data:`RING_WIDTH` lines more on each side that was
    cropped while half a line stays within :data:`RING_TOL` of the frame's colour (a JPEG's ringing),
    and :data:`FRAME_MARGIN` pixels more. Returns ``(y0, y1, x0, x1)``: ``rgb[y0:y1, x0:x1]`` is the
    photo without its frame.
    """
    frame = _frame_mask(np.asarray(rgb))
    if not frame.any():
        return None
    h, w = frame.shape
    y0, y1, x0, x1 = 0, h, 0, w
    while y1 - y0 > 0 and x1 - x0 > 0:
        box = frame[y0:y1, x0:x1]
        shares = (box[0].mean(), box[-1].mean(), box[:, 0].mean(), box[:, -1].mean())
        k = int(np.argmax(shares))
        if shares[k] == 0.0:
            break
        if k == 0:
            y0 += 1
        elif k == 1:
            y1 -= 1
        elif k == 2:
            x0 += 1
        else:
            x1 -= 1
    # a frame saved as JPEG rings where it meets the photo (up to a block of 8 pixels): edge lines
    # still mostly near the frame's colour go with it
    rgb = np.asarray(rgb)
    colour = np.median(rgb[frame], axis=0)

    def near(line):
        return np.mean(np.max(np.abs(line - colour), axis=-1) <= RING_TOL) >= 0.5

    for _ in range(RING_WIDTH):
        if y0 > 0 and y1 - y0 > 1 and near(rgb[y0, x0:x1]):
            y0 += 1
        if y1 < h and y1 - y0 > 1 and near(rgb[y1 - 1, x0:x1]):
            y1 -= 1
        if x0 > 0 and x1 - x0 > 1 and near(rgb[y0:y1, x0]):
            x0 += 1
        if x1 < w and x1 - x0 > 1 and near(rgb[y0:y1, x1 - 1]):
            x1 -= 1
    m = FRAME_MARGIN
    y0, y1 = y0 + (m if y0 else 0), y1 - (m if y1 < h else 0)
    x0, x1 = x0 + (m if x0 else 0), x1 - (m if x1 < w else 0)
    return y0, max(y0, y1), x0, max(x0, x1)
