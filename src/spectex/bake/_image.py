"""A region of a spectral texture as one plain image (PNG), for engines and tools that take images."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._validate import check_choice, check_length, check_shape

__all__ = ["IMAGE_BITS", "bake_image"]

#: Bits per channel of a baked PNG.
IMAGE_BITS = (8, 16)


def bake_image(texture, path, shape, *, pixel_size, origin=(0.0, 0.0), bit_depth=8) -> Path:
    """Bake a region of ``texture`` into one RGB PNG, 8 or 16 bits per channel.

    The pixels are :func:`spectex.bake.bake_window` of the whole region, that is
    ``bake(texture, shape, origin=origin, pixel_size=pixel_size)`` bit for bit,
    rounded to ``round(v * (2**bit_depth - 1))``: the same values as level 0 of
    :func:`spectex.bake.bake_zarr` with ``dtype="uint8"`` or ``"uint16"``. Row 0
    is the row at ``origin`` (rows go along +y). Written atomically.

    Parameters
    ----------
    texture : SpectralTexture or path
        The texture, or its file (``.toml``).
    path : str or Path
        The image to write, ``.png``.
    shape : int or (int, int)
        ``(height, width)``, pixels (at most 2**26 pixels).
    pixel_size : float
        Metres per pixel (> 0).
    origin : (float, float)
        World (x, y) of the corner of pixel (0, 0), metres.
    bit_depth : {8, 16}
        Bits per channel.

    Returns
    -------
    Path
        The image written.
    """
    from ..io import write_image
    from ..texture import SpectralTexture
    from ._block import bake_window, to_dtype
    from ._zarr import _check_origin

    # every number before the texture is loaded (that imports and may compile the sampler: seconds)
    if Path(path).suffix.lower() != ".png":
        raise ValueError(f"path must end in .png, got '{path}'")
    check_choice("bit_depth", str(bit_depth), tuple(str(b) for b in IMAGE_BITS))
    h, w = check_shape("shape", shape, maximum_pixels=1 << 26)
    check_length("pixel_size", pixel_size)
    _check_origin(origin)
    if not isinstance(texture, SpectralTexture):
        texture = SpectralTexture.load(texture)
    rgb = bake_window(texture, (0, h, 0, w), origin=origin, pixel_size=pixel_size)
    # the store's integers (to_dtype, rounded half to even), as floats that write_image gives back exactly
    top = 2 ** int(bit_depth) - 1
    stored = to_dtype(rgb, "uint8" if int(bit_depth) == 8 else "uint16")
    return write_image(path, (stored / top).astype(np.float32), bit_depth=int(bit_depth))
