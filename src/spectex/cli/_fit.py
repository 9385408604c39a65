"""``spectex fit``: fit a spectral texture to a photograph."""

from __future__ import annotations

from . import _common


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "fit",
        help="fit a spectral texture (tile, layer scales, alpha, colours) to a photograph",
        description=(
            "Analyse a photograph of a texture (power per octave, colour histograms, cross-scale "
            "dependence) and fit a layered spectral texture to it: a seamless tile made from the "
            "photograph for the finest layer (cut at the structure's period for bricks or paving), "
            "coarser layers of their own noise tile that continue its spectrum to larger scales, "
            "and tile colours that give its histograms. The photo is assumed 1.5 m across unless "
            "--photo-size or --pixel-size says otherwise. Writes into DIR: texture.toml, "
            "texture.tile0.png and texture.tile1.png (load with spectex render/view), comparison.png "
            "(exemplar | render at the same scale | render of 8x the area), band_power.png and histograms.png. "
            "Conversions: grey is repeated into RGB, an alpha channel is dropped, 16-bit keeps "
            "its precision, a flat frame around the photo (a border, a rotated photo's wedges) is "
            "cropped away, images over 512 pixels on a side are analysed on their central "
            "512 x 512 crop, resampled first where a crop would hold under 6 periods of their structure "
            "or, without one, under 128 of their grain (said in the output); a resampled photo without "
            "structure gets its tile back at full resolution (up to 2048 texels: --tile-size). Nothing is "
            "written if anything fails."
        ),
    )
    p.add_argument("exemplar", type=_common.existing_file, metavar="EXEMPLAR",
                   help="the exemplar photograph (PNG, JPEG, ..., or .npy)")
    p.add_argument("-o", "--output", type=_common.output_name, required=True, metavar="DIR",
                   help="output folder (made if missing; in an existing folder the six files replace "
                        "the earlier ones only when all are complete, and other files are left alone)")
    scale = p.add_mutually_exclusive_group()
    scale.add_argument("--pixel-size", type=_common.positive_float, default=None,
                       help="world size of one photograph pixel, metres, 1e-6 to 1e5 (default: from "
                            "--photo-size)")
    scale.add_argument("--photo-size", type=_common.positive_float, default=None,
                       help="world width of the photograph's longer side, metres (default: 1.5, a photo of "
                            "ground taken standing; the report says what was assumed)")
    p.add_argument("--layers", type=_common.positive_int, default=5, help="number of layers, 2 to 8 (default: 5)")
    p.add_argument("--ratio", type=_common.positive_float, default=4.0,
                   help="size ratio between neighbouring layers (default: 4)")
    p.add_argument("--opacity", type=_common.positive_float, default=None,
                   help="opacity of the first coarse layer (default: 0.1)")
    p.add_argument("--seed", type=_common.seed, default=0, help="random seed (default: 0)")
    p.add_argument("--max-size", type=_common.positive_int, default=None,
                   help=f"largest side analysed, pixels, {MIN_MAX_SIZE} to {MAX_MAX_SIZE} (default: 512, a 1 MB "
                        "tile; larger keeps more of a large photo at full resolution, in a larger tile, slower)")
    p.add_argument("--tile-size", type=_common.positive_int, default=None,
                   help=f"the finest tile's side, texels, {MIN_TILE_SIZE} to {MAX_TILE_SIZE} (default: the photo as "
                        "analysed, its shorter side up to --max-size; for a photo resampled for its grain, that tile "
                        "at the photo's own resolution, up to 2048: give the analysed size, e.g. 512, for a smaller "
                        "tile without the photo's finest detail)")
    p.add_argument("--keep-one-off", action="store_true",
                   help="keep content the photo shows once (a leaf, a tripod's foot) in the tile; by default it "
                        "is filled from the rest of the photo, since the texture would repeat it everywhere")
    p.add_argument("--keep-lighting", action="store_true",
                   help="keep the photo's lighting (its brightness drifting across it) in the tile; by default "
                        "it is evened out, since every patch of the texture would repeat it as blotches")
    p.add_argument("--keep-perspective", action="store_true",
                   help="keep the perspective of a photo taken at an angle; by default a structured one is "
                        "rectified from its lines and an unstructured one levelled in scale, since patches of its "
                        "near and far sides would meet as blotches of large and small grain")
    _common.add_normalize(p)
    p.set_defaults(func=run)


