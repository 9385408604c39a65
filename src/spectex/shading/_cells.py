"""The structural cells of a tile: which brick, floor tile or cobble each texel belongs to.

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

A tile drawn with free offsets (``snap`` (0, 0)) has no lattice: each patch
shows its own cells wherever it lies. Cobbles, or pebbles set in mortar,
are cells all the same, parted by a network of grout lines
(:func:`free_cell_map` finds it on the tile itself); with their map, the
sampler gives each point the patch whose own cell there lies in that
patch's region (``shading.stochastic.cell_vertex``), so cobbles are drawn
whole and a cobble that loses is cut along the winner's outline, in its
grout, instead of by the triangle grid's straight cross-fades.
"""

from __future__ import annotations

import numpy as np

from .._otsu import otsu
from .._pixels import principal_axis

__all__ = ["cell_map", "free_cell_map", "course_map", "COURSE_MIN_JOINTED", "COURSE_MIN_UNITS", "JOINT_DEPTH",
           "MIN_CONTRAST", "CHANCE_FACTOR", "MIN_INTERIOR", "MIN_CELL",
           "FREE_WIDTHS", "FREE_MIN_CELLS", "FREE_MIN_INTERIOR", "FREE_MERGED", "NO_CELL"]

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
#: A tile drawn without snapping (its patches offset freely: cobbles, pebbles in mortar) has cells where
#: a network of thin lines parts at least this many
#: (components of at least ``MIN_CELL_TEXELS`` texels; :func:`free_cell_map`) ...
FREE_MIN_CELLS = 8
MIN_CELL_TEXELS = 24
#: ... which cover at least this fraction of the tile, those more than ``FREE_MERGED`` times the median
#: cell's size left out (cells run together where a grout line is broken: a texel of one is 60 texels from
#: its centre, and a patch showing it whole showed the break as a cut through a stone, not in the grout).
FREE_MIN_INTERIOR = 0.35
FREE_MERGED = 3.0
#: The cell map's entry for a texel of no cell (a merged one's, or the grout nearest it): a centre this many
#: texels away, which no patch's region holds, so the sampler blends there (``stochastic.cell_vertex``).
NO_CELL = 4096.0
#: A tile snapped along one axis only (courses of boards, columns of bricks: :func:`course_map`) has a course
#: map where at least this share of its courses have a joint ...
COURSE_MIN_JOINTED = 0.5
#: ... and at least this many boards (units from a joint to the next) in all.
COURSE_MIN_UNITS = 4
#: A joint: a run of columns across a course at least this fraction of the grout's contrast between the
#: courses darker (or lighter) than the course about it (a top-hat of the course's mean profile).
JOINT_DEPTH = 0.4


def _torus_components(mask: np.ndarray, margin: int | None = None):
    """Components of ``mask`` on the torus: ``(labels, count, ids, wraps)`` of its 3 x 3 mosaic (``margin``:
    of the tile with that many texels of its wrap around it, a smaller mosaic where components are smaller).

    ``ids``: the labels met in the centre copy; ``wraps[i]``: (along y, along x) whether component ``i``
    runs around the torus (its extent in the mosaic at least one period).
    """
    from scipy import ndimage

    ph, pw = mask.shape
    my, mx = (ph, pw) if margin is None else (min(margin, ph), min(margin, pw))
    labels, count = ndimage.label(np.pad(mask, ((my, my), (mx, mx)), mode="wrap"))
    centre = labels[my:my + ph, mx:mx + pw]
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
    if max(int(snap[0]), int(snap[1])) == 0:
        return free_cell_map(tile)
    if min(int(snap[0]), int(snap[1])) == 0:
        return course_map(tile, snap)
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
    # every phase bin's nearest kept interior bin (itself inside one), on the mosaic so that it wraps
    cy, cx, owner = _nearest_kept(labels, keep)
    owner = owner[by:2 * by, bx:2 * bx]
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


