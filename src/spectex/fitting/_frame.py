"""A flat frame around a photo: borders, letterboxing, the wedges a rotated photo leaves.

Such a frame is not the ground's texture: left in, the finest tile holds a line or a wedge of one
colour at its edge, and every patch of the texture repeats it (black bars across gravel, one per
patch). :func:`frame_box` finds it; :func:`spectex.fitting.prepare_exemplar` crops it away and says
so. What counts as a frame: a connected region of one colour (every 3 x 3 neighbourhood within
:data:`FLAT_TOL` in each channel, the whole within :data:`COLOUR_TOL`) that runs along the photo's
edge for at least :data:`MIN_EDGE_SHARE` of a side, holds at most one hole (a border holds the
photo; a bar or a wedge none) and has no flat region of its colour elsewhere a quarter its size (a
stripe of a striped pattern); or, for a frame saved as JPEG (nowhere exact), a band of uniform
lines along a side whose colour no line across the rest of the photo has (:func:`_bands`). A grout
network is flat too, but holds a hole per tile; a clipped highlight touches the edge over a few
pixels only; a grout or joint line along the edge comes back at every period.
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
#: A band along a side (a thin frame saved as JPEG, which is nowhere exact): edge lines each within
#: this spread (2nd to 98th percentile, per channel) and of the outermost line's median colour.
BAND_TOL = 16.0 / 255.0
#: Deepest such band (a thicker frame is exact away from the photo and found as one colour): a band
#: as deep is a sky or a smooth part of the photo, not a frame.
BAND_DEPTH = 16
#: Shortest side a band is looked for along, and the least step (per channel, the largest) from its
#: colour to the photo's lines just past it: a frame stands out from the photo, where a smooth
#: photo's uniform edge (a brick's face, a sky) runs on into it.
BAND_MIN_SIDE = 128
BAND_STEP = 48.0 / 255.0
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


def _uniform(lines, colour=None, spread=BAND_TOL):
    """Per line (axis 0 of ``lines``, each a row of pixels): whether its 2nd-98th percentile spread is
    within ``spread`` in every channel (and its median within :data:`BAND_TOL` of ``colour``, where
    given)."""
    lo, mid, hi = np.percentile(lines, [2.0, 50.0, 98.0], axis=1)
    ok = np.max(hi - lo, axis=-1) <= spread
    if colour is not None:
        ok &= np.max(np.abs(mid - colour), axis=-1) <= BAND_TOL
    return ok


def _run(lines, colour):
    """How many of ``lines``, from the first, are uniform and of ``colour`` (:func:`_uniform`)."""
    if not lines.shape[0]:
        return 0
    run = _uniform(lines, colour)
    return lines.shape[0] if run.all() else int(np.argmin(run))


def _bands(rgb: np.ndarray) -> np.ndarray:
    """Uniform bands along the sides (a frame saved as JPEG: each of its lines one colour give or take
    :data:`BAND_TOL`, the photo's lines not), under :data:`BAND_DEPTH` lines deep, along a side of
    :data:`BAND_MIN_SIDE` or more, a step of :data:`BAND_STEP` from the photo past it, that the photo shows
    nowhere else (no line of the same colour across the rest of it: a grout line along the edge
    recurs at every period). Bool mask."""
    h, w = rgb.shape[:2]
    mask = np.zeros((h, w), dtype=bool)
    # each side as lines running along it, outermost first: top, bottom, left, right
    sides = (rgb, rgb[::-1], rgb.transpose(1, 0, 2), rgb.transpose(1, 0, 2)[::-1])
    views = (mask, mask[::-1], mask.T, mask.T[::-1])
    for lines, view in zip(sides, views):
        depth = min(lines.shape[0] // 4, BAND_DEPTH)
        if lines.shape[1] < BAND_MIN_SIDE or depth < 1 or not _uniform(lines[:1])[0]:
            continue
        colour = np.median(lines[0], axis=0)
        k, far = _run(lines[:depth], colour), _run(lines[::-1][:depth], colour)
        past = lines[k + FRAME_MARGIN: k + FRAME_MARGIN + 4]
        if not past.shape[0] or np.max(np.abs(np.median(past, axis=(0, 1)) - colour)) < BAND_STEP:
            continue
        # the rest: past the band and its ringing, and past a band of the same colour on the far side
        n = lines.shape[0]
        rest = lines[2 * k + FRAME_MARGIN: n - (2 * far + FRAME_MARGIN if far else 0)]
        # (a line of the photo's own, a joint between rows of planks, varies more than the edge's:
        # twice the spread)
        if 0 < k < depth and not (rest.shape[0] and _uniform(rest, colour, 2.0 * BAND_TOL).any()):
            view[:k] = True
    return mask


def _frame_mask(rgb: np.ndarray) -> np.ndarray:
    """The frame's pixels (bool, ``rgb``'s height x width)."""
    from scipy import ndimage

    h, w = rgb.shape[:2]
    # most photos have no flat run along any side: their edge rows and columns say so at once
    if max(_flat(rgb[:2])[0].mean(), _flat(rgb[-2:])[-1].mean(), _flat(rgb[:, :2])[:, 0].mean(),
           _flat(rgb[:, -2:])[:, -1].mean()) < MIN_EDGE_SHARE:
        return ndimage.binary_dilation(_bands(rgb))
    labels, n = ndimage.label(_flat(rgb))
    # how far each region runs along each side (its pixels on the edge rows and columns)
    along = np.zeros(n + 1)
    for line, side in ((labels[0], w), (labels[-1], w), (labels[:, 0], h), (labels[:, -1], h)):
        along = np.maximum(along, np.bincount(line, minlength=n + 1) / side)
    frame = _bands(rgb)
    sizes = np.bincount(labels.ravel(), minlength=n + 1)
    # the flat regions away from the edge and their mean colours (the recurrence test below)
    others = np.flatnonzero((along < MIN_EDGE_SHARE) & (sizes >= 9))
    others = others[others > 0]
    means = (np.stack([ndimage.mean(rgb[:, :, c], labels, others) for c in range(rgb.shape[2])], axis=-1)
             if others.size else None)
    for k in np.flatnonzero(along >= MIN_EDGE_SHARE):
        if k == 0:
            continue
        region = labels == k
        spread = np.percentile(rgb[region], [1.0, 99.0], axis=0)
        if float(np.max(spread[1] - spread[0])) > COLOUR_TOL:
            continue
        # a frame is there once: flat regions of its colour away from the edge as large as a quarter
        # of it (the other stripes of a striped pattern) make it the photo's own
        colour = np.median(rgb[region], axis=0)
        if means is not None:
            alike = np.max(np.abs(means - colour), axis=-1) <= COLOUR_TOL
            if sizes[others[alike]].sum() >= sizes[k] / 4:
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
    frame, until no edge holds any; then up to :data:`RING_WIDTH` lines more on each side while half
    a line stays within :data:`RING_TOL` of the frame's colour (a JPEG's ringing, and a side whose
    thin frame rang too much to be found), and :data:`FRAME_MARGIN` pixels more on each side cropped.
    Returns ``(y0, y1, x0, x1)``: ``rgb[y0:y1, x0:x1]`` is the photo without its frame.
    """
    rgb = np.asarray(rgb)
    frame = _frame_mask(rgb)
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
    colour = np.median(rgb[frame], axis=0)

    def near(line):
        return line.size > 0 and np.mean(np.max(np.abs(line - colour), axis=-1) <= RING_TOL) >= 0.5

    # (on every side: a side whose thin frame rang too much to be found goes with the others)
    for _ in range(RING_WIDTH):
        if y1 - y0 > 1 and near(rgb[y0, x0:x1]):
            y0 += 1
        if y1 - y0 > 1 and near(rgb[y1 - 1, x0:x1]):
            y1 -= 1
        if x1 - x0 > 1 and near(rgb[y0:y1, x0]):
            x0 += 1
        if x1 - x0 > 1 and near(rgb[y0:y1, x1 - 1]):
            x1 -= 1
    m = FRAME_MARGIN
    y0, y1 = y0 + (m if y0 else 0), y1 - (m if y1 < h else 0)
    x0, x1 = x0 + (m if x0 else 0), x1 - (m if x1 < w else 0)
    return y0, max(y0, y1), x0, max(x0, x1)
