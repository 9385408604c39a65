"""Pictures and numbers of courses changing patch at their joints (issue 22): ``docs/images/fit_courses.jpg``.

A photo of floor boards, or of columns of bricks, has a period across its courses and none along them: the
fit snaps its finest layer across the courses only. The triangle grid's patch boundaries then cut boards in
two (two tones without a joint), and the period tile, its courses read straight across the photo where they
could not be cut at their own joints, joined two boards at its wrap edge in every patch. Now the tile's
*course map* (``spectex.shading._cells.course_map``) lets each course change patch at a joint of the new
patch (``spectex.shading.stochastic.course_vertex``), and the period tile gets a joint of its own course
where its wrap edge joins two boards (``spectex.fitting._auto._joints_at_wrap``).

Per photo (``exemplars.py``'s ``planks``, planks of another size and seed, the same turned a quarter (columns),
and scikit-image's brick), two fits: *before* (main's code before courses: ``_switches.without_courses``) and
*after*; each baked at 1024 x 1024 at the photo's pixel size at two places. Printed: the fits' seconds (one
after the other: compare them only within the run), :func:`spectex.metrics.structural_distance` / floor over
the 8 windows of 512 x 512 of the two bakes (mean), and :func:`spectex.metrics.cell_splits`' ratio of the
two bakes (boards or bricks changing colour partway; mean). The picture: per photo a crop of the photo and
of the two bakes, 320 x 320 at full size.

Run from the repository root::

    python benchmarks/pictures_courses.py [--grid docs/images/fit_courses.jpg]
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
from _switches import without_courses  # noqa: E402

CROP = 320
ORIGINS = ((0.0, 0.0), (37.3, -81.7))


def photos():
    planks = exemplars.load("planks")
    return {"planks": planks,
            "planks, 36 px, another seed": exemplars.planks(512, board=36.0, rng=8),
            "planks turned (columns)": np.ascontiguousarray(planks.transpose(1, 0, 2)),
            "brick (scikit-image)": exemplars.load("brick")}


def _measure(photo, way):
    """One fit ``way`` ("before" or "after") of ``photo``: its seconds, its two bakes, the structural distances of
    their windows and their cell splits."""
    from spectex import metrics
    from spectex.bake._block import bake_window
    from spectex.fitting import fit_result, structure_period

    with without_courses() if way == "before" else nullcontext():
        t0 = time.perf_counter()
        result = fit_result(photo)
        seconds = time.perf_counter() - t0
        bakes = [bake_window(result.texture, (0, 1024, 0, 1024), pixel_size=result.pixel_size, origin=o)
                 for o in ORIGINS]
    reference = metrics.reference_statistics(result.exemplar)
    ratios = [metrics.structural_distance(b[y:y + 512, x:x + 512], result.exemplar, prepared=reference).ratio
              for b in bakes for y in (0, 512) for x in (0, 512)]
    period = structure_period(result.exemplar)
    splits = [metrics.cell_splits(b, result.exemplar, period=period) for b in bakes]
    splits = [s.ratio for s in splits if s is not None]
    return seconds, bakes, ratios, splits, result.texture.layers[0]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grid", help="write the picture here (JPEG)")
    args = ap.parse_args(argv)

    print(f"CPU: {cpu_name()}; bakes 1024 x 1024 at the photo's pixel size, {len(ORIGINS)} places; s: structural "
          "distance / floor over their 8 windows of 512 (mean); splits: metrics.cell_splits ratio (mean)")
    rows = []
    for name, photo in photos().items():
        firsts = {}
        for way in ("before", "after"):
            seconds, bakes, ratios, splits, layer = _measure(photo, way)
            firsts[way] = bakes[0]
            split = f"{np.mean(splits):.2f}" if splits else "-"
            print(f"{name:28s} {way:6s} fit {seconds:5.1f} s  {layer.tiling} snap {tuple(layer.snap)}  "
                  f"s {np.mean(ratios):.3f}  splits {split}", flush=True)
        rows.append((name, photo, firsts))
    if args.grid:
        save_grid([[panel(photo, name, CROP), panel(firsts["before"], "before: patches cut boards", CROP),
                    panel(firsts["after"], "after: courses change patch at joints", CROP)]
                   for name, photo, firsts in rows], args.grid)
        print(f"wrote {args.grid}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
