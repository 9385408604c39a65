"""Benchmark: how close a fitted texture is to its photo, against its peers (issue 22).

Run from the repository root::

    python benchmarks/bench_fit_quality.py            # 8 photos, all methods (many minutes on 2 cores)
    python benchmarks/bench_fit_quality.py --quick    # 3 photos, smaller renders
    python benchmarks/bench_fit_quality.py --grid docs/images/fit_quality.jpg

In one run, on the photos of ``benchmarks/exemplars.py`` (scikit-image's gravel, brick,
grass, moon, a tissue slide and a deep-field crop; procedural paving and tiles), each of:

* ``fit``: the current default, ``spectex.fitting.fit_result(photo)``;
* ``legacy``: the old default, ``fit_result(photo, method="legacy")`` where ``fit`` has a
  ``method`` keyword (else the row is left out);
* ``t&b lin`` and ``t&b hist``: tiling and blending (Heitz and Neyret 2018, linear and
  histogram-preserving blends, ``benchmarks/tiling_blending.py``);
* ``quilt``: image quilting, :func:`spectex.synthesis.quilt` (block 48).

A *near* render covers twice the photo's side at its pixel size (a fit's bake; the peers'
output), a *far* view eight times its pixel size (a fit's bake of 512 x 512 pixels, 8 times the
photo's side; tiling and blending's output of 4 times the photo's side reduced 8 x 8, quilting's
near render reduced 8 x 8: the peers hold nothing coarser than the photo). Columns:

* ``s 1x``: :func:`spectex.metrics.structural_distance` ratio of the near render's photo-sized
  corner (the photo's own place) to the photo: about 1 is as close as the photo is to itself;
* ``s near``: the same over windows spread over the whole near render;
* ``clip``: clipped channel values of the near render, percent (the photo's in the header);
* ``rp near``, ``rp far``: :func:`spectex.metrics.repeat_peak` of the near render and of the far
  view (<= 0.1 does not repeat);
* ``rs near``, ``rs far``: the same with the photo's structure lattice removed
  (``repeat_peak(..., period=)``, the period :func:`spectex.fitting.structure_period` finds on a
  structured photo, after the straightening or rectification the fit makes, so the lattice the
  fit's bake has; ``nan`` on the others): how much the *content* repeats, where the lattice
  itself (bricks, tile grout) is the photo's own repeat (``rp own`` in the header: brick 0.18,
  tiles 0.90), which no texture that keeps the structure can lower (a wall square-on, its
  mortar straight, has a higher ``rp`` than the same wall in perspective: brick rectified, 0.75);
* ``brk``: :func:`spectex.metrics.line_breaks` ratio of the near render to the photo (structured
  photos): about 1 or below keeps the photo's lines as straight; clearly above, V-shaped breaks;
* ``cells``: :func:`spectex.metrics.cell_splits` ratio of the near render to the photo as the fit reads
  it (structured photos): about 1, bricks and floor tiles as uniform as the photo's; clearly above,
  cells made of two (patch boundaries across them);
* ``short``: :func:`spectex.metrics.short_cells` of the near render, percent of its bricks or floor
  tiles under 0.6 of the photo's median cell (``short own`` in the header: the photo's own); clearly
  above the photo's, cells cut short where patches meet;
* ``copies``: :func:`spectex.metrics.coarse_copies` of the far view: the best correlation
  with the photo magnified 2-256 times, ``*`` where it is over the photo's own (in the header);
* ``1off``: :func:`spectex.metrics.one_off_repeats` of the near render: copies per photo area of
  content the photo shows once (a leaf pasted on gravel); 0 where the photo has none (all 8 default
  photos), about 1 for a texture that repeats it. ``--only gravel_leaf,grass_leaf`` runs the two
  photos of ``exemplars.EXTRA`` that hold one;
* ``blot``: :func:`spectex.metrics.lighting_blotches` of the near render: its low-frequency contrast at
  the photo's scale beyond the photo's own (its lighting divided out), ``*`` over the threshold 0.01
  (blotches show: a photo's uneven light repeated in every piece of the texture). ``--only
  gravel_lit,paving_lit,page`` runs the unevenly lit photos of ``exemplars.EXTRA``;
* ``grain``: :func:`spectex.metrics.scale_blotches` of the near render: the scatter of its blocks' log
  local frequency beyond the photo's own (its tilt taken out), ``*`` over the threshold 0.025 (patches
  of large and small grain: a photo taken at an angle, near and far mixed). ``--only
  gravel_oblique,paving_oblique,grass_oblique`` runs the photos of ``exemplars.EXTRA`` seen at an angle;
* ``s``: seconds to make the texture (fit or synthesis of the near render).

``--only`` also takes paths of photos of your own (``--only my/wall.jpg,my/gravel.png``; each shown by
its file's stem): the same table for them.

The machine, its load and the date are printed with the table.
"""

