"""spectex spectral texture for Blender (written by `spectex export --format blender`).

Run it in Blender (Scripting workspace > Open > Run Script, or
`blender --python spectex_ground.py`). It builds the material "spectex_ground":
every layer of the texture as nodes (Geometry position, Vector Math for the
layer's coordinates, Image Texture for the tile, Math and Vector Math for the
blends), the blended colour decoded from sRGB to linear light, into a Principled
BSDF's Base Color. `build_material(unlit=True)` makes an Emission material instead
(the colours as spectex draws them, before sky and haze). The material goes on
the active object if it is a mesh.

Ground: spectex x (east) is Blender's X, spectex y (north) is Blender's Y, in
metres (Blender units); the material reads the world position, so put it on a
flat object at Z = 0 (a large plane). Keep the tile PNG(s) beside this file.
"""

import math
import os

import bpy

#: The texture, from spectex: tiles (file names), per-tile mean colours, layers.
SPECTEX = {"$TEXTURE$": None}

HERE = os.path.dirname(os.path.abspath(__file__)) if "__file__" in globals() else os.getcwd()


def _node(tree, kind, location, **settings):
    node = tree.nodes.new(kind)
    node.location = location
    for key, value in settings.items():
        setattr(node, key, value)
    return node


def _math(tree, operation, a, b, location):
    node = _node(tree, "ShaderNodeMath", location, operation=operation)
    for socket, value in zip(node.inputs, (a, b)):
        if isinstance(value, (int, float)):
            socket.default_value = value
        else:
            tree.links.new(value, socket)
    return node.outputs[0]


def _vmath(tree, operation, a, b, location, scale=None):
    node = _node(tree, "ShaderNodeVectorMath", location, operation=operation)
    for socket, value in zip(node.inputs, (a, b)):
        if value is None:
            continue
        if isinstance(value, (tuple, list)):
            socket.default_value = value
        else:
            tree.links.new(value, socket)
    if scale is not None:
        node.inputs["Scale"].default_value = scale
    return node.outputs["Value" if operation == "DOT_PRODUCT" else "Vector"]


def _image(path):
    image = bpy.data.images.load(path, check_existing=True)
    image.colorspace_settings.name = "Non-Color"  # the tile is data: blended as stored, not decoded
    image.alpha_mode = "CHANNEL_PACKED"  # alpha is the blend weight: the colour is not premultiplied
    return image


