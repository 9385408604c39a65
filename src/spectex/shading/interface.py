"""The ground shader's inputs: one table, from which every binding is generated.

Each input of the ground shader (``shaders/ground.frag.glsl``) is one
:class:`Input` row of :data:`INPUTS`: its GLSL name and type, whether it is
one value or an array per layer or per tile, whether only stochastic layers
need it, when it changes (:data:`RATES`), and how it is computed, once per
route that computes it:

* ``gl``: from the shading core's own structures (:class:`GLFrame`: the
  :class:`~spectex.shading.tables.ShadingTables` of ``pack``, the camera's
  :class:`~spectex.shading.camera.ViewParams`, the anchors), for
  ``render.gl``, and for the constants the renderer writes into its shader;
* ``host``: from an export's layer table alone (:class:`HostFrame`), for
  ``export.host`` (what a program that reads only the exported files does);
* ``js``: the same as a JavaScript expression, for the web viewer and the
  ``glsl`` export (``export/templates/uniforms.js``).

Generated from it: the shader's declarations (:func:`glsl_declarations`,
as uniforms or, for the renderer, as constants), the GL uploads
(``render.gl``), the JavaScript uniform functions and setter kinds
(:func:`js_texture_entries`, :func:`js_kinds`, ...), the Python host, the
Godot and HLSL exports' constants (``export._syntax.bindings``, the ``gl``
route's values in the target's literals), MaterialX's per-layer values, and
the names the exports' READMEs cite. A program that needs one input by
name uses its row (``interface.TILE.name``), never the string: renaming an
input is a change to its row and to the shader text, nothing else (the
test ``test_interface`` counts this). The model is pygfx's binding objects,
declared once and used for both the shader text and the uploads.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .constants import ANCHOR_PERIOD, FAR_HAZE_RATIO

__all__ = ["Input", "INPUTS", "RATES", "SCOPES", "GLFrame", "HostFrame", "glsl_literal", "glsl_declarations",
           "inputs", "js_texture_entries", "js_frame_entries", "js_unit_entries", "js_sampler_entries", "js_kinds",
           "host_values", "gl_values"]

#: When an input changes: ``unit`` (a texture unit, fixed by the texture's tile count), ``texture`` (the
#: texture alone), ``sampler`` (the filter settings), ``frame`` (the camera and the picture).
RATES = ("unit", "texture", "sampler", "frame")
#: ``global``: one value; ``layer``: an array of ``N_LAYERS``; ``tile``: an array of ``N_TILES``.
SCOPES = ("global", "layer", "tile")
_LENGTH = {"global": None, "layer": "N_LAYERS", "tile": "N_TILES"}


@dataclass(frozen=True)
class Input:
    """One input of the ground shader.

    Attributes
    ----------
    name : str
        Its GLSL name.
    type : str
        GLSL type of one element (``float``, ``vec2`` .. ``vec4``, ``uint``,
        ``uvec2``, ``mat3``, ``sampler2D``).
    scope : str
        One of :data:`SCOPES`.
    rate : str
        One of :data:`RATES`.
    doc : str
        One line: what it holds (the declaration's comment).
    gl : callable
        ``gl(GLFrame) -> value`` as moderngl takes it (a list per element
        for an array; a ``mat3`` column after column).
    host : callable or None
        ``host(HostFrame) -> value``, from an export's layer table; None
        where a host leaves the shader's default (0).
    js : str or None
        The same as a JavaScript expression over the names that
        ``templates/uniforms.js`` defines; None where the viewer leaves the
        default.
    stochastic : bool
        Only stochastic layers need it (declared under ``#if STOCHASTIC``).
    fold : bool
        The renderer may write it into its shader as a constant
        (``fragment_source(constants=True)``): it does not change between
        the draws of one program.
    """

    name: str
    type: str
    scope: str
    rate: str
    doc: str
    gl: Callable[[Any], Any]
    host: Callable[[Any], Any] | None = None
    js: str | None = None
    stochastic: bool = False
    fold: bool = False

    @property
    def length(self) -> str | None:
        """The array length's macro (``N_LAYERS``, ``N_TILES``) or None for one value."""
        return _LENGTH[self.scope]


@dataclass(frozen=True)
class GLFrame:
    """What ``render.gl`` computes the inputs from (the frame's fields are None for the texture's inputs)."""

    tables: Any                   #: ``shading.tables.ShadingTables``
    n_tiles: int
    view: Any = None              #: ``shading.camera.ViewParams``
    anchor: Any = None            #: (L, 6) ``tables.anchor_coords`` of the camera's ground point
    shape: tuple | None = None    #: (H, W) of the frame drawn
    fade_bias: float = 0.0        #: log2 of the supersampling factor


@dataclass(frozen=True)
class HostFrame:
    """What ``export.host`` computes the inputs from: the exported layer table and, per frame, the camera
    basis and anchors it computes in float64 (the fields of the frame are None for the texture's inputs)."""

    table: dict                   #: ``spectex_texture.json``
    n_tiles: int
    anisotropy: float = 8.0
    shape: tuple | None = None    #: (H, W)
    z: float | None = None        #: camera altitude
    fwd: Any = None               #: (3,) float64
    right: Any = None
    up: Any = None
    tan_x: float | None = None
    tan_y: float | None = None
    anchor: list | None = None    #: per layer (s, t) mod ANCHOR_PERIOD
    ganchor: list | None = None   #: per layer, the grid position's fraction
    gbase: list | None = None     #: per layer, its grid vertex mod 2^32


def _floats(values) -> tuple:
    return tuple(float(v) for v in np.asarray(values).reshape(-1))


def _field(name: str, convert=None, zero=None):
    """A host route: per layer, its entry ``name`` of the exported table, converted; with ``zero``, a
    stochastic layer's entry and ``zero`` for a periodic layer."""
    def get(h: HostFrame) -> list:
        out = []
        for layer in h.table["layers"]:
            value = layer[name] if zero is None or layer["tiling"] == "stochastic" else zero
            out.append(value if convert is None else convert(value))
        return out
    return get


def _snap(h: HostFrame) -> list:
    """Per layer, its snap counts from the exported table; a periodic layer's (unused) are the tile's width,
    height, as ``pack`` gives them."""
    th, tw = h.table["tile_shape"]
    return [tuple(layer["snap"]) if layer["tiling"] == "stochastic" else (float(tw), float(th))
            for layer in h.table["layers"]]


def _column_major(basis) -> tuple:
    """A row-major 3 x 3 (9 numbers) as GLSL's ``mat3`` takes it: column after column."""
    return tuple(np.reshape(basis, (3, 3)).T.reshape(-1))


_JS_PICK = "L.map((l) => pick(l, {0!r}, {1}))"

# ---------------------------------------------------------------- the table, in the shader's order
SIZE = Input("u_size", "vec2", "global", "frame", "framebuffer width, height in pixels",
             gl=lambda g: (float(g.shape[1]), float(g.shape[0])),
             host=lambda h: (h.shape[1], h.shape[0]), js="[width, height]")
HEIGHT = Input("u_height", "float", "global", "frame", "camera altitude (z > 0)",
               gl=lambda g: g.view.height, host=lambda h: h.z, js="z")
FWD = Input("u_fwd", "vec3", "global", "frame", "camera basis, world coordinates",
            gl=lambda g: _floats(g.view.fwd), host=lambda h: tuple(h.fwd), js="fwd")
RIGHT = Input("u_right", "vec3", "global", "frame", "",
              gl=lambda g: _floats(g.view.right), host=lambda h: tuple(h.right), js="right")
UP = Input("u_up", "vec3", "global", "frame", "",
           gl=lambda g: _floats(g.view.up), host=lambda h: tuple(h.up), js="up")
TAN = Input("u_tan", "vec2", "global", "frame", "tan_x, tan_y: half-extents of the image plane at distance 1",
            gl=lambda g: (g.view.tan_x, g.view.tan_y), host=lambda h: (h.tan_x, h.tan_y), js="[tanX, tanY]")
DDX = Input("u_ddx", "vec3", "global", "frame",
            "d(ray)/d(pixel x) = right 2 tan_x / width (on the host: llvmpipe evaluates uniform math per pixel)",
            gl=lambda g: _floats(g.view.ddx), host=lambda h: tuple(h.right * 2 * h.tan_x / h.shape[1]),
            js="right.map((c) => c * 2 * tanX / width)")
DDY = Input("u_ddy", "vec3", "global", "frame", "d(ray)/d(pixel y) = -up 2 tan_y / height (row 0 at the top)",
            gl=lambda g: _floats(g.view.ddy), host=lambda h: tuple(-h.up * 2 * h.tan_y / h.shape[0]),
            js="up.map((c) => -c * 2 * tanY / height)")
HORIZON = Input("u_horizon", "vec3", "global", "frame", "sky colour at the horizon (and the haze's)",
                gl=lambda g: _floats(g.view.horizon), host=lambda h: tuple(h.table["atmosphere"]["horizon"]),
                js="texture.atmosphere.horizon")
ZENITH = Input("u_zenith", "vec3", "global", "frame", "sky colour at the zenith",
               gl=lambda g: _floats(g.view.zenith), host=lambda h: tuple(h.table["atmosphere"]["zenith"]),
               js="texture.atmosphere.zenith")
HAZE = Input("u_haze", "float", "global", "frame", "haze distance (m)",
             gl=lambda g: g.view.haze_distance, host=lambda h: h.table["atmosphere"]["haze_distance"], js="haze")
FAR = Input("u_far", "float", "global", "frame", "beyond this distance: horizon colour, no texture",
            gl=lambda g: g.view.far, host=lambda h: FAR_HAZE_RATIO * h.table["atmosphere"]["haze_distance"],
            js=f"{FAR_HAZE_RATIO!r} * haze")
FADE_BIAS = Input("u_fade_bias", "float", "global", "frame",
                  "log2 of the supersampling factor (0 unless supersampled): the fine blend fades by the pixel's "
                  "footprint, not the sample's", gl=lambda g: float(g.fade_bias))
TILE = Input("u_tile", "sampler2D", "tile", "unit", "per tile: its mip levels (unit i)",
             gl=lambda g: list(range(g.n_tiles)), host=lambda h: list(range(h.n_tiles)),
             js="[...Array(nTiles).keys()]")
TEX_SIZE = Input("u_tex_size", "vec2", "global", "texture", "level-0 width, height in texels",
                 gl=lambda g: (float(g.tables.widths[0]), float(g.tables.heights[0])),
                 host=lambda h: tuple(h.table["tile_shape"][::-1]),
                 js="[texture.tile_shape[1], texture.tile_shape[0]]", fold=True)
MAX_ANISO = Input("u_max_aniso", "float", "global", "sampler", "1: isotropic; else at most this many samples",
                  gl=lambda g: g.tables.max_aniso, host=lambda h: float(h.anisotropy), js="maxAniso", fold=True)
ANCHOR = Input("u_anchor", "vec2", "layer", "frame",
               f"per layer: tile coords of the camera's ground point, mod {ANCHOR_PERIOD:g}",
               gl=lambda g: [(float(a[0]), float(a[1])) for a in g.anchor], host=lambda h: h.anchor, js="anchor")
MAT = Input("u_mat", "vec4", "layer", "texture", "per layer: (m00, m01, m10, m11), world -> tile coords",
            gl=lambda g: [_floats(m) for m in g.tables.mats], host=_field("matrix", tuple),
            js="[].concat(...L.map((l) => l.matrix))", fold=True)
MEAN = Input("u_mean", "vec3", "layer", "texture", "per layer: its tile's mean colour (1 x 1 level)",
             gl=lambda g: [_floats(mu) for mu in g.tables.mean], host=_field("mean", tuple),
             js="[].concat(...L.map((l) => l.mean))", fold=True)
OPACITY = Input("u_opacity", "float", "layer", "texture", "per layer: alpha = opacity * tile alpha",
                gl=lambda g: [float(v) for v in g.tables.opacity], host=_field("opacity"),
                js="L.map((l) => l.opacity)", fold=True)
LOD_OFF = Input("u_lod_off", "float", "layer", "texture", "per layer: log2(tile width / layer size), texels per metre",
                gl=lambda g: [float(v) for v in g.tables.lod_off],
                host=_field("lod_offset"), js="L.map((l) => l.lod_offset)", fold=True)
GAUSS = Input("u_gauss", "sampler2D", "tile", "unit", "per tile: its Gaussianised levels (half-float values)",
              gl=lambda g: list(range(g.n_tiles, 2 * g.n_tiles)),
              host=lambda h: [h.n_tiles + i for i in range(h.n_tiles)],
              js="[...Array(nTiles).keys()].map((i) => nTiles + i)", stochastic=True)
LUT = Input("u_lut", "sampler2D", "global", "unit",
            "the inverse tables, SPX_LUT_SIZE x 4 rows (one channel, NEAREST)",
            gl=lambda g: 2 * g.n_tiles, host=lambda h: 2 * h.n_tiles, js="2 * nTiles", stochastic=True)
LUT_ROWS = Input("u_lut_rows", "float", "global", "texture", "rows of the table texture per channel",
                 gl=lambda g: float(g.tables.lut.shape[0]), host=lambda h: float(h.table["stochastic"]["lut_rows"]),
                 js="texture.stochastic.lut_rows", stochastic=True, fold=True)
LUT_Q = Input("u_lut_q", "float", "global", "texture", "the last mip level (rows per tile - 1 with mip-maps, else 0)",
              gl=lambda g: float(len(g.tables.widths) - 1), host=lambda h: float(h.table["stochastic"]["lut_q"]),
              js="texture.stochastic.lut_q", stochastic=True, fold=True)
GRID = Input("u_grid", "vec4", "layer", "texture", "per layer: tile coords -> skewed grid coords (m00, m01, m10, m11)",
             gl=lambda g: [_floats(m) for m in g.tables.grid],
             host=_field("grid", tuple, [0.0] * 4),
             js="[].concat(..." + _JS_PICK.format("grid", "[0, 0, 0, 0]") + ")", stochastic=True, fold=True)
GANCHOR = Input("u_ganchor", "vec2", "layer", "frame", "per layer: the anchor's grid position minus its vertex",
                gl=lambda g: [(float(a[2]), float(a[3])) for a in g.anchor], host=lambda h: h.ganchor, js="ganchor",
                stochastic=True)
GBASE = Input("u_gbase", "uvec2", "layer", "frame", "per layer: that grid vertex, mod 2^32",
              gl=lambda g: [(int(a[4]), int(a[5])) for a in g.anchor], host=lambda h: h.gbase, js="gbase",
              stochastic=True)
KEY = Input("u_key", "uint", "layer", "texture", "per layer: the hash key of its seed",
            gl=lambda g: [int(v) for v in g.tables.key], host=_field("key", zero=0),
            js=_JS_PICK.format("key", "0"), stochastic=True, fold=True)
SNAP = Input("u_snap", "vec2", "layer", "texture",
             "per layer: its snap counts along s, t, whole numbers (stochastic.snap_counts; the tile's width, height "
             "for a periodic layer, unused)",
             gl=lambda g: [_floats(s) for s in g.tables.snap], host=lambda h: _snap(h),
             js="[].concat(...L.map((l) => pick(l, 'snap', [texture.tile_shape[1], texture.tile_shape[0]])))",
             stochastic=True, fold=True)
CELL_ROW = Input("u_cell_row", "float", "layer", "texture",
                 "per layer: first row of its tile's cell map in the tables (resources.cell_rows), -1: none",
                 gl=lambda g: [float(v) for v in g.tables.cell_row], host=_field("cell_row", float, -1.0),
                 js=_JS_PICK.format("cell_row", "-1"), stochastic=True, fold=True)
LUT_ROW = Input("u_lut_row", "float", "layer", "texture", "per layer: first table row of its tile",
                gl=lambda g: [float(t * g.tables.lut_rows) for t in g.tables.tile],
                host=_field("lut_row", float, 0),
                js=_JS_PICK.format("lut_row", "0"), stochastic=True, fold=True)
BASIS = Input("u_basis", "mat3", "layer", "texture",
              "per layer: its tile's decorrelation, RGB = origin + basis v (column-major)",
              gl=lambda g: [_floats(b.T) for b in g.tables.basis],
              host=_field("basis", _column_major, [0.0] * 9),
              js="[].concat(...L.map((l) => { const b = pick(l, 'basis', [0, 0, 0, 0, 0, 0, 0, 0, 0]); "
                 "return [b[0], b[3], b[6], b[1], b[4], b[7], b[2], b[5], b[8]]; }))",
              stochastic=True, fold=True)
ORIGIN = Input("u_origin", "vec3", "layer", "texture", "per layer: its tile's decorrelation origin",
               gl=lambda g: [_floats(o) for o in g.tables.origin],
               host=_field("origin", tuple, [0.0] * 3),
               js="[].concat(..." + _JS_PICK.format("origin", "[0, 0, 0]") + ")", stochastic=True, fold=True)

#: Every input of the ground shader, in the order of its declarations.
INPUTS = (SIZE, HEIGHT, FWD, RIGHT, UP, TAN, DDX, DDY, HORIZON, ZENITH, HAZE, FAR, FADE_BIAS, TILE, TEX_SIZE,
          MAX_ANISO, ANCHOR, MAT, MEAN, OPACITY, LOD_OFF, GAUSS, LUT, LUT_ROWS, LUT_Q, GRID, GANCHOR, GBASE, KEY,
          SNAP, CELL_ROW, LUT_ROW, BASIS, ORIGIN)


def inputs(*rates: str, stochastic: bool | None = None) -> tuple[Input, ...]:
    """The rows of these rates (all without ``rates``), only the stochastic ones or only the others."""
    for rate in rates:
        if rate not in RATES:
            raise ValueError(f"rates must be among {', '.join(RATES)}, got {rate!r}")
    return tuple(i for i in INPUTS if (not rates or i.rate in rates)
                 and (stochastic is None or i.stochastic == stochastic))


# ------------------------------------------------------------------------------ GLSL
def _float(value) -> str:
    """A float32 value as a GLSL literal that parses back to exactly that float32."""
    v = float(np.float32(value))
    if not math.isfinite(v):
        raise ValueError(f"a shader constant must be finite, got {v!r}")
    return repr(v)


def glsl_literal(kind: str, value) -> str:
    """One element's value (as :attr:`Input.gl` gives it) as a GLSL constant expression of type ``kind``."""
    if kind == "float":
        return _float(value)
    if kind == "uint":
        return f"{int(value) & 0xFFFFFFFF}u"
    if kind in ("vec2", "vec3", "vec4", "mat3"):
        return f"{kind}({', '.join(_float(v) for v in np.asarray(value, dtype=np.float64).reshape(-1))})"
    raise ValueError(f"kind must be a GLSL type with constant literals, got {kind!r}")


def _declaration(row: Input, frame: GLFrame | None) -> str:
    size = f"[{row.length}]" if row.length else ""
    if frame is not None and row.fold:
        value = row.gl(frame)
        if row.length:
            text = f"{row.type}[]({', '.join(glsl_literal(row.type, v) for v in value)})"
        else:
            text = glsl_literal(row.type, value)
        head = f"const {row.type} {row.name}{size} = {text};"
    else:
        head = f"uniform {row.type} {row.name}{size};"
    return f"{head}  // {row.doc}" if row.doc else head


def glsl_declarations(frame: GLFrame | None = None) -> str:
    """The ground shader's declarations of :data:`INPUTS` (the stochastic ones under ``#if STOCHASTIC``).

    With ``frame`` (the texture's tables), the rows that may be folded are
    written as constants of their float32 values instead of uniforms.
    """
    lines = ["// The shader's inputs: generated from spectex/shading/interface.py, do not edit."]
    lines += [_declaration(row, frame) for row in inputs(stochastic=False)]
    lines += ["#if STOCHASTIC", *(_declaration(row, frame) for row in inputs(stochastic=True)), "#endif"]
    return "\n".join(lines) + "\n"


def gl_values(frame: GLFrame, *rates: str, stochastic: bool = True) -> dict:
    """``{name: value}`` of the rows of ``rates`` (all without), without the stochastic ones unless ``stochastic``."""
    return {row.name: row.gl(frame) for row in inputs(*rates) if stochastic or not row.stochastic}


def host_values(frame: HostFrame, *rates: str, stochastic: bool = True) -> dict:
    """As :func:`gl_values`, from an export's layer table (rows without a host value left out)."""
    return {row.name: row.host(frame) for row in inputs(*rates)
            if row.host is not None and (stochastic or not row.stochastic)}


# ------------------------------------------------------------------------------ JavaScript
def _js_entries(rows, indent: str, assign: bool) -> str:
    out = []
    for row in rows:
        if row.js is None:
            continue
        doc = f"  // {row.doc}" if row.doc else ""
        out.append(f"{indent}out.{row.name} = {row.js};{doc}" if assign else f"{indent}{row.name}: {row.js},{doc}")
    return "\n".join(out)


def js_texture_entries(*, stochastic: bool) -> str:
    """``spectexTextureUniforms``'s entries: object entries (periodic), or assignments to ``out`` (stochastic)."""
    return _js_entries(inputs("texture", stochastic=stochastic), "      " if stochastic else "    ", stochastic)


def js_frame_entries(*, stochastic: bool) -> str:
    """``spectexFrameUniforms``'s entries, as :func:`js_texture_entries`."""
    return _js_entries(inputs("frame", stochastic=stochastic), "      " if stochastic else "    ", stochastic)


def js_unit_entries(*, stochastic: bool) -> str:
    """``spectexUnitUniforms``'s entries (texture units of ``nTiles`` tiles)."""
    return _js_entries(inputs("unit", stochastic=stochastic), "      " if stochastic else "    ", stochastic)


def js_sampler_entries() -> str:
    """``spectexSamplerUniforms``'s entries (the filter settings: ``maxAniso``)."""
    return _js_entries(inputs("sampler"), "    ", False)


_JS_KINDS = {"float": ("1f", 1), "vec2": ("2f", 2), "vec3": ("3f", 3), "vec4": ("4f", 4), "uint": ("1ui", 1),
             "uvec2": ("2ui", 2), "sampler2D": ("1i", 1), "mat3": ("Matrix3f", 9)}


def js_kinds() -> str:
    """WebGL's setter suffix and components per element of each input, as a JavaScript object literal."""
    entries = []
    for row in INPUTS:
        suffix, width = _JS_KINDS[row.type]
        if row.length or row.type not in ("float", "sampler2D"):
            suffix += "v"
        entries.append(f"{row.name}: [{suffix!r}, {width}]")
    return "{\n    " + ",\n    ".join(entries) + ",\n  }"
