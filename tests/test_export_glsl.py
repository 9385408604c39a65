"""The ``glsl`` export: every shader compiles with glslangValidator, and the exported files
alone (shaders, layer table, mip PNGs) draw spectex's picture."""

from __future__ import annotations

import json
import subprocess
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from helpers import glslang_validator, make_test_tile, psnr
from spectex.export import export
from spectex.export._shader import GLSL_TARGETS
from spectex.export.host import draw_glsl_export, texture_uniforms
from spectex.io import read_image
from spectex.render import Camera
from spectex.render.cpu import render_cpu
from spectex.shading.resources import mip_levels, stochastic_store, stochastic_tables
from spectex.texture import Layer, SpectralTexture

SHADER_SUFFIXES = (".vert", ".frag", ".glsl")


def textures():
    paper = SpectralTexture.paper_preset(tile=make_test_tile(64, 0))
    a = make_test_tile(64, 1)[::2].copy()
    b = make_test_tile(64, 2)[1::2].copy()
    layers = [Layer(size=5.0, tile=1, rotation=20.0),
              Layer(size=23.0, tile=0, offset=(3.0, 1.0), rotation=-70.0, blend="variance", opacity=0.9),
              Layer(size=120.0, tile=1, rotation=95.0, blend="detail"),
              Layer(size=470.0, tile=0, offset=(-7.0, 2.0), rotation=-151.0, blend="overlay", opacity=0.8)]
    stochastic = SpectralTexture.paper_preset(tile=make_test_tile(64, 0), tiling="stochastic")
    # layer 1 snapped to 4 x 3 periods of its tile (Layer.snap), layer 2 not
    mixed_stochastic = SpectralTexture([a, b], [layers[0], replace(layers[1], tiling="stochastic", patch=0.3, seed=5,
                                                                   snap=(4, 3)),
                                                replace(layers[2], tiling="stochastic", seed=8)])
    return {"paper": paper, "mixed": SpectralTexture([a, b], layers), "stochastic": stochastic,
            "mixed_stochastic": mixed_stochastic}


@pytest.fixture(scope="module", params=["paper", "mixed", "stochastic", "mixed_stochastic"])
def exported(request, tmp_path_factory):
    texture = textures()[request.param]
    return texture, export(texture, tmp_path_factory.mktemp("glsl") / "out", formats="glsl").folder / "glsl"


def shader_files(folder: Path):
    return sorted(p for p in folder.rglob("*") if p.suffix in SHADER_SUFFIXES)


def test_every_shader_file_compiles_with_glslang(exported):
    tool = glslang_validator()
    _, folder = exported
    files = shader_files(folder)
    names = {p.name for p in files}
    for target in GLSL_TARGETS:
        assert {f"ground.{target}.vert", f"ground.{target}.frag"} <= names
    for path in files:
        stage = {".vert": "vert", ".frag": "frag", ".glsl": "frag"}[path.suffix]
        run = subprocess.run([tool, "-S", stage, str(path)], capture_output=True, text=True)
        assert run.returncode == 0, f"{path.name}:\n{run.stdout}{run.stderr}"
    es = (folder / "ground.es300.frag").read_text()
    assert es.startswith("#version 300 es\nprecision highp float;")
    assert (folder / "ground.330.frag").read_text().startswith("#version 330 core\n")


def test_glslang_control_rejects_a_broken_shader(exported, tmp_path):
    """Control: the compile check can fail (one layer call with a missing argument)."""
    tool = glslang_validator()
    _, folder = exported
    text = (folder / "ground.330.frag").read_text().replace("c, p, jx, jy, lam_w);", "c, p, jx, jy);", 1)
    (tmp_path / "broken.frag").write_text(text)
    run = subprocess.run([tool, str(tmp_path / "broken.frag")], capture_output=True, text=True)
    assert run.returncode != 0


def test_mip_pngs_are_the_levels_spectex_samples(exported):
    texture, folder = exported
    table = json.loads((folder / "spectex_texture.json").read_text())
    assert len(table["layers"]) == len(texture.layers)
    names = ["tile"] if len(texture.tiles) == 1 else [f"tile{i}" for i in range(len(texture.tiles))]
    for name, levels in zip(names, mip_levels(texture)):
        for d, level in enumerate(levels):
            np.testing.assert_array_equal(read_image(folder / "mips" / f"{name}.level{d}.png"), level)
        np.testing.assert_array_equal(read_image(folder / f"{name}.png"), levels[0])


