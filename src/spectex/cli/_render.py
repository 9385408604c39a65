"""``spectex render``: a spectral texture on the ground plane, as a picture or a fly-over."""

from __future__ import annotations

from . import _common

_IMAGE = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".webp", ".npy")
_ANIM = (".gif", ".mp4")
#: Most frame memory a fly-over may hold before it is written (uint8 RGB).
MAX_ANIMATION_BYTES = 1 << 30


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "render",
        help="render a spectral texture on the ground plane (picture or fly-over)",
        description=(
            "Render TEXTURE (a .toml written by 'spectex demo' or SpectralTexture.save) on the "
            "ground plane z = 0 from a camera at X,Y,Z (metres, z up) looking along compass "
            "heading YAW (degrees, 0 = north = +y) and PITCH (degrees above the horizon). With "
            "--frames N, a fly-over from --camera to --to (default: forward 40 altitudes) is "
            "written to .gif or .mp4. OpenGL (headless EGL) by default; without OpenGL the CPU "
            "reference renderer draws the same picture, and one line says so."
        ),
    )
    p.add_argument("texture", help="texture file (.toml)")
    p.add_argument("--camera", type=_common.floats(5), required=True, metavar="X,Y,Z,YAW,PITCH",
                   help="camera position (m) and heading/pitch (degrees)")
    p.add_argument("--fov", type=_common.positive_float, default=60.0,
                   help="vertical field of view, degrees (default: 60)")
    p.add_argument("--size", type=_common.size, default=(540, 960), metavar="WxH",
                   help="picture size (default: 960x540)")
    p.add_argument("-o", "--output", type=_common.output_name, required=True,
                   help="output picture (.png, ...) or, with --frames, .gif/.mp4")
    p.add_argument("--backend", choices=("auto", "gl", "cpu"), default="auto",
                   help="renderer (default: auto: OpenGL, else the CPU)")
    p.add_argument("--supersample", type=_common.positive_int, default=1,
                   help="N x N samples per pixel, box-filtered (default: 1)")
    p.add_argument("--filter", default="trilinear",
                   choices=("trilinear", "linear", "nearest", "nearest_mipmap_nearest", "linear_mipmap_nearest",
                            "nearest_mipmap_linear", "linear_mipmap_linear"),
                   help="minification filter (default: trilinear; linear = no mip-mapping)")
    p.add_argument("--anisotropy", type=_common.positive_float, default=8.0,
                   help="maximum anisotropic filtering, 1 (off: trilinear only, faster) to 16 (default: 8, "
                        "sharper and alias-free at grazing angles)")
    _common.add_haze(p)
    p.add_argument("--frames", type=_common.positive_int, default=1, help="frames of a fly-over (default: 1)")
    p.add_argument("--to", type=_common.floats(5), default=None, metavar="X,Y,Z,YAW,PITCH",
                   help="with --frames: fly-over end camera (default: 40 altitudes ahead, same height and angles)")
    p.add_argument("--fps", type=_common.positive_float, default=24.0,
                   help="with --frames: frames per second (default: 24)")
    p.set_defaults(func=run)


def flight(start, end, frames):
    """Cameras from ``start`` to ``end`` (linear in position and angles), ``frames`` of them."""
    from spectex.render import Camera

    cams = []
    for k in range(frames):
        f = 0.0 if frames == 1 else k / (frames - 1)
        pos = tuple(float(a + f * (b - a)) for a, b in zip(start.position, end.position))
        dyaw = (end.yaw - start.yaw + 180.0) % 360.0 - 180.0
        cams.append(Camera(pos, yaw=start.yaw + f * dyaw, pitch=start.pitch + f * (end.pitch - start.pitch),
                           fov=start.fov))
    return cams


def run(args) -> int:
    import math
    import sys
    import time

    # Everything is checked before anything is drawn or written.
    from pathlib import Path

    from spectex._validate import check_float
    from spectex.io import check_mp4_size, check_output_path, write_animation, write_image
    from spectex.render import Atmosphere, Camera, check_size
    from spectex.render.gl import GLUnavailable
    from spectex.texture import SpectralTexture

    # an animation when it has frames to move through, or when the output is one (a one-frame .gif, as noise)
    animated = args.frames > 1 or Path(args.output).suffix.lower() in _ANIM
    if not animated:
        _common.refuse(args, ["to", "fps"], "to a single picture (only with --frames 2 or more, or a .gif/.mp4)")
    output = check_output_path("output", args.output, _ANIM if animated else _IMAGE, inputs=[args.texture])
    h, w = check_size(args.size, args.supersample, name="--size")
    check_float("--anisotropy", args.anisotropy, minimum=1.0, maximum=16.0)  # the renderer's range, said at once
    if animated and output.suffix.lower() == ".mp4":
        check_mp4_size(h, w)
    start = Camera.from_tuple(args.camera, fov=args.fov)
    if args.to is not None:
        end = Camera.from_tuple(args.to, fov=args.fov)
    else:
        x, y, z = start.position
        d = 40.0 * z
        yaw = math.radians(start.yaw)
        end = start.moved(position=(x + d * math.sin(yaw), y + d * math.cos(yaw), z))
    if animated and args.frames * h * w * 3 > MAX_ANIMATION_BYTES:
        most = MAX_ANIMATION_BYTES // (h * w * 3)
        raise ValueError(f"--frames {args.frames} at {w}x{h} would hold {args.frames * h * w * 3} bytes of "
                         f"frames, over the budget of {MAX_ANIMATION_BYTES} bytes (1 GiB): at most {most} "
                         f"frames at this size")
    cameras = flight(start, end, args.frames) if animated else [start]
    kw = dict(filter=args.filter, anisotropy=args.anisotropy, supersample=args.supersample,
              atmosphere=Atmosphere(haze_distance=args.haze))
    texture = SpectralTexture.load(args.texture)
    check_output_path("output", output, _ANIM if animated else _IMAGE)  # again: not one of its tile files

    renderer = None
    if args.backend in ("auto", "gl"):
        from spectex.render.gl import GLRenderer

        try:
            renderer = GLRenderer(texture)
        except GLUnavailable as exc:
            if args.backend == "gl":
                raise
            print(f"spectex render: {exc}; rendering on the CPU instead", file=sys.stderr)
    if renderer is None:
        from spectex.shading.view import render_kernel, render_kernel_fast

        _common.say_if_compiling("the CPU renderer", render_kernel, render_kernel_fast)
    frames = []
    t0 = time.perf_counter()
    try:
        with _common.Progress("rendering") as progress:
            for k, cam in enumerate(cameras):
                if renderer is not None:
                    frames.append(renderer.render(cam, (h, w), **kw))
                else:
                    from spectex.render.cpu import render_cpu

                    frames.append(render_cpu(texture, cam, (h, w), **kw))
                progress(k + 1, len(cameras))
    finally:
        backend = "OpenGL" if renderer is not None else "CPU"
        if renderer is not None:
            renderer.release()
    dt = time.perf_counter() - t0
    if animated:
        write_animation(output, frames, fps=args.fps)
        _common.report(f"wrote {output} ({len(frames)} frames {w}x{h}, {backend}, {dt / len(frames):.3f} s per frame)")
    else:
        write_image(output, frames[0])
        _common.report(f"wrote {output} ({w}x{h}, {backend}, {dt:.3f} s)")
    return 0
