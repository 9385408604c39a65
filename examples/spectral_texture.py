"""The paper's spectral texture: five layers of one tile, seen from the ground to the horizon.

Berger's Figure 1 (seed 000): one seamless 512 x 512 RGBA tile drawn as five
layers from 15.625 m to 10 km, each coarser one alpha-blended over the
finer ones; on the left the tile's colour and its emboss alpha, on the
right a view over the ground plane (OpenGL when a context can be made,
else the CPU reference renderer, which gives the same picture to 1/255).

Run: ``python examples/spectral_texture.py [OUT] [--tile N] [--width W]``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from spectex import SpectralTexture, io
from spectex.render import Camera, render
from spectex.tiles import make_tile

try:
    from _gallery import parser
except ImportError:  # run as a module from elsewhere
    from examples._gallery import parser

TEST_ARGS = ["--tile", "32", "--width", "96"]


def picture(tile_size: int = 512, width: int = 960, seed: int = 0) -> np.ndarray:
    """Tile colour and alpha stacked, beside the ground view: ``(H, H / 2 + width, 3)`` float32."""
    tile = make_tile(tile_size, rng=seed)
    texture = SpectralTexture.paper_preset(tile)
    h = width * 9 // 16
    view = render(texture, Camera((0.0, 0.0, 2.5), yaw=35.0, pitch=-9.0, fov=60.0), (h, width)).image
    half = h // 2
    col = _resized(texture.tiles[0][..., :3], half, half)
    alpha = np.repeat(_resized(texture.tiles[0][..., 3:], h - half, half), 3, axis=2)
    return np.concatenate([np.concatenate([col, alpha], axis=0), view], axis=1)


def _resized(image: np.ndarray, h: int, w: int) -> np.ndarray:
    """``image`` (H, W, C) in [0, 1] box-filtered to (h, w, C) with Pillow, channel by channel."""
    from PIL import Image

    return np.stack([np.asarray(Image.fromarray(image[..., c].astype(np.float32), mode="F")
                                .resize((w, h), Image.Resampling.BOX)) for c in range(image.shape[2])], axis=2)


def main(argv=None) -> Path:
    p = parser(__doc__, "spectral_texture.jpg")
    p.add_argument("--tile", type=int, default=512, help="tile side in texels (default 512)")
    p.add_argument("--width", type=int, default=960, help="width of the view in pixels (default 960)")
    args = p.parse_args(argv)
    return io.write_image(args.out, picture(args.tile, args.width))


if __name__ == "__main__":
    print(main())
