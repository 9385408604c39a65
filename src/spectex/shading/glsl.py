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
4. for the renderer, ``shaders/ground.frag.glsl``: the camera, the uniforms
   and ``main()``, with one unrolled call per drawn layer.

``render.gl`` compiles :func:`fragment_source`; the exports write the same
text (or :func:`layer_library` alone, for an engine's own main), so the
exported shader and the renderer's shader cannot drift apart.
"""

from __future__ import annotations

from importlib import resources

import numpy as np

from .constants import BLEND_FIRST, BLENDS, TILING_STOCHASTIC, glsl_defines

__all__ = ["TARGETS", "prelude", "layer_library", "fragment_source", "vertex_source", "shader_file"]

#: Targets: desktop OpenGL 3.3 core, and WebGL2 / OpenGL ES 3.0.
TARGETS = ("330", "es300")

_TEXTURE_MACROS = """#define SPX_TEX_ARG(name) sampler2D name
#define SPX_TEX(name) name
#define SPX_LOD(name, uv, lod) textureLod(name, uv, lod)
#define SPX_UINT uint
"""


def shader_file(name: str) -> str:
    """The text of ``shading/shaders/NAME``."""
    return resources.files("spectex.shading").joinpath("shaders", name).read_text(encoding="utf-8")


def _check_target(target):
    if target not in TARGETS:
        raise ValueError(f"target must be one of {', '.join(TARGETS)}, got {target!r}")
    return target


def prelude(target: str = "330") -> str:
    """``#version`` (and, for ``"es300"``, precision) lines and the texture macros."""
    _check_target(target)
    head = ("#version 330 core\n" if target == "330" else
            "#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n")
    return head + _TEXTURE_MACROS


def layer_library(*, anisotropic: bool = False) -> str:
    """The constants and the layer library, without a prelude (for exports that bring their own).

    ``anisotropic`` compiles the anisotropic path of ``spectex_sample_grad``
    (``SPX_ANISO``): even untaken, its loop costs llvmpipe about a third of
    a frame.
    """
    return (glsl_defines() + f"#define SPX_ANISO {1 if anisotropic else 0}\n"
            + shader_file("spectex_layers.glsl"))


def _blend_name(code: int) -> str:
    return "SPX_BLEND_FIRST" if code == BLEND_FIRST else f"SPX_BLEND_{BLENDS[code].upper()}"


def _float(value) -> str:
    """A float32 value as a GLSL literal that parses back to exactly that float32."""
    v = float(np.float32(value))
    if not np.isfinite(v):
        raise ValueError(f"a shader constant must be finite, got {v!r}")
    return repr(v)


def _vec(values) -> str:
    flat = [_float(v) for v in np.asarray(values, dtype=np.float64).reshape(-1)]
    return flat[0] if len(flat) == 1 else f"vec{len(flat)}({', '.join(flat)})"


def _static_values(tables) -> tuple[dict, dict]:
    """The values of the uniforms that depend on the texture only, as GLSL constant expressions.

    Per-layer arrays: name -> (element type, one expression per layer);
    scalars: name -> (type, expression). The same numbers ``render.gl``
    would set (float32), column-major for the decorrelation's ``mat3``.
    """
    n = len(tables.tile)
    per_layer = {
        "u_mat": ("vec4", [_vec(tables.mats[k]) for k in range(n)]),
        "u_mean": ("vec3", [_vec(tables.mean[k]) for k in range(n)]),
        "u_opacity": ("float", [_float(tables.opacity[k]) for k in range(n)]),
        "u_lod_off": ("float", [_float(tables.lod_off[k]) for k in range(n)]),
        "u_grid": ("vec4", [_vec(tables.grid[k]) for k in range(n)]),
        "u_key": ("uint", [f"{int(tables.key[k]) & 0xFFFFFFFF}u" for k in range(n)]),
        "u_snap": ("vec2", [_vec(tables.snap[k]) for k in range(n)]),
        "u_lut_row": ("float", [_float(int(tables.tile[k]) * int(tables.lut_rows)) for k in range(n)]),
        "u_basis": ("mat3", ["mat3(" + ", ".join(_float(v) for v in np.asarray(tables.basis[k]).T.reshape(-1)) + ")"
                             for k in range(n)]),
        "u_origin": ("vec3", [_vec(tables.origin[k]) for k in range(n)]),
    }
    scalars = {
        "u_tex_size": ("vec2", _vec([tables.widths[0], tables.heights[0]])),
        "u_max_aniso": ("float", _float(tables.max_aniso)),
        "u_lut_rows": ("float", _float(tables.lut.shape[0])),
        "u_lut_q": ("float", _float(len(tables.widths) - 1)),
    }
    return per_layer, scalars


def _constants_for_uniforms(text: str, tables) -> str:
    """``text`` with the texture's static uniforms declared as constants (``fragment_source``'s ``constants``)."""
    per_layer, scalars = _static_values(tables)
    for name, (kind, values) in per_layer.items():
        old = f"uniform {kind} {name}[N_LAYERS];"
        if text.count(old) != 1:
            raise RuntimeError(f"ground shader: expected one {old!r}")
        text = text.replace(old, f"const {kind} {name}[N_LAYERS] = {kind}[]({', '.join(values)});")
    for name, (kind, value) in scalars.items():
        old = f"uniform {kind} {name};"
        if text.count(old) != 1:
            raise RuntimeError(f"ground shader: expected one {old!r}")
        text = text.replace(old, f"const {kind} {name} = {value};")
    return text


def fragment_source(tables, n_tiles: int, *, target: str = "330", anisotropic: bool = False,
                    iso_lod: bool = False, sky_only: bool = False, constants: bool = False) -> str:
    """The ground shader for a texture's :class:`~spectex.shading.tables.ShadingTables`.

    Sampler arrays may only be indexed by constants, so each drawn layer
    (``tables.on``) gets its own call with its tile's index and its blend
    code (``tables.blend``: the first drawn layer has ``SPX_BLEND_FIRST``)
    written in, and the compiler folds every branch away: llvmpipe runs
    both sides of a branch it cannot fold, and a runtime toggle or "first
    layer" flag cost a quarter of the frame. ``iso_lod`` (square tiles, no
    anisotropy) derives each layer's level of detail from one per-pixel
    world level (``docs/sampling.md``, section 3). ``sky_only`` compiles
    the ground branch out, for the rows that see only sky. The
    minification filter's code is written in (``MIN_FILTER``), so that the
    stochastic layers' choice of table row folds to one formula.

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
    """
    calls = []
    for k in range(len(tables.tile)):
        if not tables.on[k]:
            continue
        tile = int(tables.tile[k])
        if int(tables.tiling[k]) == TILING_STOCHASTIC:
            calls.append(f"        shade_layer_stochastic({k}, {_blend_name(int(tables.blend[k]))}, u_gauss[{tile}], "
                         "u_lut, c, p, jx, jy, lam_w);")
        else:
            calls.append(f"        shade_layer({k}, {_blend_name(int(tables.blend[k]))}, u_tile[{tile}], "
                         "c, p, jx, jy, lam_w);")
    stochastic = bool(np.any(np.asarray(tables.tiling)[np.asarray(tables.on) != 0] == TILING_STOCHASTIC))
    switches = (f"#define N_LAYERS {len(tables.tile)}\n#define N_TILES {int(n_tiles)}\n"
                f"#define ISO_LOD {1 if iso_lod and not anisotropic else 0}\n"
                f"#define SKY_ONLY {1 if sky_only else 0}\n"
                f"#define STOCHASTIC {1 if stochastic else 0}\n"
                f"#define MIN_FILTER {int(tables.min_filter)}\n")
    main = shader_file("ground.frag.glsl").replace("//@LAYERS@", "\n".join(calls))
    if constants:
        main = _constants_for_uniforms(main, tables)
    return prelude(target) + layer_library(anisotropic=anisotropic) + switches + main


def vertex_source(target: str = "330") -> str:
    """The full-screen triangle's vertex shader."""
    head = "#version 330 core\n" if _check_target(target) == "330" else "#version 300 es\nprecision highp float;\n"
    return head + shader_file("fullscreen.vert.glsl")
