"""The CPU reference renderer: the ground plane through the reference sampler.

Same camera, sky and haze as the GL renderer (``docs/sampling.md``); each
pixel's texture footprint comes from the exact derivatives of the ground
point with respect to the screen position, so the mip-map level is the one
the specification's formula gives for that footprint. Supersampling
(``n x n`` box-filtered samples per pixel) makes the reference for the
aliasing tests.
"""

from __future__ import annotations

import numpy as np

from .._validate import check_float
from .camera import Atmosphere, Camera, check_size

__all__ = ["render_cpu"]


def render_cpu(texture, camera, size, *, filter="trilinear", anisotropy=1.0, supersample=1,
               atmosphere=None, enabled=None):
    """Render ``texture`` on the ground plane as seen by ``camera``.

    Parameters
    ----------
    texture : SpectralTexture
    camera : Camera
    size : (int, int)
        ``(height, width)`` of the picture, within ``MAX_RENDER_PIXELS``.
    filter : str
        Minification filter (``spectex.sampling.FILTERS``, or "trilinear");
        ``"linear"`` or ``"nearest"`` sample level 0 only (no mip-mapping).
    anisotropy : float
        Maximum anisotropy, 1 (off) to 16.
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
    from ..texture import SpectralTexture
    from ._kernels import render_kernel, render_kernel_fast, row_order

    if not isinstance(texture, SpectralTexture):
        raise TypeError(f"texture must be a SpectralTexture, got {type(texture).__name__}")
    if not isinstance(camera, Camera):
        raise TypeError(f"camera must be a Camera, got {type(camera).__name__}")
    h, w = check_size(size, supersample)
    anisotropy = check_float("anisotropy", anisotropy, minimum=1.0, maximum=16.0)
    atmosphere = Atmosphere() if atmosphere is None else atmosphere
    args = texture.packed(filter=filter, anisotropy=anisotropy, enabled=enabled)
    x, y, z = camera.position
    anchor = texture.anchor_coords(x, y)
    fwd, right, up = camera.basis()
    tan_x, tan_y = camera.tangents(h, w)
    ddx, ddy = camera.ray_steps(h, w)
    out = np.empty((h, w, 3), dtype=np.float32)
    fast = fast_path_args(texture, args)
    if fast is not None:
        render_kernel_fast(*fast, anchor, z, fwd, right, up, tan_x, tan_y, ddx, ddy, np.array(atmosphere.horizon),
                           np.array(atmosphere.zenith), atmosphere.haze_distance, atmosphere.far,
                           int(supersample), row_order(h), out)
        return out
    render_kernel(*args, anchor, z, fwd, right, up, tan_x, tan_y, ddx, ddy, np.array(atmosphere.horizon),
                  np.array(atmosphere.zenith), atmosphere.haze_distance, atmosphere.far, int(supersample),
                  row_order(h), out)
    return out


def fast_path_args(texture, args):
    """The fast kernels' arguments for ``texture.packed(...)`` output, or None.

    The fast path (``_kernels.render_kernel_fast``) covers REPEAT wrapping,
    square power-of-two tiles, trilinear filtering without anisotropy, and
    OpenGL's default bias and lod clamps; it gives the general path's numbers
    to float rounding (``tests/test_render.py``). Anything else returns None.
    """
    (data, stride, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter, max_aniso, bias,
     min_lod, max_lod, tile_idx, mats, blends, means, opacity, on) = args
    size0 = int(widths[0])
    if not (wrap_s == 0 and wrap_t == 0 and min_filter == 5 and mag_filter == 1 and max_aniso == 1.0
            and bias == 0.0 and min_lod <= -1000.0 and max_lod >= 1000.0 and int(heights[0]) == size0
            and size0 & (size0 - 1) == 0 and widths.shape[0] == size0.bit_length()):
        return None
    lod_off = np.array([np.log2(size0 / layer.size) for layer in texture.layers], dtype=np.float64)
    return (data.reshape(-1), stride, offsets, size0, tile_idx, mats, blends, means, opacity, on.astype(np.int64),
            lod_off)
