"""The ``godot`` export: a Godot 4 spatial shader over spectex's layer library.

``godot/`` holds:

* ``spectex_ground.gdshader``: ``shader_type spatial``, then the shading
  core's layer library (:mod:`spectex.export._shader`) behind Godot's
  texture macros, the texture's layers as constants, one sampler uniform per
  tile, and a ``fragment()`` that samples every layer at the pixel's ground
  footprint (``dFdx``/``dFdy`` of the ground point), blends them as spectex
  does and hands the result to Godot as linear colour;
* ``spectex_ground.gd``: a script for the ground ``MeshInstance3D`` that
  keeps the layer anchors next to the camera (float64 in GDScript), so that
  the texture stays precise far from the origin;
* the tile(s) as lossless PNGs, and ``README.md`` (import settings);
* for stochastic layers, their tables as raw half floats
  (:mod:`spectex.export._stochastic`), which the script loads into
  ``ImageTexture`` objects exactly (``Image.create_from_data``, ``FORMAT_RGBAH``
  with every mip level, ``FORMAT_RH``): no import step, no loss.

The tile is *data* (alpha is the blend weight; colours are blended as
spectex blends them, on the stored values), so its sampler has no
``source_color`` hint: the blended colour is decoded from sRGB once, at the
end, which reproduces spectex's picture exactly in an unshaded material.
"""

from __future__ import annotations

from pathlib import Path

from ..shading.resources import mean_colours
from ._shader import has_stochastic, layer_library
from ._stochastic import LUT_FILE, constant_lines, gauss_name, layer_entries, table_info

__all__ = ["write_godot", "godot_shader", "godot_script"]

_GODOT_MACROS = """#define SPX_TEX_ARG(name) sampler2D name
#define SPX_TEX(name) name
#define SPX_LOD(name, uv, lod) textureLod(name, uv, lod)
#define SPX_UINT uint
"""


def _f(value: float) -> str:
    text = repr(float(value))
    return text if any(ch in text for ch in ".en") else text + ".0"


def _vec(values) -> str:
    return f"vec{len(values)}(" + ", ".join(_f(v) for v in values) + ")"


def _blend_name(k: int, blend: str) -> str:
    return "SPX_BLEND_FIRST" if k == 0 else f"SPX_BLEND_{blend.upper()}"


def _uvec(values) -> str:
    return f"uvec{len(values)}(" + ", ".join(f"{int(v)}u" for v in values) + ")"


