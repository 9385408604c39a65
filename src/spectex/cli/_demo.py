"""``spectex demo``: the paper's five-layer spectral texture, built, rendered and reported."""

from __future__ import annotations

from . import _common

DEFAULT_OUT = "spectex-demo"
#: The top-down bakes whose repeat_peak the demo reports: (side in pixels, pixels per finest tile).
REPEAT_BAKE = (1024, 64)
DEMO_SIZE = (540, 960)  # (height, width) of the three views
_FILES = ("ground.png", "closeup.png", "aerial.png", "tile_colour.png", "tile_alpha.png", "texture.tile.png",
          "texture.toml")


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "demo",
        help="build the paper's five-layer spectral texture, render three views, report",
        description=(
            "Berger's spectral texturing, end to end: one seamless 512x512 RGBA noise tile "
            "(emboss alpha) drawn as five layers from 15.625 m to 10 km, finest first, each "
            "coarser one blended over it (variance-preserving: the tile's contrast survives; covering the finer "
            "ones where their repeats would be a few pixels; --paper for "
            "the paper's alpha blend), and a sixth, fine detail layer (1.25 m) faded out with distance. "
            "Renders a ground-plane view to the horizon "
            "(Figure 1 of Berger's sketch, top), a close-up and an aerial view with OpenGL (headless "
            "EGL; the CPU reference renderer where there is no OpenGL), writes the tile's colour "
            "and alpha (its Figure 1, bottom) and the texture file, and reports the virtual texture "
            "size, the memory used against one image of the same texture, and render times."
        ),
    )
    p.add_argument("-o", "--output", type=_common.output_name, default=DEFAULT_OUT, metavar="DIR",
                   help=f"output folder, made if missing (default: {DEFAULT_OUT})")
    p.add_argument("--seed", type=_common.seed, default=0, help="random seed of the tile (default: 0)")
    p.add_argument("--backend", choices=("auto", "gl", "cpu"), default="auto",
                   help="renderer (default: auto: OpenGL if a context can be made, else the CPU)")
    p.add_argument("--paper", action="store_true",
                   help="the paper's own composite: five alpha-blended layers, no detail layer "
                        "(default: the variance-preserving blend and a fine detail layer)")
    _common.add_haze(p)
    p.add_argument("--repeat-peak", action="store_true",
                   help="also bake top-down views of periodic and stochastic layers and report their "
                        "repeat_peak (compiles the bake kernel: about a minute on a first run)")
    p.set_defaults(func=run)


def views():
    """The demo's cameras: ground plane to the horizon, close-up, aerial."""
    from spectex.render import DEFAULT_ANISOTROPY, Camera

    # every view at the renderers' default anisotropy (see spectex.render.DEFAULT_ANISOTROPY)
    return {
        "ground": (Camera((0.0, 0.0, 2.5), yaw=35.0, pitch=-9.0, fov=60.0), DEFAULT_ANISOTROPY),
        "closeup": (Camera((3.0, 2.0, 1.6), yaw=35.0, pitch=-55.0, fov=60.0), DEFAULT_ANISOTROPY),
        "aerial": (Camera((0.0, -1500.0, 1200.0), yaw=20.0, pitch=-40.0, fov=60.0), DEFAULT_ANISOTROPY),
    }


