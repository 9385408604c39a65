"""The structural cells of a snapped tile: which brick or floor tile each texel belongs to.

A stochastic layer snapped to its tile's structure (``Layer.snap = (nx, ny)``)
draws patches offset by whole periods, so the grout lines of every patch
fall on the same places; but the triangle grid's patch boundaries would
still run through the middle of bricks, so one brick would change colour
partway across. The *cell map* says, per level-0 texel, where the centre of
its structural cell is, so that the sampler can give a whole cell one patch
(``shading.stochastic.cell_point``) and let the patches change on the grout.

It is a deterministic function of the tile and its snap (a derived resource:
texture files do not hold it):

1. the tile is cut into its ``nx x ny`` period cells and averaged: the mean
   period cell keeps what is the same in every period (the grout, sharp) and
   flattens what is not (each brick its own colour);
2. its colours along their principal axis, lightly smoothed on the torus,
   split in two classes by Otsu's threshold; the class whose connected
   components (on the period cell taken as a *torus*: a brick straddling its
   edge is one component, running bond's half bricks) run around the torus
   along more axes (a grid of lines), or the smaller one where both run along
   as many (stripes), is the grout, the other the cells' interiors;
3. every texel (grout too) takes the interior component nearest to it, and
   the map holds the vector from the texel to that component's centre (the
   mean position of its texels, unwrapped, rounded to half texels: exact in
   half floats), tiled over the tile.

Where the structure is weak (the mean period cell varies less than
``MIN_CONTRAST`` times as much as the texels about it, or less than
``CHANCE_FACTOR`` times what its periods' mean leaves of noise, each interior
component of each period at its own mean first: a brick's, a floor tile's or
a scale's own colour is the wall's colouring, not noise about its
structure; a mosaic of tiles of any colour, or the scales of a reptile's
skin coloured in patches, vary far more from cell to cell than their grout
stands out of the mean, and were refused, so the patches' straight
boundaries cut their cells in two), the interiors cover
too little of the period cell, or an interior component runs around the torus
(a band, not a cell: the columns of a wall whose bricks have no period along
them, snapped along x only), there is no map (None) and the layer is sampled
as without one. (Bands were tried, their patches blended at the point moved
onto the band's centre line: brick's bake was no better by eye or by
``metrics.cell_splits``, and the GL frame paid for two samplings.)
"""

from __future__ import annotations

import numpy as np

from .._otsu import otsu

__all__ = ["cell_map", "MIN_CONTRAST", "CHANCE_FACTOR", "MIN_INTERIOR", "MIN_CELL"]

#: The mean period cell's variance (along its principal colour axis) must be at least this fraction of the
#: texels' variance about it (each cell of each period at its own level), and at least ``CHANCE_FACTOR``
#: times what ``N`` periods of a texture without structure leave in their mean (``1 / N`` of it): a
#: structure repeated in every period, not a texture averaged out. Floor tiles read 5-50, a reptile's
#: scales on a lattice jittered by 6 % of a scale 0.9-1.5, by 12 % 0.44-0.52 (the crevices' own jitter
#: is what is left within the cells).
MIN_CONTRAST = 0.25
#: See ``MIN_CONTRAST``.
CHANCE_FACTOR = 4.0
#: The interiors must cover at least this fraction of the period cell.
MIN_INTERIOR = 0.25
#: A component smaller than this fraction of the period cell is a speck of the grout, not a cell.
MIN_CELL = 0.02


def _torus_components(mask: np.ndarray):
    """Components of ``mask`` on the torus: ``(labels, count, ids, wraps)`` of its 3 x 3 mosaic.

    ``ids``: the labels met in the centre copy; ``wraps[i]``: (along y, along x) whether component ``i``
    runs around the torus (its extent in the mosaic at least one period).
    """
    from scipy import ndimage

    ph, pw = mask.shape
    labels, count = ndimage.label(np.tile(mask, (3, 3)))
    centre = labels[ph:2 * ph, pw:2 * pw]
    ids = np.unique(centre[centre > 0])
    wraps = np.zeros((count + 1, 2), dtype=bool)
    for i, sl in enumerate(ndimage.find_objects(labels), start=1):
        if sl is not None:
            wraps[i] = (sl[0].stop - sl[0].start >= ph + 1, sl[1].stop - sl[1].start >= pw + 1)
    return labels, count, ids, wraps


def _within_cells(deviation: np.ndarray, labels: np.ndarray, period: np.ndarray) -> float:
    """Mean square of ``deviation`` (per texel, about the mean period cell) once each interior component
    (``labels``, per texel, 0 outside the interiors) of each period (``period``, per texel, its index) has its
    own mean deviation taken out: the texture within the cells, without the cells' own colours."""
    width = int(labels.max()) + 1
    group = (period * width + labels).ravel()
    size = (int(period.max()) + 1) * width
    sums = np.bincount(group, weights=deviation.ravel(), minlength=size)
    counts = np.maximum(np.bincount(group, minlength=size), 1)
    level = sums / counts
    level[::width] = 0.0  # outside the interiors (the grout): about the mean cell only
    return float(np.mean((deviation.ravel() - level[group]) ** 2))


