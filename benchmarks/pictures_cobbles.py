"""Pictures and numbers of cobbles drawn with free cells (issue 22): ``docs/images/fit_cobbles.jpg``.

Irregular cobbles have no period, so the fit draws their tile stochastically without snapping, and
the triangle grid's cross-fades ran through the cobbles (ghosted, cut by straight lines). With the
tile's *free cell map* (``spectex.shading._cells.free_cell_map``: the cobbles parted by the grout's
network, read on the tile itself) the sampler shows, at each point, the patch whose own cobble
there lies in its region (``spectex.shading.stochastic.cell_vertex``). Per photo (``exemplars.py``'s
``paving`` and three more of its procedural pavings, other stone sizes and seeds), one fit, and
its bakes (1024 x 1024 at the photo's pixel size, two places) drawn twice: *blend*, the free map
left out (as before it existed), and *cells*. Printed: whether the tile has a map, the fit's
seconds, and :func:`spectex.metrics.structural_distance` / floor over the 8 windows of 512 x 512
of the two bakes (their mean, and on how many the cells are closer). The picture: per photo, a
crop of the photo, of the blend's bake and of the cells' bake, each 320 x 320 at full size.

Run from the repository root::

    python benchmarks/pictures_cobbles.py [--grid docs/images/fit_cobbles.jpg]
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
from _pictures import panel, save_grid  # noqa: E402
from _switches import without_free_cells  # noqa: E402

CROP = 320
ORIGINS = ((0.0, 0.0), (37.3, -81.7))


def photos():
    return {"paving": exemplars.load("paving"),
            "paving, stones of 30 px": exemplars.paving(512, cell=30.0, rng=3),
            "paving, stones of 60 px": exemplars.paving(512, cell=60.0, rng=5),
            "paving, another seed": exemplars.paving(512, cell=44.0, rng=9)}


def _bakes(result, way):
    """The two bakes of ``result`` drawn ``way`` ("cells", or "blend": the free cell map left out)."""
    from spectex.bake._block import bake_window

    def bakes():
        return [bake_window(result.texture, (0, 1024, 0, 1024), pixel_size=result.pixel_size, origin=o)
                for o in ORIGINS]

    if way == "cells":
        return bakes()
    with without_free_cells():
        return bakes()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grid", help="write the picture here (JPEG)")
    args = ap.parse_args(argv)
    from spectex import metrics
    from spectex.fitting import fit_result
    from spectex.shading._cells import free_cell_map

    print(f"CPU: {cpu_name()}; bakes 1024 x 1024 at the photo's pixel size, {len(ORIGINS)} places, "
          "structural distance / floor over their 8 windows of 512")
    rows = []
    for name, photo in photos().items():
        t0 = time.perf_counter()
        result = fit_result(photo)
        seconds = time.perf_counter() - t0
        has_map = free_cell_map(result.texture.tiles[0]) is not None
        reference = metrics.reference_statistics(result.exemplar)
        ratios, firsts = {}, {}
        for way in ("blend", "cells"):
            bakes = _bakes(result, way)
            firsts[way] = bakes[0]
            ratios[way] = [metrics.structural_distance(b[y:y + 512, x:x + 512], result.exemplar,
                                                       prepared=reference).ratio
                           for b in bakes for y in (0, 512) for x in (0, 512)]
        closer = sum(c < b for c, b in zip(ratios["cells"], ratios["blend"]))
        print(f"{name}: map {'yes' if has_map else 'no'}; fit {seconds:.1f} s; structure / floor: blend "
              f"{np.mean(ratios['blend']):.3f}, cells {np.mean(ratios['cells']):.3f} (closer in {closer} of "
              f"{len(ratios['cells'])} windows)", flush=True)
        rows.append((name, photo, firsts))
    if args.grid:
        save_grid([[panel(photo, name, CROP), panel(firsts["blend"], "before: patches cross-faded", CROP),
                    panel(firsts["cells"], "after: free cells", CROP)]
                   for name, photo, firsts in rows], args.grid)
        print(f"wrote {args.grid}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
