"""Benchmark: the RGBA tile of a spectral texture, and its parts, side by side.

Run from the repository root::

    python benchmarks/bench_tiles.py             # about half a minute
    python benchmarks/bench_tiles.py --repeat 7

Targets (issue 3), on the 2-core dev machine: a 512 x 512 RGBA tile with
emboss alpha in at most 50 ms, and 4096 x 4096 in at most 2 s.

Peers in the same run:

* the same tile by the octave method and with the other alpha modes;
* the tile's two FFT passes alone (the field, and the band limit of three
  channels), so the remaining cost (ramp, emboss, interleaving) is visible;
* octaves by filtering under magnification (``spectral.magnify``) against
  the FFT route to the same circular convolution of the zero-stuffed input
  (``numpy.fft``/``scipy.fft``), 128 x 128 cells to 512 x 512 and 4096 x 4096;
* the mip chain of a tile with sides that are not powers of two (the fit's
  tiles cut at whole structure periods: 425, 448, 510 texels),
  ``tiles.mip_chain`` (its area weights as BLAS matrix products) against the
  same weights applied with ``numpy.einsum`` (how it did it before), with
  their ratio and the largest difference of their levels.

Times are the best of ``--repeat`` runs (three times as many at 512) after
one warm-up call (numba compilation and caches excluded); the machine and
its load average are printed with them: on a shared machine the best of
several runs is the least disturbed one.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np
from _machine import cpu_name


def best_of(fn, repeat):
    fn()  # warm-up: numba compilation, FFT plans, page faults
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def fft_magnify(x, m, filt):
    """The same circular convolution of the zero-stuffed input, by FFT."""
    import scipy.fft as sfft

    from spectex.spectral import discrete_filter

    n = x.shape[0]
    big = n * m
    taps, start = discrete_filter(filt, m)
    h = np.zeros(big)
    for j, t in enumerate(taps):
        h[(j + start) % big] += t
    u = np.zeros((big, big), dtype=np.float32)
    u[::m, ::m] = x
    H = sfft.rfft(h)
    U = sfft.rfft2(u, workers=-1)
    U *= sfft.fft(h)[:, None]
    U *= H[None, :]
    return sfft.irfft2(U, s=(big, big), workers=-1)


def einsum_chain(tile):
    """``mip_chain``'s levels with its area weights applied by ``numpy.einsum`` (the peer)."""
    from spectex.tiles.mipmap import _reduce_matrix

    levels = [tile.astype(np.float32)]
    while max(levels[-1].shape[:2]) > 1:
        x = levels[-1]
        h, w = x.shape[:2]
        if h % 2 == 0 and w % 2 == 0:
            y = x.reshape(h // 2, 2, w // 2, 2, -1).astype(np.float64).mean(axis=(1, 3))
        else:
            y = x.astype(np.float64)
            if h > 1:
                y = np.einsum("ik,kjc->ijc", _reduce_matrix(h), y)
            if w > 1:
                y = np.einsum("jk,ikc->ijc", _reduce_matrix(w), y)
        levels.append(y.astype(np.float32))
    return levels


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)

    from spectex.spectral import band_limit_planes, magnify, spectral_noise
    from spectex.tiles import make_tile

    rows = []

    def add(name, seconds, target=None):
        rows.append((name, seconds, target))

    for size, target, repeat in ((512, 0.050, 3 * args.repeat), (4096, 2.0, args.repeat)):
        add(f"make_tile {size} spectral, emboss", best_of(lambda: make_tile(size, rng=0), repeat), target)
        add(f"make_tile {size} octaves, emboss",
            best_of(lambda: make_tile(size, rng=0, method="octaves"), repeat))
        if size == 512:
            for alpha in ("luminance", "noise", "none"):
                add(f"make_tile {size} spectral, {alpha}",
                    best_of(lambda: make_tile(size, rng=0, alpha=alpha), repeat))
        half = size // 2
        add(f"  part: field {half}x{half} (spectral_noise)",
            best_of(lambda: spectral_noise(half, rng=0), repeat))
        planes = np.random.default_rng(0).random((3, half, half), dtype=np.float32)
        add(f"  part: band limit 3 x {half} -> {size}",
            best_of(lambda: band_limit_planes(planes, high=0.25, shape=(size, size)), repeat))
        cells = np.random.default_rng(0).standard_normal((128, 128)).astype(np.float32)
        m = size // 128
        add(f"magnify 128 -> {size} bspline (polyphase)", best_of(lambda: magnify(cells, m), repeat))
        add(f"magnify 128 -> {size} bspline (FFT route)",
            best_of(lambda: fft_magnify(cells, m, "bspline"), repeat))

    from spectex.tiles import mip_chain

    mip_ratios = []
    for side in (425, 448, 510):
        tile = np.random.default_rng(0).random((side, side, 4)).astype(np.float32)
        ours = best_of(lambda: mip_chain(tile), args.repeat)
        peer = best_of(lambda: einsum_chain(tile), args.repeat)
        add(f"mip_chain {side} (BLAS)", ours)
        add(f"mip_chain {side} einsum (peer)", peer)
        diff = max(float(np.abs(a - b).max()) for a, b in zip(mip_chain(tile), einsum_chain(tile)))
        mip_ratios.append(f"{side}: {peer / ours:.1f}x faster, levels differ by {diff:g}")

    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    print(f"machine: {cpu_name()}, {os.cpu_count()} cores, "
          f"{platform.system()} {platform.release()}, Python {platform.python_version()}, "
          f"NumPy {np.__version__}; load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f} "
          f"(other work on the machine slows every number)")
    print(f"{'task':46s} {'best (ms)':>10s} {'target (ms)':>12s} {'ratio':>7s}")
    for name, seconds, target in rows:
        tgt = f"{target * 1e3:12.0f}" if target else f"{'':12s}"
        ratio = f"{seconds / target:7.2f}" if target else f"{'':7s}"
        print(f"{name:46s} {seconds * 1e3:10.1f} {tgt} {ratio}")
    print("mip_chain against einsum, same run: " + "; ".join(mip_ratios))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
