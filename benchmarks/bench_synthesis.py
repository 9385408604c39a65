"""Benchmark: texture synthesis from examples, side by side with baselines.

Run from the repository root::

    python benchmarks/bench_synthesis.py                   # about 1.5 minutes
    python benchmarks/bench_synthesis.py --naive-pixels 0  # run the naive baseline to the end too

Two tasks from issue 5, each with its peers in the same run:

* quilting 512 x 512 RGB from a 128 x 128 exemplar, block 32, overlap 6:
  ``spectex.synthesis.quilt`` against a plain NumPy FFT quilting written
  here (the textbook version: per block and channel, FFT correlations with
  numpy.fft, pure-Python dynamic programming for the cut);
* Efros-Leung 128 x 128 RGB from a 64 x 64 exemplar, window 11: the fast
  default (k-coherence), the exact exhaustive search (numba), and a naive
  NumPy baseline written here (per pixel, the Gaussian-weighted SSD against
  every exemplar window, vectorised over the windows).

Every result is also measured (histogram W1, band-power distance) so that a
speed-up is not bought with quality. Times are the best of ``--repeat`` runs
after one warm-up run (numba compilation and caches excluded), as wall time
and as CPU time of all threads (steadier on a shared machine); the machine
and its load are printed with them.

Embark Studios' texture-synthesis (Rust, multi-threaded, a multi-resolution
k-coherence/PatchMatch synthesiser) is not installable here; its README
reports about 1 s for a 400 x 400 output (their "Basic" example), quoted in
the notes and not measured.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time

import numpy as np

from spectex import metrics
from spectex.synthesis import efros_leung, quilt

# ---------------------------------------------------------------------------
# Exemplars
# ---------------------------------------------------------------------------

def colour_exemplar(size: int) -> np.ndarray:
    """A colour texture: stained cells, centred in a uniform region of
    scikit-image's immunohistochemistry picture (CC0)."""
    import skimage.data

    y, x = 124 - size // 2, 104 - size // 2
    img = skimage.data.immunohistochemistry()[y:y + size, x:x + size]
    return (img / 255.0).astype(np.float32)


# ---------------------------------------------------------------------------
# Baseline 1: plain NumPy FFT quilting
# ---------------------------------------------------------------------------

def _dp_cut(cost: np.ndarray) -> np.ndarray:
    n, m = cost.shape
    acc = cost.astype(np.float64).copy()
    for i in range(1, n):
        for j in range(m):
            acc[i, j] += acc[i - 1, max(j - 1, 0):min(j + 2, m)].min()
    path = np.empty(n, dtype=np.int64)
    path[-1] = int(np.argmin(acc[-1]))
    for i in range(n - 2, -1, -1):
        j = path[i + 1]
        lo = max(j - 1, 0)
        path[i] = lo + int(np.argmin(acc[i, lo:min(j + 2, m)]))
    return path


