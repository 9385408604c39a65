"""Large photos of large grain (issue 22): the fit's crop of a photo over 512 pixels, before and after it reads
the photo's grain (``spectex.fitting._core.MIN_TILE_GRAINS``), and its tile at the photo's full resolution.

Run from the repository root::

    python benchmarks/bench_large_photos.py                       # the table
    python benchmarks/bench_large_photos.py --grid docs/images/fit_large.jpg

Each photo of :mod:`exemplars` (512 pixels) is magnified ``--zooms`` times (a cubic spline, then a grain of
1.5 % white noise, so that the large photo has pixel-level detail of its own), as a user's photo taken closer or
with more pixels; and ``--native`` photos are drawn at the large size with their features as many times larger
(``exemplars.paving``'s cobbles, ``ripples``' crests), so that their grain is real detail at every pixel, as a
photo's is. Fitted three ways, the photo said to be 1.5 m across: *before* (a 512-pixel crop at full
resolution: ``_switches.grain_blind``), *analysed* (resampled for its grain, the tile the fit analysed:
``tile_size=512``) and *after* (the default: that tile at the photo's full resolution, its own detail put
back, ``fitting/_full.py``), then baked 1024 x 1024 at two views, both a little off the texel grid (origin
(0.013, 0.029) m: a view whose pixels fall on texel centres reads a tile exactly, which no camera does):

* ``far``: at the magnification times the photo's pixel size, the view of the whole photo at 512 pixels,
  against the 512-pixel photo it was made from (a drawn one area-averaged to 512: what the large photo shows at
  that scale): structural
  distance / floor over the bake's four 512-pixel windows (mean);
* ``close``: at the photo's own pixel size, against the large photo's central 1024 x 1024 at full
  resolution: the same over four windows. A photo magnified by a spline has no detail of its own beyond the
  noise, so this understates what a real photo's finest pixels lose when resampled.

Printed per photo: the factor each way (``exemplar_scale``), the tile's texels, the two views' ratios,
``repeat_peak`` of the far view and the fit's seconds (the CPU named; the three one after the other in one
process). The picture: per photo at the largest magnification, the far view before and after and the 512-pixel
photo, then a 288-pixel corner of the close view analysed, after, and of the large photo.
"""

from __future__ import annotations

import argparse
import sys
import time
from contextlib import nullcontext
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import exemplars  # noqa: E402
from _machine import cpu_name  # noqa: E402
from _pictures import panel, save_grid  # noqa: E402
from _switches import grain_blind  # noqa: E402

PHOTO_SIZE = 1.5
ORIGIN = (0.013, 0.029)
PANEL = 288  # the picture's panels, pixels
WAYS = {"before": {}, "analysed": {"tile_size": 512}, "after": {}}


def _large(photo, zoom, seed=0):
    from scipy import ndimage

    rgb = photo if photo.ndim == 3 else np.repeat(photo[:, :, None], 3, axis=2)
    # (pixel areas aligned and the edges reflected: the default's zeros beyond the edge left a dark last column,
    # which the fit took for a frame)
    big = ndimage.zoom(rgb, (zoom, zoom, 1), order=3, mode="reflect", grid_mode=True)
    big = big + 0.015 * np.random.default_rng(seed).standard_normal(big.shape)
    return np.clip(big, 0.0, 1.0).astype(np.float32)


def _native(name, zoom):
    """A photo of :mod:`exemplars` drawn at ``zoom`` times its side with its features ``zoom`` times as large: a
    large photo with real detail at every pixel (paving's grain, the ripples' sand), not magnified."""
    side = int(512 * zoom)
    if name == "paving":
        return exemplars.paving(side, cell=44.0 * zoom)
    if name == "ripples":
        return exemplars.ripples(side, wavelength=38.0 * zoom, scale=zoom)
    raise ValueError(f"no native large photo of {name!r}")


def _small(big, zoom):
    """The large photo area-averaged by ``zoom`` to 512 pixels: what it shows at the far view's scale."""
    from spectex.fitting._core import _resampled

    return _resampled(big, 512, 512)


def _views(result, photo_px, zoom):
    from spectex.bake._block import bake_window

    return [np.asarray(bake_window(result.texture, (0, 1024, 0, 1024), pixel_size=photo_px * z,
                                   origin=ORIGIN))[:, :, :3] for z in (zoom, 1.0)]


def _ratios(view, prepared, reference):
    from spectex import metrics

    return float(np.mean([metrics.structural_distance(view[y:y + 512, x:x + 512], reference, prepared=prepared).ratio
                          for y in (0, 512) for x in (0, 512)]))


def main(argv=None):
    from spectex import metrics
    from spectex.fitting import exemplar_scale, fit_result

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--photos", default="gravel,grass,paving,tissue,moon,pebbles")
    parser.add_argument("--zooms", default="2,4")
    parser.add_argument("--native", default="paving,ripples",
                        help="photos drawn at the large size (real detail at every pixel), '' for none")
    parser.add_argument("--grid", type=Path, default=None)
    args = parser.parse_args(argv)
    print(f"CPU: {cpu_name()}; photos magnified, said to be {PHOTO_SIZE} m across; far: the view of the whole photo "
          "against the 512-pixel photo; close: at the photo's pixel size against its central 1024; s = structural "
          "distance / floor (mean of 4 windows); rp: repeat_peak of the far view", flush=True)
    cells = []
    cases = [(name, False) for name in args.photos.split(",") if name] + \
        [(name, True) for name in args.native.split(",") if name]
    for name, native in cases:
        for zoom in (float(z) for z in args.zooms.split(",")):
            if native:
                big = _native(name, zoom)
                small = _small(big, zoom)
            else:
                small = exemplars.load(name)
                small = small if small.ndim == 3 else np.repeat(small[:, :, None], 3, axis=2)
                big = _large(small, zoom)
            far_ref = metrics.reference_statistics(small)
            label = f"{name}{' (drawn)' if native else ''}"
            c = (big.shape[0] - 1024) // 2
            close = big[c:c + 1024, c:c + 1024]
            close_ref = metrics.reference_statistics(close)
            photo_px = PHOTO_SIZE / big.shape[1]
            fars, nears = {}, {}
            for way, options in WAYS.items():
                with grain_blind() if way == "before" else nullcontext():
                    factor = exemplar_scale(big)
                    t0 = time.perf_counter()
                    result = fit_result(big, photo_size=PHOTO_SIZE, **options)
                    seconds = time.perf_counter() - t0
                far, near = _views(result, photo_px, zoom)
                fars[way], nears[way] = far, near
                print(f"{label:16s} x{zoom:g} {way:8s} factor {factor:5.3g} tile {result.texture.tile_shape[0]:4d}  "
                      f"far s {_ratios(far, far_ref, small):5.2f}  close s {_ratios(near, close_ref, close):5.2f}  "
                      f"rp far {metrics.repeat_peak(far):5.3f}  {seconds:4.1f} s", flush=True)
            row = [panel(fars["before"], f"{label} x{zoom:g} far, before", PANEL),
                   panel(fars["after"], "far, after", PANEL), panel(small, "the photo", PANEL),
                   panel(nears["analysed"], "close, analysed tile", PANEL),
                   panel(nears["after"], "close, after", PANEL), panel(close, "the large photo", PANEL)]
            if zoom == max(float(z) for z in args.zooms.split(",")):
                cells.append(row)
    if args.grid is not None:
        save_grid(cells, args.grid)
        print(f"wrote {args.grid}")


if __name__ == "__main__":
    main()
