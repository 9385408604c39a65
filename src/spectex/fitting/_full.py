"""The finest tile at the photo's full resolution, for a photo the fit read resampled (issue 22).

A large photo of large grain is read at a scale where its crop holds enough stones
(``_core.MIN_TILE_GRAINS``): a 2048-pixel photo of cobbles at a quarter of its resolution. Everything the
fit decides (the tile's crop and seams, its bands, its colours, the coarse layers) is decided there, fast.
The tile that comes out is registered with a crop of the photo: the same stones at the same places. So the
photo's own detail finer than the analysis's pixels, the crop at full resolution less that crop as the
analysis saw it, can be put back where it belongs, stone by stone, and the close view keeps the photo's
grain and sharp mortar instead of texels of 4 photo pixels magnified.
"""

from __future__ import annotations

import numpy as np

#: Largest side of a full-resolution tile, texels (every tile of a texture has the finest's shape: two
#: tiles of 2048 x 2048 RGBA8 are 32 MiB, 43 with their mip-maps). Beyond, the tile's texel is more than a
#: photo pixel.
MAX_FULL_TILE = 2048


def full_side(n, source, max_side=MAX_FULL_TILE):
    """Texels of the full-resolution tile of an ``n``-texel tile read from ``source``
    (``_core._prepared_with_source``): a whole multiple of ``n`` (each analysed texel ``k x k`` texels: the
    grout the shading core finds on the tile, read at most 512 texels a side, finds the cells the fit saw),
    the nearest to the photo pixels across, at most ``max_side``; ``n`` where that is 1."""
    k = int(np.clip(round(min(source["step"])), 1, max(1, max_side // n)))
    return k * n


def _zoom(image, k, mode):
    """``image`` (h, w, c) magnified ``k`` times by a cubic (Keys, a = -1/2), pixel areas aligned; beyond its
    edges it wraps (``mode="wrap"``: a tile) or is mirrored (``"reflect"``: a crop)."""
    from PIL import Image

    from ._core import resized

    h, w, pad = image.shape[0], image.shape[1], 4
    padded = np.pad(image, ((pad, pad), (pad, pad), (0, 0)), mode="wrap" if mode == "wrap" else "symmetric")
    return resized(padded, (k * h, k * w), Image.Resampling.BICUBIC, box=(pad, pad, pad + w, pad + h))


def full_resolution(colour, coarse, source, exemplar_shape, corner, *, moves=(), max_side=MAX_FULL_TILE):
    """The fitted tile ``colour`` and the coarse tile ``coarse`` at the photo's resolution.

    Parameters
    ----------
    colour : ndarray (n, n, 3)
        The fitted finest tile (seamless), registered with the exemplar's crop at ``corner``.
    coarse : ndarray (n, n, 4)
        The coarse layers' tile (smooth): magnified to the same shape, every tile of a texture having one.
    source : dict
        ``_core._prepared_with_source``'s record of the exemplar in the photo.
    exemplar_shape : (int, int)
        The exemplar's rows and columns.
    corner : (int, int)
        The tile's crop's corner (y, x) in the exemplar.
    moves : sequence of ((y0, x0, y1, x1), (sy, sx))
        The windows of the exemplar the fit filled from elsewhere (one-off content, in the order filled) and
        the corners of the windows they were filled from: the detail moves with them.

    Returns
    -------
    (full, coarse) : float32 (N, N, 3) in [0, 1] and float32 (N, N, 4), ``N`` = :func:`full_side`.

    The detail is the photo at ``k`` times the exemplar's pixels (``N = k n``) less the photo area-averaged to
    the exemplar's pixels and magnified back (the same cubic magnifies the tile): what the analysis did not
    see. It is scaled by the ratio of the tile to the crop as the analysis saw it, both blurred over two
    analysed pixels (held to 0.5-2): where the fit evened the lighting or moved a colour, the detail follows.
    It is not periodic across the tile's wrap edges; it is fine grain, and the tile's own wrap stays
    seamless.
    """
    from PIL import Image
    from scipy import ndimage

    from ._core import resized

    n = colour.shape[0]
    k = full_side(n, source, max_side) // n
    h, w = exemplar_shape
    sy, sx = source["step"]
    oy, ox = source["origin"]
    box = (ox * sx, oy * sy, (ox + w) * sx, (oy + h) * sy)
    # area-averaged where a texel holds more than a photo pixel, a cubic where it holds less
    how = Image.Resampling.BOX if k <= min(sy, sx) else Image.Resampling.BICUBIC
    photo = resized(source["photo"], (k * h, k * w), how, box=box)
    small = resized(photo, (h, w), Image.Resampling.BOX)
    detail = photo - _zoom(small, k, "reflect")
    for (wy0, wx0, wy1, wx1), (fy, fx) in moves:
        detail[k * wy0:k * wy1, k * wx0:k * wx1] = detail[k * fy:k * (fy + wy1 - wy0), k * fx:k * (fx + wx1 - wx0)]
    cy, cx = corner
    detail = detail[k * cy:k * (cy + n), k * cx:k * (cx + n)]
    small = small[cy:cy + n, cx:cx + n]
    # the ratio read at the analysis's scale, where it is smooth, and magnified
    ratio = (ndimage.gaussian_filter(colour, (2.0, 2.0, 0), mode="wrap") + 1e-3) / (
        ndimage.gaussian_filter(small, (2.0, 2.0, 0), mode="reflect") + 1e-3)
    detail *= _zoom(np.clip(ratio, 0.5, 2.0), k, "reflect")
    full = np.clip(_zoom(colour, k, "wrap") + detail, 0.0, 1.0)
    big = np.empty((k * n, k * n, 4), dtype=np.float32)
    big[:, :, :3] = np.clip(_zoom(coarse[:, :, :3], k, "wrap"), 0.0, 1.0)
    big[:, :, 3] = 1.0
    return full, big
