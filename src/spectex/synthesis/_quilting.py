"""Image quilting (Efros and Freeman 2001)."""

from __future__ import annotations

import math

import numpy as np

from .._limits import check_quilting
from .._validate import check_float, check_image, check_rng

# Batch independent blocks (see quilt); False forces block-by-block work, which
# must give the same quilt (a test compares the two).
_BATCH = True


def _workers() -> int:
    """Threads for the FFTs: the CPUs this process may use."""
    import os

    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def _layout(n: int, block: int, overlap: int, tileable: bool, name: str) -> tuple[np.ndarray, int]:
    """Block start positions along one axis and the canvas length.

    Plain quilts put blocks every ``block - overlap`` pixels on a canvas a
    little larger than ``n`` (cropped at the end). Tileable quilts live on a
    torus of exactly ``n`` pixels: ``k = ceil(n / step)`` blocks (at least 2)
    start at ``floor(i n / k)``, so the real overlaps are ``>= overlap`` and
    the last block overlaps the first across the wrap edge.
    """
    step = block - overlap
    if not tileable:
        k = max(1, math.ceil((n - overlap) / step))
        return np.arange(k, dtype=np.int64) * step, k * step + overlap
    def torus(length):
        k = max(2, math.ceil(length / step))
        starts = (np.arange(k, dtype=np.int64) * length) // k
        min_step = int(np.min(np.diff(np.append(starts, length))))
        # every block must fit, and its two overlaps must not cross
        return starts, block <= length and 2 * (block - min_step) <= block

    starts, ok = torus(n)
    if not ok:
        least = next((m for m in range(n + 1, 4 * block + 1) if torus(m)[1]), 4 * block)
        raise ValueError(f"{name}={n} is too small for a tileable quilt with block={block} and "
                         f"overlap={overlap}: it needs at least {least} pixels")
    return starts, n


def _continuation_box(src_a, pos_a, pos_b, length_y, length_x, radius, shape_y, shape_x):
    """The box of candidates that continue block a verbatim at block b.

    The source that puts block b exactly where block a's source continues is
    ``src_a + (pos_b - pos_a)`` (the displacement taken the short way round
    on a torus); the box is that position +- ``radius``, clipped to the
    candidate grid, as ``(y0, y1, x0, x1)``, or None if empty.
    """
    dy = (pos_b[0] - pos_a[0]) % length_y
    dx = (pos_b[1] - pos_a[1]) % length_x
    if dy > length_y // 2:
        dy -= length_y
    if dx > length_x // 2:
        dx -= length_x
    cy, cx = src_a[0] + dy, src_a[1] + dx
    y0, y1 = max(cy - radius, 0), min(cy + radius + 1, shape_y)
    x0, x1 = max(cx - radius, 0), min(cx + radius + 1, shape_x)
    if y0 < y1 and x0 < x1:
        return (y0, y1, x0, x1)
    return None


def _overlap_errors(f_ex, mask_terms, masked, fft_shape, valid, workers=1):
    """Sum of squared differences over the overlap, for every exemplar position.

    ``SSD(p) = sum_u M(u) |E(p + u) - T(u)|^2``, expanded as
    ``corr(sum_c E_c^2, M) - 2 sum_c corr(E_c, M T_c) + sum M T^2`` with all
    correlations done at once in the Fourier domain (channels summed there,
    so one inverse transform per block), for a batch of blocks.

    Parameters
    ----------
    f_ex : complex ndarray, shape (C, fh, fw // 2 + 1)
        ``rfft2`` of the exemplar's channels, zero-padded to ``(fh, fw)``.
    mask_terms : complex ndarray, shape (n, fh, fw // 2 + 1)
        ``rfft2(sum_c E_c^2) * conj(rfft2(M))`` for each block's mask.
    masked : ndarray, shape (n, b, b, C)
        The templates with zeros outside their masks, ``M T``.
    fft_shape : (int, int)
        ``(fh, fw)``.
    valid : (int, int)
        Number of candidate positions ``(h - b + 1, w - b + 1)``.
    workers : int
        Threads for the transforms (scipy.fft).

    Returns
    -------
    float32 ndarray, shape ``(n,) + valid``
        The errors, clipped at 0 (rounding can make a perfect match slightly
        negative).
    """
    import scipy.fft as sfft

    fh, fw = fft_shape
    patch = np.moveaxis(masked, 3, 1)  # (n, C, b, b)
    # rfft2 done by hand, pruned: the row transforms only of the b non-zero
    # rows, then the column transforms with zero padding to fh
    f_t = sfft.fft(sfft.rfft(patch, n=fw, axis=-1, workers=workers), n=fh, axis=-2, workers=workers)
    np.conjugate(f_t, out=f_t)
    f_t *= f_ex
    spec = mask_terms - 2.0 * f_t.sum(axis=1)
    # inverse: all columns, then only the rows of valid positions
    cols = sfft.ifft(spec, axis=-2, workers=workers)[:, :valid[0]]
    err = sfft.irfft(cols, n=fw, axis=-1, workers=workers)[:, :, :valid[1]]
    err += np.sum(masked.astype(np.float64) ** 2, axis=(1, 2, 3)).astype(np.float32)[:, None, None]
    np.maximum(err, 0, out=err)
    return err


