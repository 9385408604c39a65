"""Switches the benchmarks compare a route with and without (one home for each)."""

from __future__ import annotations

from contextlib import contextmanager


@contextmanager
def without_free_cells():
    """Within the block, tiles get no free cell map (``spectex.shading._cells.free_cell_map`` answers None), as
    before free cells existed; the shading cache is emptied on the way in and out, so nothing made inside is
    kept after it, nor anything from before used inside it."""
    from spectex.shading import _cells, resources

    original = _cells.free_cell_map
    _cells.free_cell_map = lambda tile: None
    resources.clear_cache()
    try:
        yield
    finally:
        _cells.free_cell_map = original
        resources.clear_cache()
