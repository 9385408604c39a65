"""The numba kernel behind a bake block: a window of a larger bake, bit-exact.

``SpectralTexture.bake`` evaluates pixel ``(r, c)`` at the world displacement
``((c + 0.5) p, (r + 0.5) p)`` from the per-layer anchor of its origin. A
block of that bake must not be a bake of its own (with a shifted origin the
anchor is rounded differently and the last bits change), so this kernel
keeps the anchor of the whole region and takes the block's first row and
column as integers: pixel ``(r0 + r, c0 + c)`` of the whole region, with
exactly the expression of ``bake_kernel``.

Compiled with ``parallel=True`` (rows in ``prange``) even where it runs on
one thread: the outlined parallel loop compiles to code about twice as fast
as the same loop serial (measured: 6.1 vs 2.4-3.1 Mpx/s on one thread, paper
preset). A bake to Zarr calls it with one numba thread per Dask thread
(``numba.set_num_threads`` is per calling thread), the parallelism being one
Dask task per shard.

This is the one place that reaches into the shading core; when the core
grows a ``bake`` entry point with a pixel offset, this module calls it.
Compiled on first use (``cache=True``), never at import.
"""

from __future__ import annotations

import numba

from ..render._kernels import shade_ground


@numba.njit(cache=True, parallel=True, nogil=True, fastmath=True)
def bake_block_kernel(data, stride, offsets, widths, heights, wrap_s, wrap_t, min_filter, mag_filter, max_aniso, bias,
                      min_lod, max_lod, tile_idx, mats, blends, means, opacity, on, anchor, pixel_size, n,
                      row0, col0, out):
    """Rows ``row0 ..`` and columns ``col0 ..`` of a bake anchored at ``anchor``, into ``out`` (h, w, 3)."""
    h, w = out.shape[0], out.shape[1]
    step = pixel_size / n
    inv = 1.0 / (n * n)
    for rr in numba.prange(h):
        r = row0 + rr
        for cc in range(w):
            c = col0 + cc
            ar = 0.0
            ag = 0.0
            ab = 0.0
            for j in range(n):
                dy = (r + (j + 0.5) / n) * pixel_size
                for i in range(n):
                    dx = (c + (i + 0.5) / n) * pixel_size
                    sr, sg, sb = shade_ground(data, stride, offsets, widths, heights, wrap_s, wrap_t, min_filter,
                                              mag_filter, max_aniso, bias, min_lod, max_lod, tile_idx, mats,
                                              blends, means, opacity, on, anchor, dx, dy, step, 0.0, 0.0, step)
                    ar += sr
                    ag += sg
                    ab += sb
            out[rr, cc, 0] = ar * inv
            out[rr, cc, 1] = ag * inv
            out[rr, cc, 2] = ab * inv
