"""The ``godot`` and ``hlsl`` exports: the shading core's library text inside, and every shader
compiled by glslangValidator (HLSL front end for the include; the Godot shader through a
small translation of Godot's few non-GLSL lines)."""

from __future__ import annotations

import re
import subprocess
from dataclasses import replace
from pathlib import Path

import pytest

from helpers import glslang_validator, make_test_tile
from spectex.export import export
from spectex.export.hlsl import ENTRY_POINT
from spectex.shading.glsl import shader_file
from spectex.shading.resources import mip_levels
from spectex.shading.tables import anchor_coords
from spectex.texture import Layer, SpectralTexture


def textures():
    paper = SpectralTexture.paper_preset(tile=make_test_tile(32, 0))
    a = make_test_tile(64, 1)[::2].copy()
    b = make_test_tile(64, 2)[1::2].copy()
    layers = [Layer(size=5.0, tile=1, rotation=20.0),
              Layer(size=23.0, tile=0, offset=(3.0, 1.0), rotation=-70.0, blend="variance", opacity=0.9),
              Layer(size=120.0, tile=1, rotation=95.0, blend="detail"),
              Layer(size=470.0, tile=0, offset=(-7.0, 2.0), rotation=-151.0, blend="overlay", opacity=0.8)]
    stochastic = SpectralTexture.paper_preset(tile=make_test_tile(32, 0), tiling="stochastic")
    # layer 0 snapped to 4 x 3 periods of its tile (Layer.snap; 3 does not divide the tile: offsets rounded
    # down to whole texels), layer 2 not
    mixed_stochastic = SpectralTexture([a, b], [replace(layers[0], tiling="stochastic", patch=0.3, seed=5,
                                                        snap=(4, 3)), layers[1],
                                                replace(layers[2], tiling="stochastic", seed=8)])
    return {"paper": paper, "mixed": SpectralTexture([a, b], layers), "stochastic": stochastic,
            "mixed_stochastic": mixed_stochastic}


@pytest.fixture(scope="module", params=["paper", "mixed", "stochastic", "mixed_stochastic"])
def exported(request, tmp_path_factory):
    texture = textures()[request.param]
    return texture, export(texture, tmp_path_factory.mktemp("engines") / "out", formats="godot,hlsl").folder


def library_body() -> str:
    """The layer library's own text (no prelude, no constants)."""
    return shader_file("spectex_layers.glsl")


# ------------------------------------------------------------------------------------ HLSL
def compile_hlsl(tool, include: Path, texture, tmp_path: Path, *defines: str):
    names = hlsl_texture_names(texture)
    decls = "\n".join(f"Texture2D {name};\nSamplerState {name}Sampler;" for name in names)
    args = ", ".join(f"{name}, {name}Sampler" for name in names)
    wrapper = tmp_path / "wrapper.hlsl"
    wrapper.write_text(f"""#include "{include.name}"
{decls}
float4 spectex_test_main(float4 position : SV_Position, float2 ground : TEXCOORD0) : SV_Target {{
    float3 colour, linear_colour;
    {ENTRY_POINT}(ground, {args}, colour, linear_colour);
    return float4(linear_colour + 0.0 * colour, 1.0);
}}
""")
    return subprocess.run([tool, "-D", "-V", "-S", "frag", "-e", "spectex_test_main", f"-I{include.parent}",
                           *(f"-D{d}" for d in defines), "-o", str(tmp_path / "out.spv"), str(wrapper)],
                          capture_output=True, text=True)


def hlsl_texture_names(texture) -> list[str]:
    """The entry point's texture inputs: the tiles, and for stochastic layers their tables."""
    n = len(texture.tiles)
    names = [f"Tile{i}" for i in range(n)]
    if texture_is_stochastic(texture):
        names += [f"Gauss{i}" for i in range(n)] + ["Lut"]
    return names


@pytest.mark.parametrize("defines", [(), ("UNITY_VERSION=202230",), ("SPECTEX_FLIP_V=1", "SPECTEX_MAX_ANISOTROPY=1.0"),
                                     ("SPECTEX_ANCHORED",)])
