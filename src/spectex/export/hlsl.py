"""The ``hlsl`` export: spectex's layer library as an HLSL include, for Unity and Unreal.

``hlsl/spectex_ground.hlsl`` is the shading core's layer library
(:mod:`spectex.export._shader`) behind an HLSL prelude (``vec*`` as
``float*``, textures as ``Texture2D`` + ``SamplerState``, ``SampleLevel``),
the texture's layers as constants, and one entry point,

``SpectexGround_float(float2 Ground, Texture2D Tile0, SamplerState Tile0Sampler, ...,
out float3 Color, out float3 Linear)``

(a texture with stochastic layers also takes ``Gauss0``, ... and ``Lut``, the
textures of :mod:`spectex.export._stochastic`, written beside it as raw half
floats) with ``Ground`` the spectex ground point in metres (x east, y north):
Unity Shader Graph's Custom Function node calls it in file mode (the
``_float`` suffix is its precision convention) and Unreal's Custom node calls
it from an include. ``Color`` is spectex's colour (stored, display-encoded
values), ``Linear`` the same decoded from sRGB, for a base colour input. By
default the layers are anchored at the ground's origin (constants); with
``SPECTEX_ANCHORED`` defined, ``Ground`` is relative to an anchor point near
the camera and the host sets ``SpectexAnchor`` and ``SpectexGridBase`` per
frame (float64 there; the README's formula), which keeps the texture exact
far from the origin.
"""

from __future__ import annotations

from pathlib import Path

from ..shading.resources import mean_colours
from ._shader import has_stochastic, layer_library
from ._stochastic import constant_lines, table_info

__all__ = ["write_hlsl", "hlsl_include", "ENTRY_POINT"]

#: The include's entry point (Unity: Custom Function name "SpectexGround").
ENTRY_POINT = "SpectexGround_float"

_PRELUDE = """// HLSL for the GLSL-subset layer library: vector types, textures as Texture2D +
// SamplerState (Unreal names a texture input's sampler <name>Sampler; use the same in
// Unity), SampleLevel for textureLod. Undefined again at the end of this file.
#define vec2 float2
#define vec3 float3
#define vec4 float4
#define SPX_TEX_ARG(name) Texture2D name, SamplerState name##Sampler
#define SPX_TEX(name) name, name##Sampler
#define SPX_UINT uint
// Unity addresses textures with v = 0 at the bottom row of the image, Unreal at the
// top; spectex's t = 0 is the image's first (top) row: flip t under Unity (v = 1 - t,
// for the clamped look-up table too; load the raw tables bottom row first there).
#ifndef SPECTEX_FLIP_V
#ifdef UNITY_VERSION
#define SPECTEX_FLIP_V 1
#else
#define SPECTEX_FLIP_V 0
#endif
#endif
#if SPECTEX_FLIP_V
#define SPX_LOD(name, uv, lod) name.SampleLevel(name##Sampler, float2(1.0, -1.0) * (uv) + float2(0.0, 1.0), lod)
#else
#define SPX_LOD(name, uv, lod) name.SampleLevel(name##Sampler, uv, lod)
#endif
"""

_UNDEF = ("vec2", "vec3", "vec4", "SPX_TEX_ARG", "SPX_TEX", "SPX_LOD", "SPX_UINT", "SPECTEX_ST_ANCHOR",
          "SPECTEX_G_ANCHOR", "SPECTEX_G_BASE")


def _f(value: float) -> str:
    text = repr(float(value))
    return text if any(ch in text for ch in ".en") else text + ".0"


def _vec(values) -> str:
    return f"float{len(values)}(" + ", ".join(_f(v) for v in values) + ")"


def _uvec(values) -> str:
    return f"uint{len(values)}(" + ", ".join(f"{int(v)}u" for v in values) + ")"


