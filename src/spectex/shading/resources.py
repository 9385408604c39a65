"""Derived data of a spectral texture, made once and kept for the renderers.

A :class:`spectex.SpectralTexture` is plain data: tiles, layers, bits. What
the samplers, the kernels and the shaders read is derived from its tiles and
lives here, as plain functions of a texture:

=========================  ===============================================
function                   what it gives
=========================  ===============================================
:func:`mip_levels`         per tile, its mip chain quantised to the bits
:func:`mean_colours`       per tile, the mean RGB (its 1 x 1 level)
:func:`texel_store`        every tile's levels as one array (the kernels')
:func:`stochastic_tables`  per tile, its stochastic tiling's tables
:func:`cell_maps`          per tile, its structural cells for the snap of
                           its snapped stochastic layers (``_cells``)
:func:`stochastic_store`   the Gaussianised levels and expanded look-up
                           tables (and the cell maps after them) as one
                           array each (the kernels')
:func:`cell_rows`          per tile, where its cell map starts in them
:func:`course_joints`      a tile's courses and their joints (what a course
                           map is made of; the fit's period tile reads them)
:func:`shading_resources`  those of them that ``shading.tables.pack``
                           reads, handed down in one bundle
=========================  ===============================================

Caching. The results depend on the tiles' texels and the texture's bits
(and the cell maps on the snapped layers' ``snap``), so they are kept in one small least-recently-used
cache of this module, keyed on content: a BLAKE2 digest of each tile's
texels (taken once per tile array, remembered while the array lives) and
the bits. Textures with the same tiles share their entries (a fit builds
many textures over one tile), a texture that is dropped leaves at most the
last :data:`KEPT` entries behind, and nothing is stored on the texture.
The renderers (``render.cpu``, ``render.gl``, the bakes and the exports)
read through this cache; :func:`clear_cache` empties it. Like the texture,
the cache takes a texture's tile arrays as never changing once made; the
returned arrays are shared between callers and must not be written to.
The cache is guarded by a lock, for the threads of a Dask bake.
"""

from __future__ import annotations

import hashlib
import threading
import weakref
from collections import OrderedDict
from typing import NamedTuple

import numpy as np

from ._cells import cell_map, course_joints

__all__ = ["KEPT", "ShadingResources", "StochasticStore", "TexelStore", "cell_map", "cell_maps", "cell_rows",
           "cell_snaps", "course_joints", "clear_cache", "mean_colours", "mip_levels", "shading_resources",
           "stochastic_store", "stochastic_tables", "texel_store", "tile_digest"]

#: Entries kept (a tile's levels, a tile's stochastic tables, a texture's store: one entry each).
KEPT = 16

_LOCK = threading.RLock()
_CACHE: OrderedDict = OrderedDict()  # key -> value, most recently used last
_DIGESTS: dict[int, tuple[weakref.ref, bytes]] = {}  # id(tile) -> (a weak reference to it, its digest)


class TexelStore(NamedTuple):
    """Every tile's levels as one array, as the kernels and the GL renderer read them."""

    data: np.ndarray      #: (N, 4) float32 RGBA
    stride: int           #: rows per tile: tile ``i``'s level ``d`` starts at row ``i * stride + offsets[d]``
    offsets: np.ndarray   #: (levels,) int64
    widths: np.ndarray    #: (levels,) int64
    heights: np.ndarray   #: (levels,) int64


class StochasticStore(NamedTuple):
    """The stochastic layers' texels as the kernels take them."""

    gauss: np.ndarray     #: every tile's Gaussianised levels, laid out as :attr:`TexelStore.data`
    #: (tiles * lut_rows + cell rows, LUT_SIZE, 4) float32, tile ``i``'s expanded table from ``i * lut_rows``,
    #: then the cell maps (:func:`cell_rows`)
    lut: np.ndarray
    lut_rows: int


def clear_cache() -> None:
    """Drop every kept entry (the next call of each function rebuilds what it needs)."""
    with _LOCK:
        _CACHE.clear()


