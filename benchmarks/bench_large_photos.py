"""Large photos of large grain (issue 22): the fit's crop of a photo over 512 pixels, before and after it reads
the photo's grain (``spectex.fitting._core.MIN_TILE_GRAINS``).

Run from the repository root::

    python benchmarks/bench_large_photos.py                       # the table
    python benchmarks/bench_large_photos.py --grid docs/images/fit_large.jpg

Each photo of :mod:`exemplars` (512 pixels) is magnified ``--zooms`` times (a cubic spline, then a grain of
1.5 % white noise, so that the large photo has pixel-level detail of its own), as a user's photo taken closer or
with more pixels. Fitted *before* (a 512-pixel crop at full resolution: ``_switches.grain_blind``) and
*after* (the default), the photo said to be 1.5 m across, then baked 1024 x 1024 at two views:

* ``far``: at the magnification times the photo's pixel size, the view of the whole photo at 512 pixels,
  against the 512-pixel photo it was made from (what the large photo shows at that scale): structural
  distance / floor over the bake's four 512-pixel windows (mean);
* ``close``: at the photo's own pixel size, against the large photo's central 1024 x 1024 at full
  resolution: the same over four windows. A photo magnified by a spline has no detail of its own beyond the
  noise, so this understates what a real photo's finest pixels lose when resampled.

Printed per photo: the factor each way (``exemplar_scale``), the two views' ratios, ``repeat_peak`` of the far
view and the fit's seconds (the CPU named; before and after one after the other in one process). The
picture: per photo at the largest magnification, the far view before, after, and the 512-pixel photo, a
384-pixel corner of each.
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


def _large(photo, zoom, seed=0):
    from scipy import ndimage

    rgb = photo if photo.ndim == 3 else np.repeat(photo[:, :, None], 3, axis=2)
    # (pixel areas aligned and the edges reflected: the default's zeros beyond the edge left a dark last column,
    # which the fit took for a frame)
    big = ndimage.zoom(rgb, (zoom, zoom, 1), order=3, mode="reflect", grid_mode=True)
    big = big + 0.015 * np.random.default_rng(seed).standard_normal(big.shape)
    return np.clip(big, 0.0, 1.0).astype(np.float32)


def _views(result, photo_px, zoom):
    from spectex.bake._block import bake_window

    return [np.asarray(bake_window(result.texture, (0, 1024, 0, 1024), pixel_size=photo_px * z,
                                   origin=(0.0, 0.0)))[:, :, :3] for z in (zoom, 1.0)]


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
    parser.add_argument("--grid", type=Path, default=None)
    args = parser.parse_args(argv)
    print(f"CPU: {cpu_name()}; photos magnified, said to be {PHOTO_SIZE} m across; far: the view of the whole photo "
          "against the 512-pixel photo; close: at the photo's pixel size against its central 1024; s = structural "
          "distance / floor (mean of 4 windows); rp: repeat_peak of the far view", flush=True)
    cells = []
    for name in args.photos.split(","):
        small = exemplars.load(name)
        small = small if small.ndim == 3 else np.repeat(small[:, :, None], 3, axis=2)
        far_ref = metrics.reference_statistics(small)
        for zoom in (float(z) for z in args.zooms.split(",")):
            big = _large(small, zoom)
            c = (big.shape[0] - 1024) // 2
            close = big[c:c + 1024, c:c + 1024]
            close_ref = metrics.reference_statistics(close)
            photo_px = PHOTO_SIZE / big.shape[1]
            fars = {}
            for way in ("before", "after"):
                with grain_blind() if way == "before" else nullcontext():
                    factor = exemplar_scale(big)
                    t0 = time.perf_counter()
                    result = fit_result(big, photo_size=PHOTO_SIZE)
                    seconds = time.perf_counter() - t0
                far, near = _views(result, photo_px, zoom)
                fars[way] = far
                print(f"{name:8s} x{zoom:g} {way:6s} factor {factor:5.3g}  far s {_ratios(far, far_ref, small):5.2f}  "
                      f"close s {_ratios(near, close_ref, close):5.2f}  rp far {metrics.repeat_peak(far):5.3f}  "
                      f"{seconds:4.1f} s", flush=True)
            row = [panel(fars["before"], f"{name} x{zoom:g} before", 384),
                   panel(fars["after"], "after", 384), panel(small, "the photo", 384)]
            if zoom == max(float(z) for z in args.zooms.split(",")):
                cells.append(row)
    if args.grid is not None:
        save_grid(cells, args.grid)
        print(f"wrote {args.grid}")


if __name__ == "__main__":
    main()