def godot_shader(texture, tile_names) -> str:
    """The ``.gdshader`` text for ``texture`` (``tile_names``: per tile, its PNG)."""
    from ..shading.tables import anchor_coords

    n = len(texture.layers)
    means = mean_colours(texture)
    anchors = anchor_coords(texture.layers, 0.0, 0.0)
    origin = anchors[:, :2]
    stochastic = has_stochastic(texture)
    h, w = texture.tile_shape
    lines = [
        "shader_type spatial;",
        "// render_mode unshaded;  // uncomment: spectex's colours exactly, without Godot's lighting",
        "",
        "// spectex spectral texture, written by `spectex export` (docs/export.md).",
        f"// {n} layers over {len(texture.tiles)} tile(s) of {w} x {h} texels: "
        + ", ".join(f"{layer.size:g} m" for layer in texture.layers) + ".",
        "// Ground coordinates: spectex x (east) = world X, spectex y (north) = world -Z, metres =",
        "// world units * spectex_metres_per_unit. The layer library below is spectex's own",
        "// (spectex/shading/shaders/spectex_layers.glsl), unchanged.",
        "",
        _GODOT_MACROS + layer_library(anisotropic=True),
        "// ---- the texture: tiles (data, not sRGB colour: no source_color), layers as constants",
    ]
    for i, name in enumerate(tile_names):
        lines.append(f"uniform sampler2D spectex_tile{i} : hint_default_white, filter_linear_mipmap, repeat_enable;"
                     f"  // {name}")
    mats = [tuple(layer.matrix().reshape(-1)) for layer in texture.layers]
    lines += [
        "// per layer: world metres -> tile coordinates (m00, m01, m10, m11), tile mean colour, opacity,",
        "// tile coordinates of world (0, 0) (float64 on the host, mod 2)",
        f"const vec4 SPECTEX_MAT[{n}] = {{{', '.join(_vec(m) for m in mats)}}};",
        f"const vec3 SPECTEX_MEAN[{n}] = {{{', '.join(_vec(means[layer.tile]) for layer in texture.layers)}}};",
        f"const float SPECTEX_OPACITY[{n}] = {{{', '.join(_f(layer.opacity) for layer in texture.layers)}}};",
        f"const vec2 SPECTEX_ORIGIN_ANCHOR[{n}] = {{{', '.join(_vec(a) for a in origin)}}};",
        f"const vec2 SPECTEX_TEX_SIZE = {_vec((w, h))};",
        *(_stochastic_declarations(texture, anchors) if stochastic else []),
        "",
        "uniform float spectex_metres_per_unit = 1.0;",
        "// spectex's own anisotropic filter (1 = off):",
        "uniform float spectex_max_anisotropy : hint_range(1.0, 16.0) = 8.0;",
        "uniform float spectex_haze_distance = 0.0;  // metres; 0 = no haze (Godot's fog instead)",
        "uniform vec3 spectex_horizon = vec3(0.78, 0.82, 0.86);  // stored (display) values, as spectex's",
        "// Set by spectex_ground.gd every frame: a ground point near the camera and each layer's",
        "// tile coordinates there (float64 on the CPU, mod 2). Without the script: world (0, 0).",
        "uniform bool spectex_anchored = false;",
        "uniform vec2 spectex_anchor_point = vec2(0.0);",
        f"uniform vec2 spectex_anchor[{n}];",
        *([f"uniform vec2 spectex_ganchor[{n}];  // stochastic layers: the grid position's fraction there",
           f"uniform ivec2 spectex_gbase[{n}];   // and its grid vertex mod 2^32 (the bits of a uint)"]
          if stochastic else []),
        "",
        "varying vec3 spectex_world;",
        "",
        "void vertex() {",
        "    spectex_world = (MODEL_MATRIX * vec4(VERTEX, 1.0)).xyz;",
        "}",
        "",
        "// One layer over c: its coordinates, its footprint, its sample, its blend.",
        "void spectex_layer(int blend, SPX_TEX_ARG(tile), vec2 anchor, vec4 m, float opacity, vec3 mean,",
        "                   inout vec3 c, vec2 p, vec2 jx, vec2 jy) {",
        "    vec2 st = spectex_layer_coords(anchor, m, p);",
        "    vec2 dx = spectex_layer_deriv(m, jx);",
        "    vec2 dy = spectex_layer_deriv(m, jy);",
        "    vec4 x = spectex_sample_grad(SPX_TEX(tile), st, dx, dy, SPECTEX_TEX_SIZE,",
        "                                 (blend == SPX_BLEND_FINE) ? 1.0 : spectex_max_anisotropy);"
        "  // fine: isotropic",
        "    float lam = (blend == SPX_BLEND_FINE || blend == SPX_BLEND_COVER)"
        " ? spectex_fade_lod(dx, dy, SPECTEX_TEX_SIZE) : 0.0;",
        "    c = spectex_blend(blend, c, x, opacity, mean, lam);",
        "}",
        "",
        *(_STOCHASTIC_LAYER if stochastic else []),
        "// spectex's colours are stored values (display-encoded); Godot's ALBEDO is linear light.",
        "vec3 spectex_srgb_to_linear(vec3 c) {",
        "    vec3 lo = c / 12.92;",
        "    vec3 hi = pow((c + 0.055) / 1.055, vec3(2.4));",
        "    return mix(hi, lo, vec3(lessThanEqual(c, vec3(0.04045))));",
        "}",
        "",
        "void fragment() {",
        "    vec2 g = vec2(spectex_world.x, -spectex_world.z) * spectex_metres_per_unit;",
        "    vec2 p = spectex_anchored ? g - spectex_anchor_point : g;",
        "    vec2 jx = dFdx(p);",
        "    vec2 jy = dFdy(p);",
        "    vec3 c = vec3(0.0);",
    ]
    for k, layer in enumerate(texture.layers):
        anchor = f"(spectex_anchored ? spectex_anchor[{k}] : SPECTEX_ORIGIN_ANCHOR[{k}])"
        if layer.tiling == "stochastic":
            lines += [
                f"    spectex_layer_stochastic({_blend_name(k, layer.blend)}, SPX_TEX(spectex_gauss{layer.tile}), "
                f"SPX_TEX(spectex_lut_texture), {anchor},",
                f"        (spectex_anchored ? spectex_ganchor[{k}] : SPECTEX_ORIGIN_GANCHOR[{k}]),",
                f"        (spectex_anchored ? uvec2(spectex_gbase[{k}]) : SPECTEX_ORIGIN_GBASE[{k}]),",
                f"        SPECTEX_MAT[{k}], SPECTEX_GRID[{k}], SPECTEX_KEY[{k}], SPECTEX_SNAP[{k}],",
                f"        SPECTEX_LUT_ROW[{k}],",
                f"        SPECTEX_B0[{k}], SPECTEX_B1[{k}], SPECTEX_B2[{k}],",
                f"        SPECTEX_ORIGIN_RGB[{k}], SPECTEX_OPACITY[{k}], SPECTEX_MEAN[{k}], c, p, jx, jy);"]
            continue
        lines.append(f"    spectex_layer({_blend_name(k, layer.blend)}, SPX_TEX(spectex_tile{layer.tile}), {anchor},")
        lines.append(f"                  SPECTEX_MAT[{k}], SPECTEX_OPACITY[{k}], SPECTEX_MEAN[{k}], c, p, jx, jy);")
    lines += [
        "    c = clamp(c, 0.0, 1.0);",
        "    if (spectex_haze_distance > 0.0) {",
        "        float dist = length(spectex_world - CAMERA_POSITION_WORLD) * spectex_metres_per_unit;",
        "        c = spectex_haze(c, dist, spectex_horizon, spectex_haze_distance);",
        "    }",
        "    ALBEDO = spectex_srgb_to_linear(c);",
        "}",
        "",
    ]
    return "\n".join(lines)