def test_hlsl_include_compiles_with_glslang(exported, tmp_path, defines):
    tool = glslang_validator()
    texture, folder = exported
    include = folder / "hlsl" / "spectex_ground.hlsl"
    run = compile_hlsl(tool, include, texture, tmp_path, *defines)
    assert run.returncode == 0, run.stdout + run.stderr
    assert (tmp_path / "out.spv").stat().st_size > 1000


def test_hlsl_control_a_broken_include_fails(exported, tmp_path):
    tool = glslang_validator()
    texture, folder = exported
    broken = tmp_path / "inc" / "spectex_ground.hlsl"
    broken.parent.mkdir()
    broken.write_text((folder / "hlsl" / "spectex_ground.hlsl").read_text().replace("#define vec3 float3\n", ""))
    run = compile_hlsl(tool, broken, texture, tmp_path)
    assert run.returncode != 0


def test_hlsl_holds_the_library_text_and_unity_names(exported):
    texture, folder = exported
    text = (folder / "hlsl" / "spectex_ground.hlsl").read_text()
    assert library_body() in text
    assert f"void {ENTRY_POINT}(float2 Ground, Texture2D Tile0, SamplerState Tile0Sampler" in text
    stochastic = sum(layer.tiling == "stochastic" for layer in texture.layers)
    assert text.count("spectex_layer(SPX_BLEND_") == len(texture.layers) - stochastic
    assert text.count("spectex_layer_stochastic(SPX_BLEND_") == stochastic
    # nothing leaks into the including shader
    tail = text[text.rindex("(SPX_BLEND_"):]
    for name in ("vec2", "vec3", "vec4", "SPX_TEX_ARG", "SPX_TEX", "SPX_LOD", "SPX_UINT"):
        assert f"#undef {name}\n" in tail
    for name in (p.name for p in (folder / "hlsl").glob("*.png")):
        assert name in (folder / "hlsl" / "README.md").read_text()


# ------------------------------------------------------------------------------------ Godot
def godot_to_glsl(text: str, stage: str) -> str:
    """Godot's shading language -> GLSL 4.50, for a syntax check of everything but Godot's own lines.

    Godot's additions here are: ``shader_type``/``render_mode`` lines, uniform hints after
    ``:``, ``varying``, the ``vertex()``/``fragment()`` entry points and a few built-ins.
    """
    out = []
    for line in text.split("\n"):
        if re.match(r"\s*(shader_type|render_mode)\b", line):
            continue
        m = re.match(r"(\s*uniform\s+\w+\s+\w+(?:\[\d+\])?)\s*:\s*[^=;]+(=.*)?;(.*)$", line)
        if m:
            line = f"{m.group(1)} {m.group(2) or ''};{m.group(3)}"
        out.append(line)
    text = "\n".join(out)
    vertex = re.search(r"void vertex\(\) \{\n(.*?)\n\}\n", text, re.S)
    fragment = re.search(r"void fragment\(\) \{\n(.*?)\n\}\n", text, re.S)
    assert vertex and fragment
    body = vertex if stage == "vert" else fragment
    text = text[:vertex.start()] + text[vertex.end():]
    text = text[:text.index("void fragment() {")]
    if stage == "vert":
        # only declarations are needed before the vertex body; drop functions that sample
        text = text.replace("varying ", "out ")
        head = "#version 450\nin vec3 VERTEX;\nuniform mat4 MODEL_MATRIX;\n"
        return head + text + "void main() {\n" + body.group(1) + "\n}\n"
    text = text.replace("varying ", "in ")
    head = "#version 450\nuniform vec3 CAMERA_POSITION_WORLD;\nout vec4 spectex_out;\nvec3 ALBEDO;\n"
    return head + text + "void main() {\n" + body.group(1) + "\n    spectex_out = vec4(ALBEDO, 1.0);\n}\n"


