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
  instead of washing it out.

The layer compositing here is the written-down specification of
``docs/sampling.md``; the GLSL renderer implements the same text.

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
import numbers
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._validate import (check_choice, check_float, check_image, check_int, check_relative_name, check_shape,
                        check_tile_shape)

__all__ = ["Layer", "SpectralTexture", "BLENDS", "FORMAT", "FORMAT_VERSION", "MAX_BAKE_PIXELS"]

#: How a layer goes over the layers drawn before it (codes 0, 1, 2 in the kernels).
BLENDS = ("alpha", "detail", "variance")
#: File format name and version written to and required in texture files.
FORMAT = "spectex.spectral-texture"
FORMAT_VERSION = 1
#: Most layers a texture may have (the GL shader is generated for up to this many).
MAX_LAYERS = 8
#: Largest bake, in pixels (times supersample squared): 64 Mpx, about 1 GiB of float32 work arrays.
MAX_BAKE_PIXELS = 1 << 26


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
    blend : {"alpha", "detail", "variance"}
        How this layer goes over the finer layers drawn before it (ignored
        for the first layer, which is drawn opaque).
    opacity : float
        In [0, 1]: the layer's alpha is ``opacity * tile_alpha`` (a global
        translucency, like a constant blend factor); it sets how much of
        the finer bands shows through on average.
    """

    size: float
    tile: int = 0
    offset: tuple[float, float] = (0.0, 0.0)
    rotation: float = 0.0
    blend: str = "alpha"
    opacity: float = 1.0

    def __post_init__(self):
        object.__setattr__(self, "size", check_float("size", self.size, minimum=0.0, exclusive_minimum=True))
        object.__setattr__(self, "tile", check_int("tile", self.tile, minimum=0))
        off = self.offset
        if not isinstance(off, (tuple, list, np.ndarray)) or len(off) != 2:
            raise ValueError(f"offset must be a pair (x, y) of numbers, got {off!r}")
        object.__setattr__(self, "offset", (check_float("offset[0]", off[0]), check_float("offset[1]", off[1])))
        object.__setattr__(self, "rotation", check_float("rotation", self.rotation))
        object.__setattr__(self, "blend", check_choice("blend", self.blend, BLENDS))
        object.__setattr__(self, "opacity", check_float("opacity", self.opacity, minimum=0.0, maximum=1.0))

    def matrix(self) -> np.ndarray:
        """The 2 x 2 map from world displacement (metres) to tile coordinates (s, t).

        ``(s, t) = R(-rotation) (p - offset) / size``.
        """
        th = math.radians(self.rotation)
        c, s = math.cos(th), math.sin(th)
        return np.array([[c, s], [-s, c]], dtype=np.float64) / self.size

    def coords(self, x, y):
        """Tile coordinates (s, t) of world points (x, y), float64."""
        m = self.matrix()
        dx = np.asarray(x, dtype=np.float64) - self.offset[0]
        dy = np.asarray(y, dtype=np.float64) - self.offset[1]
        return m[0, 0] * dx + m[0, 1] * dy, m[1, 0] * dx + m[1, 1] * dy


def _as_layer(i, value) -> Layer:
    if isinstance(value, Layer):
        return value
    if isinstance(value, dict):
        try:
            return Layer(**value)
        except TypeError as exc:
            raise ValueError(f"layers[{i}]: {exc}") from None
        except ValueError as exc:
            raise ValueError(f"layers[{i}].{exc}") from None
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
        if bits not in (8, None):
            raise ValueError(f"bits must be 8 or None, got {bits!r}")
        checked = []
        for i, tile in enumerate(tiles):
            check_tile_shape(f"tiles[{i}]", np.shape(tile))  # issue 15: before any work on it
            tile = check_image(f"tiles[{i}]", tile, channels=(3, 4), min_size=1)
            if tile.shape[2] == 3:
                tile = np.concatenate([tile, np.ones(tile.shape[:2] + (1,), np.float32)], axis=2)
            if tile.shape != checked[0].shape if checked else False:
                raise ValueError(f"tiles[{i}] has shape {tile.shape}, tiles[0] has {checked[0].shape}; "
                                 "all tiles must have the same shape")
            if np.any(tile < 0) or np.any(tile > 1):
                raise ValueError(f"tiles[{i}] values must be in [0, 1], got [{tile.min():g}, {tile.max():g}]")
            from .sampling import quantize

            checked.append(np.ascontiguousarray(quantize(tile, bits)))
        layers = [_as_layer(i, layer) for i, layer in enumerate(layers)]
        if not layers:
            raise ValueError("layers must hold at least one layer, got 0")
        if len(layers) > MAX_LAYERS:
            raise ValueError(f"layers must hold at most {MAX_LAYERS} layers, got {len(layers)}")
        for i, layer in enumerate(layers):
            if layer.tile >= len(checked):
                raise ValueError(f"layers[{i}].tile must be < {len(checked)} (the number of tiles), got {layer.tile}")
        self.tiles = checked
        self.layers = layers
        self.bits = bits
        self._levels = None
        self._stores = {}  # mipmaps -> texel store (texel_store); the tiles never change

    # ------------------------------------------------------------------ presets
    @classmethod
    def paper_preset(cls, tile=None, *, seed=0, blend="alpha", opacity=0.65, tile_size=512, bits=8):
        """The five-layer texture of the paper's Figure 1.

        Five layers of one 512 x 512 tile: the finest repeats every 1/64 km
        (15.625 m), the coarsest every 10 km, geometric steps between
        (a factor 640**(1/4) ~ 5.03). That is a virtual texture of 327680 x
        327680 texels at about 3 cm per texel, held in 1 MB. The layers are
        rotated by multiples of the golden angle and offset, so that their
        grids do not line up.

        Parameters
        ----------
        tile : ndarray, optional
            The RGBA tile; by default ``spectex.tiles.make_tile(tile_size, seed=seed)``.
        blend : {"alpha", "detail", "variance"}
            The blend of layers 2..5 (``"detail"`` gives detail texturing for comparison).
        opacity : float
            Opacity of layers 2..5. The emboss alpha averages 0.5; at full
            opacity the finest layer keeps only ``0.5**4`` of its weight and
            close-ups look flat. 0.65 (mean alpha 0.33) gives the five bands
            comparable weights (0.21 for the finest, 0.33 for the coarsest)
            and keeps the repetition peak of the finest tile at 0.10-0.18
            (seeds 0-4; 1.0 for plain tiling).
        """
        blend = check_choice("blend", blend, BLENDS)
        opacity = check_float("opacity", opacity, minimum=0.0, maximum=1.0)
        if tile is None:
            from .tiles import make_tile

            tile = make_tile(check_int("tile_size", tile_size, minimum=2), seed=seed)
        n = 5
        finest, coarsest = 1000.0 / 64.0, 10000.0
        ratio = (coarsest / finest) ** (1.0 / (n - 1))
        golden = 137.50776405003785
        layers = []
        for k in range(n):
            size = finest * ratio ** k if k < n - 1 else coarsest
            layers.append(Layer(size=size, tile=0,
                                offset=(round((0.382 * k % 1.0) * size, 6), round((0.618 * k % 1.0) * size, 6)),
                                rotation=round((golden * k) % 360.0, 6), blend=blend,
                                opacity=1.0 if k == 0 else opacity))
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
        from .sampling import gl_level_shapes

        per = sum(h * w for h, w in gl_level_shapes(*self.tile_shape)) * 4 * (1 if self.bits == 8 else 4)
        return len(self.tiles) * per

    @property
    def nbytes_as_image(self) -> int:
        """Bytes the same texture would take as one RGB8 image of virtual_size squared."""
        return self.virtual_size ** 2 * 3

    def mip_levels(self) -> list[list[np.ndarray]]:
        """Per tile, its mip chain (``spectex.tiles.mip_chain``), quantised to ``bits``.

        These exact arrays are what the CPU sampler holds and what the GL
        renderer uploads.
        """
        if self._levels is None:
            from .sampling import default_mip_chain, quantize

            self._levels = [[quantize(level, self.bits) for level in default_mip_chain(tile)]
                            for tile in self.tiles]
        return self._levels

    def mean_colours(self) -> np.ndarray:
        """Per tile, the mean RGB: its 1 x 1 mip level (the ``mu`` of the variance blend)."""
        return np.array([levels[-1][0, 0, :3] for levels in self.mip_levels()], dtype=np.float64)

    def __repr__(self):
        h, w = self.tile_shape
        sizes = ", ".join(f"{layer.size:g}" for layer in self.layers)
        return f"SpectralTexture({len(self.layers)} layers [{sizes}] m, tile {w}x{h}, bits={self.bits})"

    def __eq__(self, other):
        if not isinstance(other, SpectralTexture):
            return NotImplemented
        return (self.layers == other.layers and self.bits == other.bits and len(self.tiles) == len(other.tiles)
                and all(np.array_equal(a, b) for a, b in zip(self.tiles, other.tiles)))

    # ------------------------------------------------------------------- baking
    def texel_store(self, *, mipmaps=True):
        """All tiles' texels as one store, made once per texture and kept.

        Returns ``(data, stride, offsets, widths, heights)``: ``data`` is
        ``(N, 4)`` float32 RGBA; tile ``i``'s level ``d`` starts at row ``i *
        stride + offsets[d]`` and is ``heights[d] x widths[d]``, row-major.
        With ``mipmaps=False``, level 0 only.
        """
        key = bool(mipmaps)
        if key not in self._stores:
            from .sampling import MipTexture

            textures = [MipTexture(lv if mipmaps else lv[:1], bits=None) for lv in self.mip_levels()]
            tex = textures[0]
            data = np.ascontiguousarray(np.concatenate([t.data for t in textures]))
            self._stores[key] = (data, tex.data.shape[0], tex.offsets, tex.widths, tex.heights)
        return self._stores[key]

    def packed(self, *, filter="trilinear", anisotropy=1.0, mipmaps=True, enabled=None):
        """Kernel arguments: texel store, sampler state and layer tables (see ``render.cpu``)."""
        from .sampling import filter_code

        code = filter_code("filter", filter)
        state = (0, 0, code, 0 if code == 0 else 1,  # REPEAT both ways; NEAREST magnifies only under NEAREST
                 check_float("anisotropy", anisotropy, minimum=1.0, maximum=16.0), 0.0, -1000.0, 1000.0)
        n = len(self.layers)
        if enabled is None:
            enabled = [True] * n
        if len(enabled) != n:
            raise ValueError(f"enabled must have one flag per layer ({n}), got {len(enabled)}")
        tile_idx = np.array([layer.tile for layer in self.layers], dtype=np.int64)
        mats = np.stack([layer.matrix() for layer in self.layers]).astype(np.float64)
        blends = np.array([BLENDS.index(layer.blend) for layer in self.layers], dtype=np.int64)
        means = self.mean_colours()[tile_idx]
        opacity = np.array([layer.opacity for layer in self.layers], dtype=np.float64)
        on = np.array([bool(e) for e in enabled], dtype=np.bool_)
        return self.texel_store(mipmaps=mipmaps) + state + (tile_idx, mats, blends, means, opacity, on)

    def anchor_coords(self, x0: float, y0: float) -> np.ndarray:
        """Per layer, the tile coordinates (s, t) of world point (x0, y0), reduced modulo 2.

        Computed in float64 on the host, so that the kernels and shaders work
        with small coordinates relative to an anchor (the camera, a bake's
        corner) and keep their precision far from the world origin. Modulo 2
        is a period of both REPEAT and MIRRORED_REPEAT.
        """
        out = np.empty((len(self.layers), 2), dtype=np.float64)
        for k, layer in enumerate(self.layers):
            s, t = layer.coords(x0, y0)
            out[k] = (float(s) % 2.0, float(t) % 2.0)
        return out

    def bake(self, shape, *, origin=(0.0, 0.0), pixel_size=1.0, filter="trilinear", anisotropy=1.0,
             supersample=1, mipmaps=True):
        """Render a top-down orthographic view of a region, filtered for its footprint.

        Pixel ``(r, c)`` covers the world square with corner ``origin +
        (c, r) * pixel_size``; its sample is at the centre, ``x = origin[0] +
        (c + 0.5) * pixel_size``, ``y = origin[1] + (r + 0.5) * pixel_size``
        (rows go along +y, like a tile's rows: one layer of size ``tile_width
        * pixel_size`` with no offset or rotation bakes to the tile itself).
        Each layer is sampled with derivatives ``(pixel_size, 0)`` and ``(0,
        pixel_size)`` pushed through its map, so the mip-map level follows
        the footprint: a bake at a coarse ``pixel_size`` is the low-passed
        texture, not an aliased one.

        Parameters
        ----------
        shape : int or (int, int)
            ``(height, width)`` in pixels; at most ``MAX_BAKE_PIXELS``
            (times ``supersample**2``).
        origin : (float, float)
            World (x, y) of the top-left corner of pixel (0, 0), metres.
        pixel_size : float
            World size of one pixel, metres (> 0).
        filter : str
            Minification filter (``spectex.sampling.FILTERS`` or "trilinear").
        anisotropy : float
            Maximum anisotropy (1 = off; a top-down view is isotropic anyway).
        supersample : int
            ``n`` gives ``n x n`` box-filtered samples per pixel.
        mipmaps : bool
            With False, only level 0 is sampled (for aliasing comparisons).

        Returns
        -------
        ndarray, shape (height, width, 3), float32
            RGB in [0, 1].
        """
        n = check_int("supersample", supersample, minimum=1, maximum=16)
        h, w = check_shape("shape", shape, maximum_pixels=MAX_BAKE_PIXELS // (n * n))
        ox, oy = _pair("origin", origin)
        p = check_float("pixel_size", pixel_size, minimum=0.0, exclusive_minimum=True)
        anisotropy = check_float("anisotropy", anisotropy, minimum=1.0, maximum=16.0)
        args = self.packed(filter=filter, anisotropy=anisotropy, mipmaps=mipmaps)
        anchor = self.anchor_coords(ox, oy)
        out = np.empty((h, w, 3), dtype=np.float32)
        from .render._kernels import bake_kernel

        bake_kernel(*args, anchor, p, n, out)
        return out

    def bake_layers(self, shape, *, origin=(0.0, 0.0), pixel_size=1.0, filter="trilinear"):
        """Each layer's own filtered RGBA over the region of :meth:`bake`, shape (L, H, W, 4).

        For analysis: the alpha of layer ``k`` here is the ``a`` that layer
        blends with at each pixel.
        """
        h, w = check_shape("shape", shape, maximum_pixels=MAX_BAKE_PIXELS // max(1, len(self.layers)))
        ox, oy = _pair("origin", origin)
        p = check_float("pixel_size", pixel_size, minimum=0.0, exclusive_minimum=True)
        from .sampling import MipTexture, sample

        r, c = np.mgrid[0:h, 0:w]
        x = ox + (c + 0.5) * p
        y = oy + (r + 0.5) * p
        out = np.empty((len(self.layers), h, w, 4), dtype=np.float32)
        levels = self.mip_levels()
        for k, layer in enumerate(self.layers):
            tex = MipTexture(levels[layer.tile], min_filter=filter, bits=None)
            m = layer.matrix()
            s, t = layer.coords(x, y)
            out[k] = sample(tex, s, t, dsdx=m[0, 0] * p, dtdx=m[1, 0] * p, dsdy=m[0, 1] * p, dtdy=m[1, 1] * p)
        return out

    # ------------------------------------------------------------------- files
    def to_dict(self, tile_names) -> dict:
        return {
            "format": FORMAT,
            "version": FORMAT_VERSION,
            "bits": 8 if self.bits == 8 else 32,
            "tiles": list(tile_names),
            "layers": [{"tile": layer.tile, "size": layer.size, "offset": list(layer.offset),
                        "rotation": layer.rotation, "blend": layer.blend, "opacity": layer.opacity}
                       for layer in self.layers],
        }

    def save(self, path) -> Path:
        """Write the texture file (TOML) and its tile PNG(s) beside it, atomically.

        ``ground.toml`` gets ``ground.tile.png`` (or ``ground.tile0.png``,
        ``ground.tile1.png``, ... for several tiles): 8-bit RGBA PNGs for
        ``bits=8``, 16-bit for float tiles. The files replace earlier ones
        only when all are complete: if anything fails, the folder is left as
        it was.

        Returns
        -------
        Path
            The texture file.
        """
        from ._output import OutputSet
        from .io import check_output_path, write_image

        path = check_output_path("output", path, (".toml",))
        names = ([f"{path.stem}.tile.png"] if len(self.tiles) == 1
                 else [f"{path.stem}.tile{i}.png" for i in range(len(self.tiles))])
        text = dumps_toml(self.to_dict(names))
        # issue 15: the tiles and the texture file replace the earlier ones together, or not at all
        with OutputSet(path.parent, names + [path.name], create=False) as stage:
            for name, tile in zip(names, self.tiles):
                write_image(stage / name, tile, bit_depth=8 if self.bits == 8 else 16)
            (stage / path.name).write_text(text, encoding="utf-8")
        return path

    @classmethod
    def load(cls, path) -> "SpectralTexture":
        """Read a texture file written by :meth:`save` (or by hand).

        Every field is checked; an error names the field and the file.
        """
        from ._output import check_input_file, note_input

        path = check_input_file("texture", path)
        note_input(path)  # issue 15: no output of this command may replace it
        try:
            text = path.read_text(encoding="utf-8")
            doc = tomllib.loads(text)
        except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
            raise ValueError(f"texture file '{path}' is not valid TOML: {exc}") from None
        try:
            return cls.from_dict(doc, base=path.parent)
        except (ValueError, TypeError) as exc:
            raise ValueError(f"texture file '{path}': {exc}") from None

    @classmethod
    def from_dict(cls, doc: dict, *, base=".") -> "SpectralTexture":
        """Build from the parsed file contents; tile paths are relative to ``base``."""
        if not isinstance(doc, dict):
            raise TypeError(f"texture must be a table, got {type(doc).__name__}")
        known = {"format", "version", "bits", "tiles", "layers"}
        extra = sorted(set(doc) - known)
        if extra:
            raise ValueError(f"unknown field {extra[0]!r} (known: {', '.join(sorted(known))})")
        for key in ("format", "version", "tiles", "layers"):
            if key not in doc:
                raise ValueError(f"missing field '{key}'")
        if doc["format"] != FORMAT:
            raise ValueError(f"field 'format' must be {FORMAT!r}, got {doc['format']!r}")
        version = doc["version"]
        if not isinstance(version, int) or isinstance(version, bool):
            raise ValueError(f"field 'version' must be an integer, got {version!r}")
        if version != FORMAT_VERSION:
            raise ValueError(f"field 'version' is {version}; this spectex reads version {FORMAT_VERSION}")
        bits = doc.get("bits", 8)
        if bits not in (8, 32) or isinstance(bits, bool):
            raise ValueError(f"field 'bits' must be 8 or 32, got {bits!r}")
        names = doc["tiles"]
        if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
            raise ValueError(f"field 'tiles' must be a non-empty list of file names, got {names!r}")
        from .io import read_image

        tiles = []
        for i, name in enumerate(names):
            tile_path = Path(base) / check_relative_name(f"field 'tiles[{i}]'", name)  # issue 15
            try:
                tile = read_image(tile_path, name=f"tiles[{i}]")
            except ValueError as exc:
                raise ValueError(f"field 'tiles[{i}]': {exc}") from None
            if tile.ndim == 2:
                tile = np.repeat(tile[:, :, None], 3, axis=2)
            elif tile.shape[2] == 2:
                tile = np.concatenate([np.repeat(tile[:, :, :1], 3, axis=2), tile[:, :, 1:]], axis=2)
            tiles.append(tile)
        raw_layers = doc["layers"]
        if not isinstance(raw_layers, list) or not raw_layers:
            raise ValueError("field 'layers' must be a non-empty array of tables ([[layers]])")
        layers = []
        allowed = {"tile", "size", "offset", "rotation", "blend", "opacity"}
        for i, entry in enumerate(raw_layers):
            if not isinstance(entry, dict):
                raise ValueError(f"field 'layers[{i}]' must be a table, got {entry!r}")
            extra = sorted(set(entry) - allowed)
            if extra:
                raise ValueError(f"unknown field 'layers[{i}].{extra[0]}' (known: {', '.join(sorted(allowed))})")
            if "size" not in entry:
                raise ValueError(f"missing field 'layers[{i}].size'")
            for key in ("size", "rotation", "opacity"):
                if key in entry and (isinstance(entry[key], bool) or not isinstance(entry[key], numbers.Real)):
                    raise ValueError(f"field 'layers[{i}].{key}' must be a number, got {entry[key]!r}")
            try:
                layers.append(Layer(**entry))
            except (ValueError, TypeError) as exc:
                raise ValueError(f"field 'layers[{i}].{exc}") from None
        try:
            return cls(tiles, layers, bits=8 if bits == 8 else None)
        except (ValueError, TypeError) as exc:
            msg = str(exc)
            raise ValueError(msg if msg.startswith("layers[") else f"field {msg}") from None


def _pair(name, value) -> tuple[float, float]:
    if not isinstance(value, (tuple, list, np.ndarray)) or len(value) != 2:
        raise ValueError(f"{name} must be a pair (x, y) of numbers, got {value!r}")
    return check_float(f"{name}[0]", value[0]), check_float(f"{name}[1]", value[1])


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        text = repr(float(value))
        return text if any(ch in text for ch in ".en") else text + ".0"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    raise TypeError(f"cannot write {type(value).__name__} to TOML")


def dumps_toml(doc: dict) -> str:
    """The texture document as TOML (scalars, arrays, and one array of tables, ``layers``)."""
    lines = ["# spectex spectral texture: layers of one tile at different scales.",
             "# Layers are drawn in order (finest first); each later one is blended over the",
             "# ones before by its 'blend': alpha | detail | variance, with alpha = opacity * tile alpha.",
             "# size and offset are metres, rotation degrees counter-clockwise. Tiles are relative",
             "# to this file."]
    tables = []
    for key, value in doc.items():
        if isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            tables.append((key, value))
        else:
            lines.append(f"{key} = {_toml_value(value)}")
    for key, entries in tables:
        for entry in entries:
            lines.append("")
            lines.append(f"[[{key}]]")
            for k, v in entry.items():
                lines.append(f"{k} = {_toml_value(v)}")
    return "\n".join(lines) + "\n"
