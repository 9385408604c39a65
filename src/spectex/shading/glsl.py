"""GLSL generation: the shader text of the renderer and of every export, from one source.

A shader is put together from

1. a **prelude** for the target (:data:`TARGETS`): the ``#version`` line,
   precision statements for GLSL ES, and the three texture macros the layer
   library is written with (``SPX_TEX_ARG``, ``SPX_TEX``, ``SPX_LOD``);
2. the **constants** of ``shading/constants.py`` as ``#define`` lines
   (:func:`spectex.shading.constants.glsl_defines`);
3. the **layer library** ``shaders/spectex_layers.glsl`` (self-contained: no
   uniforms, everything by argument): layer coordinates, sampling with the
   level of detail, blending, haze and sky;
4. for the renderer, ``shaders/ground.frag.glsl``: the switches, the
   camera, the uniforms and ``main()``, with one unrolled call per drawn
   layer: a template (:mod:`spectex._template`) filled in here with names
   and numbers only.

``render.gl`` compiles :func:`fragment_source`; the exports write the same
text (or :func:`layer_library` alone, for an engine's own main), so the
exported shader and the renderer's shader cannot drift apart.
"""

from __future__ import annotations

from importlib import resources

import numpy as np

from .._template import each_block, render_text
from .constants import BLEND_FIRST, BLENDS, TILING_STOCHASTIC, glsl_defines

__all__ = ["TARGETS", "prelude", "layer_library", "fragment_source", "vertex_source", "program_sources", "shader_file",
           "texture_macros", "blend_name", "layer_item", "layer_call"]

#: Targets: desktop OpenGL 3.3 core, and WebGL2 / OpenGL ES 3.0.
TARGETS = ("330", "es300")

def texture_macros() -> str:
    """The texture macros of GLSL (``SPX_TEX_ARG``, ``SPX_TEX``, ``SPX_LOD``) and ``SPX_UINT``, as the
    layer library takes them (``shaders/texture_macros.glsl``); the prelude of GLSL-like targets (Godot) too."""
    return shader_file("texture_macros.glsl")


def shader_file(name: str) -> str:
    """The text of ``shading/shaders/NAME``."""
    return resources.files("spectex.shading").joinpath("shaders", name).read_text(encoding="utf-8")


def _check_target(target):
    if target not in TARGETS:
        raise ValueError(f"target must be one of {', '.join(TARGETS)}, got {target!r}")
    return target


def _prelude_context(target) -> dict:
    return {"desktop": _check_target(target) == "330", "macros": texture_macros().removesuffix("\n")}


def prelude(target: str = "330") -> str:
    """``#version`` (and, for ``"es300"``, precision) lines and the texture macros (``shaders/prelude.glsl``)."""
    return render_text(shader_file("version.glsl") + shader_file("prelude.glsl"), _prelude_context(target))


def layer_library(*, anisotropic: bool = False) -> str:
    """The constants and the layer library, without a prelude (for exports that bring their own).

    ``anisotropic`` compiles the anisotropic path of ``spectex_sample_grad``
    (``SPX_ANISO``): even untaken, its loop costs llvmpipe about a third of
    a frame.
    """
    return render_text(shader_file("library.glsl"), _library_context(1 if anisotropic else 0))


def _library_context(aniso) -> dict:
    """``shaders/library.glsl``'s values: the constants, ``SPX_ANISO`` and the layer library."""
    return {"defines": glsl_defines().removesuffix("\n"), "aniso": aniso,
            "library": shader_file("spectex_layers.glsl").removesuffix("\n")}


def blend_name(code: int) -> str:
    """The layer library's name of a blend code (``SPX_BLEND_FIRST`` for ``BLEND_FIRST``)."""
    return "SPX_BLEND_FIRST" if code == BLEND_FIRST else f"SPX_BLEND_{BLENDS[code].upper()}"


def layer_item(k: int, tile: int, tiling: int, blend: int) -> dict:
    """What the ground shader's ``{{#each layers}}`` block takes for drawn layer ``k``: its index, its
    tile, its blend's code name (:func:`blend_name` of a ``constants.BLEND_*`` code) and whether it is
    stochastic (``constants.TILING_*`` code); the engine exports' templates take the same."""
    return {"k": int(k), "tile": int(tile), "blend": blend_name(int(blend)),
            "stochastic": int(tiling) == TILING_STOCHASTIC}


def layer_call(k: int, tile: int, tiling: int, blend: int) -> str:
    """The ground shader's call of drawn layer ``k`` (its tile, ``constants.TILING_*`` and
    ``constants.BLEND_*`` codes written in), one line of ``main()``: the shader's ``{{#each layers}}``
    block for that layer alone (the web viewer joins them at run time)."""
    return render_text(each_block(shader_file("ground.frag.glsl"), "layers"), layer_item(k, tile, tiling, blend))


