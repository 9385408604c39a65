"""The spectral texture: layers of one tile at different scales, alpha-coupled.

Berger's spectral texturing (seed 000, [1]_): a large, non-repetitive
texture is drawn as several layers of the same seamless, low-pass filtered
RGBA tile at geometrically spaced scales. The finest layer is drawn first;
each coarser layer is blended over what is there,

    c = a * c_layer + (1 - a) * c,

so the coarser layer's alpha says where the finer bands stay visible: the
amplitude of the fine detail depends on the phase of the coarse layers.

Also here, for comparison and as options:

* ``"detail"``: detail texturing, no alpha; the layer modulates what is
  there around mid-grey, ``c = 2 * c_layer * c`` (OpenGL's ``MODULATE`` with
  a scale of 2, the classic detail-texture combiner);
* ``"variance"``: a contrast-preserving alpha blend in the spirit of Heitz
  and Neyret [2]_: ``c = mu + (a (c_layer - mu) + (1 - a)(c - mu)) /
  sqrt(a^2 + (1 - a)^2)``, with ``mu`` the layer tile's mean colour (its 1 x 1
  mip level), so that blending two independent layers keeps their variance
  instead of washing it out;
* ``"cover"``: the variance blend with the alpha raised to 1 as the pixel's
  footprint on the layer grows, so that the finer layers drawn before it
  fade out where their periods would be a few pixels on screen and their
  repeats a visible weave (``docs/rendering.md``);
* ``"overlay"``: the overlay of the layer on what is there, ``a`` of the way:
  with ``d = a (2 c_layer - 1)``, ``c (1 + d)`` below mid-grey and
  ``1 - (1 - c)(1 - d)`` from it, so that black and white stay where they
  are and the contrast below is scaled, not veiled (the fit's coarse
  layers, ``docs/fitting.md``).

This module is the data model: layers, tiles and presets, plain data. It
imports nothing from the shading core or the renderers (the shading
constants excepted: ``shading.constants`` is a leaf of plain values, the
vocabulary of blends and tilings). What is derived from the tiles (mip
levels, texel stores, stochastic tables) is ``spectex.shading.resources``';
how a texture is sampled, composited and seen is the shading core's
(``spectex.shading``, ``docs/sampling.md``), called by the renderers
(``spectex.render.bake`` for a top-down view); the file format is
``spectex.texture_file``.

References
----------
.. [1] D. R. Berger, "Spectral texturing for real-time applications",
   SIGGRAPH 2003 Sketches and Applications.
.. [2] E. Heitz and F. Neyret, "High-performance by-example noise using a
   histogram-preserving blending operator", Proc. ACM Comput. Graph.
   Interact. Tech. 1(2), 2018.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from . import texture_file
from ._validate import (
    check_choice,
    check_float,
    check_image,
    check_int,
    check_length,
    check_rng,
    check_snap,
    check_tile_shape,
)
from .shading.constants import BLENDS, DEFAULT_PATCH, MAX_LAYERS, MAX_TILES, TILINGS

__all__ = ["Layer", "SpectralTexture", "BLENDS", "GOLDEN_ANGLE", "DETAIL_SIZE", "layer_matrix", "layer_placement"]


#: Repetition size (metres) of :meth:`SpectralTexture.paper_preset`'s detail layer: the finest of
#: the five (15.625 m) over 12.5, so that its 2.4 mm texels meet the demo close-up's 2.35 mm pixels.
DETAIL_SIZE = 1.25


#: The golden angle in degrees, ``180 (3 - sqrt 5)``: successive multiples never line up.
GOLDEN_ANGLE = 137.50776405003785


def layer_placement(k: int, size: float, *, decimals: int = 6) -> tuple[tuple[float, float], float]:
    """Offset and rotation of layer ``k`` of a stack, so that the layers' grids do not line up.

    The one rule for the layers of :meth:`SpectralTexture.paper_preset` and of
    :func:`spectex.fit`: layer ``k`` is rotated by ``k`` times the golden
    angle (modulo 360 degrees) and offset by ``((0.382 k mod 1) size,
    (0.618 k mod 1) size)`` metres, fractions of its own repetition size
    (0.382 and 0.618 are the golden ratio's fractions, so the offsets of
    successive layers spread evenly). Layer 0 is neither offset nor rotated.

    Parameters
    ----------
    k : int
        The layer's index, finest first (>= 0).
    size : float
        The layer's repetition size (:attr:`Layer.size`), metres.
    decimals : int
        Decimals the offset is rounded to (short, readable numbers in a
        saved texture); the rotation is rounded to 6 decimals (a
        micro-degree).

    Returns
    -------
    offset : (float, float)
        Metres.
    rotation : float
        Degrees in [0, 360).
    """
    k = check_int("k", k, minimum=0)
    size = check_float("size", size)
    decimals = check_int("decimals", decimals, minimum=0, maximum=15)
    offset = (round((0.382 * k % 1.0) * size, decimals), round((0.618 * k % 1.0) * size, decimals))
    return offset, round((GOLDEN_ANGLE * k) % 360.0, 6)


def layer_matrix(size: float, rotation: float) -> np.ndarray:
    """The 2 x 2 map from world displacement (metres) to tile coordinates (s, t).

    ``M = R(-rotation) / size`` (rotation in degrees, counter-clockwise).
    """
    th = math.radians(rotation)
    c, s = math.cos(th), math.sin(th)
    return np.array([[c, s], [-s, c]], dtype=np.float64) / size


@dataclass(frozen=True)
class Layer:
    """One layer of a spectral texture.

    Parameters
    ----------
    size : float
        World size of one repeat of the tile, in metres (> 0).
    tile : int
        Index of the layer's tile in ``SpectralTexture.tiles``.
    offset : (float, float)
        World position (x, y) of the tile's origin (texel corner (0, 0)), metres.
    rotation : float
        Rotation of the tile grid, degrees, counter-clockwise.
    blend : {"alpha", "detail", "variance", "fine", "cover", "overlay"}
        How this layer goes over the finer layers drawn before it (ignored
        for the first layer, which is drawn opaque). ``"fine"``: the
        variance blend with the alpha faded out by the pixel's footprint on
        this layer (``shading.constants.FADE_START``, ``FADE_END``), for a
        detail layer finer than the others, drawn last. ``"cover"``: the
        variance blend with the alpha ``a`` raised to ``1 - (1 - a) f`` by
        the same fade ``f``: the layers drawn before it are gone where a
        pixel covers ``2**FADE_END`` of this layer's texels, before the
        finer periods shrink to a few pixels and their repeats show.
    opacity : float
        In [0, 1]: the layer's alpha is ``opacity * tile_alpha`` (a global
        translucency, like a constant blend factor); it sets how much of
        the finer bands shows through on average.
    tiling : {"periodic", "stochastic"}
        How the tile covers the plane. ``"periodic"`` (the paper's method):
        it repeats every ``size`` metres. ``"stochastic"``: histogram-preserving
        tiling and blending (Heitz and Neyret 2018; ``spectex.shading.stochastic``):
        a grid of triangles of side ``patch`` tiles, every vertex a random
        offset into the tile, three patches blended per point so that the
        tile's histogram is kept; the layer never repeats.
    patch : float
        Stochastic tiling: side of the grid's triangles, in tiles (0 <
        patch <= 4; 0.25 to 1 is useful: smaller patches repeat less and
        blend more). Ignored for periodic tiling.
    seed : int
        Stochastic tiling: which random offsets the grid's vertices get, 0
        to 2^32 - 1 (layers of one tile should differ). Ignored for
        periodic tiling.
    snap : (int, int)
        Stochastic tiling of a structured tile (bricks, tiles, paving): the
        tile holds ``nx`` x ``ny`` whole periods of its structure, and the
        patches' random offsets are whole periods, multiples of ``1/nx``
        of the tile along s and ``1/ny`` along t (rounded down to whole
        texels), so every patch shows the structure's grid at the same
        place and the blend crosses aligned structure, while the content
        inside the periods differs from patch to patch. 0 along an axis:
        offsets free along it (whole texels); ``(0, 0)`` (the default):
        off. Each 0 to 256. Ignored for periodic tiling.
    """

    size: float
    tile: int = 0
    offset: tuple[float, float] = (0.0, 0.0)
    rotation: float = 0.0
    blend: str = "alpha"
    opacity: float = 1.0
    tiling: str = "periodic"
    patch: float = DEFAULT_PATCH
    seed: int = 0
    snap: tuple[int, int] = (0, 0)

    def __post_init__(self):
        object.__setattr__(self, "size", check_length("size", self.size))
        object.__setattr__(self, "tile", check_int("tile", self.tile, minimum=0))
        off = self.offset
        if not isinstance(off, (tuple, list, np.ndarray)) or len(off) != 2:
            raise ValueError(f"offset must be a pair (x, y) of numbers, got {off!r}")
        object.__setattr__(self, "offset", (check_float("offset[0]", off[0]), check_float("offset[1]", off[1])))
        object.__setattr__(self, "rotation", check_float("rotation", self.rotation))
        object.__setattr__(self, "blend", check_choice("blend", self.blend, BLENDS))
        object.__setattr__(self, "opacity", check_float("opacity", self.opacity, minimum=0.0, maximum=1.0))
        object.__setattr__(self, "tiling", check_choice("tiling", self.tiling, TILINGS))
        object.__setattr__(self, "patch", check_float("patch", self.patch, minimum=0.0, exclusive_minimum=True,
                                                      maximum=4.0))
        object.__setattr__(self, "seed", check_int("seed", self.seed, minimum=0, maximum=2 ** 32 - 1))
        object.__setattr__(self, "snap", check_snap("snap", self.snap))

    def matrix(self) -> np.ndarray:
        """The 2 x 2 map from world displacement (metres) to tile coordinates (s, t).

        ``(s, t) = R(-rotation) (p - offset) / size``.
        """
        return layer_matrix(self.size, self.rotation)

    def coords(self, x, y):
        """Tile coordinates (s, t) of world points (x, y), float64."""
        m = self.matrix()
        dx = np.asarray(x, dtype=np.float64) - self.offset[0]
        dy = np.asarray(y, dtype=np.float64) - self.offset[1]
        return m[0, 0] * dx + m[0, 1] * dy, m[1, 0] * dx + m[1, 1] * dy


_LAYER_FIELDS = frozenset(field.name for field in fields(Layer))


def _as_layer(i, value) -> Layer:
    if isinstance(value, Layer):
        return value
    if isinstance(value, dict):
        unknown = sorted(set(value) - _LAYER_FIELDS, key=str)
        if unknown:
            raise ValueError(f"layers[{i}]: unknown field {unknown[0]!r} (known: {', '.join(sorted(_LAYER_FIELDS))})")
        try:
            return Layer(**value)
        except (TypeError, ValueError) as exc:  # a field's check: "size must be ..."
            raise type(exc)(f"layers[{i}].{exc}") from None
    raise TypeError(f"layers[{i}] must be a Layer or a dict, got {type(value).__name__}")


class SpectralTexture:
    """A spectral texture: an ordered list of layers over one or more RGBA tiles.

    Parameters
    ----------
    tiles : ndarray or sequence of ndarray
        Seamless tiles, each ``(H, W, 4)`` float in [0, 1] (RGB gets alpha 1),
        all of the same shape (powers of two sample fastest). Usually one, from
        ``spectex.tiles.make_tile``.
    layers : sequence of Layer or dict
        Drawing order: the first (usually the finest) is drawn opaque, each
        next one is blended over it by its ``blend``.
    bits : {8, None}
        Texel precision: 8 bits per channel (an RGBA8 texture, the paper's
        1 MB for a 512 x 512 tile) or float32. The tiles are quantised here,
        so files, the CPU sampler and the GL renderer all hold the same texels.

    Notes
    -----
    World coordinates are metres, ``x`` east, ``y`` north, ``z`` up; the
    ground is the plane ``z = 0``. A layer maps world ``(x, y)`` to tile
    coordinates ``(s, t)`` (:meth:`Layer.coords`), ``s`` along the tile's
    columns and ``t`` along its rows (row 0 at ``t = 0``).
    """

    def __init__(self, tiles, layers, *, bits=8):
        if isinstance(tiles, np.ndarray):
            tiles = [tiles]
        tiles = list(tiles)
        if not tiles:
            raise ValueError("tiles must hold at least one tile, got 0")
        if len(tiles) > MAX_TILES:
            raise ValueError(f"tiles must hold at most {MAX_TILES} tiles, got {len(tiles)}")
        if bits not in (8, None):
            raise ValueError(f"bits must be 8 or None, got {bits!r}")
        checked = []
        for i, tile in enumerate(tiles):
            check_tile_shape(f"tiles[{i}]", np.shape(tile))  # before any work on it
            tile = check_image(f"tiles[{i}]", tile, channels=(3, 4), min_size=1)
            if tile.shape[2] == 3:
                tile = np.concatenate([tile, np.ones(tile.shape[:2] + (1,), np.float32)], axis=2)
            if tile.shape != checked[0].shape if checked else False:
                raise ValueError(f"tiles[{i}] has shape {tile.shape}, tiles[0] has {checked[0].shape}; "
                                 "all tiles must have the same shape")
            if np.any(tile < 0) or np.any(tile > 1):
                raise ValueError(f"tiles[{i}] values must be in [0, 1], got [{tile.min():g}, {tile.max():g}]")
            checked.append(tile)
        layers = [_as_layer(i, layer) for i, layer in enumerate(layers)]
        if not layers:
            raise ValueError("layers must hold at least one layer, got 0")
        if len(layers) > MAX_LAYERS:
            raise ValueError(f"layers must hold at most {MAX_LAYERS} layers, got {len(layers)}")
        for i, layer in enumerate(layers):
            if layer.tile >= len(checked):
                raise ValueError(f"layers[{i}].tile must be < {len(checked)} (the number of tiles), got {layer.tile}")
        from .tiles.mipmap import quantize  # NumPy only (the tiles' package loads its numba modules lazily)

        for i, tile in enumerate(checked):
            checked[i] = np.ascontiguousarray(quantize(tile, bits))
        self.tiles = checked
        self.layers = layers
        self.bits = bits

    # ------------------------------------------------------------------ presets
    @classmethod
    def paper_preset(cls, tile=None, *, rng=0, blend="cover", opacity=0.65, tile_size=512, bits=8,
                     tiling="periodic", patch=DEFAULT_PATCH, detail=True):
        """The five-layer texture of the paper's Figure 1, with contrast that survives the layers.

        ``paper_preset(tile, blend="alpha", detail=False)`` is the paper's own
        texture and picture; the defaults keep its five layers but composite
        them with the variance-preserving blend and add a fine detail layer
        (``docs/rendering.md``, "A first picture": the paper's alpha blend
        keeps 20 % of the tile's local contrast in the demo's ground view,
        11 % in the close-up; these defaults 62 % and 64 %), each coarser
        layer covering the finer ones where their periods shrink to a few
        pixels (blend ``"cover"``: the plain variance blend showed the
        15.625 m layer's repeats as a weave over the demo's aerial view).

        Five layers of one 512 x 512 tile: the finest repeats every 1/64 km
        (15.625 m), the coarsest every 10 km, geometric steps between
        (a factor 640**(1/4) ~ 5.03). That is a virtual texture of 327680 x
        327680 texels at about 3 cm per texel, held in 1 MB. The layers are
        rotated by multiples of the golden angle and offset, so that their
        grids do not line up.

        Parameters
        ----------
        tile : ndarray, optional
            The RGBA tile; by default ``spectex.tiles.make_tile(tile_size, rng=rng)``.
        rng : int, numpy.random.Generator or None
            Randomness of the default tile (as :func:`spectex.tiles.make_tile`
            takes it; unused when ``tile`` is given): the same int gives the
            same texture.
        blend : {"alpha", "detail", "variance", "cover"}
            The blend of layers 2..5: ``"cover"`` (the default) is
            ``"variance"`` with each layer's alpha raised to 1 by the pixel's
            footprint (:class:`Layer`), so that a finer layer is gone where
            its period would span fewer than about 13 pixels (``512 /
            5.03 / 2**FADE_END``) and its repeats would show; ``"variance"``
            keeps the tile's contrast through the layers (Heitz and Neyret's
            variance-preserving blend around the tile's mean colour) and
            draws every layer at every distance;
            ``"alpha"`` is the paper's (a weighted average of nearly
            independent layers, which keeps about ``sqrt(sum w_k^2)`` of the
            contrast); ``"detail"`` gives detail texturing for comparison.
        opacity : float
            Opacity of layers 2..5. The emboss alpha averages 0.5; at full
            opacity the finest layer keeps only ``0.5**4`` of its weight and
            close-ups look flat. 0.65 (mean alpha 0.33) gives the five bands
            comparable weights (0.21 for the finest, 0.33 for the coarsest)
            and keeps the repetition peak of the finest tile at 0.10-0.18
            (seeds 0-4; 1.0 for plain tiling).
        tiling : {"periodic", "stochastic"}
            Every layer's tiling (:class:`Layer`). ``"periodic"`` is the
            paper's method; ``"stochastic"`` makes every layer a
            histogram-preserving tiling and blending of the tile (layer
            ``k`` with hash seed ``k``), which never repeats: the fine
            detail's :func:`spectex.metrics.repeat_peak` on top-down bakes
            falls from 0.77 to 0.92 to under 0.1 (``docs/sampling.md``).
        patch : float
            The stochastic layers' triangle side, in tiles.
        detail : bool
            Add a sixth layer, drawn last: the same tile repeating every
            ``DETAIL_SIZE`` (1.25 m, 12.5 times finer than the finest of the
            five: 2.4 mm texels), with its own offset and rotation, blend
            ``"fine"`` (the variance blend with the alpha faded out by the
            pixel's footprint, ``shading.constants.FADE_START``/``FADE_END``):
            texture under the feet at 1 m, gone from about 10 m on, before
            its repetition could be seen or its texels alias.
        """
        rng = check_rng(rng)
        blend = check_choice("blend", blend, BLENDS)
        tiling = check_choice("tiling", tiling, TILINGS)
        opacity = check_float("opacity", opacity, minimum=0.0, maximum=1.0)
        if tile is None:
            from .tiles import make_tile

            tile = make_tile(check_int("tile_size", tile_size, minimum=2), rng=rng)
        n = 5
        finest, coarsest = 1000.0 / 64.0, 10000.0
        ratio = (coarsest / finest) ** (1.0 / (n - 1))
        layers = []
        for k in range(n):
            size = finest * ratio ** k if k < n - 1 else coarsest
            offset, rotation = layer_placement(k, size)
            layers.append(Layer(size=size, tile=0, offset=offset, rotation=rotation, blend=blend,
                                opacity=1.0 if k == 0 else opacity, tiling=tiling, patch=patch,
                                seed=k if tiling == "stochastic" else 0))
        if not isinstance(detail, (bool, np.bool_)):
            raise TypeError(f"detail must be True or False, got {detail!r}")
        if detail:
            offset, rotation = layer_placement(n, DETAIL_SIZE)
            layers.append(Layer(size=DETAIL_SIZE, tile=0, offset=offset, rotation=rotation, blend="fine",
                                opacity=1.0, tiling=tiling, patch=patch, seed=n if tiling == "stochastic" else 0))
        return cls(tile, layers, bits=bits)

    @classmethod
    def plain(cls, tile, size, *, bits=8):
        """One layer: plain tiling of ``tile`` every ``size`` metres (the control)."""
        return cls(tile, [Layer(size=size)], bits=bits)

    # --------------------------------------------------------------- properties
    @property
    def tile_shape(self) -> tuple[int, int]:
        return self.tiles[0].shape[:2]

    @property
    def texel_size(self) -> float:
        """World size of one texel of the finest layer (metres)."""
        return min(layer.size for layer in self.layers) / self.tile_shape[1]

    @property
    def virtual_size(self) -> int:
        """Texels along the coarsest repeat at the finest layer's resolution (327680 for the paper)."""
        return int(round(max(layer.size for layer in self.layers) / self.texel_size))

    @property
    def nbytes(self) -> int:
        """Bytes of texture memory the tiles take at level 0 (RGBA, 1 byte per channel for bits=8)."""
        h, w = self.tile_shape
        return len(self.tiles) * h * w * 4 * (1 if self.bits == 8 else 4)

    @property
    def nbytes_mipmapped(self) -> int:
        """Bytes with all mip levels."""
        from .tiles.mipmap import gl_level_shapes

        per = sum(h * w for h, w in gl_level_shapes(*self.tile_shape)) * 4 * (1 if self.bits == 8 else 4)
        return len(self.tiles) * per

    @property
    def nbytes_as_image(self) -> int:
        """Bytes the same texture would take as one RGB8 image of virtual_size squared."""
        return self.virtual_size ** 2 * 3

    def __repr__(self):
        h, w = self.tile_shape
        sizes = ", ".join(f"{layer.size:g}" for layer in self.layers)
        return f"SpectralTexture({len(self.layers)} layers [{sizes}] m, tile {w}x{h}, bits={self.bits})"

    def __eq__(self, other):
        if not isinstance(other, SpectralTexture):
            return NotImplemented
        return (self.layers == other.layers and self.bits == other.bits and len(self.tiles) == len(other.tiles)
                and all(np.array_equal(a, b) for a, b in zip(self.tiles, other.tiles)))

    # ------------------------------------------------------------------- files
    def save(self, path):
        """Write the texture file (TOML) and its tile PNG(s) beside it (``spectex.texture_file.save``)."""
        return texture_file.save(self, path)

    @classmethod
    def load(cls, path) -> "SpectralTexture":
        """Read a texture file (``spectex.texture_file.load``); every field is checked."""
        return texture_file.load(path, texture_type=cls)

