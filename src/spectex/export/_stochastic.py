"""The stochastic layers' tables as the exports ship them (``docs/export.md``, "Stochastic layers").

A stochastic layer (``Layer(tiling="stochastic")``; ``spectex.shading.stochastic``)
does not sample its tile but two textures made from it: per tile its
*Gaussianised* levels (RGBA half floats, mip-mapped, filtered like the tile,
wrap ``REPEAT``) and one table texture of every tile's inverse look-up
tables (one channel of half floats, ``SPX_LUT_SIZE`` wide, point-sampled,
clamped; channel ``c``'s rows in the ``c``-th quarter, tile ``i``'s from row
``i * rows``). Both are exactly what ``render.gl`` uploads: the values are
half floats already (``stochastic.stochastic_tables`` rounds them), so the
exports write their IEEE half bits and lose nothing:

* the web viewer embeds them as ``data:`` URIs (deflated little-endian
  halves) and uploads them as ``RGBA16F``/``R16F`` with ``HALF_FLOAT``;
* the engine exports write raw files, ``<name>.rgba16f`` and
  ``spectex_lut.r16f``: little-endian IEEE 754 half floats, rows top first
  (row 0 is ``t = 0``), every mip level one after the other (level 0 first),
  as Godot's ``Image.create_from_data``, Unity's ``LoadRawTextureData`` and
  three.js's ``DataTexture`` take them.

The table texture also holds, after the tables, the cell maps of stochastic layers' tiles
(``shading.resources.cell_rows``; ``docs/sampling.md``, 6b, "Cells" and "Free cells"). Per layer the shader
also takes its grid map, hash key, snap counts, cell-map row, first table row and
decorrelation (:func:`layer_entries`), and, per frame, the grid position of
the anchor (``shading.tables.anchor_coords``, columns 2-5).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..shading.resources import stochastic_store, stochastic_tables

__all__ = ["LUT_FILE", "gauss_name", "gauss_levels", "lut_planar", "layer_entries", "table_info", "write_tables",
           "read_raw"]

#: The table texture's file in the engine exports.
LUT_FILE = "spectex_lut.r16f"


def gauss_name(texture, i: int) -> str:
    """File name of tile ``i``'s Gaussianised levels: ``gauss.rgba16f`` or ``gauss<i>.rgba16f``."""
    return "gauss.rgba16f" if len(texture.tiles) == 1 else f"gauss{i}.rgba16f"


def gauss_levels(texture) -> list[list[np.ndarray]]:
    """Per tile, its Gaussianised mip levels as float16 ``(h, w, 4)`` arrays (exact: they are halves)."""
    out = []
    for tables in stochastic_tables(texture):
        levels = [np.ascontiguousarray(level, dtype=np.float16) for level in tables.gaussian]
        for level, ref in zip(levels, tables.gaussian):
            if not np.array_equal(level.astype(np.float32), ref):
                raise RuntimeError("stochastic tables: a Gaussianised level is not made of half floats")
        out.append(levels)
    return out


def lut_planar(texture) -> np.ndarray:
    """The table texture, ``(4 rows, LUT_SIZE)`` float16: channel ``c``'s rows in the ``c``-th quarter.

    ``rows`` is every tile's expanded table (``SpectralTexture.stochastic_store``),
    one after the other; this is the array ``render.gl`` uploads.
    """
    _, lut, _ = stochastic_store(texture)
    planar = np.concatenate([lut[:, :, c] for c in range(4)], axis=0)
    half = np.ascontiguousarray(planar, dtype=np.float16)
    if not np.array_equal(half.astype(np.float32), planar):
        raise RuntimeError("stochastic tables: the look-up table is not made of half floats")
    return half


def table_info(texture) -> dict | None:
    """What the shader takes about the table texture as a whole (``None`` without stochastic layers):
    ``lut_rows`` (its rows per channel), ``lut_q`` (the last mip level),
    ``lut_size``, ``level_shapes`` (height, width of each mip level, as in the raw files)."""
    if not any(getattr(layer, "tiling", "periodic") == "stochastic" for layer in texture.layers):
        return None
    from spectex.shading.constants import LUT_SIZE

    _, lut, _ = stochastic_store(texture)
    shapes = [[int(v) for v in level.shape[:2]] for level in stochastic_tables(texture)[0].gaussian]
    return {"lut_rows": int(lut.shape[0]), "lut_q": len(shapes) - 1, "lut_size": LUT_SIZE, "level_shapes": shapes}


def layer_entries(texture) -> list[dict]:
    """Per layer, its tiling and, for a stochastic layer, what its shader call takes (JSON values).

    ``grid`` (m00, m01, m10, m11: tile -> skewed grid coordinates), ``key``
    (the hash key of its seed, a uint32), ``snap`` (its snap counts along s
    and t, whole numbers: ``Layer.snap``'s structure periods per tile, or
    the tile's width and height where that is 0; ``shading.stochastic.snap_counts``), ``cell_row`` (the first table
    row of its tile's cell map, ``shading.resources.cell_rows``, -1 without), ``lut_row`` (its tile's first
    table row), ``basis`` (3 x 3, row-major: RGB = origin + basis v; GLSL's
    ``mat3`` takes the transpose, column after column), ``origin``; and
    ``patch``, ``seed`` and ``snap_periods`` (``Layer.snap`` itself) for people.
    """
    from spectex.shading.tables import pack

    tables = pack(texture) if table_info(texture) is not None else None
    out = []
    for k, layer in enumerate(texture.layers):
        tiling = getattr(layer, "tiling", "periodic")
        entry = {"tiling": tiling}
        if tiling == "stochastic":
            entry.update({
                "patch": float(layer.patch), "seed": int(layer.seed),
                "grid": [float(v) for v in tables.grid[k].reshape(-1)],
                "key": int(tables.key[k]),
                "snap": [float(v) for v in tables.snap[k]],
                "snap_periods": [int(v) for v in getattr(layer, "snap", (0, 0))],
                "cell_row": float(tables.cell_row[k]),
                "lut_row": int(tables.tile[k]) * int(tables.lut_rows),
                "basis": [float(v) for v in tables.basis[k].reshape(-1)],
                "origin": [float(v) for v in tables.origin[k]],
            })
        out.append(entry)
    return out


def write_tables(texture, folder: Path) -> list[Path]:
    """Write the raw table files into ``folder`` (nothing without stochastic layers); return them."""
    if table_info(texture) is None:
        return []
    folder = Path(folder)
    files = []
    for i, levels in enumerate(gauss_levels(texture)):
        path = folder / gauss_name(texture, i)
        path.write_bytes(b"".join(level.astype("<f2").tobytes() for level in levels))
        files.append(path)
    path = folder / LUT_FILE
    path.write_bytes(lut_planar(texture).astype("<f2").tobytes())
    files.append(path)
    return files


def read_raw(path, shape_levels, channels: int) -> list[np.ndarray]:
    """Read a raw half-float file back: ``shape_levels`` the (h, w) of each level; float32 arrays."""
    data = np.fromfile(path, dtype="<f2")
    out = []
    pos = 0
    for h, w in shape_levels:
        n = h * w * channels
        out.append(data[pos:pos + n].reshape(h, w, channels).astype(np.float32))
        pos += n
    if pos != data.size:
        raise ValueError(f"{path}: {data.size} halves, expected {pos}")
    return out
