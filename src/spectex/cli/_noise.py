"""``spectex noise``: procedural noise and textures to an image, array or animation."""

from __future__ import annotations

from . import _common

KINDS = ("perlin", "value", "fbm", "turbulence", "marble", "wood", "stripes", "clouds")


def register(sub) -> None:
    p = sub.add_parser(
        "noise",
        help="write an image (or animation) of procedural noise",
        description="Procedural noise and textures: Perlin and value noise, their fractal sums (fbm), "
                    "turbulence, marble, wood, stripes and clouds, coloured through a ramp. Options that "
                    "do not apply to the chosen kind (--octaves for perlin and value; --lacunarity, "
                    "--gain and --basis for all but fbm and turbulence) are refused.",
    )
    p.add_argument("kind", choices=KINDS, help="what to draw")
    p.add_argument("--size", type=_common.size, default=(512, 512), metavar="WxH",
                   help="image size in pixels (default 512x512)")
    p.add_argument("--scale", type=_common.positive_float, default=4.0,
                   help="noise lattice cells across the image width (default 4)")
    p.add_argument("--octaves", type=_common.positive_int, default=6,
                   help="fractal octaves: all kinds but perlin and value (default 6)")
    p.add_argument("--lacunarity", type=_common.positive_float, default=2.0,
                   help="fbm and turbulence: frequency ratio between octaves (default 2)")
    p.add_argument("--gain", type=_common.positive_float, default=0.5,
                   help="fbm and turbulence: amplitude ratio between octaves (default 0.5)")
    p.add_argument("--basis", choices=("perlin", "value"), default="perlin",
                   help="fbm and turbulence: the noise summed (default perlin)")
    p.add_argument("--seed", type=_common.seed, default=0, help="random seed (default 0)")
    p.add_argument("--tileable", action="store_true", help="make the image tile seamlessly")
    p.add_argument("--colormap", default=None, metavar="NAME",
                   help="colour ramp: grey, earth, stone, sand, moss, marble, wood, clouds, fire, lava, "
                        "ocean, rust, blue, or any Matplotlib colormap (default: grey, or the kind's own)")
    p.add_argument("--bit-depth", type=_common.bit_depth, default=8, help="PNG bits per channel, 8 or 16 (default 8)")
    p.add_argument("--frames", type=_common.positive_int, default=None,
                   help="write an animation of N frames (slices of 3-D noise) to .gif or .mp4")
    p.add_argument("--speed", type=_common.finite_float, default=0.05,
                   help="with --frames: lattice units moved per frame (default 0.05)")
    p.add_argument("--fps", type=_common.positive_float, default=24.0,
                   help="with --frames: frames per second (default 24)")
    p.add_argument("-o", "--output", type=_common.output_name, required=True, metavar="PATH",
                   help=".png, .jpg, .tif, .npy (raw floats), or .gif/.mp4 with --frames")
    p.set_defaults(func=run)


_DEFAULT_COLORMAPS = {"marble": "marble", "wood": "wood", "clouds": "clouds"}


def run(args) -> int:
    from pathlib import Path

    import numpy as np

    from .. import io, procedural

    out = Path(args.output)
    suffix = out.suffix.lower()
    animated = suffix in io.ANIMATION_SUFFIXES
    if animated and args.frames is None:
        raise _common_error(f"--frames is needed for {suffix} output, got none")
    if args.frames is not None and not animated:
        raise _common_error(f"--frames needs a .gif or .mp4 output, got '{out}'")
    io.check_output_path("output", out, io.ANIMATION_SUFFIXES if animated
                         else io.IMAGE_SUFFIXES + io.ARRAY_SUFFIXES)
    _refuse_unused(args, suffix)
    h, w = args.size
    if suffix == ".mp4":
        io.check_mp4_size(h, w)
    if args.kind in ("fbm", "turbulence") and 1 < args.octaves <= 32:  # more: the library says so
        import math

        top = (args.octaves - 1) * math.log10(args.lacunarity)
        if abs(top) > 300:
            raise _common_error(f"--lacunarity {args.lacunarity:g} with --octaves {args.octaves} gives a finest "
                                f"octave of 1e{top:.0f} times the first, beyond floating point: choose a "
                                "lacunarity nearer 2 or fewer octaves")
    limit = 1 << 26
    if h * w * (args.frames or 1) > limit:
        raise _common_error(f"--size {w}x{h} with {args.frames or 1} frame(s) is over the limit of "
                            f"{limit} pixels in all")
    params = _params(args)
    if args.kind == "wood" and args.tileable:
        raise _common_error("--tileable does not apply to wood (its rings are radial)")
    cmap = args.colormap or _DEFAULT_COLORMAPS.get(args.kind, "grey")
    if args.colormap is not None:
        from ..color import get_ramp

        get_ramp(args.colormap)  # fail early on an unknown name
    fmt = suffix.lstrip(".").upper() or "image"
    if animated:
        with _common.Steps(3) as steps:
            steps.step(f"computing {args.frames} frames of {args.kind}")
            frames = procedural.animate(args.kind, (h, w), args.frames, speed=args.speed, **params)
            steps.step("colouring")
            vrange = procedural.contrast_range(frames[0], kind=args.kind)
            images = [procedural.colorize(f, cmap, kind=args.kind, vrange=vrange) for f in frames]
            steps.step(f"writing {fmt}")
            io.write_animation(out, images, fps=args.fps)
        _common.report(f"wrote {out} ({args.frames} frames, {w}x{h})")
        return 0
    with _common.Steps(2 if suffix == ".npy" else 3) as steps:
        steps.step(f"computing {args.kind} {w}x{h}")
        field = procedural.texture(args.kind, (h, w), **params)
        if suffix == ".npy":
            steps.step("writing NPY")
            io.write_image(out, field)
        else:
            steps.step("colouring")
            if args.colormap is None and cmap == "grey":
                lo, hi = procedural.contrast_range(field, kind=args.kind)
                image = np.clip((field - lo) / (hi - lo), 0.0, 1.0)
            else:
                image = procedural.colorize(field, cmap, kind=args.kind)
            del field
            steps.step(f"writing {fmt}")
            io.write_image(out, image, bit_depth=args.bit_depth)
    _common.report(f"wrote {out} ({w}x{h})")
    return 0


def _refuse_unused(args, suffix: str) -> None:
    """Refuse, in one line, options that would do nothing for this kind and output."""
    kind = args.kind
    if kind in ("perlin", "value"):
        _common.refuse(args, ["octaves"], f"to {kind} (one octave; fbm sums several)")
    if kind not in ("fbm", "turbulence"):
        _common.refuse(args, ["lacunarity", "gain", "basis"], f"to {kind} (only to fbm and turbulence)")
    if args.frames is None:
        _common.refuse(args, ["speed", "fps"], "without --frames (only to animations)")
    if suffix != ".png":
        _common.refuse(args, ["bit_depth"], f"to {suffix or 'this'} output (only to .png)")
    if suffix == ".npy":
        _common.refuse(args, ["colormap"], "to .npy output (the raw noise values, not colours)")


def _params(args) -> dict:
    kind = args.kind
    params = {"seed": args.seed}
    if kind != "wood":
        params["tileable"] = args.tileable
    params["scale"] = args.scale
    if kind in ("perlin", "value"):
        return params
    params["octaves"] = args.octaves
    if kind in ("fbm", "turbulence"):
        params.update(lacunarity=args.lacunarity, gain=args.gain, basis=args.basis)
    return params


def _common_error(message):
    from ._common import UsageError

    return UsageError(message)