#: The range of --max-size, pixels: the fit's smallest photo, and a 16 MB tile (bounded work).
MIN_MAX_SIZE, MAX_MAX_SIZE = 32, 2048

#: The range of --tile-size, texels: the fit's smallest photo, and the largest full-resolution tile
#: (``fitting._full.MAX_FULL_TILE``; a quilt that large from a small photo takes seconds, not minutes).
MIN_TILE_SIZE, MAX_TILE_SIZE = 32, 2048

#: The range of --pixel-size, metres (a micrometre to 100 km per pixel).
MIN_PIXEL_SIZE, MAX_PIXEL_SIZE = 1e-6, 1e5

#: The smallest --opacity: below it a layer is invisible in 8 bits (and the fit's search degenerates).
MIN_OPACITY = 1e-3
#: Beyond these the fit is reported as a poor match (``compare`` calls W1 <= 0.03 and <= 1.5 dB close).
POOR_W1, POOR_BAND_DB = 0.1, 6.0

#: The fit's texture has two tiles: the photo's (the finest layer) and the coarse layers' own.
_FILES = ("texture.toml", "texture.tile0.png", "texture.tile1.png", "comparison.png", "band_power.png",
          "histograms.png")


def _plots(folder, exemplar, same, large):
    from spectex.figures import plot_band_power, plot_histograms

    h, w = exemplar.shape[:2]
    big = large[:1024, :1024] if min(large.shape[:2]) >= 1024 else large  # a fast FFT size
    plot_band_power(folder / "band_power.png", [exemplar, same, big],
                    ["exemplar", "render, same scale", "render, 8x the area"], segments=[None, (h, w), None])
    plot_histograms(folder / "histograms.png", [exemplar, same], ["exemplar", "render"])


def _comparison(exemplar, same, large):
    from spectex.figures import montage

    return montage([exemplar, same, large], ["exemplar", "render", "render, 8x the area"], background=1.0)


def _write_fast_png(path, image):
    """An 8-bit PNG with light compression (the comparison is large; the folder is the atomic unit)."""
    from PIL import Image

    from spectex.io import to_uint

    Image.fromarray(to_uint(image, 8)).save(path, format="PNG", compress_level=1)