def tile_digest(tile: np.ndarray) -> bytes:
    """A 16-byte BLAKE2 digest of a tile's shape, dtype and texels, taken once per array object."""
    with _LOCK:
        entry = _DIGESTS.get(id(tile))
        if entry is not None and entry[0]() is tile:
            return entry[1]
    digest = hashlib.blake2b(repr((tile.shape, tile.dtype.str)).encode(), digest_size=16)
    digest.update(np.ascontiguousarray(tile).data)
    value = digest.digest()
    key = id(tile)

    def forget(ref, key=key):
        with _LOCK:
            if _DIGESTS.get(key, (None,))[0] is ref:
                del _DIGESTS[key]

    with _LOCK:
        _DIGESTS[key] = (weakref.ref(tile, forget), value)
    return value


def _kept(key, make):
    """The cached value of ``key``, made by ``make()`` on a miss (under the lock: made once)."""
    with _LOCK:
        value = _CACHE.pop(key, None)
        if value is None:
            value = make()
        _CACHE[key] = value
        while len(_CACHE) > KEPT:
            _CACHE.popitem(last=False)
        return value


def _tile_levels(tile: np.ndarray, bits) -> list[np.ndarray]:
    from ..tiles.mipmap import quantize
    from ._mip_texture import default_mip_chain

    return _kept(("levels", tile_digest(tile), bits),
                 lambda: [quantize(level, bits) for level in default_mip_chain(tile)])


def mip_levels(texture) -> list[list[np.ndarray]]:
    """Per tile, its mip chain (``spectex.tiles.mip_chain``), quantised to the texture's bits.

    These exact arrays are what the CPU sampler holds, what the GL renderer
    uploads and what the exports write.
    """
    return [_tile_levels(tile, texture.bits) for tile in texture.tiles]


def mean_colours(texture) -> np.ndarray:
    """Per tile, the mean RGB, ``(tiles, 3)`` float64: its 1 x 1 mip level (the ``mu`` of the variance blend)."""
    return np.array([levels[-1][0, 0, :3] for levels in mip_levels(texture)], dtype=np.float64)


def _texture_key(texture) -> tuple:
    return (texture.bits, tuple(tile_digest(tile) for tile in texture.tiles))


def texel_store(texture, *, mipmaps=True) -> TexelStore:
    """All tiles' texels as one :class:`TexelStore` (level 0 only with ``mipmaps=False``)."""
    mipmaps = bool(mipmaps)

    def make():
        from ._mip_texture import MipTexture

        textures = [MipTexture(lv if mipmaps else lv[:1], bits=None) for lv in mip_levels(texture)]
        tex = textures[0]
        data = np.ascontiguousarray(np.concatenate([t.data for t in textures]))
        return TexelStore(data, tex.data.shape[0], tex.offsets, tex.widths, tex.heights)

    return _kept(("store", _texture_key(texture), mipmaps), make)


class ShadingResources(NamedTuple):
    """What :func:`spectex.shading.tables.pack` reads of a texture's derived data, fetched in one call."""

    store: TexelStore               #: :func:`texel_store`
    means: np.ndarray               #: :func:`mean_colours`
    stochastic: StochasticStore | None  #: :func:`stochastic_store`; None without ``stochastic``
    tables: list | None             #: :func:`stochastic_tables`; None without ``stochastic``


def shading_resources(texture, *, mipmaps=True, stochastic=False) -> ShadingResources:
    """The texel store and mean colours of ``texture`` and, with ``stochastic``, its stochastic store and
    tables: everything the packed tables hold of the tiles, handed down in one bundle."""
    store = texel_store(texture, mipmaps=mipmaps)
    means = mean_colours(texture)
    if not stochastic:
        return ShadingResources(store, means, None, None)
    return ShadingResources(store, means, stochastic_store(texture, mipmaps=mipmaps), stochastic_tables(texture))


def stochastic_tables(texture) -> list:
    """Per tile, the :class:`~spectex.shading.stochastic.StochasticTables` of its stochastic tiling.

    The Gaussianised tile's mip levels, the per-level inverse look-up tables
    and the colour decorrelation: a deterministic function of the tile's
    texels (what a file stores rebuilds them exactly). A tile with a cell map
    (:func:`cell_maps`) has its levels Gaussianised one by one
    (``stochastic_tables(..., per_level=True)``: exact tables at every level).
    A tile no stochastic layer draws (a fit's coarse tile) gets
    ``stochastic.unused_tables``: its shapes, no values, nothing to rank (the
    Gaussianisation of a 2048-texel tile takes seconds).
    """
    from .stochastic import stochastic_tables as build
    from .stochastic import unused_tables

    return [_kept(("unused tables", tile.shape), lambda tile=tile: unused_tables(tile)) if snap is None else
            _kept(("tables", tile_digest(tile), cells is not None),
                  lambda tile=tile, per_level=cells is not None: build(tile, per_level=per_level))
            for tile, cells, snap in zip(texture.tiles, cell_maps(texture), cell_snaps(texture))]


