"""Bakes beyond one image: a region of a spectral texture as a sharded OME-Zarr pyramid.

:func:`bake_zarr` evaluates each level of the pyramid directly with the
texture's mip-mapped sampler at the level's pixel size, one Dask task per
shard, on this machine's threads or on a ``dask.distributed`` cluster, and
writes OME-NGFF 0.5 on Zarr v3 (sharding codec). :func:`bake_window` is the
exact window of a larger ``spectex.render.bake``, and :func:`to_dtype` the
one conversion to the stored pixel types. :func:`bake_image` writes a region
as one plain PNG (8 or 16 bits), for engines and tools that take images. See
``docs/bake.md``.
"""

from ._block import DTYPES, bake_window, to_dtype
from ._image import IMAGE_BITS, bake_image
from ._zarr import MAX_SHARD_BYTES, BakeResult, bake_zarr, level_shapes, ome_metadata

__all__ = ["BakeResult", "DTYPES", "IMAGE_BITS", "MAX_SHARD_BYTES", "bake_image", "bake_window", "bake_zarr",
           "level_shapes", "ome_metadata", "to_dtype"]