def run(args) -> int | None:
    import time

    from spectex._output import OutputSet
    from spectex.fitting import (
        MAX_ANALYSIS_SIZE,
        check_options,
        even_lighting,
        fit_result,
        prepare_exemplar,
        report_reference,
    )
    start = time.perf_counter()
    # a denormal opacity ran for minutes (fuzz_hostile)
    if args.opacity is not None and not MIN_OPACITY <= args.opacity <= 1.0:
        raise ValueError(f"--opacity must be between {MIN_OPACITY:g} and 1, got {args.opacity:g}")
    max_size = MAX_ANALYSIS_SIZE if args.max_size is None else args.max_size
    if not MIN_MAX_SIZE <= max_size <= MAX_MAX_SIZE:
        raise ValueError(f"--max-size must be between {MIN_MAX_SIZE} and {MAX_MAX_SIZE} pixels, got {max_size}")
    if args.tile_size is not None and not MIN_TILE_SIZE <= args.tile_size <= MAX_TILE_SIZE:
        raise ValueError(f"--tile-size must be between {MIN_TILE_SIZE} and {MAX_TILE_SIZE} texels, "
                         f"got {args.tile_size}")
    if args.pixel_size is not None and not MIN_PIXEL_SIZE <= args.pixel_size <= MAX_PIXEL_SIZE:
        raise ValueError(f"--pixel-size must be between {MIN_PIXEL_SIZE:g} and {MAX_PIXEL_SIZE:g} metres, "
                         f"got {args.pixel_size:g}")
    # every option before the photo is read (a large one takes seconds)
    check_options(layers=args.layers, ratio=args.ratio, opacity=args.opacity, rng=args.seed)
    # Every file checked before the work (none may be the photo); all six replace the earlier
    # ones only when complete.
    outputs = OutputSet(args.output, _FILES, inputs=[args.exemplar])
    photo = _common.read_unit_image(args, args.exemplar, "EXEMPLAR")
    exemplar, _ = prepare_exemplar(photo, max_size=max_size)
    if not args.keep_lighting:  # measured against the photo as the fit reads it: lighting is not texture
        exemplar, _ = even_lighting(exemplar)
    # The report's measures of the photo alone (its structural floor, its own range for magnified
    # copies: half the report's work) need no texture: made in a second thread while the fit runs
    # (a daemon: a failed fit or Ctrl-C does not wait for it).
    magnifications = _layer_magnifications(args.ratio, args.layers)
    reference = _Background(lambda: report_reference(exemplar, coarse_magnifications=magnifications,
                                                     max_size=max_size))
    from spectex.shading.view import bake_kernel

    _common.say_if_compiling("the CPU renderer the fit bakes its trials with", bake_kernel)
    with _common.Progress("fitting") as bar:
        result = fit_result(photo, pixel_size=args.pixel_size, photo_size=args.photo_size, layers=args.layers,
                            ratio=args.ratio, opacity=args.opacity, rng=args.seed,
                            keep_one_off=args.keep_one_off, keep_lighting=args.keep_lighting,
                            keep_perspective=args.keep_perspective, max_size=max_size, tile_size=args.tile_size,
                            progress=bar)
    return _finish(args, outputs, exemplar, result, reference, magnifications, start, max_size)


def _layer_magnifications(ratio, layers):
    """The magnifications of the photo its coarse layers would show if they drew it (``ratio ** k``),
    those :func:`spectex.metrics.coarse_copies` can search (>= 1.5); None (its default) if none."""
    mags = tuple(ratio ** k for k in range(1, layers) if ratio ** k >= 1.5)
    return mags or None


class _Background:
    """``function()`` in a daemon thread; :meth:`result` waits for its value (or raises its error)."""

    def __init__(self, function):
        import threading

        self._value = self._error = None
        self._thread = threading.Thread(target=self._run, args=(function,), daemon=True)
        self._thread.start()

    def _run(self, function):
        try:
            self._value = function()
        except BaseException as error:  # handed to the caller of result()
            self._error = error

    def result(self):
        self._thread.join()
        if self._error is not None:
            raise self._error
        return self._value


