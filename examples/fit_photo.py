"""Fit a spectral texture to a photo (the paper's future work), and bake it beyond the photo.

scikit-image's gravel (left) is fitted by ``spectex.fit``: the finest layer
is a tile made from the photo, drawn stochastically with sharp blend weights
(no cross-faded double stones), the coarser layers a noise tile of their own
that continues the photo's spectrum to larger scales (never the photo
magnified), colours matched to the photo's histograms. Second: the fitted
texture baked at the photo's scale; third: baked over 8 times the area
(about 2.8 times the side, shown at the same size). Right, the control: the
old fit (``method="legacy"``) over the same 8 times the area, whose coarse
layers are the photo magnified (blotches, ghost stones). Each bake of 8 times the area is labelled with its
``spectex.metrics.repeat_peak`` (<= 0.1: it does not repeat).

Run: ``python examples/fit_photo.py [OUT] [--size N]``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import spectex
from spectex import io
from spectex.render import bake

try:
    from _gallery import parser
except ImportError:
    from examples._gallery import parser

TEST_ARGS = ["--size", "48"]


def picture(size: int = 256, seed: int = 0) -> np.ndarray:
    """Photo, bake at its scale, bakes of 8x the area (default fit, periodic fit), labelled:
    ``(LABEL_HEIGHT + size, 4 size + 3 gaps, 3)``."""
    from skimage import data

    from spectex.figures import montage
    from spectex.metrics import repeat_peak

    photo = np.repeat((data.gravel()[:size, :size].astype(np.float32) / 255.0)[..., None], 3, axis=2)
    side = int(round(size * np.sqrt(8.0)))
    idx = np.minimum((np.arange(size) * side) // size, side - 1)
    images, labels = [photo], ["photo (gravel)"]
    for method in ("auto", "legacy"):
        texture = spectex.fit(photo, pixel_size=0.01, rng=seed, method=method)
        if method == "auto":
            images.append(bake(texture, (size, size), pixel_size=0.01))
            labels.append("fit, at the photo scale")
        far = bake(texture, (side, side), pixel_size=0.01)
        peak = repeat_peak(far, min_lag=min(24, side // 2))
        images.append(far[idx][:, idx])  # nearest, so that no detail is smoothed away
        name = "fit" if method == "auto" else "old fit (legacy)"
        labels.append(f"{name}, 8x area: repeat_peak {peak:.2f}")
    return montage(images, labels)


def main(argv=None) -> Path:
    p = parser(__doc__, "fit_gravel_example.jpg")
    p.add_argument("--size", type=int, default=256, help="photo crop side in pixels (default 256)")
    args = p.parse_args(argv)
    return io.write_image(args.out, picture(args.size))


if __name__ == "__main__":
    print(main())
