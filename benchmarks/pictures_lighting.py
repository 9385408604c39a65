"""Pictures and numbers of a photo's uneven lighting evened out by the fit (issue 22): ``docs/images/fit_lighting.jpg``.

Photos lit unevenly (``exemplars.py``): scikit-image's gravel and the procedural paving under a light
from one side with a vignette (``exemplars.lit``, a drift of about 14 % RMS), and scikit-image's
``page``, a scanned page that the scanner lit unevenly (real light; text is no ground texture, but
its pieces show the blotches the clearest). Per photo, the fit made twice, ``keep_lighting=True``
(the fit before the lighting was evened out) and the default, and printed: the fit's seconds, the
lighting found and :func:`spectex.metrics.lighting_blotches` of a bake of 8 times the photo's area
at its pixel size (what ``spectex fit`` reports on). The picture: per photo, the photo and the two
bakes, side by side (each bake shown at the photo's height).

Run from the repository root::

    python benchmarks/pictures_lighting.py [--grid docs/images/fit_lighting.jpg]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import exemplars  # noqa: E402
from _machine import cpu_name  # noqa: E402
from pictures_one_off import picture, save_grid  # noqa: E402


def photos():
    return {name: exemplars.load(name) for name in ("gravel_lit", "paving_lit", "page")}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", help="write the picture here (JPEG)")
    args = ap.parse_args(argv)
    from spectex.fitting import fit_result
    from spectex.metrics import lighting_blotches
    from spectex.render import bake

    print(f"CPU: {cpu_name()}")
    rows = []
    for name, photo in photos().items():
        h, w = photo.shape[:2]
        scale = np.sqrt(8.0)
        shape = (int(round(scale * h)), int(round(scale * w)))  # 8 times the photo's area, its aspect
        views = []
        for keep in (True, False):
            t0 = time.perf_counter()
            result = fit_result(photo, rng=0, keep_lighting=keep)
            seconds = time.perf_counter() - t0
            view = bake(result.texture, shape, pixel_size=result.pixel_size)
            seen = lighting_blotches(view, photo)
            way = "keep_lighting=True" if keep else "default"
            light = result.params["lighting"]
            print(f"{name:10s} {way:18s} fit {seconds:5.2f} s; photo's lighting {100 * seen.lighting:4.1f}% RMS "
                  f"({'evened out' if light else 'kept'}); 8x its area: low-frequency contrast "
                  f"{seen.view_contrast:.3f} (photo's own {seen.photo_contrast:.3f}), excess {seen.excess:.3f} "
                  f"{'within' if seen.within else 'BLOTCHES'} (threshold {seen.threshold:g})")
            views.append(view)
        height = 256 if h >= w else 160
        rows.append([picture(photo, f"{name}: photo", height),
                     picture(views[0], "keep_lighting=True, 8x the area", height),
                     picture(views[1], "default, 8x the area", height)])
    if args.grid:
        save_grid(rows, args.grid)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