@pytest.mark.parametrize("stage", ["vert", "frag"])
def test_godot_shader_compiles_as_glsl(exported, tmp_path, stage):
    tool = glslang_validator()
    _, folder = exported
    text = (folder / "godot" / "spectex_ground.gdshader").read_text()
    assert text.startswith("shader_type spatial;\n")
    path = tmp_path / f"godot.{stage}"
    path.write_text(godot_to_glsl(text, stage))
    run = subprocess.run([tool, str(path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr


def test_godot_control_a_broken_shader_fails(exported, tmp_path):
    tool = glslang_validator()
    _, folder = exported
    good = (folder / "godot" / "spectex_ground.gdshader").read_text()
    text = good.replace("p, jx, jy, SPECTEX_TEX_SIZE", "p, jx, SPECTEX_TEX_SIZE", 1)  # a layer step's argument gone
    assert text != good
    path = tmp_path / "broken.frag"
    path.write_text(godot_to_glsl(text, "frag"))
    assert subprocess.run([tool, str(path)], capture_output=True, text=True).returncode != 0


def test_godot_holds_the_library_text_tiles_and_script(exported):
    texture, folder = exported
    shader = (folder / "godot" / "spectex_ground.gdshader").read_text()
    assert library_body() in shader
    for i in range(len(texture.tiles)):
        line = next(x for x in shader.split("\n") if x.startswith(f"uniform sampler2D spectex_tile{i} "))
        assert "repeat_enable" in line and "filter_linear_mipmap" in line
        assert "source_color" not in line  # the tile is data (docs/export.md)
    stochastic = sum(layer.tiling == "stochastic" for layer in texture.layers)
    assert shader.count("spectex_layer(SPX_BLEND_") == len(texture.layers) - stochastic
    assert shader.count("spectex_layer_stochastic(SPX_BLEND_") == stochastic
    script = (folder / "godot" / "spectex_ground.gd").read_text()
    if stochastic:  # the script loads the tables the export wrote beside it
        for name in ("gauss.rgba16f" if len(texture.tiles) == 1 else "gauss0.rgba16f", "spectex_lut.r16f"):
            assert f'"{name}"' in script and (folder / "godot" / name).is_file()
        assert "Image.FORMAT_RGBAH" in script and "spectex_gbase" in script and "spectex_ganchor" in script
    assert script.startswith("@tool\nextends MeshInstance3D\n")
    assert script.count("\t[") == len(texture.layers)
    assert "fposmod" in script and "spectex_anchor" in script
    readme = (folder / "godot" / "README.md").read_text()
    assert "Lossless" in readme and "Fix Alpha Border: off" in readme and "Compress To: Disabled" in readme


# ------------------------------------ the engine shaders' arithmetic, drawn by llvmpipe on a ground mesh
def _view_projection(camera, h, w, world_to_spectex):
    """A world point (4-vector) -> clip space of spectex's camera (x, y as spectex's rays; w = depth)."""
    import numpy as np

    fwd, right, up = camera.basis()
    tan_x, tan_y = camera.tangents(h, w)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = right / tan_x, up / tan_y, fwd
    view[:3, 3] = -view[:3, :3] @ np.array(camera.position)
    clip = np.array([view[0], view[1], 0.5 * view[2], view[2]])
    return clip @ world_to_spectex


#: Godot's world (X, Y, Z) is spectex's (x, z, -y).
GODOT_TO_SPECTEX = [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
#: The HLSL entry point takes spectex's ground point itself.
GROUND_TO_SPECTEX = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]

ENCODE_SRGB = ("vec3 a = clamp(ALBEDO, 0.0, 1.0);\n    spectex_out = vec4(mix(1.055 * pow(a, vec3(1.0 / 2.4)) - 0.055, "
               "12.92 * a, vec3(lessThanEqual(a, vec3(0.0031308)))), 1.0);")


def upload_tables(gl, texture, folder, *, flip_rows=False):
    """The stochastic tables from an export's raw files alone, as the READMEs say: per tile its
    Gaussianised levels on units n .. 2n - 1, the look-up table on unit 2n."""
    import moderngl
    import numpy as np

    from spectex.export._stochastic import LUT_FILE, gauss_name, read_raw

    n = len(texture.tiles)
    shapes = [lv.shape[:2] for lv in mip_levels(texture)[0]]
    out = []
    for i in range(n):
        levels = read_raw(folder / gauss_name(texture, i), shapes, 4)
        levels = [lv[::-1] for lv in levels] if flip_rows else levels  # as loaded by an engine with v = 0 at the bottom
        tex = gl.texture(shapes[0][::-1], 4, np.ascontiguousarray(levels[0].astype("f2")).tobytes(), dtype="f2",
                         alignment=1)
        tex.build_mipmaps(0, len(levels) - 1)
        for d, level in enumerate(levels[1:], start=1):
            tex.write(np.ascontiguousarray(level.astype("f2")).tobytes(), level=d, alignment=1)
        tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        tex.repeat_x = tex.repeat_y = True
        tex.use(location=n + i)
        out.append(tex)
    size = (folder / LUT_FILE).stat().st_size // 2 // 1024
    lut = read_raw(folder / LUT_FILE, [(size, 1024)], 1)[0]
    lut = lut[::-1] if flip_rows else lut
    tex = gl.texture((1024, size), 1, np.ascontiguousarray(lut.astype("f2")).tobytes(), dtype="f2", alignment=1)
    tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
    tex.repeat_x = tex.repeat_y = False
    tex.use(location=2 * n)
    out.append(tex)
    return out


def draw_ground(gl, texture, camera, size, vert, frag, quad, world_to_spectex, *, setup=None, flip_rows=False,
                tables=None):
    """Draw ``quad`` (4 world points, a triangle strip) with the shaders; RGBA uint8, row 0 at the top.
    ``tables``: the export's folder, whose stochastic tables to upload."""
    import moderngl
    import numpy as np

    from spectex.render.gl import park_framebuffer

    h, w = size
    program = gl.program(vertex_shader=vert, fragment_shader=frag)
    textures = []
    for unit, levels in enumerate(mip_levels(texture)):
        levels = [lv[::-1] for lv in levels] if flip_rows else levels  # as an engine with v = 0 at the bottom
        raw = [np.ascontiguousarray(np.floor(lv * 255 + 0.5).astype(np.uint8)).tobytes() for lv in levels]
        tex = gl.texture(levels[0].shape[1::-1], 4, raw[0], alignment=1)
        tex.build_mipmaps(0, len(levels) - 1)
        for d, data in enumerate(raw[1:], start=1):
            tex.write(data, level=d, alignment=1)
        tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        tex.repeat_x = tex.repeat_y = True
        tex.use(location=unit)
        textures.append(tex)
    if tables is not None and texture_is_stochastic(texture):
        textures += upload_tables(gl, texture, tables, flip_rows=flip_rows)
    program["u_view_proj"].write(_view_projection(camera, h, w, np.array(world_to_spectex)).T.astype("f4").tobytes())
    if setup is not None:
        setup(program)
    vbo = gl.buffer(np.asarray(quad, dtype="f4").tobytes())
    vao = gl.vertex_array(program, [(vbo, f"{len(quad[0])}f", "VERTEX")])
    rb = gl.renderbuffer((w, h), 4)
    fbo = gl.framebuffer(color_attachments=[rb])
    try:
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        fbo.clear(0.0, 0.0, 0.0, 0.0)
        vao.render(moderngl.TRIANGLE_STRIP)
        return np.frombuffer(fbo.read(components=4, alignment=1), np.uint8).reshape(h, w, 4)[::-1]
    finally:
        park_framebuffer(gl)
        for obj in (vao, vbo, fbo, rb, program, *textures):
            obj.release()


def texture_is_stochastic(texture) -> bool:
    return any(layer.tiling == "stochastic" for layer in texture.layers)


def ground_psnr(texture, camera, rgba) -> float:
    """PSNR of the drawn pixels against the CPU renderer without haze (anisotropy 8, as the engines' default)."""
    import numpy as np

    from spectex.render import Atmosphere
    from spectex.render.cpu import render_cpu

    drawn = rgba[..., 3] > 0
    assert drawn.mean() > 0.99  # the views look down: the quad fills the picture
    reference = render_cpu(texture, camera, rgba.shape[:2], anisotropy=8.0, atmosphere=Atmosphere(haze_distance=0))
    mse = float(np.mean((rgba[..., :3][drawn] / 255.0 - reference[drawn]) ** 2))
    return 10 * np.log10(1 / mse)


VIEWS = [
    (((0.0, 0.0, 2.0), 30.0, -40.0), False),
    (((1000.0, -500.0, 60.0), 200.0, -60.0), False),
    (((900.0, -700.0, 6.0), 300.0, -35.0), True),
]


@pytest.mark.gl
@pytest.mark.parametrize("camera_args, anchored", VIEWS)
def test_godot_shader_draws_spectex_ground(exported, gl, camera_args, anchored):
    """The exported .gdshader, translated to GLSL, on a ground mesh seen by spectex's camera,
    matches the CPU renderer (no haze): the ground mapping, the anchors and the blends, periodic
    and stochastic layers. (Control, run by hand: with spectex y = +Z instead of -Z, 9-32 dB.)"""
    from spectex.render import Camera

    texture, folder = exported
    position, yaw, pitch = camera_args
    camera = Camera(position, yaw=yaw, pitch=pitch, fov=50.0)
    rgba = draw_godot(gl, texture, folder, camera, anchored)
    # measured 53-58 dB on llvmpipe (its dFdx/dFdy are exact for the plane's linear ground point)
    assert ground_psnr(texture, camera, rgba) >= 45.0


@pytest.mark.gl
def test_godot_stochastic_controls_fail(gl, tmp_path):
    """Controls: the stochastic Godot shader with other hash keys, or anchored without the grid
    vertex (the script's spectex_gbase left at zero), is far from spectex's picture."""
    from spectex.render import Camera

    texture = textures()["mixed_stochastic"]
    folder = export(texture, tmp_path / "out", formats="godot").folder
    camera = Camera(VIEWS[2][0][0], yaw=VIEWS[2][0][1], pitch=VIEWS[2][0][2], fov=50.0)
    assert ground_psnr(texture, camera, draw_godot(gl, texture, folder, camera, True)) >= 45.0
    text = (folder / "godot" / "spectex_ground.gdshader").read_text()
    line = next(x for x in text.split("\n") if x.startswith("const uint SPECTEX_KEY["))
    wrong_keys = text.replace(line, re.sub(r"(\d+)u", lambda m: f"{(int(m.group(1)) + 1) % 2 ** 32}u", line))
    assert wrong_keys != text
    assert ground_psnr(texture, camera, draw_godot(gl, texture, folder, camera, True, text=wrong_keys)) < 30.0
    assert ground_psnr(texture, camera, draw_godot(gl, texture, folder, camera, True, gbase=False)) < 30.0


def draw_godot(gl, texture, folder, camera, anchored, *, text=None, gbase=True):
    """The exported .gdshader (or ``text``), translated to GLSL, drawn on a ground mesh with what
    spectex_ground.gd would set (``gbase=False``: the grid vertices left at zero)."""
    if text is None:
        text = (folder / "godot" / "spectex_ground.gdshader").read_text()
    vert = godot_to_glsl(text, "vert").replace(
        "#version 450\n", "#version 450\nuniform mat4 u_view_proj;\n").rstrip()[:-1] + (
        "    gl_Position = u_view_proj * vec4(spectex_world, 1.0);\n}\n")
    frag = godot_to_glsl(text, "frag").replace("spectex_out = vec4(ALBEDO, 1.0);", ENCODE_SRGB)

    def setup(program):
        import numpy as np

        n = len(texture.tiles)
        for unit in range(n):
            set_if_used(program, f"spectex_tile{unit}", unit)
            set_if_used(program, f"spectex_gauss{unit}", n + unit)
        set_if_used(program, "spectex_lut_texture", 2 * n)
        program["MODEL_MATRIX"].write(np.eye(4, dtype="f4").tobytes())
        if anchored:  # what spectex_ground.gd sets: a point near the camera, snapped, and its anchors
            x0, y0, _ = camera.position
            ax, ay = round(x0 / 256.0) * 256.0, round(y0 / 256.0) * 256.0
            coords = anchor_coords(texture.layers, ax, ay)
            program["spectex_anchored"].value = True
            program["spectex_anchor_point"].value = (ax, ay)
            set_if_used(program, "spectex_anchor", [tuple(a[:2]) for a in coords])
            set_if_used(program, "spectex_ganchor", [tuple(a[2:4]) for a in coords])
            if gbase:  # the script's PackedInt32Array: the grid vertex's bits as int32
                set_if_used(program, "spectex_gbase", [tuple(int(v) - 2 ** 32 if v >= 2 ** 31 else int(v)
                                                             for v in a[4:]) for a in coords])

    x0, y0, _ = camera.position
    r = 4000.0
    quad = [[x0 - r, 0, -(y0 - r)], [x0 + r, 0, -(y0 - r)], [x0 - r, 0, -(y0 + r)], [x0 + r, 0, -(y0 + r)]]
    return draw_ground(gl, texture, camera, (90, 160), vert, frag, quad, GODOT_TO_SPECTEX, setup=setup,
                       tables=folder / "godot")


def set_if_used(program, name, value):
    """Set a uniform the compiler kept (arrays cut to the length it kept)."""
    if name not in program:
        return
    if isinstance(value, list):
        value = value[:program[name].array_length]
        value = value[0] if len(value) == 1 else value
    program[name].value = value


def hlsl_to_glsl(text: str) -> str:
    """The HLSL include as GLSL 4.50: GLSL texture macros for its HLSL prelude, HLSL names as macros."""
    from spectex.export.hlsl import _PRELUDE

    assert _PRELUDE in text
    glsl_prelude = """#define SPX_TEX_ARG(name) sampler2D name
#define SPX_TEX(name) name
#define SPX_UINT uint
#if SPECTEX_FLIP_V
#define SPX_LOD(name, uv, lod) textureLod(name, vec2(1.0, -1.0) * (uv) + vec2(0.0, 1.0), lod)
#else
#define SPX_LOD(name, uv, lod) textureLod(name, uv, lod)
#endif
"""
    text = text.replace(_PRELUDE, glsl_prelude)
    text = re.sub(r"Texture2D (\w+), SamplerState \w+Sampler", r"sampler2D \1", text)
    text = text.replace("static const ", "const ")
    text = re.sub(r"^float4 (Spectex\w+\[)", r"uniform float4 \1", text, flags=re.M)
    head = ("#version 450\n#define float2 vec2\n#define float3 vec3\n#define float4 vec4\n#define uint2 uvec2\n"
            "#define ddx dFdx\n"
            "#define ddy dFdy\n#define lerp mix\n#define saturate(x) clamp(x, 0.0, 1.0)\n")
    return head + text


@pytest.mark.gl
@pytest.mark.parametrize("camera_args, flip", [(VIEWS[0][0], False), (VIEWS[1][0], True), (VIEWS[2][0], False)])
def test_hlsl_entry_point_draws_spectex_ground(exported, gl, camera_args, flip):
    """The exported HLSL include's entry point, its HLSL names mapped to GLSL, on a ground mesh:
    matches the CPU renderer (measured 53-58 dB), periodic and stochastic layers. ``flip``:
    Unity's convention (SPECTEX_FLIP_V, the tile and tables uploaded bottom row first).
    (Control, run by hand: the rows in the other order than the flip expects, 7-23 dB.)"""
    from spectex.render import Camera

    texture, folder = exported
    position, yaw, pitch = camera_args
    camera = Camera(position, yaw=yaw, pitch=pitch, fov=50.0)
    rgba = draw_hlsl(gl, texture, folder, camera, flip)
    assert ground_psnr(texture, camera, rgba) >= 45.0


@pytest.mark.gl
@pytest.mark.parametrize("flip", [False, True])
def test_hlsl_anchored_holds_far_from_the_origin(gl, tmp_path, flip):
    """SPECTEX_ANCHORED, 3000 km out: the host's anchors (the README's formula, float64) and a
    ground point relative to the anchor point draw spectex's picture; controls: the grid vertex
    left at zero, or no anchors at all (the origin's constants, the ground point absolute in
    float32), are far from it."""
    from spectex.render import Camera

    texture = textures()["mixed_stochastic"]
    folder = export(texture, tmp_path / "out", formats="hlsl").folder
    camera = Camera((3.0e6, -2.0e6, 20.0), yaw=40.0, pitch=-40.0, fov=50.0)
    assert ground_psnr(texture, camera, draw_hlsl(gl, texture, folder, camera, flip, anchored=True)) >= 45.0
    wrong = draw_hlsl(gl, texture, folder, camera, flip, anchored=True, gbase=False)
    assert ground_psnr(texture, camera, wrong) < 30.0
    assert ground_psnr(texture, camera, draw_hlsl(gl, texture, folder, camera, flip)) < 30.0


def draw_hlsl(gl, texture, folder, camera, flip, *, anchored=False, gbase=True):
    """The exported include's entry point (GLSL names for its HLSL ones) on a ground mesh. With
    ``anchored``, SPECTEX_ANCHORED: the mesh's points relative to an anchor point near the camera,
    SpectexAnchor and SpectexGridBase as the README says (``gbase=False``: the vertex left at 0)."""
    import numpy as np

    include = hlsl_to_glsl((folder / "hlsl" / "spectex_ground.hlsl").read_text())
    head = f"#version 450\n#define SPECTEX_FLIP_V {int(flip)}\n" + ("#define SPECTEX_ANCHORED\n" if anchored else "")
    include = include.replace("#version 450\n", head)
    names = hlsl_texture_names(texture)
    samplers = "".join(f"uniform sampler2D {name};\n" for name in names)
    frag = include + samplers + f"""in vec2 v_ground;
out vec4 spectex_out;
void main() {{
    vec3 c, lin;
    SpectexGround_float(v_ground, {', '.join(names)}, c, lin);
    spectex_out = vec4(c, 1.0);
}}
"""
    vert = """#version 450
uniform mat4 u_view_proj;
in vec2 VERTEX;
out vec2 v_ground;
void main() {
    v_ground = VERTEX;
    gl_Position = u_view_proj * vec4(VERTEX, 0.0, 1.0);
}
"""
    x0, y0, _ = camera.position
    ax, ay = (round(x0 / 256.0) * 256.0, round(y0 / 256.0) * 256.0) if anchored else (0.0, 0.0)

    def setup(program):
        for unit, name in enumerate(names):
            set_if_used(program, name, unit)
        if anchored:
            coords = anchor_coords(texture.layers, ax, ay)
            set_if_used(program, "SpectexAnchor", [tuple(a[:4]) for a in coords])
            halves = [(a[4] // 65536, a[4] % 65536, a[5] // 65536, a[5] % 65536) if gbase else (0.0,) * 4
                      for a in coords]
            set_if_used(program, "SpectexGridBase", halves)

    r = 4000.0
    # the mesh's points relative to the anchor point; the view-projection moves them back (float64 here)
    quad = [[x0 - ax - r, y0 - ay - r], [x0 - ax + r, y0 - ay - r], [x0 - ax - r, y0 - ay + r],
            [x0 - ax + r, y0 - ay + r]]
    to_spectex = np.array(GROUND_TO_SPECTEX)
    to_spectex[:2, 3] = (ax, ay)
    return draw_ground(gl, texture, camera, (90, 160), vert, frag, quad, to_spectex, setup=setup, flip_rows=flip,
                       tables=folder / "hlsl")
