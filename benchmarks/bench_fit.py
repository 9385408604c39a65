"""Benchmark: fitting a spectral texture to a photograph (issue 6).

Run from the repository root::

    python benchmarks/bench_fit.py             # about a minute
    python benchmarks/bench_fit.py --repeat 5
    python benchmarks/bench_fit.py --time-only     # the time part only
    python benchmarks/bench_fit.py --command-only  # spectex fit PHOTO against the bare fit

Two parts, each side by side in one run:

* **time**: ``spectex.fit`` on a 512 x 512 exemplar (scikit-image's gravel,
  whole), best of ``--repeat`` after a warm-up (numba caches excluded), wall
  and CPU time, against the legacy fit (``method="legacy"``) timed
  interleaved in the same run (a ratio); and the whole ``spectex fit PHOTO -o DIR`` command in a
  fresh process (imports, fit, renders, the report's measures, plots, files), against the issue's
  10 s, interleaved with the bare fit of the same photo in a fresh process (the fit's own seconds,
  after its imports and a warm-up): the command's cost as a ratio to the fit's
  (``--command-only`` for that line alone);
* **fidelity**: for brick, grass and gravel (128 x 128 crops, as in the
  tests, and the whole 512 x 512 pictures), the fitted texture against the
  unfitted default (``SpectralTexture.paper_preset()``), both baked at the
  exemplar's pixel size over twice its side: band power distance (dB RMS,
  target <= 1.5), the largest per-channel histogram W1 (target <= 0.03),
  the cross-scale dependence against the exemplar's (same sign, within
  0.15), at the exemplar's own place and at a far place the fit never
  baked; plus the repetition at the exemplar's period
  (:func:`spectex.metrics.repetition`, 1 for plain tiling of the exemplar)
  and the continuation: power per octave of bakes at 4x and 16x the pixel
  size against the exemplar's coarsest band.

The machine and its load are printed with the numbers.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

from _machine import cpu_name

from spectex.render import bake


def _cpu_wall(fn):
    t0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - t0, time.process_time() - c0


#: The bare fit in a fresh process, as a user's script runs it: imports, then a small warm-up fit
#: (numba's caches on disk), then the timed fit of the photo.
_BARE_FIT = """
import sys, time
from spectex import fit
from spectex.io import read_image
photo = read_image(sys.argv[1])
fit(photo[:64, :64], iterations=1)
t = time.perf_counter()
fit(photo)
print(time.perf_counter() - t)
"""


def _child(cmd):
    """Run ``cmd``; its wall time and its CPU time (user + system, all its threads), seconds."""
    import resource
    import subprocess
    import sys

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, *cmd], check=True, capture_output=True, text=True).stdout
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime
    return out, wall, cpu


def command_line(photo, folder, repeat):
    """``spectex fit PHOTO -o DIR`` (a fresh process: imports, fit, renders, the report's measures,
    plots, files) against the bare fit of the same photo in a fresh process, interleaved, as a ratio."""
    cmd, fits = [], []
    for i in range(repeat):  # interleaved: the same load for both
        out, wall, cpu = _child(["-c", _BARE_FIT, photo])
        fits.append((float(out.split()[-1]), wall, cpu))
        cmd.append(_child(["-m", "spectex", "fit", photo, "-o", os.path.join(folder, f"cmd{i}")])[1:])
    best_cmd = min(cmd)
    best_fit = min(fits)
    print(f"spectex fit PHOTO (fresh process: fit + renders + report + plots + files), 512 x 512 gravel, "
          f"{cpu_name()}: best wall {best_cmd[0]:.2f} s, CPU {best_cmd[1]:.2f} s (runs: "
          f"{', '.join(f'{w:.2f}' for w, _ in cmd)}; target 10 s); the bare fit in a fresh process: best "
          f"{best_fit[0]:.2f} s (its process {best_fit[1]:.2f} s wall, {best_fit[2]:.2f} s CPU): command / fit "
          f"{best_cmd[0] / best_fit[0]:.2f}; load average after {os.getloadavg()[0]:.2f}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--time-only", action="store_true", help="the time part only (seconds)")
    ap.add_argument("--command-only", action="store_true",
                    help="only the command against the bare fit (fresh processes, a ratio)")
    args = ap.parse_args(argv)

    import skimage.data

    from spectex.fitting import fit, fit_report, fit_result
    from spectex.io import write_image
    from spectex.metrics import band_power, repetition
    from spectex.texture import SpectralTexture

    print(f"machine: {cpu_name()}, {os.cpu_count()} CPUs, "
          f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")

    # ------------------------------------------------------------------ time
    gravel = skimage.data.gravel()
    if args.command_only:
        with tempfile.TemporaryDirectory() as tmp:
            photo = os.path.join(tmp, "gravel.png")
            write_image(photo, gravel / 255.0)
            command_line(photo, tmp, args.repeat)
        return 0
    fit(gravel[:64, :64], iterations=1)  # warm-up: numba caches, imports
    fit(gravel[:64, :64], iterations=1, method="legacy")
    walls, cpus, legacy = [], [], []
    for _ in range(args.repeat):  # interleaved: the same load for both
        _, wall, cpu = _cpu_wall(lambda: fit(gravel))
        walls.append(wall)
        cpus.append(cpu)
        legacy.append(_cpu_wall(lambda: fit(gravel, method="legacy"))[1])
    print(f"\nfit, 512 x 512 exemplar (gravel): best wall {min(walls):.2f} s, CPU {min(cpus):.2f} s "
          f"(runs: {', '.join(f'{w:.2f}' for w in walls)}; target 10 s); legacy fit best {min(legacy):.2f} s: "
          f"ratio {min(walls) / min(legacy):.2f}")
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    with tempfile.TemporaryDirectory() as tmp:
        photo = os.path.join(tmp, "gravel.png")
        write_image(photo, gravel / 255.0)
        command_line(photo, tmp, args.repeat)
    if args.time_only:
        return 0

    # -------------------------------------------------------------- fidelity
    default = SpectralTexture.paper_preset(tile_size=256)
    origins = ((0.0, 0.0), (1000.0, 3000.0))
    print("\nfidelity at the exemplar's pixel size (bake of twice the exemplar's side):")
    print(f"{'exemplar':<14}{'texture':<9}{'origin':<14}{'band dB':>8}{'W1 max':>8}"
          f"{'cross':>8}{'target':>8}{'fit s':>7}{'rep':>7}")
    for size in (128, 512):
        for name in ("brick", "grass", "gravel"):
            img = getattr(skimage.data, name)()[:size, :size]
            res, wall, _ = _cpu_wall(lambda: fit_result(img))
            rep = repetition(bake(res.texture, (2 * size, 2 * size)), (size, size))
            rep_default = repetition(bake(default, (2 * size, 2 * size)), (size, size))
            for label, tex, secs, r in (("fitted", res.texture, f"{wall:7.2f}", rep),
                                        ("default", default, "", rep_default)):
                for o in origins:
                    rp = fit_report(tex, img, origin=o)
                    print(f"{name} {size:<8}{label:<9}{str(o):<14}{rp.band_power_distance_db:8.2f}"
                          f"{max(rp.histogram_w1):8.3f}{rp.cross_scale_texture:8.2f}"
                          f"{rp.cross_scale_exemplar:8.2f}{secs:>7}{r:7.3f}")
                    secs = ""
            if size == 128:
                # continuation: coarser bakes (mip-filtered) against the exemplar's coarsest band
                ex_bands = band_power(res.exemplar)[1]
                line = []
                for factor in (4, 16):
                    b = bake(res.texture, (256, 256), pixel_size=float(factor))
                    line.append(f"x{factor}: " + " ".join(f"{p:.1f}" for p in band_power(b)[1]))
                print(f"    continuation ({name}): exemplar bands {' '.join(f'{p:.1f}' for p in ex_bands)} dB; "
                      f"{'; '.join(line)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
