"""``spectex compare``: quality measures of a texture against an exemplar."""

from __future__ import annotations

from . import _common


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "compare",
        help="measure an image against its exemplar (histograms, band power, copies, repetition, tiling)",
        description=(
            "Print the measures of spectex.metrics for IMAGE against the exemplar given with "
            "--reference: per-channel histogram Wasserstein-1 distance, power per octave band and its "
            "RMS distance in dB, tileability of both, the largest verbatim copy of the reference in "
            "IMAGE, how strongly the fine detail of each repeats (repeat_peak, any period and "
            "direction), the structural distance (Portilla-Simoncelli texture statistics) as a "
            "ratio to the exemplar's own floor (about 1: as close as the photo is to itself), the "
            "clipped values against the exemplar's, for a structured exemplar (bricks, floor tiles) how much "
            "its cells change colour partway across against its own, with --zoom a search for magnified "
            "copies of the "
            "exemplar in IMAGE taken as a zoomed-out view, "
            "and with --block the seam energy of a quilt. Grey against colour compares "
            "the colour image's luma."
        ),
    )
    p.add_argument("inputs", type=_common.existing_file, nargs="+", metavar="IMAGE",
                   help="the image to judge")
    p.add_argument("--reference", type=_common.existing_file, default=None, metavar="EXEMPLAR",
                   help="the exemplar (or any reference image) IMAGE is judged against")
    p.add_argument("--block", type=_common.positive_int, default=None,
                   help="quilt block size, for the seam energy")
    p.add_argument("--overlap", type=_common.nonneg_int, default=0,
                   help="with --block: quilt overlap, for the seam energy (default: 0)")
    p.add_argument("--zoom", type=_common.positive_float, default=None,
                   help="IMAGE is a view of a texture at ZOOM times the exemplar's pixel size (>= 1, e.g. 8): "
                        "also search it for the exemplar magnified 2 to 256 times (giant copies)")
    p.add_argument("--json", action="store_true", help="print the measures as JSON")
    _common.add_normalize(p)
    p.add_argument("-o", "--output", type=_common.output_name, default=None,
                   help="also write the reference and IMAGE side by side, labelled, to this image")
    p.set_defaults(func=run)


def _inputs(args):
    """``(image, reference)`` paths: IMAGE --reference EXEMPLAR."""
    from ._common import UsageError

    if len(args.inputs) == 1:
        if args.reference is None:
            raise UsageError("compare needs the exemplar: spectex compare IMAGE --reference EXEMPLAR")
        return args.inputs[0], args.reference
    raise UsageError("compare takes one IMAGE and --reference EXEMPLAR, got "
                     f"{len(args.inputs)} images" + (" and --reference" if args.reference is not None else ""))


def _as_common_channels(a, b):
    """Bring a and b to the same channel count (grey vs colour: luma; alpha dropped)."""
    import numpy as np

    from spectex.color import luma

    def colour(img):
        if img.ndim == 2:
            return img
        return img[:, :, :3] if img.shape[2] >= 3 else img[:, :, 0]

    a, b = colour(a), colour(b)
    if a.ndim != b.ndim:
        a, b = luma(a), luma(b)
    return a.astype(np.float32), b.astype(np.float32)


def run(args) -> int | None:
    import json
    from pathlib import Path

    from spectex import metrics
    from spectex.figures import montage
    from spectex.io import IMAGE_SUFFIXES, check_output_path, write_image

    if args.block is None:
        _common.refuse(args, ["overlap"], "without --block (only to the seam energy of a quilt)")
    image_path, reference_path = _inputs(args)
    _common.require_stdout("the measures would be lost")
    output = (check_output_path("output", args.output, IMAGE_SUFFIXES, inputs=[image_path, reference_path])
              if args.output else None)
    from spectex._validate import check_image

    # errors name IMAGE or the reference, not the metric's argument
    image = check_image("IMAGE", _common.read_unit_image(args, image_path, "IMAGE"))
    reference = check_image("--reference", _common.read_unit_image(args, reference_path, "--reference"))
    image, reference = _as_common_channels(image, reference)
    if args.zoom is not None and args.zoom < 1.0:
        raise ValueError(f"--zoom must be >= 1 (the view's pixel size over the exemplar's), got {args.zoom:g}")
    try:
        result = metrics.compare(image, reference=reference, block=args.block, overlap=args.overlap,
                                 zoom=args.zoom, period=_period(reference))
    except ValueError as exc:
        if args.zoom is None:
            raise
        raise ValueError(f"--zoom {args.zoom:g}: {exc}") from None
    if args.json:  # strict JSON: NaN and infinity (flat images) become null
        print(json.dumps(_finite(result.as_dict()), indent=2, allow_nan=False))
    else:
        _print_table(result, image, reference)
    if output is not None:
        label = f"image: {Path(image_path).name}"
        if result.structure is not None:
            label += f", structure {result.structure.ratio:.2f}x the photo's own"
        labels = [f"reference: {Path(reference_path).name}", label]
        write_image(output, montage([reference, image], labels))
        _common.report(f"wrote {output}")
    return 0


def _period(reference):
    """The reference's structure period where the fit would call it structured (bricks, floor tiles), else None."""
    from spectex.fitting import STRUCTURED_PEAK, structure_peak, structure_period

    if reference.ndim != 3 or min(reference.shape[:2]) < 64 or structure_peak(reference) < STRUCTURED_PEAK:
        return None
    period = structure_period(reference)
    return None if period == (None, None) else period