def build_material(name="spectex_ground", unlit=False):
    """The material for the texture; ``unlit``: Emission (spectex's colours as they are)."""
    material = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    material.use_nodes = True
    tree = material.node_tree
    tree.nodes.clear()
    position = _node(tree, "ShaderNodeNewGeometry", (-1600, 0)).outputs["Position"]
    images = [_image(os.path.join(HERE, file)) for file in SPECTEX["tiles"]]
    colour = None
    for k, layer in enumerate(SPECTEX["layers"]):
        y = -400 * k
        if layer["tiling"] != "periodic":
            print(f"spectex: layer {k} uses spectex's {layer['tiling']} tiling, which Blender's nodes cannot "
                  "draw: it is drawn as its periodic tile instead (it repeats every "
                  f"{layer['size']:g} m), and does not match spectex's picture")
        th = math.radians(layer["rotation"])
        c, s = math.cos(th), math.sin(th)
        rel = _vmath(tree, "SUBTRACT", position, (layer["offset"][0], layer["offset"][1], 0.0), (-1400, y))
        # (s, t) = R(-rotation) (p - offset) / size; Blender's v = 0 is the image's bottom row and
        # spectex's t = 0 its top row: v = -t on a periodic image
        u = _vmath(tree, "DOT_PRODUCT", rel, (c, s, 0.0), (-1200, y))
        v = _vmath(tree, "DOT_PRODUCT", rel, (s, -c, 0.0), (-1200, y - 150))
        combine = _node(tree, "ShaderNodeCombineXYZ", (-1000, y))
        tree.links.new(u, combine.inputs["X"])
        tree.links.new(v, combine.inputs["Y"])
        uv = _vmath(tree, "SCALE", combine.outputs["Vector"], None, (-850, y), scale=1.0 / layer["size"])
        tex = _node(tree, "ShaderNodeTexImage", (-700, y), image=images[layer["tile"]], interpolation="Linear",
                    extension="REPEAT")
        tree.links.new(uv, tex.inputs["Vector"])
        x = tex.outputs["Color"]
        if colour is None:  # the first layer sets the colour
            colour = x
            continue
        a = _math(tree, "MULTIPLY", tex.outputs["Alpha"], layer["opacity"], (-450, y - 150))
        if layer["blend"] == "alpha":  # c = a x + (1 - a) c = c + a (x - c)
            d = _vmath(tree, "SUBTRACT", x, colour, (-300, y))
            colour = _vmath(tree, "ADD", colour, _scaled(tree, d, a, (-150, y)), (0, y))
        elif layer["blend"] == "detail":  # c = 2 x c
            colour = _vmath(tree, "SCALE", _vmath(tree, "MULTIPLY", x, colour, (-300, y)), None, (-150, y),
                            scale=2.0)
        else:  # variance: c = mu + (a (x - mu) + (1 - a)(c - mu)) / sqrt(a^2 + (1 - a)^2)
            mu = tuple(SPECTEX["means"][layer["tile"]])
            dx = _vmath(tree, "SUBTRACT", x, mu, (-300, y))
            dc = _vmath(tree, "SUBTRACT", colour, mu, (-300, y - 100))
            b = _math(tree, "SUBTRACT", 1.0, a, (-300, y - 200))
            num = _vmath(tree, "ADD", _scaled(tree, dx, a, (-150, y)), _scaled(tree, dc, b, (-150, y - 100)),
                         (0, y))
            norm = _math(tree, "SQRT", _math(tree, "ADD", _math(tree, "MULTIPLY", a, a, (-150, y - 200)),
                                              _math(tree, "MULTIPLY", b, b, (-150, y - 300)), (0, y - 200)),
                         0.0, (150, y - 200))
            inv = _math(tree, "DIVIDE", 1.0, norm, (300, y - 200))
            colour = _vmath(tree, "ADD", _scaled(tree, num, inv, (450, y)), mu, (600, y))
    separate = _node(tree, "ShaderNodeSeparateXYZ", (800, 0))
    tree.links.new(colour, separate.inputs["Vector"])
    linear = _node(tree, "ShaderNodeCombineXYZ", (1400, 0))
    for i, axis in enumerate("XYZ"):  # clamp to [0, 1], then the sRGB decode, channel by channel
        ch = _math(tree, "MINIMUM", _math(tree, "MAXIMUM", separate.outputs[axis], 0.0, (950, -300 * i)), 1.0,
                   (1050, -300 * i))
        low = _math(tree, "DIVIDE", ch, 12.92, (1150, -300 * i))
        high = _math(tree, "POWER", _math(tree, "DIVIDE", _math(tree, "ADD", ch, 0.055, (1150, -300 * i - 100)),
                                          1.055, (1250, -300 * i - 100)), 2.4, (1350, -300 * i - 100))
        step = _math(tree, "GREATER_THAN", ch, 0.04045, (1150, -300 * i - 200))
        mix = _math(tree, "ADD", low, _math(tree, "MULTIPLY", step, _math(tree, "SUBTRACT", high, low,
                                                                            (1250, -300 * i - 200)),
                                            (1350, -300 * i - 200)), (1450, -300 * i))
        tree.links.new(mix, linear.inputs[axis])
    out = _node(tree, "ShaderNodeOutputMaterial", (2000, 0))
    if unlit:
        shader = _node(tree, "ShaderNodeEmission", (1700, 0))
        tree.links.new(linear.outputs["Vector"], shader.inputs["Color"])
        tree.links.new(shader.outputs["Emission"], out.inputs["Surface"])
    else:
        shader = _node(tree, "ShaderNodeBsdfPrincipled", (1700, 0))
        tree.links.new(linear.outputs["Vector"], shader.inputs["Base Color"])
        tree.links.new(shader.outputs["BSDF"], out.inputs["Surface"])
    return material


def _scaled(tree, vector, factor, location):
    node = _node(tree, "ShaderNodeVectorMath", location, operation="SCALE")
    tree.links.new(vector, node.inputs[0])
    tree.links.new(factor, node.inputs["Scale"])
    return node.outputs["Vector"]


if __name__ == "__main__":
    _material = build_material()
    _object = bpy.context.view_layer.objects.active if bpy.context.view_layer else None
    if _object is not None and _object.type == "MESH":
        _object.data.materials.clear()
        _object.data.materials.append(_material)