_STOCHASTIC_LAYER = [
    "// A stochastic layer over c (histogram-preserving tiling and blending): as spectex's",
    "// shade_layer_stochastic, with the grid position relative to the anchor's.",
    "void spectex_layer_stochastic(int blend, SPX_TEX_ARG(gauss), SPX_TEX_ARG(lut), vec2 anchor, vec2 ganchor,",
    "                              uvec2 gbase, vec4 m, vec4 gm, uint key, vec2 snap, float lut_row, vec3 b0,",
    "                              vec3 b1,",
    "                              vec3 b2, vec3 origin, float opacity, vec3 mean, inout vec3 c, vec2 p, vec2 jx,",
    "                              vec2 jy) {",
    "    vec2 rel = spectex_layer_deriv(m, p);",
    "    vec2 g = ganchor + vec2(gm.x * rel.x + gm.y * rel.y, gm.z * rel.x + gm.w * rel.y);",
    "    vec4 x = spectex_sample_stochastic_grad(SPX_TEX(gauss), SPX_TEX(lut), anchor + rel, g, gbase.x, gbase.y, key,",
    "                                            snap,",
    "                                            spectex_layer_deriv(m, jx), spectex_layer_deriv(m, jy),",
    "                                            SPECTEX_TEX_SIZE, (blend == SPX_BLEND_FINE) ? 1.0 : "
    "spectex_max_anisotropy, gm,",
    "                                            SPX_FILTER_LINEAR_MIPMAP_LINEAR, SPECTEX_LUT_Q, lut_row,",
    "                                            SPECTEX_LUT_ROWS, b0, b1, b2, origin);",
    "    float lam = (blend == SPX_BLEND_FINE || blend == SPX_BLEND_COVER)",
    "        ? spectex_fade_lod(spectex_layer_deriv(m, jx), spectex_layer_deriv(m, jy), SPECTEX_TEX_SIZE) : 0.0;",
    "    c = spectex_blend(blend, c, x, opacity, mean, lam);",
    "}",
    "",
]


