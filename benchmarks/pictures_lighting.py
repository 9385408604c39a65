"""Pictures and numbers of a photo's uneven lighting evened out, and of one taken at an angle levelled (issue 22).

``docs/images/fit_lighting.jpg`` (the default case, ``lighting``) and ``docs/images/fit_oblique.jpg``
(``--case oblique``).

Photos lit unevenly (``exemplars.py``): scikit-image's gravel and the procedural paving under a light
from one side with a vignette (``exemplars.lit``, a drift of about 14 % RMS), and scikit-image's
``page``, a scanned page that the scanner lit unevenly (real light; text is no ground texture, but
its pieces show the blotches the clearest). Per photo, the fit made twice, ``keep_lighting=True``
(the fit before the lighting was evened out) and the default, and printed: the fit's seconds, the
lighting found and :func:`spectex.metrics.lighting_blotches` of a bake of 8 times the photo's area
at its pixel size (what ``spectex fit`` reports on). The picture: per photo, the photo and the two
bakes, side by side (each bake shown at the photo's height).

``--case oblique``: gravel, paving and grass seen at an angle (``exemplars.oblique``: the far side's
grain 0.45 times the near side's across, 0.2 times along), the fit made with ``keep_perspective=True``
and by default (levelled), measured by :func:`spectex.metrics.scale_blotches`.

Run from the repository root::

    python benchmarks/pictures_lighting.py [--grid docs/images/fit_lighting.jpg]
    python benchmarks/pictures_lighting.py --case oblique [--grid docs/images/fit_oblique.jpg]
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

#: Per case: its photos, the fit's keyword that keeps what the default takes out, the measure.
CASES = {"lighting": (("gravel_lit", "paving_lit", "page"), "keep_lighting", "lighting_blotches"),
         "oblique": (("gravel_oblique", "paving_oblique", "grass_oblique"), "keep_perspective", "scale_blotches")}


def _describe(result, seen, keyword):
    if keyword == "keep_lighting":
        done = "evened out" if result.params["lighting"] else "kept"
        return (f"photo's lighting {100 * seen.lighting:4.1f}% RMS ({done}); 8x its area: low-frequency contrast "
                f"{seen.view_contrast:.3f} (photo's own {seen.photo_contrast:.3f})")
    level = result.params["level"]
    done = f"levelled, crop {level['crop'][0]} x {level['crop'][1]}" if level else "kept"
    return (f"photo's grain {seen.spread:.2f}-fold across it ({done}); 8x its area: scale scatter "
            f"{seen.view_scatter:.3f} (photo's own {seen.photo_scatter:.3f})")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", help="write the picture here (JPEG)")
    ap.add_argument("--case", choices=sorted(CASES), default="lighting")
    args = ap.parse_args(argv)
    from spectex import metrics
    from spectex.fitting import fit_result
    from spectex.render import bake

    names, keyword, measure = CASES[args.case]

    print(f"CPU: {cpu_name()}")
    rows = []
    for name in names:
        photo = exemplars.load(name)
        h, w = photo.shape[:2]
        scale = np.sqrt(8.0)
        shape = (int(round(scale * h)), int(round(scale * w)))  # 8 times the photo's area, its aspect
        views = []
        for keep in (True, False):
            t0 = time.perf_counter()
            result = fit_result(photo, rng=0, **{keyword: keep})
            seconds = time.perf_counter() - t0
            view = bake(result.texture, shape, pixel_size=result.pixel_size)
            seen = getattr(metrics, measure)(view, photo)
            way = f"{keyword}=True" if keep else "default"
            print(f"{name:14s} {way:21s} fit {seconds:5.2f} s; {_describe(result, seen, keyword)}, excess "
                  f"{seen.excess:.3f} {'within' if seen.within else 'BLOTCHES'} (threshold {seen.threshold:g})")
            views.append(view)
        height = 256 if h >= w else 160
        rows.append([picture(photo, f"{name}: photo", height),
                     picture(views[0], f"{keyword}=True, 8x the area", height),
                     picture(views[1], "default, 8x the area", height)])
    if args.grid:
        save_grid(rows, args.grid)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
