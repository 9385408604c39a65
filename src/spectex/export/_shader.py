"""Where the exports get their shader text: the shading core's generator, and nothing else.

Every exported shader is text from :mod:`spectex.shading.glsl`, the module
that writes the renderer's own shader: the same layer library
(``shading/shaders/spectex_layers.glsl``), the same generated constants, the
same ``main()``, with the target's prelude (GLSL ES 3.00 for WebGL2, GLSL
3.30, or an engine's own: Godot, HLSL). No export holds a shader of its own
beyond the few lines that connect the library to an engine.
"""

from __future__ import annotations

from spectex.shading.constants import BLENDS

__all__ = ["GLSL_TARGETS", "prelude", "layer_library", "vertex_source", "ground_fragment", "ground_template",
           "has_stochastic"]

#: GLSL dialects the exports write: WebGL2 / OpenGL ES 3.0, and desktop OpenGL 3.3.
GLSL_TARGETS = ("es300", "330")


def prelude(target: str) -> str:
    """The lines that open a GLSL shader for ``target`` (``#version``, precision, texture macros)."""
    from spectex.shading import glsl

    return glsl.prelude(target)


def layer_library(*, anisotropic: bool = True) -> str:
    """The generated constants and the layer library, without a prelude."""
    from spectex.shading import glsl

    return glsl.layer_library(anisotropic=anisotropic)


def vertex_source(target: str) -> str:
    """The renderer's full-screen-triangle vertex shader for ``target``."""
    from spectex.shading import glsl

    return glsl.vertex_source(target)


def _fragment(texture, target: str, *, anisotropic: bool, enabled=None) -> str:
    from spectex.shading import glsl
    from spectex.shading.constants import DEFAULT_ANISOTROPY
    from spectex.shading.tables import pack

    tables = pack(texture, anisotropy=DEFAULT_ANISOTROPY if anisotropic else 1.0, enabled=enabled)
    return glsl.fragment_source(tables, len(texture.tiles), target=target, anisotropic=anisotropic,
                                iso_lod=_iso_lod(texture))


def _iso_lod(texture) -> bool:
    h, w = texture.tile_shape
    return h == w


def ground_fragment(texture, target: str, *, anisotropic: bool = True) -> str:
    """The renderer's ground fragment shader for ``texture``, every layer drawn, for ``target``.

    With ``anisotropic`` the anisotropic path is compiled in (the renderer's
    ``SPX_ANISO``); an anisotropy limit of 1 then gives plain trilinear filtering.
    """
    return _fragment(texture, target, anisotropic=anisotropic)


def has_stochastic(texture) -> bool:
    """Whether any layer of ``texture`` uses the stochastic tiling (its exports then carry the tables)."""
    return any(getattr(layer, "tiling", "periodic") == "stochastic" for layer in texture.layers)


def ground_template(texture, target: str) -> dict:
    """The renderer's ground fragment shader for ``texture``, with the layer calls left open.

    The renderer compiles one program per set of layer toggles, with each
    drawn layer's call written in (the first one sets the colour). A viewer
    that toggles layers at run time needs the same text with those calls
    still open: the generator writes them open (``fragment_source(open_switches=True)``)
    and each call with :func:`spectex.shading.glsl.layer_call`, as for the
    renderer. Returns a dict:

    ``source``
        the shader for ``target`` with ``@ANISO@`` (1: the anisotropic
        path), ``@ISO_LOD@``, ``@STOCHASTIC@`` (1: some drawn layer is
        stochastic), ``@MIN_FILTER@`` (the minification filter's code) and
        ``//@LAYERS@`` still to fill in;
    ``first``, ``over``
        per layer, its call when it is the first drawn layer (sets the
        colour) and when it goes over others (its blend);
    ``iso_lod``
        whether ``@ISO_LOD@`` may be 1 (square tiles), as the renderer
        decides it: only when the anisotropic path is off.
    """
    from spectex.shading import glsl
    from spectex.shading.constants import BLEND_FIRST
    from spectex.shading.tables import pack

    tables = pack(texture, anisotropy=1.0)
    source = glsl.fragment_source(tables, len(texture.tiles), target=target, iso_lod=_iso_lod(texture),
                                  open_switches=True)
    layers = [(int(tables.tile[k]), int(tables.tiling[k])) for k in range(len(texture.layers))]
    first = [glsl.layer_call(k, tile, tiling, BLEND_FIRST) for k, (tile, tiling) in enumerate(layers)]
    # layer 0 is drawn first whenever it is drawn; the others go over with their own blend
    over = first[:1] + [glsl.layer_call(k, tile, tiling, BLENDS.index(texture.layers[k].blend))
                        for k, (tile, tiling) in enumerate(layers) if k > 0]
    return {"source": source, "first": first, "over": over, "iso_lod": _iso_lod(texture)}
