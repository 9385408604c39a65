"""The ``web`` export: one self-contained HTML file, a WebGL2 fly-over of the texture.

``index.html`` holds everything: the viewer's script (written for spectex,
no libraries), the renderer's own shaders as GLSL ES 3.00
(:mod:`spectex.export._shader`), the layer table, and every mip level of
every tile exactly as spectex samples it (:meth:`SpectralTexture.mip_levels`),
as ``data:`` URIs of deflate-compressed raw RGBA bytes that the page inflates
with the browser's ``DecompressionStream`` and uploads level by level. A
texture with stochastic layers also carries their tables
(:mod:`spectex.export._stochastic`): per tile the Gaussianised levels and the
look-up table texture, as deflated half floats, uploaded as ``RGBA16F`` and
``R16F`` exactly as the OpenGL renderer uploads them. No
network access, no build step: it opens by double-click from ``file://``.

The URL fragment holds the view, ``#camera=X,Y,Z,YAW,PITCH&fov=F`` (the
command line's conventions: metres, z up, yaw 0 = +y, degrees), and is
written back as the camera moves; ``&hud=0`` hides the overlay and
``&aniso=A`` sets the maximum anisotropy (default 8, as ``spectex view``; 1
is off). When the first frame at the requested camera is drawn, the page's
title becomes ``spectex:ready``.
"""

from __future__ import annotations

import base64
import json
import zlib
from importlib import resources
from pathlib import Path

import numpy as np

from ..shading.constants import DEFAULT_ANISOTROPY as _DEFAULT_ANISOTROPY
from ..shading.resources import mean_colours, mip_levels
from ._shader import ground_template, vertex_source
from ._stochastic import gauss_levels, layer_entries, lut_planar, table_info

__all__ = ["write_web", "viewer_html", "viewer_data", "layer_table", "uniforms_js", "DEFAULT_CAMERA",
           "DEFAULT_ANISOTROPY"]

#: The view the page opens at without a fragment: (x, y, z, yaw, pitch, fov), as ``spectex view``.
DEFAULT_CAMERA = (0.0, 0.0, 2.0, 0.0, -10.0, 60.0)
#: Maximum anisotropy while the viewer's anisotropy is on (``spectex view``'s N key): the renderers'.
DEFAULT_ANISOTROPY = _DEFAULT_ANISOTROPY


def _level_uri(level: np.ndarray, bits) -> str:
    """One mip level as a data: URI: row-major RGBA (uint8, float32 or, for ``bits=16``, IEEE half
    floats; little-endian), deflated."""
    if bits == 8:
        raw = np.floor(np.asarray(level, dtype=np.float64) * 255.0 + 0.5).astype(np.uint8)
    elif bits == 16:
        raw = np.asarray(level, dtype="<f2")
    else:
        raw = np.asarray(level, dtype="<f4")
    data = zlib.compress(np.ascontiguousarray(raw).tobytes(), 9)
    return "data:application/octet-stream;base64," + base64.b64encode(data).decode("ascii")


def layer_table(texture, *, atmosphere=None) -> dict:
    """The texture's layers and the atmosphere as plain JSON values (float64 numbers kept exact):
    what ``templates/uniforms.js`` reads."""
    from spectex.render import Atmosphere

    atmosphere = Atmosphere() if atmosphere is None else atmosphere
    h, w = texture.tile_shape
    means = mean_colours(texture)
    layers = []
    for layer, extra in zip(texture.layers, layer_entries(texture)):
        layers.append({
            "matrix": [float(v) for v in layer.matrix().reshape(-1)],
            "offset": [float(layer.offset[0]), float(layer.offset[1])],
            "opacity": float(layer.opacity),
            "lod_offset": float(np.log2(w / layer.size)),
            "mean": [float(v) for v in means[layer.tile]],
            "size": float(layer.size),
            "rotation": float(layer.rotation),
            "blend": layer.blend,
            "tile": int(layer.tile),
            **extra,
        })
    return {
        "bits": 8 if texture.bits == 8 else 32,
        "tile_shape": [int(h), int(w)],
        "layers": layers,
        "stochastic": table_info(texture),
        "atmosphere": {"horizon": list(atmosphere.horizon), "zenith": list(atmosphere.zenith),
                       "haze_distance": float(atmosphere.effective_haze)},
    }