def free_cell_map(tile) -> np.ndarray | None:
    """:func:`cell_map` of a tile whose patches are offset freely (``snap`` (0, 0)): its cells read on the
    tile itself (a torus: it wraps), or None.

    The grout of cobbles, of pebbles set in mortar or the joints of floor boards is a network of thin lines,
    darker or lighter than what they part: the tile's colours along their principal axis, smoothed by a
    Gaussian of one texel, less their grey closing (or opening) over ``k x k`` texels (a top-hat: what is
    thinner than ``k`` and darker, or lighter, than about it), split by Otsu's threshold. It is a grout
    where one component of it runs around the torus along both axes, parting at least ``FREE_MIN_CELLS``
    cells (components of at least ``MIN_CELL_TEXELS`` texels and at most ``FREE_MERGED`` times their median
    size, none running around) that cover at least ``FREE_MIN_INTERIOR`` of the tile; and its lines a network at the
    next smaller ``k`` of :data:`FREE_WIDTHS` too (a grout, not what one width happens to link: grass's
    light blades link up at 17 texels only). The widest such width (dark lines first, then light) gives the map (the
    grout is widened by ``GROUT_WIDEN`` texels first: a line broken for a few texels would join two
    cells); none: None. Every texel (grout too) takes the nearest component; the map holds the vector to its
    centre, as :func:`cell_map`'s, or ``(NO_CELL, NO_CELL)`` where that component is no cell (a merged one, or
    one running around the torus): the sampler blends the patches there.
    """
    from scipy import ndimage

    h, w = tile.shape[:2]
    if min(h, w) < 4 * FREE_WIDTHS[-1]:
        return None
    f = _cell_step(h, w)
    if f > 1:
        return _magnified_map(free_cell_map(tile[:, :, :3].reshape(h // f, f, w // f, f, 3).mean(axis=(1, 3))), f)
    rgb = tile[:, :, :3].astype(np.float64)
    axis = principal_axis(rgb)
    level = ndimage.gaussian_filter(rgb @ axis, 1.0, mode="wrap")
    for sign in (1.0, -1.0):
        for i in range(len(FREE_WIDTHS) - 1, 0, -1):  # the widest first
            cells, _ = _free_cells(sign * level, FREE_WIDTHS[i])
            if cells is not None and _free_cells(sign * level, FREE_WIDTHS[i - 1], network_only=True)[1]:
                return _centres(*cells, h, w)
    return None


#: Largest side :func:`free_cell_map` reads a tile at (texels): a larger tile whose sides are the least
#: whole multiple ``f`` of one under it (a fit's tile at the photo's full resolution, ``fitting/_full.py``) is
#: read area-averaged by ``f`` and its map magnified, so that its grout is as wide, in the texels the
#: widths below count, as in the tile the fit analysed, and the map costs what that tile's does.
FREE_READ_SIDE = 512


def _cell_step(h, w):
    """The whole factor ``f`` by which :func:`free_cell_map` reads an ``h x w`` tile: the least that brings
    both sides to :data:`FREE_READ_SIDE` or under, where it divides both; else 1 (read as it is)."""
    f = -(-max(h, w) // FREE_READ_SIDE)
    return f if f > 1 and h % f == 0 and w % f == 0 else 1


def _magnified_map(small, f):
    """A cell map read on a tile area-averaged by ``f``, for the tile itself: each texel the cell of the
    small texel it lies in, the vector to that cell's centre in its own texels (rounded to half texels)."""
    if small is None:
        return None
    big = np.repeat(np.repeat(small.astype(np.float64), f, axis=0), f, axis=1)
    none = big[:, :, 0] == NO_CELL
    r = np.arange(big.shape[0]) % f, np.arange(big.shape[1]) % f
    big[:, :, 0] = f * big[:, :, 0] + (f - 1) / 2.0 - r[1][None, :]
    big[:, :, 1] = f * big[:, :, 1] + (f - 1) / 2.0 - r[0][:, None]
    big = np.round(2.0 * big) / 2.0
    big[none] = NO_CELL
    return np.ascontiguousarray(big, dtype=np.float32)


#: Widths of the top-hat :func:`free_cell_map` tries (texels), narrowest first.
FREE_WIDTHS = (7, 11, 17)
#: Texels the grout found is widened by on every side before the cells are told apart.
GROUT_WIDEN = 2
#: Texels of the tile's wrap :func:`free_cell_map` labels around it (a cell, or three merged, spans less).
FREE_MARGIN = 128


def _free_cells(level, k, network_only=False):
    """``(labels, keep, merged)`` of the cells parted by the dark lines of ``level`` thinner than ``k`` texels
    (:func:`free_cell_map`'s test), on the 3 x 3 mosaic, or None; and whether those lines are a network
    (``network_only``: that alone, the cells not looked for)."""
    from scipy import ndimage

    h, w = level.shape
    hat = ndimage.grey_closing(level, size=(k, k), mode="wrap") - level
    # widened by 2 texels (on the torus): a grout line broken for a few texels (worn mortar, a stone's
    # edge as light as it) otherwise joins two cells, and soon every cell of a tile into one
    grout = np.pad(hat > otsu(hat.ravel())[0], GROUT_WIDEN, mode="wrap")
    grout = ndimage.binary_dilation(grout, iterations=GROUT_WIDEN)[GROUT_WIDEN:-GROUT_WIDEN, GROUT_WIDEN:-GROUT_WIDEN]
    _, _, gids, gwraps = _torus_components(grout, FREE_MARGIN)
    if not gwraps[gids].all(axis=1).any():
        return None, False
    if network_only:
        return None, True
    labels, count, ids, wraps = _torus_components(~grout, FREE_MARGIN)
    sizes = ndimage.sum_labels(np.ones(labels.shape), labels, index=np.arange(count + 1))
    keep = sizes >= MIN_CELL_TEXELS  # every copy in the mosaic (the nearest cell of a texel by the edge)
    keep[0] = False
    mine = ids[keep[ids]]
    if len(mine) < FREE_MIN_CELLS:
        return None, True
    merged = (sizes > FREE_MERGED * float(np.median(sizes[mine]))) | wraps.any(axis=1)
    cells = keep & ~merged
    m = min(FREE_MARGIN, h), min(FREE_MARGIN, w)
    if int(np.count_nonzero(cells[mine])) < FREE_MIN_CELLS or \
            float(cells[labels[m[0]:m[0] + h, m[1]:m[1] + w]].mean()) < FREE_MIN_INTERIOR:
        return None, True
    return (labels, keep, merged), True


def _nearest_kept(labels, keep):
    """Per component of ``labels`` (a mosaic) its centre ``(cy, cx)`` over its kept texels (``keep[label]``),
    and per texel of the mosaic the label of its nearest kept texel (itself where it is one)."""
    from scipy import ndimage

    kept = keep[labels]
    yy, xx = np.indices(labels.shape, dtype=np.float64)
    index = np.arange(int(labels.max()) + 1)
    n = np.maximum(ndimage.sum_labels(kept, labels, index=index), 1.0)
    cy = ndimage.sum_labels(np.where(kept, yy, 0.0), labels, index=index) / n
    cx = ndimage.sum_labels(np.where(kept, xx, 0.0), labels, index=index) / n
    _, (iy, ix) = ndimage.distance_transform_edt(~kept, return_indices=True)
    return cy, cx, labels[iy, ix]


def _centres(labels, keep, merged, h, w):
    """The cell map of the kept components of ``labels`` (an ``h x w`` tile with ``FREE_MARGIN`` texels of its
    wrap around it): per texel of the tile the vector to the centre of its nearest kept component, rounded
    to half texels, or ``NO_CELL`` where that component is ``merged``."""
    cy, cx, owner = _nearest_kept(labels, keep)
    my, mx = min(FREE_MARGIN, h), min(FREE_MARGIN, w)
    owner = owner[my:my + h, mx:mx + w]
    py, px = np.indices((h, w), dtype=np.float64)
    d = np.round(2.0 * np.stack([cx[owner] - (px + mx), cy[owner] - (py + my)], axis=2)) / 2.0
    d[merged[owner]] = NO_CELL
    return np.ascontiguousarray(d, dtype=np.float32)


def course_map(tile, snap) -> np.ndarray | None:
    """:func:`cell_map` of a tile snapped along one axis only: its courses (rows of floor boards, columns of
    bricks whose joints have no period along the column) and the joints within each, or None.

    The courses: the tile's colours along their principal axis, averaged along the courses and folded
    into the snap's period, split by Otsu's threshold; the thinner class, one run per period, is the grout
    between courses, its centre line a course's edge. A snap of one period across (``(0, 1)``: a wall of
    courses of several heights, each patch offset along the courses only) reads the profile unfolded: each
    run of grout an edge, the courses of their own heights (:func:`_course_lines`). The joints: per course,
    the mean over its interior lines of the same colours, less its grey closing (or opening, for a light
    grout) over ``k`` texels (``k = 2 w + 3``, ``w`` the grout's width, at least 5), at least
    :data:`JOINT_DEPTH` times the grout's own contrast; a run of such texels is a joint, and a board (a
    *unit*) runs from a joint's start to the next's, on the torus. A map where at least
    :data:`COURSE_MIN_JOINTED` of the courses have a joint
    and there are at least :data:`COURSE_MIN_UNITS` boards.

    Returns
    -------
    ndarray, shape (H, W, 4), float32, or None
        Along the courses (x for ``snap`` ``(0, ny)``, y for ``(nx, 0)``): the texels from the texel to the
        start of its unit (``<= 0``) and to the next unit's start (``>= 1``), ``-NO_JOINT`` and ``NO_JOINT``
        in a course without a joint; across them, the vector to its course's centre line (multiples of 1/2,
        as :func:`cell_map`'s); and the tile's longest unit in texels (the same in every texel). The sampler
        changes patch along a course at a joint (``shading.stochastic.course_vertex``).
    """
    from .constants import NO_JOINT

    found = course_joints(tile, snap)
    if found is None:
        return None
    courses, across, runs = found
    along_x = int(snap[0]) == 0
    h, w = (tile.shape[0], tile.shape[1]) if along_x else (tile.shape[1], tile.shape[0])
    along = np.empty((h, w, 2))
    along[:, :, 0], along[:, :, 1] = -NO_JOINT, NO_JOINT
    x = np.arange(w)
    jointed, units, longest = 0, 0, 0
    for c, joints in enumerate(runs):
        if not joints:
            continue
        first = np.array([j[0] for j in joints])
        jointed += 1
        units += len(first)
        # per texel its unit's start (the last joint start at or before it) and the next, on the torus
        at = np.searchsorted(first, x, side="right") - 1  # -1: before the first, the last one's (wrapped)
        prev = first[at]
        start = np.where(at >= 0, prev, prev - w)
        following = np.concatenate([first[1:], first[:1] + w])
        end = np.where(at >= 0, following[at], first[0])
        longest = max(longest, int(np.max(np.diff(np.concatenate([first, first[:1] + w])))))
        along[courses == c, :, 0] = start - x
        along[courses == c, :, 1] = end - x
    if jointed < COURSE_MIN_JOINTED * len(runs) or units < COURSE_MIN_UNITS:
        return None
    out = np.empty((h, w, 4), dtype=np.float32)
    out[:, :, :2] = along
    out[:, :, 2] = across[:, None]
    out[:, :, 3] = longest
    return np.ascontiguousarray(out if along_x else out.transpose(1, 0, 2))


def _course_lines(level, n):
    """The courses of :func:`course_joints` (``level``: the tile's colours along their principal axis, courses
    along x; ``n`` courses, or 1: courses of their own heights): ``(course, across, inside, contrast, k)`` or
    None where there is no grout between courses. Per line its course's index, the vector to its centre line
    and whether it is inside the course (not grout); the grout's contrast to the courses, and the closing's
    size that finds the joints.

    With ``n >= 2`` (a period of ``h / n`` lines): the mean profile across the courses folded into a period,
    split by Otsu's threshold; the thinner class, one run per period, is the grout, its centre line a
    course's edge. With ``n == 1`` (a wall of courses of several heights, the tile one period of them): the
    same on the profile unfolded, its runs of grout (at least two, on the torus) the edges of courses of
    their own heights, each at least 4 lines."""
    h = level.shape[0]
    rows = level.mean(axis=1)
    if n >= 2:
        _, phase, bins, period = _phases(h, n)
        profile = np.bincount(phase, weights=rows, minlength=bins) / np.maximum(np.bincount(phase, minlength=bins),
                                                                                1)
    else:
        phase, bins, period, profile = np.arange(h), h, float(h), rows
    high = profile > otsu(profile)[0]
    grout = high if high.sum() <= (~high).sum() else ~high
    starts = np.flatnonzero(grout & ~np.roll(grout, 1))
    if not grout.any() or grout.all() or (n >= 2 and len(starts) != 1) or grout.mean() > 0.4:
        return None
    contrast = float(profile[grout].mean() - profile[~grout].mean())
    y = np.arange(h, dtype=np.float64) + 0.5
    if n >= 2:
        run = int(grout.sum())
        edge = (starts[0] + run / 2.0) * period / bins  # the grout's centre line, texels into the period
        # each line's course (its edge below it) and that course's centre line
        course = np.floor((y - edge) / period)
        across = np.round(2.0 * (edge + (course + 0.5) * period - y)) / 2.0
        course = course.astype(np.int64) % n
        return course, across, ~grout[phase], contrast, max(5, 2 * int(round(run * period / bins)) + 3)
    if len(starts) < 2:
        return None
    # each run's centre line on the torus (a run may wrap over the tile's edge)
    ends = np.flatnonzero(grout & ~np.roll(grout, -1))
    stops = np.array([ends[np.searchsorted(ends, a) % len(ends)] for a in starts])
    widths = (stops - starts) % h + 1
    edges = np.sort((starts + widths / 2.0) % h)
    heights = np.diff(np.concatenate([edges, edges[:1] + h]))
    if heights.min() < 4.0:
        return None
    # each line's course: the last edge at or above it (the last one's, wrapped, above the first)
    course = (np.searchsorted(edges, y, side="right") - 1) % len(edges)
    top = np.where(y >= edges[0], edges[course], edges[course] - h)
    across = np.round(2.0 * (top + heights[course] / 2.0 - y)) / 2.0
    return course, across, ~grout, contrast, max(5, 2 * int(round(float(np.mean(widths)))) + 3)


def course_joints(tile, snap):
    """The courses and joints :func:`course_map` reads (courses along x: a tile snapped along x only is read
    turned), or None where there is no grout between courses: ``(courses, across, runs)``, per line its
    course's index (0 to ``n - 1``) and the vector to the course's centre line, and per course its joints,
    ``[(start, width), ...]`` in texels along it (sorted starts; empty for a course without one)."""
    from scipy import ndimage

    along_x = int(snap[0]) == 0
    n = int(snap[1] if along_x else snap[0])
    rgb = np.asarray(tile)[:, :, :3].astype(np.float64)
    if not along_x:
        rgb = rgb.transpose(1, 0, 2)  # courses along x from here on
    h, w = rgb.shape[:2]
    if n < 1 or h < 4 * n:
        return None
    axis = principal_axis(rgb)
    level = rgb @ axis
    found = _course_lines(level, n)
    if found is None:
        return None
    course, across, inside, contrast, k = found
    runs = []
    for c in range(int(course.max()) + 1):
        lines = (course == c) & inside
        joints = []
        if lines.any():
            mean = level[lines].mean(axis=0)
            if contrast < 0:  # dark grout: dark joints
                hat = ndimage.grey_closing(mean, size=k, mode="wrap") - mean
            else:
                hat = mean - ndimage.grey_opening(mean, size=k, mode="wrap")
            joint = hat >= JOINT_DEPTH * abs(contrast)
            if joint.any() and not joint.all():
                first = np.flatnonzero(joint & ~np.roll(joint, 1))
                ends = np.flatnonzero(joint & ~np.roll(joint, -1))
                for a in first:
                    b = ends[np.searchsorted(ends, a) % len(ends)]
                    joints.append((int(a), int((b - a) % w + 1)))
        runs.append(joints)
    return course, across, runs