def _finish(args, outputs, exemplar, result, reference, magnifications, start, max_size) -> int:
    """Bake, measure, write and report a finished fit (``reference``: the photo's measures, in a thread)."""
    import math
    import time
    from pathlib import Path

    out = outputs.path
    pixel_size = result.pixel_size
    if not MIN_PIXEL_SIZE <= pixel_size <= MAX_PIXEL_SIZE:
        raise ValueError(f"--photo-size gives a pixel size of {pixel_size:g} m, outside {MIN_PIXEL_SIZE:g} to "
                         f"{MAX_PIXEL_SIZE:g} metres")
    fit_seconds = time.perf_counter() - start
    texture = result.texture
    h, w = exemplar.shape[:2]
    from spectex.render import bake

    side = math.sqrt(8.0)
    large = bake(texture, (16 * round(side * h / 16), 16 * round(side * w / 16)), pixel_size=pixel_size)
    same = large[:h, :w]  # the render at the photo's own place (a bake is the same pixels in any region)
    # the numbers, on the render of 8x the area that comparison.png shows
    from spectex.fitting import fit_report

    # the report's measures in a second thread (it waits for the photo's half), the files meanwhile
    numbers = _Background(lambda: fit_report(texture, exemplar, pixel_size=pixel_size, bake=large,
                                             coarse_magnifications=magnifications, prepared=reference.result(),
                                             max_size=max_size))
    with outputs as stage:
        texture.save(stage / "texture.toml")
        # the scale the fit assumed or was given, as a comment in the texture file itself
        with open(stage / "texture.toml", "a", encoding="utf-8") as fh:
            fh.write(f"\n# spectex fit of {Path(args.exemplar).name}: {result.params['scale']}\n")
        _write_fast_png(stage / "comparison.png", _comparison(exemplar, same, large))
        _plots(stage, exemplar, same, large)
        numbers = numbers.result()  # a failure here leaves nothing written
    for note in result.notes:  # the conversions and the scale assumed
        _common.report(f"note: {note}")
    pr = result.params
    _common.report(f"fitted {len(texture.layers)} layers of a {pr['tile_px']}x{pr['tile_px']} tile from "
                   f"{args.exemplar} in {fit_seconds:.1f} s")
    _common.report(f"  scale: {pr['scale']}")
    _common.report(f"  layer sizes {', '.join(f'{lay.size:.4g}' for lay in texture.layers)} m; opacities "
                   f"{', '.join(f'{o:.3f}' for o in pr['opacities'])}; finest tile: {pr['tile_method']}"
                   + ("; drawn with free cells (its grout's network found: each cell whole from one patch, the "
                      "patches meeting in the grout)" if pr.get("free_cells") else "")
                   + ("; its courses change patch at their joints (each board or brick whole, or ended by a "
                      "joint)" if pr.get("courses") else ""))
    w1 = max(numbers.histogram_w1)
    _common.report(f"  at the exemplar's pixel size, on the render of 8x its area (comparison.png): band power "
                   f"{numbers.band_power_distance_db:.2f} dB RMS, "
                   f"histogram W1 <= {w1:.3f}, cross-scale dependence {numbers.cross_scale_texture:+.2f} "
                   f"(exemplar {numbers.cross_scale_exemplar:+.2f})")
    resampled = None
    why = _resampled_why(result.params)
    if why is not None and numbers.structure is not None:
        # a turned finest layer's texels never fall on the pixels, a finer one's are read from its mip-maps
        # between them: a bilinear resampling, which the structural distance counts as lost detail, weighs
        # less with both halved
        from spectex._pixels import box_halved
        from spectex.metrics import structural_distance

        resampled = (why, structural_distance(box_halved(same), box_halved(exemplar)).ratio)
    repeat = result.params.get("repeat")
    _common.report(_structure_line(numbers, result.params.get("lighting"), result.params.get("level"), resampled,
                                   copy=bool(repeat) and not repeat.get("whole")))
    misses = []
    if w1 > POOR_W1:
        misses.append(f"histogram W1 {w1:.3f} > {POOR_W1}")
    if not numbers.band_power_distance_db <= POOR_BAND_DB:  # NaN counts as a miss
        misses.append(f"band power {numbers.band_power_distance_db:.2f} dB > {POOR_BAND_DB} dB")
    if misses:  # said, not hidden behind "fitted": the files are written for a look, the match is poor
        _common.report(f"  poor match: {'; '.join(misses)}; the texture does not reproduce this exemplar well "
                       "(see comparison.png)")
    _common.report(f"wrote {', '.join(_FILES)} to {out}/")
    return 0


def _resampled_why(params):
    """Why the report's render resamples the finest tile (a clause), or None: drawn turned, or finer than the
    photo as the fit read it (a tile at the photo's full resolution)."""
    if params.get("turn_deg"):
        return f"the finest layer drawn turned by {params['turn_deg']:.1f} degrees: its texels fall between the pixels"
    if params.get("full_resolution"):
        k = params["full_resolution"] // params["analysis_px"]
        return (f"the finest tile {k} times finer than the photo as analysed: read from its mip-maps between the "
                "pixels")
    return None


