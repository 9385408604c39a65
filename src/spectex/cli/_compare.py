"""``spectex compare``: quality measures of a texture against an exemplar."""

from __future__ import annotations

from . import _common


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "compare",
        help="measure a texture against its exemplar (histograms, band power, copies, tiling)",
        description=(
            "Print the measures of spectex.metrics for image B against exemplar A: per-channel "
            "histogram Wasserstein-1 distance, power per octave band and its RMS distance in dB, "
            "tileability of both, the largest verbatim copy of A in B, repetition of B at A's "
            "period, and with --block the seam energy of a quilt. Grey against colour compares "
            "the colour image's luma."
        ),
    )
    p.add_argument("a", type=_common.existing_file, metavar="A", help="exemplar (reference) image")
    p.add_argument("b", type=_common.existing_file, metavar="B", help="texture to judge")
    p.add_argument("--block", type=_common.positive_int, default=None,
                   help="quilt block size, for the seam energy")
    p.add_argument("--overlap", type=_common.nonneg_int, default=0, help="with --block: quilt overlap, for the seam energy (default: 0)")
    p.add_argument("--json", action="store_true", help="print the measures as JSON")
    p.add_argument("-o", "--output", type=_common.output_name, default=None,
                   help="also write A and B side by side to this image")
    p.set_defaults(func=run)


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


def side_by_side(a, b, gap: int = 8):
    """A and B next to each other on a mid-grey canvas (grey becomes RGB)."""
    import numpy as np

    def rgb(img):
        return np.repeat(img[:, :, None], 3, axis=2) if img.ndim == 2 else img

    a, b = rgb(a), rgb(b)
    h = max(a.shape[0], b.shape[0])
    canvas = np.full((h, a.shape[1] + gap + b.shape[1], 3), 0.5, dtype=np.float32)
    canvas[:a.shape[0], :a.shape[1]] = a
    canvas[:b.shape[0], a.shape[1] + gap:] = b
    return canvas


def run(args) -> int | None:
    import json

    from spectex import metrics
    from spectex.io import IMAGE_SUFFIXES, check_output_path, read_image, write_image

    if args.block is None:
        _common.refuse(args, ["overlap"], "without --block (only to the seam energy of a quilt)")
    _common.require_stdout("the measures would be lost")
    output = (check_output_path("output", args.output, IMAGE_SUFFIXES, inputs=[args.a, args.b])
              if args.output else None)
    from spectex._validate import check_image

    a = check_image("A", read_image(args.a, name="A"))  # errors name A or B, not the metric's argument
    b = check_image("B", read_image(args.b, name="B"))
    a, b = _as_common_channels(a, b)
    result = metrics.compare(a, b, block=args.block, overlap=args.overlap)
    if args.json:  # strict JSON: NaN and infinity (flat images) become null
        print(json.dumps(_finite(result), indent=2, allow_nan=False))
    else:
        _print_table(result, a, b)
    if output is not None:
        write_image(output, side_by_side(a, b))
        _common.report(f"wrote {output}")
    return 0


def _finite(value):
    import math

    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_finite(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _print_table(r, a, b) -> None:
    import math

    def num(v, fmt="{:.4f}"):
        if v is None:
            return "n/a (image too small)"
        if math.isnan(v):
            return "n/a (undefined for a flat image)"
        if math.isinf(v):
            return "infinite"
        return fmt.format(v)

    print(f"A: {a.shape[1]}x{a.shape[0]}   B: {b.shape[1]}x{b.shape[0]}")
    print("histogram W1 per channel   " + "  ".join(num(v) for v in r["histogram_w1"])
          + "   (<= 0.03 is close)")
    if r["bands"] is not None:
        print("band power (dB)     cycles/px      A         B")
        for (lo, hi), pa, pb in zip(r["bands"], r["band_power_reference_db"], r["band_power_image_db"]):
            print(f"                    {lo:.4f}-{hi:.4f}  {num(pa, '{:8.2f}'):>8s}  {num(pb, '{:8.2f}'):>8s}")
    print(f"band power distance        {num(r['band_power_distance_db'], '{:.2f} dB')}   (<= 1.5 dB is close)")
    print(f"tileability A / B          {num(r['tileability_reference'], '{:.2f}')} / "
          f"{num(r['tileability_image'], '{:.2f}')}   (about 1 tiles seamlessly)")
    print(f"verbatim copy of A in B    {num(r['verbatim_copy'])}   (largest region copied with one offset, "
          "fraction of B)")
    print(f"repetition at A's period   {num(r['repetition'])}   (about 0: no tiling of A)")
    if "seam_energy" in r:
        print(f"seam energy                {num(r['seam_energy'], '{:.3f}')}   (about 1: seams like the interior)")
