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

# The names below are loaded from their modules on first use (PEP 562), not here: ``from_noise`` and
# ``ops`` import numba, and every texture that is made or loaded goes through ``spectex.tiles.mipmap``
# (its tiles quantized), so an eager import here made every command that reads a texture import numba
# before it could refuse a bad argument, and ``spectex export`` import it without ever compiling.
_HOMES = {
    "ALPHAS": "from_noise",
    "MAX_SIZE": "from_noise",
    "METHODS": "from_noise",
    "make_tile": "from_noise",
    "SEAM_BAND": "from_photo",
    "make_seamless": "from_photo",
    "mip_chain": "mipmap",
    "emboss": "ops",
    "fit_range": "ops",
    "preview": "ops",
}

__all__ = sorted(_HOMES)


def __getattr__(name):
    home = _HOMES.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    from importlib import import_module

    value = getattr(import_module(f"{__name__}.{home}"), name)
    globals()[name] = value  # found directly from now on
    return value


def __dir__():
    return sorted(set(globals()) | set(_HOMES))
