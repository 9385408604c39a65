"""``spectex view``: fly over a spectral texture in a window."""

from __future__ import annotations

from . import _common


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "view",
        help="fly over a spectral texture in an interactive window",
        description=(
            "Open a window (OpenGL 3.3 through glfw) and fly over TEXTURE. Mouse: drag to look "
            "around; wheel: speed. Keys: W/S forward/back, A/D sideways, R/F up/down, "
            "1-8 toggle layers, M mip-mapping on/off, N anisotropic filtering on/off, "
            "H haze on/off, Esc quits. Speed scales with altitude; frames per second are shown "
            "on screen. Without a display this says so: use 'spectex render' instead."
        ),
    )
    p.add_argument("texture", help="texture file (.toml)")
    p.add_argument("--camera", type=_common.floats(5), default=(0.0, 0.0, 2.0, 0.0, -10.0),
                   metavar="X,Y,Z,YAW,PITCH", help="start camera (default: 0,0,2,0,-10)")
    p.add_argument("--fov", type=_common.positive_float, default=60.0, help="vertical field of view (default: 60)")
    p.add_argument("--size", type=_common.size, default=(720, 1280), metavar="WxH",
                   help="window size (default: 1280x720)")
    _common.add_haze(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from spectex.render import Camera, check_size
    from spectex.render.viewer import check_display, run_viewer
    from spectex.texture import SpectralTexture

    check_size(args.size, name="--size")  # the render budget; X and GL refuse larger windows with a traceback
    camera = Camera.from_tuple(args.camera, fov=args.fov)
    texture = SpectralTexture.load(args.texture)  # a bad file is named before a missing display
    check_display()
    run_viewer(texture, camera=camera, size=args.size, haze=args.haze)
    return 0