def viewer_data(texture, *, atmosphere=None) -> dict:
    """Everything the page needs, as plain JSON values."""
    tiles = [{"levels": [{"width": int(lv.shape[1]), "height": int(lv.shape[0]), "data": _level_uri(lv, texture.bits)}
                         for lv in levels]}
             for levels in mip_levels(texture)]
    shader = ground_template(texture, "es300")
    stochastic = None
    if table_info(texture) is not None:
        lut = lut_planar(texture)
        stochastic = {
            "gauss": [{"levels": [{"width": int(lv.shape[1]), "height": int(lv.shape[0]), "data": _level_uri(lv, 16)}
                                  for lv in levels]} for levels in gauss_levels(texture)],
            "lut": {"width": int(lut.shape[1]), "height": int(lut.shape[0]), "data": _level_uri(lut, 16)},
        }
    return {
        **layer_table(texture, atmosphere=atmosphere),
        "tiles": tiles,
        "stochastic_textures": stochastic,
        "camera": list(DEFAULT_CAMERA),
        "anisotropy": DEFAULT_ANISOTROPY,
        "shader": {"vertex": vertex_source("es300"), "fragment": shader["source"], "first": shader["first"],
                   "over": shader["over"], "iso_lod": bool(shader["iso_lod"])},
    }


def viewer_html(texture, *, atmosphere=None) -> str:
    """The viewer page for ``texture``, as text."""
    template = resources.files("spectex.export").joinpath("templates", "viewer.html").read_text(encoding="utf-8")
    data = json.dumps(viewer_data(texture, atmosphere=atmosphere), separators=(",", ":"), allow_nan=False)
    # Inside <script>, "</" could close the element; "<\/" is the same JSON string.
    data = data.replace("</", "<\\/")
    from spectex.shading import interface
    from spectex.shading.constants import FILTER_LINEAR, FILTER_LINEAR_MIPMAP_LINEAR

    template = _fill(template, "/*@SPECTEX_UNIFORM_KINDS@*/", interface.js_kinds(), "viewer template")
    template = _fill(template, "/*@FILTER_LINEAR@*/", str(FILTER_LINEAR), "viewer template")
    template = _fill(template, "/*@FILTER_LINEAR_MIPMAP_LINEAR@*/", str(FILTER_LINEAR_MIPMAP_LINEAR), "viewer template")
    template = _fill(template, "/*@SPECTEX_UNIFORMS_JS@*/", uniforms_js(), "viewer template")
    return _fill(template, "/*@SPECTEX_DATA@*/", data, "viewer template")


def uniforms_js() -> str:
    """The shader's uniforms in JavaScript, shared by the viewer and the glsl export: ``templates/uniforms.js``
    with its entries from the table of :mod:`spectex.shading.interface` and its constants from
    :mod:`spectex.shading.constants`."""
    from spectex.shading import interface
    from spectex.shading.constants import ANCHOR_PERIOD, HAZE_OFF

    text = resources.files("spectex.export").joinpath("templates", "uniforms.js").read_text(encoding="utf-8")
    fills = {"TEXTURE": interface.js_texture_entries(stochastic=False),
             "TEXTURE_STOCHASTIC": interface.js_texture_entries(stochastic=True),
             "UNIT": interface.js_unit_entries(stochastic=False),
             "UNIT_STOCHASTIC": interface.js_unit_entries(stochastic=True),
             "SAMPLER": interface.js_sampler_entries(),
             "FRAME": interface.js_frame_entries(stochastic=False),
             "FRAME_STOCHASTIC": interface.js_frame_entries(stochastic=True)}
    for name, entries in fills.items():
        text = _fill(text, f"/*@{name}@*/", entries, "uniforms.js")
    text = text.replace("/*@ANCHOR_PERIOD@*/", repr(float(ANCHOR_PERIOD)))
    return _fill(text, "/*@HAZE_OFF@*/", repr(float(HAZE_OFF)), "uniforms.js")


def _fill(text: str, marker: str, value: str, what: str) -> str:
    """``text`` with its one ``marker`` replaced by ``value``."""
    if text.count(marker) != 1:
        raise RuntimeError(f"{what}: {marker} must appear once")
    return text.replace(marker, value)


def write_web(texture, folder: Path) -> list[Path]:
    """Write ``folder/index.html``; return the files written."""
    path = Path(folder) / "index.html"
    path.write_text(viewer_html(texture), encoding="utf-8")
    return [path]
