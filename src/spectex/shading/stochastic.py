"""Histogram-preserving tiling and blending: a tile that never repeats.

Heitz and Neyret's by-example noise [1]_: the plane is covered by a grid of
equilateral triangles; every grid vertex gets a random offset into the
tile, and a point inside a triangle is the blend of the three patches its
vertices point to, weighted by its barycentric coordinates. A plain linear
blend would wash out the contrast and change the histogram where patches
overlap; here the blend is made on a *Gaussianised* tile, where a
variance-preserving blend keeps the distribution, and a look-up table maps
the result back to the tile's own values:

1. **Decorrelate** the colour: the principal axes of the tile's RGB values
   (a 3 x 3 orthogonal ``basis`` and the mean ``origin``), so that the
   three channels can be Gaussianised one by one (Deliot and Heitz [2]_
   replace the paper's optimal transport by exactly this).
2. **Gaussianise** each decorrelated channel and the alpha: a texel of rank
   ``r`` among ``N`` (ties share their mean rank) becomes ``0.5 +
   GAUSS_SCALE * Phi^-1((r + 0.5) / N)``: a normal distribution of mean 0.5
   and standard deviation ``GAUSS_SCALE`` (0.1: five standard deviations
   fit in [0, 1]), stored as half floats (an ``RGBA16F`` texture on the
   GPU; the CPU holds the same values).
3. **Blend** the three patches ``G_i`` with the barycentric weights ``w_i``:
   ``G = 0.5 + sum w_i (G_i - 0.5) / sqrt(sum w_i^2)``. For independent
   Gaussian patches this has the tile's own mean and variance everywhere,
   inside triangles as on their vertices.
4. **Invert**: a look-up table per channel takes ``G`` back to the
   decorrelated colour (and alpha); ``origin + basis @ v`` is the RGB.

**Mip-mapping** ([1]_, section 5; [2]_). The Gaussian tile is mip-mapped
like any tile, and the three patches are sampled at the level of detail of
the *un-offset* coordinates (their derivatives are the same; a seam-free
lambda). A level-``d`` texel of the Gaussian tile is the mean of many
Gaussian texels, not a Gaussian texel, and the colour it stands for is the
mean of their colours, not the look-up of their mean. So the table is made
per level: row ``d`` is the least-squares *monotone* regression of the
level-``d`` colour texels (the mip chain of the decorrelated tile) on the
level-``d`` Gaussian texels (isotonic regression, pool-adjacent-violators),
sampled at ``LUT_SIZE`` points of [0, 1]. Row 0 is the exact inverse of the
Gaussianisation; the last row maps everything to the tile's mean. A lookup
at a fractional level interpolates the two rows the Gaussian samples came
from, with the same ``beta`` (section 4 of ``docs/sampling.md``).

Everything here is a deterministic function of the tile: a texture file
stores the tile and the layer's ``patch``, and the tables are rebuilt.

References
----------
.. [1] E. Heitz and F. Neyret, "High-performance by-example noise using a
   histogram-preserving blending operator", Proc. ACM Comput. Graph.
   Interact. Tech. 1(2), article 31, 2018.
.. [2] T. Deliot and E. Heitz, "Procedural stochastic textures by tiling
   and blending", GPU Zen 2, 2019.
.. [3] B. Burley, "On histogram-preserving blending for randomized texture
   tiling", JCGT 8(4), 2019.
.. [4] C. Wellons, "Prospecting for hash functions", 2018 (``lowbias32``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from .._parallel import in_parts
from .._validate import check_float, check_image, check_seed
from ._jit import jit_inline as _jit_inline
from ._mip_texture import MipTexture, filter_code
from .constants import (
    BAND_SALT,
    CELL_LOD_MARGIN,
    COURSE_ROUND,
    COURSE_SEGMENT,
    COURSE_SLIVER,
    COURSE_TRIES,
    GAUSS_MEAN,
    GAUSS_SCALE,
    HASH_MUL1,
    HASH_MUL2,
    LUT_SIZE,
    LUT_SUBROWS,
    NO_JOINT,
    SHARP_LOD,
    WEIGHT_SQUARINGS,
)
from .sampler import anisotropic_footprint, clamp_lod, sample_at_lod

__all__ = [
    "GAUSS_SCALE",
    "LUT_SIZE",
    "StochasticTables",
    "snap_counts",
    "cell_rows",
    "cell_point",
    "cell_vertex",
    "cell_mix",
    "stochastic_tables",
    "gaussianize",
    "decorrelation",
    "sample_stochastic",
    "triangle_grid_matrix",
    "layer_grid",
    "course_band_shift",
    "lowbias32",
    "layer_key",
    "expand_lut",
    "sample_stochastic_grad",
    "sample_stochastic_at_lod",
]

#: ``sqrt(3)``: the height of an equilateral triangle of side 2.
_SQRT3 = math.sqrt(3.0)


def triangle_grid_matrix(patch: float) -> np.ndarray:
    """The 2 x 2 map from tile coordinates ``(s, t)`` to skewed grid coordinates.

    The triangle grid's vertices are the integer points of the skewed
    coordinates ``k = A (s, t)``; in tile coordinates they are the lattice
    spanned by ``patch (1, 0)`` and ``patch (1/2, sqrt(3)/2)``, equilateral
    triangles of side ``patch`` tiles. ``A = [[1, -1/sqrt(3)], [0,
    2/sqrt(3)]] / patch``.
    """
    patch = check_float("patch", patch, minimum=0.0, exclusive_minimum=True)
    return np.array([[1.0, -1.0 / _SQRT3], [0.0, 2.0 / _SQRT3]], dtype=np.float64) / patch


def layer_grid(patch: float, snap=(0, 0)) -> np.ndarray:
    """The 2 x 2 map from a stochastic layer's tile coordinates to its grid coordinates.

    :func:`triangle_grid_matrix` of ``patch``, except for a layer snapped along one axis with one period
    across (``Layer.snap`` ``(0, 1)`` or ``(1, 0)``: a wall of courses of their own heights), whose rows of
    triangles run along the courses, ``q`` of them in a tile's height exactly, ``q`` the whole number
    nearest ``2 / (sqrt(3) patch)`` (the equilateral grid's rows, at least 1): rows (``(0, 1)``)
    ``[[1 / patch, -q / 2], [0, q]]``, the lattice spanned by ``patch (1, 0)`` and ``(patch / 2, 1 / q)``;
    columns (``(1, 0)``) the same turned, ``[[q, 0], [-q / 2, 1 / patch]]``. So the grid's row (column)
    index, which the renderers hold exactly (``tables.anchor_coords``), counts whole tiles across the
    courses: ``floor(index / q)`` is the tile's band there (:func:`course_band_shift`).
    """
    grid = triangle_grid_matrix(patch)
    nx, ny = (int(v) for v in snap)
    if (nx, ny) not in ((0, 1), (1, 0)):
        return grid
    patch = float(patch)
    q = float(max(1, round(2.0 / (_SQRT3 * patch))))
    if ny == 1:
        return np.array([[1.0 / patch, -q / 2.0], [0.0, q]], dtype=np.float64)
    return np.array([[q, 0.0], [-q / 2.0, 1.0 / patch]], dtype=np.float64)


def lowbias32(x):
    """Wellons' ``lowbias32`` integer hash on uint32 values (NumPy; the kernels' twin)."""
    x = np.asarray(x, dtype=np.uint32).copy()
    with np.errstate(over="ignore"):
        x ^= x >> np.uint32(16)
        x *= np.uint32(HASH_MUL1)
        x ^= x >> np.uint32(15)
        x *= np.uint32(HASH_MUL2)
        x ^= x >> np.uint32(16)
    return x


# --------------------------------------------------------------------------
# The tables (NumPy, once per tile)
# --------------------------------------------------------------------------

def decorrelation(rgb) -> tuple[np.ndarray, np.ndarray]:
    """The principal axes of an image's colours: ``(basis, origin)``.

    ``origin`` is the mean RGB, ``basis`` the eigenvectors of the colour
    covariance as columns (largest variance first), each with its largest
    component positive (so the result does not depend on the eigensolver's
    sign choice). ``v = basis.T @ (c - origin)`` are the decorrelated
    channels and ``c = origin + basis @ v``.

    Parameters
    ----------
    rgb : ndarray, shape (H, W, 3) or (H, W, 4)
        Alpha, if present, is ignored.

    Returns
    -------
    basis : ndarray, shape (3, 3), float64
    origin : ndarray, shape (3,), float64
    """
    rgb = check_image("rgb", rgb, channels=(3, 4))
    c = rgb[:, :, :3].reshape(-1, 3).astype(np.float64)
    origin = c.mean(axis=0)
    cov = np.cov((c - origin).T, bias=True)
    values, vectors = np.linalg.eigh(cov)
    order = np.argsort(values)[::-1]
    basis = vectors[:, order]
    for k in range(3):
        if basis[np.argmax(np.abs(basis[:, k])), k] < 0:
            basis[:, k] = -basis[:, k]
    return basis, origin


def gaussianize(values) -> np.ndarray:
    """Values mapped by rank to a normal distribution of mean 0.5 and std ``GAUSS_SCALE``.

    A value of (mean) rank ``r`` (0-based; tied values share the mean of
    their ranks, so equal values stay equal) among ``N`` becomes ``0.5 +
    GAUSS_SCALE * Phi^-1((r + 0.5) / N)``, clipped to [0, 1].

    Parameters
    ----------
    values : ndarray
        Any shape, finite.

    Returns
    -------
    ndarray of float64, the same shape
    """
    from scipy.special import ndtri
    from scipy.stats import rankdata

    values = np.asarray(values, dtype=np.float64)
    if values.size == 0:
        raise ValueError("values must not be empty")
    if not np.all(np.isfinite(values)):
        raise ValueError("values must be finite, got NaN or infinity")
    ranks = rankdata(values.ravel(), method="average") - 1.0
    g = GAUSS_MEAN + GAUSS_SCALE * ndtri((ranks + 0.5) / values.size)
    return np.clip(g, 0.0, 1.0).reshape(values.shape)


def _pooled(g: np.ndarray):
    """``np.unique(g, return_inverse=True, return_counts=True)``; without a sort where every value of ``g``
    is a non-negative half float (the Gaussian levels: :func:`_half`), whose bit patterns order as their
    values: one count over the 2^15 patterns (a 2048-texel tile's table: 4 M values a channel and level)."""
    h = g.astype(np.float16)
    if g.size < 4096 or not (np.array_equal(h, g) and np.all(h >= 0)):
        return np.unique(g, return_inverse=True, return_counts=True)
    code = (h + np.float16(0.0)).view(np.uint16)  # -0.0 is +0.0
    counts = np.bincount(code, minlength=1 << 15)
    present = np.flatnonzero(counts)
    index = np.zeros(counts.size, dtype=np.intp)
    index[present] = np.arange(present.size)
    return present.astype(np.uint16).view(np.float16).astype(g.dtype), index[code], counts[present]


def _monotone_table(g: np.ndarray, v: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Least-squares non-decreasing regression of ``v`` on ``g``, sampled at ``grid``.

    Pairs with equal ``g`` are pooled first (their mean, weighted by their
    count); the isotonic fit on the pooled points is interpolated linearly
    between them and held constant beyond the first and the last.
    """
    from scipy.optimize import isotonic_regression

    keys, inverse, counts = _pooled(g)
    means = np.bincount(inverse, weights=v, minlength=keys.size) / counts
    if keys.size == 1:
        return np.full(grid.shape, means[0])
    fitted = isotonic_regression(means, weights=counts.astype(np.float64), increasing=True).x
    return np.interp(grid, keys, fitted)


@dataclass(frozen=True)
class StochasticTables:
    """What the stochastic sampling of one tile needs (see :func:`stochastic_tables`).

    Attributes
    ----------
    gaussian : list of ndarray, each (h_d, w_d, 4), float32
        The Gaussianised tile's mip levels: decorrelated channels 0-2 and
        alpha, each with mean 0.5 and std ``GAUSS_SCALE`` at level 0; the
        values are exactly representable as half floats.
    lut : ndarray, shape (levels, LUT_SIZE, 4), float32
        Row ``d``, entry ``i``: the decorrelated colour (0-2) and alpha (3)
        for a level-``d`` Gaussian value ``i / (LUT_SIZE - 1)``; half-float
        values (an ``RGBA16F`` texture, linearly filtered, on the GPU).
    basis : ndarray, shape (3, 3), float64
        RGB = ``origin + basis @ v`` for decorrelated ``v``.
    origin : ndarray, shape (3,), float64
    """

    gaussian: list
    lut: np.ndarray
    basis: np.ndarray
    origin: np.ndarray

    @property
    def levels(self) -> int:
        return len(self.gaussian)

    def expanded(self) -> np.ndarray:
        """The table as the samplers read it: :func:`expand_lut` of :attr:`lut`."""
        return expand_lut(self.lut)

    def texture(self, **kwargs) -> MipTexture:
        """The Gaussian tile as a float :class:`spectex.sampling.MipTexture` (its sampler state from ``kwargs``)."""
        return MipTexture(self.gaussian, bits=None, **kwargs)


def snap_counts(snap, tile_shape) -> tuple[float, float]:
    """What a stochastic layer's patch offsets are snapped to, as counts per tile along s and t.

    ``snap = (nx, ny)`` (``Layer.snap``); an axis with 0 gets the tile's
    level-0 width or height (``tile_shape = (h, w)``): offsets in whole
    texels, as without snapping.
    """
    h, w = int(tile_shape[0]), int(tile_shape[1])
    return float(snap[0] or w), float(snap[1] or h)


def expand_lut(lut: np.ndarray) -> np.ndarray:
    """Per-level tables ``(levels, LUT_SIZE, 4)`` with ``LUT_SUBROWS`` rows per level step, as sampled.

    Row ``r`` is the table at the fractional level ``r / LUT_SUBROWS``:
    ``(1 - f) lut[d] + f lut[d + 1]`` for ``d = r // LUT_SUBROWS``, ``f = (r
    mod LUT_SUBROWS) / LUT_SUBROWS``; ``(levels - 1) LUT_SUBROWS + 1`` rows,
    half floats. The samplers take the nearest row and the nearest entry
    (one texel fetch per channel on the GPU, instead of a bilinear sample
    blending two levels: a third less time per frame on llvmpipe); the
    sub-rows keep the step between neighbouring levels' tables under
    1/16 of their difference, and 1024 entries keep the step along a row
    under 1/2048 of the Gaussian's range.
    """
    lut = np.asarray(lut, dtype=np.float64)
    levels = lut.shape[0]
    rows = (levels - 1) * LUT_SUBROWS + 1
    out = np.empty((rows,) + lut.shape[1:], dtype=np.float64)
    for r in range(rows):
        d, k = divmod(r, LUT_SUBROWS)
        if k == 0:
            out[r] = lut[d]
        else:
            f = k / LUT_SUBROWS
            out[r] = (1.0 - f) * lut[d] + f * lut[d + 1]
    return np.ascontiguousarray(_half(out))


def cell_rows(cells: np.ndarray) -> np.ndarray:
    """A cell map (``shading._cells.cell_map``, ``(h, w, 2)``, or a course map's ``(h, w, 4)``) as rows of the
    expanded table, ``(rows, LUT_SIZE, 4)``.

    Texel ``(x, y)``'s entry is at index ``idx = y w + x``: row ``idx //
    LUT_SIZE``, entry ``idx mod LUT_SIZE``, ``dx, dy`` in channels 0 and 1
    (2 and 3 are 0; a course map's four values in channels 0-3); ``ceil(h w / LUT_SIZE)`` rows, appended after the
    tables (the samplers read them from the layer's ``cell_row``:
    :func:`cell_point`). Its values are multiples of 1/2, exact in half floats.
    """
    cells = np.asarray(cells, dtype=np.float32)
    flat = cells.reshape(-1, cells.shape[2])
    rows = -(-flat.shape[0] // LUT_SIZE)
    out = np.zeros((rows * LUT_SIZE, 4), dtype=np.float32)
    out[:flat.shape[0], :flat.shape[1]] = flat
    out = out.reshape(rows, LUT_SIZE, 4)
    if cells.shape[2] == 4:
        out = np.concatenate([out, course_starts_row(cells)])
    return _half(out)


def course_starts_row(course_map: np.ndarray) -> np.ndarray:
    """The course-start table of a course map (``shading._cells.course_map``): one row ``(1, LUT_SIZE, 4)``
    whose entry ``e`` holds in channel 0 the first line (texels across the courses) of course ``floor(e n /
    LUT_SIZE)`` of the tile's ``n``, in order (:func:`course_band_shift` picks an entry). A course's lines are
    those whose course centre (the map's channel 2 across, plus the line's centre) is the same, modulo the
    tile; the courses run along x where that channel is the same along every row."""
    course_map = np.asarray(course_map, dtype=np.float64)
    along_x = bool(np.all(course_map[:, :, 2] == course_map[:, :1, 2]))
    across = course_map[:, 0, 2] if along_x else course_map[0, :, 2]
    size = across.shape[0]
    centre = (np.arange(size) + 0.5 + across) % size
    starts = np.flatnonzero(centre != np.roll(centre, 1))
    if starts.size == 0:
        starts = np.zeros(1, dtype=np.int64)
    out = np.zeros((1, LUT_SIZE, 4), dtype=np.float32)
    out[0, :, 0] = starts[(np.arange(LUT_SIZE) * starts.size) // LUT_SIZE]
    return out


def _half(values: np.ndarray) -> np.ndarray:
    """Round to the nearest half float, back as float32 (what an RGBA16F texture holds)."""
    return np.asarray(values, dtype=np.float32).astype(np.float16).astype(np.float32)


def stochastic_tables(tile, *, per_level: bool = False) -> StochasticTables:
    """Build the Gaussian tile, its mip chain and the per-level inverse tables of a tile.

    Parameters
    ----------
    tile : ndarray, shape (H, W, 4) or (H, W, 3)
        A tile in [0, 1] (RGB gets alpha 1): the texels the periodic
        sampling would show (already quantised, for an 8-bit texture).
    per_level : bool
        False (the paper's prefiltering): level ``d`` of the Gaussian tile is
        the mip chain of its level 0, and the table of level ``d`` the
        monotone regression of the colour's level ``d`` on it. True (a tile
        with a cell map, ``shading.resources``): level ``d`` >= 1 is the
        colour's level ``d`` Gaussianised by its own ranks, and its table
        that Gaussianisation's exact inverse; level 0 is the same either way.

    Returns
    -------
    StochasticTables

    Notes
    -----
    Per level ``d`` of ``spectex.tiles.mip_chain``: the Gaussian tile's
    level ``d`` (rounded to half floats) and, per channel, the monotone
    least-squares regression of the decorrelated colour's level ``d`` on
    it (see the module's text). Deterministic: the same tile gives the same
    tables.

    Why ``per_level`` for tiles of floor tiles or bricks: one monotone
    function per channel cannot take a filtered Gaussian value back to the
    filtered colour where the colours are two populations (light grout, a
    few per cent of the texels, in the Gaussian's tail, and the cells): a
    level-1 texel that mixes grout into a dark cell has the filtered
    Gaussian value of a lighter cell, and the regression maps both to one
    colour, shifting every cell's. On a fitted floor the mapped levels 1-3
    were 30, 27 and 26 dB from the colour's mip levels (a gravel tile:
    42-44 dB), and a mip-mapped view's floor tiles took other colours than
    the supersampled level 0 (``docs/fitting.md``, "GL = CPU and
    aliasing"). Gaussianised per level, every level's table is exact (to
    half floats), and the three patches' blend at level ``d`` still has the
    level's own Gaussian statistics.

    References
    ----------
    Heitz and Neyret 2018, section 5 (prefiltering); Deliot and Heitz 2019
    (decorrelated 1-D histogram transformations, prefiltered table).
    """
    from ..tiles import mip_chain

    tile = check_image("tile", tile, channels=(3, 4))
    if tile.shape[2] == 3:
        tile = np.concatenate([tile, np.ones(tile.shape[:2] + (1,), np.float32)], axis=2)
    basis, origin = decorrelation(tile)
    h, w = tile.shape[:2]
    values = np.empty((h, w, 4), dtype=np.float64)
    values[:, :, :3] = (tile[:, :, :3].astype(np.float64) - origin) @ basis
    values[:, :, 3] = tile[:, :, 3]
    gauss0 = np.empty((h, w, 4), dtype=np.float64)
    for c in range(4):
        gauss0[:, :, c] = gaussianize(values[:, :, c])
    gauss_levels = [_half(level) for level in mip_chain(_half(gauss0))]
    value_levels = mip_chain(values.astype(np.float32))
    if per_level:
        for d in range(1, len(value_levels)):
            level = np.empty(value_levels[d].shape, dtype=np.float64)
            for c in range(4):
                level[:, :, c] = gaussianize(value_levels[d][:, :, c])
            gauss_levels[d] = _half(level)
    grid = np.linspace(0.0, 1.0, LUT_SIZE)
    lut = np.empty((len(gauss_levels), LUT_SIZE, 4), dtype=np.float32)
    for d, (gl, vl) in enumerate(zip(gauss_levels, value_levels)):
        for c in range(4):
            lut[d, :, c] = _monotone_table(gl[:, :, c].ravel().astype(np.float64),
                                           vl[:, :, c].ravel().astype(np.float64), grid)
    return StochasticTables(gaussian=gauss_levels, lut=np.ascontiguousarray(_half(lut)), basis=basis, origin=origin)


def unused_tables(tile) -> StochasticTables:
    """:class:`StochasticTables` for a tile no stochastic layer draws: zeros in the shapes of
    :func:`stochastic_tables`' (its Gaussian levels, its table's rows), the identity colour basis; so
    that the stores every renderer and export lays out per tile keep their layout, at no cost."""
    from ..tiles.mipmap import gl_level_shapes

    h, w = np.shape(tile)[:2]
    gaussian = [np.zeros(shape + (4,), dtype=np.float32) for shape in gl_level_shapes(h, w)]
    return StochasticTables(gaussian=gaussian, lut=np.zeros((len(gaussian), LUT_SIZE, 4), dtype=np.float32),
                            basis=np.eye(3), origin=np.zeros(3))


# --------------------------------------------------------------------------
# The per-pixel part (numba), in the shape of sampling.sample_grad
# --------------------------------------------------------------------------

_M32 = 0xFFFFFFFF


@_jit_inline
def _mul32(a, c):
    """``(a * c) mod 2^32`` for ``a``, ``c`` in [0, 2^32), in int64 without overflow."""
    lo = a * (c & 0xFFFF)
    hi = ((a * (c >> 16)) & 0xFFFF) << 16
    return (lo + hi) & _M32


@_jit_inline
def hash32(x):
    """``lowbias32`` on an int64 holding a uint32."""
    x ^= x >> 16
    x = _mul32(x, HASH_MUL1)
    x ^= x >> 15
    x = _mul32(x, HASH_MUL2)
    x ^= x >> 16
    return x


@_jit_inline
def vertex_offset(i, j, key, w0, h0, nx, ny):
    """The random offset (tile units) of grid vertex ``(i, j)`` under a layer's ``key``.

    ``h = lowbias32(i ^ lowbias32(j ^ key))`` on the vertex's coordinates
    as uint32 (two's complement, so the grid's vertices repeat only after
    2^32 of them); its halves ``(h & 0xFFFF, h >> 16) / 65536`` in [0, 1)^2
    pick one of ``nx`` x ``ny`` snap positions, ``k = floor(u nx)`` (in
    integers: ``(u16 nx) >> 16``), which lies ``floor(k w0 / nx)`` texels
    of the ``w0 x h0`` level 0 into the tile (integer division), so that a
    patch's texels fall where the un-offset tile's would: a bake on the
    texel grid samples texel centres, unblurred. ``nx, ny`` are the
    layer's snap counts (:func:`snap_counts`): ``Layer.snap``'s whole
    structure periods, or ``w0, h0`` (every texel) without snapping. All in
    integers, so every renderer computes the same offsets exactly.
    """
    h = hash32((i & _M32) ^ hash32((j & _M32) ^ key))
    ix = np.int64(nx)
    iy = np.int64(ny)
    kx = ((h & 0xFFFF) * ix) >> 16
    ky = ((h >> 16) * iy) >> 16
    return ((kx * np.int64(w0)) // ix) / w0, ((ky * np.int64(h0)) // iy) / h0


@_jit_inline
def sharpen_weights(w1, w2, w3, lam, plod):
    """The blend's weights from the barycentric ones, at level of detail ``lam``.

    The barycentric weights raised to the power ``2 ** e`` and renormalised
    to sum 1, ``e = clamp(plod - lam, 0, WEIGHT_SQUARINGS)``, where
    ``plod`` is ``log2`` of the patch's side in level-0 texels
    (:func:`patch_lod`): ``2 ** e`` is the patch's width in pixels, up to
    ``2 ** WEIGHT_SQUARINGS``. A transition between two patches then spans
    about half a pixel wherever a patch is under 8 pixels wide, and at most a
    sixteenth of the patch closer: sharp transitions, continuous, 1 at a
    vertex, most of a triangle one patch at full contrast (no cross-faded
    double images), until a patch shrinks to a pixel, where the weights are
    the barycentric ones. A fractional ``e`` takes the linear mix of the
    two renormalised powers about it (no popping). Sharper masks for the
    finer levels, as in Wronski and Pesce's Laplacian-pyramid blending.
    """
    e = min(max(plod - lam, 0.0), float(WEIGHT_SQUARINGS))
    k = math.floor(e)
    s1, s2, s3 = w1, w2, w3
    for i in range(WEIGHT_SQUARINGS):
        if i < k:
            s1 = s1 * s1
            s2 = s2 * s2
            s3 = s3 * s3
    n1 = s1 * s1
    n2 = s2 * s2
    n3 = s3 * s3
    inv = 1.0 / (s1 + s2 + s3)
    s1 *= inv
    s2 *= inv
    s3 *= inv
    inv = 1.0 / (n1 + n2 + n3)
    f = e - k
    return s1 + f * (n1 * inv - s1), s2 + f * (n2 * inv - s2), s3 + f * (n3 * inv - s3)


@_jit_inline
def patch_lod(w0, grid):
    """``log2`` of a stochastic layer's patch (the triangle grid's side) in level-0 texels: ``w0 / grid[0, 0]``
    (``grid[0, 0]`` is ``1 / patch``, :func:`triangle_grid_matrix`; ``w0`` the tile's width in texels)."""
    return math.log2(w0 / grid[0, 0])


@_jit_inline
def keep_between(v, x1, x2, x3):
    """The blended Gaussian value ``v`` kept between the smallest and largest of its three sources.

    The variance-preserving blend divides by ``sqrt(w1^2 + w2^2 + w3^2)``
    (< 1 between vertices): where the three patches deviate from the mean
    the same way (two tiles of different colours, both above the mean in
    a channel) it pushes the value past all three, into the Gaussian's
    tail, which the table maps to the tile's rarest colour (grout-coloured
    specks inside the tiles of a fitted floor). Kept inside the sources'
    range per channel, the blend makes no value that none of the three
    patches has there; with mixed signs (independent patches) it is
    unchanged, and at a vertex it is the vertex's value.
    """
    lo = min(x1, min(x2, x3))
    hi = max(x1, max(x2, x3))
    return min(max(v, lo), hi)


@_jit_inline
def triangle_vertices(kx, ky):
    """The triangle of the skewed grid holding ``(kx, ky)``: its three vertices and barycentric weights.

    Returns ``i1, j1, w1, i2, j2, w2, i3, j3, w3`` (vertices relative to
    the skewed grid's origin; the weights barycentric, :func:`sharpen_weights`
    makes the blend's). The lower triangle of a cell (``fx + fy <
    1``) has vertices (0, 0), (1, 0), (0, 1); the upper (1, 1), (0, 1),
    (1, 0).
    """
    fi = math.floor(kx)
    fj = math.floor(ky)
    fx = kx - fi
    fy = ky - fj
    i0 = np.int64(fi)
    j0 = np.int64(fj)
    if fx + fy < 1.0:
        return i0, j0, 1.0 - fx - fy, i0 + 1, j0, fx, i0, j0 + 1, fy
    return i0 + 1, j0 + 1, fx + fy - 1.0, i0, j0 + 1, 1.0 - fx, i0 + 1, j0, 1.0 - fy


@_jit_inline
def lut_level(lam, min_filter, q):
    """The (fractional) level whose table goes with the levels :func:`sampling.sample_at_lod` reads.

    0 in magnification and without mip-maps; the level ``*_MIPMAP_NEAREST``
    picks; ``min(lambda, q)`` for the ``*_MIPMAP_LINEAR`` filters, whose
    samples blend levels ``floor(lambda)`` and ``floor(lambda) + 1``.
    """
    if lam <= 0.0 or min_filter < 2:
        return 0.0
    if min_filter <= 3:
        return min(math.ceil(lam + 0.5) - 1.0, q) if lam > 0.5 else 0.0
    return min(lam, q)


@_jit_inline
def lut_lookup(lut, row0, level, g, c):
    """Channel ``c`` of the expanded table (:func:`expand_lut`) at level ``level`` and Gaussian value ``g``.

    The nearest sub-row, ``row0 + floor(level * LUT_SUBROWS + 1/2)``, and
    the nearest entry, ``floor(clamp(g, 0, 1) (LUT_SIZE - 1) + 1/2)``: what a
    ``NEAREST``-filtered table texture returns.
    """
    n = lut.shape[1]
    i = np.int64(math.floor(min(max(g, 0.0), 1.0) * (n - 1) + 0.5))
    r = row0 + np.int64(math.floor(level * LUT_SUBROWS + 0.5))
    return lut[r, i, c]


@_jit_inline
def cell_entry(lut, cell_row, x, y, w0, h0, c):
    """Channel ``c`` of the cell map's entry of level-0 texel ``(x, y)`` (whole numbers, wrapped onto the tile)."""
    iw = np.int64(w0)
    idx = (np.int64(y) % np.int64(h0)) * iw + np.int64(x) % iw
    n = np.int64(lut.shape[1])
    return lut[np.int64(cell_row) + idx // n, idx % n, c]


@_jit_inline
def cell_point(lut, cell_row, s, t, kx, ky, grid, w0, h0):
    """Where a snapped layer takes its patches' weights: the centre of the structural cell holding ``(s, t)``.

    The texel under ``(s, t)`` (level 0, ``w0 x h0``) reads its cell map
    entry (``shading._cells.cell_map``: ``(dx, dy)``), stored in the
    expanded table ``lut`` from row ``cell_row`` on: texel ``idx = y w0 +
    x`` at row ``cell_row + idx // LUT_SIZE``, entry ``idx mod LUT_SIZE``
    (:func:`cell_rows`). The cell's centre ``((x + 1/2 + dx) / w0, (y +
    1/2 + dy) / h0)`` is the same for every texel of the cell; returned in
    the skewed grid (``grid``: tile -> grid; ``(kx, ky)`` is ``(s, t)``
    there, as the samplers hold it).
    """
    x = math.floor(s * w0)
    y = math.floor(t * h0)
    cs = (x + 0.5 + cell_entry(lut, cell_row, x, y, w0, h0, 0)) / w0 - s
    ct = (y + 0.5 + cell_entry(lut, cell_row, x, y, w0, h0, 1)) / h0 - t
    return kx + (grid[0, 0] * cs + grid[0, 1] * ct), ky + (grid[1, 0] * cs + grid[1, 1] * ct)


@_jit_inline
def winner(w1, w2, w3):
    """1, 2 or 3: the vertex with the largest weight (the first of equals): the nearest vertex."""
    if w1 >= w2 and w1 >= w3:
        return 1
    return 2 if w2 >= w3 else 3


@_jit_inline
def blend_patches(x1, x2, x3, w1, w2, w3, inv):
    """The variance-preserving blend of three Gaussian values (``inv = 1 / |w|``), kept between them."""
    m = GAUSS_MEAN
    return keep_between(m + (w1 * (x1 - m) + w2 * (x2 - m) + w3 * (x3 - m)) * inv, x1, x2, x3)


@_jit_inline
def nearest_vertex(gx, gy):
    """The vertex (relative to the grid's origin) of :func:`winner` in ``(gx, gy)``'s triangle."""
    i1, j1, w1, i2, j2, w2, i3, j3, w3 = triangle_vertices(gx, gy)
    win = winner(w1, w2, w3)
    return (i1 if win == 1 else (i2 if win == 2 else i3)), (j1 if win == 1 else (j2 if win == 2 else j3))


@_jit_inline
def cell_score(gx, gy, ci, cj):
    """How well vertex ``(ci, cj)`` holds a cell centred at grid point ``(gx, gy)``: its barycentric weight
    there (the hat ``1 - max(|dx|, |dy|, |dx + dy|)``, 0 outside its six triangles), plus 1 where it is
    the centre's nearest vertex (the cell lies in its own patch's region)."""
    dx = gx - ci
    dy = gy - cj
    hat = max(1.0 - max(abs(dx), max(abs(dy), abs(dx + dy))), 0.0)
    ni, nj = nearest_vertex(gx, gy)
    return hat + 1.0 if (ni == ci and nj == cj) else hat


@_jit_inline
def course_vertex(lut, cell_row, s, t, kx, ky, grid, w0, h0, bi, bj, key, nx, ny):
    """The grid vertex (relative to ``(bi, bj)``) whose patch a layer snapped along one axis shows at ``(s, t)``,
    and that patch's shift along the course (texels).

    The layer's tile has a course map (``shading._cells.course_map``): its courses (rows of boards, or
    columns of bricks) run along the free axis, and every patch's courses fall where the un-offset tile's
    do. Each course changes patch at a joint, never inside a board: the course's centre line (from the
    map) is cut into *segments* of ``m`` whole grid cells along it (``m`` the fewest whose length is at
    least ``COURSE_SEGMENT`` times the tile's longest board; counted from the grid's absolute vertex
    index, so the same wherever the anchor is), each segment shown by the patch of the grid vertex where
    it starts. Every other segment (the odd ones, by the absolute index) is *aligned*: its patch is
    shifted along the course (by at most a unit) so that one of its unit starts (a joint and the board after
    it) falls on the patch before's first unit start in the segment, and takes over there: neither board is
    cut. The even segments' patches are not shifted (so no chain of shifts runs along a course), and take
    over at a unit start of their own in the segment: of their first ``COURSE_TRIES``, the one that hides
    least of the board the (shifted) patch before shows there (nothing where both have a joint there), a
    cut leaving that board shorter than ``COURSE_SLIVER`` times the course's height (a sliver) only where
    every other hides more than a tile; the patch before shows up to there, its board ended by the new
    patch's joint. A segment that cannot be aligned (no joint of the patch before in it) takes over as an
    even one; a course without a joint, or a segment without a joint of the new patch, is cut at the
    segment's start. Every course decides alone: the courses change patch on the grout between them.
    """
    along_x = ny < h0  # snapped across y: the courses run along x
    xt = math.floor(s * w0)
    yt = math.floor(t * h0)
    across = cell_entry(lut, cell_row, xt, yt, w0, h0, 2)
    longest = cell_entry(lut, cell_row, xt, yt, w0, h0, 3)
    if along_x:
        size = w0
        vc = (yt + 0.5 + across) / h0  # the course's centre line (t)
        ul = kx + grid[0, 1] * (vc - t)  # the point moved onto it, in the grid
        wl = ky + grid[1, 1] * (vc - t)
        step = grid[0, 0]  # grid cells per tile unit along the course
        rho = 0.0  # the other grid coordinate's change per cell along it
        base = bi
        u = s
        height = h0 / ny
        vrow = math.floor(vc * h0)
    else:
        size = h0
        vc = (xt + 0.5 + across) / w0
        ul = ky + grid[1, 0] * (vc - s)
        wl = kx + grid[0, 0] * (vc - s)
        step = grid[1, 1]
        rho = grid[0, 1] / grid[1, 1]
        base = bj
        u = t
        height = w0 / nx
        vrow = math.floor(vc * w0)
    m = np.int64(max(math.ceil(COURSE_SEGMENT * longest * step / size), 1.0))
    fu = np.int64(math.floor(ul))
    i0 = fu - ((base + fu) & _M32) % m  # the segment's first cell (relative), from the absolute index
    u0 = u + (i0 - ul) / step  # the segment's start and end along the course (tile units)
    u1 = u0 + m / step
    j0 = np.int64(math.floor(wl + rho * (i0 - ul) + COURSE_ROUND))
    jp = np.int64(math.floor(wl + rho * (i0 - m - ul) + COURSE_ROUND))
    ci, cj = (i0, j0) if along_x else (j0, i0)
    pi, pj = (i0 - m, jp) if along_x else (jp, i0 - m)
    ox, oy = vertex_offset(bi + ci, bj + cj, key, w0, h0, nx, ny)
    qx, qy = vertex_offset(bi + pi, bj + pj, key, w0, h0, nx, ny)
    # the offsets are whole texels: (along, across) of each patch
    ox = math.floor(ox * w0 + 0.5)
    oy = math.floor(oy * h0 + 0.5)
    qx = math.floor(qx * w0 + 0.5)
    qy = math.floor(qy * h0 + 0.5)
    oa, ob = (ox, oy) if along_x else (oy, ox)
    pa, pb = (qx, qy) if along_x else (qy, qx)
    # the aligned change this segment reads: an odd segment's own (its patch shifted onto the patch before's
    # first unit start in it: neither board cut), or an even one's patch before's (odd: shifted onto the one
    # before it); one call either way
    end = u1 * size
    start = float(math.floor(u0 * size + COURSE_ROUND))
    odd = (((base + i0) & _M32) // m) % 2 == 1
    if odd:
        j, shift = _course_align(lut, cell_row, start, end, pa, pb, oa, ob, vrow, along_x, w0, h0)
    else:
        # (the patch of the segment before the patch before; GLSL reads it either way, one call for both)
        jq = np.int64(math.floor(wl + rho * (i0 - 2 * m - ul) + COURSE_ROUND))
        ri, rj = (i0 - 2 * m, jq) if along_x else (jq, i0 - 2 * m)
        rx, ry = vertex_offset(bi + ri, bj + rj, key, w0, h0, nx, ny)
        rx = math.floor(rx * w0 + 0.5)
        ry = math.floor(ry * h0 + 0.5)
        ra, rb = (rx, ry) if along_x else (ry, rx)
        before = float(math.floor((u0 - m / step) * size + COURSE_ROUND))
        j, shift = _course_align(lut, cell_row, before, start, ra, rb, pa, pb, vrow, along_x, w0, h0)
    if odd and j >= 0.0:
        if u * size >= j:
            return ci, cj, shift
        return pi, pj, 0.0
    prev_shift = shift if (not odd and j >= 0.0) else 0.0
    pa += prev_shift
    # the cut (an even segment, or an odd one not aligned): of the new patch's first COURSE_TRIES unit starts in
    # the segment, the one that hides least of the board the patch before shows there (none where its own
    # joint is there too), slivers avoided
    cut = u0 * size
    best = np.inf
    pos = start
    for _ in range(COURSE_TRIES):
        b = _course_at(lut, cell_row, pos, vrow, oa, ob, along_x, w0, h0, 1)
        if b >= 0.5 * NO_JOINT or pos + b >= end:
            break
        pos += b
        a = _course_at(lut, cell_row, pos - 1.0, vrow, pa, pb, along_x, w0, h0, 0)
        hidden = _course_at(lut, cell_row, pos - 1.0, vrow, pa, pb, along_x, w0, h0, 1) - 1.0
        if hidden > 0.0 and 1.0 - a < COURSE_SLIVER * height:
            hidden += size  # a sliver of a board: only where nothing better
        if hidden < best:
            best = hidden
            cut = pos
    if u * size >= cut:
        return ci, cj, 0.0
    return pi, pj, prev_shift


@_jit_inline
def course_band_shift(lut, cell_row, kx, ky, grid, w0, h0, bi, bj, key, nx, ny):
    """Where a wall of courses of their own heights starts its band's courses: ``(ds, dt)``, tile units.

    A layer snapped along one axis with one period across (``ny == 1``, free along x: courses along x; or
    ``nx == 1``, free along y) whose tile has a course map (``cell_row >= 0``) is cut across its courses
    into bands one tile high, and band ``b`` shows the tile's courses from the start of one of them on
    (its coordinates shifted across the courses by that start, whole texels): the courses' order is the
    tile's, but where it begins changes from band to band, so the course heights, and the stones each
    course holds, do not repeat once a tile across the wall. Every band boundary falls on grout (a
    course's first line, in the tile and in the band). The bands are the grid's rows (columns) of
    triangles, ``q`` to a tile (:func:`layer_grid`), as :func:`course_vertex` reads them at a course's centre
    line (after adding ``COURSE_ROUND``): band ``b`` holds rows ``q b`` to ``q b + q - 1``, so that no
    course of one band takes its patches from a row of the next (the same course at the end of one band
    and the start of the next was drawn twice, the same stones above each other). It begins ``lead =
    round(COURSE_ROUND size / q)`` texels before tile coordinate ``b`` (whole texels); its index is
    ``floor((bj + floor(ky + q lead / size)) mod 2^32 / q)``, from the renderers' exact integers. It picks
    entry ``((h & 0xFFFF) LUT_SIZE) >> 16``, ``h = lowbias32(b ^ lowbias32(key ^ BAND_SALT))``, of the
    course-start table after the map (:func:`cell_rows`): a course's first line ``f``, and the shift is
    ``(f + lead) / size``. ``(0, 0)`` for any other layer.
    """
    rows = ny == 1.0 and nx >= w0
    if cell_row < 0.0 or not (rows or (nx == 1.0 and ny >= h0)):
        return 0.0, 0.0
    if rows:
        size, base, k, q = h0, bj, ky, math.floor(grid[1, 1] + 0.5)
    else:
        size, base, k, q = w0, bi, kx, math.floor(grid[0, 0] + 0.5)
    lead = math.floor(COURSE_ROUND * size / q + 0.5)
    gridline = (base + np.int64(math.floor(k + q * lead / size))) & _M32
    h = hash32((gridline // np.int64(q)) ^ hash32((key & _M32) ^ BAND_SALT))
    n = np.int64(lut.shape[1])
    e = ((h & 0xFFFF) * n) >> 16
    row = np.int64(cell_row) + (np.int64(w0) * np.int64(h0) + n - 1) // n
    shift = (np.float64(lut[row, e, 0]) + lead) / size
    if rows:
        return 0.0, shift
    return shift, 0.0


@_jit_inline
def _course_at(lut, cell_row, along, vrow, oa, ob, along_x, w0, h0, c):
    """Channel ``c`` of the course map at texel ``along`` of the course in texel row ``vrow`` (across), as a patch
    offset by ``(oa, ob)`` whole texels (along, across) shows it."""
    if along_x:
        return cell_entry(lut, cell_row, along + oa, vrow + ob, w0, h0, c)
    return cell_entry(lut, cell_row, vrow + ob, along + oa, w0, h0, c)


@_jit_inline
def _course_align(lut, cell_row, start, end, pa, pb, oa, ob, vrow, along_x, w0, h0):
    """An aligned patch change (:func:`course_vertex`): ``(j, shift)``, ``j`` the first unit start at or after texel
    ``start`` (and before ``end``) of the patch before (offsets ``(pa, pb)``), ``shift`` (texels, at most 0) what
    moves the new patch's (``(oa, ob)``) unit start at or before ``j`` onto it; ``(-1, 0)`` where the patch before
    has no unit start there, or either course no joint. Where that start is the patch before's own joint at ``j``
    (the same course of the tile, the same joint: the course would run on unchanged, and come back a tile on),
    the new patch's next unit start after ``j`` instead (``shift`` positive); ``(-1, 0)`` where that is the same
    joint too (a course of one joint)."""
    b = _course_at(lut, cell_row, start - 1.0, vrow, pa, pb, along_x, w0, h0, 1)
    if b >= 0.5 * NO_JOINT:
        return -1.0, 0.0
    j = start - 1.0 + b
    if j >= end:
        return -1.0, 0.0
    a = _course_at(lut, cell_row, j, vrow, oa, ob, along_x, w0, h0, 0)
    if a <= -0.5 * NO_JOINT:
        return -1.0, 0.0
    size, across = (w0, h0) if along_x else (h0, w0)
    if (ob - pb) % across == 0.0 and (oa + a - pa) % size == 0.0:
        a = _course_at(lut, cell_row, j, vrow, oa, ob, along_x, w0, h0, 1)
        if (oa + a - pa) % size == 0.0:
            return -1.0, 0.0
    return j, a


@_jit_inline
def cell_vertex(lut, cell_row, s, t, kx, ky, grid, w0, h0, bi, bj, key, nx, ny):
    """The grid vertex (relative to ``(bi, bj)``) whose patch a layer with a cell map shows whole at ``(s, t)``.

    Snapped along one axis only (a course map: rows of boards, columns of
    bricks), the vertex of :func:`course_vertex`: the course changes patch
    at a joint. Snapped along both (``nx < w0`` and ``ny < h0``; the map is made for a snapped
    tile's lattice, where every patch's cells fall where the un-offset
    tile's do), the vertex nearest the centre of the cell under ``(s, t)``
    (:func:`cell_point`). Free along both axes (cobbles, pebbles in mortar:
    ``shading._cells.free_cell_map``; each patch has its own cells), each
    vertex ``k`` of the point's triangle reads the cell its own patch has
    under the point, centred at ``c_k``, and the one with
    the highest :func:`cell_score` at ``c_k`` wins: a cell whose centre lies
    in its patch's own region beats one that does not, and of two, the
    deeper; so each cell is whole where its patch wins, and a cell that
    loses is cut by the winner's outline (in the grout), not by a straight
    line. Returns ``(ci, cj, whole, ds, dt)``: ``(ds, dt)`` the patch's shift (tile units; a course's
    aligned segment, else 0); ``whole`` False (and ``(ci, cj)``
    of no meaning) where no vertex's
    cell lies in its own region (the gaps between cells that each lie in
    another patch's region; 6 % of a fitted paving's texels, or a texel of
    no cell, ``_cells.NO_CELL``), where the
    sampler blends at the point instead (a hard cut there showed
    fragments of cells).
    """
    if (nx < w0) != (ny < h0):
        ci, cj, shift = course_vertex(lut, cell_row, s, t, kx, ky, grid, w0, h0, bi, bj, key, nx, ny)
        if ny < h0:  # (the courses run along x)
            return ci, cj, True, shift / w0, 0.0
        return ci, cj, True, 0.0, shift / h0
    if nx < w0 or ny < h0:
        gx, gy = cell_point(lut, cell_row, s, t, kx, ky, grid, w0, h0)
        ci, cj = nearest_vertex(gx, gy)
        return ci, cj, True, 0.0, 0.0
    i1, j1, w1, i2, j2, w2, i3, j3, w3 = triangle_vertices(kx, ky)
    ci, cj = i1, j1  # (kept only where a vertex scores: else not whole, and the blend is drawn)
    best = 0.0
    ox, oy = vertex_offset(bi + i1, bj + j1, key, w0, h0, nx, ny)
    gx, gy = cell_point(lut, cell_row, s + ox, t + oy, kx, ky, grid, w0, h0)
    score = cell_score(gx, gy, i1, j1)
    if score > best:
        best, ci, cj = score, i1, j1
    ox, oy = vertex_offset(bi + i2, bj + j2, key, w0, h0, nx, ny)
    gx, gy = cell_point(lut, cell_row, s + ox, t + oy, kx, ky, grid, w0, h0)
    score = cell_score(gx, gy, i2, j2)
    if score > best:
        best, ci, cj = score, i2, j2
    ox, oy = vertex_offset(bi + i3, bj + j3, key, w0, h0, nx, ny)
    gx, gy = cell_point(lut, cell_row, s + ox, t + oy, kx, ky, grid, w0, h0)
    score = cell_score(gx, gy, i3, j3)
    if score > best:
        best, ci, cj = score, i3, j3
    return ci, cj, best >= 1.0, 0.0, 0.0


@_jit_inline
def vertex_patch_at(data, base, offsets, widths, heights, s, t, ci, cj, ds, dt, bi, bj, key, w0, h0, nx, ny, lam,
                    min_filter, mag_filter, wrap_s, wrap_t):
    """The Gaussian RGBA at ``(s, t)`` of the one patch of grid vertex ``(ci, cj)`` (relative to ``(bi, bj)``;
    :func:`cell_vertex`): sampled at ``(s, t)`` plus its offset and the shift ``(ds, dt)`` its cell or course
    gives it, its own value (one fetch). Apart from :func:`patches_at` so that each kernel inlines the
    texel sampler once per fetch it makes."""
    ox, oy = vertex_offset(bi + ci, bj + cj, key, w0, h0, nx, ny)
    return sample_at_lod(data, base, offsets, widths, heights, s + ox + ds, t + oy + dt, lam, min_filter,
                         mag_filter, wrap_s, wrap_t)


@_jit_inline
def patches_at(data, base, offsets, widths, heights, s, t, gx, gy, bi, bj, key, w0, h0, nx, ny, lam, min_filter,
               mag_filter, wrap_s, wrap_t, plod):
    """The blended Gaussian RGBA at ``(s, t)`` of the patches whose weights are taken at grid point ``(gx, gy)``.

    The vertices of ``(gx, gy)``'s triangle (relative to vertex ``(bi, bj)``)
    with their weights sharpened at ``lam`` for patches of ``2 ** plod`` texels (:func:`sharpen_weights`), the
    three patches sampled at ``(s, t)`` plus their offsets and blended
    (:func:`blend_patches`); the one patch of a cell: :func:`vertex_patch_at`.
    """
    i1, j1, w1, i2, j2, w2, i3, j3, w3 = triangle_vertices(gx, gy)
    w1, w2, w3 = sharpen_weights(w1, w2, w3, lam, plod)
    ox, oy = vertex_offset(bi + i1, bj + j1, key, w0, h0, nx, ny)
    r1, g1, b1, a1 = sample_at_lod(data, base, offsets, widths, heights, s + ox, t + oy, lam, min_filter,
                                   mag_filter, wrap_s, wrap_t)
    ox, oy = vertex_offset(bi + i2, bj + j2, key, w0, h0, nx, ny)
    r2, g2, b2, a2 = sample_at_lod(data, base, offsets, widths, heights, s + ox, t + oy, lam, min_filter,
                                   mag_filter, wrap_s, wrap_t)
    ox, oy = vertex_offset(bi + i3, bj + j3, key, w0, h0, nx, ny)
    r3, g3, b3, a3 = sample_at_lod(data, base, offsets, widths, heights, s + ox, t + oy, lam, min_filter,
                                   mag_filter, wrap_s, wrap_t)
    inv = 1.0 / math.sqrt(w1 * w1 + w2 * w2 + w3 * w3)
    return (blend_patches(r1, r2, r3, w1, w2, w3, inv), blend_patches(g1, g2, g3, w1, w2, w3, inv),
            blend_patches(b1, b2, b3, w1, w2, w3, inv), blend_patches(a1, a2, a3, w1, w2, w3, inv))


@_jit_inline
def cell_mix(lam, w0, h0, nx, ny):
    """How far a snapped layer with cells has gone from the cell's one patch (0) to the blend at the point (1)
    at level ``lam``: 0 up to ``l_c = max(SHARP_LOD, log2(p) - CELL_LOD_MARGIN)``, ``p = min(w0 / nx, h0 /
    ny)`` the snap's shorter period in level-0 texels (the cells hold while they span 4 pixels), 1 from
    ``l_c + 1``, linear in between (no popping). The one formula of the reference and the fast path.

    A layer free along both axes (``nx >= w0`` and ``ny >= h0``: free cells) keeps its cells at every
    level (0): there the cells choose *which* patch shows a place, not only where a cell is whole, and
    the blend's choice is another picture, so the switch would change the stones as the view comes
    closer, and a mip-mapped view at mid distance would show the blend's stones where the supersampled
    truth shows the cells' (fitted paving, 100 m: 31.6 / 40.2 dB full-band / low-passed against that truth
    with the switch at ``SHARP_LOD``, 34.3 / 44.7 without it)."""
    if nx >= w0 or ny >= h0:
        return 0.0
    return min(max(lam - max(SHARP_LOD, math.log2(min(w0 / nx, h0 / ny)) - CELL_LOD_MARGIN), 0.0), 1.0)


@_jit_inline
def sample_stochastic_at_lod(data, base, offsets, widths, heights, lut, row0, basis, origin, s, t, kx, ky,
                             bi, bj, key, snap, lam, min_filter, mag_filter, wrap_s, wrap_t, grid):
    """One histogram-preserving sample at a clamped level of detail; returns RGBA in [0, 1].

    ``(s, t)``: the un-offset tile coordinates; ``(kx, ky)``: the same
    point in skewed grid coordinates relative to the grid vertex ``(bi,
    bj)`` (integers; the host splits a far-away position into this vertex
    and a small remainder); ``key``: the layer's hash key; ``snap``: its
    snap counts and cell-map row ``(nx, ny, cell_row)`` (:func:`vertex_offset`;
    one argument: a call of more than 30 cannot be inlined by numba). ``data, base,
    offsets, widths, heights``: the Gaussian tile's levels in a texel store
    (as in :func:`sampling.sample_at_lod`); ``lut[row0:]``: the tile's
    expanded table (:func:`expand_lut`); ``basis``, ``origin``: the
    decorrelation; ``grid``: the tile -> skewed grid map.

    A snapped layer whose tile has a cell map (``cell_row >= 0``;
    ``shading._cells``) takes, up to ``lam = l_c``, the one patch of
    the vertex nearest its cell's centre (:func:`cell_point`; its own value,
    one fetch): a brick or floor tile whole from one patch, the patches
    changing on the grout, where they agree (their offsets are whole
    periods); from ``l_c + 1`` on the blend at the point; in between,
    the linear mix of the two (no popping). ``l_c = max(SHARP_LOD,
    log2(p) - CELL_LOD_MARGIN)``, ``p = min(w0 / nx, h0 / ny)`` the
    snap's shorter period in texels: the cells hold while they are 4
    pixels wide or more.
    """
    nx, ny, cell_row = snap
    w0 = np.float64(widths[0])
    h0 = np.float64(heights[0])
    tm = cell_mix(lam, w0, h0, nx, ny)
    cells = cell_row >= 0.0 and tm < 1.0
    v0 = v1 = v2 = v3 = 0.0
    if cell_row >= 0.0:  # a wall of courses of their own heights: its band's courses (else 0)
        sb, tb = course_band_shift(lut, cell_row, kx, ky, grid, w0, h0, bi, bj, key, nx, ny)
        s += sb
        t += tb
    if cells:
        ci, cj, whole, ds, dt = cell_vertex(lut, cell_row, s, t, kx, ky, grid, w0, h0, bi, bj, key, nx, ny)
        if whole:
            v0, v1, v2, v3 = vertex_patch_at(data, base, offsets, widths, heights, s, t, ci, cj, ds, dt, bi, bj,
                                             key, w0, h0, nx, ny, lam, min_filter, mag_filter, wrap_s, wrap_t)
        else:
            tm = 1.0  # the blend at the point
    if not cells or tm > 0.0:
        u0, u1, u2, u3 = patches_at(data, base, offsets, widths, heights, s, t, kx, ky, bi, bj, key, w0, h0, nx, ny,
                                    lam, min_filter, mag_filter, wrap_s, wrap_t, patch_lod(w0, grid))
        if cells:  # l_c < lambda < l_c + 1: towards the blend at the point
            v0 += tm * (u0 - v0)
            v1 += tm * (u1 - v1)
            v2 += tm * (u2 - v2)
            v3 += tm * (u3 - v3)
        else:
            v0, v1, v2, v3 = u0, u1, u2, u3
    level = lut_level(lam, min_filter, np.float64(widths.shape[0] - 1))
    x0 = lut_lookup(lut, row0, level, v0, 0)
    x1 = lut_lookup(lut, row0, level, v1, 1)
    x2 = lut_lookup(lut, row0, level, v2, 2)
    al = lut_lookup(lut, row0, level, v3, 3)
    r = origin[0] + basis[0, 0] * x0 + basis[0, 1] * x1 + basis[0, 2] * x2
    g = origin[1] + basis[1, 0] * x0 + basis[1, 1] * x1 + basis[1, 2] * x2
    b = origin[2] + basis[2, 0] * x0 + basis[2, 1] * x1 + basis[2, 2] * x2
    return (min(max(r, 0.0), 1.0), min(max(g, 0.0), 1.0), min(max(b, 0.0), 1.0), min(max(al, 0.0), 1.0))


@_jit_inline
def sample_stochastic_grad(data, base, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter,
                           max_aniso, bias, min_lod, max_lod, lut, row0, basis, origin, grid, bi, bj, key,
                           snap, s, t, kx, ky, dsdx, dtdx, dsdy, dtdy):
    """:func:`sampling.sample_grad` for a stochastic layer: lambda from the un-offset derivatives.

    The level of detail (and the anisotropic recipe's ``N`` samples along
    the major axis) come from the derivatives of ``(s, t)``, exactly as for
    a periodic layer; each of the ``N`` samples is a full
    :func:`sample_stochastic_at_lod` at its own point (its grid position
    moved by ``grid`` (2 x 2, tile -> skewed grid coordinates) times the
    step), and the ``N`` RGBA results are averaged
    (:func:`_sample_stochastic_along`).
    """
    lam, n, ds, dt = anisotropic_footprint(widths, heights, min_filter, max_aniso, bias, min_lod, max_lod,
                                           dsdx, dtdx, dsdy, dtdy)
    return _sample_stochastic_along(data, base, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter,
                                    lut, row0, basis, origin, grid, bi, bj, key, snap, s, t, kx, ky, lam, n, ds, dt)


@_jit_inline
def _sample_stochastic_along(data, base, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter, lut,
                             row0, basis, origin, grid, bi, bj, key, snap, s, t, kx, ky, lam, n, ds, dt):
    """The mean of ``n`` :func:`sample_stochastic_at_lod` samples at ``lam``, evenly along ``(ds, dt)``
    (tile coordinates) around ``(s, t)`` (one sample at ``(s, t)`` itself when ``n`` is 1)."""
    dkx = grid[0, 0] * ds + grid[0, 1] * dt
    dky = grid[1, 0] * ds + grid[1, 1] * dt
    r = 0.0
    g = 0.0
    b = 0.0
    a = 0.0
    for i in range(1, n + 1):
        f = i / (n + 1.0) - 0.5 if n > 1 else 0.0
        r1, g1, b1, a1 = sample_stochastic_at_lod(data, base, offsets, widths, heights, lut, row0, basis, origin,
                                                  s + f * ds, t + f * dt, kx + f * dkx, ky + f * dky, bi, bj, key,
                                                  snap, lam, min_filter, mag_filter, wrap_s, wrap_t, grid)
        r += r1
        g += g1
        b += b1
        a += a1
    inv = 1.0 / n
    return r * inv, g * inv, b * inv, a * inv


@numba.njit(cache=True, nogil=True)  # serial: split over threads by the caller (_parallel.in_parts)
def _stochastic_kernel(data, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter, max_aniso, bias,
                       min_lod, max_lod, lut, basis, origin, grid, key, nx, ny, cell_row, mode, s, t, dsdx, dtdx,
                       dsdy, dtdy, lod, out):
    # one inlined sampler for both modes (each inlined copy of the sampler costs seconds of compile): the
    # explicit lod is the anisotropic recipe's one sample (n = 1, no step), the same numbers as calling
    # sample_stochastic_at_lod at the clamped lod directly
    for k in range(s.shape[0]):
        kx = grid[0, 0] * s[k] + grid[0, 1] * t[k]
        ky = grid[1, 0] * s[k] + grid[1, 1] * t[k]
        if mode == 1:
            lam, n, ds, dt = anisotropic_footprint(widths, heights, min_filter, max_aniso, bias, min_lod, max_lod,
                                                   dsdx[k], dtdx[k], dsdy[k], dtdy[k])
        else:
            lam = clamp_lod(lod[k], bias, min_lod, max_lod)
            n = 1
            ds = 0.0
            dt = 0.0
        r, g, b, a = _sample_stochastic_along(data, 0, offsets, widths, heights, wrap_s, wrap_t, min_filter,
                                              mag_filter, lut, 0, basis, origin, grid, 0, 0, key,
                                              (nx, ny, cell_row), s[k], t[k], kx, ky, lam, n, ds, dt)
        out[k, 0] = r
        out[k, 1] = g
        out[k, 2] = b
        out[k, 3] = a


def layer_key(seed) -> int:
    """A layer's hash key from its seed: ``lowbias32(seed mod 2^32)`` (the kernels' ``key``)."""
    seed = check_seed("seed", seed, allow_none=False)
    return int(lowbias32(np.uint32(seed & 0xFFFFFFFF)))


def sample_stochastic(tables, s, t, *, patch=0.5, seed=0, snap=(0, 0), cells=None, filter="trilinear", mipmaps=True,
                      anisotropy=1.0, dsdx=None, dtdx=None, dsdy=None, dtdy=None, lod=None):
    """Sample a tile by histogram-preserving tiling and blending at ``(s, t)``.

    Like :func:`spectex.sampling.sample` with ``REPEAT`` wrapping, for the
    stochastic tiling of the tile behind ``tables``: the triangle grid of
    side ``patch`` (tile units) starts at ``(s, t) = (0, 0)``.

    Parameters
    ----------
    tables : StochasticTables
        From :func:`stochastic_tables`.
    s, t : array_like
        Tile coordinates (broadcast with the derivatives).
    patch : float
        Side of the grid's triangles in tiles (> 0; 0.25 to 1 is useful).
    seed : int
        Which random offsets the vertices get (>= 0).
    snap : (int, int)
        Whole structure periods the tile holds along s and t; the offsets
        are snapped to them (``Layer.snap``; 0: off along that axis).
    cells : ndarray, shape (H, W, 2), optional
        The tile's cell map for this snap (``shading._cells.cell_map``): whole
        structural cells take one patch (:func:`cell_point`). None: off.
    filter : str
        Minification filter (``spectex.sampling.FILTERS`` or "trilinear");
        magnification is ``NEAREST`` under ``NEAREST``, else ``LINEAR``.
    mipmaps : bool
        False: level 0 only (the no-mip control).
    anisotropy : float
        Maximum anisotropy, 1 to 16.
    dsdx, dtdx, dsdy, dtdy : array_like, optional
        Screen-space derivatives of ``(s, t)``; all four or none.
    lod : array_like, optional
        An explicit level of detail instead of derivatives.

    Returns
    -------
    ndarray, shape ``broadcast_shape + (4,)``, float32
        RGBA in [0, 1].
    """
    if not isinstance(tables, StochasticTables):
        raise TypeError(f"tables must be StochasticTables, got {type(tables).__name__}")
    from .._validate import check_snap
    snap = check_snap("snap", snap)
    grid = layer_grid(patch, snap)
    key = layer_key(seed)
    nx, ny = snap_counts(snap, tables.gaussian[0].shape[:2])
    code = filter_code("filter", filter)
    anisotropy = check_float("anisotropy", anisotropy, minimum=1.0, maximum=16.0)
    levels = tables.gaussian if mipmaps else tables.gaussian[:1]
    tex = MipTexture(levels, bits=None)
    derivs = (dsdx, dtdx, dsdy, dtdy)
    given = [d is not None for d in derivs]
    if any(given) and not all(given):
        raise ValueError("give all four derivatives dsdx, dtdx, dsdy, dtdy or none")
    if all(given) and lod is not None:
        raise ValueError("give derivatives or lod, not both")
    arrays = [np.asarray(s, dtype=np.float64), np.asarray(t, dtype=np.float64)]
    mode = 1 if all(given) else 0
    if mode:
        arrays += [np.asarray(d, dtype=np.float64) for d in derivs]
    else:
        arrays.append(np.asarray(0.0 if lod is None else lod, dtype=np.float64))
    for name, a in zip(("s", "t", "dsdx" if mode else "lod"), arrays):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name} must be finite, got NaN or infinity")
    b = np.broadcast_arrays(*arrays)
    shape = b[0].shape
    flat = [np.ascontiguousarray(x.reshape(-1)) for x in b]
    out = np.empty((flat[0].size, 4), dtype=np.float32)
    if mode:
        s_, t_, a_, b_, c_, d_ = flat
        lod_ = np.zeros(1)
    else:
        s_, t_, lod_ = flat
        a_ = b_ = c_ = d_ = np.zeros(1)
    lut = tables.expanded()
    cell_row = -1.0
    if cells is not None:
        cells = np.asarray(cells, dtype=np.float32)
        if cells.shape != tables.gaussian[0].shape[:2] + (2,):
            raise ValueError(f"cells must have shape {tables.gaussian[0].shape[:2] + (2,)}, got {cells.shape}")
        cell_row = float(lut.shape[0])
        lut = np.ascontiguousarray(np.concatenate([lut, cell_rows(cells)]))
    n = out.shape[0]

    def part(i, j):  # the per-point arrays cut, the length-1 placeholders whole
        _stochastic_kernel(tex.data, tex.offsets, tex.widths, tex.heights, 0, 0, code, 0 if code == 0 else 1,
                           anisotropy, 0.0, -1000.0, 1000.0, lut, tables.basis, tables.origin, grid, key, nx, ny,
                           cell_row, mode, *(x[i:j] if x.shape[0] == n else x for x in (s_, t_, a_, b_, c_, d_, lod_,
                                                                                        out)))

    in_parts(n, part)
    return out.reshape(shape + (4,))
