"""A spectral texture taken out of spectex: exported as GLSL and drawn by OpenGL from the files alone.

The paper's five-layer texture with every layer stochastic (a tile that
never repeats) is exported with ``spectex.export.export(..., formats="glsl")``.
Then, as any OpenGL program would, this script reads only the exported
folder: the ground program (``ground.330.vert``/``.frag``), the layer table
(``spectex_texture.json``), the tile's mip levels (``mips/*.png``) and the
stochastic tables (``gauss.rgba16f``, ``spectex_lut.r16f``: raw half
floats); it computes the uniforms as ``glsl/README.md`` says (the layer
anchors in float64, from the unreduced tile coordinates for the grid) and
draws with moderngl (headless EGL). On the left the exported shader's
picture, on the right spectex's own CPU renderer at the same camera: the two
agree to about 1/255.

Run: ``python examples/export_viewer.py [OUT] [--tile N] [--width W]``.
"""

from __future__ import annotations

import json
import math
import tempfile
from pathlib import Path

import numpy as np

from spectex import SpectralTexture, io
from spectex.export import export
from spectex.render import Camera
from spectex.render.cpu import render_cpu
from spectex.tiles import make_tile

try:
    from _gallery import parser
except ImportError:  # run as a module from elsewhere
    from examples._gallery import parser

TEST_ARGS = ["--tile", "32", "--width", "96"]

#: The view: 1,000 km east of the origin, low over the ground, towards the horizon.
CAMERA = Camera((1.0e6, 3.0e3, 4.0), yaw=35.0, pitch=-20.0, fov=60.0)


def frame_uniforms(table: dict, camera: Camera, width: int, height: int) -> dict:
    """The ground program's per-frame uniforms from the exported table (``glsl/README.md``), float64."""
    x, y, z = camera.position
    yaw, pitch = math.radians(camera.yaw), math.radians(camera.pitch)
    fwd = np.array([math.cos(pitch) * math.sin(yaw), math.cos(pitch) * math.cos(yaw), math.sin(pitch)])
    right = np.array([math.cos(yaw), -math.sin(yaw), 0.0])
    up = np.cross(right, fwd)
    tan_y = math.tan(math.radians(camera.fov) / 2)
    tan_x = tan_y * width / height
    anchor, ganchor, gbase = [], [], []
    for layer in table["layers"]:
        m = layer["matrix"]
        dx, dy = x - layer["offset"][0], y - layer["offset"][1]
        s, t = m[0] * dx + m[1] * dy, m[2] * dx + m[3] * dy
        anchor.append((s % 2.0, t % 2.0))
        g = layer.get("grid", [0.0] * 4)  # stochastic layers: the grid position of the unreduced (s, t)
        kx, ky = g[0] * s + g[1] * t, g[2] * s + g[3] * t
        ganchor.append((kx - math.floor(kx), ky - math.floor(ky)))
        gbase.append((math.floor(kx) % 2 ** 32, math.floor(ky) % 2 ** 32))
    atm = table["atmosphere"]
    return {"u_size": (width, height), "u_height": z, "u_fwd": tuple(fwd), "u_right": tuple(right),
            "u_up": tuple(up), "u_tan": (tan_x, tan_y), "u_ddx": tuple(right * 2 * tan_x / width),
            "u_ddy": tuple(-up * 2 * tan_y / height), "u_horizon": tuple(atm["horizon"]),
            "u_zenith": tuple(atm["zenith"]), "u_haze": atm["haze_distance"], "u_far": 50 * atm["haze_distance"],
            "u_anchor": anchor, "u_ganchor": ganchor, "u_gbase": gbase}


def texture_uniforms(table: dict, n_tiles: int) -> dict:
    """The uniforms that depend only on the texture (``spectexTextureUniforms``), and the texture units."""
    layers = table["layers"]

    def pick(layer, name, zero):
        return layer[name] if layer["tiling"] == "stochastic" else zero

    out = {"u_tile": list(range(n_tiles)), "u_tex_size": tuple(table["tile_shape"][::-1]),
           "u_mat": [tuple(layer["matrix"]) for layer in layers], "u_opacity": [layer["opacity"] for layer in layers],
           "u_lod_off": [layer["lod_offset"] for layer in layers], "u_mean": [tuple(layer["mean"]) for layer in layers],
           "u_max_aniso": 8.0}
    if table["stochastic"] is not None:
        out.update({
            "u_gauss": [n_tiles + i for i in range(n_tiles)], "u_lut": 2 * n_tiles,
            "u_lut_rows": float(table["stochastic"]["lut_rows"]), "u_lut_q": float(table["stochastic"]["lut_q"]),
            "u_grid": [tuple(pick(layer, "grid", [0.0] * 4)) for layer in layers],
            "u_key": [pick(layer, "key", 0) for layer in layers],
            "u_lut_row": [float(pick(layer, "lut_row", 0)) for layer in layers],
            # mat3 is column-major: the transpose of the row-major basis
            "u_basis": [tuple(np.reshape(pick(layer, "basis", [0.0] * 9), (3, 3)).T.reshape(-1)) for layer in layers],
            "u_origin": [tuple(pick(layer, "origin", [0.0] * 3)) for layer in layers]})
    return out