def _structure_line(numbers, evened=None, levelled=None, resampled=None, copy=False) -> str:
    """The structural measures of the report (issue 22), one line (``evened``, ``levelled``: the fit's
    ``params["lighting"]`` and ``params["level"]``, where it evened the photo's lighting out or levelled
    its perspective; ``resampled``: ``(why, ratio)`` where the render resamples the finest tile
    (:func:`_resampled_why`), the structural distance with render and photo halved; ``copy``: the fit read
    one copy of a photo tiled before it was saved, whose one-off content the photo shows once a copy)."""
    st, far, clip, coarse = numbers.structure, numbers.structure_far, numbers.clipping, numbers.coarse
    if st is None:
        line = "  structure: n/a (the photo holds no two 32x32 windows)"
    else:
        line = (f"  structure {st.ratio:.2f}x the photo's own floor at its place, {far.ratio:.2f}x over 8x its "
                "area (about 1: as close as the photo is to itself)")
        if resampled is not None:
            line += (f" ({resampled[0]}, a resampling the measure counts as lost detail; {resampled[1]:.2f}x with "
                     "both halved)")
        if getattr(st, "copies", 0):
            line += (f" (the photo repeats itself: {st.copies} pairs of its {st.window[1]}x{st.window[0]} windows are "
                     "copies, left out of its floor)")
    line += f"; clipped {100 * clip.image:.1f}% of values (photo {100 * clip.reference:.1f}%)"
    if coarse is not None:
        mags = ", ".join(f"{m:g}" for m, v in zip(coarse.magnifications, coarse.per_magnification) if v == v)
        line += (f"; magnified copies {'none' if coarse.within else 'FOUND'} at {coarse.zoom:g}x zoomed out "
                 f"({coarse.value:.2f}, photo's own {coarse.reference:.2f}; searched {mags}x)")
    if getattr(numbers, "cells", None) is not None:
        line += (f"; bricks or tiles changing colour partway across {numbers.cells.ratio:.2f}x the photo's own "
                 f"({numbers.cells.cells_image} cells)")
    short = getattr(numbers, "short", None)
    if short is not None:
        line += (f"; bricks or tiles cut short {100 * short.image:.0f}% of {short.cells_image} cells (photo "
                 f"{100 * short.reference:.0f}%)")
    if getattr(numbers, "lines", None) is not None:
        line += (f"; lines along {'y' if numbers.lines.axis == 0 else 'x'} holding their places "
                 f"{numbers.lines.ratio:.2f}x the photo's own (under 0.9: they end and go on aside)")
    one_off = getattr(numbers, "one_off", None)
    if one_off is not None and one_off.box is None:
        line += "; one-off content none"
    elif one_off is not None:
        y0, x0, y1, x1 = one_off.box
        line += (f"; one-off content at photo x {x0}-{x1}, y {y0}-{y1} shown {one_off.copies} times over 8x its "
                 "area" + (" (the photo shows it once in each of its copies)" if copy else
                           "" if one_off.within else " (a viewer sees the same object repeated: crop it out of "
                                                     "the photo if it is not part of the texture)"))
    light = getattr(numbers, "lighting", None)
    if light is not None:
        line += (f"; blotches {'none' if light.within else 'SEEN'} at the photo's scale (excess {light.excess:.3f} "
                 f"over the photo's own, threshold {light.threshold:g}; "
                 + (f"the photo's lighting, {100 * evened['rms']:.0f}% RMS, evened out)" if evened else
                    f"the photo's lighting, {100 * light.lighting:.0f}% RMS, kept)" if light.significant else
                    "the photo lit evenly)"))
    grain = getattr(numbers, "scale", None)
    if grain is not None:
        line += (f"; grain scale {'even' if grain.within else 'MIXED'} (excess {grain.excess:.3f} over the "
                 f"photo's own, threshold {grain.threshold:g}"
                 + (f"; the photo taken at an angle, levelled: {levelled['spread']:.2f}-fold across it)" if levelled
                    else f"; the photo taken at an angle, {grain.spread:.2f}-fold across it, kept)" if grain.oblique
                    else ")"))
    return line
