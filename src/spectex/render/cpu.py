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

from ..shading.camera import check_size, view_params
from ._defaults import DEFAULT_ANISOTROPY

__all__ = ["render_cpu"]


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
    from ..shading.tables import pack
    from ..shading.view import render_kernel, render_kernel_fast, row_order
    from ..texture import SpectralTexture

    if not isinstance(texture, SpectralTexture):
        raise TypeError(f"texture must be a SpectralTexture, got {type(texture).__name__}")
    h, w = check_size(shape, supersample)
    view = view_params(camera, (h, w), atmosphere=atmosphere, supersample=supersample)
    tables = pack(texture, filter=filter, anisotropy=anisotropy, enabled=enabled)
    anchor = texture.anchor_coords(*camera.position[:2])
    out = np.empty((h, w, 3), dtype=np.float32)
    kernel = render_kernel_fast if tables.fast else render_kernel
    kernel(tables, anchor, view, row_order(h), out)
    return out