def draw_exported(folder: Path, camera: Camera, width: int, height: int) -> np.ndarray:
    """Draw ``folder`` (an export's ``glsl/``) with OpenGL 3.3: ``(height, width, 3)`` float32, row 0 at the top."""
    import moderngl

    table = json.loads((folder / "spectex_texture.json").read_text(encoding="utf-8"))
    ctx = moderngl.create_standalone_context(backend="egl", require=330)
    try:
        program = ctx.program(vertex_shader=(folder / "ground.330.vert").read_text(encoding="utf-8"),
                              fragment_shader=(folder / "ground.330.frag").read_text(encoding="utf-8"))
        names = sorted({p.name.split(".level")[0] for p in (folder / "mips").glob("*.png")})
        unit = 0
        for name in names:  # the tiles, with spectex's own mip levels (RGBA8, no flip)
            levels = [io.read_image(p) for p in sorted((folder / "mips").glob(f"{name}.level*.png"),
                                                       key=lambda p: int(p.stem.split("level")[1]))]
            raw = [np.floor(lv * 255.0 + 0.5).astype(np.uint8).tobytes() for lv in levels]
            tex = ctx.texture(levels[0].shape[1::-1], 4, raw[0], alignment=1)
            _levels(tex, raw, moderngl.LINEAR_MIPMAP_LINEAR, True)
            tex.use(location=unit)
            unit += 1
        if table["stochastic"] is not None:  # the stochastic tables: raw little-endian half floats
            shapes = table["stochastic"]["level_shapes"]
            for i in range(len(names)):
                gauss = "gauss.rgba16f" if len(names) == 1 else f"gauss{i}.rgba16f"
                data = np.fromfile(folder / gauss, dtype="<f2")
                parts = np.split(data, np.cumsum([4 * h * w for h, w in shapes])[:-1])
                tex = ctx.texture(shapes[0][::-1], 4, parts[0].tobytes(), dtype="f2", alignment=1)
                _levels(tex, [p.tobytes() for p in parts], moderngl.LINEAR_MIPMAP_LINEAR, True)
                tex.use(location=unit)
                unit += 1
            rows = 4 * table["stochastic"]["lut_rows"]
            lut = ctx.texture((table["stochastic"]["lut_size"], rows), 1, (folder / "spectex_lut.r16f").read_bytes(),
                              dtype="f2", alignment=1)
            _levels(lut, [], moderngl.NEAREST, False)
            lut.use(location=unit)
        values = {**texture_uniforms(table, len(names)), **frame_uniforms(table, camera, width, height)}
        for name, value in values.items():
            if name not in program:  # optimised away
                continue
            if isinstance(value, list):  # the compiler may trim an array after its last used element
                value = value[:program[name].array_length]
                value = value[0] if len(value) == 1 else value
            program[name].value = value
        fbo = ctx.framebuffer(color_attachments=[ctx.renderbuffer((width, height), 4)])
        fbo.use()
        ctx.vertex_array(program, []).render(moderngl.TRIANGLES, vertices=3)
        pixels = np.frombuffer(fbo.read(components=3, alignment=1), np.uint8).reshape(height, width, 3)
        return (pixels[::-1] / np.float32(255.0)).astype(np.float32)  # OpenGL's row 0 is the bottom one
    finally:
        ctx.release()


def _levels(tex, raw, min_filter, repeat):
    """Give ``tex`` the mip levels ``raw`` (level 0 already in it), a filter and a wrap mode."""
    import moderngl

    if len(raw) > 1:
        tex.build_mipmaps(0, len(raw) - 1)  # allocates the levels; overwritten next
        for d, data in enumerate(raw[1:], start=1):
            tex.write(data, level=d, alignment=1)
    tex.filter = (min_filter, moderngl.NEAREST if min_filter == moderngl.NEAREST else moderngl.LINEAR)
    tex.repeat_x = tex.repeat_y = repeat


def picture(tile_size: int = 512, width: int = 960, seed: int = 0) -> np.ndarray:
    """The exported shader's picture beside spectex's CPU render: ``(H, 2 width, 3)`` float32."""
    texture = SpectralTexture.paper_preset(make_tile(tile_size, rng=seed), tiling="stochastic")
    height = width * 9 // 16
    with tempfile.TemporaryDirectory() as tmp:
        folder = export(texture, Path(tmp) / "ground", formats="glsl").folder / "glsl"
        exported = draw_exported(folder, CAMERA, width, height)
    reference = render_cpu(texture, CAMERA, (height, width), anisotropy=8.0)
    return np.concatenate([exported, reference], axis=1)


def main(argv=None) -> Path:
    p = parser(__doc__, "export_viewer.jpg")
    p.add_argument("--tile", type=int, default=512, help="tile side in texels (default 512)")
    p.add_argument("--width", type=int, default=960, help="width of each view in pixels (default 960)")
    args = p.parse_args(argv)
    return io.write_image(args.out, picture(args.tile, args.width))


if __name__ == "__main__":
    print(main())
