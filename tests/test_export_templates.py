"""The exports' shaders come from template files: no shader statement is held in a Python string in
``export/*.py``; the template language and the targets' ``Syntax``."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

import spectex.export
from spectex._template import each_block
from spectex.export import _template
from spectex.export._syntax import GODOT, HLSL

EXPORT = Path(spectex.export.__file__).resolve().parent

#: A line of shader (or host) code: a declaration or directive, a typed declaration, an assignment or
#: call ending in ';', or a block's opening line.
STATEMENT = re.compile(r"""^\s*(?:
      (?:uniform|varying|static\s+const|const|void|return|\#\s*(?:define|if|ifdef|ifndef|else|endif|undef))\b
    | (?:float[234]?|[iu]?vec[234]|int|uint[234]?|bool|mat[234]|sampler2D|Texture2D)\s+\w+
    | [\w.\[\]]+\s*(?:[-+*/]?=|\().*;\s*(?://.*)?$
    | \w[\w\s,()]*\)\s*\{\s*$
)""", re.X)


def _docstrings(tree) -> set[int]:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                out.add(id(first.value))
    return out


def string_literals(source: str):
    """Every string literal of a module but its docstrings (an f-string with ``X`` for each field)."""
    tree = ast.parse(source)
    skip = _docstrings(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.JoinedStr):
            skip.update(id(v) for v in node.values)
            yield "".join(v.value if isinstance(v, ast.Constant) else "X" for v in node.values)
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in skip:
            yield node.value


def shader_statements(source: str) -> list[str]:
    """The lines of ``source``'s string literals that state code."""
    return [line for text in string_literals(source) for line in text.split("\n") if STATEMENT.match(line)]


def test_no_export_module_holds_a_shader_statement():
    found = {p.name: shader_statements(p.read_text(encoding="utf-8")) for p in sorted(EXPORT.glob("*.py"))}
    assert {name: lines for name, lines in found.items() if lines} == {}


def test_the_shading_generator_holds_no_shader_statement():
    """``shading/glsl.py`` fills the shader templates of ``shading/shaders/`` (the renderer's and every
    export's text) with names and numbers: its prelude, library, switches and layer calls are template text."""
    glsl = EXPORT.parent / "shading" / "glsl.py"
    assert shader_statements(glsl.read_text(encoding="utf-8")) == []
    # control: the f-string that used to write a layer's call is a statement
    assert shader_statements('X = f"        shade_layer({k}, {b}, u_tile[{t}], c, p, jx, jy, lam_w);"')


@pytest.mark.parametrize("source", [
    'LINES = ["    vec2 st = spectex_layer_coords(anchor, m, p);"]',
    'def f(n):\n    return f"const vec4 SPECTEX_MAT[{n}] = {{x}};"',
    'X = "#define SPX_TEX(name) name"',
    'X = """void spectex_layer(int blend) {\n}"""',
    'X = "uniform sampler2D spectex_tile0 : hint_default_white;"',
    'X = "const table = await (await fetch(name)).json();"',
])
def test_control_a_shader_statement_in_a_string_is_found(source):
    assert shader_statements(source)


def test_control_prose_and_docstrings_are_not_statements():
    source = ('"""Module: ``vec2 st = f(p);``\n\nvoid main() {\n"""\n'
              'def f():\n    """Docstring: c = g(x);"""\n'
              '    return "averages its samples per pixel (no mip-maps, no filter);"\n')
    assert shader_statements(source) == []


def test_every_export_template_is_used():
    used = set()
    for p in EXPORT.glob("*.py"):
        used.update(re.findall(r"""["']((?:godot|hlsl|glsl|materialx)/[\w.]+)["']""", p.read_text(encoding="utf-8")))
    files = {p.relative_to(EXPORT / "templates").as_posix() for p in (EXPORT / "templates").rglob("*")
             if p.is_file() and p.parent != EXPORT / "templates"}
    assert files == used


def test_template_language(tmp_path, monkeypatch):
    text = ("{{! a comment of the template\nhead {{a}}\n{{#each items}}\n  item {{k}} of {{a}}\n{{#if odd}}\n"
            "  odd\n{{/if}}\n{{#if not odd}}\n  even\n{{/if}}\n{{/each}}\ntail\n")
    monkeypatch.setattr(_template, "read", lambda name: text)
    out = _template.render("x", {"a": "A", "items": [{"k": 1, "odd": True}, {"k": 2, "odd": False}]})
    assert out == "head A\n  item 1 of A\n  odd\n  item 2 of A\n  even\ntail\n"
    assert each_block(text, "items") == ("  item {{k}} of {{a}}\n{{#if odd}}\n  odd\n{{/if}}\n"
                                         "{{#if not odd}}\n  even\n{{/if}}")
    with pytest.raises(KeyError, match="a"):
        _template.render("x", {"items": []})
    monkeypatch.setattr(_template, "read", lambda name: "{{#if x}}\nno end\n")
    with pytest.raises(ValueError, match="not closed"):
        _template.render("x", {"x": True})


def test_syntax_spells_types_and_literals():
    assert GODOT.literal("vec2", (1, 2.5)) == "vec2(1.0, 2.5)"
    assert HLSL.literal("vec2", (1, 2.5)) == "float2(1.0, 2.5)"
    assert HLSL.literal("uvec2", (3, 4)) == "uint2(3u, 4u)"
    assert GODOT.array("float", [0.1, 2]) == "{0.1, 2.0}"
    assert HLSL.texture_params(["Tile0"]) == "Texture2D Tile0, SamplerState Tile0Sampler"
    assert float(GODOT.number(0.1 + 0.2)) == 0.1 + 0.2  # float64 kept exactly
    with pytest.raises(ValueError, match="kind"):
        GODOT.literal("mat3", [0.0] * 9)


def test_engine_layers_take_the_first_enabled_layer_as_pack_does():
    """The Godot and HLSL calls' blend codes are ``pack``'s (the first enabled layer sets the colour), not
    "layer 0"; a stub that marks layer 0 whatever the flags would fail the second half."""
    from helpers import make_test_tile
    from spectex.export._syntax import layer_calls
    from spectex.shading.glsl import blend_name
    from spectex.shading.tables import pack
    from spectex.texture import SpectralTexture

    texture = SpectralTexture.paper_preset(tile=make_test_tile(32, 0))
    calls = layer_calls(texture)
    assert [c["blend"] for c in calls] == [blend_name(int(b)) for b in pack(texture).blend]
    assert calls[0]["blend"] == "SPX_BLEND_FIRST"
    assert all(c["blend"] != "SPX_BLEND_FIRST" for c in calls[1:])
    off = pack(texture, enabled=[False] + [True] * (len(texture.layers) - 1)).blend
    assert blend_name(int(off[1])) == "SPX_BLEND_FIRST"  # the rule layer_calls takes from pack
