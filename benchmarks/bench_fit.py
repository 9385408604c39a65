"""Benchmark: fitting a spectral texture to a photograph (issue 6).

Run from the repository root::

    python benchmarks/bench_fit.py             # about a minute
    python benchmarks/bench_fit.py --repeat 5
    python benchmarks/bench_fit.py --time-only     # the time part only

Two parts, each side by side in one run:

* **time**: ``spectex.fit`` on a 512 x 512 exemplar (scikit-image's gravel,
  whole), best of ``--repeat`` after a warm-up (numba caches excluded), wall
  and CPU time, against the legacy fit (``method="legacy"``) timed
  interleaved in the same run (a ratio); and the whole ``spectex fit PHOTO -o DIR`` command in this
  process (fit, renders, plots, files), against the issue's 10 s;
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


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--time-only", action="store_true", help="the time part only (seconds)")
    args = ap.parse_args(argv)

    import skimage.data

    from spectex.cli import main as cli_main
    from spectex.fitting import fit, fit_report, fit_result
    from spectex.io import write_image
    from spectex.metrics import band_power, repetition
    from spectex.texture import SpectralTexture

    print(f"machine: {cpu_name()}, {os.cpu_count()} CPUs, "
          f"load average {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}")

    # ------------------------------------------------------------------ time
    gravel = skimage.data.gravel()
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
        cli_walls = []
        for i in range(args.repeat):
            _, wall, _ = _cpu_wall(lambda: cli_main(["fit", photo, "-o", os.path.join(tmp, f"out{i}")]))
            cli_walls.append(wall)
    print(f"spectex fit (in process, fit + renders + plots + files): best wall {min(cli_walls):.2f} s "
          f"(runs: {', '.join(f'{w:.2f}' for w in cli_walls)})")
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