def hlsl_include(texture, tile_names) -> str:
    """The text of ``spectex_ground.hlsl`` for ``texture``."""
    from ..shading.tables import anchor_coords

    n = len(texture.layers)
    h, w = texture.tile_shape
    means = mean_colours(texture)
    anchors = anchor_coords(texture.layers, 0.0, 0.0)
    origin = anchors[:, :2]
    tiles = range(len(texture.tiles))
    mats = [layer.matrix() for layer in texture.layers]
    tile_of = [layer.tile for layer in texture.layers]
    stochastic = has_stochastic(texture)
    args = ", ".join(f"Texture2D Tile{i}, SamplerState Tile{i}Sampler" for i in tiles)
    if stochastic:
        args += "".join(f", Texture2D Gauss{i}, SamplerState Gauss{i}Sampler" for i in tiles)
        args += ", Texture2D Lut, SamplerState LutSampler"
    lines = [
        "// spectex spectral texture for Unity Shader Graph (Custom Function, file mode, name",
        "// \"SpectexGround\") and Unreal (Custom node with this file as an include), written by",
        "// `spectex export` (docs/export.md).",
        f"// {n} layers over {len(texture.tiles)} tile(s) of {w} x {h} texels ("
        + ", ".join(tile_names) + "): " + ", ".join(f"{layer.size:g} m" for layer in texture.layers) + ".",
        "// The layer library below is spectex's own (spectex/shading/shaders/spectex_layers.glsl), unchanged.",
        "#ifndef SPECTEX_GROUND_INCLUDED",
        "#define SPECTEX_GROUND_INCLUDED",
        "",
        _PRELUDE + layer_library(anisotropic=True),
        "// ---- the texture's layers",
        f"static const float4 SPECTEX_MAT[{n}] = {{{', '.join(_vec(m.reshape(-1)) for m in mats)}}};",
        f"static const float3 SPECTEX_MEAN[{n}] = {{{', '.join(_vec(means[t]) for t in tile_of)}}};",
        f"static const float SPECTEX_OPACITY[{n}] = {{{', '.join(_f(layer.opacity) for layer in texture.layers)}}};",
        "// each layer's tile coordinates of the ground point (0, 0), computed in float64, mod 2",
        f"static const float2 SPECTEX_ORIGIN_ANCHOR[{n}] = {{{', '.join(_vec(a) for a in origin)}}};",
        f"static const float2 SPECTEX_TEX_SIZE = {_vec((w, h))};",
        *(_stochastic_constants(texture, anchors) if stochastic else []),
        "#ifdef SPECTEX_ANCHORED",
        "// Set by the host every frame, in float64 there: per layer, its tile coordinates (s, t) at the",
        "// anchor point mod 2 (xy) and, for a stochastic layer, the anchor's triangle-grid fraction (zw);",
        "// the grid vertex mod 2^32 as whole 16-bit halves (x_hi, x_lo, y_hi, y_lo). Ground is then",
        "// relative to the anchor point (README.md).",
        f"float4 SpectexAnchor[{n}];",
        f"float4 SpectexGridBase[{n}];",
        "#define SPECTEX_ST_ANCHOR(k) SpectexAnchor[k].xy",
        "#define SPECTEX_G_ANCHOR(k) SpectexAnchor[k].zw",
        "#define SPECTEX_G_BASE(k) (uint2(SpectexGridBase[k].xz) * 65536u + uint2(SpectexGridBase[k].yw))",
        "#else",
        "#define SPECTEX_ST_ANCHOR(k) SPECTEX_ORIGIN_ANCHOR[k]",
        "#define SPECTEX_G_ANCHOR(k) SPECTEX_ORIGIN_GANCHOR[k]",
        "#define SPECTEX_G_BASE(k) SPECTEX_ORIGIN_GBASE[k]",
        "#endif",
        "#ifndef SPECTEX_MAX_ANISOTROPY",
        "#define SPECTEX_MAX_ANISOTROPY 8.0  // spectex's own anisotropic filter; 1 = off",
        "#endif",
        "",
        "// One layer over c.",
        "void spectex_layer(int blend, SPX_TEX_ARG(tile), int k, inout vec3 c, vec2 p, vec2 jx, vec2 jy) {",
        "    vec4 m = SPECTEX_MAT[k];",
        "    vec2 st = spectex_layer_coords(SPECTEX_ST_ANCHOR(k), m, p);",
        "    vec2 dx = spectex_layer_deriv(m, jx);",
        "    vec2 dy = spectex_layer_deriv(m, jy);",
        "    vec4 x = spectex_sample_grad(SPX_TEX(tile), st, dx, dy, SPECTEX_TEX_SIZE,",
        "                                 (blend == SPX_BLEND_FINE) ? 1.0 : SPECTEX_MAX_ANISOTROPY);"
        "  // fine: isotropic",
        "    float lam = (blend == SPX_BLEND_FINE || blend == SPX_BLEND_COVER)"
        " ? spectex_fade_lod(dx, dy, SPECTEX_TEX_SIZE) : 0.0;",
        "    c = spectex_blend(blend, c, x, SPECTEX_OPACITY[k], SPECTEX_MEAN[k], lam);",
        "}",
        "",
        *(_STOCHASTIC_LAYER if stochastic else []),
        "// Ground: the spectex ground point in metres (x east, y north). In a pixel shader only",
        "// (the footprint comes from ddx/ddy). Color: spectex's colour; Linear: decoded from sRGB.",
        f"void {ENTRY_POINT}(float2 Ground, {args}, out float3 Color, out float3 Linear) {{",
        "    vec2 p = Ground;",
        "    vec2 jx = ddx(p);",
        "    vec2 jy = ddy(p);",
        "    vec3 c = float3(0.0, 0.0, 0.0);",
    ]
    for k, layer in enumerate(texture.layers):
        blend = "SPX_BLEND_FIRST" if k == 0 else f"SPX_BLEND_{layer.blend.upper()}"
        if layer.tiling == "stochastic":
            lines.append(f"    spectex_layer_stochastic({blend}, SPX_TEX(Gauss{layer.tile}), SPX_TEX(Lut), {k}, "
                         "c, p, jx, jy);")
        else:
            lines.append(f"    spectex_layer({blend}, SPX_TEX(Tile{layer.tile}), {k}, c, p, jx, jy);")
    lines += [
        "    Color = saturate(c);",
        "    float3 lo = Color / 12.92;",
        "    float3 hi = pow((Color + 0.055) / 1.055, float3(2.4, 2.4, 2.4));",
        "    Linear = lerp(hi, lo, step(Color, float3(0.04045, 0.04045, 0.04045)));  // lo where Color <= 0.04045",
        "}",
        "",
        *(f"#undef {name}" for name in _UNDEF),
        "#endif  // SPECTEX_GROUND_INCLUDED",
        "",
    ]
    return "\n".join(lines)