def _finite(value):
    import math

    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_finite(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _print_structure(st, num) -> None:
    """The structural distance's lines of :func:`_print_table` (``num`` its number format)."""
    if st is None:
        print("structural distance        n/a (the reference needs two 32x32 windows and some texture)")
        return
    print(f"structural distance        {num(st.ratio, '{:.2f}')} x the reference's own floor "
          f"({num(st.distance, '{:.3f}')} / {num(st.floor, '{:.3f}')}; about 1 is as close as the "
          "reference is to itself)")
    if st.copies:
        print(f"  the reference repeats itself: {st.copies} pairs of its {st.window[1]}x{st.window[0]} windows "
              "are copies, left out of its floor")
    print("  per group (x floor)      " + "  ".join(f"{g} {num(v, '{:.2f}')}" for g, v in st.group_ratios.items()))


def _print_cells(r, num) -> None:
    """The cell measures' lines of :func:`_print_table` (a structured reference's bricks or floor tiles)."""
    from spectex import metrics

    if r.cells is not None:
        k = r.cells
        print(f"cells split image / ref.   {num(k.image, '{:.2f}')} / {num(k.reference, '{:.2f}')} = "
              f"{num(k.ratio, '{:.2f}')}x   (bricks, floor tiles changing colour partway across; about 1 is "
              "the reference's own)")
    if r.short is not None:
        k = r.short
        print(f"cells cut short image / ref. {100 * k.image:.0f}% / {100 * k.reference:.0f}%   (bricks, floor tiles "
              f"under {metrics.SHORT_CELL:g} of the reference's median cell; {k.cells_image} / {k.cells_reference} "
              "cells)")


def _print_table(r, image, reference) -> None:
    import math

    def num(v, fmt="{:.4f}"):
        if v is None:
            return "n/a (image too small)"
        if math.isnan(v):
            return "n/a (undefined for a flat image)"
        if math.isinf(v):
            return "infinite"
        return fmt.format(v)

    print(f"image: {image.shape[1]}x{image.shape[0]}   reference: {reference.shape[1]}x{reference.shape[0]}")
    print("histogram W1 per channel   " + "  ".join(num(v) for v in r.histogram_w1)
          + "   (<= 0.03 is close)")
    if r.bands is not None:
        print("band power (dB)     cycles/px      image  reference")
        for (lo, hi), pi, pr in zip(r.bands, r.band_power_image_db, r.band_power_reference_db):
            print(f"                    {lo:.4f}-{hi:.4f}  {num(pi, '{:8.2f}'):>8s}  {num(pr, '{:8.2f}'):>8s}")
    print(f"band power distance        {num(r.band_power_distance_db, '{:.2f} dB')}   (<= 1.5 dB is close)")
    print(f"tileability image / ref.   {num(r.tileability_image, '{:.2f}')} / "
          f"{num(r.tileability_reference, '{:.2f}')}   (about 1 tiles seamlessly)")
    print(f"verbatim copy of reference {num(r.verbatim_copy)}   (largest region copied with one offset, "
          "fraction of the image)")
    print(f"repetition image / ref.    {num(r.repeat_peak_image, '{:.3f}')} / "
          f"{num(r.repeat_peak_reference, '{:.3f}')}   (repeat_peak of the fine detail, any period; "
          "<= 0.1 does not repeat)")
    _print_structure(r.structure, num)
    c = r.clipping
    print(f"clipped values image / ref. {100 * c.image:.1f}% / {100 * c.reference:.1f}%   "
          + ("(within the reference's + 1 point)" if c.within else "(MORE than the reference's + 1 point)"))
    if r.coarse is not None:
        k = r.coarse
        print(f"magnified copies (zoom {k.zoom:g})  {num(k.value, '{:.3f}')} (reference's own "
              f"{num(k.reference, '{:.3f}')}): " + ("none found" if k.within else "FOUND, the reference magnified"))
    _print_cells(r, num)
    if r.lines is not None:
        k = r.lines
        print(f"lines kept image / ref.    {k.image:.2f} / {k.reference:.2f} = {k.ratio:.2f}x   (edges along "
              f"{'y' if k.axis == 0 else 'x'} holding their places through {k.length} pixels; under 0.9 they end "
              "and go on aside)")
    if r.one_off is not None:
        k = r.one_off
        if k.box is None:
            print(f"one-off content            none in the reference (its rarest patch {k.rarity:.1f} <= "
                  f"{k.threshold:g})")
        else:
            y0, x0, y1, x1 = k.box
            print(f"one-off content            reference x {x0}-{x1}, y {y0}-{y1} (rarity {k.rarity:.1f}): shown "
                  f"{k.copies} times ({k.per_photo_area:.2f} per reference area): "
                  + ("at most once" if k.within else "REPEATED, the same object at several places"))
    if r.lighting is not None:
        k = r.lighting
        print(f"blotches image / ref.      {k.view_contrast:.3f} / {k.photo_contrast:.3f}, excess {k.excess:.3f} "
              f"(reference's lighting {100 * k.lighting:.0f}% RMS, divided out): "
              + ("none seen" if k.within else f"SEEN, over {k.threshold:g} (the reference's lighting repeated?)"))
    if r.scale is not None:
        k = r.scale
        print(f"grain scale image / ref.   {k.view_scatter:.3f} / {k.photo_scatter:.3f}, excess {k.excess:.3f} "
              + (f"(reference taken at an angle, {k.spread:.2f}-fold, tilt taken out): " if k.oblique else ": ")
              + ("even" if k.within else f"MIXED, over {k.threshold:g} (large and small grain patch by patch)"))
    if r.seam_energy is not None:
        print(f"seam energy                {num(r.seam_energy, '{:.3f}')}   (about 1: seams like the interior)")