def numpy_quilt(ex: np.ndarray, size: int, block: int, overlap: int, tolerance: float = 0.1,
                seed: int = 0) -> np.ndarray:
    """Efros-Freeman quilting in plain NumPy (the baseline)."""
    rng = np.random.default_rng(seed)
    eh, ew, nch = ex.shape
    step = block - overlap
    n = int(np.ceil((size - overlap) / step))
    canvas = np.zeros((n * step + overlap,) * 2 + (nch,))
    ph, pw = eh - block + 1, ew - block + 1
    fex = np.fft.rfft2(np.moveaxis(ex, 2, 0).astype(np.float64))
    fsq = np.fft.rfft2(np.sum(ex.astype(np.float64) ** 2, axis=2))
    for i in range(n):
        for j in range(n):
            y, x = i * step, j * step
            mask = np.zeros((block, block))
            if i > 0:
                mask[:overlap, :] = 1
            if j > 0:
                mask[:, :overlap] = 1
            if i == 0 and j == 0:
                sy, sx = rng.integers(ph), rng.integers(pw)
            else:
                tmpl = canvas[y:y + block, x:x + block]
                pad = np.zeros((nch + 1, eh, ew))
                pad[0, :block, :block] = mask
                pad[1:, :block, :block] = np.moveaxis(mask[:, :, None] * tmpl, 2, 0)
                f = np.conj(np.fft.rfft2(pad))
                err = np.fft.irfft2(fsq * f[0] - 2 * np.sum(fex * f[1:], axis=0), s=(eh, ew))
                err = np.maximum(err[:ph, :pw] + np.sum(mask[:, :, None] * tmpl ** 2), 0.0)
                cand = np.flatnonzero(err <= err.min() * (1 + tolerance))
                sy, sx = divmod(int(cand[rng.integers(cand.size)]), pw)
            patch = ex[sy:sy + block, sx:sx + block]
            new = np.ones((block, block), dtype=bool)
            if i > 0 or j > 0:
                diff = np.sum((canvas[y:y + block, x:x + block] - patch) ** 2, axis=2)
                if j > 0:
                    path = _dp_cut(diff[:, :overlap])
                    new &= np.arange(block)[None, :] >= path[:, None]
                if i > 0:
                    path = _dp_cut(diff[:overlap, :].T)
                    new &= np.arange(block)[:, None] >= path[None, :]
            region = canvas[y:y + block, x:x + block]
            region[new] = patch[new]
    return canvas[:size, :size].astype(np.float32)


# ---------------------------------------------------------------------------
# Baseline 2: naive NumPy Efros-Leung
# ---------------------------------------------------------------------------

def numpy_efros_leung(ex: np.ndarray, size: int, window: int, seed: int = 0, max_pixels: int | None = None):
    """Efros-Leung with a per-pixel NumPy search over every exemplar window.

    Returns ``(image, pixels_done)``; with ``max_pixels`` it stops early so
    the time per pixel can be extrapolated.
    """
    rng = np.random.default_rng(seed)
    from numpy.lib.stride_tricks import sliding_window_view

    half = window // 2
    eh, ew, nch = ex.shape
    wins = sliding_window_view(ex, (window, window), axis=(0, 1))  # (vh, vw, C, win, win)
    vh, vw = wins.shape[:2]
    wins = wins.reshape(vh * vw, nch, window, window).astype(np.float64)
    sigma = window / 6.4
    r = np.arange(window) - half
    gauss = np.exp(-(r[:, None] ** 2 + r[None, :] ** 2) / (2 * sigma * sigma))
    out = np.zeros((size + 2 * half, size + 2 * half, nch))
    filled = np.zeros((size + 2 * half,) * 2, dtype=bool)
    sy, sx = rng.integers(0, eh - 2), rng.integers(0, ew - 2)
    c0 = half + (size - 3) // 2
    out[c0:c0 + 3, c0:c0 + 3] = ex[sy:sy + 3, sx:sx + 3]
    filled[c0:c0 + 3, c0:c0 + 3] = True
    done = 9
    threshold = 0.3
    inner = np.zeros_like(filled)
    inner[half:half + size, half:half + size] = True
    while done < size * size:
        grown = np.zeros_like(filled)
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                grown |= np.roll(np.roll(filled, dy, 0), dx, 1)
        ys, xs = np.nonzero(grown & ~filled & inner)
        progress = False
        for y, x in zip(ys, xs):
            m = filled[y - half:y + half + 1, x - half:x + half + 1] * gauss
            tmpl = np.moveaxis(out[y - half:y + half + 1, x - half:x + half + 1], 2, 0)
            err = np.sum(((wins - tmpl) ** 2) * m, axis=(1, 2, 3)) / (m.sum() * nch)
            cand = np.flatnonzero(err <= err.min() * 1.1)
            pick = int(cand[rng.integers(cand.size)])
            if err[pick] <= threshold:
                py, px = divmod(pick, vw)
                out[y, x] = ex[py + half, px + half]
                filled[y, x] = True
                done += 1
                progress = True
                if max_pixels is not None and done >= max_pixels:
                    return out[half:half + size, half:half + size].astype(np.float32), done
        if not progress:
            threshold *= 1.1
    return out[half:half + size, half:half + size].astype(np.float32), done