_STOCHASTIC_LAYER = [
    "// A stochastic layer over c (histogram-preserving tiling and blending), as spectex's",
    "// shade_layer_stochastic: the grid position relative to the anchor's.",
    "void spectex_layer_stochastic(int blend, SPX_TEX_ARG(gauss), SPX_TEX_ARG(lut), int k, inout vec3 c, vec2 p,",
    "                              vec2 jx, vec2 jy) {",
    "    vec4 m = SPECTEX_MAT[k];",
    "    vec4 gm = SPECTEX_GRID[k];",
    "    vec2 rel = spectex_layer_deriv(m, p);",
    "    vec2 g = SPECTEX_G_ANCHOR(k) + vec2(gm.x * rel.x + gm.y * rel.y, gm.z * rel.x + gm.w * rel.y);",
    "    uint2 base = SPECTEX_G_BASE(k);",
    "    vec4 x = spectex_sample_stochastic_grad(SPX_TEX(gauss), SPX_TEX(lut), SPECTEX_ST_ANCHOR(k) + rel, g, base.x,",
    "                                            base.y, SPECTEX_KEY[k], SPECTEX_SNAP[k], spectex_layer_deriv(m, jx),",
    "                                            spectex_layer_deriv(m, jy), SPECTEX_TEX_SIZE, "
    "(blend == SPX_BLEND_FINE) ? 1.0 : SPECTEX_MAX_ANISOTROPY,",
    "                                            gm, SPX_FILTER_LINEAR_MIPMAP_LINEAR, SPECTEX_LUT_Q,",
    "                                            SPECTEX_LUT_ROW[k], SPECTEX_LUT_ROWS, SPECTEX_B0[k], SPECTEX_B1[k],",
    "                                            SPECTEX_B2[k], SPECTEX_ORIGIN_RGB[k]);",
    "    float lam = (blend == SPX_BLEND_FINE || blend == SPX_BLEND_COVER)",
    "        ? spectex_fade_lod(spectex_layer_deriv(m, jx), spectex_layer_deriv(m, jy), SPECTEX_TEX_SIZE) : 0.0;",
    "    c = spectex_blend(blend, c, x, SPECTEX_OPACITY[k], SPECTEX_MEAN[k], lam);",
    "}",
    "",
]


