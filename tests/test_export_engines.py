"""The ``godot`` and ``hlsl`` exports: the shading core's library text inside, and every shader
compiled by glslangValidator (HLSL front end for the include; the Godot shader through a
small translation of Godot's few non-GLSL lines)."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from spectex.export import export
from spectex.export.hlsl import ENTRY_POINT
from spectex.shading.glsl import shader_file
from spectex.texture import Layer, SpectralTexture

sys.path.insert(0, str(Path(__file__).parent))
from conftest import make_test_tile  # noqa: E402


def glslang() -> str:
    path = shutil.which("glslangValidator")
    if path is None:
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail("glslangValidator is missing: CI must have it (apt-get install glslang-tools)")
        pytest.skip("glslangValidator is missing (apt-get install glslang-tools)")
    return path


def textures():
    paper = SpectralTexture.paper_preset(tile=make_test_tile(32, 0))
    a = make_test_tile(64, 1)[::2].copy()
    b = make_test_tile(64, 2)[1::2].copy()
    layers = [Layer(size=5.0, tile=1, rotation=20.0),
              Layer(size=23.0, tile=0, offset=(3.0, 1.0), rotation=-70.0, blend="variance", opacity=0.9),
              Layer(size=120.0, tile=1, rotation=95.0, blend="detail")]
    return {"paper": paper, "mixed": SpectralTexture([a, b], layers)}


@pytest.fixture(scope="module", params=["paper", "mixed"])
def exported(request, tmp_path_factory):
    texture = textures()[request.param]
    return texture, export(texture, tmp_path_factory.mktemp("engines") / "out", formats="godot,hlsl").folder


def library_body() -> str:
    """The layer library's own text (no prelude, no constants)."""
    return shader_file("spectex_layers.glsl")


# ------------------------------------------------------------------------------------ HLSL
def compile_hlsl(tool, include: Path, texture, tmp_path: Path, *defines: str):
    n_tiles = len(texture.tiles)
    decls = "\n".join(f"Texture2D Tile{i};\nSamplerState Tile{i}Sampler;" for i in range(n_tiles))
    args = ", ".join(f"Tile{i}, Tile{i}Sampler" for i in range(n_tiles))
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


@pytest.mark.parametrize("defines", [(), ("UNITY_VERSION=202230",), ("SPECTEX_FLIP_V=1", "SPECTEX_MAX_ANISOTROPY=1.0")])
def test_hlsl_include_compiles_with_glslang(exported, tmp_path, defines):
    tool = glslang()
    texture, folder = exported
    include = folder / "hlsl" / "spectex_ground.hlsl"
    run = compile_hlsl(tool, include, texture, tmp_path, *defines)
    assert run.returncode == 0, run.stdout + run.stderr
    assert (tmp_path / "out.spv").stat().st_size > 1000


