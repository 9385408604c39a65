"""``spectex tile``: a seamless RGBA tile from noise, or from a photograph."""

from __future__ import annotations

from . import _common

_METHODS = ("spectral", "octaves", "noise")
_ALPHAS = ("emboss", "luminance", "noise", "none", "keep")
_FILTERS = ("box", "tent", "bspline", "catmull-rom", "gaussian")
_SUFFIXES = (".png", ".tif", ".tiff", ".webp", ".npy")


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "tile",
        help="make a seamless RGBA tile (coloured low-pass noise, or a photograph made tileable)",
        description=(
            "Make the seamless, low-pass RGBA tile of a spectral texture: random noise "
            "(--method), coloured through a ramp (--colormap), band-limited to --cutoff cycles "
            "per pixel, with an alpha channel from an emboss filter (Berger's choice), the "
            "luminance, independent noise, or a constant (none). With --from, a photograph is "
            "made tileable instead (Moisan's periodic-plus-smooth decomposition, with the "
            "seams' detail matched to their neighbourhood), cropped about "
            "its centre to --size if given; grey is repeated into RGB, a palette is expanded, "
            "16-bit keeps its precision, and the photograph's own alpha is dropped unless "
            "--alpha keep. --preview also writes NAME_preview.png: the colour repeated 3 x 3 "
            "beside the alpha repeated 3 x 3, to show that the tile is seamless. Options that do not "
            "apply to the chosen method, alpha or source are refused."
        ),
    )
    p.add_argument("--method", choices=_METHODS, default="spectral",
                   help="noise: spectral (FFT 1/f^beta), octaves (sum of magnified octaves) or "
                        "noise (fractal Perlin) (default: spectral)")
    p.add_argument("--alpha", choices=_ALPHAS, default=None,
                   help="alpha channel (default: emboss; none, i.e. opaque, with --from; keep: the "
                        "photograph's own)")
    p.add_argument("--size", type=_common.size, default=None, metavar="N|WxH",
                   help="tile size (default: 512; with --from: the whole photograph)")
    p.add_argument("--seed", type=_common.seed, default=0, help="random seed (default: 0)")
    p.add_argument("--from", dest="source", default=None, metavar="EXEMPLAR",
                   help="make this photograph tileable instead of making noise")
    p.add_argument("--seam", choices=("matched", "moisan"), default="matched",
                   help="with --from: join the wrap edges with detail like their neighbourhood "
                        "(matched) or plain Moisan periodic component (moisan) (default: matched)")
    p.add_argument("--colormap", default="earth",
                   help="colour ramp: earth, stone, sand, moss, marble, wood, clouds, fire, lava, "
                        "ocean, rust, grey, blue or a Matplotlib name (default: earth)")
    p.add_argument("--cutoff", type=_common.positive_float, default=None,
                   help="low-pass cut-off, cycles per pixel, at most 0.5 (default: 0.25; with "
                        "--from: none)")
    p.add_argument("--beta", type=_common.finite_float, default=2.0,
                   help="spectral and octaves: exponent of the noise, power ~ 1/f^beta (default: 2)")
    p.add_argument("--low", type=_common.positive_float, default=None,
                   help="spectral: low cut-off of the noise, cycles per pixel (default: none)")
    p.add_argument("--octaves", type=_common.positive_int, default=None,
                   help="octaves and noise: how many octaves (default: octaves, as many as the tile holds; noise, 6)")
    p.add_argument("--kernel", choices=_FILTERS, default="bspline",
                   help="octaves: magnification kernel that enlarges each octave (default: bspline)")
    p.add_argument("--azimuth", type=_common.finite_float, default=135.0,
                   help="emboss: light direction, degrees counter-clockwise from +x (default: 135)")
    p.add_argument("--strength", type=_common.finite_float, default=1.0,
                   help="emboss: contrast; 1 reaches 0 or 1 at the steepest slope (default: 1)")
    p.add_argument("--alpha-value", type=_common.finite_float, default=None,
                   help="--alpha none: the constant alpha (default: 0.5; with --from: 1)")
    p.add_argument("--bit-depth", type=_common.bit_depth, default=8,
                   help="PNG bits per channel, 8 or 16 (default: 8)")
    _common.add_normalize(p)
    p.add_argument("--preview", action="store_true", help="also write NAME_preview.png (3 x 3 repetition)")
    p.add_argument("-o", "--output", type=_common.output_name, required=True,
                   help="output RGBA image (.png, .tif, .webp, or .npy)")
    p.set_defaults(func=run)


