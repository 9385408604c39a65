"""The default fit of two checkouts side by side, measured at several places of each bake (issue 22).

``bench_fit_quality`` measures each fit at one place, the photo-sized corner at the world origin. A
texture's coarse layers change what a photo-sized view shows from place to place, so a change to them
(or to the colours they go over) is measured here at ``--places`` places (the origin and far ones, at
whole pixels: a view that falls between texels is blurred by bilinear filtering, for every method
alike, and that is not what is compared), for this checkout's ``src`` and another's (``--against``:
a worktree of an earlier commit, ``git worktree add /tmp/before <commit>``), each fitted in its own
process, one photo at a time, alternating, in one run.

Printed per photo and checkout: structural distance / floor (:func:`spectex.metrics.structural_distance`)
at each place and their mean, the clipped fraction of all places' values (the photo's beside it), the
first percentile of the values (the darkest shadow's level: a veil lifts it) against the photo's, the
largest ``repeat_peak`` of a bake of twice the photo's side at the places (``rp``: the finest layer's
content coming back; <= 0.1 asked), and the fit's seconds; then the means over the photos and the ratio of
this checkout's to the other's. ``--side N`` cuts every photo to its top-left ``N x N`` first: small photos,
whose finest tile the fit makes otherwise than a 512-pixel photo's.

Run from the repository root::

    python benchmarks/bench_places.py --against /tmp/before/src [--only gravel,roof] [--places 4] [--side 256]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import exemplars  # noqa: E402
from _machine import cpu_name  # noqa: E402

#: Places of the bakes, in photo sides from the origin (the first is the origin: the fit's own place).
PLACES = ((0.0, 0.0), (12.43, 3.7), (-30.23, 83.63), (411.5, -259.23), (-977.1, -1511.9), (2718.3, 1414.2))
#: Photos by default: the benchmark's eight and the new ones of ``exemplars.EXTRA`` that are not
#: variants of them, plus a roof of tiles with black gaps (``exemplars.roof``).
DEFAULT = exemplars.NAMES + ("page", "scales", "wall_turned", "tiles_turned", "roof")


def measure(name: str, places: int, side: int = 0) -> dict:
    """Fit ``name`` with the spectex on ``sys.path`` and measure its bakes (run in a child process)."""
    import time

    from spectex import fitting, metrics
    from spectex.render import bake

    photo = exemplars.load(name)
    if side:
        photo = photo[:side, :side]
    photo = np.dstack([photo] * 3) if photo.ndim == 2 else photo[:, :, :3]
    t0 = time.perf_counter()
    result = fitting.fit_result(photo, rng=0)
    seconds = time.perf_counter() - t0
    h, w = photo.shape[:2]
    p = result.pixel_size
    prepared = metrics.reference_statistics(photo)
    ratios, bakes, repeats = [], [], []
    for fx, fy in PLACES[:places]:
        origin = (round(fx * w) * p, round(fy * h) * p)
        twice = bake(result.texture, (2 * h, 2 * w), origin=origin, pixel_size=p)
        near = twice[:h, :w]
        ratios.append(metrics.structural_distance(near, photo, prepared=prepared).ratio)
        repeats.append(metrics.repeat_peak(twice))
        bakes.append(near)
    values = np.concatenate(bakes)
    return {"ratios": ratios, "clip": 100 * metrics.clipped_fraction(values),
            "clip photo": 100 * metrics.clipped_fraction(photo), "p1": float(np.percentile(values, 1)),
            "p1 photo": float(np.percentile(photo, 1)), "rp": max(repeats), "seconds": seconds}


def _run(src: str, name: str, places: int, side: int) -> dict:
    env = dict(os.environ, PYTHONPATH=src)
    out = subprocess.run([sys.executable, __file__, "--child", name, "--places", str(places), "--side", str(side)],
                         env=env,
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--against", help="the other checkout's src folder (its spectex package's parent)")
    ap.add_argument("--only", help="comma-separated photo names (exemplars.py)")
    ap.add_argument("--places", type=int, default=4, choices=range(1, len(PLACES) + 1))
    ap.add_argument("--side", type=int, default=0, help="cut every photo to its top-left SIDE x SIDE (0: whole)")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(measure(args.child, args.places, args.side)))
        return 0
    if not args.against:
        ap.error("--against is required: the other checkout's src folder")
    here = str(Path(__file__).resolve().parent.parent / "src")
    names = args.only.split(",") if args.only else DEFAULT
    print(f"# {cpu_name()}; structural distance / floor at {args.places} whole-pixel places; "
          f"this checkout ({here}) against {args.against}" + (f"; photos cut to {args.side} px" if args.side else ""))
    print(f"{'photo':14s} {'checkout':8s} {'mean':>6s}  {'places':28s} {'clip %':>13s} {'1st pct':>13s} "
          f"{'rp':>5s} {'s':>5s}")
    means = {"this": [], "other": []}
    for name in names:
        for label, src in (("other", args.against), ("this", here)):
            m = _run(src, name, args.places, args.side)
            means[label].append(float(np.mean(m["ratios"])))
            print(f"{name:14s} {label:8s} {np.mean(m['ratios']):6.3f}  "
                  f"{' '.join(f'{r:.2f}' for r in m['ratios']):28s} {m['clip']:5.2f} ({m['clip photo']:5.2f}) "
                  f"{m['p1']:5.3f} ({m['p1 photo']:5.3f}) {m['rp']:5.3f} {m['seconds']:5.1f}", flush=True)
    this, other = np.mean(means["this"]), np.mean(means["other"])
    print(f"mean over {len(names)} photos: this {this:.3f}, other {other:.3f}, ratio {this / other:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