def _stochastic_declarations(texture, anchors) -> list[str]:
    """The stochastic layers' textures and constants (zeros for periodic layers)."""
    lines = ["// ---- stochastic layers: their tables (set by spectex_ground.gd from the raw files; data, linear)"]
    for i in range(len(texture.tiles)):
        lines.append(f"uniform sampler2D spectex_gauss{i} : hint_default_white, filter_linear_mipmap, repeat_enable;"
                     f"  // {gauss_name(texture, i)}")
    return lines + [
        f"uniform sampler2D spectex_lut_texture : hint_default_white, filter_nearest, repeat_disable;  // {LUT_FILE}",
        "// per layer: tile -> triangle-grid map, hash key, snap counts, first table row, decorrelation",
        "// (RGB = origin + b0 v.x + b1 v.y + b2 v.z), and the grid position of world (0, 0) (float64 on the host)",
        *constant_lines(texture, anchors, declare="const", types={}, number=_f, vector=_vec, uvector=_uvec),
    ]


def godot_script(texture) -> str:
    """``spectex_ground.gd``: keeps the shader's layer anchors next to the camera (and, for
    stochastic layers, loads their tables)."""
    stochastic = has_stochastic(texture)
    rows = []
    for layer, entry in zip(texture.layers, layer_entries(texture)):
        values = [*layer.matrix().reshape(-1), layer.offset[0], layer.offset[1], *entry.get("grid", [])]
        rows.append(f"\t[{', '.join(repr(float(v)) for v in values)}],")
    lines = [
        "@tool",
        "extends MeshInstance3D",
        "## spectex ground: keeps the layer anchors of spectex_ground.gdshader next to the camera,",
        "## computed in float64 (GDScript floats), so the texture stays precise far from the origin.",
        "## Attach to the MeshInstance3D that carries the spectex ground material (material_override",
        "## or surface 0). With follow_camera, the mesh also moves with the camera in x and z (an",
        "## endless ground plane; the texture stays fixed to the world).",
        "",
        "## Per layer: m00, m01, m10, m11 (world metres -> tile coordinates), offset x, offset y (metres);",
        "## for a stochastic layer also g00, g01, g10, g11 (tile coordinates -> triangle-grid coordinates).",
        "const LAYERS = [",
        *rows,
        "]",
    ]
    if stochastic:
        info = table_info(texture)
        gauss = ", ".join(f'"{gauss_name(texture, i)}"' for i in range(len(texture.tiles)))
        lines += [
            "## The stochastic layers' tables: raw little-endian half floats beside this script.",
            f"const GAUSS_FILES = [{gauss}]",
            f"const GAUSS_SIZE = Vector2i({info['level_shapes'][0][1]}, {info['level_shapes'][0][0]})",
            f"const LUT_FILE = \"{LUT_FILE}\"",
            f"const LUT_SIZE = Vector2i({info['lut_size']}, {4 * info['lut_rows']})",
        ]
    lines += [
        "",
        "@export var follow_camera := true",
        "## The anchor point moves in steps of this many metres (it only needs to stay near the camera).",
        "@export var anchor_step := 256.0",
        "",
    ]
    if stochastic:
        lines += [
            "var _tables_for: ShaderMaterial = null",
            "",
            "",
            "## Give the material the stochastic tables, every mip level as spectex made it (no import).",
            "func _load_tables(material: ShaderMaterial) -> void:",
            "\tvar folder: String = get_script().resource_path.get_base_dir()",
            "\tfor i in GAUSS_FILES.size():",
            "\t\tvar data := FileAccess.get_file_as_bytes(folder.path_join(GAUSS_FILES[i]))",
            "\t\tvar image := Image.create_from_data(GAUSS_SIZE.x, GAUSS_SIZE.y, true, Image.FORMAT_RGBAH, data)",
            "\t\tmaterial.set_shader_parameter(\"spectex_gauss%d\" % i, ImageTexture.create_from_image(image))",
            "\tvar lut := FileAccess.get_file_as_bytes(folder.path_join(LUT_FILE))",
            "\tvar lut_image := Image.create_from_data(LUT_SIZE.x, LUT_SIZE.y, false, Image.FORMAT_RH, lut)",
            "\tmaterial.set_shader_parameter(\"spectex_lut_texture\", ImageTexture.create_from_image(lut_image))",
            "\t_tables_for = material",
            "",
        ]
    lines += [
        "",
        "func _process(_delta: float) -> void:",
        "\tvar camera := get_viewport().get_camera_3d()",
        "\tif camera == null:",
        "\t\treturn",
        "\tvar material := material_override as ShaderMaterial",
        "\tif material == null:",
        "\t\tmaterial = get_active_material(0) as ShaderMaterial",
        "\tif material == null:",
        "\t\treturn",
        *(["\tif material != _tables_for:", "\t\t_load_tables(material)"] if stochastic else []),
        "\tvar eye := camera.global_position",
        "\tif follow_camera:",
        "\t\tglobal_position = Vector3(eye.x, global_position.y, eye.z)",
        "\tvar scale = material.get_shader_parameter(\"spectex_metres_per_unit\")",
        "\tif scale == null or scale <= 0.0:",
        "\t\tscale = 1.0",
        "\t# spectex ground coordinates: x = world X, y = -world Z (metres)",
        "\tvar ax := snappedf(eye.x * scale, anchor_step)",
        "\tvar ay := snappedf(-eye.z * scale, anchor_step)",
        "\tvar anchors := PackedVector2Array()",
        "\tvar ganchors := PackedVector2Array()",
        "\tvar gbase := PackedInt32Array()",
        "\tfor layer in LAYERS:",
        "\t\tvar dx: float = ax - layer[4]",
        "\t\tvar dy: float = ay - layer[5]",
        "\t\tvar s: float = layer[0] * dx + layer[1] * dy",
        "\t\tvar t: float = layer[2] * dx + layer[3] * dy",
        "\t\tanchors.append(Vector2(fposmod(s, 2.0), fposmod(t, 2.0)))",
        "\t\tif layer.size() > 6:",
        "\t\t\t# the grid position of the unreduced (s, t): its fraction, and its vertex mod 2^32",
        "\t\t\tvar kx: float = layer[6] * s + layer[7] * t",
        "\t\t\tvar ky: float = layer[8] * s + layer[9] * t",
        "\t\t\tganchors.append(Vector2(kx - floorf(kx), ky - floorf(ky)))",
        "\t\t\tgbase.append(_uint_bits(int(floorf(kx))))",
        "\t\t\tgbase.append(_uint_bits(int(floorf(ky))))",
        "\t\telse:",
        "\t\t\tganchors.append(Vector2.ZERO)",
        "\t\t\tgbase.append(0)",
        "\t\t\tgbase.append(0)",
        "\tmaterial.set_shader_parameter(\"spectex_anchored\", true)",
        "\tmaterial.set_shader_parameter(\"spectex_anchor_point\", Vector2(ax, ay))",
        "\tmaterial.set_shader_parameter(\"spectex_anchor\", anchors)",
    ]
    if stochastic:
        lines += [
            "\tmaterial.set_shader_parameter(\"spectex_ganchor\", ganchors)",
            "\tmaterial.set_shader_parameter(\"spectex_gbase\", gbase)",
        ]
    lines += [
        "",
        "",
        "## v mod 2^32 as the int32 with the same bits (the shader reads them as a uint).",
        "func _uint_bits(v: int) -> int:",
        "\tvar u := posmod(v, 4294967296)",
        "\treturn u - 4294967296 if u >= 2147483648 else u",
        "",
    ]
    return "\n".join(lines)


