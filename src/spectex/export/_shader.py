"""Where the exports get their shader text: the shading core's generator, and nothing else.

Every exported shader is text from :mod:`spectex.shading.glsl`, the module
that writes the renderer's own shader: the same layer library
(``shading/shaders/spectex_layers.glsl``), the same generated constants, the
same ``main()``, with the target's prelude (GLSL ES 3.00 for WebGL2, GLSL
3.30, or an engine's own: Godot, HLSL). No export holds a shader of its own
beyond the few lines that connect the library to an engine.
"""

from __future__ import annotations

import re

from spectex.shading.constants import FILTER_LINEAR_MIPMAP_LINEAR

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
    from spectex.shading.tables import pack

    tables = pack(texture, anisotropy=8.0 if anisotropic else 1.0, enabled=enabled)
    return glsl.fragment_source(tables, len(texture.tiles), target=target, anisotropic=anisotropic,
                                iso_lod=_iso_lod(texture))


def _iso_lod(texture) -> bool:
    h, w = texture.tile_shape
    return h == w


def ground_fragment(texture, target: str, *, anisotropic: bool = True) -> str:
    """The renderer's ground fragment shader for ``texture``, every layer drawn, for ``target``.

    With ``anisotropic`` the anisotropic path is compiled in (the renderer's
    ``SPX_ANISO``); ``u_max_aniso = 1`` then gives plain trilinear filtering.
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
    still open; they are cut out of the generator's own output here. Returns
    a dict:

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
    n = len(texture.layers)
    iso = _iso_lod(texture)

    def calls(on):
        text = _fragment(texture, target, anisotropic=False, enabled=[j in on for j in range(n)])
        # the switch that follows the drawn layers' tilings is the viewer's to set: the same in every variant
        return text.replace("#define STOCHASTIC 1\n", "#define STOCHASTIC 0\n")

    empty = calls(())
    first = [_difference(empty, calls((k,))) for k in range(n)]
    # layer 0 is drawn first whenever it is drawn; for the others, their call after layer 0's
    base = calls((0,))
    over = [first[0]] + [_difference(base, calls((0, k))) for k in range(1, n)]
    for k in range(n):
        for call in (first[k], over[k]):
            if not re.fullmatch(rf"\s*shade_layer(_stochastic)?\({k}, [^\n]*;", call):
                raise RuntimeError(f"ground shader: could not find layer {k}'s call")
    marker = "vec3 c = vec3(0.0);  // black where every layer is off\n"
    switches = {"#define SPX_ANISO 0\n": "#define SPX_ANISO @ANISO@\n",
                f"#define ISO_LOD {1 if iso else 0}\n": "#define ISO_LOD @ISO_LOD@\n",
                "#define STOCHASTIC 0\n": "#define STOCHASTIC @STOCHASTIC@\n",
                f"#define MIN_FILTER {FILTER_LINEAR_MIPMAP_LINEAR}\n": "#define MIN_FILTER @MIN_FILTER@\n",
                marker: marker + "//@LAYERS@\n"}
    source = empty
    for old, new in switches.items():
        if source.count(old) != 1:
            raise RuntimeError(f"ground shader: expected one {old.strip()!r}")
        source = source.replace(old, new)
    return {"source": source, "first": first, "over": over, "iso_lod": iso}


def _difference(base: str, more: str) -> str:
    """The lines ``more`` has where ``base`` has other (or no) lines: one changed block."""
    a = base.split("\n")
    b = more.split("\n")
    i = 0
    while i < min(len(a), len(b)) and a[i] == b[i]:
        i += 1
    j = 0
    while j < min(len(a), len(b)) - i and a[-1 - j] == b[-1 - j]:
        j += 1
    return "\n".join(line for line in b[i:len(b) - j] if line.strip())
