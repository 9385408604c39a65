"""The shading core: one table of constants, generated GLSL, the layering rule,
block bakes."""

import ast
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

import spectex
from helpers import glslang_validator
from spectex.render import bake
from spectex.shading import constants as C
from spectex.shading import glsl, pack
from spectex.texture import SpectralTexture
from spectex.tiles import make_tile

SRC = Path(spectex.__file__).parent


def _imports(path: Path) -> set[str]:
    """Absolute names of the spectex modules ``path`` imports (relative imports resolved)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = ".".join(("spectex",) + path.relative_to(SRC).with_suffix("").parts[:-1])
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            out.add(name)
        elif isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names)
    return {n for n in out if n.startswith("spectex")}


def test_nothing_in_the_shading_core_imports_anything_above_it():
    above = ("spectex.texture", "spectex.texture_file", "spectex.render", "spectex.cli", "spectex.analysis",
             "spectex.synthesis", "spectex.io", "spectex.metrics")
    found = {}
    for path in sorted((SRC / "shading").glob("*.py")):
        bad = sorted(n for n in _imports(path) if n.startswith(above))
        if bad:
            found[path.name] = bad
    assert not found, found


def test_the_import_checker_sees_an_upward_import():
    # the control: render/cpu.py does import from above the core (texture)
    assert "spectex.texture" in _imports(SRC / "render" / "cpu.py")


def test_glsl_defines_hold_every_code_of_the_table():
    text = C.glsl_defines()
    for i, name in enumerate(C.BLENDS):
        assert f"#define SPX_BLEND_{name.upper()} {i}\n" in text
    assert f"#define SPX_BLEND_FIRST {C.BLEND_FIRST}\n" in text
    for i, name in enumerate(C.TILINGS):
        assert f"#define SPX_TILING_{name.upper()} {i}\n" in text
    assert "#define SPX_SKY_FALLOFF 4.0\n" in text and "#define SPX_FAR_HAZE_RATIO 50.0\n" in text


def test_the_shader_sources_hold_no_literal_codes_or_constants():
    """The GLSL refers to the table by name only: no ``blend == 0`` and no
    sky falloff or far ratio written as a number."""
    for name in ("spectex_layers.glsl", "ground.frag.glsl"):
        text = glsl.shader_file(name)
        code = "\n".join(line.split("//")[0] for line in text.splitlines())
        assert not re.search(r"blend\s*==\s*-?\d", code), name
        assert not re.search(r"exp\(\s*-\s*4\.0", code), name
        assert "50.0" not in code, name


def test_fragment_source_unrolls_the_drawn_layers_with_their_codes():
    tex = SpectralTexture.paper_preset(make_tile(16, rng=1), blend="variance")
    tables = pack(tex, enabled=[False, True, True, False, True, True])
    src = glsl.fragment_source(tables, 1)
    calls = re.findall(r"shade_layer\((\d), (\w+), u_tile\[0\]", src)
    assert calls == [("1", "SPX_BLEND_FIRST"), ("2", "SPX_BLEND_VARIANCE"), ("4", "SPX_BLEND_VARIANCE"),
                     ("5", "SPX_BLEND_FINE")]
    assert src.startswith("#version 330 core\n")
    assert glsl.fragment_source(tables, 1, target="es300").startswith("#version 300 es\nprecision highp float;")
    with pytest.raises(ValueError, match="target.*es100"):
        glsl.fragment_source(tables, 1, target="es100")


@pytest.mark.parametrize("target", glsl.TARGETS)
@pytest.mark.parametrize("anisotropic", [False, True])
def test_generated_shaders_compile_with_glslang(tmp_path, target, anisotropic):
    exe = glslang_validator()
    tex = SpectralTexture(make_tile(16, rng=1), [dict(size=3.0), dict(size=17.0, blend="detail"),
                                                  dict(size=40.0, tiling="stochastic", seed=3)])
    tables = pack(tex, anisotropy=4.0 if anisotropic else 1.0)
    assert "shade_layer_stochastic(2, SPX_BLEND_ALPHA, u_gauss[0], u_lut" in glsl.fragment_source(tables, 1)
    for name, text in (("ground.frag", glsl.fragment_source(tables, 1, target=target, anisotropic=anisotropic,
                                                            iso_lod=not anisotropic)),
                       ("sky.frag", glsl.fragment_source(tables, 1, target=target, sky_only=True)),
                       ("full.vert", glsl.vertex_source(target))):
        path = tmp_path / name
        path.write_text(text)
        proc = subprocess.run([exe, str(path)], capture_output=True, text=True)
        assert proc.returncode == 0, proc.stdout + proc.stderr
    broken = tmp_path / "broken.frag"  # the control: the validator does reject a bad shader
    good = glsl.fragment_source(tables, 1, target=target)
    text = good.replace("return spectex_blend(", "return spectex_blnd(")  # in the library's layer step
    assert text != good
    broken.write_text(text)
    assert subprocess.run([exe, str(broken)], capture_output=True, text=True).returncode != 0


def test_block_bakes_have_the_bits_of_the_whole_bake():
    tex = SpectralTexture.paper_preset(make_tile(32, rng=2))
    kw = dict(origin=(1234.5, -987.25), pixel_size=0.37)
    whole = bake(tex, (40, 56), **kw)
    for r0, c0, h, w in ((0, 0, 16, 16), (16, 24, 24, 32), (33, 7, 7, 49)):
        block = bake(tex, (h, w), start=(r0, c0), **kw)
        np.testing.assert_array_equal(block, whole[r0:r0 + h, c0:c0 + w])
    assert not np.array_equal(whole[16:40, 24:56], whole[:24, :32])  # the blocks differ from each other
    with pytest.raises(ValueError, match="start"):
        bake(tex, (4, 4), start=(-1, 0))


def test_view_params_and_tables_are_what_both_renderers_read():
    from spectex.render import Camera
    from spectex.shading import view_params

    cam = Camera((10.0, 20.0, 3.0), yaw=30.0, pitch=-20.0, fov=50.0)
    view = view_params(cam, (90, 160), supersample=2)
    ddx, ddy = cam.ray_steps(90, 160)
    np.testing.assert_array_equal(view.ddx, ddx)
    np.testing.assert_array_equal(view.ddy, ddy)
    assert view.height == 3.0 and view.supersample == 2 and view.far == 50.0 * view.haze_distance
    tex = SpectralTexture.paper_preset(make_tile(16, rng=1))
    tables = pack(tex)
    np.testing.assert_allclose(tables.lod_off, [np.log2(16 / layer.size) for layer in tex.layers], rtol=1e-15)
    with pytest.raises(TypeError, match="camera"):
        view_params("north", (9, 16))


def test_layer_library_without_uint_leaves_out_only_the_stochastic_functions(tmp_path):
    # a prelude that defines no SPX_UINT (an export target without unsigned ints) still gets a
    # library that compiles, without the section 6b functions; with it, they are there
    exe = glslang_validator()
    lib = glsl.layer_library()
    prelude = glsl.prelude("330").replace("#define SPX_UINT uint\n", "")
    assert "#define SPX_UINT" not in prelude and "#ifdef SPX_UINT" in lib
    for head, has in ((prelude, False), (glsl.prelude("330"), True)):
        text = head + lib + "out vec4 o;\nvoid main() { o = vec4(spectex_sky(0.5, vec3(0.1), vec3(0.9)), 1.0); }\n"
        if has:
            text = text.replace("void main() {", "void main() { o.x = spectex_vertex_offset(1u, 2u, 3u, vec2(8.0), "
                                                  "vec2(0.125), vec2(8.0)).x;")
        path = tmp_path / f"lib{int(has)}.frag"
        path.write_text(text)
        proc = subprocess.run([exe, str(path)], capture_output=True, text=True)
        assert proc.returncode == 0, proc.stdout + proc.stderr
