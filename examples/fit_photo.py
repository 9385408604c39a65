"""Fit a spectral texture to a photo (the paper's future work), and bake it beyond the photo.

scikit-image's gravel (left) is fitted by ``spectex.fit``: a tile made from
the photo, layer scales, opacities and an alpha that match the photo's band
power, colour histograms and cross-scale dependence, with stochastic layers
(the default), so that it never repeats. Second: the fitted texture baked
at the photo's scale; third: baked over 8 times the area (about 2.8 times
the side, shown at the same size), where the coarser layers continue the
photo's spectrum. Right, the control: the same fit with periodic layers
(``tiling="periodic"``), the same 8 times the area, where the tile's repeat
shows as a lattice. Each bake of 8 times the area is labelled with its
``spectex.metrics.repeat_peak`` (<= 0.1: it does not repeat).

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
    """Photo, bake at its scale, bakes of 8x the area (default fit, periodic fit), labelled:
    ``(LABEL_HEIGHT + size, 4 size + 3 gaps, 3)``."""
    from skimage import data

    from spectex.figures import montage
    from spectex.metrics import repeat_peak

    photo = np.repeat((data.gravel()[:size, :size].astype(np.float32) / 255.0)[..., None], 3, axis=2)
    side = int(round(size * np.sqrt(8.0)))
    idx = np.minimum((np.arange(size) * side) // size, side - 1)
    images, labels = [photo], ["photo (gravel)"]
    for tiling in ("auto", "periodic"):
        texture = spectex.fit(photo, pixel_size=0.01, rng=seed, tiling=tiling)
        if tiling == "auto":
            images.append(texture.bake((size, size), pixel_size=0.01))
            labels.append("fit, at the photo scale")
        far = texture.bake((side, side), pixel_size=0.01)
        peak = repeat_peak(far, min_lag=min(24, side // 2))
        images.append(far[idx][:, idx])  # nearest, so that no detail is smoothed away
        name = "fit" if tiling == "auto" else "periodic fit"
        labels.append(f"{name}, 8x area: repeat_peak {peak:.2f}")
    return montage(images, labels)


def main(argv=None) -> Path:
    p = parser(__doc__, "fit_gravel_example.jpg")
    p.add_argument("--size", type=int, default=256, help="photo crop side in pixels (default 256)")
    args = p.parse_args(argv)
    return io.write_image(args.out, picture(args.size))


if __name__ == "__main__":
    print(main())