def _readme(texture, tile_names) -> str:
    tiles = ", ".join(f"`{n}`" for n in tile_names)
    return f"""# spectex texture: Godot 4

Written by `spectex export`: `spectex_ground.gdshader` (a spatial shader),
`spectex_ground.gd` (keeps the texture precise far from the origin), {tiles}.

1. Copy this folder into your project (e.g. `res://spectex/`).
2. Import the tile(s) losslessly, so that the alpha (each layer's blend weight)
   survives: select {tiles}, Import dock: *Compress > Mode: Lossless*,
   *Mipmaps > Generate: on*, *Process > Fix Alpha Border: off* (it changes the
   colour of transparent texels), *Process > Premult Alpha: off*, *Detect 3D >
   Compress To: Disabled* (otherwise Godot switches a texture used in 3D to VRAM
   compression, which damages the alpha), then *Reimport*.
3. Add a `MeshInstance3D` with a large `PlaneMesh` (e.g. 20 km, a few
   subdivisions) at height 0; *Geometry > Material Override: New ShaderMaterial*,
   shader `spectex_ground.gdshader`; set {', '.join(f'`spectex_tile{i}`' for i in range(len(tile_names)))}
   to {tiles}.
4. Attach `spectex_ground.gd` to the mesh. It moves the mesh with the camera
   (an endless ground) and sets the layer anchors every frame.

Shader parameters: `spectex_metres_per_unit` (1 if one Godot unit is a
metre), `spectex_max_anisotropy` (spectex's own anisotropic filter, 1 = off),
`spectex_haze_distance` (spectex's haze; 0 leaves it to Godot's fog).

What matches spectex: the layer arithmetic (the same library text), the
texel addressing, the level of detail per layer, the anisotropic recipe and
the blend. With `render_mode unshaded`, *Tonemap: Linear*, no fog and no glow,
the colours are spectex's (the blended value is decoded from sRGB once, and
Godot encodes it back). What differs: Godot generates the mip levels on import
(not spectex's levels; close, not identical); the footprint comes from
`dFdx`/`dFdy` (per 2 x 2 pixel quad), not from spectex's exact per-pixel
derivatives; world positions are 32-bit floats in a standard Godot build, so
far from the origin the ground point itself loses precision (the anchors keep
the texture coordinates small; use a double-precision build or move the world
origin for very large worlds).
""" + (_stochastic_readme(texture) if has_stochastic(texture) else "")


