"""Where the exports get their shader text: the renderer's own shaders.

Every exported shader is the text the GL renderer compiles, with a
target-specific first line (``#version`` and precision statements); no export
holds a shader of its own. This module is the one place that fetches it.
"""

from __future__ import annotations

from importlib import resources

__all__ = ["GLSL_TARGETS", "prelude", "vertex_source", "ground_template", "ground_fragment"]

#: GLSL dialects the exports write: WebGL2 / OpenGL ES 3.0, and desktop OpenGL 3.3.
GLSL_TARGETS = ("es300", "330")

_PRELUDES = {
    "es300": "#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n",
    "330": "#version 330 core\n",
}


def prelude(target: str) -> str:
    """The lines that open a shader for ``target`` (``"es300"`` or ``"330"``)."""
    if target not in _PRELUDES:
        raise ValueError(f"target must be one of {', '.join(map(repr, GLSL_TARGETS))}, got {target!r}")
    return _PRELUDES[target]


def _renderer_shader(name: str) -> str:
    return resources.files("spectex.render").joinpath("shaders", name).read_text(encoding="utf-8")


def _retarget(source: str, target: str) -> str:
    """Swap the renderer's ``#version 330 core`` line for ``target``'s prelude."""
    first, rest = source.split("\n", 1)
    if not first.startswith("#version"):
        raise RuntimeError(f"renderer shader does not start with #version: {first!r}")
    return prelude(target) + rest


def vertex_source(target: str) -> str:
    """The renderer's full-screen-triangle vertex shader for ``target``."""
    return _retarget(_renderer_shader("fullscreen.vert.glsl"), target)


def ground_template(texture, target: str) -> dict:
    """The renderer's ground fragment shader for ``texture``, with the layer calls left open.

    The renderer compiles one program per set of layer toggles, with each
    enabled layer's call written in (the first one sets the colour, code -1).
    A viewer that toggles layers at run time needs the same text with those
    calls still open. Returns a dict:

    ``source``
        the shader for ``target`` with ``@ANISO@`` (1: the anisotropic
        path), ``@ISO_LOD@`` and ``//@LAYERS@`` still to fill in;
    ``first``, ``over``
        per layer, its call when it is the first enabled layer (sets the
        colour) and when it goes over others (its blend);
    ``iso_lod``
        whether ``@ISO_LOD@`` may be 1 (square tiles), as the renderer
        decides it: only when the anisotropic path is off.
    """
    from spectex.render.gl import fragment_source

    n = len(texture.layers)
    tiles = [layer.tile for layer in texture.layers]
    blends = [("alpha", "detail", "variance").index(layer.blend) for layer in texture.layers]
    iso = texture.tile_shape[0] == texture.tile_shape[1]
    marker = "@@SPECTEX-LAYERS@@"
    # The renderer's generator with every layer off leaves an empty line where
    # the calls go; each layer alone (first) or after layer 0 (over) gives its call.
    def calls(enabled):
        return fragment_source(n, len(texture.tiles), tiles, blends, anisotropic=False, iso_lod=iso,
                               enabled=enabled)

    empty = calls([False] * n)
    first, over = [], []
    for k in range(n):
        alone = calls([j == k for j in range(n)])
        first.append(_difference(empty, alone))
    for k in range(n):
        if k == 0:  # drawn first whenever it is enabled
            over.append(first[0])
            continue
        base = calls([j == 0 for j in range(n)])
        both = calls([j in (0, k) for j in range(n)])
        over.append(_difference(base, both))
    source = _retarget(empty, target)
    anchor = "c = vec3(0.0);  // black where every layer is off\n"
    if anchor not in source:
        raise RuntimeError("renderer shader: no place for the layer calls")
    source = source.replace(anchor, anchor + marker + "\n", 1)
    aniso_line = "#define ANISO 0"
    if aniso_line not in source:
        raise RuntimeError("renderer shader: no ANISO switch")
    iso_line = f"#define ISO_LOD {1 if iso else 0}"
    if iso_line not in source:
        raise RuntimeError("renderer shader: no ISO_LOD switch")
    source = (source.replace(aniso_line, "#define ANISO @ANISO@", 1).replace(iso_line, "#define ISO_LOD @ISO_LOD@", 1)
              .replace(marker, "//@LAYERS@"))
    return {"source": source, "first": first, "over": over, "iso_lod": iso}


def _difference(base: str, more: str) -> str:
    """The lines ``more`` has that ``base`` lacks (one inserted block)."""
    a = base.split("\n")
    b = more.split("\n")
    i = 0
    while i < len(a) and a[i] == b[i]:
        i += 1
    j = 0
    while j < len(a) - i and a[-1 - j] == b[-1 - j]:
        j += 1
    return "\n".join(b[i:len(b) - j])


def ground_fragment(texture, target: str, *, anisotropic: bool = True) -> str:
    """The renderer's ground fragment shader for ``texture``, every layer drawn, for ``target``.

    With ``anisotropic`` the anisotropic path is compiled in (the renderer's
    ``ANISO``); ``u_max_aniso = 1`` then gives plain trilinear filtering.
    """
    from spectex.render.gl import fragment_source

    n = len(texture.layers)
    text = fragment_source(n, len(texture.tiles), [layer.tile for layer in texture.layers],
                           [("alpha", "detail", "variance").index(layer.blend) for layer in texture.layers],
                           anisotropic=anisotropic, iso_lod=texture.tile_shape[0] == texture.tile_shape[1])
    return _retarget(text, target)
