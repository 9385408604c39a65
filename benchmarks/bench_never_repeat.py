"""Benchmark: textures that never repeat (issue 12), side by side in one run.

For each photograph (scikit-image's brick, grass and gravel, plus moon and
immunohistochemistry; whole 512 x 512 pictures, or ``--crop N`` pixels from
the top-left corner), these textures, all at the photo's pixel size (1):

* ``plain``: the photo made seamless (``spectex.tiles.make_seamless``) and
  tiled, one layer;
* ``t&b``: tiling and blending alone, single scale, in NumPy
  (:func:`tiling_and_blending`: Heitz and Neyret's triangle grid, three
  randomly offset patches per pixel, variance-preserving blend of the
  colours, no Gaussianisation): the issue's 60-line baseline;
* ``hp t&b``: one stochastic layer of the same seamless photo (the shading
  core's histogram-preserving tiling and blending, ``Layer(tiling=
  "stochastic")``, patch 0.5): tiling and blending alone, renderable;
* ``fit periodic``: ``spectex.fit(photo, tiling="periodic", method="legacy")``,
  the fit before stochastic layers (every layer periodic);
* ``fit legacy``: ``spectex.fit(photo, method="legacy")``, the default before
  issue 22 (stochastic layers; a periodic finest layer for a structured photo);
* ``fit``: ``spectex.fit(photo, pixel_size=1)``, the default since issue 22 (a
  stochastic or period-cut finest layer, periodic coarse layers on their own
  noise tile).

Columns:

* ``near``: :func:`spectex.metrics.repeat_peak` of a 2048 x 2048 bake at the
  photo's pixel size; ``far``: of a 1024 x 1024 bake at 8 times the pixel
  size (target for the fit: <= 0.1 both);
* ``band dB``: :func:`spectex.metrics.band_power_distance` between the near
  bake and the photo (target <= 1.5);
* ``slope 8x``: dB per octave (towards coarser scales) of the far bake's
  power over its three coarsest bands (scales of 1/8 to 1/2 of the far
  bake: 8 to 32 times the photo's side), beside ``photo``: the photo's own
  slope over its three coarsest bands. Plain tiling has no power at scales
  above the tile, so its slope falls steeply;
* ``W1``: the largest per-channel histogram distance between the near bake
  and the photo (target <= 0.03);
* ``fit s``: seconds the fit took;
* ``fps``: OpenGL frames per second at 1920 x 1080 (offscreen, llvmpipe
  here; the best of ``--repeats`` runs of 3 frames, the photo's textures'
  runs interleaved), the camera 300 photo pixels up, looking 20 degrees
  down.

Below the table, the cost of stochastic layers in OpenGL as CPU time per
frame (llvmpipe's threads included), each a median over ``--repeats``
interleaved runs: the default fit against the periodic fit, per photo,
and the paper's five layers (``SpectralTexture.paper_preset(rng=1)``)
stochastic against periodic at the demo's ground view (``spectex demo``:
2.5 m up, looking 9 degrees down), with trilinear filtering alone (issue
12's target, at most 3 times, was set so) and with the renderer's default
anisotropic filter (8 taps at most; each tap of a stochastic layer reads
three patches and four table texels, so the ratio nears that cost ratio).

Run from the repository root::

    python benchmarks/bench_never_repeat.py [--crop 128] [--patch 0.25] [--repeats 4] [--gl-only]

The machine's load is printed with the numbers.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from spectex.render import bake

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _machine import cpu_name  # noqa: E402

PHOTOS = ("brick", "grass", "gravel", "moon", "immunohistochemistry")


def _bilinear_repeat(level: np.ndarray, s: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Bilinear sample of ``level`` (h, w, C) at tile coordinates (s, t), wrapping (texel centres at halves)."""
    h, w = level.shape[:2]
    u = s * w - 0.5
    v = t * h - 0.5
    i0 = np.floor(u).astype(np.int64)
    j0 = np.floor(v).astype(np.int64)
    a = (u - i0)[..., None].astype(np.float32)
    b = (v - j0)[..., None].astype(np.float32)
    i1, j1 = (i0 + 1) % w, (j0 + 1) % h
    i0, j0 = i0 % w, j0 % h
    return ((1 - a) * (1 - b) * level[j0, i0] + a * (1 - b) * level[j0, i1]
            + (1 - a) * b * level[j1, i0] + a * b * level[j1, i1])


