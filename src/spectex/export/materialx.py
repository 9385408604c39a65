"""The ``materialx`` export: a MaterialX 1.39 document of standard nodes, and its tile(s).

The node graph ``NG_spectex_ground`` computes the texture's colour at a
surface point from its world position, with the standard library's nodes
only (``position``, ``dotproduct``, ``combine2``, ``subtract``, ``image``,
``convert``, ``extract``, ``multiply``, ``mix``, ``overlay``, ``add``, ``divide``,
``sqrt``, ``clamp``): per layer, ``(s, t) = anchor_k + M_k p`` (the shader's
inputs of ``shading.interface``: the layer's map and the tile coordinates of
the world origin) as two dot products and an add, the tile through ``image`` (periodic, linear), and the blends of
``docs/sampling.md``, section 6, written out node by node (alpha as ``mix``;
not ``over``, which assumes premultiplied colour). Two materials use it:
``spectex_ground`` (``standard_surface``, the texture as base colour) and
``spectex_ground_unlit`` (``surface_unlit``, the texture as it is, as
spectex draws it before sky and haze).

A layer whose tiling has no standard-node equivalent (spectex's stochastic
tiling) is drawn with ``hextiledimage`` instead, and the file says so next
to it: that layer will not match spectex's picture (and a snapped one,
``Layer.snap``, loses its structure's grid: the comment says that too).

The document is the template ``templates/materialx/spectex_ground.mtlx``
(the nodes, written out once) filled in with names and numbers, so
exporting needs no MaterialX installation; the tests read it with MaterialX,
validate it and generate GLSL from it.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["write_materialx", "materialx_document", "MATERIALX_VERSION", "GROUND_AXES"]

#: The MaterialX version the document declares.
MATERIALX_VERSION = "1.39"
#: Default world axes of the ground plane, for a Y-up scene: spectex x (east) is
#: world +X, spectex y (north) is world -Z. A Z-up scene sets ``ground_v`` to (0, 1, 0).
GROUND_AXES = ((1.0, 0.0, 0.0), (0.0, 0.0, -1.0))


def _num(value: float) -> str:
    """A float as text that reads back as the same float64 (renderers round it to their precision)."""
    text = repr(float(value))
    return "0" if text in ("-0.0", "0.0") else text


def _vec(values) -> str:
    return ", ".join(_num(v) for v in values)


def _attribute(text: str) -> str:
    """``text`` as an XML attribute value between double quotes (as ``xml.etree`` escapes it)."""
    for raw, escaped in (("&", "&amp;"), ("<", "&lt;"), (">", "&gt;"), ('"', "&quot;"), ("\r", "&#13;"),
                         ("\n", "&#10;"), ("\t", "&#09;")):
        text = text.replace(raw, escaped)
    return text


#: What the document says next to a layer whose tiling has no standard-node equivalent (and its snap).
TILING_NOTE = ("layer {k} uses spectex's {tiling} tiling, which has no standard-node equivalent: hextiledimage "
               "(MaterialX 1.39.4 and later) stands in for it. It breaks up the repetition too, but with its own "
               "cells, rotations and blending: this layer will not match spectex's picture.")
SNAP_NOTE = (" Its snap to whole periods of the tile's structure (Layer.snap {snap}: patch offsets of whole "
             "periods, which keep a brick or tile grid in place) is lost too: hextiledimage's cells break the grid.")
#: What it says next to a fine (detail) layer and a cover layer, whose alphas need the pixel's footprint.
BLEND_NOTES = {
    "fine": ("layer {k} is a fine (detail) layer: spectex fades its alpha out with the pixel's footprint, which "
             "standard nodes cannot see; here it is the variance blend at full alpha, so it stays at every "
             "distance (the renderer's mip-maps still filter it)."),
    "cover": ("layer {k} is a cover layer: spectex raises its alpha to 1 as the pixel's footprint grows, so that "
              "the finer layers' repeats fade out where they would be small on screen; standard nodes cannot see "
              "the footprint: here it is the variance blend at its own alpha, and the finer layers repeat in the "
              "distance."),
}


def _layer_item(k: int, layer, value: dict, file: str, below: str | None) -> dict:
    """What the template's ``{{#each layers}}`` block takes for layer ``k``: its numbers (the interface
    table's ``value``: its map, its anchor at the world origin, mean colour, opacity), its tile's file, its
    blend's flags and notes, and ``below``, the node of the colour it goes over (None: it is the first)."""
    m00, m01, m10, m11 = value["MAT"]
    anchor_s, anchor_t = value["ORIGIN_ANCHOR"]
    tiling = getattr(layer, "tiling", "periodic")
    snap = tuple(getattr(layer, "snap", (0, 0)))
    over = below is not None
    return {
        "k": k, "file": _attribute(file),
        "about": (f"layer {k}: size {layer.size:g} m, offset ({layer.offset[0]:g}, {layer.offset[1]:g}) m, "
                  f"rotation {layer.rotation:g} deg, blend {layer.blend}, opacity {layer.opacity:g}, tile {file}"),
        # v = -t: the image's v = 0 is the file's bottom row, spectex's t = 0 its top row
        "map_s": _vec((m00, m01)), "map_v": _vec((-m10, -m11)), "anchor": _vec((anchor_s, -anchor_t)),
        "periodic": tiling == "periodic",
        "tiling_note": TILING_NOTE.format(k=k, tiling=tiling) + (SNAP_NOTE.format(snap=snap) if snap != (0, 0) else ""),
        "over": over, "alpha": over and layer.blend == "alpha", "detail": over and layer.blend == "detail",
        "overlay": over and layer.blend == "overlay",
        "variance": over and layer.blend not in ("alpha", "detail", "overlay"),
        "blend_note": BLEND_NOTES[layer.blend].format(k=k) if layer.blend in BLEND_NOTES else "",
        "opacity": _num(value["OPACITY"]), "mean": _vec(value["MEAN"]), "below": below or "",
    }


def materialx_document(texture, tile_files) -> str:
    """The ``.mtlx`` text for ``texture`` (``templates/materialx/spectex_ground.mtlx``); ``tile_files``: per
    tile, its file name (beside the document)."""
    from . import _template
    from ._syntax import layer_values

    layers = []
    colour = None  # the node holding the colour so far
    # each layer's map, anchor, mean colour and opacity as the shader's inputs take them (shading.interface)
    for k, (layer, value) in enumerate(zip(texture.layers, layer_values(texture))):
        layers.append(_layer_item(k, layer, value, tile_files[layer.tile], colour))
        if colour is None:  # the first layer sets the colour
            colour = f"layer{k}_rgb"
        else:
            colour = {"alpha": f"layer{k}_over", "detail": f"layer{k}_detail",
                      "overlay": f"layer{k}_overlay"}.get(layer.blend, f"layer{k}_variance")
    return _template.render("materialx/spectex_ground.mtlx", {
        "version": MATERIALX_VERSION, "ground_u": _vec(GROUND_AXES[0]), "ground_v": _vec(GROUND_AXES[1]),
        "layers": layers, "colour": colour, "channels": [{"c": c, "index": i} for i, c in enumerate("rgb")]})


def write_materialx(texture, folder: Path) -> list[Path]:
    """Write ``folder/materialx/spectex_ground.mtlx`` and its tile(s); return the files."""
    from ._tiles import write_tiles

    out = Path(folder) / "materialx"
    out.mkdir()
    tiles = write_tiles(texture, out)
    doc = out / "spectex_ground.mtlx"
    doc.write_text(materialx_document(texture, [p.name for p in tiles]), encoding="utf-8")
    return [doc, *tiles]
