"""The tiles as files, shared by the exports that ship them beside a shader."""

from __future__ import annotations

from pathlib import Path

__all__ = ["tile_names", "write_tiles"]


def tile_names(texture, stem: str = "tile") -> list[str]:
    """File names of the texture's tiles: ``tile.png``, or ``tile0.png``, ``tile1.png``, ..."""
    n = len(texture.tiles)
    return [f"{stem}.png"] if n == 1 else [f"{stem}{i}.png" for i in range(n)]


def write_tiles(texture, folder: Path) -> list[Path]:
    """The tiles as lossless PNGs (8-bit RGBA for ``bits=8``, 16-bit for float tiles)."""
    from spectex.io import write_image

    paths = []
    for name, tile in zip(tile_names(texture), texture.tiles):
        paths.append(write_image(folder / name, tile, bit_depth=8 if texture.bits == 8 else 16))
    return paths
