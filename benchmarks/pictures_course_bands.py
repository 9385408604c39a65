"""Walls of courses of their own heights seen from afar, with and without bands of courses (issue 22):
``docs/images/fit_course_bands.jpg``.

A wall drawn by its courses of their own heights (``snap`` of one period across: each patch offset along its
courses only) showed the tile's sequence of courses once a tile across them, and a view from 8 times as far
showed it as bands of the same courses at the tile's period. Now the wall is cut across its courses into bands
one tile high, each starting the tile's courses at one of them (``spectex.shading.stochastic.course_band_shift``).

Per photo (``exemplars.py``'s ``ashlar``, and every ``--photo PATH``, e.g. supertuxkart-data's
``stk_generic_greyWall_a.png``), one fit, drawn *before* (``_switches.without_course_bands``: every band starts
at the same course) and *after*:

- ``s 1x``: :func:`spectex.metrics.structural_distance` / floor of 768 x 768 bakes at the photo's pixel size,
  at ``PLACES`` places (mean and its standard error);
- from 8 times as far (512 x 512 bakes at 8 times the pixel size, two places, mean):
  ``courses``: the largest autocorrelation of the view's profile across the courses (its luma averaged along
  them, the mean removed; lags of 24 pixels to half the view, each over the overlap): the courses' sequence
  coming back (a tile repeated across its courses: near 1);
  ``rp``: :func:`spectex.metrics.repeat_peak` with the courses' lattice (the tile's side across them) removed.

The picture: per photo, the photo and the far views before and after, 384 x 384.

Run from the repository root::

    python benchmarks/pictures_course_bands.py [--photo PATH ...] [--grid docs/images/fit_course_bands.jpg]
"""

from __future__ import annotations

import sys
from contextlib import nullcontext
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _machine import cpu_name  # noqa: E402
from _pictures import panel, save_grid, wall_photos  # noqa: E402
from _switches import without_course_bands  # noqa: E402

CROP = 384
PLACES = 8
FAR = 8.0
MIN_LAG = 24


def course_repeat(view, along_x=True, min_lag=MIN_LAG):
    """The largest autocorrelation of ``view``'s luma profile across its courses (averaged along them), at lags
    from ``min_lag`` to half the profile, each normalised over its overlap."""
    luma = np.asarray(view[:, :, :3], np.float64) @ np.array([0.2126, 0.7152, 0.0722])
    profile = luma.mean(axis=1 if along_x else 0)
    profile = profile - profile.mean()
    best = -1.0
    for lag in range(min_lag, profile.size // 2 + 1):
        a, b = profile[:-lag], profile[lag:]
        best = max(best, float(np.dot(a, b) / max(np.sqrt(np.dot(a, a) * np.dot(b, b)), 1e-12)))
    return best


def _drawn(result, photo, bands):
    """The fit ``result`` drawn with or without its bands of courses: 1x structure ratios, far views' course
    repeats and repeat peaks, and the first far view."""
    from spectex import metrics
    from spectex.bake._block import bake_window

    layer = result.texture.layers[0]
    along_x = int(layer.snap[0]) == 0
    side = result.params.get("tile_px") or photo.shape[0]
    rng = np.random.default_rng(5)
    places = rng.uniform(0.0, 40.0, (PLACES, 2)) * result.pixel_size * 100.0
    with nullcontext() if bands else without_course_bands():
        ratios = [metrics.structural_distance(
            bake_window(result.texture, (0, 768, 0, 768), pixel_size=result.pixel_size, origin=tuple(o))[:, :, :3],
            photo).ratio for o in places]
        fars = [bake_window(result.texture, (0, 512, 0, 512), pixel_size=FAR * result.pixel_size, origin=o)[:, :, :3]
                for o in ((0.013, 0.029), (31.3, 57.1))]
    lattice = (side / FAR, None) if along_x else (None, side / FAR)
    courses = np.mean([course_repeat(f, along_x) for f in fars])
    peaks = np.mean([metrics.repeat_peak(f, period=lattice) for f in fars])
    return ratios, courses, peaks, fars[0]


def main(argv=None) -> int:
    args, photos = wall_photos(__doc__.split("\n")[0], argv)
    from spectex.fitting import fit_result

    print(f"CPU: {cpu_name()}; s 1x: structural distance / floor, 768 x 768 at the photo's pixel size, {PLACES} "
          f"places (mean +- standard error); from {FAR:g} times as far (512 x 512, 2 places): courses (the "
          "profile across the courses repeating), rp (repeat_peak, the courses' lattice removed)")
    rows = []
    for name, photo in photos.items():
        result = fit_result(photo)
        method = result.params["tile_method"]
        if not method.startswith("a wall of courses of their own heights"):
            print(f"{name:24s} not drawn by its courses: {method[:80]}")
            continue
        fars = {}
        for way, bands in (("before", False), ("after", True)):
            ratios, courses, peaks, fars[way] = _drawn(result, photo, bands)
            print(f"{name:24s} {way:6s} s 1x {np.mean(ratios):.3f} +- {np.std(ratios) / np.sqrt(len(ratios)):.3f}"
                  f"  courses {courses:.2f}  rp {peaks:.2f}", flush=True)
        rows.append((name, photo, fars))
    if args.grid and rows:
        save_grid([[panel(photo, name, CROP), panel(fars["before"], f"before, {FAR:g}x as far", CROP),
                    panel(fars["after"], f"after, {FAR:g}x as far", CROP)] for name, photo, fars in rows], args.grid)
        print(f"wrote {args.grid}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