def _phases(n: int, count: int):
    """Along an axis of ``n`` texels holding ``count`` periods (``n / count`` texels each, not necessarily
    whole): per texel its period's index and its phase among ``round(n / count)`` bins, the bins' number
    and the period."""
    period = n / count
    bins = int(round(period))
    centre = np.arange(n) + 0.5
    index = np.minimum((centre // period).astype(np.int64), count - 1)
    phase = np.clip(((centre - index * period) * bins / period).astype(np.int64), 0, bins - 1)
    return index, phase, bins, period


def cell_map(tile, snap) -> np.ndarray | None:
    """Per texel of ``tile``, the vector to the centre of its structural cell, or None.

    Parameters
    ----------
    tile : ndarray, shape (H, W, 3) or (H, W, 4)
        A tile in [0, 1]; alpha is ignored.
    snap : (int, int)
        ``(nx, ny)``: the whole structure periods the tile holds along x and y
        (``Layer.snap``; 0: the whole tile is one period along that axis, as
        where the offsets are not snapped along it). No map unless there are
        at least 4 periods in all (the mean period cell needs them), each at
        least 4 texels across. A period need not be a whole number of
        texels: the tile is folded into ``round(period)`` phases.

    Returns
    -------
    ndarray, shape (H, W, 2), float32, or None
        ``(dx, dy)``: the centre of texel ``(x, y)``'s cell is at texel
        position ``(x + dx, y + dy)`` (unwrapped: near the texel, possibly
        outside the tile; multiples of 1/2). None where the tile shows no
        separate cells (see the module's text).
    """
    from scipy import ndimage

    tile = np.asarray(tile)
    nx, ny = max(int(snap[0]), 1), max(int(snap[1]), 1)
    h, w = tile.shape[:2]
    if nx * ny < 4 or h < 4 * ny or w < 4 * nx:
        return None
    # each texel's period and phase: a period of a fractional number of texels (a hexagonal lattice's rows,
    # sqrt(3) times its columns, never both whole in a square tile) is folded into round(p) phase bins
    ky, fy, by, ph = _phases(h, ny)
    kx, fx, bx, pw = _phases(w, nx)
    rgb = tile[:, :, :3].astype(np.float64)
    if h % ny == 0 and w % nx == 0:
        mean = rgb.reshape(ny, by, nx, bx, 3).mean(axis=(0, 2))
    else:
        phase = (fy[:, None] * bx + fx[None, :]).ravel()
        counts = np.maximum(np.bincount(phase, minlength=by * bx), 1)
        mean = np.stack([np.bincount(phase, weights=rgb[:, :, c].ravel(), minlength=by * bx) / counts
                         for c in range(3)], axis=1).reshape(by, bx, 3)
    flat = mean.reshape(-1, 3) - mean.reshape(-1, 3).mean(axis=0)
    axis = np.linalg.svd(flat, full_matrices=False)[2][0]
    level = (mean @ axis)
    level = sum(np.roll(np.roll(level, dy, axis=0), dx, axis=1) for dy in (-1, 0, 1) for dx in (-1, 0, 1)) / 9.0
    high = level > otsu(level.ravel())[0]
    if high.all() or not high.any():
        return None
    classes = []
    for mask in (high, ~high):
        labels, count, ids, wraps = _torus_components(mask)
        classes.append((int(wraps[ids].any(axis=0).sum()), mask.mean(), mask, labels, count, ids, wraps))
    # the grout: runs around along more axes, or the smaller class where both run along as many
    grout = max(range(2), key=lambda c: (classes[c][0], -classes[c][1]))
    _, area, _, labels, count, ids, wraps = classes[1 - grout]
    # the structure's strength: the mean period cell's variance against the texels' own about it, each cell
    # of each period taken at its own level first (a brick, a floor tile or a scale has its own colour: what
    # the mean flattens of it is the colouring, not an absence of structure)
    centre = labels[by:2 * by, bx:2 * bx]
    structure = float(np.var(mean @ axis))
    deviation = rgb @ axis - (mean @ axis)[fy[:, None], fx[None, :]]
    residual = _within_cells(deviation, centre[fy[:, None], fx[None, :]], ky[:, None] * nx + kx[None, :])
    if area < MIN_INTERIOR or structure < max(MIN_CONTRAST, CHANCE_FACTOR / (nx * ny)) * residual:
        return None
    sizes = ndimage.sum_labels(np.ones(labels.shape), labels, index=np.arange(count + 1))
    keep = np.zeros(count + 1, dtype=bool)
    keep[ids] = sizes[ids] >= MIN_CELL * by * bx
    if not keep.any() or wraps[keep].any():
        return None  # no cells, or bands running around the torus
    kept = keep[labels]
    yy, xx = np.indices(labels.shape, dtype=np.float64)
    index = np.arange(count + 1)
    n = np.maximum(ndimage.sum_labels(kept, labels, index=index), 1.0)
    cy = ndimage.sum_labels(np.where(kept, yy, 0.0), labels, index=index) / n
    cx = ndimage.sum_labels(np.where(kept, xx, 0.0), labels, index=index) / n
    # every phase bin's nearest kept interior bin (itself inside one), on the mosaic so that it wraps
    _, (iy, ix) = ndimage.distance_transform_edt(~kept, return_indices=True)
    owner = labels[iy, ix][by:2 * by, bx:2 * bx]
    if h % ny == 0 and w % nx == 0:
        py, px = np.indices((by, bx), dtype=np.float64)
        d = np.stack([cx[owner] - (px + bx), cy[owner] - (py + by)], axis=2)
        d = np.tile(d, (ny, nx, 1))
    else:
        # the cell's centre in texels: its period's start plus its centre's phase (bin centres at half bins)
        own = owner[fy[:, None], fx[None, :]]
        y = np.arange(h, dtype=np.float64)[:, None] + 0.5
        x = np.arange(w, dtype=np.float64)[None, :] + 0.5
        dy = ky[:, None] * ph + (cy[own] - by + 0.5) * (ph / by) - y
        dx = kx[None, :] * pw + (cx[own] - bx + 0.5) * (pw / bx) - x
        d = np.stack([dx, dy], axis=2)
    d = np.round(2.0 * d) / 2.0
    return np.ascontiguousarray(d, dtype=np.float32)
