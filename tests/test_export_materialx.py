"""The ``materialx`` export: read by MaterialX, valid, standard nodes only, GLSL from
MaterialX's own generator, and the node graph's arithmetic equal to spectex's."""

from __future__ import annotations

import os
import shutil
import subprocess
import xml.etree.ElementTree as ET
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from helpers import make_test_tile
from spectex.export import export
from spectex.io import read_image
from spectex.render import bake
from spectex.sampling import MipTexture, sample
from spectex.texture import Layer, SpectralTexture

try:
    import MaterialX as mx
except ImportError:  # CI installs it (the test extras): there a missing package is a failure
    if os.environ.get("CI", "").lower() == "true":
        raise
    pytest.skip("MaterialX is not installed (pip install materialx)", allow_module_level=True)

#: The nodes the graph may use: MaterialX standard library nodes, and not ``over``.
ALLOWED = {"hextiledimage", "position", "dotproduct", "combine2", "subtract", "divide", "image", "convert",
           "extract", "multiply", "mix", "add", "sqrt", "clamp", "power", "ifgreater", "combine3", "overlay"}


def textures():
    tile = make_test_tile(64, 3)
    square = SpectralTexture.paper_preset(tile=tile)
    a = make_test_tile(128, 4)[::2].copy()
    b = make_test_tile(128, 5)[1::2].copy()
    layers = [Layer(size=7.0, tile=0, offset=(1.5, -2.0), rotation=10.0),
              Layer(size=31.0, tile=1, offset=(-3.0, 4.0), rotation=137.5, blend="variance", opacity=0.8),
              Layer(size=170.0, tile=0, rotation=-61.0, blend="detail"),
              Layer(size=420.0, tile=1, offset=(9.0, -4.0), rotation=77.0, blend="overlay", opacity=0.7),
              Layer(size=900.0, tile=1, offset=(100.0, 50.0), rotation=200.0, opacity=0.6)]
    return {"paper": square, "mixed": SpectralTexture([a, b], layers, bits=8),
            "float": SpectralTexture([a, b], layers, bits=None)}


@pytest.fixture(scope="module", params=["paper", "mixed", "float"])
def exported(request, tmp_path_factory):
    texture = textures()[request.param]
    result = export(texture, tmp_path_factory.mktemp("mtlx") / "out", formats="materialx")
    return texture, result.folder / "materialx" / "spectex_ground.mtlx"


def stdlib():
    lib = mx.createDocument()
    search = mx.FileSearchPath(os.path.dirname(mx.__file__))
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), search, lib)
    return lib, search


def test_files_written(exported):
    texture, path = exported
    names = sorted(p.name for p in path.parent.iterdir())
    expected = ["tile.png"] if len(texture.tiles) == 1 else [f"tile{i}.png" for i in range(len(texture.tiles))]
    assert names == sorted(["spectex_ground.mtlx", *expected])
    for name, tile in zip(expected, texture.tiles):
        png = read_image(path.parent / name)
        assert png.shape == tile.shape  # RGBA: the alpha survives
        atol = 0.0 if texture.bits == 8 else 0.5 / 65535
        np.testing.assert_allclose(png, tile, atol=atol, rtol=0)


def test_materialx_reads_and_validates_it_with_nodedefs_for_every_node(exported):
    _, path = exported
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(path))
    assert doc.getVersionString() == "1.39"
    lib, _ = stdlib()
    doc.importLibrary(lib)
    valid, message = doc.validate()
    assert valid, message
    graph = doc.getNodeGraph("NG_spectex_ground")
    nodes = graph.getNodes()
    assert len(nodes) > 10
    for node in nodes:
        assert node.getNodeDef() is not None, node.getName()
    assert {node.getCategory() for node in nodes} <= ALLOWED - {"hextiledimage"}  # every layer periodic here
    for name in ("spectex_ground", "spectex_ground_unlit"):
        material = doc.getChild(name)
        assert material is not None and material.getCategory() == "surfacematerial"
        shader = material.getInput("surfaceshader").getConnectedNode()
        assert shader.getNodeDef() is not None


def test_materialx_generates_glsl_that_compiles(exported, tmp_path):
    import MaterialX.PyMaterialXGenGlsl as mx_glsl
    import MaterialX.PyMaterialXGenShader as mx_gen

    _, path = exported
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(path))
    lib, search = stdlib()
    doc.importLibrary(lib)
    generator = mx_glsl.GlslShaderGenerator.create()
    context = mx_gen.GenContext(generator)
    context.registerSourceCodeSearchPath(search)
    for name in ("spectex_ground", "spectex_ground_unlit"):
        shader = generator.generate(name, doc.getChild(name), context)
        pixel = shader.getSourceCode(mx_gen.PIXEL_STAGE)
        vertex = shader.getSourceCode(mx_gen.VERTEX_STAGE)
        assert "layer0_texel_file" in pixel and "texture(" in pixel
        glslang = shutil.which("glslangValidator")
        if glslang is None:
            if os.environ.get("CI", "").lower() == "true":
                pytest.fail("glslangValidator is missing (apt-get install glslang-tools)")
            continue
        (tmp_path / f"{name}.frag").write_text(pixel)
        (tmp_path / f"{name}.vert").write_text(vertex)
        run = subprocess.run([glslang, str(tmp_path / f"{name}.vert"), str(tmp_path / f"{name}.frag")],
                             capture_output=True, text=True)
        assert run.returncode == 0, run.stdout + run.stderr


