"""Bake-to-Zarr benchmark: throughput against the in-memory bake, scaling, memory, a projection.

Side by side in one run (STYLE.md: ratios, not timed tests), the paper's
five-layer texture (512 x 512 tile) at its finest texel size (15.625 m /
512 = 3.05 cm per pixel):

* **throughput**: ``spectex.render.bake`` of an N x N region held in
  memory (numba's threads) against ``spectex.bake.bake_zarr`` of the same
  region to a sharded OME-Zarr store (level 0 only; Dask threads, one shard
  per task, zstd compression and the writes overlapped with the sampling),
  each on 1 and on 2 threads, best of ``--repeats``, interleaved so that
  the machine's load hits both alike. Target: Zarr >= 80% of in-memory on
  the same number of threads;
* **cost per pixel at coarser pixel sizes** (levels 0, 3, 6), and the
  compressed bytes per pixel, to project the time and the storage of the
  whole 327680 x 327680 pyramid on N machines;
* with ``--memory``: the peak resident memory of a fresh process that bakes
  level 0 of 4096^2 .. ``--memory-max``^2 regions (default 32768^2, 1 Gpx),
  and of 8192^2 with other shard sizes: flat in the region, set by the shard.

Run: ``python benchmarks/bench_bake.py [--size N] [--repeats N] [--memory]``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from spectex.render import bake

PAPER_TEXEL = 15.625 / 512  # metres per texel of the paper's finest layer
VIRTUAL = 327680


def _texture():
    from spectex.texture import SpectralTexture
    from spectex.tiles import make_tile

    return SpectralTexture.paper_preset(make_tile(512, rng=0))


def _du(path: Path) -> int:
    return sum(f.stat().st_size for f in path.rglob("*") if f.is_file())


def _status_mib(field: str) -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1]) / 1024
    raise OSError(f"no {field} in /proc/self/status")


def child(size, shard, chunk, out):
    """Bake level 0 of size x size in this process; print the peak RSS of the bake as JSON.

    The texture is made and the kernels loaded first (a small bake), then the
    kernel's peak-RSS mark (VmHWM) is reset through ``/proc/self/clear_refs``,
    so the peak is the bake's own, not the set-up's.
    """
    import gc

    from spectex.bake import bake_zarr

    tex = _texture()
    bake_zarr(tex, out + ".warm.zarr", (64, 64), pixel_size=PAPER_TEXEL, levels=1, chunk=64, shard=64)
    shutil.rmtree(out + ".warm.zarr")
    gc.collect()
    Path("/proc/self/clear_refs").write_text("5")  # reset VmHWM to the current RSS (Linux)
    base = _status_mib("VmRSS")
    result = bake_zarr(tex, out, (size, size), pixel_size=PAPER_TEXEL, origin=(1000.0, 2000.0), levels=1,
                       chunk=chunk, shard=shard)
    peak = _status_mib("VmHWM")
    print(json.dumps({"size": size, "shard": shard, "chunk": chunk, "peak_mib": peak, "before_mib": base,
                      "seconds": result.seconds, "mpx_s": result.pixels_per_second / 1e6,
                      "cpu_s": resource.getrusage(resource.RUSAGE_SELF).ru_utime, "bytes": _du(Path(out))}))


def memory(args, folder: Path):
    print("\npeak resident memory of a process while it bakes level 0 (uint8, chunk 512, all cores):")
    print(f"  {'region':>13} {'shard':>6} {'peak MiB':>9} {'before MiB':>10} {'bake MiB':>9} {'Mpx/s':>6} {'s':>7} "
          f"{'MiB on disk':>11}")
    runs = []
    n = 4096
    while n <= args.memory_max:
        runs.append((n, 4096))
        n *= 2
    runs += [(8192, 1024), (8192, 2048), (8192, 8192)]
    for size, shard in runs:
        out = folder / f"mem-{size}-{shard}.zarr"
        proc = subprocess.run([sys.executable, __file__, "--child", str(size), str(shard), "512", str(out)],
                              capture_output=True, text=True, check=True)
        row = json.loads(proc.stdout.strip().splitlines()[-1])
        print(f"  {size:>6}x{size:<6} {shard:>6} {row['peak_mib']:>9.0f} {row['before_mib']:>10.0f} "
              f"{row['peak_mib'] - row['before_mib']:>9.0f} {row['mpx_s']:>6.2f} {row['seconds']:>7.1f} "
              f"{row['bytes'] / 2**20:>11.0f}", flush=True)
        shutil.rmtree(out)


def cluster_runs(tex, n, origin, folder, best, repeats):
    """The same bake through a dask.distributed LocalCluster of 1 and 2 worker processes (1 thread each)."""
    from distributed import LocalCluster

    from spectex.bake import bake_zarr

    print(f"\nthrough a dask.distributed LocalCluster ({n}x{n} px, 1 thread per worker process, best of {repeats}):")
    rates = {}
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                          silence_logs=50) as cluster:
            bake_zarr(tex, folder / "cwarm.zarr", (64, 64), pixel_size=PAPER_TEXEL, levels=1, chunk=64, shard=64,
                      scheduler=cluster.scheduler_address)
            shutil.rmtree(folder / "cwarm.zarr")
            for rep in range(repeats):
                out = folder / f"c{workers}-{rep}.zarr"
                result = bake_zarr(tex, out, (n, n), pixel_size=PAPER_TEXEL, origin=origin, levels=1, chunk=512,
                                   shard=max(512, min(2048, n // 4)), scheduler=cluster.scheduler_address)
                rates[workers] = max(rates.get(workers, 0.0), result.pixels_per_second / 1e6)
                shutil.rmtree(out)
        mem = n * n / best[("in memory", min(workers, max(t for _, t in best)))] / 1e6
        print(f"  {workers} worker{'s' if workers > 1 else ' '}: {rates[workers]:6.2f} Mpx/s "
              f"(in memory on as many threads: {mem:.2f}; ratio {rates[workers] / mem:.2f})")
    print(f"  scaling 1 -> 2 worker processes: x{rates[2] / rates[1]:.2f}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=4096, help="region edge for the throughput runs (default 4096)")
    parser.add_argument("--repeats", type=int, default=3, help="best of this many measurements (default 3)")
    parser.add_argument("--memory", action="store_true", help="also measure peak memory up to --memory-max")
    parser.add_argument("--memory-max", type=int, default=32768)
    parser.add_argument("--cluster", action="store_true",
                        help="also bake through a LocalCluster of 1 and of 2 worker processes")
    parser.add_argument("--child", nargs=4, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        size, shard, chunk, out = args.child
        child(int(size), int(shard), int(chunk), out)
        return

    import numba

    from spectex.bake import bake_zarr

    tex = _texture()
    n = args.size
    origin = (1000.0, 2000.0)
    folder = Path(tempfile.mkdtemp(prefix="bench_bake_", dir=os.environ.get("BENCH_TMP")))
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")
    print(f"texture: {tex!r}; region {n} x {n} px at {PAPER_TEXEL * 100:.2f} cm per pixel")
    try:
        # compile (cached) outside the timing
        bake(tex, (16, 16), pixel_size=PAPER_TEXEL)
        bake_zarr(tex, folder / "warm.zarr", (64, 64), pixel_size=PAPER_TEXEL, levels=1, chunk=64, shard=64)
        cores = numba.config.NUMBA_NUM_THREADS
        threads = [1, 2] if cores >= 2 else [1]
        best = {}
        cpu = {}
        sizes_on_disk = 0
        for rep in range(args.repeats):
            for t in threads:
                numba.set_num_threads(t)
                c0, w0 = time.process_time(), time.perf_counter()
                bake(tex, (n, n), origin=origin, pixel_size=PAPER_TEXEL)
                dt, dc = time.perf_counter() - w0, time.process_time() - c0
                numba.set_num_threads(cores)
                key = ("in memory", t)
                if dt < best.get(key, float("inf")):
                    best[key], cpu[key] = dt, dc
                out = folder / f"t{t}-{rep}.zarr"
                c0 = time.process_time()
                result = bake_zarr(tex, out, (n, n), pixel_size=PAPER_TEXEL, origin=origin, levels=1, chunk=512,
                                   shard=max(512, min(2048, n // 4)), workers=t)
                dc = time.process_time() - c0
                key = ("to Zarr", t)
                if result.seconds < best.get(key, float("inf")):
                    best[key], cpu[key] = result.seconds, dc
                sizes_on_disk = _du(out)
                shutil.rmtree(out)
        px = n * n
        print(f"\nthroughput, {n}x{n} px, best of {args.repeats} (wall Mpx/s; CPU ns per pixel):")
        for t in threads:
            mem, zar = px / best[("in memory", t)] / 1e6, px / best[("to Zarr", t)] / 1e6
            ns_mem, ns_zarr = cpu[("in memory", t)] / px * 1e9, cpu[("to Zarr", t)] / px * 1e9
            print(f"  {t} thread{'s' if t > 1 else ' '}: in memory {mem:6.2f} Mpx/s ({ns_mem:5.0f} ns/px)"
                  f"   to Zarr {zar:6.2f} Mpx/s ({ns_zarr:5.0f} ns/px)   Zarr / memory = {zar / mem:.2f}")
        for t in threads:
            print(f"  CPU time per pixel, in memory / to Zarr, {t} thread{'s' if t > 1 else ''}: "
                  f"{cpu[('in memory', t)] / cpu[('to Zarr', t)]:.2f} (the Zarr bake's efficiency, whatever else runs)")
        if len(threads) == 2:
            print(f"  scaling 1 -> 2 threads: in memory x{best[('in memory', 1)] / best[('in memory', 2)]:.2f}, "
                  f"to Zarr x{best[('to Zarr', 1)] / best[('to Zarr', 2)]:.2f}")
        bpp = sizes_on_disk / px
        if args.cluster:
            cluster_runs(tex, n, origin, folder, best, args.repeats)

        # per-pixel cost at coarser pixel sizes (pyramid levels 0, 3, 6), one thread
        print("\ncost per pixel by level (to Zarr, 1 thread, 2048 x 2048 px):")
        level_ns = {}
        for k in (0, 3, 6):
            out = folder / f"level{k}.zarr"
            c0 = time.process_time()
            result = bake_zarr(tex, out, (2048, 2048), pixel_size=PAPER_TEXEL * 2 ** k, origin=origin, levels=1,
                               chunk=512, shard=1024, workers=1)
            level_ns[k] = (time.process_time() - c0) / result.pixels * 1e9
            print(f"  level {k} ({PAPER_TEXEL * 2 ** k * 100:7.2f} cm/px): {level_ns[k]:5.0f} ns/px CPU, "
                  f"{result.seconds / result.pixels * 1e9:5.0f} ns/px wall, "
                  f"{_du(out) / result.pixels:.3f} bytes/px on disk")
            shutil.rmtree(out)

        # projection for the whole pyramid of the paper's virtual texture, from CPU time per pixel
        # (core-seconds; less sensitive to the other jobs on a shared machine than wall time)
        levels = 1
        while -(-VIRTUAL // 2 ** (levels - 1)) > 512:
            levels += 1
        counts = [(-(-VIRTUAL // 2 ** k)) ** 2 for k in range(levels)]
        total = sum(counts)
        cost = [level_ns[0] if k == 0 else level_ns[3] if k <= 3 else level_ns[6] for k in range(levels)]
        core_seconds = sum(c * ns * 1e-9 for c, ns in zip(counts, cost))
        print(f"\nprojection: the {VIRTUAL} x {VIRTUAL} pyramid, {levels} levels, {total / 1e9:.1f} Gpx "
              f"(level 0: {counts[0] / 1e9:.1f} Gpx)")
        print(f"  cost: CPU ns/px as measured (level 0; levels 1-3 at level 3's; 4+ at level 6's) -> "
              f"{core_seconds / 3600:.0f} core-hours")
        print(f"  storage: {bpp:.3f} bytes/px (uint8 RGB, zstd level 1, measured at level 0) -> "
              f"{total * bpp / 1e9:.0f} GB (raw RGB8 {total * 3 / 1e9:.0f} GB)")
        for machines, cores_each in ((1, 2), (1, 16), (10, 16), (100, 16)):
            hours = core_seconds / (machines * cores_each) / 3600
            print(f"  {machines:>3} machine{'s' if machines > 1 else ' '} x {cores_each:>2} cores: "
                  f"{hours:8.2f} h ({hours * 60:7.1f} min) at one core's measured cost per pixel, "
                  f"scaling linearly (shards are independent)")
        if args.memory:
            memory(args, folder)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
