"""The ``blender`` export: a Python script that builds the texture as a Blender material, and its tile(s).

``blender/spectex_ground.py`` is ``templates/blender_ground.py.in`` (a plain
Blender script: Geometry position, Vector Math, Image Texture, Math nodes) with
the texture's table written into it: tiles, and per layer the shader's inputs of
``shading.interface`` (its map, the tile coordinates of the world origin, its
tile's mean colour, its opacity), its blend, tile and tiling (and its size, for
a message). Run in Blender, it builds the material ``spectex_ground``: each
layer's coordinates ``(s, t) = anchor + M p`` from the world position, the tile
through an Image Texture node (Linear, Repeat, Non-Color, alpha channel-packed), the blends
of ``docs/sampling.md`` section 6 node by node, and the blended (sRGB-encoded)
colour decoded to linear light into the Base Color (or an Emission, unlit).

What Blender's nodes cannot hold: spectex's mip-maps, level of detail and
anisotropic filter (Cycles samples level 0 and averages its samples per pixel),
sky and haze (the world's), and stochastic tiling: a stochastic layer is drawn
as its periodic tile instead, and the script, the README and
``STOCHASTIC_NOTE`` say so.
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path

__all__ = ["COVER_NOTE", "FINE_NOTE", "SNAP_NOTE", "STOCHASTIC_NOTE", "blender_script", "write_blender"]

#: What the export says about a stochastic layer (the script prints its own line per layer).
STOCHASTIC_NOTE = ("uses spectex's stochastic tiling, which Blender's nodes cannot draw: it is drawn as its "
                   "periodic tile instead (it repeats), and does not match spectex's picture")

#: What the export adds for a stochastic layer snapped to its structure's periods (``Layer.snap``).
SNAP_NOTE = ("Its snap to whole periods of the tile's structure (Layer.snap) has nothing to act on: the "
             "periodic tile keeps the structure's grid, and repeats.")

#: What the export says about a fine (detail) layer, whose fade needs the pixel's footprint.
FINE_NOTE = ("is a fine (detail) layer: spectex fades it out with the pixel's footprint, which Blender's nodes "
             "cannot see; it is drawn with the variance blend at full alpha, at every distance")

#: What the export says about a cover layer, whose alpha rises with the pixel's footprint.
COVER_NOTE = ("is a cover layer: spectex raises its alpha to 1 with the pixel's footprint, so that the finer "
              "layers' repeats fade out in the distance, which Blender's nodes cannot see; it is drawn with the "
              "variance blend at its own alpha, and the finer layers repeat in the distance")


def blender_script(texture, tile_files) -> str:
    """The script's text for ``texture``; ``tile_files``: per tile, its file name (beside the script)."""
    from ._syntax import layer_values

    # each layer's map, anchor, mean colour and opacity as the shader's inputs take them (shading.interface)
    table = {
        "tiles": list(tile_files),
        "layers": [{"map": [float(v) for v in value["MAT"]], "anchor": [float(v) for v in value["ORIGIN_ANCHOR"]],
                    "mean": [float(v) for v in value["MEAN"]], "opacity": float(value["OPACITY"]),
                    "blend": layer.blend, "tile": int(layer.tile), "tiling": getattr(layer, "tiling", "periodic"),
                    "size": float(layer.size)}
                   for layer, value in zip(texture.layers, layer_values(texture))],
    }
    template = (resources.files("spectex.export").joinpath("templates", "blender_ground.py.in")
                .read_text(encoding="utf-8"))
    marker = 'SPECTEX = {"$TEXTURE$": None}'
    assert marker in template
    return template.replace(marker, "SPECTEX = " + json.dumps(table, indent=1))


def _readme(texture, tile_files) -> str:
    notes = [f"* layer {k} {STOCHASTIC_NOTE}." + (f" {SNAP_NOTE}" if getattr(layer, "snap", (0, 0)) != (0, 0)
                                                 else "")
             for k, layer in enumerate(texture.layers) if getattr(layer, "tiling", "periodic") != "periodic"]
    notes += [f"* layer {k} {FINE_NOTE}." for k, layer in enumerate(texture.layers) if layer.blend == "fine"]
    notes += [f"* layer {k} {COVER_NOTE}." for k, layer in enumerate(texture.layers) if layer.blend == "cover"]
    stochastic = ("\n## What Blender's nodes cannot draw\n\n" + "\n".join(notes) + "\n") if notes else ""
    return f"""# spectex texture: Blender

Written by `spectex export`: `spectex_ground.py` and {', '.join(f'`{n}`' for n in tile_files)}.

1. Keep this folder together (the script loads the tile(s) from beside itself).
2. In Blender: add a large plane at height 0 (spectex x east = X, y north = Y,
   metres) and select it; *Scripting* workspace, *Open* `spectex_ground.py`,
   *Run Script*. The plane gets the material `spectex_ground` (a Principled
   BSDF whose Base Color is the texture). From the command line:
   `blender scene.blend --python spectex_ground.py`.
3. For spectex's colours as they are (no lighting): in the script's Python,
   `build_material(unlit=True)` makes an Emission material; render with
   *Color Management > View Transform: Standard*.

The tile(s) are loaded as *Non-Color* with *Alpha: Channel Packed*: the tile is
data (its alpha is the blend weight, its colour is blended as stored), and the
blended colour is decoded from sRGB once, at the end, by Math nodes.

What differs from spectex: Cycles samples the tile's full resolution and
averages its samples per pixel (no mip-maps, no spectex anisotropic filter);
spectex's sky and haze are not part of the material (use the World's).
{stochastic}"""


def write_blender(texture, folder: Path) -> list[Path]:
    """Write ``folder/blender/spectex_ground.py``, its README and tile(s); return the files."""
    from ._tiles import write_tiles

    out = Path(folder) / "blender"
    out.mkdir()
    tiles = write_tiles(texture, out)
    names = [p.name for p in tiles]
    script = out / "spectex_ground.py"
    script.write_text(blender_script(texture, names), encoding="utf-8")
    readme = out / "README.md"
    readme.write_text(_readme(texture, names), encoding="utf-8")
    return [script, readme, *tiles]