from __future__ import annotations

import argparse
import inspect
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _machine import cpu_name
from exemplars import exemplars
from exemplars import load as load_photo
from tiling_blending import tile_and_blend

from spectex.render import bake

METHODS = ("fit", "legacy", "t&b lin", "t&b hist", "quilt")


def _down(image, f):
    h, w = image.shape[:2]
    img = image[: h // f * f, : w // f * f]
    return img.reshape(h // f, f, w // f, f, *img.shape[2:]).mean(axis=(1, 3))


def _rgb(image):
    return np.repeat(image[:, :, None], 3, axis=2) if image.ndim == 2 else image[:, :, :3]


def _make(method, photo, near_shape, far_side, rng):
    """``(near, far, seconds)`` of one method on one photo; None where the method does not exist."""
    from spectex import fitting
    from spectex.synthesis import quilt

    if method in ("fit", "legacy"):
        kwargs = {}
        if method == "legacy":
            if "method" not in inspect.signature(fitting.fit_result).parameters:
                return None
            kwargs["method"] = "legacy"
        t0 = time.perf_counter()
        result = fitting.fit_result(photo, rng=rng, **kwargs)
        seconds = time.perf_counter() - t0
        p = result.pixel_size
        near = bake(result.texture, near_shape, pixel_size=p)
        far = bake(result.texture, (far_side, far_side), pixel_size=8.0 * p)
        return near, far, seconds
    t0 = time.perf_counter()
    if method == "t&b lin":
        near = tile_and_blend(photo, near_shape, blend="linear", rng=rng)
        big = tile_and_blend(photo, (4 * far_side, 4 * far_side), blend="linear", rng=rng)
    elif method == "t&b hist":
        near = tile_and_blend(photo, near_shape, blend="histogram", rng=rng)
        big = tile_and_blend(photo, (4 * far_side, 4 * far_side), blend="histogram", rng=rng)
    else:
        near = quilt(photo, near_shape, block=48, rng=rng)
        big = near
    seconds = time.perf_counter() - t0
    return near, _down(big, 8), seconds


def _period(photo):
    """The photo's structure period ``(py, px)`` in pixels where it is structured (the fit's own test), else None,
    and the photo as the fit reads it: straightened or rectified first where the fit does (its period is the
    one the fit's bake has), else the photo."""
    from spectex.fitting import STRUCTURED_PEAK, prepare_exemplar, structure_peak
    from spectex.fitting._auto import _photo_as_ground, _straighten_structure
    from spectex.fitting._structure import structure_period

    # the fit's own steps before it reads the structure (a brick wall taken at an angle is levelled first, and
    # only then reads as structured)
    exemplar = _photo_as_ground(prepare_exemplar(photo)[0], [], keep_lighting=False, keep_perspective=False,
                                keep_one_off=False)[0]
    structure = structure_peak(exemplar)
    if structure < STRUCTURED_PEAK:
        return None, photo
    exemplar = _straighten_structure(exemplar, structure, [])[0]
    period = structure_period(exemplar)
    return (None, photo) if period == (None, None) else (period, exemplar)


def _content_repeat(image, period, zoom=1):
    """``repeat_peak`` with the structure's lattice (``period`` / ``zoom`` pixels) removed; nan without one."""
    from spectex import metrics

    if period is None:
        return float("nan")
    scaled = tuple(None if p is None or p / zoom < 2 else p / zoom for p in period)
    if scaled == (None, None):
        return float("nan")
    return metrics.repeat_peak(image, period=scaled, min_lag=min(24, min(image.shape[:2]) // 2))


def _measure(photo, near, far, period=None, straight=None, prepared=None):
    """The columns for one method's renders; ``prepared``: a dict kept per photo for what is
    measured of the photo alone (its structural floor, its own range per far-view shape)."""
    from spectex import metrics

    prepared = {} if prepared is None else prepared
    h, w = photo.shape[:2]
    if "statistics" not in prepared:
        prepared["statistics"] = metrics.reference_statistics(photo)
    s1 = metrics.structural_distance(near[:h, :w], photo, prepared=prepared["statistics"])
    sn = metrics.structural_distance(near, photo, prepared=prepared["statistics"])
    clip = metrics.clipping(near, photo)
    copies = None
    if min(far.shape[:2]) >= 96 and min(photo.shape[:2]) >= 192:  # (the search's least photo)
        shape = far.shape[:2]
        if shape not in prepared:
            prepared[shape] = metrics.coarse_reference(photo, view_shape=shape, zoom=8)
        copies = metrics.coarse_copies(far, photo, zoom=8, prepared=prepared[shape])
    return {"s 1x": s1.ratio, "s near": sn.ratio, "clip": 100 * clip.image, "clip photo": 100 * clip.reference,
            "rp near": metrics.repeat_peak(near),
            "rp far": metrics.repeat_peak(far, min_lag=min(24, min(far.shape[:2]) // 2)),
            "copies": copies.value if copies else float("nan"),
            "copies photo": copies.reference if copies else float("nan"),
            "copies flag": (copies is not None and not copies.within),
            "rs near": _content_repeat(near, period), "rs far": _content_repeat(far, period, zoom=8),
            "rs photo": _content_repeat(photo if straight is None else straight, period),
            "breaks": metrics.line_breaks(near, photo).ratio if period is not None else float("nan"),
            "cells": _cells(near, photo if straight is None else straight, period),
            "short": _short(near, photo if straight is None else straight, period),
            "one-off": metrics.one_off_repeats(near, photo).per_photo_area,
            "blotches": metrics.lighting_blotches(near, photo),
            "grain": metrics.scale_blotches(near, photo),
            "groups": s1.group_ratios}


def _short(near, reference, period):
    """:func:`spectex.metrics.short_cells` of the near render and of the photo as the fit reads it, percent:
    ``(image, photo)``; nan without a structure or where either shows no separate cells."""
    from spectex import metrics

    found = None if period is None else metrics.short_cells(near, reference, period=period)
    return (float("nan"),) * 2 if found is None else (100 * found.image, 100 * found.reference)


def _cells(near, reference, period):
    """:func:`spectex.metrics.cell_splits` ratio of the near render to the photo as the fit reads it; nan
    without a structure or where either shows no separate cells."""
    from spectex import metrics

    if period is None:
        return float("nan")
    found = metrics.cell_splits(near, reference, period=period)
    return float("nan") if found is None else found.ratio


def metrics_rp(image):
    from spectex import metrics

    return metrics.repeat_peak(image)


def _grid(rows, path):
    """Photo | each method's near render (photo-sized corner) | far views, one row per photo."""
    from PIL import Image, ImageDraw

    cell = 128
    names = ["photo"] + [f"{m} near" for m in METHODS] + ["fit far", "legacy far"]
    pics = []
    for name, photo, made in rows:
        h, w = photo.shape[:2]
        row = [_rgb(photo)]
        for m in METHODS:
            row.append(_rgb(made[m][0][:h, :w]) if made.get(m) else None)
        for m in ("fit", "legacy"):
            row.append(_rgb(made[m][1]) if made.get(m) else None)
        pics.append((name, row))
    width, height = cell * len(names), (cell + 14) * len(pics) + 14
    canvas = Image.new("RGB", (width, height), (255, 255, 255))
    draw = ImageDraw.Draw(canvas)
    for j, n in enumerate(names):
        draw.text((j * cell + 4, 1), n, fill=(0, 0, 0))
    for i, (name, row) in enumerate(pics):
        y = 14 + i * (cell + 14)
        draw.text((4, y), name, fill=(0, 0, 0))
        for j, img in enumerate(row):
            if img is None:
                continue
            im = Image.fromarray((np.clip(img, 0, 1) * 255 + 0.5).astype(np.uint8)).resize((cell - 4, cell - 4),
                                                                                         Image.LANCZOS)
            canvas.paste(im, (j * cell + 2, y + 12))
    path.parent.mkdir(parents=True, exist_ok=True)
    canvas.save(path, quality=75)  # about 280 KB for 8 photos (busy textures compress poorly)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="3 photos at 256 x 256, smaller renders")
    ap.add_argument("--grid", type=Path, default=None, help="write the picture grid here (PNG or JPEG)")
    ap.add_argument("--only", default=None, help="comma-separated photo names, or paths of your own photos")
    ap.add_argument("--methods", default=",".join(METHODS), help="comma-separated methods")
    ap.add_argument("--rng", type=int, default=0)
    args = ap.parse_args(argv)
    methods = [m for m in args.methods.split(",") if m]
    load = os.getloadavg()
    print(f"machine: {cpu_name()}, {os.cpu_count()} CPUs, load average {load[0]:.1f}; "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    sets = exemplars(quick=args.quick)
    if args.only:  # any photo exemplars.load knows, the extra ones too
        # a path (a photo of your own) is shown by its file's stem
        try:
            sets = [(os.path.splitext(os.path.basename(n))[0][:11], load_photo(n)) for n in args.only.split(",") if n]
        except ValueError as exc:  # an unknown name, or a path that is not an image: one line, exit 2
            ap.error(f"--only: {exc}")
    if args.quick:
        sets = [(n, p[:256, :256]) for n, p in sets]
    rows = []
    header = f"{'photo':11s} {'method':9s} {'s 1x':>5s} {'s near':>6s} {'clip%':>6s} {'rp near':>7s} {'rp far':>6s} " \
             f"{'rs near':>7s} {'rs far':>6s} {'brk':>5s} {'cells':>5s} {'short':>5s} {'copies':>7s} {'1off':>5s} " \
             f"{'blot':>6s} " \
             f"{'grain':>6s} {'s':>6s}"
    print(header)
    means = {m: [] for m in methods}
    nears = {m: [] for m in methods}
    for name, photo in sets:
        h, w = photo.shape[:2]
        near_shape = (2 * h, 2 * w)
        far_side = 256 if args.quick else 512
        made = {}
        first = True
        period, straight = _period(photo)
        prepared = {}
        for m in methods:
            out = _make(m, photo, near_shape, far_side, args.rng)
            if out is None:
                continue
            near, far, seconds = out
            made[m] = (near, far)
            r = _measure(photo, near, far, period, straight, prepared)
            means[m].append(r["s 1x"])
            nears[m].append(r["s near"])
            if first:
                print(f"{name:11s} (photo: clip {r['clip photo']:.1f}%, copies own {r['copies photo']:.2f}, "
                      f"rp own {metrics_rp(photo):.3f}"
                      + ("" if straight is photo else f" ({metrics_rp(straight):.3f} as the fit reads it)")
                      + f", structure period {period}, rs own {r['rs photo']:.3f}, short own {r['short'][1]:.0f}%)")
                first = False
            flag = "*" if r["copies flag"] else " "
            print(f"{'':11s} {m:9s} {r['s 1x']:5.2f} {r['s near']:6.2f} {r['clip']:6.1f} {r['rp near']:7.3f} "
                  f"{r['rp far']:6.3f} {r['rs near']:7.3f} {r['rs far']:6.3f} {r['breaks']:5.2f} {r['cells']:5.2f} "
                  f"{r['short'][0]:5.0f} "
                  f"{r['copies']:6.2f}{flag} {r['one-off']:5.2f} {r['blotches'].excess:5.3f}"
                  f"{' ' if r['blotches'].within else '*'} {r['grain'].excess:5.3f}"
                  f"{' ' if r['grain'].within else '*'}"
                  f"{seconds:6.1f}", flush=True)
        rows.append((name, photo, made))
        if args.grid is not None:  # after every photo: a long run stopped early keeps its picture
            _grid(rows, args.grid)
    print("mean s 1x: " + ", ".join(f"{m} {np.mean(v):.2f}" for m, v in means.items() if v))
    print("mean s near: " + ", ".join(f"{m} {np.mean(v):.2f}" for m, v in nears.items() if v))
    if len(means.get("fit", ())) == len(rows):
        # the issue's count: photos where the fit is as close as a peer or closer, at the photo's own place
        # (one set of windows) and over the near render (windows spread over four photo areas)
        for m in methods:
            if m != "fit" and len(means[m]) == len(rows):
                at_1x = sum(f <= p for f, p in zip(means["fit"], means[m]))
                near = sum(f <= p for f, p in zip(nears["fit"], nears[m]))
                print(f"fit at or below {m}: s 1x on {at_1x} of {len(rows)} photos, s near on {near} of {len(rows)}")
    if args.grid is not None:
        print(f"wrote {args.grid}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