def run(args) -> int:
    import sys
    import time

    from spectex._output import OutputSet
    from spectex.io import write_image
    from spectex.render import Atmosphere
    from spectex.render import render as _render
    from spectex.render.gl import GLUnavailable
    from spectex.texture import SpectralTexture

    # Every file checked before the work; the set replaces the earlier demo only when complete.
    outputs = OutputSet(args.output, _FILES, name="--output")
    out = outputs.path

    from spectex.tiles import make_tile  # numba: after the outputs are checked

    t0 = time.perf_counter()
    tile = make_tile(512, rng=args.seed)
    style = {"blend": "alpha", "detail": False} if args.paper else {}
    texture = SpectralTexture.paper_preset(tile, **style)
    atmosphere = Atmosphere(haze_distance=args.haze)
    t_build = time.perf_counter() - t0

    images, times = {}, {}
    backend = args.backend
    renderer = None
    device = "CPU reference renderer (numba)"
    if backend in ("auto", "gl"):
        from spectex.render.gl import GLRenderer

        try:
            renderer = GLRenderer(texture)
            device = f"OpenGL, {renderer.ctx.info['GL_RENDERER']}"
        except GLUnavailable as exc:
            if backend == "gl":
                raise
            print(f"spectex demo: {exc}; rendering on the CPU instead", file=sys.stderr)
    if renderer is None:
        from spectex.shading.view import render_kernel  # the demo's views filter anisotropically

        _common.say_if_compiling("the CPU renderer", render_kernel)
    try:
        for name, (cam, aniso) in views().items():
            t = time.perf_counter()
            if renderer is not None:
                images[name] = renderer.render(cam, DEMO_SIZE, anisotropy=aniso, atmosphere=atmosphere)
            else:
                images[name] = _render(texture, cam, DEMO_SIZE, backend="cpu", anisotropy=aniso,
                                       atmosphere=atmosphere).image
            times[name] = time.perf_counter() - t
    finally:
        if renderer is not None:
            renderer.release()

    # Write everything or nothing.
    with outputs as stage:
        for name, img in images.items():
            write_image(stage / f"{name}.png", img)
        write_image(stage / "tile_colour.png", texture.tiles[0][:, :, :3])
        write_image(stage / "tile_alpha.png", texture.tiles[0][:, :, 3])
        texture.save(stage / "texture.toml")  # and texture.tile.png
    written = [out / name for name in _FILES]

    sizes = ", ".join(f"{layer.size:.6g} m" for layer in texture.layers)
    ratio = texture.layers[1].size / texture.layers[0].size
    h, w = DEMO_SIZE
    report = _common.report
    report(f"spectex demo: a {len(texture.layers)}-layer spectral texture (Berger, SIGGRAPH 2003 sketch)")
    report(f"  tile: 512x512 RGBA, emboss alpha, seed {args.seed} ({t_build:.2f} s to make)")
    report(f"  layers: {sizes} (steps of x{ratio:.3f}" + (")" if args.paper else
           "; the last a fine detail layer), variance-preserving blend, each layer covering the finer "
           "ones in the distance (--paper: the paper's alpha blend)"))
    # the virtual texture of the paper's five layers; the fine layer adds texels under the feet only
    spectral = [layer.size for layer in texture.layers if layer.blend != "fine"]
    texel = min(spectral) / texture.tile_shape[1]
    virtual = int(round(max(spectral) / texel))
    as_image = virtual ** 2 * 3
    fine = [layer.size for layer in texture.layers if layer.blend == "fine"]
    report(f"  virtual texture: {virtual} x {virtual} texels, {texel * 100:.2f} cm per texel over "
           f"{max(spectral) / 1000:g} x {max(spectral) / 1000:g} km"
           + (f" (and {fine[0] / texture.tile_shape[1] * 1000:.2f} mm texels under the feet)" if fine else ""))
    report(f"  memory: {texture.nbytes / 2**20:.2f} MiB ({texture.nbytes_mipmapped / 2**20:.2f} MiB with mip-maps) "
           f"against {as_image / 2**30:.1f} GiB as one RGB image "
           f"(1 : {as_image / texture.nbytes_mipmapped:,.0f})")
    haze = f"haze {args.haze:g} m" if args.haze else "no haze"
    report(f"  renderer: {device}; trilinear mip-mapping and anisotropic filtering, {len(texture.layers)} layers "
           f"in one pass, sky and {haze}")
    for name, (cam, aniso) in views().items():
        x, y, z = cam.position
        report(f"  {name:8s} {w}x{h}: {times[name]:.3f} s  (camera {x:g},{y:g},{z:g}, yaw {cam.yaw:g}, "
               f"pitch {cam.pitch:g}, anisotropy {aniso:g})")
    report(f"  wrote {len(written)} files to {out}/: " + ", ".join(p.name for p in written))
    if args.repeat_peak:  # after the pictures: the bake kernel's first compilation takes a minute
        from spectex.metrics import repeat_peak

        side, per_tile = REPEAT_BAKE
        peaks = {}
        from spectex.render import bake

        for tiling in ("periodic", "stochastic"):
            tex = SpectralTexture.paper_preset(tile, tiling=tiling, **style)
            peaks[tiling] = repeat_peak(bake(tex, (side, side), pixel_size=tex.layers[0].size / per_tile),
                                        min_lag=min(24, side // 2))
        report(f"  repeat_peak (top-down {side}x{side} bake, {per_tile} px per finest tile; <= 0.1 does not "
               f"repeat): periodic layers {peaks['periodic']:.3f}, stochastic layers {peaks['stochastic']:.3f}")
    return 0
