"""Pictures and numbers of the fit's period tiles (issue 22): ``docs/images/fit_cells.jpg`` and
``docs/images/fit_snap.jpg``.

Run from the repository root::

    python benchmarks/pictures_fit.py                                  # numbers only
    python benchmarks/pictures_fit.py --grid docs/images/fit_cells.jpg # and the picture
    python benchmarks/pictures_fit.py --snap docs/images/fit_snap.jpg  # the snapped fit's picture only

``--snap``: per photo (``--photos``), the photo, the default fit (snapped) and the fit forced
periodic (``tiling="periodic"``), each a bake of twice the photo's side at its pixel size shown
at half size, and the default fit zoomed out 8 times (a bake at 8 times the pixel size, filtered
as the renderers filter it).

On ``benchmarks/exemplars.py``'s tiles (a period along both axes) and scikit-image's brick
(columns of bricks: a period across, none down), the default fit (``spectex.fitting.fit_result``,
the photo's default scale) made twice: *before*, the period tile's straight cut along the axis
without a period (main's code before the strips were cut at their joints: the fit with
``spectex.fitting._auto._strip_tile`` answering None, which is exactly that code path), and
*after*, each strip of a photo with a period along one axis only cut at its own joints
(``_strip_cuts``). Printed per photo and way:

* the fit's seconds (the machine's CPU named; the two ways one after the other, so compare them
  only within one run);
* the period tile's cut bricks: the share of the tile's wrap edge (along the strips) inside bricks
  whose two sides differ by more than ``--step`` (a brick made of two photo bricks), and the mean
  colour step there against the mean step between neighbours inside bricks elsewhere (the noise's).
  (The strips cut at their joints have their cuts in the mortar, off the wrap edge; the count of such
  steps over the whole tile, which ``tests/test_joints.py`` takes on walls of plain bricks, is on brick
  mostly its bricks' own marks and is not printed.) Inside
  bricks: the grout's colour class of the photo's columns (``_grout_lines``) left out, eroded by
  three texels along the strip (the resampled mortar's edges);
* :func:`spectex.metrics.structural_distance` ratios (distance / the photo's own floor) of
  1024 x 1024 bakes at the photo's pixel size at ``--origins`` places: the photo-sized corner
  (``1x``) and over the whole bake (it scatters by about 0.4 between places: read the spread).

The picture: 384 x 384 crops of the first bake, tiles and brick, before and after.
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
from _pictures import label  # noqa: E402

BAKE = 1024
CROP = 384


def _fit(photo, way):
    """The fit (``way``: "before" or "after") and the period tile it cut (None where it cut none)."""
    from spectex.fitting import _auto, fit_result

    seen = {}
    period_tile, strip_tile = _auto._period_tile, _auto._strip_tile

    def spy(exemplar, period, words=None):
        out = period_tile(exemplar, period, words)
        seen.update(tile=None if out is None else out[0], exemplar=exemplar, period=period)
        return out

    _auto._period_tile = spy
    if way == "before":
        _auto._strip_tile = lambda *args: None
    try:
        result = fit_result(photo)
    finally:
        _auto._period_tile, _auto._strip_tile = period_tile, strip_tile
    return result, seen


def _cut_bricks(tile, exemplar, period, step):
    """``(wrap step, neighbours' step, wrap fraction)`` of a period tile whose photo has a period along
    one axis (see the module's text); None otherwise."""
    from spectex.fitting._auto import _grout_lines

    if tile is None or (period[0] is None) == (period[1] is None):
        return None
    if period[1] is None:  # courses: turned to columns
        tile, exemplar, period = np.swapaxes(tile, 0, 1), np.swapaxes(exemplar, 0, 1), period[::-1]
    photo = exemplar.astype(np.float64)
    grout = _grout_lines(np.moveaxis(photo, 1, 0), period[1])
    if grout is None:
        return None
    columns = photo.mean(axis=0)
    brick, mortar = columns[~grout].mean(axis=0), columns[grout].mean(axis=0)
    level = (tile - brick) @ (mortar - brick) / float((mortar - brick) @ (mortar - brick))
    inside_one = level < 0.5
    inside = np.logical_and.reduce([np.roll(inside_one, k, axis=0) for k in range(-3, 3)])
    below = np.roll(tile, -1, axis=0)
    jump = np.abs(below - tile).mean(axis=2)
    wrap = float(jump[-1][inside[-1]].mean())
    rest = float(jump[:-1][inside[:-1]].mean())
    return wrap, rest, float(np.mean(jump[-1][inside[-1]] > step))


def _bakes(result, origins):
    """``origins`` bakes of ``BAKE`` x ``BAKE`` pixels at the photo's pixel size, at places a few tiles apart."""
    from spectex.render import bake

    p = result.pixel_size
    side = BAKE * p
    return [bake(result.texture, (BAKE, BAKE), pixel_size=p, origin=(k * 0.37 * side, k * 0.61 * side))
            for k in range(origins)]


def _snap_picture(names, path):
    """``--snap``: photo | default fit | forced periodic | default fit 8x out, a row per photo."""
    from PIL import Image

    from spectex.fitting import fit_result
    from spectex.render import bake

    side = 256
    rows = []
    for name in names:
        photo = exemplars.load(name)
        h, w = photo.shape[:2]
        shown = [("photo", photo)]
        default = fit_result(photo)
        periodic = fit_result(photo, tiling="periodic")
        p = default.pixel_size
        shown.append((f"fit (snap {default.texture.layers[0].snap})", bake(default.texture, (2 * h, 2 * w),
                                                                           pixel_size=p)))
        shown.append(("fit forced periodic", bake(periodic.texture, (2 * h, 2 * w), pixel_size=periodic.pixel_size)))
        shown.append(("fit, 8x zoomed out", bake(default.texture, (side, side), pixel_size=8 * p)))
        panels = []
        for words, image in shown:
            image = np.clip(np.asarray(image, dtype=np.float64), 0.0, 1.0)
            if image.ndim == 2:
                image = np.repeat(image[:, :, None], 3, axis=2)
            img = Image.fromarray((image[:, :, :3] * 255 + 0.5).astype(np.uint8)).resize((side, side),
                                                                                        Image.LANCZOS)
            panels.append(label(img, f"{name}: {words}"))
        rows.append(panels)
    cw, ch = rows[0][0].width, rows[0][0].height
    grid = Image.new("RGB", (4 * cw + 3 * 8, len(rows) * ch + (len(rows) - 1) * 8), (128, 128, 128))
    for r, panels in enumerate(rows):
        for c, panel in enumerate(panels):
            grid.paste(panel, (c * (cw + 8), r * (ch + 8)))
    grid.save(path, quality=90)
    print(f"wrote {path}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--grid", help="write the picture here (JPEG)")
    ap.add_argument("--origins", type=int, default=4, help="bake places per fit (default 4)")
    ap.add_argument("--step", type=float, default=0.01,
                    help="a step between neighbours inside bricks over this is two bricks (default 0.01: brick's "
                         "bricks differ by a few hundredths, its noise's steps 0.003)")
    ap.add_argument("--photos", default="tiles,brick", help="exemplars.py names (default tiles,brick)")
    ap.add_argument("--snap", help="write only the snapped fit's picture here (JPEG): see the module's text")
    args = ap.parse_args(argv)
    if args.snap:
        _snap_picture(args.photos.split(","), args.snap)
        return 0
    from spectex import metrics

    print(f"CPU: {cpu_name()}; bakes {BAKE} x {BAKE} at the photo's pixel size, {args.origins} places")
    panels = []
    for name in args.photos.split(","):
        photo = exemplars.load(name)
        reference = metrics.reference_statistics(photo)
        h, w = photo.shape[:2]
        for way in ("before", "after"):
            t0 = time.perf_counter()
            result, seen = _fit(photo, way)
            seconds = time.perf_counter() - t0
            cut = _cut_bricks(seen.get("tile"), seen.get("exemplar"), seen.get("period", (None, None)), args.step)
            bakes = _bakes(result, args.origins)
            ones = [metrics.structural_distance(b[:h, :w], photo, prepared=reference).ratio for b in bakes]
            wholes = [metrics.structural_distance(b, photo, prepared=reference).ratio for b in bakes]
            words = "" if cut is None else (f"; wrap edge inside bricks: {100 * cut[2]:.0f}% of its texels step "
                                            f"over {args.step}, mean step {cut[0]:.4f} (neighbours elsewhere "
                                            f"{cut[1]:.4f})")
            print(f"{name} {way}: {result.params['tile_method']}")
            print(f"{name} {way}: fit {seconds:.1f} s{words}; structure / floor 1x "
                  + ", ".join(f"{v:.2f}" for v in ones) + f" (mean {np.mean(ones):.2f}); over the bake "
                  + ", ".join(f"{v:.2f}" for v in wholes) + f" (mean {np.mean(wholes):.2f}); "
                  + f"snap {result.texture.layers[0].snap}", flush=True)
            panels.append((name, way, bakes[0]))
    if args.grid:
        from PIL import Image

        tiles = []
        for name, way, baked in panels:
            crop = np.clip(baked[:CROP, :CROP], 0.0, 1.0)
            if crop.ndim == 2:
                crop = np.repeat(crop[:, :, None], 3, axis=2)
            img = Image.fromarray((crop[:, :, :3] * 255 + 0.5).astype(np.uint8))
            words = {"before": "before (main: straight cut along the axis without a period)",
                     "after": "after (strips cut at their own joints)"}[way]
            if name == "tiles":
                words = {"before": "before (main)", "after": "after (a period on both axes: unchanged)"}[way]
            tiles.append(label(img, f"{name}: {words}"))
        cols = 2
        rows = (len(tiles) + cols - 1) // cols
        cw, ch = tiles[0].width, tiles[0].height
        grid = Image.new("RGB", (cols * cw + (cols - 1) * 8, rows * ch), (128, 128, 128))
        for k, t in enumerate(tiles):
            grid.paste(t, ((k % cols) * (cw + 8), (k // cols) * ch))
        grid.save(args.grid, quality=90)
        print(f"wrote {args.grid}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
