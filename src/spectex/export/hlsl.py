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
    context = {"tile_files": tiles, "entry_point": ENTRY_POINT, "ports": ports, "extra": extra,
               "lut_sampler": lut_sampler, "call": call, "stochastic": has_stochastic(texture)}
    if context["stochastic"]:
        from ._stochastic import LUT_FILE, gauss_name

        info = table_info(texture)
        context.update({
            "gauss_files": ", ".join(f"`{gauss_name(texture, i)}`" for i in range(len(tile_names))),
            "level_shapes": ", ".join(f"{w} x {h}" for h, w in info["level_shapes"]),
            "lut_file": LUT_FILE, "lut_width": info["lut_size"], "lut_height": 4 * info["lut_rows"]})
    return _template.render("hlsl/README.md", context)


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