# ---------------------------------------------------------------------------
# Running and reporting
# ---------------------------------------------------------------------------

def best_time(fn, repeat: int):
    """Best wall time and best CPU time (all threads) of ``repeat`` runs."""
    fn()  # warm-up: numba compilation, caches
    walls, cpus = [], []
    result = None
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        result = fn()
        walls.append(time.perf_counter() - t)
        cpus.append(time.process_time() - c)
    return (min(walls), min(cpus)), result


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return f"{cpu}, {cores} cores, Python {platform.python_version()}, NumPy {np.__version__}"


def quality(ex, out) -> str:
    w1 = float(np.max(metrics.histogram_w1(ex, out)))
    return f"W1 {w1:.4f}, bands {metrics.band_power_distance(ex, out):.2f} dB"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="timed runs per entry (best is kept)")
    parser.add_argument("--naive-pixels", type=int, default=2048,
                        help="time the naive Efros-Leung on this many pixels and extrapolate "
                             "(its cost per pixel is constant); 0 runs it to the end (about 4 minutes)")
    args = parser.parse_args(argv)

    print(f"machine: {machine()}")
    print()
    rows = []

    ex128 = colour_exemplar(128)
    t_fast, q_fast = best_time(lambda: quilt(ex128, (512, 512), block=32, overlap=6, rng=0), args.repeat)
    t_np, q_np = best_time(lambda: numpy_quilt(ex128, 512, 32, 6, rng=0), max(1, args.repeat - 2))
    rows.append(("quilting 512x512 RGB from 128x128, block 32, overlap 6", [
        ("spectex quilt", t_fast, quality(ex128, q_fast), "target <= 0.5 s"),
        ("plain NumPy FFT quilting (baseline)", t_np, quality(ex128, q_np), ""),
        ("Embark texture-synthesis (Rust, 400x400)", None, "", "published ~1 s, not measured"),
    ]))

    ex64 = colour_exemplar(64)
    t_el, el = best_time(lambda: efros_leung(ex64, (128, 128), window=11, rng=0), max(1, args.repeat - 2))
    t_ex, exh = best_time(lambda: efros_leung(ex64, (128, 128), window=11, rng=0, method="exhaustive"), 1)
    total = 128 * 128
    limit = args.naive_pixels if args.naive_pixels > 0 else None
    t0, c0 = time.perf_counter(), time.process_time()
    naive, done = numpy_efros_leung(ex64, 128, 11, seed=0, max_pixels=limit)
    t_nv = (time.perf_counter() - t0, time.process_time() - c0)
    note = ""
    if done < total:
        t_nv = (t_nv[0] * total / done, t_nv[1] * total / done)
        note = f"extrapolated from {done} pixels"
    rows.append(("Efros-Leung 128x128 RGB from 64x64, window 11", [
        ("spectex efros_leung, fast default (k-coherence)", t_el, quality(ex64, el), "target <= 10 s"),
        ("spectex efros_leung, method='exhaustive' (numba)", t_ex, quality(ex64, exh), ""),
        ("naive NumPy exhaustive (baseline)", t_nv, quality(ex64, naive) if done == total else "", note),
    ]))

    print(f"load average at the end: {os.getloadavg()[0]:.2f} (other jobs slow the wall times down)")
    print()
    for title, entries in rows:
        print(title)
        base = entries[0][1]
        print(f"  {'method':50s} {'wall':>9s} {'cpu':>9s} {'x fast':>7s}   quality / notes")
        for name, t, qual, extra in entries:
            wall = "--" if t is None else f"{t[0]:8.3f}s"
            cpu = "--" if t is None else f"{t[1]:8.3f}s"
            ratio = "--" if t is None else f"{t[0] / base[0]:6.1f}x"
            print(f"  {name:50s} {wall:>9s} {cpu:>9s} {ratio:>7s}   {qual}{'; ' if qual and extra else ''}{extra}")
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main())
