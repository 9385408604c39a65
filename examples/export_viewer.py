"""A spectral texture taken out of spectex: exported as GLSL and drawn by OpenGL from the files alone.

The paper's five-layer texture with every layer stochastic (a tile that
never repeats) is exported with ``spectex.export.export(..., formats="glsl")``.
Then, as any OpenGL program would, ``spectex.export.host`` reads only the
exported folder: the ground program (``ground.330.vert``/``.frag``), the
layer table (``spectex_texture.json``), the tile's mip levels
(``mips/*.png``) and the stochastic tables (``gauss.rgba16f``,
``spectex_lut.r16f``: raw half floats); it computes the uniforms as
``glsl/README.md`` says (the layer anchors in float64, from the unreduced
tile coordinates for the grid) and draws with moderngl (headless EGL). On the left the exported shader's
picture, on the right spectex's own CPU renderer at the same camera: the two
agree to about 1/255.

Run: ``python examples/export_viewer.py [OUT] [--tile N] [--width W]``.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from spectex import SpectralTexture, io
from spectex.export import export
from spectex.export.host import draw_glsl_export
from spectex.render import Camera
from spectex.render.cpu import render_cpu
from spectex.tiles import make_tile

try:
    from _gallery import parser
except ImportError:  # run as a module from elsewhere
    from examples._gallery import parser

TEST_ARGS = ["--tile", "32", "--width", "96"]

#: The view: 1,000 km east of the origin, low over the ground, towards the horizon.
CAMERA = Camera((1.0e6, 3.0e3, 4.0), yaw=35.0, pitch=-20.0, fov=60.0)


def picture(tile_size: int = 512, width: int = 960, seed: int = 0) -> np.ndarray:
    """The exported shader's picture beside spectex's CPU render: ``(H, 2 width, 3)`` float32."""
    texture = SpectralTexture.paper_preset(make_tile(tile_size, rng=seed), tiling="stochastic")
    height = width * 9 // 16
    with tempfile.TemporaryDirectory() as tmp:
        folder = export(texture, Path(tmp) / "ground", formats="glsl").folder / "glsl"
        exported = draw_glsl_export(folder, CAMERA, (height, width), anisotropy=8.0)
    reference = render_cpu(texture, CAMERA, (height, width), anisotropy=8.0)
    return np.concatenate([exported, reference], axis=1)


def main(argv=None) -> Path:
    p = parser(__doc__, "export_viewer.jpg")
    p.add_argument("--tile", type=int, default=512, help="tile side in texels (default 512)")
    p.add_argument("--width", type=int, default=960, help="width of each view in pixels (default 960)")
    args = p.parse_args(argv)
    return io.write_image(args.out, picture(args.tile, args.width))


if __name__ == "__main__":
    print(main())