def fragment_source(tables, n_tiles: int, *, target: str = "330", anisotropic: bool = False,
                    iso_lod: bool = False, sky_only: bool = False, constants: bool = False,
                    open_switches: bool = False) -> str:
    """The ground shader for a texture's :class:`~spectex.shading.tables.ShadingTables`.

    ``shaders/ground.frag.glsl`` is a template (:mod:`spectex._template`)
    filled in here with the switches, the inputs' declarations
    (``shading.interface``) and the drawn layers. Sampler arrays may only
    be indexed by constants, so each drawn layer (``tables.on``) gets its
    own call (the template's ``{{#each layers}}`` block) with its tile's
    index and its blend code (``tables.blend``: the first drawn layer has
    ``SPX_BLEND_FIRST``) written in, and the compiler folds every branch
    away: llvmpipe runs both sides of a branch it cannot fold, and a runtime
    toggle or "first layer" flag cost a quarter of the frame. ``iso_lod``
    (square tiles, no anisotropy) derives each layer's level of detail from
    one per-pixel world level (``docs/sampling.md``, section 3).
    ``sky_only`` compiles the ground branch out, for the rows that see only
    sky. The minification filter's code is written in (``MIN_FILTER``), so
    that the stochastic layers' choice of table row folds to one formula.

    ``constants`` writes the values of the uniforms that depend on the
    texture alone (the layers' maps, opacities, level offsets, mean colours,
    grids, hash keys, table rows and decorrelations; the tile size, the
    table's height and last level, the anisotropy limit) into the text as
    constants of the same name and float32 value, leaving as uniforms only
    what changes with the camera (the anchors, the view). llvmpipe then
    folds them into the instructions instead of keeping them live in
    registers: measured (1920 x 1080, the demo's ground view) 17 % off a
    frame of the paper's five periodic layers and 24 % off five stochastic
    ones. The renderer compiles one program per texture and sampler state
    anyway; the exports keep the uniforms (``constants=False``), which a
    viewer sets at run time.

    ``open_switches`` leaves the switches a viewer sets at run time open, as
    ``@ANISO@``, ``@ISO_LOD@``, ``@STOCHASTIC@`` and ``@MIN_FILTER@``, and no
    layer call but the marker ``//@LAYERS@`` where the drawn layers' calls
    (:func:`layer_call`) go (the web viewer's template).
    """
    return render_text(*_fragment(tables, n_tiles, target=target, anisotropic=anisotropic, iso_lod=iso_lod,
                                  sky_only=sky_only, constants=constants, open_switches=open_switches))


def _fragment(tables, n_tiles, *, target, anisotropic, iso_lod, sky_only, constants, open_switches):
    """:func:`fragment_source`'s template (``prelude.glsl``, ``library.glsl`` and ``ground.frag.glsl``, one
    after the other) and its values."""
    from . import interface

    layers = [layer_item(k, tables.tile[k], tables.tiling[k], tables.blend[k])
              for k in range(len(tables.tile)) if tables.on[k]]
    stochastic = bool(np.any(np.asarray(tables.tiling)[np.asarray(tables.on) != 0] == TILING_STOCHASTIC))
    values = {"ISO_LOD": 1 if iso_lod and not anisotropic else 0, "STOCHASTIC": 1 if stochastic else 0,
              "MIN_FILTER": int(tables.min_filter), "SPX_ANISO": 1 if anisotropic else 0}
    if open_switches:  # left to the viewer: @NAME@ in their place, and the layer calls' marker kept
        values = {name: f"@{name.removeprefix('SPX_')}@" for name in values}
        layers = []
    text = (shader_file("version.glsl") + shader_file("prelude.glsl") + shader_file("library.glsl")
            + shader_file("ground.frag.glsl"))
    context = {**_prelude_context(target), **_library_context(values["SPX_ANISO"]),
               "n_layers": len(tables.tile), "n_tiles": int(n_tiles), "iso_lod": values["ISO_LOD"],
               "sky_only": 1 if sky_only else 0, "any_stochastic": values["STOCHASTIC"],
               "min_filter": values["MIN_FILTER"], "open_layers": open_switches, "layers": layers}
    declarations = interface.glsl_declarations(interface.GLFrame(tables, int(n_tiles)) if constants else None)
    return text, {**context, "inputs": declarations.removesuffix("\n")}


def _vertex(target) -> tuple[str, dict]:
    text = shader_file("version.glsl") + shader_file("fullscreen.vert.glsl")
    return text, {"desktop": _check_target(target) == "330"}


def vertex_source(target: str = "330") -> str:
    """The full-screen triangle's vertex shader (``shaders/fullscreen.vert.glsl``)."""
    return render_text(*_vertex(target))


def program_sources(tables, n_tiles: int, *, target: str = "330", **switches) -> tuple[str, str]:
    """The renderer's program: :func:`vertex_source` and :func:`fragment_source` (its keywords), both
    templates filled in after everything they hold is known."""
    switches = {"anisotropic": False, "iso_lod": False, "sky_only": False, "constants": False,
                "open_switches": False, **switches}
    vertex = _vertex(target)
    fragment = _fragment(tables, n_tiles, target=target, **switches)
    return render_text(*vertex), render_text(*fragment)
