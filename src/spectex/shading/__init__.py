"""The shading core: how a spectral texture is sampled, composited and seen.

One home for the shading specification (``docs/sampling.md``), below the
renderers (``spectex.render``), which call down into it. It reads textures
(``spectex.texture``: plain data, which imports nothing from here but the
leaf ``shading.constants``) through their attributes and ``Layer.matrix``,
without importing them; nothing here imports anything above.

========================  ================================================
module                    what lives there
========================  ================================================
``shading.constants``     the one table of codes and constants (blends,
                          tilings, filters, wraps, sky and haze, limits)
``shading.sampler``       the OpenGL-exact single-texture sampler (1-5)
``shading._mip_texture``  its texture object, :class:`MipTexture` (plain
                          data: no kernel, no numba), and the filter and
                          wrap names' codes
``shading.resources``     derived data of a texture (mip levels, texel
                          stores, stochastic tables), cached by content
``shading.tables``        a texture as one typed structure for the kernels
                          and the shader (:class:`ShadingTables`)
``shading._layers``       a layer's sample and blend, per point and per row (6)
``shading.stochastic``    stochastic tiling: its tables and per-point sample (6b)
``shading.camera``        camera, atmosphere, :class:`ViewParams` (7)
``shading.view``          ground footprint, haze, sky; bake and render kernels (7-8)
``shading.glsl``          the GLSL of the renderer and the exports, generated
``shading/shaders/``      the GLSL sources: the layer library and ``main()``
========================  ================================================

A new layer mode: its name in ``constants``, one branch in
``_layers.sample_layer``, one in ``shaders/spectex_layers.glsl``.

Nothing heavy is imported here: the numba modules load on first use.
"""

from __future__ import annotations

from . import constants

__all__ = ["constants", "Camera", "Atmosphere", "ViewParams", "view_params", "check_size", "MAX_RENDER_PIXELS",
           "ShadingTables", "pack", "anchor_coords"]

_LAZY = {"ShadingTables": "tables", "pack": "tables", "anchor_coords": "tables",
         "Camera": "camera", "Atmosphere": "camera", "ViewParams": "camera", "view_params": "camera",
         "check_size": "camera", "MAX_RENDER_PIXELS": "camera"}


def __getattr__(name):
    if name in _LAZY:
        from importlib import import_module

        return getattr(import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
