"""Texture synthesis from an example (seed 002): more of a photo than the photo holds.

scikit-image's gravel (left, a 128 x 128 crop) grown to four times its
side by image quilting (Efros and Freeman: overlapping blocks, minimum
error boundary cuts), tileable; the quilted texture is shown 2 x 2 (right)
so that its seamless wrap is visible.

Run: ``python examples/synthesis.py [OUT] [--crop N] [--block B]``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from spectex import io, synthesis

try:
    from _gallery import parser
except ImportError:
    from examples._gallery import parser

TEST_ARGS = ["--crop", "32", "--block", "8"]


def exemplar(crop: int) -> np.ndarray:
    """A ``crop x crop`` RGB float32 crop of scikit-image's gravel photo."""
    from skimage import data

    img = data.gravel()
    img = np.repeat(img[..., None], 3, axis=2) if img.ndim == 2 else img[..., :3]
    return (img[:crop, :crop].astype(np.float32) / 255.0).astype(np.float32)


def picture(crop: int = 128, block: int = 32, seed: int = 1) -> np.ndarray:
    """Exemplar (padded to the height) beside the quilted texture tiled 2 x 2."""
    ex = exemplar(crop)
    out = synthesis.quilt(ex, (4 * crop, 4 * crop), block=block, tileable=True, seed=seed)
    tiled = np.tile(out, (2, 2, 1))
    left = np.ones((tiled.shape[0], crop, 3), np.float32)
    left[:crop] = ex
    return np.concatenate([left, tiled], axis=1)


def main(argv=None) -> Path:
    p = parser(__doc__, "synthesis_quilting.jpg")
    p.add_argument("--crop", type=int, default=128, help="exemplar side in pixels (default 128)")
    p.add_argument("--block", type=int, default=32, help="quilting block side (default 32)")
    args = p.parse_args(argv)
    return io.write_image(args.out, picture(args.crop, args.block))


if __name__ == "__main__":
    print(main())