def quilt(exemplar, shape, *, block: int = 32, overlap: int | None = None, tolerance: float = 0.1,
          rng=0, tileable: bool = False, reuse: float = 0.0, progress=None) -> np.ndarray:
    """Synthesise a texture by image quilting (Efros and Freeman 2001).

    Square blocks of the exemplar are laid in raster order, each overlapping
    its left and upper neighbours by ``overlap`` pixels. For every block, the
    sum of squared differences over the overlap is computed for *all*
    ``(h - block + 1) x (w - block + 1)`` exemplar positions at once by FFT
    correlation (``sum M E^2 - 2 sum (M T) E + sum M T^2`` for the overlap
    mask ``M``, template ``T`` and exemplar ``E``); one position is drawn at
    random among those within ``(1 + tolerance)`` of the best error. The
    block is then pasted along the minimum-error boundary cut, found by
    dynamic programming on each overlap (vertical and horizontal), the two
    cuts combined in the corner as in the paper.

    The best error is taken over candidates that are *not* the verbatim
    continuation (within ``overlap // 2`` pixels) of an already placed
    neighbour. A continuation matches its neighbour exactly (error 0), so
    with the plain rule it would be the only candidate every time and the
    quilt would degenerate into copies of the exemplar; here it stays one
    candidate among the others within tolerance.

    With ``reuse > 0`` no source block dominates: every placed block marks
    the candidate positions within ``block // 2`` of its source (in both
    directions) as used once more, and a candidate's error is raised by
    ``reuse * s * uses`` before the choice, ``s`` the 1st percentile of the
    block's candidate errors (the scale of a good match). ``reuse = 1``
    doubles the error of a good candidate used once, so it drops out of the
    tolerance while fresh ones are left.

    Speed: the exemplar's spectra are computed once, the mask terms once per
    mask shape, channels are summed in the Fourier domain and the template
    transform is pruned to its non-zero rows. A block depends only on its
    left, upper and upper-right neighbours, so the blocks with the same
    ``2 i + j`` (row i, column j) are independent: their transforms run as
    one batch, threaded over the CPUs. Each block's random draw is made in
    advance, so the quilt is exactly the one block-by-block work gives.

    Parameters
    ----------
    exemplar : ndarray, shape (h, w) or (h, w, C)
        The example texture, float in [0, 1] (integers are scaled by their
        dtype's maximum). All channels, alpha included, are matched and
        copied alike. Must be at least ``block`` pixels in each direction.
    shape : int or (int, int)
        Output ``(height, width)``.
    block : int
        Block size in pixels, >= 2.
    overlap : int, optional
        Overlap between neighbouring blocks, ``1 <= overlap < block``;
        default ``max(1, block // 6)`` (the paper's choice). Tileable quilts
        need ``overlap < block / 2``.
    tolerance : float
        Relative error tolerance of the block choice (the paper uses 0.1).
    rng : int, numpy.random.Generator or None
        Randomness (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, the same int the same result; a
        Generator is used (and advanced); None draws fresh randomness.
    tileable : bool
        Quilt on a torus: the last column and row of blocks also overlap the
        first ones across the wrap edge (with their own boundary cuts), so
        the output tiles seamlessly. The block layout then spreads ``k``
        blocks evenly over the output (overlaps slightly larger than asked).
    reuse : float
        Penalty on reusing a source block (see above), >= 0; 0 (default)
        is the paper's plain choice, 1 what :func:`spectex.fit` uses. A
        trade: on 256-pixel crops of six photos (block 32) the most-used
        source cell supplied 2-4 % of the blocks with 0 and 1 % with 1, and
        the quilt was closer to the photo by the structural distance on five
        of them, but its seams were stronger on all six
        (:func:`spectex.metrics.seam_energy` 0.95-1.24 with 0, 1.01-1.70
        with 1: fresh blocks match their neighbours less well).
    progress : callable, optional
        Called as ``progress(done, total)`` with counts of blocks.

    Returns
    -------
    ndarray of float32, shape ``shape`` or ``shape + (C,)``
        The quilt, with the exemplar's channels. Non-tileable quilts start a
        block every ``block - overlap`` pixels from the top-left corner, the
        layout :func:`spectex.metrics.seam_energy` expects.

    Raises
    ------
    ValueError
        If the exemplar is smaller than ``block``, ``overlap`` is not in
        ``[1, block)``, or a tileable output is too small for the blocks.

    References
    ----------
    .. [1] A. A. Efros and W. T. Freeman, "Image quilting for texture
       synthesis and transfer", SIGGRAPH 2001, pp. 341-346.
    """
    from ._cut import place_block

    ex = check_image("exemplar", exemplar, unit=True)
    tolerance = check_float("tolerance", tolerance, minimum=0.0)
    rng = check_rng(rng)
    tileable = bool(tileable)
    reuse = check_float("reuse", reuse, minimum=0.0, maximum=1e6)
    eh, ew = ex.shape[:2]
    out_h, out_w, block, overlap = check_quilting(ex.shape, shape, block=block, overlap=overlap, tileable=tileable,
                                                  channels=1 if ex.ndim == 2 else ex.shape[2])
    grey = ex.ndim == 2
    e3 = np.ascontiguousarray(ex[:, :, None] if grey else ex)
    ys, canvas_h = _layout(out_h, block, overlap, tileable, "height")
    xs, canvas_w = _layout(out_w, block, overlap, tileable, "width")
    spectra = _ExemplarSpectra(e3, block)
    ph, pw = spectra.positions
    canvas = np.zeros((canvas_h, canvas_w, e3.shape[2]), dtype=np.float32)
    filled = np.zeros((canvas_h, canvas_w), dtype=bool)
    sources = {}
    ny, nx = len(ys), len(xs)
    total = ny * nx
    first = (int(rng.integers(ph)), int(rng.integers(pw)))
    uniform = rng.random((ny, nx))  # one draw per block, whatever the order of work
    workers = _workers()
    uses = np.zeros((ph, pw), dtype=np.float32) if reuse > 0 else None
    half = block // 2
    done = 0
    for wave in _waves(ny, nx, tileable, overlap, block):
        items = [_block_view(i, j, ys, xs, canvas, filled, block) for (i, j) in wave]
        errors = spectra.overlap_errors([it for it in items if it[7].any()], workers)
        for (i, j, y0, x0, ix, view, fview, known) in items:
            err = errors.get((i, j))
            if err is None:
                sy, sx = first
                view[...] = e3[sy:sy + block, sx:sx + block]
            else:
                boxes = _neighbour_boxes(i, j, y0, x0, ys, xs, sources, tileable, (canvas_h, canvas_w),
                                         max(1, overlap // 2), (ph, pw))
                if uses is not None and uses.any():
                    scale = float(np.percentile(err, 1.0))
                    err = err + np.float32(reuse * max(scale, 1e-12)) * uses
                sy, sx = place_block(err, boxes, tolerance, float(uniform[i, j]), view, known, e3)
            if uses is not None:
                uses[max(sy - half, 0):sy + half + 1, max(sx - half, 0):sx + half + 1] += 1.0
            sources[(i, j)] = (int(sy), int(sx))
            fview[...] = True
            if ix is not None:
                canvas[ix] = view
                filled[ix] = fview
            done += 1
            if progress is not None:
                progress(done, total)
    out = canvas[:out_h, :out_w]
    return np.ascontiguousarray(out[:, :, 0] if grey else out)


class _ExemplarSpectra:
    """The exemplar's transforms, made once per quilt, and the overlap errors of blocks against it.

    The FFT size is padded to a fast length; the mask terms (``sum M E^2``
    for each overlap mask ``M``) are kept per mask shape.
    """

    def __init__(self, e3, block):
        import scipy.fft as sfft

        eh, ew = e3.shape[:2]
        self.block = block
        self.size = (sfft.next_fast_len(eh, real=True), sfft.next_fast_len(ew, real=True))
        e_chw = np.ascontiguousarray(np.moveaxis(e3, 2, 0), dtype=np.float32)
        self.f_ex = sfft.rfft2(e_chw, s=self.size, axes=(1, 2))
        self.f_sq = sfft.rfft2(np.sum(e_chw.astype(np.float64) ** 2, axis=0).astype(np.float32), s=self.size)
        self.positions = (eh - block + 1, ew - block + 1)  # candidate positions
        self.mask_terms: dict[bytes, np.ndarray] = {}
        self.mask_pad = np.zeros(self.size, dtype=np.float32)

    def overlap_errors(self, need, workers):
        """``{(i, j): errors}`` for the blocks ``need`` (items of :func:`_block_view` with a known part)."""
        import scipy.fft as sfft

        if not need:
            return {}
        terms = []
        for it in need:
            key = it[7].tobytes()
            term = self.mask_terms.get(key)
            if term is None:
                self.mask_pad[:self.block, :self.block] = it[7]
                term = self.f_sq * np.conj(sfft.rfft2(self.mask_pad))
                self.mask_terms[key] = term
            terms.append(term)
        masked = np.stack([it[5] * it[7][:, :, None] for it in need])
        errs = _overlap_errors(self.f_ex, np.stack(terms), masked, self.size, self.positions,
                               workers if len(need) > 1 else 1)
        return {(it[0], it[1]): e for it, e in zip(need, errs)}


def _waves(ny, nx, tileable, overlap, block):
    """The blocks in groups that can be matched together, in order.

    Block (i, j) depends on its left, upper and upper-right neighbours (the
    last overlaps its top-right corner), so the blocks with the same
    ``2 i + j`` are independent when overlap < block / 2: their errors are
    computed in one batch of transforms. Tileable quilts (whose last blocks
    depend on the first ones) and wide overlaps go block by block. Without
    batching, the same order one block at a time (the reuse penalty depends
    on the order).
    """
    if not tileable and 2 * overlap < block:
        waves = [[(i, t - 2 * i) for i in range(ny) if 0 <= t - 2 * i < nx] for t in range(2 * (ny - 1) + nx)]
        if not _BATCH:
            waves = [[item] for wave in waves for item in wave]
        return waves
    return [[(i, j)] for i in range(ny) for j in range(nx)]


def _block_view(i, j, ys, xs, canvas, filled, block):
    """Block (i, j)'s place: ``(i, j, y0, x0, ix, view, filled view, known)``.

    ``ix`` is the wrapped index (a tileable quilt's block across the wrap
    edge; ``view`` is then a copy to write back) or None (``view`` is a view
    of the canvas); ``known`` a copy of the filled mask before the block.
    """
    canvas_h, canvas_w = filled.shape
    y0, x0 = int(ys[i]), int(xs[j])
    if y0 + block > canvas_h or x0 + block > canvas_w:  # tileable: across the wrap edge
        offsets = np.arange(block)
        ix = np.ix_((y0 + offsets) % canvas_h, (x0 + offsets) % canvas_w)
        view, fview = canvas[ix], filled[ix]
    else:
        ix = None
        view = canvas[y0:y0 + block, x0:x0 + block]
        fview = filled[y0:y0 + block, x0:x0 + block]
    return (i, j, y0, x0, ix, view, fview, fview.copy())


def _neighbour_boxes(i, j, y0, x0, ys, xs, sources, tileable, canvas_shape, radius, positions):
    """Boxes of candidates that continue a placed neighbour verbatim, ``(n, 4)`` int64.

    They are left out of the best error and kept as candidates (see :func:`quilt`).
    """
    ny, nx = len(ys), len(xs)
    neighbours = [(i, j - 1), (i - 1, j)]
    if tileable:
        neighbours += [(i, (j + 1) % nx), ((i + 1) % ny, j)]
    boxes = []
    for (ni, nj) in neighbours:
        if (ni, nj) in sources and (ni, nj) != (i, j):
            box = _continuation_box(sources[(ni, nj)], (ys[ni], xs[nj]), (y0, x0), canvas_shape[0],
                                    canvas_shape[1], radius, positions[0], positions[1])
            if box is not None:
                boxes.append(box)
    return np.array(boxes, dtype=np.int64).reshape(-1, 4)
