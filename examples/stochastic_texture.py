"""Periodic against stochastic layers: the paper's texture in the same view, with and without repeats.

The paper's five layers of one tile (Berger's Figure 1) seen straight down
from 120 m, where the finest layer's 15.625 m tile repeats about 9 times
across the picture (at about 32 pixels per tile). Left: every layer periodic, the paper's method; right: every
layer stochastic (``SpectralTexture.paper_preset(tiling="stochastic")``:
histogram-preserving tiling and blending of the same tile, Heitz and Neyret
2018), which never repeats. Top: the views; bottom: the autocorrelation of
their fine detail (the luma minus its Gaussian blur of 3 pixels; lag 0 in
the centre), where the periodic layers' repeats show as a lattice of bright
points and the stochastic layers show one point only. ``main`` also prints
``spectex.metrics.repeat_peak`` of the two views (the highest of those
autocorrelations away from lag 0): 0.46 periodic against 0.03 stochastic
(<= 0.1 does not repeat).

Run: ``python examples/stochastic_texture.py [OUT] [--tile N] [--width W]``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from spectex import SpectralTexture, io
from spectex.render import Camera, render
from spectex.tiles import make_tile

try:
    from _gallery import parser
except ImportError:  # run as a module from elsewhere
    from examples._gallery import parser

TEST_ARGS = ["--tile", "32", "--width", "96"]

#: The view both textures are seen in: straight down from 120 m.
CAMERA = Camera((0.0, 0.0, 120.0), yaw=20.0, pitch=-90.0, fov=60.0)
#: Gap between the two views, pixels (mid grey).
GAP = 8


def textures(tile_size: int = 512, seed: int = 0):
    """The paper preset on one tile, periodic and stochastic: ``{"periodic": ..., "stochastic": ...}``."""
    tile = make_tile(tile_size, rng=seed)
    # the paper's own composite (alpha blend, no detail layer), the picture and numbers the README shows
    return {tiling: SpectralTexture.paper_preset(tile, tiling=tiling, blend="alpha", detail=False)
            for tiling in ("periodic", "stochastic")}


def autocorrelation(view: np.ndarray, sigma: float = 3.0) -> np.ndarray:
    """The circular autocorrelation of the view's fine detail, lag 0 in the centre: ``(H, W, 3)`` in [0, 1].

    The fine detail is the luma minus its Gaussian blur of ``sigma`` pixels,
    as in :func:`spectex.metrics.repeat_peak`; the autocorrelation is divided
    by its value at lag 0 (white) and clipped at 0 (black). A repeat shows as
    a lattice of bright points, one per period.
    """
    from scipy import ndimage

    from spectex.color import luma

    lum = luma(view).astype(np.float64)
    detail = lum - ndimage.gaussian_filter(lum, sigma, mode="wrap")
    detail -= detail.mean()
    spec = np.fft.rfft2(detail)
    acf = np.fft.irfft2(spec.real ** 2 + spec.imag ** 2, s=lum.shape)
    acf = np.fft.fftshift(acf / max(float(acf[0, 0]), 1e-300))
    return np.repeat(np.clip(acf, 0.0, 1.0)[..., None], 3, axis=2).astype(np.float32)


def picture(tile_size: int = 512, width: int = 480, seed: int = 0) -> np.ndarray:
    """Views on top, their fine detail's autocorrelation below, periodic left, stochastic right:
    ``(2 H, 2 width + GAP, 3)`` float32 with ``H = width * 9 // 16``."""
    h = width * 9 // 16
    views = [render(tex, CAMERA, (h, width)).image for tex in textures(tile_size, seed).values()]
    gap = np.full((h, GAP, 3), 0.5, dtype=np.float32)
    top = np.concatenate([views[0], gap, views[1]], axis=1)
    bottom = np.concatenate([autocorrelation(views[0]), gap, autocorrelation(views[1])], axis=1)
    return np.concatenate([top, bottom], axis=0)


def repeat_peaks(tile_size: int = 512, width: int = 480, seed: int = 0) -> dict:
    """``spectex.metrics.repeat_peak`` of the two views: ``{"periodic": ..., "stochastic": ...}``."""
    from spectex.metrics import repeat_peak

    h = width * 9 // 16
    return {tiling: repeat_peak(render(tex, CAMERA, (h, width)).image, min_lag=min(24, h // 2))
            for tiling, tex in textures(tile_size, seed).items()}


def main(argv=None) -> Path:
    p = parser(__doc__, "stochastic_texture.jpg")
    p.add_argument("--tile", type=int, default=512, help="tile side in texels (default 512)")
    p.add_argument("--width", type=int, default=480, help="width of each view in pixels (default 480)")
    args = p.parse_args(argv)
    return io.write_image(args.out, picture(args.tile, args.width))


if __name__ == "__main__":
    print(main())
    print("repeat_peak of the views:", ", ".join(f"{k} {v:.3f}" for k, v in repeat_peaks().items()))
