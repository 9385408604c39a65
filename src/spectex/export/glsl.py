"""The ``glsl`` export: the renderer's shaders as GLSL ES 3.00 (WebGL2, three.js) and GLSL 3.30.

``glsl/`` holds:

* ``spectex_layers.es300.glsl`` and ``spectex_layers.330.glsl``: the layer
  library alone (the prelude, the generated constants and
  ``shading/shaders/spectex_layers.glsl``), to put before an engine's own
  ``main()``;
* ``ground.es300.vert``/``.frag`` and ``ground.330.vert``/``.frag``: the
  renderer's own ground program (a full-screen triangle; every pixel casts
  its ray to the ground plane, samples the layers, adds sky and haze),
  every layer drawn, the anisotropic path compiled in (an anisotropy limit
  of 1 turns it off);
* ``spectex_texture.json``: the layer table (matrices, offsets, opacities,
  level-of-detail offsets, mean colours) and the atmosphere;
* ``spectex_uniforms.js``: the shader's uniforms from that table and a
  camera, as an ES module (the web viewer's own code);
* ``tile.png`` and ``mips/tile.level<d>.png``: the tile and every mip level
  spectex samples (:meth:`SpectralTexture.mip_levels`), lossless, for
  engines that accept given mip levels (three.js ``texture.mipmaps``);
* for a texture with stochastic layers, their tables (:mod:`spectex.export._stochastic`):
  ``gauss.rgba16f`` (per tile, its Gaussianised levels) and ``spectex_lut.r16f``
  (the look-up table texture), raw little-endian half floats, lossless;
* ``README.md``: how to use them (three.js and plain OpenGL).
"""

from __future__ import annotations

import json
from pathlib import Path

from ..shading.resources import mip_levels
from . import _template
from ._shader import GLSL_TARGETS, ground_fragment, has_stochastic, layer_library, prelude, vertex_source

__all__ = ["write_glsl"]


def _names(rows) -> str:
    """The uniforms' names as a Markdown list: `a`, `b`, ..."""
    return ", ".join(f"`{row.name}`" for row in rows)


def _readme(texture, tiles, levels) -> str:
    """``templates/glsl/README.md`` for ``texture`` (``tiles``: its files; ``levels``: mip levels per tile)."""
    from spectex.shading import interface
    from spectex.shading.constants import LUT_SIZE

    from ._stochastic import LUT_FILE, gauss_name, table_info

    h, w = texture.tile_shape
    n_tiles = len(texture.tiles)
    context = {
        "n_layers": len(texture.layers), "n_tiles": n_tiles, "width": w, "height": h,
        "sizes": ", ".join(f"{layer.size:g} m" for layer in texture.layers),
        "tile_files": ", ".join(f"`{t}`" for t in tiles), "levels": levels,
        "tile_stems": json.dumps([t.rsplit(".", 1)[0] for t in tiles]),
        "tile_input": interface.TILE.name, "aniso_input": interface.MAX_ANISO.name,
        "anchor_input": interface.ANCHOR.name,
        "texture_inputs": _names(interface.inputs("texture", stochastic=False)),
        "frame_inputs": _names(row for row in interface.inputs("frame", stochastic=False) if row.js is not None),
        "stochastic": has_stochastic(texture),
    }
    if context["stochastic"]:
        info = table_info(texture)
        context.update({
            "stochastic_layers": ", ".join(str(k) for k, layer in enumerate(texture.layers)
                                           if layer.tiling == "stochastic"),
            "gauss_files": ", ".join(f"`{gauss_name(texture, i)}`" for i in range(n_tiles)),
            "gauss_files_json": json.dumps([gauss_name(texture, i) for i in range(n_tiles)]),
            "level_shapes": ", ".join(f"{w} x {h}" for h, w in info["level_shapes"]),
            "lut_file": LUT_FILE, "lut_size": LUT_SIZE, "lut_height": 4 * info["lut_rows"], "lut_unit": 2 * n_tiles,
            "gauss_input": interface.GAUSS.name, "lut_input": interface.LUT.name,
            "basis_input": interface.BASIS.name, "ganchor_input": interface.GANCHOR.name,
            "gbase_input": interface.GBASE.name,
            "stochastic_inputs": _names(interface.inputs("texture", stochastic=True))})
    return _template.render("glsl/README.md", context)


def write_glsl(texture, folder: Path) -> list[Path]:
    """Write ``folder/glsl/``; return the files written."""
    from spectex.io import write_image

    from ._stochastic import write_tables
    from ._tiles import tile_names
    from .web import layer_table, uniforms_js

    out = Path(folder) / "glsl"
    (out / "mips").mkdir(parents=True)
    files = []
    for target in GLSL_TARGETS:
        path = out / f"spectex_layers.{target}.glsl"
        path.write_text(prelude(target) + layer_library(anisotropic=True), encoding="utf-8")
        files.append(path)
        for suffix, text in (("vert", vertex_source(target)), ("frag", ground_fragment(texture, target))):
            path = out / f"ground.{target}.{suffix}"
            path.write_text(text, encoding="utf-8")
            files.append(path)
    path = out / "spectex_texture.json"
    path.write_text(json.dumps(layer_table(texture), indent=1) + "\n", encoding="utf-8")
    files.append(path)
    path = out / "spectex_uniforms.js"
    path.write_text(uniforms_js() + "\nexport { spectexTextureUniforms, spectexFrameUniforms };\n", encoding="utf-8")
    files.append(path)
    names = tile_names(texture)
    depth = 8 if texture.bits == 8 else 16
    for name, tile, levels in zip(names, texture.tiles, mip_levels(texture)):
        files.append(write_image(out / name, tile, bit_depth=depth))
        stem = name.rsplit(".", 1)[0]
        for d, level in enumerate(levels):
            files.append(write_image(out / "mips" / f"{stem}.level{d}.png", level, bit_depth=depth))
    files += write_tables(texture, out)
    path = out / "README.md"
    path.write_text(_readme(texture, names, len(mip_levels(texture)[0])), encoding="utf-8")
    files.append(path)
    return files
