"""Pictures and numbers of structures the fit used to cut with straight seams (issue 22): a reptile's scales
coloured in patches (cells refused a map), and a wall and a floor photographed turned (cut along the photo's
axes at an inexact super-lattice).

``docs/images/fit_turned.jpg``. Photos (``exemplars.py``): ``scales`` (domed scales on a jittered hexagonal
lattice, coloured in patches larger than a scale), ``wall_turned`` (a running-bond wall turned 14 degrees)
and ``tiles_turned`` (the floor tiles turned 25 degrees). Per photo, the fit made by the rules before (the
control, main 8e95900 emulated: no cell map unless both periods are whole numbers of texels, the mean period
cell's strength against the texels about it alone; no turned design; any structure's orientation read and
straightened, hexagons' too) and by default, each baked at the photo's pixel size over twice its side, and
printed: the fit's seconds, structural distance / floor of the bake's photo-sized corner (and of both at
half size, where the turned layer's bilinear resampling, which the measure counts as lost detail, weighs
less), ``line_breaks``, and how well the structure's lattice holds across the bake straightened by the
photo's angle (``fitting._auto._lattice_hold``, the share of its luma's variance that folding by its
periods keeps; the photo's own in the header).

Run from the repository root::

    python benchmarks/pictures_turned.py [--grid docs/images/fit_turned.jpg]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import exemplars  # noqa: E402
from _machine import cpu_name  # noqa: E402
from bench_fit_quality import _down  # noqa: E402
from pictures_one_off import picture, save_grid  # noqa: E402

PHOTOS = ("scales", "wall_turned", "tiles_turned")


def _before(cell_map):
    """``cell_map`` as it was before (main 8e95900): no map unless both periods are whole numbers of texels,
    and the mean period cell weighed at ``MIN_CONTRAST = 0.5`` against the texels about it (each cell's own
    colour counted as noise); the map itself, where one is made, is the same."""
    from spectex.shading import _cells

    def before(tile, snap):
        nx, ny = max(int(snap[0]), 1), max(int(snap[1]), 1)
        if tile.shape[1] % nx or tile.shape[0] % ny:
            return None
        saved = _cells.MIN_CONTRAST, _cells.CHANCE_FACTOR, _cells._within_cells
        _cells.MIN_CONTRAST, _cells.CHANCE_FACTOR = 0.5, 0.0
        _cells._within_cells = lambda deviation, labels, period: float(np.mean(deviation ** 2))
        try:
            return cell_map(tile, snap)
        finally:
            _cells.MIN_CONTRAST, _cells.CHANCE_FACTOR, _cells._within_cells = saved
    return before


def _fit(photo, before):
    """The default fit, or (``before``) the fit by the rules before this change (no turned design, any
    structure's orientation read and straightened, :func:`_before`'s cell map); the cell maps' cache emptied
    so that each fit's renders make their own."""
    from spectex import fitting
    from spectex.fitting import _auto
    from spectex.render import bake
    from spectex.shading import _cells, resources

    saved = _auto.DESIGN_HOLD, _auto.MIN_LINE_COHERENCE, _cells.cell_map, resources.cell_map
    if before:
        _auto.DESIGN_HOLD, _auto.MIN_LINE_COHERENCE = np.inf, 0.0
        _cells.cell_map = resources.cell_map = _before(saved[2])
    try:
        resources._CACHE.clear()
        t0 = time.perf_counter()
        result = fitting.fit_result(photo, rng=0)
        seconds = time.perf_counter() - t0
        h, w = photo.shape[:2]
        near = bake(result.texture, (2 * h, 2 * w), pixel_size=result.pixel_size)
        has_cells = any(c is not None for c in resources.cell_maps(result.texture))
    finally:
        _auto.DESIGN_HOLD, _auto.MIN_LINE_COHERENCE, _cells.cell_map, resources.cell_map = saved
        resources._CACHE.clear()
    return result, near, seconds, has_cells


def main(argv=None) -> int:
    from spectex import metrics
    from spectex.fitting._auto import _lattice_hold, _straightened
    from spectex.fitting._structure import structure_orientation

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grid", type=Path, default=None, help="write the picture grid here (JPEG)")
    args = ap.parse_args(argv)
    print(f"machine: {cpu_name()}, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}; "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    rows = []
    for name in PHOTOS:
        photo = exemplars.load(name)
        h, w = photo.shape[:2]
        angle = structure_orientation(photo)
        angle += structure_orientation(_straightened(photo, angle))
        own = _lattice_hold(_straightened(photo, angle))
        print(f"{name} (lines at {angle:.1f} degrees; the photo's lattice holds {own:.2f} straightened)")
        row = [picture(photo, name)]
        for before in (True, False):
            result, near, seconds, has_cells = _fit(photo, before)
            s1 = metrics.structural_distance(near[:h, :w], photo).ratio
            s_half = metrics.structural_distance(_down(near[:h, :w], 2), _down(photo, 2)).ratio
            breaks = metrics.line_breaks(near, photo).ratio
            hold = _lattice_hold(_straightened(near, angle))
            how = "before" if before else "default"
            turn = result.params.get("turn_deg", 0.0)
            print(f"  {how:8s} turn {turn:6.1f}  cells {'yes' if has_cells else 'no ':3s} "
                  f"s 1x {s1:5.2f}  s half {s_half:5.2f}  breaks {breaks:5.2f}  lattice holds {hold:5.2f}  "
                  f"{seconds:5.1f} s", flush=True)
            row.append(picture(near[:h, :w], f"{how}: s {s1:.2f}, holds {hold:.2f}"))
        rows.append(row)
    if args.grid is not None:
        save_grid(rows, args.grid)
        print(f"wrote {args.grid}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