def run(args) -> int | None:
    from spectex._limits import MAX_TILE_SIDE
    from spectex._output import OutputSet
    from spectex._validate import check_shape
    from spectex.io import check_output_path, write_image

    _refuse_unused(args)
    if args.size is not None:  # checked here to name --size (the library says shape=), before numba is imported
        h, w = check_shape("--size", args.size)
        if not 8 <= min(h, w) <= max(h, w) <= MAX_TILE_SIDE:
            raise ValueError(f"--size must be between 8 and {MAX_TILE_SIDE} on each side, got {w}x{h}")
    inputs = [args.source] if args.source is not None else []
    output = check_output_path("output", args.output, _SUFFIXES, inputs=inputs)
    if args.bit_depth == 16 and output.suffix.lower() != ".png":
        raise ValueError(f"--bit-depth 16 needs a .png output, got '{output}'")
    if output.suffix.lower() != ".png":
        _common.refuse(args, ["bit_depth"], f"to {output.suffix or 'this'} output (only to .png)")
    preview = output.with_name(f"{output.stem}_preview.png") if args.preview else None
    # Both files or neither, planned (and checked against the inputs) before the work.
    outputs = (OutputSet(output.parent, [output.name, preview.name], inputs=inputs, create=False)
               if preview is not None else None)
    steps = _common.Steps((3 if args.source is not None else 2) + (preview is not None))
    with steps:
        if args.source is not None:
            steps.step(f"reading {args.source}")
            photo = _common.read_unit_image(args, args.source, "--from image")
            # the tiles' package imports numba: after the photo is read, so that a bad one is refused first
            from spectex.tiles import make_seamless

            steps.step("making it tileable")
            tile = make_seamless(photo, shape=args.size, alpha=args.alpha or "none", cutoff=args.cutoff,
                                 rng=args.seed, seam=args.seam, azimuth=args.azimuth,
                                 strength=args.strength,
                                 alpha_value=1.0 if args.alpha_value is None else args.alpha_value)
            what = f"from {args.source}"
        else:
            if args.alpha == "keep":
                raise ValueError("--alpha keep needs --from EXEMPLAR (a photograph with an alpha channel)")
            from spectex.tiles import make_tile

            steps.step(f"making {args.method} noise")
            tile = make_tile(512 if args.size is None else args.size, rng=args.seed, method=args.method,
                             alpha=args.alpha or "emboss", colormap=args.colormap,
                             cutoff=0.25 if args.cutoff is None else args.cutoff, beta=args.beta,
                             low=args.low, octaves=args.octaves, kernel=args.kernel,
                             azimuth=args.azimuth, strength=args.strength,
                             alpha_value=0.5 if args.alpha_value is None else args.alpha_value)
            what = f"{args.method} noise"
        fmt = output.suffix.lstrip(".").upper()
        if outputs is None:
            steps.step(f"writing {fmt}")
            write_image(output, tile, bit_depth=args.bit_depth)
        else:
            from spectex.tiles import preview as make_preview

            with outputs as stage:
                steps.step("writing the preview")
                write_image(stage / preview.name, make_preview(tile))
                steps.step(f"writing {fmt}")
                write_image(stage / output.name, tile, bit_depth=args.bit_depth)
    h, w = tile.shape[:2]
    cutoff = args.cutoff if args.cutoff is not None else (None if args.source else 0.25)
    band = f", cut-off {cutoff:g} cycles/pixel" if cutoff else ""
    alpha = args.alpha or ("none" if args.source else "emboss")
    _common.report(f"wrote {output} ({w}x{h} RGBA, {what}, alpha {alpha}{band})")
    if preview is not None:
        _common.report(f"wrote {preview} (3x3 colour | 3x3 alpha)")
    return 0


def _refuse_unused(args) -> None:
    """Refuse, in one line, options that would do nothing for this source, method and alpha."""
    if args.source is not None:
        _common.refuse(args, ["method", "colormap", "beta", "low", "octaves", "kernel"],
                       "with --from (a photograph has its own colours and spectrum)")
        alpha = args.alpha or "none"
    else:
        _common.refuse(args, ["seam"], "without --from (noise tiles have no seams to join)")
        _common.refuse(args, ["normalize"], "without --from (noise tiles are made in [0, 1])")
        alpha = args.alpha or "emboss"
        method = args.method
        if method == "noise":
            _common.refuse(args, ["beta"], "to --method noise (only to spectral and octaves)")
        if method != "spectral":
            _common.refuse(args, ["low"], f"to --method {method} (only to spectral)")
        if method == "spectral":
            _common.refuse(args, ["octaves"], "to --method spectral (only to octaves and noise)")
        if method != "octaves":
            _common.refuse(args, ["kernel"], f"to --method {method} (only to octaves)")
    if alpha != "emboss":
        _common.refuse(args, ["azimuth", "strength"], f"to --alpha {alpha} (only to emboss)")
    if alpha != "none":
        _common.refuse(args, ["alpha_value"], f"to --alpha {alpha} (only to none)")
