"""The ``materialx`` export: a MaterialX 1.39 document of standard nodes, and its tile(s).

The node graph ``NG_spectex_ground`` computes the texture's colour at a
surface point from its world position, with the standard library's nodes
only (``position``, ``dotproduct``, ``combine2``, ``subtract``, ``image``,
``convert``, ``extract``, ``multiply``, ``mix``, ``add``, ``divide``,
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

The document is written with the standard library's ``xml.etree``, so
exporting needs no MaterialX installation; the tests read it with MaterialX,
validate it and generate GLSL from it.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
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


class _Graph:
    """A small builder for a MaterialX node graph as XML elements."""

    def __init__(self, parent: ET.Element, name: str):
        self.element = ET.SubElement(parent, "nodegraph", name=name)
        self.count = 0

    def comment(self, text: str) -> None:
        self.element.append(ET.Comment(f" {text} "))

    def input(self, name: str, type_: str, value: str, doc: str) -> str:
        ET.SubElement(self.element, "input", name=name, type=type_, value=value, doc=doc)
        return name

    def node(self, category: str, type_: str, name: str | None = None, **inputs) -> str:
        """A node; each input is ``(type, value[, attributes])`` for a constant, a node (``_Ref``),
        or ``("interface", name, type)``."""
        self.count += 1
        name = name or f"{category}{self.count}"
        node = ET.SubElement(self.element, category, name=name, type=type_)
        for key, value in inputs.items():
            key = key.rstrip("_")  # in_ -> in
            if isinstance(value, tuple) and value[0] == "interface":
                ET.SubElement(node, "input", name=key, type=value[2], interfacename=value[1])
            elif isinstance(value, tuple):
                extra = value[2] if len(value) > 2 else {}
                ET.SubElement(node, "input", name=key, type=value[0], value=value[1], **extra)
            else:
                ET.SubElement(node, "input", name=key, type=value.type_, nodename=value.name)
        return _Ref(name, type_)

    def output(self, name: str, ref) -> None:
        ET.SubElement(self.element, "output", name=name, type=ref.type_, nodename=ref.name)


class _Ref:
    def __init__(self, name: str, type_: str):
        self.name = name
        self.type_ = type_


def _srgb_decode(g: _Graph, colour: _Ref) -> _Ref:
    """The IEC 61966-2-1 sRGB decode of ``colour``, channel by channel, in math nodes.

    spectex blends the stored (sRGB-encoded) values and its pictures are those values; a
    renderer's colour inputs are linear light. Not ``srgb_texture_to_lin_rec709``: three.js's
    MaterialX loader rejects that node, and a colour-space declaration on the image would
    decode before the blend, not after.
    """
    g.comment("the blended colour is sRGB-encoded, as spectex stores and shows it: decode it to "
              "linear light once, here (c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055)^2.4)")
    channels = []
    for i, name in enumerate("rgb"):
        c = g.node("extract", "float", f"stored_{name}", in_=colour, index=("integer", str(i)))
        low = g.node("divide", "float", f"decode_{name}_low", in1=c, in2=("float", "12.92"))
        shifted = g.node("add", "float", f"decode_{name}_shift", in1=c, in2=("float", "0.055"))
        scaled = g.node("divide", "float", f"decode_{name}_scale", in1=shifted, in2=("float", "1.055"))
        high = g.node("power", "float", f"decode_{name}_high", in1=scaled, in2=("float", "2.4"))
        channels.append(g.node("ifgreater", "float", f"linear_{name}", value1=c, value2=("float", "0.04045"),
                               in1=high, in2=low))
    return g.node("combine3", "color3", "ground_linear", in1=channels[0], in2=channels[1], in3=channels[2])


def materialx_document(texture, tile_files) -> str:
    """The ``.mtlx`` text for ``texture``; ``tile_files``: per tile, its file name (beside the document)."""
    from ._syntax import layer_values

    # each layer's map, anchor, mean colour and opacity as the shader's inputs take them (shading.interface)
    values = layer_values(texture)
    root = ET.Element("materialx", version=MATERIALX_VERSION, colorspace="lin_rec709")
    root.append(ET.Comment(
        " spectex spectral texture: layers of one tile at different scales, blended by the tile's alpha "
        "(docs/export.md). Standard nodes only. The tiles are data: declared lin_rec709 so that no renderer "
        "converts them before the blend; the blended colour (output 'stored', sRGB-encoded as spectex shows it) "
        "is decoded to linear light by math nodes (output 'out', the materials' colour). "
        "Filtering and mip-maps are the renderer's; spectex's sky "
        "and distance haze are not part of the material. "))
    g = _Graph(root, "NG_spectex_ground")
    u_axis = g.input("ground_u", "vector3", _vec(GROUND_AXES[0]),
                     "world direction of spectex x (east), in world units per metre")
    v_axis = g.input("ground_v", "vector3", _vec(GROUND_AXES[1]),
                     "world direction of spectex y (north), in world units per metre; (0, 1, 0) for a Z-up scene")
    pos = g.node("position", "vector3", "world_position", space=("string", "world"))
    px = g.node("dotproduct", "float", "ground_x", in1=pos, in2=("interface", u_axis, "vector3"))
    py = g.node("dotproduct", "float", "ground_y", in1=pos, in2=("interface", v_axis, "vector3"))
    ground = g.node("combine2", "vector2", "ground_xy", in1=px, in2=py)
    colour = None
    first = True
    for k, (layer, value) in enumerate(zip(texture.layers, values)):
        tiling = getattr(layer, "tiling", "periodic")
        m00, m01, m10, m11 = value["MAT"]
        anchor_s, anchor_t = value["ORIGIN_ANCHOR"]
        g.comment(f"layer {k}: size {layer.size:g} m, offset ({layer.offset[0]:g}, {layer.offset[1]:g}) m, "
                  f"rotation {layer.rotation:g} deg, blend {layer.blend}, opacity {layer.opacity:g}, "
                  f"tile {tile_files[layer.tile]}")
        # (s, t) = anchor + M p: the layer's map and the tile coordinates of the world origin, the shader's
        # inputs (shading.interface: MAT, and ANCHOR at ground point (0, 0), a whole number of tiles off).
        s_ = g.node("dotproduct", "float", f"layer{k}_s", in1=ground, in2=("vector2", _vec((m00, m01))))
        # image's texcoord has v = 0 at the bottom row of the file; spectex's t = 0
        # is the top row (row 0), so v = 1 - t, which is -t for a periodic image.
        v = g.node("dotproduct", "float", f"layer{k}_v", in1=ground, in2=("vector2", _vec((-m10, -m11))))
        sv = g.node("combine2", "vector2", f"layer{k}_mapped", in1=s_, in2=v)
        uv = g.node("add", "vector2", f"layer{k}_uv", in1=sv, in2=("vector2", _vec((anchor_s, -anchor_t))))
        file = ("filename", tile_files[layer.tile], {"colorspace": "lin_rec709"})
        if tiling == "periodic":
            img = g.node("image", "color4", f"layer{k}_texel", file=file, texcoord=uv,
                         uaddressmode=("string", "periodic"), vaddressmode=("string", "periodic"),
                         filtertype=("string", "linear"))
        else:
            g.comment(f"layer {k} uses spectex's {tiling} tiling, which has no standard-node equivalent: "
                      "hextiledimage (MaterialX 1.39.4 and later) stands in for it. It breaks up the "
                      "repetition too, but with its own cells, rotations and blending: this layer will not "
                      "match spectex's picture."
                      + (f" Its snap to whole periods of the tile's structure (Layer.snap {tuple(layer.snap)}: "
                         "patch offsets of whole periods, which keep a brick or tile grid in place) is lost "
                         "too: hextiledimage's cells break the grid." if getattr(layer, "snap", (0, 0)) != (0, 0)
                         else ""))
            img = g.node("hextiledimage", "color4", f"layer{k}_texel", file=file, texcoord=uv)
        x = g.node("convert", "color3", f"layer{k}_rgb", in_=img)
        if first:  # the first layer sets the colour
            colour, first = x, False
            continue
        alpha = g.node("extract", "float", f"layer{k}_tile_alpha", in_=img, index=("integer", "3"))
        a = g.node("multiply", "float", f"layer{k}_alpha", in1=alpha, in2=("float", _num(value["OPACITY"])))
        if layer.blend == "alpha":  # c = a x + (1 - a) c
            colour = g.node("mix", "color3", f"layer{k}_over", fg=x, bg=colour, mix=a)
        elif layer.blend == "detail":  # c = 2 x c
            xc = g.node("multiply", "color3", f"layer{k}_modulate", in1=x, in2=colour)
            colour = g.node("multiply", "color3", f"layer{k}_detail", in1=xc, in2=("float", "2"))
        else:  # variance: c = mu + (a (x - mu) + (1 - a)(c - mu)) / sqrt(a^2 + (1 - a)^2)
            if layer.blend == "fine":
                g.comment(f"layer {k} is a fine (detail) layer: spectex fades its alpha out with the pixel's "
                          "footprint, which standard nodes cannot see; here it is the variance blend at full "
                          "alpha, so it stays at every distance (the renderer's mip-maps still filter it).")
            elif layer.blend == "cover":
                g.comment(f"layer {k} is a cover layer: spectex raises its alpha to 1 as the pixel's footprint "
                          "grows, so that the finer layers' repeats fade out where they would be small on "
                          "screen; standard nodes cannot see the footprint: here it is the variance blend at "
                          "its own alpha, and the finer layers repeat in the distance.")
            mu = _vec(value["MEAN"])
            dx = g.node("subtract", "color3", f"layer{k}_x_dev", in1=x, in2=("color3", mu))
            dc = g.node("subtract", "color3", f"layer{k}_c_dev", in1=colour, in2=("color3", mu))
            num = g.node("mix", "color3", f"layer{k}_dev", fg=dx, bg=dc, mix=a)
            b = g.node("subtract", "float", f"layer{k}_one_minus_alpha", in1=("float", "1"), in2=a)
            a2 = g.node("multiply", "float", f"layer{k}_alpha2", in1=a, in2=a)
            b2 = g.node("multiply", "float", f"layer{k}_one_minus_alpha2", in1=b, in2=b)
            sum2 = g.node("add", "float", f"layer{k}_sum2", in1=a2, in2=b2)
            den = g.node("sqrt", "float", f"layer{k}_norm", in_=sum2)
            scaled = g.node("divide", "color3", f"layer{k}_dev_scaled", in1=num, in2=den)
            colour = g.node("add", "color3", f"layer{k}_variance", in1=scaled, in2=("color3", mu))
    stored = g.node("clamp", "color3", "ground_colour", in_=colour, low=("float", "0"), high=("float", "1"))
    g.output("stored", stored)
    g.output("out", _srgb_decode(g, stored))

    surf = ET.SubElement(root, "standard_surface", name="SR_spectex_ground", type="surfaceshader")
    ET.SubElement(surf, "input", name="base", type="float", value="1")
    ET.SubElement(surf, "input", name="base_color", type="color3", nodegraph="NG_spectex_ground", output="out")
    ET.SubElement(surf, "input", name="specular", type="float", value="0")
    mat = ET.SubElement(root, "surfacematerial", name="spectex_ground", type="material")
    ET.SubElement(mat, "input", name="surfaceshader", type="surfaceshader", nodename="SR_spectex_ground")
    unlit = ET.SubElement(root, "surface_unlit", name="SR_spectex_ground_unlit", type="surfaceshader")
    ET.SubElement(unlit, "input", name="emission_color", type="color3", nodegraph="NG_spectex_ground", output="out")
    mat = ET.SubElement(root, "surfacematerial", name="spectex_ground_unlit", type="material")
    ET.SubElement(mat, "input", name="surfaceshader", type="surfaceshader", nodename="SR_spectex_ground_unlit")
    ET.indent(root, space="  ")
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write_materialx(texture, folder: Path) -> list[Path]:
    """Write ``folder/materialx/spectex_ground.mtlx`` and its tile(s); return the files."""
    from ._tiles import write_tiles

    out = Path(folder) / "materialx"
    out.mkdir()
    tiles = write_tiles(texture, out)
    doc = out / "spectex_ground.mtlx"
    doc.write_text(materialx_document(texture, [p.name for p in tiles]), encoding="utf-8")
    return [doc, *tiles]
