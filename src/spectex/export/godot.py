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

from . import _template
from ._shader import has_stochastic, layer_library
from ._stochastic import LUT_FILE, gauss_name, layer_entries, table_info
from ._syntax import GODOT, bindings, layer_calls

__all__ = ["write_godot", "godot_shader", "godot_script"]


def godot_shader(texture, tile_names) -> str:
    """The ``.gdshader`` text for ``texture`` (``tile_names``: per tile, its PNG):
    ``templates/godot/spectex_ground.gdshader`` with the texture's values."""
    from spectex.shading.glsl import texture_macros

    h, w = texture.tile_shape
    context = {
        "n_layers": len(texture.layers), "n_tiles": len(texture.tiles), "width": w, "height": h,
        "sizes": ", ".join(f"{layer.size:g} m" for layer in texture.layers),
        "library": texture_macros() + layer_library(anisotropic=True),
        "tiles": [{"i": i, "file": name, "gauss_file": gauss_name(texture, i)} for i, name in enumerate(tile_names)],
        "lut_file": LUT_FILE, "stochastic": has_stochastic(texture), "layers": layer_calls(texture),
        **bindings(texture, GODOT),
    }
    return _template.render("godot/spectex_ground.gdshader", context)


def godot_script(texture) -> str:
    """``spectex_ground.gd``: keeps the shader's layer anchors next to the camera (and, for
    stochastic layers, loads their tables)."""
    from spectex.shading.constants import ANCHOR_PERIOD

    rows = []
    for layer, entry in zip(texture.layers, layer_entries(texture)):
        values = [*layer.matrix().reshape(-1), layer.offset[0], layer.offset[1], *entry.get("grid", [])]
        rows.append({"row": ", ".join(repr(float(v)) for v in values)})
    context = {"layers": rows, "stochastic": has_stochastic(texture), "anchor_period": repr(float(ANCHOR_PERIOD))}
    if context["stochastic"]:
        info = table_info(texture)
        context.update({
            "gauss_files": ", ".join(f'"{gauss_name(texture, i)}"' for i in range(len(texture.tiles))),
            "gauss_width": info["level_shapes"][0][1], "gauss_height": info["level_shapes"][0][0],
            "lut_file": LUT_FILE, "lut_width": info["lut_size"], "lut_height": 4 * info["lut_rows"]})
    return _template.render("godot/spectex_ground.gd", context)


def _readme(texture, tile_names) -> str:
    """``templates/godot/README.md`` for ``texture`` (``tile_names``: its tiles' files)."""
    return _template.render("godot/README.md", {
        "tile_files": ", ".join(f"`{n}`" for n in tile_names),
        "tile_parameters": ", ".join(f"`spectex_tile{i}`" for i in range(len(tile_names))),
        "gauss_files": ", ".join(f"`{gauss_name(texture, i)}`" for i in range(len(texture.tiles))),
        "lut_file": LUT_FILE, "stochastic": has_stochastic(texture)})


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