# ----------------------------------------------------------------------------------------------
# An independent evaluation of the node graph: the MaterialX specification's meaning of each node,
# in NumPy, on a grid of world points; images sampled bilinearly at level 0 with the v axis up
# (MaterialX: texcoord (0, 0) is the lower-left corner of the image).

def _value(text: str, type_: str):
    if type_ in ("string", "filename"):
        return text
    if type_ == "integer":
        return int(text)
    values = np.array([float(v) for v in text.split(",")])
    return values[0] if type_ == "float" else values


class _Graph:
    """What the node rules need: the ground points, the graph's interface and its folder."""

    def __init__(self, path, x, y, interface, v_up):
        self.path, self.x, self.y, self.interface, self.v_up = path, x, y, interface, v_up

    def vec(self, a):
        a = np.asarray(a, dtype=np.float64)
        return a if a.ndim == 2 else (a[:, None] if a.ndim == 1 and a.shape[0] == self.x.size else a[None, :])


def _position(g, node, ins):
    assert ins["space"] == "world"
    u, v = g.interface["ground_u"], g.interface["ground_v"]
    # world point of ground (x, y): x u + y v (u, v orthonormal here)
    return g.x[:, None] * u[None, :] + g.y[:, None] * v[None, :]


def _arithmetic(g, node, ins):
    n = g.x.size
    a, b = ins["in1"], ins["in2"]
    a = a if np.ndim(a) != 1 or np.shape(a)[0] == n else np.asarray(a)[None, :]
    b = b if np.ndim(b) != 1 or np.shape(b)[0] == n else np.asarray(b)[None, :]
    a = a[:, None] if np.ndim(a) == 1 and np.ndim(b) == 2 else a
    b = b[:, None] if np.ndim(b) == 1 and np.ndim(a) == 2 else b
    ops = {"subtract": np.subtract, "add": np.add, "multiply": np.multiply, "divide": np.divide}
    return ops[node.tag](a, b)


def _mix(g, node, ins):  # bg (1 - mix) + fg mix
    m = ins["mix"][:, None]
    return g.vec(ins["bg"]) * (1.0 - m) + g.vec(ins["fg"]) * m


def _overlay(g, node, ins):  # the standard library's overlay of fg on bg, mixed with bg by mix
    fg, bg, m = g.vec(ins["fg"]), g.vec(ins["bg"]), ins["mix"][:, None]
    full = np.where(bg >= 0.5, 1.0 - 2.0 * (1.0 - bg) * (1.0 - fg), 2.0 * fg * bg)
    return bg * (1.0 - m) + full * m


def _convert(g, node, ins):
    assert node.get("type") == "color3"
    return ins["in"][:, :3]


def _image(g, node, ins):
    assert ins["uaddressmode"] == ins["vaddressmode"] == "periodic" and ins["filtertype"] == "linear"
    tile = read_image(g.path.parent / ins["file"])
    tex = MipTexture([tile], min_filter="linear", bits=None)
    uv = ins["texcoord"]
    t = 1.0 - uv[:, 1] if g.v_up else uv[:, 1]
    return sample(tex, uv[:, 0], t, lod=0.0).astype(np.float64)


#: What each node category computes from its inputs (MaterialX's standard nodes, as far as the export uses them).
_NODE_RULES = {
    "position": _position,
    "dotproduct": lambda g, node, ins: np.sum(g.vec(ins["in1"]) * g.vec(ins["in2"]), axis=1),
    "combine2": lambda g, node, ins: np.stack([np.broadcast_to(ins["in1"], g.x.shape),
                                               np.broadcast_to(ins["in2"], g.x.shape)], axis=1),
    "subtract": _arithmetic, "add": _arithmetic, "multiply": _arithmetic, "divide": _arithmetic,
    "mix": _mix, "overlay": _overlay,
    "combine3": lambda g, node, ins: np.stack([np.broadcast_to(ins[k], g.x.shape) for k in ("in1", "in2", "in3")],
                                              axis=1),
    "power": lambda g, node, ins: np.power(ins["in1"], ins["in2"]),
    # in1 where value1 > value2, else in2
    "ifgreater": lambda g, node, ins: np.where(ins["value1"] > ins["value2"], ins["in1"], ins["in2"]),
    "sqrt": lambda g, node, ins: np.sqrt(ins["in"]),
    "clamp": lambda g, node, ins: np.clip(ins["in"], ins["low"], ins["high"]),
    "convert": _convert,
    "extract": lambda g, node, ins: ins["in"][:, ins["index"]],
    "image": _image,
}