def _stochastic_readme(texture) -> str:
    gauss = ", ".join(f"`{gauss_name(texture, i)}`" for i in range(len(texture.tiles)))
    return f"""
## Stochastic layers

The stochastic layers (spectex's histogram-preserving tiling: they never
repeat) sample no tile but two textures made from it: {gauss} (per tile its
Gaussianised levels) and `{LUT_FILE}` (the look-up tables), raw little-endian
half floats, lossless. `spectex_ground.gd` loads them itself
(`Image.create_from_data` with `FORMAT_RGBAH` and every mip level spectex
made, `FORMAT_RH` for the table) and sets `spectex_gauss*` and
`spectex_lut_texture`: leave those parameters empty. Godot does not import
these files: in *Project > Export > Resources*, add `*.rgba16f, *.r16f` to
*Filters to export non-resource files*. The script also sets each stochastic
layer's grid position (`spectex_ganchor`, `spectex_gbase`) in float64; without
it the shader uses the origin's.
"""


def write_godot(texture, folder: Path) -> list[Path]:
    """Write ``folder/godot/``; return the files written."""
    from ._stochastic import write_tables
    from ._tiles import write_tiles

    out = Path(folder) / "godot"
    out.mkdir()
    tiles = write_tiles(texture, out)
    names = [p.name for p in tiles]
    files = []
    for name, text in (("spectex_ground.gdshader", godot_shader(texture, names)),
                       ("spectex_ground.gd", godot_script(texture)), ("README.md", _readme(texture, names))):
        (out / name).write_text(text, encoding="utf-8")
        files.append(out / name)
    return files + tiles + write_tables(texture, out)
