"""``spectex synth``: texture synthesis from an example image."""

from __future__ import annotations

from . import _common

_METHODS = ("histogram", "efros-leung", "quilting")


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "synth",
        help="synthesise a texture from an example image",
        description=(
            "Synthesise a larger (or tileable) texture from an example image. "
            "Methods: histogram (pixels drawn independently from the exemplar's colours), "
            "efros-leung (pixel by pixel, Efros and Leung 1999), quilting (blocks with "
            "minimum-error cuts, Efros and Freeman 2001). Palette images become RGB (RGBA "
            "with transparency), 16-bit images keep their precision (write them back with "
            "--bit-depth 16), an alpha channel is synthesised like a colour. Options of another "
            "method than the chosen one are refused."
        ),
    )
    p.add_argument("exemplar", type=_common.existing_file, help="example image (PNG, JPEG, ..., or .npy)")
    p.add_argument("--method", choices=_METHODS, default="quilting", help="synthesis method (default: quilting)")
    p.add_argument("--size", type=_common.size, default=(256, 256), metavar="WxH",
                   help="output size (default: 256x256)")
    p.add_argument("--window", type=_common.positive_int, default=11,
                   help="efros-leung: odd neighbourhood size (default: 11)")
    p.add_argument("--exhaustive", action="store_true",
                   help="efros-leung: exact exhaustive search instead of the fast k-coherence search")
    p.add_argument("--block", type=_common.positive_int, default=32, help="quilting: block size (default: 32)")
    p.add_argument("--overlap", type=_common.positive_int, default=None,
                   help="quilting: block overlap (default: block/6)")
    p.add_argument("--tolerance", type=_common.finite_float, default=0.1,
                   help="quilting: relative error tolerance of the block choice (default: 0.1)")
    p.add_argument("--reuse", type=_common.finite_float, default=0.0,
                   help="quilting: penalty on reusing a source block, so that none dominates (default: 0, the "
                        "paper's plain choice; 1: as spectex fit, more variety, stronger seams)")
    p.add_argument("--colours", choices=("joint", "per-channel"), default="joint",
                   help="histogram: keep the joint colour distribution (default) or only each channel's")
    p.add_argument("--match", type=_common.existing_file, default=None, metavar="IMAGE",
                   help="histogram: instead of sampling, give IMAGE the exemplar's histogram exactly "
                        "(its structure and size are kept)")
    p.add_argument("--tileable", action="store_true",
                   help="efros-leung and quilting: make the output tile seamlessly (histogram output, "
                        "white noise, always does)")
    p.add_argument("--seed", type=_common.seed, default=0, help="random seed (default: 0)")
    _common.add_normalize(p)
    p.add_argument("--bit-depth", type=_common.bit_depth, default=8, help="PNG bits per channel, 8 or 16 (default: 8)")
    p.add_argument("-o", "--output", type=_common.output_name, required=True,
                   help="output image (.png, .jpg, .tif, ..., or .npy)")
    p.set_defaults(func=run)


def run(args) -> int | None:
    from spectex import _limits
    from spectex.io import ARRAY_SUFFIXES, IMAGE_SUFFIXES, check_output_path

    output = check_output_path("output", args.output, IMAGE_SUFFIXES + ARRAY_SUFFIXES,
                               inputs=[args.exemplar, args.match])
    if args.bit_depth == 16 and output.suffix.lower() != ".png":
        raise ValueError(f"--bit-depth 16 needs a .png output, got '{output}'")
    if output.suffix.lower() != ".png":
        _common.refuse(args, ["bit_depth"], f"to {output.suffix or 'this'} output (only to .png)")
    if args.match is not None and args.method != "histogram":
        raise ValueError(f"--match works with --method histogram, got --method {args.method}")
    _refuse_unused(args)
    # Every size and cost is checked with the exemplar's size from its header (check_header), before
    # it is decoded or numba is imported, so that a refusal comes at once.
    plan = _plan(args)
    tighter = None if args.method == "histogram" else (
        _limits.SYNTH_EXEMPLAR_PIXELS, f"for {args.method} (SPECTEX_MAX_SYNTH_EXEMPLAR_PIXELS; set it to raise "
                                       "the limit, or crop or shrink the exemplar)")
    exemplar = _common.read_unit_image(args, args.exemplar, "exemplar", max_pixels=tighter,
                                       check_header=plan)
    from spectex import synthesis
    from spectex.io import write_image

    joint = args.colours == "joint"
    if args.match is not None:
        image = _common.read_unit_image(args, args.match, "match image")
        result = synthesis.match_histogram(image, exemplar, joint=joint, rng=args.seed)
    elif args.method == "histogram":
        result = synthesis.sample_histogram(exemplar, args.size, joint=joint, rng=args.seed)
    elif args.method == "efros-leung":
        with _common.Progress("efros-leung") as bar:
            result = synthesis.efros_leung(exemplar, args.size, window=args.window, rng=args.seed,
                                           method="exhaustive" if args.exhaustive else "fast",
                                           tileable=args.tileable, progress=bar)
    else:
        with _common.Progress("quilting") as bar:
            result = synthesis.quilt(exemplar, args.size, block=args.block, overlap=args.overlap,
                                     tolerance=args.tolerance, rng=args.seed, tileable=args.tileable,
                                     reuse=args.reuse, progress=bar)
    write_image(output, result, bit_depth=args.bit_depth)
    h, w = result.shape[:2]
    _common.report(f"wrote {output} ({w}x{h}, {args.method})")
    return 0


def _plan(args):
    """The check of this synthesis's sizes and cost for an exemplar of ``(height, width, channels)`` (from
    its header; the library checks again with the image)."""
    from spectex import _limits
    from spectex._validate import check_float, check_shape

    def plan(exemplar_shape) -> None:
        if args.match is not None:
            return  # the matched image keeps its own size
        if args.method == "histogram":
            check_shape("--size", args.size)
        elif args.method == "quilting":
            check_float("tolerance", args.tolerance, minimum=0.0)
            check_float("reuse", args.reuse, minimum=0.0, maximum=1e6)
            _limits.check_quilting(exemplar_shape, args.size, block=args.block, overlap=args.overlap,
                                   tileable=args.tileable, channels=exemplar_shape[2])
        else:
            _limits.check_efros_leung(exemplar_shape, args.size, window=args.window, k=4,
                                      method="exhaustive" if args.exhaustive else "fast", channels=exemplar_shape[2])
    return plan


def _refuse_unused(args) -> None:
    """Refuse, in one line, options of another method than the chosen one."""
    method = args.method
    if method != "efros-leung":
        _common.refuse(args, ["window", "exhaustive"], f"to --method {method} (only to efros-leung)")
    if method != "quilting":
        _common.refuse(args, ["block", "overlap", "tolerance", "reuse"], f"to --method {method} (only to quilting)")
    if method != "histogram":
        _common.refuse(args, ["colours"], f"to --method {method} (only to histogram)")
    if args.match is not None:
        _common.refuse(args, ["size", "tileable"], "with --match (the matched image keeps its size and structure)")
