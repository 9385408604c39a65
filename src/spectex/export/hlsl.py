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

from . import _template
from ._shader import has_stochastic, layer_library
from ._stochastic import table_info
from ._syntax import HLSL, bindings, layer_calls

__all__ = ["write_hlsl", "hlsl_include", "ENTRY_POINT"]

#: The include's entry point (Unity: Custom Function name "SpectexGround").
ENTRY_POINT = "SpectexGround_float"

#: The HLSL prelude of the layer library (``templates/hlsl/prelude.hlsl``): vector types and texture macros.
_PRELUDE = _template.read("hlsl/prelude.hlsl")


def _texture_inputs(texture) -> list[str]:
    """The entry point's texture inputs: the tiles, and for stochastic layers their Gaussianised levels
    and the table."""
    tiles = range(len(texture.tiles))
    names = [f"Tile{i}" for i in tiles]
    if has_stochastic(texture):
        names += [f"Gauss{i}" for i in tiles] + ["Lut"]
    return names


def hlsl_include(texture, tile_names) -> str:
    """The text of ``spectex_ground.hlsl`` for ``texture``: ``templates/hlsl/spectex_ground.hlsl`` with
    the texture's values."""
    h, w = texture.tile_shape
    context = {
        "n_layers": len(texture.layers), "n_tiles": len(texture.tiles), "width": w, "height": h,
        "tile_files": ", ".join(tile_names), "sizes": ", ".join(f"{layer.size:g} m" for layer in texture.layers),
        "prelude": _PRELUDE, "library": layer_library(anisotropic=True), "entry_point": ENTRY_POINT,
        "texture_params": HLSL.texture_params(_texture_inputs(texture)), "stochastic": has_stochastic(texture),
        "layers": layer_calls(texture), **bindings(texture, HLSL),
    }
    return _template.render("hlsl/spectex_ground.hlsl", context)


def _readme(texture, tile_names) -> str:
    tiles = ", ".join(f"`{n}`" for n in tile_names)
    inputs = _texture_inputs(texture)
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