def test_hlsl_control_a_broken_include_fails(exported, tmp_path):
    tool = glslang()
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
    assert text.count("spectex_layer(SPX_BLEND_") == len(texture.layers)
    # nothing leaks into the including shader
    tail = text[text.rindex("spectex_layer(SPX_BLEND_"):]
    for name in ("vec2", "vec3", "vec4", "SPX_TEX_ARG", "SPX_TEX", "SPX_LOD"):
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
    tool = glslang()
    _, folder = exported
    text = (folder / "godot" / "spectex_ground.gdshader").read_text()
    assert text.startswith("shader_type spatial;\n")
    path = tmp_path / f"godot.{stage}"
    path.write_text(godot_to_glsl(text, stage))
    run = subprocess.run([tool, str(path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr


def test_godot_control_a_broken_shader_fails(exported, tmp_path):
    tool = glslang()
    _, folder = exported
    text = (folder / "godot" / "spectex_ground.gdshader").read_text().replace("c, p, jx, jy);", "c, p, jx);", 1)
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
    assert shader.count("spectex_layer(SPX_BLEND_") == len(texture.layers)
    script = (folder / "godot" / "spectex_ground.gd").read_text()
    assert script.startswith("@tool\nextends MeshInstance3D\n")
    assert script.count("\t[") == len(texture.layers)
    assert "fposmod" in script and "spectex_anchor" in script
    readme = (folder / "godot" / "README.md").read_text()
    assert "Lossless" in readme and "Fix Alpha Border: off" in readme


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


def draw_ground(gl, texture, camera, size, vert, frag, quad, world_to_spectex, *, setup=None, flip_rows=False):
    """Draw ``quad`` (4 world points, a triangle strip) with the shaders; RGBA uint8, row 0 at the top."""
    import moderngl
    import numpy as np

    from spectex.render.gl import park_framebuffer

    h, w = size
    program = gl.program(vertex_shader=vert, fragment_shader=frag)
    textures = []
    for unit, levels in enumerate(texture.mip_levels()):
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


def ground_psnr(texture, camera, rgba) -> float:
    """PSNR of the drawn pixels against the CPU renderer without haze (anisotropy 8, as the engines' default)."""
    import numpy as np

    from spectex.render import Atmosphere
    from spectex.render.cpu import render_cpu

    drawn = rgba[..., 3] > 0
    assert drawn.mean() > 0.99  # the views look down: the quad fills the picture
    reference = render_cpu(texture, camera, rgba.shape[:2], anisotropy=8.0, atmosphere=Atmosphere(haze_distance=1e9))
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
    matches the CPU renderer (no haze): the ground mapping, the anchors and the blends.
    (Control, run by hand: with spectex y = +Z instead of -Z, 9-32 dB.)"""
    from spectex.render import Camera

    texture, folder = exported
    position, yaw, pitch = camera_args
    camera = Camera(position, yaw=yaw, pitch=pitch, fov=50.0)
    text = (folder / "godot" / "spectex_ground.gdshader").read_text()
    vert = godot_to_glsl(text, "vert").replace(
        "#version 450\n", "#version 450\nuniform mat4 u_view_proj;\n").rstrip()[:-1] + (
        "    gl_Position = u_view_proj * vec4(spectex_world, 1.0);\n}\n")
    frag = godot_to_glsl(text, "frag").replace("spectex_out = vec4(ALBEDO, 1.0);", ENCODE_SRGB)

    def setup(program):
        import numpy as np

        for unit in range(len(texture.tiles)):
            program[f"spectex_tile{unit}"].value = unit
        program["MODEL_MATRIX"].write(np.eye(4, dtype="f4").tobytes())
        if anchored:  # what spectex_ground.gd sets: a point near the camera, snapped, and its anchors
            x0, y0, _ = camera.position
            ax, ay = round(x0 / 256.0) * 256.0, round(y0 / 256.0) * 256.0
            program["spectex_anchored"].value = True
            program["spectex_anchor_point"].value = (ax, ay)
            anchors = [tuple(a[:2]) for a in texture.anchor_coords(ax, ay)]
            program["spectex_anchor"].value = anchors if len(anchors) > 1 else anchors[0]

    x0, y0, _ = camera.position
    r = 4000.0
    quad = [[x0 - r, 0, -(y0 - r)], [x0 + r, 0, -(y0 - r)], [x0 - r, 0, -(y0 + r)], [x0 + r, 0, -(y0 + r)]]
    rgba = draw_ground(gl, texture, camera, (90, 160), vert, frag, quad, GODOT_TO_SPECTEX, setup=setup)
    # measured 53-58 dB on llvmpipe (its dFdx/dFdy are exact for the plane's linear ground point)
    assert ground_psnr(texture, camera, rgba) >= 45.0


def hlsl_to_glsl(text: str) -> str:
    """The HLSL include as GLSL 4.50: GLSL texture macros for its HLSL prelude, HLSL names as macros."""
    from spectex.export.hlsl import _PRELUDE

    assert _PRELUDE in text
    glsl_prelude = """#define SPX_TEX_ARG(name) sampler2D name
#define SPX_TEX(name) name
#if SPECTEX_FLIP_V
#define SPX_LOD(name, uv, lod) textureLod(name, vec2(1.0, -1.0) * (uv), lod)
#else
#define SPX_LOD(name, uv, lod) textureLod(name, uv, lod)
#endif
"""
    text = text.replace(_PRELUDE, glsl_prelude)
    text = re.sub(r"Texture2D (\w+), SamplerState \w+Sampler", r"sampler2D \1", text)
    text = text.replace("static const ", "const ")
    head = ("#version 450\n#define float2 vec2\n#define float3 vec3\n#define float4 vec4\n#define ddx dFdx\n"
            "#define ddy dFdy\n#define lerp mix\n#define saturate(x) clamp(x, 0.0, 1.0)\n")
    return head + text


@pytest.mark.gl
@pytest.mark.parametrize("camera_args, flip", [(VIEWS[0][0], False), (VIEWS[1][0], True), (VIEWS[2][0], False)])
def test_hlsl_entry_point_draws_spectex_ground(exported, gl, camera_args, flip):
    """The exported HLSL include's entry point, its HLSL names mapped to GLSL, on a ground mesh:
    matches the CPU renderer (measured 53-58 dB). ``flip``: Unity's convention (SPECTEX_FLIP_V,
    the tile uploaded bottom row first). (Control, run by hand: the rows in the other order
    than the flip expects, 7-23 dB.)"""
    from spectex.render import Camera

    texture, folder = exported
    position, yaw, pitch = camera_args
    camera = Camera(position, yaw=yaw, pitch=pitch, fov=50.0)
    include = hlsl_to_glsl((folder / "hlsl" / "spectex_ground.hlsl").read_text())
    include = include.replace("#version 450\n", f"#version 450\n#define SPECTEX_FLIP_V {int(flip)}\n")
    tiles = ", ".join(f"Tile{i}" for i in range(len(texture.tiles)))
    samplers = "".join(f"uniform sampler2D Tile{i};\n" for i in range(len(texture.tiles)))
    frag = include + samplers + f"""in vec2 v_ground;
out vec4 spectex_out;
void main() {{
    vec3 c, lin;
    SpectexGround_float(v_ground, {tiles}, c, lin);
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

    def setup(program):
        for unit in range(len(texture.tiles)):
            program[f"Tile{unit}"].value = unit

    x0, y0, _ = camera.position
    r = 4000.0
    quad = [[x0 - r, y0 - r], [x0 + r, y0 - r], [x0 - r, y0 + r], [x0 + r, y0 + r]]
    rgba = draw_ground(gl, texture, camera, (90, 160), vert, frag, quad, GROUND_TO_SPECTEX, setup=setup,
                       flip_rows=flip)
    assert ground_psnr(texture, camera, rgba) >= 45.0


@pytest.mark.parametrize("fmt", ["web", "glsl", "godot", "hlsl"])
def test_non_periodic_layers_are_refused_not_drawn_wrong(tmp_path, fmt):
    texture = textures()["paper"]
    object.__setattr__(texture.layers[1], "tiling", "stochastic")  # as issue 12's layers will carry it
    with pytest.raises(ValueError, match=r"layers\[1\]: tiling 'stochastic' is not in the"):
        export(texture, tmp_path / "out", formats=fmt)
    assert not list(tmp_path.iterdir())