def cell_snaps(texture) -> tuple:
    """Per tile, the ``snap`` its cell map is made for: that of the first stochastic layer drawing it
    (``Layer.snap``; (0, 0), offsets free along both axes, takes ``shading._cells.free_cell_map``'s cells
    where the tile has a grout), or None (no stochastic layer, no map)."""
    out = [None] * len(texture.tiles)
    for layer in texture.layers:
        snap = tuple(int(v) for v in getattr(layer, "snap", (0, 0)))
        if getattr(layer, "tiling", "periodic") == "stochastic" and out[layer.tile] is None:
            out[layer.tile] = snap
    return tuple(out)


def cell_maps(texture) -> list:
    """Per tile, its cell map (``shading._cells.cell_map``: per level-0 texel the vector to the centre of its
    brick, floor tile or cobble) for :func:`cell_snaps`' snap, or None (no stochastic layer, or no separate
    cells)."""

    return [None if snap is None else _kept(("cells", tile_digest(tile), snap),
                                            lambda tile=tile, snap=snap: _Maybe(cell_map(tile, snap))).value
            for tile, snap in zip(texture.tiles, cell_snaps(texture))]


class _Maybe(NamedTuple):
    """A cached value that may be None (the cache takes None for a miss)."""

    value: object


def cell_rows(texture) -> tuple:
    """Per tile, the first row of its cell map in :func:`stochastic_store`'s ``lut`` (``stochastic.cell_rows``
    lays it out), or -1 without a map. The maps follow every tile's expanded table, in tile order."""
    row = len(texture.tiles) * _lut_rows(texture)
    out = []
    for cells in cell_maps(texture):
        if cells is None:
            out.append(-1)
        else:
            out.append(row)
            # (a course map's course-start table after it: stochastic.course_starts_row)
            row += -(-cells.shape[0] * cells.shape[1] // _lut_size()) + (cells.shape[2] == 4)
    return tuple(out)


def _lut_size() -> int:
    from .constants import LUT_SIZE

    return LUT_SIZE


def _lut_rows(texture) -> int:
    """Rows of one tile's expanded table (``stochastic.expand_lut``)."""
    from .constants import LUT_SUBROWS

    return (len(stochastic_tables(texture)[0].gaussian) - 1) * LUT_SUBROWS + 1


def stochastic_store(texture, *, mipmaps=True) -> StochasticStore:
    """The stochastic layers' texels as one :class:`StochasticStore`.

    ``gauss`` holds every tile's Gaussianised levels laid out exactly as
    :func:`texel_store`'s ``data`` (level 0 only without ``mipmaps``);
    ``lut`` every tile's expanded table
    (``spectex.shading.stochastic.expand_lut``), ``lut_rows`` rows each,
    and after them the tiles' cell maps (:func:`cell_maps`, laid out by
    ``stochastic.cell_rows``; where :func:`cell_rows` says).
    """
    mipmaps = bool(mipmaps)

    def make():
        from ._mip_texture import MipTexture

        tables = stochastic_tables(texture)
        textures = [MipTexture(tb.gaussian if mipmaps else tb.gaussian[:1], bits=None) for tb in tables]
        gauss = np.ascontiguousarray(np.concatenate([t.data for t in textures]))
        rows = [tb.expanded() for tb in tables]
        from .stochastic import cell_rows as layout

        cells = [layout(c) for c in cell_maps(texture) if c is not None]
        lut = np.ascontiguousarray(np.concatenate(rows + cells), dtype=np.float32)
        return StochasticStore(gauss, lut, rows[0].shape[0])

    return _kept(("stochastic_store", _texture_key(texture), mipmaps, cell_snaps(texture)), make)
