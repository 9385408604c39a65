"""What the engine exports' shader languages spell differently, and the texture's values in that spelling.

A :class:`Syntax` holds a target's type names and how it writes literals
(MaterialX ShaderGen's ``Syntax`` classes); everything else a shader states is
in the target's template files (``export/templates/``, :mod:`spectex.export._template`).
:func:`bindings` gives the texture's inputs, computed by the rows of
:mod:`spectex.shading.interface` (the renderer's own routes), as literals of a
target, and :func:`layer_calls` each layer's part of a template: its blend
code with the first *enabled* layer's marked as ``pack`` marks it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Syntax", "GODOT", "HLSL", "bindings", "layer_values", "layer_calls"]


@dataclass(frozen=True)
class Syntax:
    """A shader language's spelling of the GLSL types and literals the exports use.

    Attributes
    ----------
    name : str
    types : dict
        GLSL type -> the target's name for it (types not listed are spelt as in GLSL).
    texture_param : str
        A texture parameter of a function named ``{name}`` (the layer library's ``SPX_TEX_ARG``).
    """

    name: str
    types: dict = field(default_factory=dict)
    texture_param: str = "sampler2D {name}"

    def texture_params(self, names) -> str:
        """A function's texture parameters ``names``, comma-separated."""
        return ", ".join(self.texture_param.format(name=name) for name in names)

    def type(self, kind: str) -> str:
        """The target's name of the GLSL type ``kind``."""
        return self.types.get(kind, kind)

    @staticmethod
    def number(value) -> str:
        """A float literal that reads back as the same float64 (renderers round it to their precision)."""
        text = repr(float(value))
        return text if any(ch in text for ch in ".en") else text + ".0"

    def literal(self, kind: str, value) -> str:
        """One value of GLSL type ``kind`` (``float``, ``uint``, ``vecN``, ``uvecN``) as the target writes it."""
        if kind == "float":
            return self.number(value)
        if kind == "uint":
            return f"{int(value)}u"
        values = np.asarray(value).reshape(-1)
        if kind.startswith("uvec"):
            return f"{self.type(kind)}({', '.join(f'{int(v)}u' for v in values)})"
        if kind.startswith("vec"):
            return f"{self.type(kind)}({', '.join(self.number(v) for v in values)})"
        raise ValueError(f"kind must be float, uint, vecN or uvecN, got {kind!r}")

    def array(self, kind: str, values) -> str:
        """A constant array's initialiser: ``{a, b, ...}``."""
        return "{" + ", ".join(self.literal(kind, v) for v in values) + "}"


#: Godot's shading language: GLSL's names.
GODOT = Syntax("godot")
#: HLSL (Unity, Unreal).
HLSL = Syntax("hlsl", {"vec2": "float2", "vec3": "float3", "vec4": "float4", "uvec2": "uint2"},
              texture_param="Texture2D {name}, SamplerState {name}Sampler")


def _key(row) -> str:
    """A row's name in the templates: its GLSL name without the ``u_`` prefix, in capitals."""
    return row.name.split("_", 1)[1].upper()


def bindings(texture, syntax: Syntax) -> dict:
    """The texture's inputs as constants of ``syntax``, one template value per row of the interface table.

    ``{KEY}`` for each row that depends on the texture alone (its name without
    the prefix, in capitals: an array initialiser per layer, else one literal;
    a ``mat3`` per layer as its columns ``{KEY}0`` .. ``{KEY}2``, ``vec3``
    arrays), and ``ORIGIN_{KEY}`` for the per-frame anchors at ground point
    (0, 0), for engines that draw without the host's float64 anchors; and
    ``max_anisotropy``, the renderers' default limit.
    """
    from spectex.shading import interface
    from spectex.shading.constants import DEFAULT_ANISOTROPY

    frame = _origin_frame(texture)
    out = {"max_anisotropy": syntax.number(DEFAULT_ANISOTROPY)}
    for row in interface.inputs("texture"):
        value = row.gl(frame)
        if row.type == "mat3":
            for j in range(3):
                out[f"{_key(row)}{j}"] = syntax.array("vec3", [np.asarray(v)[3 * j:3 * j + 3] for v in value])
        elif row.length:
            out[_key(row)] = syntax.array(row.type, value)
        else:
            out[_key(row)] = syntax.literal(row.type, value)
    for row in interface.inputs("frame"):
        if row.scope == "layer":
            out[f"ORIGIN_{_key(row)}"] = syntax.array(row.type, row.gl(frame))
    return out


def _origin_frame(texture):
    """The interface table's frame of ``texture``'s packed tables, with the anchors of ground point (0, 0)."""
    from spectex.shading import interface
    from spectex.shading.tables import anchor_coords, pack

    tables = pack(texture)
    return interface.GLFrame(tables, len(texture.tiles), anchor=anchor_coords(tables, 0.0, 0.0))


def layer_values(texture) -> list[dict]:
    """Per layer, its values of the interface table's per-layer rows, as numbers (the ``gl`` route).

    ``{KEY: value}`` for each row that depends on the texture alone (``MAT``:
    the world -> tile map ``(m00, m01, m10, m11)``, ``MEAN``, ``OPACITY``,
    ``LOD_OFF``, and the stochastic rows), and ``ORIGIN_{KEY}`` for the
    per-frame rows at ground point (0, 0) (``ORIGIN_ANCHOR``: the tile
    coordinates of the world origin, so that ``(s, t) = ORIGIN_ANCHOR + MAT
    p``): for the exports whose nodes hold the numbers themselves (MaterialX,
    Blender), which draw without a host's per-frame anchors.
    """
    from spectex.shading import interface

    frame = _origin_frame(texture)
    rows = [(_key(row), row.gl(frame)) for row in interface.inputs("texture") if row.scope == "layer"]
    rows += [(f"ORIGIN_{_key(row)}", row.gl(frame)) for row in interface.inputs("frame") if row.scope == "layer"]
    return [{key: values[k] for key, values in rows} for k in range(len(texture.layers))]


def layer_calls(texture) -> list[dict]:
    """Per layer, what a template's ``{{#each layers}}`` block takes: ``k``, ``tile``, ``blend`` (the
    library's code name; ``SPX_BLEND_FIRST`` for the first enabled layer, as ``pack`` decides it) and
    ``stochastic``: the items of the renderer's own ground shader (``shading.glsl.layer_item``)."""
    from spectex.shading.glsl import layer_item
    from spectex.shading.tables import pack

    tables = pack(texture)
    return [layer_item(k, tables.tile[k], tables.tiling[k], tables.blend[k]) for k in range(len(tables.tile))]