def _stochastic_constants(texture, anchors) -> list[str]:
    """The stochastic layers' constants (zeros for periodic layers)."""
    types = {"vec2": "float2", "vec3": "float3", "vec4": "float4", "uvec2": "uint2"}
    return [
        "// ---- stochastic layers: per layer its tile -> triangle-grid map, hash key, snap counts, first table row,",
        "// decorrelation (RGB = origin + b0 v.x + b1 v.y + b2 v.z) and the grid position of ground (0, 0)",
        *constant_lines(texture, anchors, declare="static const", types=types, number=_f, vector=_vec,
                        uvector=_uvec),
    ]


def _readme(texture, tile_names) -> str:
    tiles = ", ".join(f"`{n}`" for n in tile_names)
    inputs = [f"Tile{i}" for i in range(len(tile_names))]
    if has_stochastic(texture):
        inputs += [f"Gauss{i}" for i in range(len(tile_names))] + ["Lut"]
    call = ", ".join(f"{name}, {name}Sampler" for name in inputs)
    ports = ", ".join(f"`{name}` (Bare Texture2D), `{name}Sampler` (Bare SamplerState)" for name in inputs)
    extra = ("" if not has_stochastic(texture) else
             "\n   Stochastic layers also take their Gaussianised levels (`Gauss0`, ...) and the\n"
             "   look-up table (`Lut`) with their samplers: load them as *Stochastic layers*\n"
             "   below says and set them as Texture 2D properties too.")
    lut_sampler = ("" if not has_stochastic(texture) else
                   " for the tiles and the Gaussianised levels, and one with\n   Filter: Point, Wrap: Clamp for `Lut`")
    return f"""# spectex texture: HLSL (Unity Shader Graph, Unreal)

Written by `spectex export`: `spectex_ground.hlsl` and {tiles}.

The include defines `{ENTRY_POINT}(Ground, Tile0, Tile0Sampler, ..., out Color, out Linear)`.
`Ground` is the spectex ground point in metres: x east, y north.

## Unity (Shader Graph)

1. Import {tiles} with *sRGB (Color Texture): off* (the tile is data),
   *Alpha Is Transparency: off* (it changes the colour of transparent texels),
   *Compression: None*, *Generate Mip Maps: on*, *Wrap Mode: Repeat*,
   *Filter Mode: Trilinear*.
2. Add a *Custom Function* node: *Type: File*, *Source: spectex_ground.hlsl*,
   *Name: SpectexGround*, and in the Graph Inspector's node settings
   *Precision: Single* (Shader Graph calls `SpectexGround_float`; the include
   has no `_half` version). Inputs, in this order: `Ground` (Vector 2), {ports};
   outputs: `Color` (Vector 3), `Linear` (Vector 3).{extra}
3. `Ground`: *Position* node (World) into a *Swizzle* `xz` (Unity: x east,
   z north; times metres per unit if a unit is not a metre). Texture inputs:
   Texture 2D properties; sampler inputs: a *Sampler State* node (Filter:
   Trilinear, Wrap: Repeat){lut_sampler}.
4. `Linear` into *Base Color* (in a linear-colour-space project; `Color` in a
   gamma one).

## Unreal

1. Import {tiles}: *sRGB: off*, *Compression Settings: UserInterface2D (RGBA)*
   or *VectorDisplacementmap* (uncompressed 8-bit RGBA, so the alpha survives),
   *Mip Gen Settings: SimpleAverage*, *X/Y-axis Tiling Method: Wrap*.
2. Put `spectex_ground.hlsl` in a shader directory your project maps (a
   plugin's or module's `Shaders/` folder, mapped with
   `AddShaderSourceDirectoryMapping`), e.g. as `/Project/spectex_ground.ush`.
3. A *Custom* node: *Include File Paths*: that path; *Output Type*: Float 3;
   inputs `Ground` (e.g. `WorldPosition.yx / 100`: Unreal's y east, x north,
   centimetres) and the tile(s) as *Texture Object* inputs named `Tile0`, ...
   (Unreal passes `Tile0` and `Tile0Sampler`); code:
   `float3 c, lin; {ENTRY_POINT}(Ground, {call}, c, lin); return lin;`

Under Unity (`UNITY_VERSION` defined) the include flips the texture's v axis
(Unity's v = 0 is the image's bottom row); elsewhere it does not. Define
`SPECTEX_FLIP_V` 0 or 1 before the include to choose, and
`SPECTEX_MAX_ANISOTROPY` (default 8, 1 = off) for spectex's own anisotropic
filter.

What matches spectex: the layer arithmetic (the same library text),
addressing, level of detail and blend. What differs: the engine generates
the mip levels; the footprint comes from `ddx`/`ddy` (per 2 x 2 pixel quad);
the ground point is a 32-bit float, so by default the texture is exact near
the origin and loses precision thousands of kilometres away; see *Far from the
origin* below.

## Far from the origin: `SPECTEX_ANCHORED`

Define `SPECTEX_ANCHORED` before the include and pass `Ground` relative to an
anchor point `a` near the camera (e.g. snapped to 256 m, so it moves rarely;
the world position minus `a`, with `a` subtracted in double precision on the
CPU or in camera-relative rendering). Set, per frame and per layer `k`, the
global arrays (Unity: `Shader.SetGlobalVectorArray`), computed in float64:

* `(s, t) = M_k (a - offset_k)` (`M_k`: the layer's 2 x 2 matrix, from
  `spectex_ground.hlsl`'s `SPECTEX_MAT[k]` or `spectex export --format glsl`'s
  table; `offset_k` its offset);
* `SpectexAnchor[k] = (s mod 2, t mod 2, kx - floor(kx), ky - floor(ky))`, with
  `(kx, ky) = G_k (s, t)` for a stochastic layer (`G_k`: `SPECTEX_GRID[k]`,
  applied to the *unreduced* `s, t`), zeros in z, w otherwise;
* `SpectexGridBase[k] = (bx >> 16, bx & 65535, by >> 16, by & 65535)` with
  `bx = floor(kx) mod 2^32`, `by = floor(ky) mod 2^32`: the grid vertex, whose
  hash picks the patches, as 16-bit halves (whole numbers: exact in a float).
""" + (_stochastic_readme(texture, tile_names) if has_stochastic(texture) else "")


