"""A bake of a spectral texture to a sharded OME-Zarr pyramid, on Dask.

Layout (OME-NGFF 0.5 on Zarr v3): the root group's attributes hold ``ome``
(``multiscales`` and ``omero``) and ``spectex`` (the parameters and the
texture file); arrays ``0``, ``1``, ... are the levels, axes ``(c, y, x)``,
chunks ``(3, chunk, chunk)`` inside shards ``(3, shard, shard)``.

One Dask task bakes one whole shard of one level and writes it (no two tasks
touch one shard), then leaves a marker file; a run that finds markers
skips those shards. The ``ome`` metadata and ``spectex.complete = true`` are
written last, after every marker is there, so a store that a reader opens
as an image is a finished one.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import re
import shutil
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._limits import limit
from .._validate import MAX_LENGTH, check_choice, check_float, check_int, check_length, check_shape
from ._block import DTYPES, run_window, to_dtype, window_packed

__all__ = ["BakeResult", "bake_zarr", "level_shapes", "MAX_SHARD_BYTES", "MAX_BAKE_BYTES", "MAX_BAKE_SHARDS"]

#: Largest shard, in bytes of stored pixels (3 * shard**2 * itemsize): 256 MiB.
MAX_SHARD_BYTES = 1 << 28
#: Most bytes a whole pyramid may hold, uncompressed (``$SPECTEX_MAX_BAKE_BYTES``; 1 TiB).
MAX_BAKE_BYTES = limit("BAKE_BYTES", 1 << 40)
#: Most shards (tasks) of one bake (``$SPECTEX_MAX_BAKE_SHARDS``): bounds the bookkeeping.
MAX_BAKE_SHARDS = limit("BAKE_SHARDS", 1 << 18)
#: Tasks handed to the scheduler at a time: the graph is built a batch at a time, never whole.
BATCH = 1024
#: Folder inside the store for the per-shard markers of an unfinished bake (each holds its shard's size).
MARKERS = ".spectex-progress"
#: File inside a finished store: each shard's size in bytes (-1: no file, an all-zero shard).
MANIFEST = "spectex-shards.json"
#: Lock file inside the store while a bake writes it (the owner's PID and host, JSON); not hidden, so that
#: a user sees that a bake is (or was, if it was killed) writing the store.
LOCK = "spectex.lock"
#: Network schemes of dask.distributed that reach a scheduler in another process.
_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx")
#: The attribute group of our own parameters in the root ``zarr.json``.
ATTRS = "spectex"
_ADDRESS = re.compile(r"^([a-z][a-z0-9+.-]*)://(\[[0-9a-fA-F:.]+\]|[A-Za-z0-9_.-]+):([0-9]{1,5})$")
_PARTIAL = re.compile(r"\.[0-9a-f]{32}\.partial$")  # zarr's LocalStore temporary files


@dataclass(frozen=True)
class BakeResult:
    """What :func:`bake_zarr` wrote.

    Attributes
    ----------
    path : Path
        The store (a folder ending in ``.zarr``).
    shapes : list of (int, int)
        ``(height, width)`` of each level, level 0 first.
    pixel_sizes : list of float
        Metres per pixel of each level (``pixel_size * 2**k``).
    dtype : str
        Stored type of the pixels.
    shards : int
        Shards in the whole pyramid (one Dask task each).
    baked : int
        Shards baked and written by this call.
    resumed : int
        Shards found finished by an earlier, interrupted call, and kept.
    pixels : int
        Pixels baked by this call (all levels).
    seconds : float
        Wall time of the baking (tasks), excluding set-up.
    """

    path: Path
    shapes: list
    pixel_sizes: list
    dtype: str
    shards: int
    baked: int
    resumed: int
    pixels: int
    seconds: float

    @property
    def pixels_per_second(self) -> float:
        return self.pixels / self.seconds if self.seconds > 0 else float("nan")


@dataclass(frozen=True)
class _Job:
    """Everything a worker needs to bake any shard: sent once per worker."""

    path: str
    packed: tuple
    shapes: tuple
    pixel_sizes: tuple
    chunk: int
    shard: int
    dtype: str


def level_shapes(shape, levels) -> list[tuple[int, int]]:
    """``(height, width)`` of each level: ``ceil(H / 2**k) x ceil(W / 2**k)``, the same region."""
    h, w = shape
    return [(-(-h // 2 ** k), -(-w // 2 ** k)) for k in range(levels)]


def default_levels(shape, chunk) -> int:
    """Levels until the coarsest fits in one chunk."""
    n = 1
    while max(level_shapes(shape, n)[-1]) > chunk:
        n += 1
    return n


def bake_zarr(texture, path, shape, *, pixel_size, origin=(0.0, 0.0), levels=None, chunk=512, shard=4096,
              dtype="uint8", scheduler=None, workers=None, progress=None, connect_timeout=10.0) -> BakeResult:
    """Bake a region of a spectral texture into a sharded OME-Zarr pyramid.

    Level ``k`` is ``spectex.render.bake`` of the same region at ``pixel_size *
    2**k`` (the sampler's mip-mapping filters it; no level is made from
    another), converted by :func:`to_dtype`. Level 0 equals
    ``to_dtype(bake(texture, shape, origin=origin, pixel_size=pixel_size))``
    bit for bit, whatever ``chunk``, ``shard``, ``workers`` or scheduler.

    Parameters
    ----------
    texture : SpectralTexture or path
        The texture, or its file (``.toml``; its text goes into the attributes).
    path : str or Path
        The store to write, a folder ending in ``.zarr``. If it holds an
        unfinished bake with the same arguments, the missing shards are
        baked and the rest kept; with other arguments, ValueError.
    shape : int or (int, int)
        ``(height, width)`` of level 0, pixels.
    pixel_size : float
        Metres per pixel of level 0 (> 0).
    origin : (float, float)
        World (x, y) of the corner of pixel (0, 0), metres (rows go along +y).
    levels : int, optional
        Pyramid levels; by default until the coarsest fits in one chunk.
    chunk : int
        Chunk edge, pixels (the unit a reader fetches); a multiple of 16.
    shard : int
        Shard edge, pixels, a multiple of ``chunk`` (the unit of a file and
        of a task); ``3 * shard**2 * itemsize <= MAX_SHARD_BYTES``.
    dtype : {"uint8", "uint16", "float32"}
    scheduler : str, optional
        None: Dask's threaded scheduler on this machine. A ``dask.distributed``
        scheduler address (``tcp://host:port``): the same tasks on its
        cluster; every worker must see ``path`` under the same name.
    workers : int, optional
        Threads of the local scheduler (default: all cores). Not with ``scheduler``.
    progress : callable, optional
        Called as ``progress(done_pixels, total_pixels)`` as shards finish.
    connect_timeout : float
        Seconds to wait for ``scheduler`` to answer (default 10).

    Returns
    -------
    BakeResult

    Notes
    -----
    Peak memory per worker thread is bounded by about ``4 * 3 * shard**2 *
    itemsize + 24 * chunk * shard`` bytes: the shard as stored, up to about
    three times as much again while zarr splits, compresses and joins it,
    and the float32 strip of ``chunk`` rows with its conversion (about 200
    MiB for uint8 at ``shard=4096``, ``chunk=512``; measured 193 MiB). It
    depends on ``chunk`` and ``shard`` only, never on ``shape``
    (``benchmarks/bench_bake.py --memory``). The task graph is handed to
    the scheduler :data:`BATCH` shards at a time, so its memory is bounded too.

    The whole pyramid may hold at most :data:`MAX_BAKE_BYTES` uncompressed
    and :data:`MAX_BAKE_SHARDS` shards (environment variables
    ``SPECTEX_MAX_BAKE_BYTES`` and ``SPECTEX_MAX_BAKE_SHARDS`` raise them).

    A bake trusts nothing it finds: every shard recorded as written (by a
    marker, or in a finished store's ``spectex-shards.json``) is checked to
    be there with its recorded size, and one that is not is baked again. A
    lock file (``spectex.lock``: PID and host) refuses a second writer; the
    lock of a process that no longer runs on this host is taken over.
    """
    from .. import texture_file

    # --- everything is checked before anything is written, and every number before the texture is
    # loaded (loading it imports and may compile the sampler: seconds), so that a refusal is at once
    path = _check_store_path(path)
    h, w = check_shape("shape", shape, maximum_pixels=1 << 62)
    p = check_length("pixel_size", pixel_size)
    ox, oy = _check_origin(origin)
    dtype = check_choice("dtype", dtype, DTYPES)
    chunk, shard = _check_chunk_shard(chunk, shard, dtype)
    levels = _check_levels((h, w), levels, chunk, shard, dtype)
    _check_free_space(path, (h, w), levels, dtype)
    connect_timeout = check_float("connect_timeout", connect_timeout, minimum=1e-3, maximum=3600.0)
    workers = _check_scheduler(scheduler, workers)
    if scheduler is not None:
        _probe(scheduler, connect_timeout)  # nothing listening: said before anything is loaded
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable, got {type(progress).__name__}")
    _require()
    texture, text = _texture_and_text(texture)

    shapes = level_shapes((h, w), levels)
    sizes = [p * 2.0 ** k for k in range(levels)]
    params = {
        "spectex_version": _version(),
        "shape": [h, w], "origin": [ox, oy], "pixel_size": p, "levels": levels,
        "chunk": chunk, "shard": shard, "dtype": dtype, "filter": "trilinear",
        "layers": texture_file.to_dict(texture, [])["layers"], "bits": texture_file.to_dict(texture, [])["bits"],
        "tiles_sha256": [_tile_hash(t) for t in texture.tiles],
    }
    params = json.loads(json.dumps(params))  # as the attributes will read back (lists, floats)

    # --- connect first: an unreachable scheduler must not leave a store behind
    client = _connect(scheduler, connect_timeout) if scheduler is not None else None
    path = path.absolute()
    try:
        with _Lock(path):
            return _bake_locked(texture, path, params, text, shapes, sizes, (ox, oy), p, chunk, shard, dtype,
                                client, workers, progress)
    except OSError as exc:
        if exc.filename is not None and not str(exc.filename).startswith(str(path)):
            raise
        # zarr's writes fail without a file name: name the store, and say that a rerun finishes it
        raise OSError(exc.errno, f"store '{path}' could not be written: {exc.strerror or exc}; run the "
                                 "same bake again to finish it") from None
    finally:
        if client is not None:
            client.close()


def _texture_and_text(texture):
    """The texture (loaded, if it is a path) and the TOML text that goes into the attributes."""
    from .. import texture_file
    from ..texture import SpectralTexture

    if isinstance(texture, (str, os.PathLike)):
        texture_path = Path(texture)
        return SpectralTexture.load(texture_path), texture_path.read_text(encoding="utf-8")
    if not isinstance(texture, SpectralTexture):
        raise TypeError(f"texture must be a SpectralTexture or a texture file, got {type(texture).__name__}")
    names = texture_file.tile_names(Path("texture"), len(texture.tiles))
    return texture, texture_file.dumps(texture_file.to_dict(texture, names))


def _check_store_path(path) -> Path:
    path = Path(path)
    if not path.name.lower().endswith(".zarr"):
        raise ValueError(f"path must end in .zarr, got '{path}'")
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise ValueError(f"path is in a folder that does not exist: '{path}'")
    return path


def _check_origin(origin) -> tuple[float, float]:
    if not isinstance(origin, (tuple, list)) or len(origin) != 2:
        raise ValueError(f"origin must be a pair (x, y) of numbers, got {origin!r}")
    ox = check_float("origin[0]", origin[0], minimum=-MAX_LENGTH, maximum=MAX_LENGTH)
    oy = check_float("origin[1]", origin[1], minimum=-MAX_LENGTH, maximum=MAX_LENGTH)
    return ox, oy


def _check_chunk_shard(chunk, shard, dtype) -> tuple[int, int]:
    chunk = check_int("chunk", chunk, minimum=16)
    if chunk % 16:
        raise ValueError(f"chunk must be a multiple of 16, got {chunk}")
    shard = check_int("shard", shard, minimum=chunk)
    if shard % chunk:
        raise ValueError(f"shard must be a multiple of chunk ({chunk}), got {shard}")
    itemsize = np.dtype(dtype).itemsize
    if 3 * shard * shard * itemsize > MAX_SHARD_BYTES:
        raise ValueError(f"shard of {shard} px holds {3 * shard * shard * itemsize / 2**20:.0f} MiB of {dtype}, "
                         f"over the limit of {MAX_SHARD_BYTES / 2**20:.0f} MiB")
    return chunk, shard


def _check_levels(shape, levels, chunk, shard, dtype) -> int:
    """The pyramid's levels, checked against the limits on bytes and shards."""
    h, w = shape
    itemsize = np.dtype(dtype).itemsize
    top = 1 + math.ceil(math.log2(max(h, w))) if max(h, w) > 1 else 1
    levels = default_levels((h, w), chunk) if levels is None else check_int("levels", levels, minimum=1, maximum=top)
    stored = sum(3 * lh * lw * itemsize for lh, lw in level_shapes((h, w), levels))
    if stored > MAX_BAKE_BYTES:
        raise ValueError(f"shape {w}x{h} (--size) at {dtype} makes {levels} levels of {stored:.3g} bytes, over the "
                         f"limit of {MAX_BAKE_BYTES} bytes (SPECTEX_MAX_BAKE_BYTES; set it to raise the limit)")
    n_shards = sum(-(-lh // shard) * -(-lw // shard) for lh, lw in level_shapes((h, w), levels))
    if n_shards > MAX_BAKE_SHARDS:
        raise ValueError(f"shape {w}x{h} (--size) with shard {shard} makes {n_shards} shards, over the limit of "
                         f"{MAX_BAKE_SHARDS} (SPECTEX_MAX_BAKE_SHARDS; set it to raise the limit, or a larger shard)")
    return levels


def _check_free_space(path: Path, shape, levels, dtype) -> None:
    """Refuse a pyramid whose uncompressed bytes (less what an earlier run has written) exceed the free disk.

    Compression may make the store smaller, but a bake that fills the disk hours in helps no one (as
    ImageMagick's disk limit): the check is made before the first byte is written.
    """
    itemsize = np.dtype(dtype).itemsize
    stored = sum(3 * lh * lw * itemsize for lh, lw in level_shapes(shape, levels))
    folder = path.parent if str(path.parent) else Path(".")
    try:
        free = shutil.disk_usage(folder).free
    except OSError:
        return  # a file system that cannot say: the write itself will tell
    if stored <= free:
        return
    written = 0
    if path.is_dir():
        for root, _, files in os.walk(path):
            for name in files:
                with contextlib.suppress(OSError):
                    written += os.lstat(os.path.join(root, name)).st_size
    if stored - written > free:
        more = f"{stored - written} more bytes" if written else f"{stored} bytes"
        raise ValueError(f"shape {shape[1]}x{shape[0]} (--size) at {dtype} makes {levels} levels that need {more} "
                         f"uncompressed, more than the {free} bytes free on the disk of '{folder}': free "
                         "some space or bake a smaller region")


def _check_scheduler(scheduler, workers):
    """Check the scheduler address; return ``workers`` checked (for the local scheduler only)."""
    if scheduler is not None:
        found = _ADDRESS.match(scheduler) if isinstance(scheduler, str) else None
        if found is None or found.group(1) not in _SCHEMES or not 1 <= int(found.group(3)) <= 65535:
            raise ValueError(f"scheduler must be the network address of a dask.distributed scheduler, "
                             f"{'|'.join(_SCHEMES)}://HOST:PORT such as tcp://host:8786, got {scheduler!r}")
        if workers is not None:
            raise ValueError("workers applies to the local scheduler only; a cluster has its own workers "
                             f"(got workers={workers!r} with scheduler={scheduler!r})")
        return workers
    if workers is not None:
        workers = check_int("workers", workers, minimum=1, maximum=1024)
    return workers


def _bake_locked(texture, path, params, text, shapes, sizes, origin, p, chunk, shard, dtype, client, workers,
                 progress) -> BakeResult:
    """The bake, once this process holds the store's lock."""
    ox, oy = origin
    state = _open_or_create(path, params, text, shapes, chunk, shard, dtype)
    tasks = [(k, i, j) for k, (lh, lw) in enumerate(shapes)
             for i in range(-(-lh // shard)) for j in range(-(-lw // shard))]
    done = _verified(path, shapes, state)
    if state == "complete" and len(done) == len(tasks):
        return BakeResult(path, shapes, sizes, dtype, len(tasks), 0, len(tasks), 0, 0.0)
    if state == "complete":  # a shard went missing or changed since: the store is unfinished again
        _reopen(path, done)
    todo = [t for t in tasks if _marker_name(*t) not in done]
    job = _Job(str(path), window_packed(texture, (ox, oy), p), tuple(shapes), tuple(sizes), chunk, shard,
               dtype)
    total = sum(_shard_pixels(job, *t) for t in todo)
    t0 = time.perf_counter()
    if todo:
        if client is None:
            _run_local(job, todo, workers, progress, total)
        else:
            _run_distributed(job, todo, client, progress, total)
    seconds = time.perf_counter() - t0
    _finish(path, params, text, sizes, (ox, oy), tasks)
    return BakeResult(path, shapes, sizes, dtype, len(tasks), len(todo), len(tasks) - len(todo), total, seconds)


# ---------------------------------------------------------------------- tasks
def _shard_pixels(job, k, i, j) -> int:
    lh, lw = job.shapes[k]
    return (min(job.shard, lh - i * job.shard)) * (min(job.shard, lw - j * job.shard))


def bake_shard(job: _Job, k: int, i: int, j: int) -> int:
    """Bake shard ``(i, j)`` of level ``k``, write it whole, then its marker; return its pixels.

    The shard is assembled in a ``(3, h, w)`` buffer from strips of ``chunk``
    rows (float32 only a strip at a time) and written with one assignment
    that covers the whole shard.
    """
    import numba
    import zarr

    lh, lw = job.shapes[k]
    r0, c0 = i * job.shard, j * job.shard
    sh, sw = min(job.shard, lh - r0), min(job.shard, lw - c0)
    packed = job.packed[:-2] + (job.pixel_sizes[k], job.packed[-1])  # same anchor, this level's pixel size
    buf = np.empty((3, sh, sw), dtype=job.dtype)
    strip = np.empty((min(job.chunk, sh), sw, 3), dtype=np.float32)
    threads = numba.get_num_threads()
    numba.set_num_threads(1)  # this thread's setting only: the Dask threads are the parallelism
    try:
        for a in range(0, sh, job.chunk):
            rows = min(job.chunk, sh - a)
            block = strip[:rows]
            run_window(packed, r0 + a, c0, block)
            buf[:, a:a + rows, :] = np.moveaxis(to_dtype(block, job.dtype), 2, 0)
    finally:
        numba.set_num_threads(threads)
    del strip
    array = zarr.open_array(store=job.path, path=str(k), mode="r+")
    # zarr reads an edge shard back before writing it (it merges into the full shard shape), so a
    # half-written file left by a killed worker would be read, or fail its checksum: remove it first.
    (Path(job.path) / str(k) / array.metadata.encode_chunk_key((0, i, j))).unlink(missing_ok=True)
    array[:, r0:r0 + sh, c0:c0 + sw] = buf
    shard_file = Path(job.path) / str(k) / array.metadata.encode_chunk_key((0, i, j))
    try:
        size = shard_file.stat().st_size
    except FileNotFoundError:
        size = -1  # zarr writes no file for a shard that is all fill value (black)
    marker = Path(job.path) / MARKERS / _marker_name(k, i, j)
    marker.parent.mkdir(parents=True, exist_ok=True)
    part = marker.with_name(f".{marker.name}.part")
    part.write_text(str(size))
    os.replace(part, marker)  # a marker is whole or absent
    return sh * sw


def _marker_name(k, i, j) -> str:
    return f"{k}.{i}.{j}"


def _finished_markers(path: Path) -> set[str]:
    return set(_recorded_markers(path))


def _recorded_markers(path: Path) -> dict[str, int | None]:
    """Marker name -> the shard size it records (None: unreadable, an older marker without a size)."""
    folder = path / MARKERS
    out = {}
    if not folder.is_dir():
        return out
    for f in folder.iterdir():
        if f.name.startswith("."):
            continue
        try:
            out[f.name] = int(f.read_text().strip())
        except (OSError, ValueError):
            out[f.name] = None
    return out


def _shard_file(path: Path, name: str) -> Path:
    k, i, j = name.split(".")
    return path / k / "c" / "0" / i / j  # zarr v3's default chunk key encoding, "/" separated


def _verified(path: Path, shapes, state) -> set[str]:
    """The shards recorded as written whose file is there with the recorded size (or absent, as recorded).

    A marker (or a manifest entry) that does not match its shard is
    removed, so that the shard is baked again.
    """
    if state == "new":
        return set()
    if state == "complete":
        try:
            recorded = json.loads((path / MANIFEST).read_text(encoding="utf-8"))
            if not isinstance(recorded, dict):
                recorded = {}
        except (OSError, UnicodeDecodeError, json.JSONDecodeError):
            recorded = {}
    else:
        recorded = _recorded_markers(path)
    good = set()
    for name, size in recorded.items():
        if (not isinstance(name, str) or not re.fullmatch(r"\d+\.\d+\.\d+", name)
                or int(name.split(".")[0]) >= len(shapes)):
            continue
        if isinstance(size, int) and not isinstance(size, bool):
            try:
                found = _shard_file(path, name).stat().st_size
            except FileNotFoundError:
                found = -1
            if found == size:
                good.add(name)
                continue
        if state != "complete":
            (path / MARKERS / name).unlink(missing_ok=True)
    return good


def _reopen(path: Path, good: set[str]) -> None:
    """Make a finished store unfinished again, keeping the shards in ``good`` (as markers)."""
    import zarr

    recorded = json.loads((path / MANIFEST).read_text(encoding="utf-8")) if (path / MANIFEST).is_file() else {}
    group = zarr.open_group(store=str(path), mode="r+")
    attrs = dict(group.attrs)
    attrs.pop("ome", None)  # a reader must not take the store for a finished image now
    attrs[ATTRS] = dict(attrs[ATTRS], complete=False)
    group.attrs.put(attrs)
    folder = path / MARKERS
    folder.mkdir(exist_ok=True)
    for name in good:
        (folder / name).write_text(str(recorded[name]))
    (path / MANIFEST).unlink(missing_ok=True)


def _run_local(job, todo, workers, progress, total) -> None:
    from dask.callbacks import Callback
    from dask.threaded import get

    job_key = "spectex-bake-job-" + _token(job)
    done = [0]

    def posttask(key, result, dsk, state, worker_id):
        if key != job_key:
            done[0] += result
            if progress is not None:
                progress(done[0], total)

    for start in range(0, len(todo), BATCH):  # a bounded graph at a time
        graph = {job_key: job}
        keys = []
        for k, i, j in todo[start:start + BATCH]:
            key = f"spectex-bake-{k}-{i}-{j}"
            graph[key] = (bake_shard, job_key, k, i, j)
            keys.append(key)
        with Callback(posttask=posttask):
            get(graph, keys, num_workers=workers or os.cpu_count() or 1)


def _probe(scheduler, timeout) -> None:
    """Refuse at once an address where nothing listens or whose host has no address (TCP-based schemes).

    dask.distributed retries a refused connection until its timeout: one plain TCP connection says
    "nothing listens there" in milliseconds. Slow or filtered networks are left to the timeout.
    """
    import socket

    found = _ADDRESS.match(scheduler)
    scheme, host, port = found.group(1), found.group(2).strip("[]"), int(found.group(3))
    if scheme not in ("tcp", "tls", "ws", "wss"):
        return
    try:
        with socket.create_connection((host, port), timeout=timeout):
            pass
    except ConnectionRefusedError:
        raise OSError(f"cannot reach the scheduler {scheduler}: nothing listens on port {port} of {host} "
                      "(connection refused)") from None
    except socket.gaierror as exc:
        raise OSError(f"cannot reach the scheduler {scheduler}: host {host!r} not found ({exc.strerror})") from None
    except OSError:
        return  # a timeout, an unreachable network...: dask.distributed's own connection says what it finds


def _connect(scheduler, timeout):
    """A ``distributed.Client`` of ``scheduler``, or OSError within about ``timeout`` seconds.

    The client is made in a daemon thread that is waited for at most ``timeout + 2`` seconds:
    dask.distributed does not bound its handshake, so an address where something else listens (a web
    server, a silent socket) would otherwise hang the bake for ever.
    """
    import threading

    try:
        from distributed import Client
    except ImportError:
        raise ValueError("scheduler needs dask.distributed: pip install 'spectex[bake]'") from None
    box = {}

    def connect():
        try:
            box["client"] = Client(scheduler, timeout=f"{timeout}s", set_as_default=False)
        except BaseException as exc:  # handed to the waiting thread
            box["error"] = exc

    thread = threading.Thread(target=connect, name="spectex-connect", daemon=True)
    thread.start()
    thread.join(timeout + 2.0)
    if thread.is_alive():
        raise OSError(f"cannot reach the scheduler {scheduler} within {timeout:g} s: something listens there but "
                      "does not answer as a dask.distributed scheduler")
    exc = box.get("error")
    if isinstance(exc, (OSError, TimeoutError)):
        raise OSError(f"cannot reach the scheduler {scheduler} within {timeout:g} s: {exc}") from None
    if isinstance(exc, ValueError):  # an address that dask.distributed cannot parse
        raise ValueError(f"scheduler {scheduler!r} is not an address dask.distributed can reach: {exc}") from None
    if exc is not None:
        raise exc
    return box["client"]


def _run_distributed(job, todo, client, progress, total) -> None:
    from distributed import as_completed

    job_future = client.scatter(job, broadcast=True)
    token = _token(job)
    done = 0
    for start in range(0, len(todo), BATCH):  # a bounded number of futures at a time
        futures = [client.submit(bake_shard, job_future, k, i, j, key=f"spectex-bake-{k}-{i}-{j}-{token}",
                                 pure=False, retries=2)
                   for k, i, j in todo[start:start + BATCH]]
        for future in as_completed(futures, loop=client.loop):  # this client's loop: it need not be the default
            done += future.result()
            if progress is not None:
                progress(done, total)


def _token(job) -> str:
    text = f"{job.path}|{job.shapes}|{job.pixel_sizes}|{job.shard}|{job.dtype}"
    return hashlib.sha256(text.encode()).hexdigest()[:16]


# ---------------------------------------------------------------------- store
class _Lock:
    """The store's lock file, held while a bake writes it: ``{"pid": ..., "host": ...}``.

    Made whole (written beside, then hard-linked to its name, which fails if
    it exists), so a second writer always reads a complete lock. A lock
    whose process is gone on this host is taken over; one of a live process
    or of another host is refused in one line. A store folder that this
    lock made, and that holds nothing else when the bake fails, is removed.
    """

    def __init__(self, path: Path):
        self.path = path
        self.lock = path / LOCK
        self.made = False

    def __enter__(self):
        import socket

        path = self.path
        if path.exists() and not path.is_dir():
            raise ValueError(f"path '{path}' exists and is not a spectex bake; choose another path")
        try:
            path.mkdir()
            self.made = True
        except FileExistsError:
            pass
        me = {"pid": os.getpid(), "host": socket.gethostname()}
        part = path / f".{LOCK}.{os.getpid()}.part"
        try:
            part.write_text(json.dumps(me), encoding="utf-8")
            for _ in range(3):
                try:
                    os.link(part, self.lock)
                    return self
                except FileExistsError:
                    pass
                owner = _lock_owner(self.lock)
                if owner is not None and _alive(owner, me["host"]):
                    raise ValueError(f"path '{path}' is being baked by process {owner['pid']} on "
                                     f"{owner['host']} (lock file '{self.lock}'); wait for it to finish, or "
                                     "remove the lock file if that process is gone")
                self.lock.unlink(missing_ok=True)  # a stale lock: its process is gone
            raise ValueError(f"path '{path}': cannot take the lock file '{self.lock}' (other bakes keep taking it)")
        except BaseException:
            part.unlink(missing_ok=True)
            self._remove_made()
            raise
        finally:
            part.unlink(missing_ok=True)

    def __exit__(self, *exc):
        if _lock_owner(self.lock) == {"pid": os.getpid(), "host": __import__("socket").gethostname()}:
            self.lock.unlink(missing_ok=True)
        if exc[0] is not None:
            self._remove_made()
        return False

    def _remove_made(self):
        if self.made:
            try:
                self.path.rmdir()  # only if empty: nothing was written
            except OSError:
                pass


def _lock_owner(lock: Path):
    try:
        owner = json.loads(lock.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None
    if not isinstance(owner, dict) or not isinstance(owner.get("pid"), int) or not isinstance(owner.get("host"), str):
        return None
    return {"pid": owner["pid"], "host": owner["host"]}


def _alive(owner, host) -> bool:
    """Whether the lock's owner may still run: always for another host (it cannot be checked from here)."""
    if owner["host"] != host:
        return True
    if owner["pid"] == os.getpid():
        return False  # this process's own lock, left by a call that was interrupted
    try:
        os.kill(owner["pid"], 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _require() -> None:
    missing = []
    for name in ("zarr", "dask"):
        try:
            __import__(name)
        except ImportError:
            missing.append(name)
    if missing:
        raise ValueError(f"bake to Zarr needs {', '.join(missing)}: pip install 'spectex[bake]'")


def _version() -> str:
    from .._version import __version__

    return __version__


def _tile_hash(tile) -> str:
    tile = np.ascontiguousarray(tile, dtype=np.float32)
    digest = hashlib.sha256(str(tile.shape).encode())
    digest.update(tile.tobytes())
    return digest.hexdigest()


def _read_attrs(path: Path):
    """The root group's attributes, or None if ``path`` is no Zarr v3 group."""
    meta = path / "zarr.json"
    if not meta.is_file():
        return None
    try:
        doc = json.loads(meta.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError):
        return None
    if not isinstance(doc, dict) or doc.get("node_type") != "group":
        return None
    return doc.get("attributes", {})


def _open_or_create(path: Path, params, text, shapes, chunk, shard, dtype) -> str:
    """Return "complete", "resume" or "new"; refuse a store that holds anything else."""
    import zarr
    from zarr.codecs import ZstdCodec

    if (path / "zarr.json").exists() or set(os.listdir(path)) - {LOCK}:
        attrs = _read_attrs(path) if path.is_dir() else None
        ours = attrs.get(ATTRS) if isinstance(attrs, dict) else None
        if not isinstance(ours, dict) or "bake" not in ours:
            raise ValueError(f"path '{path}' exists and is not a spectex bake; choose another path")
        stored = ours["bake"]
        if stored != params:
            diff = next((key for key in params if stored.get(key) != params[key]),
                        next(iter(set(stored) - set(params)), "?"))
            raise ValueError(f"path '{path}' holds a bake with other arguments ({diff}: "
                             f"{_brief(stored.get(diff))} there, {_brief(params.get(diff))} now); "
                             "remove it or choose another path")
        _clean_leftovers(path)
        if ours.get("complete") is True:
            shutil.rmtree(path / MARKERS, ignore_errors=True)  # left by a run stopped after its last write
            return "complete"
        state = "resume"
    else:
        state = "new"
        zarr.create_group(store=str(path), zarr_format=3,
                          attributes={ATTRS: {"bake": params, "complete": False, "texture_file": text}})
    for k, lshape in enumerate(shapes):
        if (path / str(k) / "zarr.json").is_file():
            array = zarr.open_array(store=str(path), path=str(k), mode="r")
            if (array.shape != (3,) + lshape or array.chunks != (3, chunk, chunk)
                    or array.shards != (3, shard, shard) or array.dtype != np.dtype(dtype)):
                raise ValueError(f"path '{path}' has a level {k} that this bake did not make; "
                                 "remove it or choose another path")
            continue
        zarr.create_array(store=str(path), name=str(k), shape=(3,) + lshape, dtype=dtype,
                          chunks=(3, chunk, chunk), shards=(3, shard, shard), compressors=ZstdCodec(level=1),
                          fill_value=0, dimension_names=("c", "y", "x"))
    return state


def _clean_leftovers(path: Path) -> None:
    """Remove the temporary files a killed run left: zarr's ``.*.partial``, our ``.*.part`` (we hold the lock)."""
    for f in [*path.rglob("*.partial"), *path.rglob(".*.part")]:
        if f.is_symlink() or not (_PARTIAL.search(f.name) or f.name.endswith(".part")):
            continue
        if f.is_dir():
            shutil.rmtree(f, ignore_errors=True)
        else:
            f.unlink(missing_ok=True)


def _brief(value) -> str:
    text = json.dumps(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _finish(path, params, text, sizes, origin, tasks) -> None:
    import zarr

    recorded = _recorded_markers(path)
    missing = set(_marker_name(*t) for t in tasks) - set(recorded)
    if missing:
        raise OSError(f"bake of '{path}' ended with {len(missing)} shards unwritten (e.g. {sorted(missing)[0]}); "
                      "run it again to finish them")
    manifest = {name: recorded[name] for name in sorted(_marker_name(*t) for t in tasks)}
    part = path / f".{MANIFEST}.part"
    part.write_text(json.dumps(manifest), encoding="utf-8")
    os.replace(part, path / MANIFEST)
    group = zarr.open_group(store=str(path), mode="r+")
    group.attrs.put({
        "ome": ome_metadata(path.name, sizes, origin, params["dtype"]),
        ATTRS: {"bake": params, "complete": True, "texture_file": text},
    })
    shutil.rmtree(path / MARKERS, ignore_errors=True)


def ome_metadata(name, sizes, origin, dtype) -> dict:
    """OME-NGFF 0.5 ``ome`` attributes: one multiscale image, axes (c, y, x) in metres.

    Level ``k``'s pixel ``(r, c)`` covers the world square with corner
    ``origin + (c, r) * size_k``; OME-NGFF places pixel centres at ``scale *
    index + translation``, so the translation is ``origin + size_k / 2``.
    """
    ox, oy = origin
    datasets = [{"path": str(k), "coordinateTransformations": [
        {"type": "scale", "scale": [1.0, s, s]},
        {"type": "translation", "translation": [0.0, oy + 0.5 * s, ox + 0.5 * s]}]}
        for k, s in enumerate(sizes)]
    top = {"uint8": 255, "uint16": 65535, "float32": 1.0}[dtype]
    channels = [{"label": label, "color": color, "active": True, "coefficient": 1.0, "family": "linear",
                 "inverted": False, "window": {"min": 0, "max": top, "start": 0, "end": top}}
                for label, color in (("red", "FF0000"), ("green", "00FF00"), ("blue", "0000FF"))]
    return {
        "version": "0.5",
        "multiscales": [{
            "name": name,
            "axes": [{"name": "c", "type": "channel"},
                     {"name": "y", "type": "space", "unit": "meter"},
                     {"name": "x", "type": "space", "unit": "meter"}],
            "datasets": datasets,
            "type": "spectex mip-mapped sampling",
            "metadata": {"description": "each level sampled directly at its own pixel size by spectex's "
                                        "trilinear mip-mapped sampler; no level is computed from another"},
        }],
        "omero": {"name": name, "channels": channels, "rdefs": {"model": "color", "defaultZ": 0, "defaultT": 0}},
    }
