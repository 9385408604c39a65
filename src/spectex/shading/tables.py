"""A texture's layers as the kernels and the shader take them: one typed structure.

:func:`pack` turns a spectral texture (anything with ``layers``, ``tiles``
and ``bits``, i.e. :class:`spectex.SpectralTexture`; this module imports
nothing above it; what is derived from the tiles comes from
``shading.resources`` in one bundle)
and a sampler state into :class:`ShadingTables`, a ``NamedTuple`` of
arrays and scalars that numba passes to the kernels as one argument and
from which ``render.gl`` sets the shader's per-layer uniforms. Everything a
layer needs that is derived on the host (its map, its level-of-detail
offset, its blend code with the first drawn layer marked) is computed here
and nowhere else.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .._validate import check_float
from ._mip_texture import filter_code
from .constants import (
    ANCHOR_PERIOD,
    BLEND_FIRST,
    BLENDS,
    DEFAULT_MAX_LOD,
    DEFAULT_MIN_LOD,
    FILTER_LINEAR,
    FILTER_LINEAR_MIPMAP_LINEAR,
    FILTER_NEAREST,
    TILING_STOCHASTIC,
    TILINGS,
    WRAP_REPEAT,
)
from .resources import cell_rows, cell_snaps, shading_resources

__all__ = ["ShadingTables", "pack", "anchor_coords"]


class ShadingTables(NamedTuple):
    """The texel store, the sampler state and the per-layer tables of a texture.

    Per-layer arrays have one entry per layer ``k`` in drawing order.
    """

    data: np.ndarray       #: (N, 4) float32: every tile's mip levels, RGBA (``spectex.shading.resources.texel_store``)
    flat: np.ndarray       #: (4 N,) float32: the same texels as one flat array (the fast path's view)
    stride: int            #: rows of ``data`` per tile
    offsets: np.ndarray    #: (levels,) int64: first row of each mip level within a tile
    widths: np.ndarray     #: (levels,) int64
    heights: np.ndarray    #: (levels,) int64
    wrap_s: int            #: ``constants.WRAP_*``
    wrap_t: int
    min_filter: int        #: ``constants.FILTER_*``
    mag_filter: int
    max_aniso: float       #: 1 = off
    bias: float
    min_lod: float
    max_lod: float
    tile: np.ndarray       #: (L,) int64: the layer's tile
    mats: np.ndarray       #: (L, 2, 2) float64: world metres -> tile coordinates (each layer's ``matrix()``)
    blend: np.ndarray      #: (L,) int64: ``constants.BLEND_*``; ``BLEND_FIRST`` for the first enabled layer
    tiling: np.ndarray     #: (L,) int64: ``constants.TILING_*``
    mean: np.ndarray       #: (L, 3) float64: mean colour of the layer's tile (its 1 x 1 level)
    opacity: np.ndarray    #: (L,) float64
    on: np.ndarray         #: (L,) int64: 1 if the layer is drawn
    lod_off: np.ndarray    #: (L,) float64: log2(tile width / layer size), texels per metre (section 3)
    size0: int             #: width of level 0
    fast: bool             #: the fast path's sampler state (docs/sampling.md, section 10)
    # stochastic tiling (section 6b; ``shading.stochastic``); 1-row placeholders when no layer is stochastic
    gauss: np.ndarray      #: (N, 4) float32: every tile's Gaussianised levels, laid out as ``data``
    #: (tiles * lut_rows, LUT_SIZE, 4) float32: expanded inverse tables, tile ``i`` from row ``i * lut_rows``
    lut: np.ndarray
    lut_rows: int          #: table rows per tile (``stochastic.expand_lut``)
    grid: np.ndarray       #: (L, 2, 2) float64: tile coordinates -> skewed triangle-grid coordinates
    key: np.ndarray        #: (L,) int64: the layer's hash key (``stochastic.layer_key(seed)``)
    #: (L, 2) float64: what the patch offsets are snapped to along s, t, as a count per tile (whole
    #: numbers): ``Layer.snap``'s periods, or the level-0 width, height (whole texels) where it is 0
    snap: np.ndarray
    #: (L,) float64: the first row of the layer's tile's cell map in ``lut`` (``resources.cell_rows``) for a
    #: stochastic layer whose snap the map was made for (free cells for (0, 0)), else -1 (no cells: the
    #: triangle grid's patches)
    cell_row: np.ndarray
    basis: np.ndarray      #: (L, 3, 3) float64: RGB = origin + basis @ decorrelated
    origin: np.ndarray     #: (L, 3) float64
    shift: np.ndarray      #: (L, 2) float64: the layer's offset (``Layer.offset``), world metres (for the anchors)


def anchor_coords(layers, x0: float, y0: float) -> np.ndarray:
    """Per layer, where world point ``(x0, y0)`` is in the layer's tile and grid, ``(L, 6)``.

    ``layers``: the texture's layers, or its :class:`ShadingTables` (which
    hold each layer's map, offset and grid: the renderers' way, the same
    numbers). Columns 0-1: the tile coordinates modulo ``ANCHOR_PERIOD``.
    Columns 2-5, for a stochastic layer (zero otherwise): the point in the
    skewed triangle-grid coordinates ``k = grid @ (s, t)`` split into its
    fraction ``k - floor(k)`` (2-3) and the grid vertex ``floor(k)`` modulo
    2^32 (4-5, whole numbers): the grid's vertices are hashed by their
    index, so it must be known exactly, not modulo a small period. Computed
    in float64 on the host, so that the kernels and shaders work with small
    coordinates relative to an anchor (the camera, a bake's corner) and keep
    their precision far from the world origin.
    """
    if isinstance(layers, ShadingTables):
        maps, offsets, grids = layers.mats, layers.shift, layers.grid
        stochastic = [int(t) == TILING_STOCHASTIC for t in layers.tiling]
    else:
        maps = [layer.matrix() for layer in layers]
        offsets = [layer.offset for layer in layers]
        stochastic = [getattr(layer, "tiling", "periodic") == "stochastic" for layer in layers]
        if any(stochastic):
            from .stochastic import layer_grid

            grids = [layer_grid(layer.patch, getattr(layer, "snap", (0, 0))) if st else None
                     for layer, st in zip(layers, stochastic)]
    out = np.zeros((len(maps), 6), dtype=np.float64)
    for k, m in enumerate(maps):
        dx = float(x0) - offsets[k][0]
        dy = float(y0) - offsets[k][1]
        s = m[0, 0] * dx + m[0, 1] * dy
        t = m[1, 0] * dx + m[1, 1] * dy
        out[k, 0] = s % ANCHOR_PERIOD
        out[k, 1] = t % ANCHOR_PERIOD
        if stochastic[k]:
            g = grids[k]
            kx = g[0, 0] * s + g[0, 1] * t
            ky = g[1, 0] * s + g[1, 1] * t
            bx, by = math.floor(kx), math.floor(ky)
            out[k, 2:] = (kx - bx, ky - by, bx % 2 ** 32, by % 2 ** 32)
    return out


def pack(texture, *, filter="trilinear", anisotropy=1.0, mipmaps=True, enabled=None) -> ShadingTables:
    """The :class:`ShadingTables` of ``texture`` for a sampler state.

    The texture's layers are read as plain data (each layer's map from
    ``Layer.matrix``), and everything derived from its tiles comes from
    ``shading.resources`` in one bundle (:func:`~spectex.shading.resources.shading_resources`).

    Parameters
    ----------
    texture : SpectralTexture
    filter : str
        Minification filter (``constants.FILTERS`` or an alias such as
        "trilinear"); ``"nearest"`` also magnifies with NEAREST.
    anisotropy : float
        Maximum anisotropy, 1 (off) to 16.
    mipmaps : bool
        False keeps level 0 only (for aliasing comparisons).
    enabled : sequence of bool, optional
        Per layer, whether it is drawn.
    """
    code = filter_code("filter", filter)
    aniso = check_float("anisotropy", anisotropy, minimum=1.0, maximum=16.0)
    layers = texture.layers
    n = len(layers)
    flags = [True] * n if enabled is None else [bool(e) for e in enabled]
    if len(flags) != n:
        raise ValueError(f"enabled must have one flag per layer ({n}), got {len(flags)}")
    on = np.array(flags, dtype=np.int64)
    h0, w0 = texture.tiles[0].shape[:2]
    tile = np.zeros(n, dtype=np.int64)
    blend = np.zeros(n, dtype=np.int64)
    tiling = np.zeros(n, dtype=np.int64)
    mats = np.zeros((n, 2, 2), dtype=np.float64)
    shift = np.zeros((n, 2), dtype=np.float64)
    opacity = np.zeros(n, dtype=np.float64)
    lod_off = np.zeros(n, dtype=np.float64)
    grid = np.zeros((n, 2, 2), dtype=np.float64)
    key = np.zeros(n, dtype=np.int64)
    snap = np.tile(np.array([w0, h0], dtype=np.float64), (n, 1))
    cell_row = np.full(n, -1.0)
    for k, layer in enumerate(layers):
        tile[k] = layer.tile
        blend[k] = BLENDS.index(layer.blend)
        tiling[k] = TILINGS.index(getattr(layer, "tiling", "periodic"))
        mats[k] = layer.matrix()
        shift[k] = layer.offset
        opacity[k] = layer.opacity
        lod_off[k] = math.log2(w0 / layer.size)
        if tiling[k] == TILING_STOCHASTIC:
            from .stochastic import layer_grid, layer_key, snap_counts

            grid[k] = layer_grid(layer.patch, getattr(layer, "snap", (0, 0)))
            key[k] = layer_key(layer.seed)
            snap[k] = snap_counts(getattr(layer, "snap", (0, 0)), (h0, w0))
    if on.any():
        blend[int(np.argmax(on))] = BLEND_FIRST
    stochastic = bool(np.any(tiling == TILING_STOCHASTIC))
    res = shading_resources(texture, mipmaps=mipmaps, stochastic=stochastic)
    data, stride, offsets, widths, heights = res.store
    mag = FILTER_NEAREST if code == FILTER_NEAREST else FILTER_LINEAR
    size0 = int(widths[0])
    fast = bool(code == FILTER_LINEAR_MIPMAP_LINEAR and aniso == 1.0 and h0 == w0 and size0 & (size0 - 1) == 0
                and widths.shape[0] == size0.bit_length())
    basis = np.zeros((n, 3, 3), dtype=np.float64)
    origin = np.zeros((n, 3), dtype=np.float64)
    if stochastic:
        gauss, lut, lut_rows = res.stochastic
        rows, snaps = cell_rows(texture), cell_snaps(texture)
        for k in np.flatnonzero(tiling == TILING_STOCHASTIC):
            basis[k] = res.tables[tile[k]].basis
            origin[k] = res.tables[tile[k]].origin
            if rows[tile[k]] >= 0 and tuple(int(v) for v in getattr(layers[k], "snap", (0, 0))) == snaps[tile[k]]:
                cell_row[k] = rows[tile[k]]
    else:
        gauss = np.zeros((1, 4), dtype=np.float32)
        lut = np.zeros((1, 2, 4), dtype=np.float32)
        lut_rows = 1
    return ShadingTables(
        data=data, flat=data.reshape(-1), stride=int(stride), offsets=offsets, widths=widths, heights=heights,
        wrap_s=WRAP_REPEAT, wrap_t=WRAP_REPEAT, min_filter=code, mag_filter=mag, max_aniso=aniso, bias=0.0,
        min_lod=DEFAULT_MIN_LOD, max_lod=DEFAULT_MAX_LOD, tile=tile, mats=mats, blend=blend, tiling=tiling,
        mean=np.ascontiguousarray(res.means[tile], dtype=np.float64), opacity=opacity, on=on, lod_off=lod_off,
        size0=size0, fast=fast, gauss=gauss, lut=lut, lut_rows=int(lut_rows), grid=grid, key=key,
        snap=snap, cell_row=cell_row, basis=basis, origin=origin, shift=shift)