def test_stochastic_table_files_are_the_renderers_arrays(exported):
    """The raw half-float files hold, bit for bit, the Gaussianised levels and the table texture
    render.gl uploads (and nothing is written for a texture without stochastic layers)."""
    from spectex.export._stochastic import read_raw

    texture, folder = exported
    table = json.loads((folder / "spectex_texture.json").read_text())
    if not any(layer.tiling == "stochastic" for layer in texture.layers):
        assert table["stochastic"] is None and not list(folder.glob("*16f"))
        return
    names = ["gauss.rgba16f"] if len(texture.tiles) == 1 else [f"gauss{i}.rgba16f" for i in range(len(texture.tiles))]
    for name, tables in zip(names, stochastic_tables(texture)):
        levels = read_raw(folder / name, [lv.shape[:2] for lv in tables.gaussian], 4)
        for got, want in zip(levels, tables.gaussian):
            np.testing.assert_array_equal(got, want)
    _, lut, _ = stochastic_store(texture)
    planar = read_raw(folder / "spectex_lut.r16f", [(4 * lut.shape[0], lut.shape[1])], 1)[0][:, :, 0]
    np.testing.assert_array_equal(planar, np.concatenate([lut[:, :, c] for c in range(4)]))
    assert table["stochastic"]["level_shapes"] == [list(lv.shape[:2]) for lv in stochastic_tables(texture)[0].gaussian]


@pytest.mark.gl
@pytest.mark.parametrize("camera, anisotropy", [
    (Camera((0.0, 0.0, 2.0), yaw=0.0, pitch=-10.0), 1.0),
    (Camera((4.0e6, 1.0e6, 12.0), yaw=230.0, pitch=-3.0), 8.0),
    (Camera((-50.0, 70.0, 400.0), yaw=80.0, pitch=-45.0, fov=40.0), 4.0),
])
def test_exported_files_alone_draw_spectex_picture(exported, gl, camera, anisotropy):
    """OpenGL 3.3 (llvmpipe) with only what the export holds, vs the CPU renderer: >= 40 dB."""
    texture, folder = exported
    h, w = 120, 200
    image = draw_exported(gl, texture, folder, camera, anisotropy, (h, w))
    reference = render_cpu(texture, camera, (h, w), anisotropy=anisotropy)
    assert psnr(image, reference) >= 40.0  # measured 53.5-58.3 dB
    # control: the picture has texture in it (not a flat colour)
    assert image[h // 2:].std() > 0.02


@pytest.mark.gl
def test_stochastic_controls_fail(gl):
    """Controls for the stochastic layers' uniforms 4000 km out: without the grid vertex (u_gbase
    zero: the anchor reduced as the tile coordinates are) or with other hash keys, the exported
    shader's picture is far from spectex's."""
    texture = textures()["mixed_stochastic"]
    with tempfile.TemporaryDirectory() as tmp:
        folder = export(texture, Path(tmp) / "out", formats="glsl").folder / "glsl"
        camera = Camera((4.0e6, 1.0e6, 12.0), yaw=230.0, pitch=-3.0)
        reference = render_cpu(texture, camera, (120, 200), anisotropy=8.0)
        right = draw_exported(gl, texture, folder, camera, 8.0, (120, 200))
        assert psnr(right, reference) >= 40.0
        table = json.loads((folder / "spectex_texture.json").read_text())
        n = len(table["layers"])
        for override in ({"u_gbase": [(0, 0)] * n},
                         {"u_key": [(v + 1) % 2 ** 32 for v in texture_uniforms(table, len(texture.tiles))["u_key"]]}):
            wrong = draw_exported(gl, texture, folder, camera, 8.0, (120, 200), override)
            assert psnr(wrong, reference) < 30.0


def draw_exported(gl, texture, folder, camera, anisotropy, size, override=None):
    """Draw ground.330.* with the exported files alone (``spectex.export.host``: uniforms as the
    README says; ``override`` replaces some); (h, w, 3) in [0, 1], row 0 at the top."""
    assert len(texture.tiles) == len(list(folder.joinpath("mips").glob("*.level0.png")))
    return draw_glsl_export(folder, camera, size, ctx=gl, anisotropy=anisotropy, override=override)


def test_readme_names_three_js_settings(exported):
    _, folder = exported
    text = (folder / "README.md").read_text()
    for word in ("RawShaderMaterial", "THREE.GLSL3", "RepeatWrapping", "LinearMipmapLinearFilter",
                 "premultiplyAlpha = false", "NoColorSpace", "flipY = false"):
        assert word in text, word


def test_host_refuses_what_is_not_a_glsl_export(tmp_path):
    """draw_glsl_export: a folder without the layer table, or a bad shape, is one ValueError naming it."""
    camera = Camera((0.0, 0.0, 2.0))
    with pytest.raises(ValueError, match="folder must be the glsl/ folder of a spectex export"):
        draw_glsl_export(tmp_path, camera, (10, 10))
    (tmp_path / "spectex_texture.json").write_text("{not json", encoding="utf-8")
    with pytest.raises(ValueError, match="folder must be the glsl/ folder"):
        draw_glsl_export(tmp_path, camera, (10, 10))
    with pytest.raises(ValueError, match="shape"):
        draw_glsl_export(tmp_path, camera, (0, 10))