def evaluate_graph(path: Path, x, y, *, v_up=True, output="stored"):
    root = ET.parse(path).getroot()
    graph = root.find("nodegraph[@name='NG_spectex_ground']")
    interface = {i.get("name"): _value(i.get("value"), i.get("type")) for i in graph.findall("input")}
    nodes = {n.get("name"): n for n in graph if n.tag not in ("input", "output") and isinstance(n.tag, str)}
    g = _Graph(path, x, y, interface, v_up)
    cache = {}

    def inputs(node):
        out = {}
        for i in node.findall("input"):
            if i.get("nodename"):
                out[i.get("name")] = value_of(i.get("nodename"))
            elif i.get("interfacename"):
                out[i.get("name")] = interface[i.get("interfacename")]
            else:
                out[i.get("name")] = _value(i.get("value"), i.get("type"))
        return out

    def value_of(name):
        if name in cache:
            return cache[name]
        node = nodes[name]
        rule = _NODE_RULES.get(node.tag)
        if rule is None:
            raise AssertionError(f"node {node.tag} has no meaning here")
        cache[name] = rule(g, node, inputs(node))
        return cache[name]

    out = graph.find(f"output[@name='{output}']")
    return value_of(out.get("nodename"))

def test_graph_computes_what_spectex_bakes(exported):
    """Evaluated node by node, the graph gives spectex.render.bake's colours (level 0, bilinear)."""
    texture, path = exported
    h, w, p = 24, 32, 3.7
    origin = (-300.0, 200.0)
    # standard nodes cannot see a footprint: a fine or cover layer is the variance blend at its own alpha there
    assert {"fine", "cover"} <= {layer.blend for layer in textures()["paper"].layers}
    reference = SpectralTexture(texture.tiles, [replace(layer, blend="variance") if layer.blend in ("fine", "cover")
                                                else layer for layer in texture.layers], bits=texture.bits)
    text = path.read_text()
    assert ("is a fine (detail) layer" in text and "is a cover layer" in text) or reference == texture
    baked = bake(reference, (h, w), origin=origin, pixel_size=p, filter="linear", mipmaps=False)
    r, c = np.mgrid[0:h, 0:w]
    x = (origin[0] + (c + 0.5) * p).reshape(-1)
    y = (origin[1] + (r + 0.5) * p).reshape(-1)
    graph = evaluate_graph(path, x, y).reshape(h, w, 3)
    np.testing.assert_allclose(graph, baked, atol=2e-5, rtol=0)
    # the materials' colour ('out') is that colour decoded from sRGB to linear light, once
    linear = evaluate_graph(path, x, y, output="out").reshape(h, w, 3)
    decoded = np.where(baked <= 0.04045, baked / 12.92, ((baked + 0.055) / 1.055) ** 2.4)
    np.testing.assert_allclose(linear, decoded, atol=6e-5, rtol=0)  # the decode steepens 2e-5 at most 2.4-fold
    assert np.abs(linear - baked).max() > 0.1  # control: the decode is not a no-op
    # control: reading the image with v pointing down (the wrong convention) is visibly different
    flipped = evaluate_graph(path, x, y, v_up=False).reshape(h, w, 3)
    assert np.abs(flipped - baked).max() > 0.05


def test_no_over_node_and_a_note_on_colour_space(exported):
    _, path = exported
    text = path.read_text(encoding="utf-8")
    assert "<over " not in text and "colorspace=\"lin_rec709\"" in text
    assert "sky" in text and "haze" in text  # the file says what it leaves out


def test_a_layer_without_standard_node_equivalent_is_named_in_the_file(tmp_path):
    """A non-periodic layer (spectex's stochastic tiling) becomes hextiledimage, with a note."""
    paper = textures()["paper"]
    layers = list(paper.layers)
    layers[2] = replace(layers[2], tiling="stochastic", patch=0.4, seed=7)
    texture = SpectralTexture(paper.tiles, layers)
    path = export(texture, tmp_path / "out", formats="materialx").folder / "materialx" / "spectex_ground.mtlx"
    text = path.read_text()
    assert "layer 2 uses spectex's stochastic tiling, which has no standard-node equivalent" in text
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(path))
    lib, _ = stdlib()
    doc.importLibrary(lib)
    assert doc.validate()[0]
    graph = doc.getNodeGraph("NG_spectex_ground")
    assert graph.getNode("layer2_texel").getCategory() == "hextiledimage"
    assert graph.getNode("layer2_texel").getNodeDef() is not None
    assert graph.getNode("layer1_texel").getCategory() == "image"