def _hash_offsets(i: np.ndarray, j: np.ndarray, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Per grid vertex a random offset in [0, 1)^2 (a splitmix-style integer hash)."""
    x = (i.astype(np.int64).astype(np.uint64) * np.uint64(0x9E3779B97F4A7C15)
         ^ j.astype(np.int64).astype(np.uint64) * np.uint64(0xC2B2AE3D27D4EB4F)
         ^ np.uint64(seed) * np.uint64(0x165667B19E3779F9))
    x ^= x >> np.uint64(31)
    x *= np.uint64(0xBF58476D1CE4E5B9)
    x ^= x >> np.uint64(29)
    return ((x & np.uint64(0xFFFFFFFF)).astype(np.float64) / 2.0 ** 32,
            (x >> np.uint64(32)).astype(np.float64) / 2.0 ** 32)


def tiling_and_blending(tile: np.ndarray, shape, *, pixel_size: float = 1.0, patch: float = 0.25,
                        seed: int = 0) -> np.ndarray:
    """Single-scale tiling and blending of a seamless tile, in NumPy (the baseline).

    Output pixel ``(r, c)`` is at tile coordinates ``((c + 1/2) p / w, (r +
    1/2) p / h)`` for a pixel size ``p`` in tile texels. The plane is cut
    into equilateral triangles of side ``patch`` tiles (a skewed grid);
    each vertex gets a random offset; a pixel blends the three patches of
    its triangle's vertices with its barycentric weights ``w_i`` as
    ``mu + sum w_i (T_i - mu) / sqrt(sum w_i^2)`` (``mu`` the tile's mean),
    which keeps the variance but not the histogram's shape. Coarser pixels
    (``p > 1``) sample the tile's mip level ``round(log2 p)`` bilinearly.
    """
    from spectex.tiles import mip_chain

    h, w = tile.shape[:2]
    rows, cols = shape
    level = mip_chain(tile)[max(0, int(round(math.log2(pixel_size))))] if pixel_size > 1 else tile
    mu = tile.reshape(-1, tile.shape[2]).mean(axis=0)
    r, c = np.mgrid[0:rows, 0:cols]
    s = (c + 0.5) * pixel_size / w
    t = (r + 0.5) * pixel_size / h
    kx = (s - t / math.sqrt(3.0)) / patch
    ky = (2.0 * t / math.sqrt(3.0)) / patch
    ci, cj = np.floor(kx), np.floor(ky)
    fx, fy = kx - ci, ky - cj
    lower = fx + fy < 1.0
    verts = ((np.where(lower, ci, ci + 1), np.where(lower, cj, cj + 1), np.where(lower, 1 - fx - fy, fx + fy - 1)),
             (np.where(lower, ci + 1, ci), np.where(lower, cj, cj + 1), np.where(lower, fx, 1 - fx)),
             (np.where(lower, ci, ci + 1), np.where(lower, cj + 1, cj), np.where(lower, fy, 1 - fy)))
    acc = np.zeros((rows, cols, tile.shape[2]), dtype=np.float64)
    norm = np.zeros((rows, cols), dtype=np.float64)
    for vi, vj, wt in verts:
        ox, oy = _hash_offsets(vi, vj, seed)
        acc += wt[..., None] * (_bilinear_repeat(level, s + ox, t + oy) - mu)
        norm += wt * wt
    return np.clip(mu + acc / np.sqrt(norm)[..., None], 0.0, 1.0).astype(np.float32)


def _slope(power_db: np.ndarray) -> float:
    tail = power_db[-3:]
    return float(np.polyfit(np.arange(len(tail), dtype=np.float64), tail, 1)[0])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--crop", type=int, default=512, help="photo side in pixels (default 512, whole)")
    ap.add_argument("--patch", type=float, default=0.25, help="t&b triangle side in tiles (default 0.25)")
    ap.add_argument("--photos", default=",".join(PHOTOS))
    ap.add_argument("--repeats", type=int, default=4, help="interleaved GL timing runs (default 4)")
    ap.add_argument("--gl-only", action="store_true", help="only the paper preset's GL frame ratio")
    ap.add_argument("--cells-only", action="store_true",
                    help="only the GL frame of snapped fits (tiles, brick) with their cells against without")
    ap.add_argument("--coarse-blend-only", action="store_true",
                    help="only the default fits' GL frame with the coarse layers overlaid against alpha-blended")
    ap.add_argument("--free-cells-only", action="store_true",
                    help="only the GL frame of paving's fit with its free cells (cobbles) against without")
    ap.add_argument("--courses-only", action="store_true",
                    help="only the GL frame of planks' fit with its course map (boards) against without")
    ap.add_argument("--fit-frame-only", action="store_true",
                    help="only the GL frame of the default and legacy fits of gravel against its periodic fit, "
                         "at anisotropy 1 and 8")
    args = ap.parse_args(argv)

    import skimage.data

    from spectex.fitting import fit, prepare_exemplar
    from spectex.metrics import band_power, band_power_distance, histogram_w1, repeat_peak
    from spectex.render.gl import gl_available
    from spectex.texture import Layer, SpectralTexture
    from spectex.tiles import make_seamless

    gl = gl_available()
    frame_ratio: dict = {}

    load = os.getloadavg()
    print(f"machine: {cpu_name()}, {os.cpu_count()} CPUs, "
          f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    if (args.gl_only or args.cells_only or args.coarse_blend_only or args.fit_frame_only or args.free_cells_only
            or args.courses_only):
        if gl:
            (_cells_ratio if args.cells_only else _coarse_blend_ratio if args.coarse_blend_only
             else _fit_frame_ratio if args.fit_frame_only else _free_cells_ratio if args.free_cells_only
             else _courses_ratio if args.courses_only else _paper_ratio)(args.repeats)
        return 0
    print(f"photos cropped to {args.crop} x {args.crop}; near: 2048^2 at the photo's pixel size, "
          f"far: 1024^2 at 8x; t&b patch {args.patch} tiles")
    head = (f"{'photo':<22}{'texture':<14}{'near':>7}{'far':>7}{'band dB':>8}{'slope 8x':>9}{'photo':>7}{'W1':>7}"
            f"{'fit s':>7}{'fps':>7}")
    print(head)
    print("-" * len(head))
    for name in args.photos.split(","):
        photo, _ = prepare_exemplar(getattr(skimage.data, name)()[:args.crop, :args.crop])
        h, w = photo.shape[:2]
        photo_slope = _slope(band_power(photo)[1])
        tile = make_seamless(photo)[:, :, :3]
        rows = []
        plain = SpectralTexture.plain(tile, float(w))
        rows.append(("plain", bake(plain, (2048, 2048)), bake(plain, (1024, 1024), pixel_size=8.0), "", plain))
        rows.append(("t&b", tiling_and_blending(tile, (2048, 2048), patch=args.patch),
                     tiling_and_blending(tile, (1024, 1024), pixel_size=8.0, patch=args.patch), "", None))
        hp = SpectralTexture(tile, [Layer(size=float(w), tiling="stochastic")])
        rows.append(("hp t&b", bake(hp, (2048, 2048)), bake(hp, (1024, 1024), pixel_size=8.0), "", hp))
        for label, kwargs in (("fit periodic", {"tiling": "periodic", "method": "legacy"}),
                              ("fit legacy", {"method": "legacy"}), ("fit", {"pixel_size": 1.0})):
            try:
                t0 = time.perf_counter()
                tex = fit(photo, **kwargs)
                secs = f"{time.perf_counter() - t0:7.1f}"
            except TypeError as exc:  # a spectex without the tiling option
                print(f"{name:<22}{label:<14}skipped: {exc}")
                continue
            rows.append((label, bake(tex, (2048, 2048)), bake(tex, (1024, 1024), pixel_size=8.0), secs, tex))
        timed = {label: tex for label, _, _, _, tex in rows if tex is not None}
        frames = _gl_frames(timed, args.repeats) if gl else {}
        for label, near, far, secs, _tex in rows:
            fps = f"{1.0 / np.min(frames[label][0]):7.1f}" if label in frames else ""
            print(f"{name:<22}{label:<14}{repeat_peak(near):7.3f}{repeat_peak(far):7.3f}"
                  f"{band_power_distance(near, photo):8.2f}{_slope(band_power(far)[1]):9.2f}{photo_slope:7.2f}"
                  f"{float(np.max(histogram_w1(near, photo))):7.3f}{secs:>7}{fps:>7}", flush=True)
        if "fit" in frames and "fit periodic" in frames:
            frame_ratio[name] = tuple(float(np.median(frames[a][1] / frames["fit periodic"][1]))
                                      for a in ("fit", "fit legacy"))
    if frame_ratio:
        print("\nGL CPU time per frame over the periodic fit's, median of interleaved runs, fit (issue 22: a "
              "stochastic finest layer, periodic coarse layers) and the legacy fit (stochastic layers): "
              + ", ".join(f"{k} {r[0]:.2f} / {r[1]:.2f}" for k, r in frame_ratio.items())
              + " (target: fit <= legacy)")
    if gl:
        _paper_ratio(args.repeats)
        _cells_ratio(args.repeats)
    load = os.getloadavg()
    print(f"load average at the end {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    return 0


def _gl_frames(textures: dict, repeats: int, camera=None, frames: int = 3, anisotropy=None,
               without_free_cells=(), switch=None) -> dict:
    """Per texture, (wall seconds, CPU seconds) per 1920 x 1080 frame of each of ``repeats`` runs.

    The textures' runs are interleaved (one run of each, then the next
    round), so that they share the machine's load alike; CPU time includes
    llvmpipe's threads. The default camera: 300 photo pixels up, looking
    20 degrees down. ``anisotropy``: the renderer's maximum anisotropy (None:
    its default, 8). ``without_free_cells``: the labels whose renderers are made
    without their tiles' free cell maps (``spectex.shading._cells.free_cell_map``
    answering None meanwhile), made within ``switch()`` (a context manager of ``_switches``, default
    ``without_free_cells``).
    """
    from spectex.render import Camera
    from spectex.render.gl import create_context

    kw = {} if anisotropy is None else {"anisotropy": anisotropy}
    ctx = create_context()
    renderers = {}
    try:
        for label, texture in textures.items():
            cam = camera
            if cam is None:
                size = float(texture.layers[0].size) / texture.tile_shape[1]  # metres per tile texel
                cam = Camera((0.0, 0.0, 300.0 * size), yaw=35.0, pitch=-20.0, fov=60.0)
            r = _renderer(texture, ctx, label in without_free_cells, switch)
            renderers[label] = (r, cam)
            r.time_frames(cam, (1080, 1920), frames=1, **kw)  # compiles the programs
        out = {label: ([], []) for label in renderers}
        for _ in range(max(1, int(repeats))):
            for label, (r, cam) in renderers.items():
                c0 = time.process_time()
                wall = r.time_frames(cam, (1080, 1920), frames=frames, **kw)
                out[label][0].append(wall)
                out[label][1].append((time.process_time() - c0) / (frames + 1))  # and one warm-up frame
        return {label: (np.array(w), np.array(c)) for label, (w, c) in out.items()}
    finally:
        for r, _ in renderers.values():
            r.release()
        ctx.release()


def _renderer(texture, ctx, without_free_cells, switch=None):
    """A GLRenderer of ``texture``, its resources made without free cell maps (or within ``switch()``) where
    asked."""
    from _switches import without_free_cells as switched_off

    from spectex.render.gl import GLRenderer

    if not without_free_cells:
        return GLRenderer(texture, ctx=ctx)
    with (switch or switched_off)():
        return GLRenderer(texture, ctx=ctx)


def _free_cells_ratio(repeats: int) -> None:
    """The default fit of ``exemplars.py``'s paving (cobbles: an unsnapped finest layer whose tile has a free
    cell map) with its free cells against without (each point then reads three cells' entries more), GL CPU
    time per frame at two views (40 and 300 texels up)."""
    from exemplars import load as load_photo

    from spectex.fitting import fit
    from spectex.render import Camera

    tex = fit(load_photo("paving"), pixel_size=1.0)
    size = float(tex.layers[0].size) / tex.tile_shape[1]  # metres per tile texel
    for view, cam in (("close", Camera((0.0, 0.0, 40.0 * size), yaw=35.0, pitch=-30.0, fov=60.0)),
                      ("300 px up", Camera((0.0, 0.0, 300.0 * size), yaw=35.0, pitch=-20.0, fov=60.0))):
        frames = _gl_frames({"cells": tex, "blend": tex}, repeats, camera=cam, without_free_cells=("blend",))
        a, b = frames["cells"][1], frames["blend"][1]
        load = os.getloadavg()
        print(f"GL CPU time per frame, paving fit, {view}, 1920 x 1080: free cells {np.median(a) * 1e3:.1f} ms, "
              f"without {np.median(b) * 1e3:.1f} ms, ratio {np.median(a / b):.2f} (runs: "
              f"{', '.join(f'{v:.2f}' for v in a / b)}; load {load[0]:.2f})", flush=True)


def _courses_ratio(repeats: int) -> None:
    """The default fit of ``exemplars.py``'s planks (boards: a finest layer snapped across its courses whose tile
    has a course map) drawn with its course map against without (the triangle grid's blend: three fetches a
    tap, where the courses read up to 8 map entries and one texel), GL CPU time per frame at two views (40 and
    300 texels up)."""
    from _switches import without_courses
    from exemplars import load as load_photo

    from spectex.fitting import fit
    from spectex.render import Camera

    tex = fit(load_photo("planks"), pixel_size=1.0)
    size = float(tex.layers[0].size) / tex.tile_shape[1]  # metres per tile texel
    for view, cam in (("close", Camera((0.0, 0.0, 40.0 * size), yaw=35.0, pitch=-30.0, fov=60.0)),
                      ("300 px up", Camera((0.0, 0.0, 300.0 * size), yaw=35.0, pitch=-20.0, fov=60.0))):
        frames = _gl_frames({"courses": tex, "blend": tex}, repeats, camera=cam, without_free_cells=("blend",),
                            switch=without_courses)
        a, b = frames["courses"][1], frames["blend"][1]
        load = os.getloadavg()
        print(f"GL CPU time per frame, planks fit, {view}, 1920 x 1080: courses {np.median(a) * 1e3:.1f} ms, "
              f"without {np.median(b) * 1e3:.1f} ms, ratio {np.median(a / b):.2f} (runs: "
              f"{', '.join(f'{v:.2f}' for v in a / b)}; load {load[0]:.2f})", flush=True)


def _fits_side_by_side(names, variant, labels, repeats: int) -> None:
    """Per photo of ``names`` (``exemplars.py``), its default fit against ``variant(fit)`` (``(texture, note)``,
    or None: skipped), GL CPU time per 1920 x 1080 frame, interleaved, at two views (40 and 300 texels up);
    ``labels``: how the two are named in the printed line."""
    from exemplars import load as load_photo

    from spectex.fitting import fit
    from spectex.render import Camera

    for name in names:
        tex = fit(load_photo(name), pixel_size=1.0)
        made = variant(tex)
        if made is None:
            print(f"{name}: no {labels[1]} variant of its fit; skipped")
            continue
        other, note = made
        size = float(tex.layers[0].size) / tex.tile_shape[1]  # metres per tile texel
        for view, cam in (("close", Camera((0.0, 0.0, 40.0 * size), yaw=35.0, pitch=-30.0, fov=60.0)),
                          ("300 px up", Camera((0.0, 0.0, 300.0 * size), yaw=35.0, pitch=-20.0, fov=60.0))):
            frames = _gl_frames({"this": tex, "other": other}, repeats, camera=cam)
            a, b = frames["this"][1], frames["other"][1]
            load = os.getloadavg()
            print(f"GL CPU time per frame, {name} fit{note}, {view}, 1920 x 1080: {labels[0]} "
                  f"{np.median(a) * 1e3:.1f} ms, {labels[1]} {np.median(b) * 1e3:.1f} ms, ratio "
                  f"{np.median(a / b):.2f} (runs: {', '.join(f'{v:.2f}' for v in a / b)}; load {load[0]:.2f})",
                  flush=True)


def _cells_ratio(repeats: int) -> None:
    """Snapped fits (the procedural tiles floor, scikit-image's brick wall), their finest layer drawn with its
    structural cells (issue 22: a whole floor tile from one patch, one fetch of the Gaussian tile inside a
    cell) against the same texture with the layer's snap off (the triangle grid's three patches everywhere,
    the shader's code and cost before the cells): GL CPU time per frame, two views each."""
    import dataclasses

    from spectex.texture import SpectralTexture

    def plain(tex):
        if tuple(tex.layers[0].snap) == (0, 0):
            return None  # the fit did not snap its finest layer
        return (SpectralTexture(tex.tiles, [dataclasses.replace(tex.layers[0], snap=(0, 0)), *tex.layers[1:]],
                                bits=tex.bits), f" (snap {tuple(tex.layers[0].snap)})")

    _fits_side_by_side(("tiles", "brick"), plain, ("with cells", "without"), repeats)


def _coarse_blend_ratio(repeats: int) -> None:
    """Default fits (gravel, the tiles floor), their coarse layers overlaying the finest one (issue 22, since
    2026-11-26) against the same texture with the coarse layers alpha-blended (the code before): GL CPU time
    per frame, two views each."""
    import dataclasses

    from spectex.texture import SpectralTexture

    def veiled(tex):
        return (SpectralTexture(tex.tiles, [tex.layers[0], *(dataclasses.replace(layer, blend="alpha")
                                                             for layer in tex.layers[1:])], bits=tex.bits), "")

    _fits_side_by_side(("gravel", "tiles"), veiled, ("coarse layers overlaid", "alpha-blended"), repeats)


def _fit_frame_ratio(repeats: int) -> None:
    """Gravel's default fit (issue 22: a stochastic finest layer, periodic coarse layers) and its legacy fit
    (every layer stochastic) against its periodic fit, GL CPU time per frame at two views (40 and 300 texels
    up), with trilinear filtering alone and with the renderer's default anisotropic filter: the issue's
    target, the fit's frame no dearer than stochastic layers'."""
    from exemplars import load as load_photo

    from spectex.fitting import fit
    from spectex.render import Camera

    photo = load_photo("gravel")
    textures = {"fit": fit(photo, pixel_size=1.0), "legacy": fit(photo, method="legacy", pixel_size=1.0),
                "periodic": fit(photo, tiling="periodic", method="legacy", pixel_size=1.0)}
    for anisotropy in (1.0, None):
        for view, up, pitch in (("close", 40.0, -30.0), ("300 px up", 300.0, -20.0)):
            cams = {}
            for label, tex in textures.items():
                size = float(tex.layers[0].size) / tex.tile_shape[1]  # metres per tile texel
                cams[label] = Camera((0.0, 0.0, up * size), yaw=35.0, pitch=pitch, fov=60.0)
            # the three fits' tiles have the photo's pixel as their texel, so one camera serves them
            frames = _gl_frames(textures, repeats, camera=cams["fit"], anisotropy=anisotropy)
            per = frames["periodic"][1]
            load = os.getloadavg()
            print(f"GL CPU time per frame, gravel, {view}, 1920 x 1080, anisotropy "
                  f"{'1' if anisotropy else '8 (default)'}: periodic fit {np.median(per) * 1e3:.1f} ms, "
                  + ", ".join(f"{k} {np.median(frames[k][1]) * 1e3:.1f} ms ({np.median(frames[k][1] / per):.2f} "
                              "times)" for k in ("fit", "legacy"))
                  + f" (target: fit <= legacy; load {load[0]:.2f})", flush=True)


def _paper_ratio(repeats: int) -> None:
    """The paper's five layers, stochastic against periodic, at the demo's ground view (GL CPU time per frame),
    with trilinear filtering alone (anisotropy 1: issue 12's target of at most 3 times was set so) and with
    the renderer's default anisotropic filter (8 taps at most): each tap of a stochastic layer reads three
    patches and four table texels where a periodic one reads one sample, so the ratio grows towards their
    cost ratio as taps take over the frame."""
    from spectex.render import Camera
    from spectex.texture import SpectralTexture

    camera = Camera((0.0, 0.0, 2.5), yaw=35.0, pitch=-9.0, fov=60.0)
    paper = {"blend": "alpha", "detail": False}  # the paper's five layers, as documented
    textures = {"periodic": SpectralTexture.paper_preset(rng=1, **paper),
                "stochastic": SpectralTexture.paper_preset(rng=1, tiling="stochastic", **paper)}
    for anisotropy, words in ((1.0, "anisotropy 1 (trilinear)"), (None, "the default anisotropy 8")):
        frames = _gl_frames(textures, repeats, camera=camera, anisotropy=anisotropy)
        per, sto = frames["periodic"][1], frames["stochastic"][1]
        load = os.getloadavg()
        target = "target <= 3" if anisotropy == 1.0 else "issue 12's target was set at anisotropy 1"
        print(f"GL CPU time per frame, paper preset at the demo's ground view, 1920 x 1080, {words}: periodic "
              f"{np.median(per) * 1e3:.1f} ms, stochastic {np.median(sto) * 1e3:.1f} ms, ratio "
              f"{np.median(sto / per):.2f} (runs: {', '.join(f'{v:.2f}' for v in sto / per)}; {target}; "
              f"load {load[0]:.2f})", flush=True)


if __name__ == "__main__":
    raise SystemExit(main())
