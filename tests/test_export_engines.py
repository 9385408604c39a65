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
