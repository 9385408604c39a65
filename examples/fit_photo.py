"""Fit a spectral texture to a photo (the paper's future work), and bake it beyond the photo.

scikit-image's gravel (left) is fitted by ``spectex.fit``: a tile made from
the photo, layer scales, opacities and an alpha that match the photo's band
power, colour histograms and cross-scale dependence. Middle: the fitted
texture baked at the photo's scale; right: baked over 8 times the area
(about 2.8 times the side), where the coarser layers continue the photo's
spectrum.

Run: ``python examples/fit_photo.py [OUT] [--size N]``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import spectex
from spectex import io

try:
    from _gallery import parser
except ImportError:
    from examples._gallery import parser

TEST_ARGS = ["--size", "48"]


def picture(size: int = 256, seed: int = 0) -> np.ndarray:
    """Photo, bake at its scale, bake of 8x the area shown at the same size: ``(size, 3 size, 3)``."""
    from skimage import data

    photo = np.repeat((data.gravel()[:size, :size].astype(np.float32) / 255.0)[..., None], 3, axis=2)
    texture = spectex.fit(photo, pixel_size=0.01, seed=seed)
    near = texture.bake((size, size), pixel_size=0.01)
    side = int(round(size * np.sqrt(8.0)))
    far = texture.bake((side, side), pixel_size=0.01)
    idx = np.minimum((np.arange(size) * side) // size, side - 1)
    shown = far.reshape(side, side, 3)[idx][:, idx]  # nearest, so that no detail is smoothed away
    return np.concatenate([photo, near, shown], axis=1)


def main(argv=None) -> Path:
    p = parser(__doc__, "fit_gravel_example.jpg")
    p.add_argument("--size", type=int, default=256, help="photo crop side in pixels (default 256)")
    args = p.parse_args(argv)
    return io.write_image(args.out, picture(args.size))


if __name__ == "__main__":
    print(main())
