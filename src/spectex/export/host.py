"""A Python OpenGL host for the ``glsl`` export: what ``glsl/README.md`` tells a program to do.

An exported ``glsl/`` folder holds the ground program (``ground.330.vert``,
``ground.330.frag``), the layer table (``spectex_texture.json``), each tile's
mip levels (``mips/TILE.levelD.png``, spectex's own levels) and, for
stochastic layers, the tables as raw little-endian half floats
(``gauss.rgba16f`` or ``gaussI.rgba16f`` per tile, every level one after the
other, and ``spectex_lut.r16f``). This module reads only those files and
draws with moderngl, the way the README describes for any OpenGL program:

* :func:`texture_uniforms`: the uniforms that depend on the texture alone
  (layer matrices, opacities, level offsets, means; the stochastic layers'
  grid maps, hash keys, table rows and decorrelation) and the texture units
  (tiles ``0 .. n-1``, Gaussian tiles ``n .. 2n-1``, the look-up table ``2n``);
* :func:`frame_uniforms`: the per-frame uniforms of a camera, with each
  layer's anchor computed in float64 on the host (the tile coordinates of
  the camera modulo 2 and, for stochastic layers, the triangle-grid position
  split into its fraction and its vertex modulo 2^32), which is what keeps
  the picture precise thousands of kilometres from the origin;
* :func:`draw_glsl_export`: both, the textures uploaded, one frame drawn.

It serves Python programs that draw the export themselves (a moderngl,
pyglet or Qt viewer) and it is how the tests and ``examples/export_viewer.py``
check that the files alone give spectex's picture.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ..shading.constants import DEFAULT_ANISOTROPY

__all__ = ["read_table", "texture_uniforms", "frame_uniforms", "upload_textures", "draw_glsl_export"]


def read_table(folder) -> dict:
    """The layer table ``spectex_texture.json`` of an exported ``glsl/`` folder.

    Raises
    ------
    ValueError
        If ``folder`` is not a ``glsl/`` export (no readable table in it).
    """
    path = Path(folder) / "spectex_texture.json"
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise ValueError(f"folder must be the glsl/ folder of a spectex export, got {str(folder)!r} "
                         f"({type(exc).__name__}: no readable spectex_texture.json)") from None


def _tile_names(folder: Path) -> list[str]:
    return sorted({p.name.split(".level")[0] for p in (folder / "mips").glob("*.level0.png")})


def texture_uniforms(table: dict, n_tiles: int, *, anisotropy: float = DEFAULT_ANISOTROPY) -> dict:
    """The uniforms that depend only on the texture, and the texture units (README, "Uniforms").

    Parameters
    ----------
    table : dict
        The layer table (:func:`read_table`).
    n_tiles : int
        How many tiles the texture has (units ``0 .. n_tiles - 1``).
    anisotropy : float
        spectex's anisotropic filter, at most this many samples per pixel
        (1: trilinear alone).
    """
    from ..shading import interface

    frame = interface.HostFrame(table, int(n_tiles), anisotropy=float(anisotropy))
    return interface.host_values(frame, "unit", "texture", "sampler", stochastic=table["stochastic"] is not None)


def frame_uniforms(table: dict, camera, shape) -> dict:
    """The per-frame uniforms of ``camera`` for a picture of ``shape = (H, W)`` pixels (README, "Anchors").

    Everything is computed in float64: the camera basis (yaw 0 looks along
    +y, z up), the per-pixel ray steps, and per layer ``k`` the anchor
    ``M_k (camera - offset_k) mod 2``; for a stochastic layer also the
    triangle-grid position ``g = G_k M_k (camera - offset_k)`` of the
    *unreduced* tile coordinates, split into ``g - floor(g)`` and
    ``floor(g) mod 2^32`` (the grid's vertices are hashed by their index,
    which must be exact). The uniforms' names and which value goes where:
    :mod:`spectex.shading.interface`.
    """
    from ..shading import interface
    from ..shading.constants import ANCHOR_PERIOD

    h, w = int(shape[0]), int(shape[1])
    x, y, z = (float(v) for v in camera.position)
    yaw, pitch = math.radians(camera.yaw), math.radians(camera.pitch)
    fwd = np.array([math.cos(pitch) * math.sin(yaw), math.cos(pitch) * math.cos(yaw), math.sin(pitch)])
    right = np.array([math.cos(yaw), -math.sin(yaw), 0.0])
    up = np.cross(right, fwd)
    tan_y = math.tan(math.radians(camera.fov) / 2)
    tan_x = tan_y * w / h
    anchor, ganchor, gbase = [], [], []
    for layer in table["layers"]:
        m = layer["matrix"]
        dx, dy = x - layer["offset"][0], y - layer["offset"][1]
        s, t = m[0] * dx + m[1] * dy, m[2] * dx + m[3] * dy
        anchor.append((s % ANCHOR_PERIOD, t % ANCHOR_PERIOD))
        g = layer.get("grid", [0.0] * 4)
        kx, ky = g[0] * s + g[1] * t, g[2] * s + g[3] * t
        ganchor.append((kx - math.floor(kx), ky - math.floor(ky)))
        gbase.append((math.floor(kx) % 2 ** 32, math.floor(ky) % 2 ** 32))
    frame = interface.HostFrame(table, 0, shape=(h, w), z=z, fwd=fwd, right=right, up=up, tan_x=tan_x, tan_y=tan_y,
                                anchor=anchor, ganchor=ganchor, gbase=gbase)
    return interface.host_values(frame, "frame")


def _set_levels(tex, raw, min_filter, repeat):
    """Give ``tex`` the mip levels ``raw`` (level 0 already in it), a filter and a wrap mode."""
    import moderngl

    if len(raw) > 1:
        tex.build_mipmaps(0, len(raw) - 1)  # allocates the levels; overwritten next
        for d, data in enumerate(raw[1:], start=1):
            tex.write(data, level=d, alignment=1)
    tex.filter = (min_filter, moderngl.NEAREST if min_filter == moderngl.NEAREST else moderngl.LINEAR)
    tex.repeat_x = tex.repeat_y = repeat


def upload_textures(ctx, folder, table: dict) -> list:
    """Upload the export's textures from its files alone, bound to their units (see :func:`texture_uniforms`).

    The tiles as RGBA8 with spectex's own mip levels (alpha kept as data,
    no flip, repeat, trilinear); the stochastic tables as half floats, the
    Gaussian tiles with their levels (repeat, trilinear), the look-up table
    without (clamped, nearest). Returns the moderngl textures (the caller
    releases them).
    """
    import moderngl

    from ..io import read_image

    folder = Path(folder)
    names = _tile_names(folder)
    out = []
    for unit, name in enumerate(names):
        paths = sorted((folder / "mips").glob(f"{name}.level*.png"), key=lambda p: int(p.stem.split("level")[1]))
        raw = [np.floor(read_image(p) * 255.0 + 0.5).astype(np.uint8) for p in paths]
        tex = ctx.texture(raw[0].shape[1::-1], 4, raw[0].tobytes(), alignment=1)
        _set_levels(tex, [r.tobytes() for r in raw], moderngl.LINEAR_MIPMAP_LINEAR, True)
        tex.use(location=unit)
        out.append(tex)
    if table["stochastic"] is not None:
        shapes = [tuple(v) for v in table["stochastic"]["level_shapes"]]
        sizes = [4 * h * w for h, w in shapes]
        for i in range(len(names)):
            data = np.fromfile(folder / ("gauss.rgba16f" if len(names) == 1 else f"gauss{i}.rgba16f"), dtype="<f2")
            if data.size != sum(sizes):
                raise ValueError(f"gauss table of tile {i} holds {data.size} values, expected {sum(sizes)}")
            parts = np.split(data, np.cumsum(sizes)[:-1])
            tex = ctx.texture(shapes[0][::-1], 4, parts[0].tobytes(), dtype="f2", alignment=1)
            _set_levels(tex, [p.tobytes() for p in parts], moderngl.LINEAR_MIPMAP_LINEAR, True)
            tex.use(location=len(names) + i)
            out.append(tex)
        size, rows = table["stochastic"]["lut_size"], 4 * table["stochastic"]["lut_rows"]
        data = np.fromfile(folder / "spectex_lut.r16f", dtype="<f2")
        if data.size != size * rows:
            raise ValueError(f"spectex_lut.r16f holds {data.size} values, expected {size * rows}")
        lut = ctx.texture((size, rows), 1, data.tobytes(), dtype="f2", alignment=1)
        _set_levels(lut, [], moderngl.NEAREST, False)
        lut.use(location=2 * len(names))
        out.append(lut)
    return out


def draw_glsl_export(folder, camera, shape, *, ctx=None, anisotropy: float = DEFAULT_ANISOTROPY,
                     override=None) -> np.ndarray:
    """Draw an exported ``glsl/`` folder with OpenGL 3.3 from its files alone.

    Parameters
    ----------
    folder : path
        The export's ``glsl/`` folder.
    camera : spectex.Camera
        Where from (metres, z up, yaw 0 looks along +y, degrees).
    shape : (int, int)
        ``(H, W)`` of the picture.
    ctx : moderngl.Context, optional
        A current context to draw in (its objects made here are released
        afterwards); by default a headless EGL context of its own.
    anisotropy : float
        spectex's anisotropic filter's limit (1: trilinear alone).
    override : dict, optional
        Uniform values that replace the computed ones (for experiments and
        the tests' controls).

    Returns
    -------
    ndarray, shape (H, W, 3), float32
        In [0, 1], row 0 at the top.
    """
    import moderngl

    from ..shading.camera import check_size

    folder = Path(folder)
    h, w = check_size(shape)
    table = read_table(folder)
    own = ctx is None
    if own:
        from .._gl import create_context

        ctx = create_context(what="drawing a GLSL export")
    objects = []
    try:
        program = ctx.program(vertex_shader=(folder / "ground.330.vert").read_text(encoding="utf-8"),
                              fragment_shader=(folder / "ground.330.frag").read_text(encoding="utf-8"))
        objects.append(program)
        objects += upload_textures(ctx, folder, table)
        values = {**texture_uniforms(table, len(_tile_names(folder)), anisotropy=anisotropy),
                  **frame_uniforms(table, camera, (h, w)), **(override or {})}
        for name, value in values.items():
            if name not in program:  # optimised away
                continue
            if isinstance(value, list):  # the compiler may trim an array after its last used element
                value = value[:program[name].array_length]
                value = value[0] if len(value) == 1 else value
            program[name].value = value
        rb = ctx.renderbuffer((w, h), 4)
        fbo = ctx.framebuffer(color_attachments=[rb])
        vao = ctx.vertex_array(program, [])
        objects += [vao, fbo, rb]
        fbo.use()
        fbo.viewport = (0, 0, w, h)
        vao.render(moderngl.TRIANGLES, vertices=3)
        pixels = np.frombuffer(fbo.read(components=3, alignment=1), np.uint8).reshape(h, w, 3)
        return (pixels[::-1] / np.float32(255.0)).astype(np.float32)  # OpenGL's row 0 is the bottom one
    finally:
        if own:
            ctx.release()
        else:
            from ..render.gl import park_framebuffer

            park_framebuffer(ctx)
            for obj in reversed(objects):
                obj.release()
