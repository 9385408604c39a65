"""Seamless RGBA tiles, their alpha channels and their mip-map chains.

The spectral texture of Berger (2006) is built from one tile: low-pass
filtered random noise, coloured through a ramp, seamless, with an alpha
channel derived from the colour by an emboss filter. One module per concept:

:mod:`spectex.tiles.from_noise`
    :func:`make_tile`: the tile from noise (the steps and the cut-off are in
    that module's docstring); ``METHODS``, ``ALPHAS``, ``MAX_SIZE``.
:mod:`spectex.tiles.from_photo`
    :func:`make_seamless`: a user's photograph made into such a tile
    (Moisan's periodic component, :mod:`spectex.periodic`, with matched
    seams); ``SEAM_BAND``.
:mod:`spectex.tiles.mipmap`
    :func:`mip_chain`: the mip-map levels the renderer uploads, averaged as
    stored or in linear light.
:mod:`spectex.tiles.ops`
    Operations on tile images: :func:`emboss` (the paper's alpha),
    :func:`fit_range` (back into [0, 1] without breaking a band limit),
    :func:`preview` (is the tile seamless?).

Every name is also here, ``spectex.tiles.make_tile`` and so on. The colour
helpers ``luma``, ``srgb_to_linear`` and ``linear_to_srgb`` live in
:mod:`spectex.color`.

References
----------
D. R. Berger, "Spectral texturing for real-time applications", SIGGRAPH
2006 sketch. L. Moisan, "Periodic plus smooth image decomposition", JMIV
39(2), 2011. L. Williams, "Pyramidal parametrics", SIGGRAPH 1983 (mip-maps).
"""

from .from_noise import ALPHAS, MAX_SIZE, METHODS, make_tile
from .from_photo import SEAM_BAND, make_seamless
from .mipmap import mip_chain
from .ops import emboss, fit_range, preview

__all__ = [
    "ALPHAS",
    "MAX_SIZE",
    "METHODS",
    "SEAM_BAND",
    "emboss",
    "fit_range",
    "make_seamless",
    "make_tile",
    "mip_chain",
    "preview",
]
