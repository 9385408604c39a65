"""The shader's interface table (``shading/interface.py``): every input named once, and its routes agreeing."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from helpers import make_test_tile
from spectex.render import Camera
from spectex.shading import interface
from spectex.shading.camera import view_params
from spectex.shading.glsl import shader_file
from spectex.shading.tables import anchor_coords, pack
from spectex.texture import SpectralTexture

SRC = Path(interface.__file__).resolve().parents[1]  # src/spectex
HOMES = {"shading/interface.py", "shading/shaders/ground.frag.glsl"}
TEXT = {".py", ".glsl", ".js", ".html", ".in", ".md", ".toml", ".json"}


def files_naming(root: Path, name: str) -> set[str]:
    """The source files under ``root`` whose text holds ``name`` as a word."""
    word = re.compile(rf"\b{re.escape(name)}\b")
    return {p.relative_to(root).as_posix() for p in root.rglob("*")
            if p.is_file() and p.suffix in TEXT and word.search(p.read_text(encoding="utf-8", errors="replace"))}


def misplaced(root: Path) -> dict[str, set[str]]:
    """Per input named outside its row and the shader, the files that name it."""
    out = {}
    for row in interface.INPUTS:
        files = files_naming(root, row.name)
        if files - HOMES or "shading/interface.py" not in files:
            out[row.name] = files
    return out


def test_every_input_is_named_in_its_row_and_the_shader_only():
    assert misplaced(SRC) == {}


def names_in_many_files(root: Path) -> dict[str, set[str]]:
    """Every ``u_*`` word of the sources (a table row's or not) that more than two source files name."""
    files: dict[str, set[str]] = {}
    for p in root.rglob("*"):
        if p.is_file() and p.suffix in TEXT:
            for name in set(re.findall(r"\bu_\w+", p.read_text(encoding="utf-8", errors="replace"))):
                files.setdefault(name, set()).add(p.relative_to(root).as_posix())
    return {name: where for name, where in files.items() if len(where) > 2}


def test_no_shader_input_name_is_written_in_a_third_file():
    """The grep count: every ``u_*`` name, in the table or not (the MaterialX and Blender exports take
    the table's values and name no input), is in at most two source files."""
    assert names_in_many_files(SRC) == {}
    assert all(len(files_naming(SRC, row.name)) == 2 for row in interface.INPUTS)


def test_control_a_name_written_by_hand_elsewhere_is_found(tmp_path):
    root = tmp_path / "spectex"
    shutil.copytree(SRC, root, ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    assert misplaced(root) == {}
    gl = root / "render" / "gl.py"
    gl.write_text(gl.read_text(encoding="utf-8") + f'\n_LEAK = "{interface.MAT.name}"\n', encoding="utf-8")
    assert misplaced(root) == {interface.MAT.name: HOMES | {"render/gl.py"}}
    assert names_in_many_files(root) == {interface.MAT.name: HOMES | {"render/gl.py"}}
    # a name of no row, written in three files, is found as well
    for name in ("export/materialx.py", "export/blender.py", "render/cpu.py"):
        path = root / name
        path.write_text(path.read_text(encoding="utf-8") + '\n_LEAK2 = "u_by_hand"\n', encoding="utf-8")
    assert names_in_many_files(root)["u_by_hand"] == {"export/materialx.py", "export/blender.py", "render/cpu.py"}


def test_the_shader_declares_exactly_the_table(texture):
    from spectex.shading.glsl import fragment_source

    declarations = interface.glsl_declarations()
    source = fragment_source(pack(texture), len(texture.tiles))
    assert source.count(declarations) == 1
    used = set(re.findall(r"\bu_\w+", source.replace(declarations, "")))  # the shader's text and its layer calls
    assert used == {row.name for row in interface.INPUTS}
    assert set(re.findall(r"\bu_\w+", shader_file("ground.frag.glsl"))) == used  # layer calls: the template's
    text = declarations
    assert len(re.findall(r"^uniform ", text, flags=re.M)) == len(interface.INPUTS)
    assert "const " not in text


@pytest.fixture(scope="module")
def texture():
    from dataclasses import replace

    paper = SpectralTexture.paper_preset(tile=make_test_tile(32, 0))
    layers = list(paper.layers)
    layers[1] = replace(layers[1], tiling="stochastic", seed=3)
    return SpectralTexture(paper.tiles, layers)


def test_folded_declarations_hold_the_gl_values_as_float32(texture):
    tables = pack(texture)
    text = interface.glsl_declarations(interface.GLFrame(tables, len(texture.tiles)))
    folded = [row for row in interface.INPUTS if row.fold]
    assert len(re.findall(r"^const ", text, flags=re.M)) == len(folded)
    line = next(x for x in text.splitlines() if f" {interface.OPACITY.name}[" in x)
    numbers = [float(v) for v in re.findall(r"[-\d.e]+(?=[,)])", line.split("=", 1)[1])]
    assert numbers == [float(np.float32(layer.opacity)) for layer in texture.layers]


def _as_float32(value):
    return np.asarray(value, dtype=np.float64).astype(np.float32)


def test_gl_and_host_routes_give_the_same_values(texture, tmp_path):
    """render.gl's values (from ShadingTables and ViewParams) and export.host's (from the exported files
    alone): two routes, one table; they agree in float32 for every input both set."""
    from spectex.export import export
    from spectex.export.host import frame_uniforms, read_table, texture_uniforms

    folder = export(texture, tmp_path / "out", formats="glsl").folder / "glsl"
    table = read_table(folder)
    camera = Camera(position=(1234.5, -987.25, 30.0), yaw=33.0, pitch=-12.0, fov=55.0)
    shape = (48, 80)
    tables = pack(texture, anisotropy=8.0)
    frame = interface.GLFrame(tables, len(texture.tiles), view=view_params(camera, shape), shape=shape,
                              anchor=anchor_coords(texture.layers, *camera.position[:2]))
    gl = interface.gl_values(frame)
    host = {**texture_uniforms(table, len(texture.tiles)), **frame_uniforms(table, camera, shape)}
    assert set(host) == {row.name for row in interface.INPUTS if row.host is not None}
    for name, value in host.items():
        np.testing.assert_array_equal(_as_float32(value), _as_float32(gl[name]), err_msg=name)
    # control: a different camera moves the frame's values apart
    other = frame_uniforms(table, Camera(position=(1234.5, -900.0, 30.0), yaw=33.0, pitch=-12.0, fov=55.0), shape)
    assert not np.array_equal(_as_float32(other[interface.ANCHOR.name]), _as_float32(gl[interface.ANCHOR.name]))


def test_javascript_entries_and_kinds_cover_the_table():
    from spectex.export.web import uniforms_js

    js = uniforms_js()
    assert "/*@" not in js
    for row in interface.INPUTS:
        assert (f"{row.name}:" in js or f"out.{row.name} =" in js) == (row.js is not None), row.name
        assert f"{row.name}: [" in interface.js_kinds()


@pytest.mark.gl
def test_a_folded_input_that_changes_gets_its_own_program(gl, texture):
    """The renderer writes the anisotropy limit into its shader (``fold``): a second limit on the same
    renderer must draw as a fresh renderer does, not with the first limit's program."""
    from spectex.render.gl import GLRenderer

    camera = Camera(position=(0.0, 0.0, 1.5), yaw=0.0, pitch=-8.0, fov=60.0)
    with GLRenderer(texture, gl) as r:
        eight = r.render(camera, (40, 60), anisotropy=8.0)
        two_after = r.render(camera, (40, 60), anisotropy=2.0)
    with GLRenderer(texture, gl) as r:
        two = r.render(camera, (40, 60), anisotropy=2.0)
    assert not np.array_equal(eight, two)  # the limit shows in this view
    np.testing.assert_array_equal(two_after, two)