def _stochastic_readme(texture, tile_names) -> str:
    from ._stochastic import LUT_FILE, gauss_name

    info = table_info(texture)
    gauss = ", ".join(f"`{gauss_name(texture, i)}`" for i in range(len(tile_names)))
    shapes = ", ".join(f"{w} x {h}" for h, w in info["level_shapes"])
    return f"""
## Stochastic layers

The stochastic layers (spectex's histogram-preserving tiling: they never
repeat) sample no tile but two textures made from it, shipped losslessly as
raw little-endian IEEE half floats, rows top first:

* {gauss}: per tile `i`, input `Gauss{{i}}`: RGBA half floats, mip levels
  {shapes} one after the other; wrap *Repeat*, trilinear;
* `{LUT_FILE}`: input `Lut`: one channel of half floats,
  {info['lut_size']} x {4 * info['lut_rows']}, no mip-maps; *Point* filtering,
  *Clamp*.

Unity: `new Texture2D(w, h, TextureFormat.RGBAHalf, mipCount, true)` (linear),
`LoadRawTextureData(bytes)`, `Apply(false)`; `TextureFormat.RHalf` without
mip-maps for the table; Unity's v = 0 is the bottom row, so reverse each
level's rows when loading (the include flips v under Unity). Unreal: create
the textures from the raw data in an editor script (`PF_FloatRGBA`, `PF_R16F`),
or convert them to EXR half-float images with any tool that keeps halves.
"""


def write_hlsl(texture, folder: Path) -> list[Path]:
    """Write ``folder/hlsl/``; return the files written."""
    from ._stochastic import write_tables
    from ._tiles import write_tiles

    out = Path(folder) / "hlsl"
    out.mkdir()
    tiles = write_tiles(texture, out)
    names = [p.name for p in tiles]
    files = []
    for name, text in (("spectex_ground.hlsl", hlsl_include(texture, names)), ("README.md", _readme(texture, names))):
        (out / name).write_text(text, encoding="utf-8")
        files.append(out / name)
    return files + tiles + write_tables(texture, out)
