"""The CPU reference renderer: the ground plane through the shading core's kernels.

Same camera, sky and haze as the GL renderer (``docs/sampling.md``,
section 7); each pixel's texture footprint comes from the exact derivatives
of the ground point with respect to the screen position, so the mip-map
level is the one the specification's formula gives for that footprint.
Supersampling (``n x n`` box-filtered samples per pixel) makes the
reference for the aliasing tests. The kernels are ``spectex.shading.view``'s.
"""

from __future__ import annotations

import numpy as np

from .._validate import check_float, check_int, check_length, check_shape
from ..shading.camera import check_size, view_params
from ..shading.constants import DEFAULT_ANISOTROPY

__all__ = ["MAX_BAKE_PIXELS", "bake", "bake_layers", "render_cpu"]

#: Largest bake, in pixels (times supersample squared): 64 Mpx, about 1 GiB of float32 work arrays.
MAX_BAKE_PIXELS = 1 << 26


def render_cpu(texture, camera, shape, *, filter="trilinear", anisotropy=DEFAULT_ANISOTROPY,
               supersample=1, atmosphere=None, enabled=None):
    """Render ``texture`` on the ground plane as seen by ``camera``.

    Parameters
    ----------
    texture : SpectralTexture
    camera : Camera
    shape : (int, int)
        ``(height, width)`` of the picture, within ``MAX_RENDER_PIXELS``.
    filter : str
        Minification filter (``spectex.sampling.FILTERS``, or "trilinear");
        ``"linear"`` or ``"nearest"`` sample level 0 only (no mip-mapping).
    anisotropy : float
        Maximum anisotropy, 1 (off) to 16; default ``DEFAULT_ANISOTROPY``
        (8, see :data:`spectex.render.DEFAULT_ANISOTROPY`). 1 runs the fast
        isotropic kernel, about 10x faster on the CPU.
    supersample : int
        ``n x n`` samples per pixel, box-filtered (each with its own, ``n``
        times smaller, footprint).
    atmosphere : Atmosphere, optional
    enabled : sequence of bool, optional
        Per layer, whether it is drawn (the viewer's toggles).

    Returns
    -------
    ndarray, shape (H, W, 3), float32
        RGB in [0, 1], row 0 at the top.
    """
    from ..shading.tables import anchor_coords, pack
    from ..shading.view import render_kernel, render_kernel_fast, row_order

    _check_texture(texture)
    h, w = check_size(shape, supersample)
    view = view_params(camera, (h, w), atmosphere=atmosphere, supersample=supersample)
    tables = pack(texture, filter=filter, anisotropy=anisotropy, enabled=enabled)
    anchor = anchor_coords(tables, *camera.position[:2])
    out = np.empty((h, w, 3), dtype=np.float32)
    kernel = render_kernel_fast if tables.fast else render_kernel
    kernel(tables, anchor, view, row_order(h), out)
    return out


def _check_texture(texture) -> None:
    from ..texture import SpectralTexture

    if not isinstance(texture, SpectralTexture):
        raise TypeError(f"texture must be a SpectralTexture, got {type(texture).__name__}")


def _pair(name, value) -> tuple[float, float]:
    if not isinstance(value, (tuple, list, np.ndarray)) or len(value) != 2:
        raise ValueError(f"{name} must be a pair (x, y) of numbers, got {value!r}")
    return check_float(f"{name}[0]", value[0]), check_float(f"{name}[1]", value[1])


def bake(texture, shape, *, origin=(0.0, 0.0), pixel_size=1.0, filter="trilinear", anisotropy=1.0,
         supersample=1, mipmaps=True, start=(0, 0)) -> np.ndarray:
    """Render a top-down orthographic view of a region of ``texture``, filtered for its footprint.

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
    texture : SpectralTexture
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
    start : (int, int)
        Bake the block of the region's pixel grid whose first pixel is
        ``(row, column) = start``: pixel ``(r, c)`` of the result is pixel
        ``(start[0] + r, start[1] + c)`` of the grid anchored at
        ``origin``, with the same bits as in a bake of the whole region
        (for baking a large region in blocks).

    Returns
    -------
    ndarray, shape (height, width, 3), float32
        RGB in [0, 1].
    """
    _check_texture(texture)
    n = check_int("supersample", supersample, minimum=1, maximum=16)
    h, w = check_shape("shape", shape, maximum_pixels=MAX_BAKE_PIXELS // (n * n))
    ox, oy = _pair("origin", origin)
    p = check_length("pixel_size", pixel_size)
    if not isinstance(start, (tuple, list)) or len(start) != 2:
        raise ValueError(f"start must be a pair (row, column) of integers, got {start!r}")
    row0 = check_int("start[0]", start[0], minimum=0)
    col0 = check_int("start[1]", start[1], minimum=0)
    from ..shading.tables import anchor_coords, pack
    from ..shading.view import bake_kernel

    tables = pack(texture, filter=filter, anisotropy=anisotropy, mipmaps=mipmaps)
    out = np.empty((h, w, 3), dtype=np.float32)
    bake_kernel(tables, anchor_coords(tables, ox, oy), p, n, row0, col0, out)
    return out


def bake_layers(texture, shape, *, origin=(0.0, 0.0), pixel_size=1.0, filter="trilinear") -> np.ndarray:
    """Each layer's own filtered RGBA over the region of :func:`bake`, shape (L, H, W, 4) float32.

    For analysis: the alpha of layer ``k`` here is the ``a`` that layer
    blends with at each pixel.
    """
    _check_texture(texture)
    h, w = check_shape("shape", shape, maximum_pixels=MAX_BAKE_PIXELS // max(1, len(texture.layers)))
    ox, oy = _pair("origin", origin)
    p = check_length("pixel_size", pixel_size)
    from ..shading.resources import mip_levels, stochastic_tables
    from ..shading.sampler import MipTexture, sample

    r, c = np.mgrid[0:h, 0:w]
    x = ox + (c + 0.5) * p
    y = oy + (r + 0.5) * p
    out = np.empty((len(texture.layers), h, w, 4), dtype=np.float32)
    levels = mip_levels(texture)
    for k, layer in enumerate(texture.layers):
        m = layer.matrix()
        s, t = layer.coords(x, y)
        derivs = dict(dsdx=m[0, 0] * p, dtdx=m[1, 0] * p, dsdy=m[0, 1] * p, dtdy=m[1, 1] * p)
        if layer.tiling == "stochastic":
            from ..shading.stochastic import sample_stochastic

            out[k] = sample_stochastic(stochastic_tables(texture)[layer.tile], s, t, patch=layer.patch,
                                       seed=layer.seed, snap=layer.snap, filter=filter, **derivs)
        else:
            out[k] = sample(MipTexture(levels[layer.tile], min_filter=filter, bits=None), s, t, **derivs)
    return out
