"""Pictures and numbers of walls of courses of their own heights and of walls few bricks across (issue 22):
``docs/images/fit_coursed.jpg``.

A wall of coursed ashlar (courses of several heights in no order: no period across them) was drawn by the
period of its shortest courses, its tall stones cut in two where their rows changed patch at different joints,
or, without a period, stochastically, its courses ending in stubs. Now the fit finds its grout lines running the
whole photo (``spectex.fitting._joints.wall_courses``), cuts a tile from one grout line to another, each course at
its own joints (``coursed_tile``), and draws it with each patch offset along the courses only (``snap`` of one
period across: every patch's courses where the tile's are) and a course map of courses of their own heights
(``spectex.shading._cells.course_map``), where its trial finds it closer than the other ways. A wall whose courses
hold 2.5 bricks at the largest tile side now takes a side at which every course wraps at its own joints.

Per photo (``exemplars.py``'s ``ashlar``, and every ``--photo PATH``, e.g. supertuxkart-data's
``stk_generic_greyWall_a.png`` and ``stk_generic_brickA.png``, halved), two fits: *before*
(``_switches.without_coursed_walls``) and *after*, each baked at 768 x 768 at the photo's pixel size at four
places. Printed: the way, the fits' seconds, :func:`spectex.metrics.structural_distance` / floor of the bakes
(mean) and, for a photo with a structure period, :func:`spectex.metrics.short_cells` of the bakes (mean; the
photo's own beside it). The picture: per photo a crop of the photo and of the two first bakes, 384 x 384.

Run from the repository root::

    python benchmarks/pictures_coursed.py [--photo PATH ...] [--grid docs/images/fit_coursed.jpg]
"""

from __future__ import annotations

import sys
import time
from contextlib import nullcontext
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _machine import cpu_name  # noqa: E402
from _pictures import panel, save_grid, wall_photos  # noqa: E402
from _switches import without_coursed_walls  # noqa: E402

CROP = 384
ORIGINS = ((0.013, 0.029), (3.31, 7.77), (11.5, 2.2), (20.1, 13.3))


def _measure(photo, way):
    """One fit ``way`` ("before" or "after") of ``photo``: its seconds, way, bakes, structural distances and
    short cells (with the photo's own)."""
    from spectex import metrics
    from spectex.bake._block import bake_window
    from spectex.fitting import fit_result, structure_period

    with without_coursed_walls() if way == "before" else nullcontext():
        t0 = time.perf_counter()
        result = fit_result(photo)
        seconds = time.perf_counter() - t0
    bakes = [bake_window(result.texture, (0, 768, 0, 768), pixel_size=result.pixel_size, origin=o)[:, :, :3]
             for o in ORIGINS]
    ratios = [metrics.structural_distance(b, photo).ratio for b in bakes]
    period = structure_period(photo)
    shorts = [metrics.short_cells(b, photo, period=period) for b in bakes] if period is not None else []
    shorts = [s for s in shorts if s is not None]
    method = result.params["tile_method"]
    way_words = method.split(" (")[0] if method.startswith("a wall") else method.split(";")[0].split(" where")[0]
    return seconds, way_words, bakes, ratios, shorts


def main(argv=None) -> int:
    args, photos = wall_photos(__doc__.split("\n")[0], argv)
    print(f"CPU: {cpu_name()}; bakes 768 x 768 at the photo's pixel size, {len(ORIGINS)} places; s: structural "
          "distance / floor (mean); short: metrics.short_cells of the bakes (mean; the photo's own)")
    rows = []
    for name, photo in photos.items():
        firsts = {}
        for way in ("before", "after"):
            seconds, words, bakes, ratios, shorts = _measure(photo, way)
            firsts[way] = bakes[0]
            short = (f"  short {np.mean([s.image for s in shorts]):.2f} (photo {shorts[0].reference:.2f})"
                     if shorts else "")
            print(f"{name:24s} {way:6s} fit {seconds:5.1f} s  s {np.mean(ratios):.3f}{short}  {words[:80]}",
                  flush=True)
        rows.append((name, photo, firsts))
    if args.grid:
        save_grid([[panel(photo, name, CROP), panel(firsts["before"], "before", CROP),
                    panel(firsts["after"], "after", CROP)] for name, photo, firsts in rows], args.grid)
        print(f"wrote {args.grid}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
