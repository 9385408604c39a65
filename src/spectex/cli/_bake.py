"""``spectex bake``: a region of a spectral texture as a sharded OME-Zarr pyramid, or as one PNG."""

from __future__ import annotations

from . import _common


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "bake",
        help="bake a region of a spectral texture into a sharded OME-Zarr pyramid (Dask, clusters)",
        description=(
            "Bake the region of TEXTURE (a .toml) whose top-left pixel corner is --origin X,Y "
            "(metres; rows go along +y) at --pixel-size metres per pixel into OUT.zarr: OME-NGFF "
            "0.5 multiscales on Zarr v3 with the sharding codec, axes (c, y, x), level k sampled "
            "directly at 2**k times the pixel size. One task per shard, on this machine's threads "
            "or, with --scheduler tcp://HOST:PORT, on a dask.distributed cluster. Run again with "
            "the same arguments to finish an interrupted bake; other arguments over an existing "
            "store are refused. With an output ending in .png, the region as one plain PNG instead "
            "(--dtype uint8 or uint16: 8 or 16 bits per channel), for engines and tools that take "
            "images. See docs/bake.md."
        ),
    )
    p.add_argument("texture", help="texture file (.toml)")
    p.add_argument("-o", "--output", required=True,
                   help="output store (a folder ending in .zarr), or one image (.png)")
    p.add_argument("--size", type=_common.size, required=True, metavar="WxH", help="level 0 size in pixels")
    p.add_argument("--pixel-size", type=_common.positive_float, required=True, metavar="P",
                   help="metres per pixel of level 0")
    p.add_argument("--origin", type=_common.floats(2), default=(0.0, 0.0), metavar="X,Y",
                   help="world corner of pixel (0, 0), metres (default: 0,0)")
    p.add_argument("--levels", type=_common.positive_int, default=None,
                   help="pyramid levels (default: until the coarsest fits one chunk)")
    p.add_argument("--chunk", type=_common.positive_int, default=None, help="chunk edge, pixels (default: 512)")
    p.add_argument("--shard", type=_common.positive_int, default=None,
                   help="shard edge, pixels, a multiple of --chunk; one task each (default: 4096)")
    p.add_argument("--dtype", choices=("uint8", "uint16", "float32"), default="uint8",
                   help="stored pixel type (default: uint8 = round(v * 255))")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="dask.distributed scheduler address, tcp://HOST:PORT (default: threads on this machine)")
    p.add_argument("--workers", type=_common.positive_int, default=None,
                   help="threads on this machine (default: all cores); not with --scheduler")
    p.add_argument("--connect-timeout", type=_common.positive_float, default=10.0, metavar="SECONDS",
                   help="how long to wait for --scheduler to answer (default: 10)")
    p.set_defaults(func=run)


def check_inputs_apart(texture_path, output) -> None:
    """Refuse an output that is, or holds, the texture file or one of its tiles."""
    from pathlib import Path

    from spectex.texture_file import named_files

    from ._common import UsageError

    out = Path(output).resolve()
    for path in named_files(texture_path):
        if path == out or out in path.parents:
            raise UsageError(f"--output '{output}' is, or holds, the input '{path}'; choose another path")


def run(args) -> int:
    from pathlib import Path

    from ._common import UsageError

    if not Path(args.texture).is_file():
        raise UsageError(f"texture file not found: '{args.texture}'")
    check_inputs_apart(args.texture, args.output)
    if _common.given(args, "connect_timeout") and args.scheduler is None:
        _common.refuse(args, ["connect_timeout"], "without --scheduler")
    h, w = args.size
    suffix = Path(args.output).suffix.lower()
    if suffix not in (".zarr", ".png"):
        raise UsageError(f"--output must end in .zarr (a store) or .png (one image), got '{args.output}'")
    if suffix == ".png":
        return _run_image(args)
    from spectex import texture_file

    texture_file.check(args.texture)  # every field, before dask and zarr are imported
    from spectex.bake import bake_zarr

    args.chunk = 512 if args.chunk is None else args.chunk
    args.shard = 4096 if args.shard is None else args.shard
    with _common.Progress("baking") as progress:
        result = bake_zarr(args.texture, args.output, (h, w), pixel_size=args.pixel_size, origin=args.origin,
                           levels=args.levels, chunk=args.chunk, shard=args.shard, dtype=args.dtype,
                           scheduler=args.scheduler, workers=args.workers, progress=progress,
                           connect_timeout=args.connect_timeout)
    lh, lw = result.shapes[-1]
    if result.baked == 0:
        _common.report(f"{result.path} is complete already ({len(result.shapes)} levels, {w}x{h} to {lw}x{lh}); "
                       "nothing to do")
        return 0
    resumed = f", {result.resumed} kept from an earlier run" if result.resumed else ""
    _common.report(f"wrote {result.path}: {len(result.shapes)} levels, {w}x{h} to {lw}x{lh} {result.dtype}, "
                   f"{result.baked} shards baked{resumed}; {result.pixels / 1e6:.1f} Mpx in {result.seconds:.1f} s "
                   f"({result.pixels_per_second / 1e6:.2f} Mpx/s)")
    return 0


def _run_image(args) -> int:
    """``-o X.png``: the region as one PNG; the pyramid's options are refused, not ignored."""
    from spectex.bake import bake_image

    from ._common import UsageError

    for option in ("levels", "chunk", "shard", "scheduler", "workers"):
        if getattr(args, option) is not None:
            raise UsageError(f"--{option} applies to a .zarr store, not to a .png output")
    if args.dtype == "float32":
        raise UsageError("--dtype float32 needs a .zarr store; a .png takes uint8 or uint16")
    h, w = args.size
    path = bake_image(args.texture, args.output, (h, w), pixel_size=args.pixel_size, origin=args.origin,
                      bit_depth=8 if args.dtype == "uint8" else 16)
    _common.report(f"wrote {path} ({w}x{h}, {8 if args.dtype == 'uint8' else 16}-bit RGB)")
    return 0
