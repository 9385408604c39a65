"""The photos the fit-quality benchmarks use (issue 22): one loader, shared by
``bench_fit_quality.py`` and anyone redesigning the fit, so both measure on the same set.

All offline: scikit-image's bundled pictures (gravel, brick, grass, moon, a crop of the
immunohistochemistry slide, a crop of the Hubble deep field: black sky, so a clipping test)
and two procedurally made structured photos (irregular cobble paving, a regular grid of
tiles), drawn with a fixed seed. Each is float32 in [0, 1], grey ``(H, W)`` or RGB
``(H, W, 3)``, 512 x 512 unless said.

    from exemplars import exemplars        # run from benchmarks/, or put it on sys.path
    for name, photo in exemplars(): ...
"""

from __future__ import annotations

import numpy as np

#: The set, in order; ``quick`` keeps the first three of :data:`QUICK`.
NAMES = ("gravel", "brick", "grass", "moon", "tissue", "deep_field", "paving", "tiles")
QUICK = ("gravel", "brick", "paving")
#: By name only (``--only``): photos holding one object each (issue 22's one-off content), 256-pixel
#: crops of gravel and grass with an orange leaf pasted on (:func:`with_leaf`); photos lit unevenly,
#: gravel and paving under a light from one side with a vignette (:func:`lit`) and scikit-image's
#: ``page`` (a scanned page of text, lit unevenly by the scanner: real uneven light, 191 x 384); photos
#: of gravel, paving and grass taken at an angle (:func:`oblique`); small photos of objects larger than a
#: quilt's overlap: scikit-image's ``coins`` (303 x 384, coins of about 50 pixels on a cloth lit from one
#: side) and :func:`pebbles` (256 x 256); :func:`planks` (floor boards: a structure along one axis only),
#: :func:`weave` (a basket weave, a regular pattern) and :func:`ripples` (sand ripples, quasi-periodic
#: across one direction); :func:`hexagons` (hexagonal floor tiles: a lattice no straight cut follows) and
#: :func:`wood` (wood grain: stripes whose phase meanders); :func:`ashlar` (a wall of courses of their own
#: heights: no period across them).
EXTRA = ("gravel_leaf", "grass_leaf", "gravel_lit", "paving_lit", "page", "gravel_oblique", "paving_oblique",
         "grass_oblique", "scales", "wall_turned", "tiles_turned", "roof", "coins", "pebbles", "planks", "weave",
         "ripples", "hexagons", "wood", "ashlar")


def _skimage(name):
    import skimage.data

    return getattr(skimage.data, name)().astype(np.float32) / 255.0


def _noise(shape, rng, sigma):
    from scipy import ndimage

    n = ndimage.gaussian_filter(rng.standard_normal(shape), sigma, mode="wrap")
    return n / n.std()


def paving(side: int = 512, *, cell: float = 44.0, rng=7) -> np.ndarray:
    """Irregular cobbles (a jittered Voronoi diagram) in mortar, RGB: each stone its own grey-brown,
    domed (lighter towards its middle), with fine grain; mortar darker and rough."""
    from scipy.spatial import cKDTree

    rng = np.random.default_rng(rng)
    n = int(np.ceil(side / cell)) + 2
    gy, gx = np.mgrid[-1:n - 1, -1:n - 1]
    pts = np.stack([gy.ravel(), gx.ravel()], axis=1) * cell + rng.uniform(0.15, 0.85, (gy.size, 2)) * cell
    yy, xx = np.mgrid[0:side, 0:side]
    d, idx = cKDTree(pts).query(np.stack([yy.ravel(), xx.ravel()], axis=1).astype(np.float64), k=2)
    edge = (d[:, 1] - d[:, 0]).reshape(side, side)  # distance to the cell's border, times about 2
    cell_id = idx[:, 0].reshape(side, side)
    base = rng.uniform(0.35, 0.7, len(pts))
    tint = rng.normal(0.0, 0.02, (len(pts), 3)) + np.array([0.04, 0.0, -0.05])
    dome = np.clip(edge / (0.5 * cell), 0.0, 1.0) ** 0.5
    grain = 0.05 * _noise((side, side), rng, 0.8) + 0.04 * _noise((side, side), rng, 3.0)
    stone = (base[cell_id] * (0.75 + 0.25 * dome) + grain)[:, :, None] + tint[cell_id]
    mortar_level = 0.22 + 0.05 * _noise((side, side), rng, 1.5)
    mortar = np.clip((4.0 - edge) / 2.0, 0.0, 1.0)[:, :, None]
    img = stone * (1.0 - mortar) + (mortar_level[:, :, None] + np.array([0.02, 0.02, 0.0])) * mortar
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def tiles(side: int = 512, *, period: int = 64, grout: int = 5, rng=11) -> np.ndarray:
    """A regular grid of square ceramic tiles in grout, RGB: each tile a slightly different
    terracotta, with mottling; a structured, periodic photo."""
    rng = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side]
    ty, tx = yy // period, xx // period
    k = ty * (side // period + 1) + tx
    colour = np.array([0.72, 0.42, 0.30]) + rng.normal(0.0, 0.035, (k.max() + 1, 3))
    mottle = 0.05 * _noise((side, side), rng, 4.0) + 0.03 * _noise((side, side), rng, 1.0)
    img = colour[k] * (1.0 + mottle[:, :, None])
    fy, fx = yy % period, xx % period
    g = (np.minimum(fy, period - 1 - fy) < grout / 2) | (np.minimum(fx, period - 1 - fx) < grout / 2)
    grout_colour = 0.78 + 0.04 * _noise((side, side), rng, 1.0)
    img[g] = grout_colour[g][:, None] * np.array([1.0, 0.97, 0.92])
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def with_leaf(photo: np.ndarray, cy: int, cx: int, r: float = 18.0) -> np.ndarray:
    """``photo`` (grey or RGB) as RGB with an orange leaf pasted on it (an ellipse ``r`` pixels long,
    centred at ``(cy, cx)``): content the photo shows once (issue 22's one-off content)."""
    rgb = np.repeat(photo[:, :, None], 3, axis=2) if photo.ndim == 2 else photo[:, :, :3]
    rgb = rgb.astype(np.float32).copy()
    yy, xx = np.mgrid[:rgb.shape[0], :rgb.shape[1]]
    rgb[((yy - cy) / r) ** 2 + ((xx - cx) / (0.45 * r)) ** 2 <= 1.0] = (0.85, 0.55, 0.1)
    return rgb


def lit(photo: np.ndarray, strength: float = 0.45) -> np.ndarray:
    """``photo`` under an uneven light: brightness falling by ``strength`` from the top left corner to the
    bottom right (0.6 of it along x, 0.4 along y) and a vignette (``0.78 strength`` darker at the corners
    than at the centre, relatively): a photo taken with the sun to one side and a plain lens. The
    default's drift is about 14 % RMS of log luma."""
    h, w = photo.shape[:2]
    y, x = np.mgrid[0:h, 0:w] / max(h, w)
    light = (1.0 - strength * (0.6 * x + 0.4 * y)) * (1.0 - 1.56 * strength * ((x - 0.5) ** 2 + (y - 0.5) ** 2))
    return (photo * (light[:, :, None] if photo.ndim == 3 else light)).astype(np.float32)


def oblique(photo: np.ndarray, far: float = 0.45, side: int = 512) -> np.ndarray:
    """``photo`` as ground seen at an angle, ``side`` pixels square: the photo mirrored into a plane 4 x 4
    times its size (mirrored, so that it continues without seams; its mirror lines show), seen by a camera
    pitched down, the ground at the top row magnified ``far`` times as much as at the bottom row along x
    and ``far ** 2`` along y (a plane's homography with the vanishing line above the photo): its grain
    shrinks towards the top, as in a photo of the ground taken standing."""
    from scipy import ndimage

    plane = np.concatenate([photo, photo[:, ::-1]], axis=1)
    plane = np.concatenate([plane, plane[::-1]], axis=0)
    plane = np.tile(plane, (2, 2) + ((1,) if photo.ndim == 3 else ()))
    h = plane.shape[0]
    yy, xx = np.mgrid[0:side, 0:side] / side
    d = 1.0 - (1.0 - far) * (1.0 - yy)  # magnification along x: far at the top, 1 at the bottom
    gx = ((xx - 0.5) / d) * side + plane.shape[1] / 2.0
    gy = h - 1.0 - ((1.0 - yy) / d) * side
    channels = [plane] if plane.ndim == 2 else [plane[:, :, c] for c in range(plane.shape[2])]
    out = [ndimage.map_coordinates(c.astype(np.float64), [gy, gx], order=1, mode="mirror") for c in channels]
    return (out[0] if plane.ndim == 2 else np.stack(out, axis=2)).astype(np.float32)


def scales(side: int = 512, cell: float = 22.0, jitter: float = 0.12, rng=3) -> np.ndarray:
    """A reptile's skin, RGB: domed scales on a hexagonal lattice (``cell`` pixels apart, each centre
    jittered by ``jitter`` of it) in dark crevices, coloured in patches larger than a scale (green to
    brown, with near-black blotches): a structure whose cells vary more in colour than their crevices
    stand out of the mean."""
    from scipy.spatial import cKDTree

    gen = np.random.default_rng(rng)
    n = int(side / cell) + 4
    pts = np.array([(r * 0.866 * cell, (c + 0.5 * (r % 2)) * cell) for r in range(-2, n) for c in range(-2, n)])
    pts = pts + gen.normal(0.0, jitter * cell, pts.shape)
    yy, xx = np.mgrid[0:side, 0:side]
    d, idx = cKDTree(pts).query(np.stack([yy.ravel(), xx.ravel()], axis=1).astype(np.float64), k=2)
    edge = (d[:, 1] - d[:, 0]).reshape(side, side)
    owner = idx[:, 0].reshape(side, side)
    pattern = _noise((side, side), gen, 30.0)
    at = pattern[np.clip(pts[:, 0].astype(int), 0, side - 1), np.clip(pts[:, 1].astype(int), 0, side - 1)][owner]
    t = np.clip(0.5 + 0.5 * at, 0.0, 1.0)[:, :, None]
    dark = np.array([0.12, 0.12, 0.08])
    base = np.array([0.35, 0.42, 0.2]) * t + np.array([0.45, 0.33, 0.2]) * (1.0 - t)
    base = np.where((at > 1.1)[:, :, None], dark + 0.05, base)
    dome = np.clip(edge / (0.5 * cell), 0.0, 1.0) ** 0.6
    img = base * (0.55 + 0.45 * dome[:, :, None]) + 0.02 * _noise((side, side), gen, 0.8)[:, :, None]
    crevice = np.clip((2.5 - edge) / 2.0, 0.0, 1.0)[:, :, None]
    return np.clip(img * (1.0 - crevice) + dark * crevice, 0.0, 1.0).astype(np.float32)


def running_bond(side: int = 768, rng=8) -> np.ndarray:
    """A running-bond wall, RGB: bricks 58 x 26 pixels (mortar 4), each its own red, with grain."""
    gen = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side].astype(np.float64)
    bh, bw, m = 26, 58, 4
    row = (yy // bh).astype(int)
    shift = np.where(row % 2 == 0, 0.0, bw / 2.0)
    _, inv = np.unique(row * 1000 + ((xx + shift) // bw).astype(int), return_inverse=True)
    colours = np.array([0.62, 0.30, 0.22]) * gen.uniform(0.75, 1.15, (inv.max() + 1, 1)) \
        + gen.normal(0.0, 0.02, (inv.max() + 1, 3))
    img = colours[inv.reshape(side, side)] * (1.0 + 0.06 * _noise((side, side), gen, 1.5))[:, :, None]
    mortar = (yy % bh < m) | ((xx + shift) % bw < m)
    img[mortar] = np.array([0.7, 0.68, 0.63]) * (1.0 + 0.05 * _noise((side, side), gen, 1.0))[mortar][:, None]
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def turned(photo: np.ndarray, angle: float, side: int = 512) -> np.ndarray:
    """The centre ``side`` x ``side`` of ``photo`` (RGB, at least ``1.5 side``) turned by ``angle`` degrees
    (cubic): a structure photographed turned, or laid at an angle."""
    from scipy import ndimage

    rot = np.stack([ndimage.rotate(photo[:, :, c].astype(np.float64), angle, reshape=False, order=3, mode="mirror")
                    for c in range(3)], axis=2)
    y0, x0 = (rot.shape[0] - side) // 2, (rot.shape[1] - side) // 2
    return np.clip(rot[y0:y0 + side, x0:x0 + side], 0.0, 1.0).astype(np.float32)


def roof(side: int = 512, width: float = 36.0, height: float = 28.0, rng=3) -> np.ndarray:
    """A roof of clay tiles, RGB: rows ``height`` pixels apart, each row's tiles ``width`` wide and offset
    by half a tile from the row above, rounded at their feet, each its own red and darker towards its top
    where the row above overlaps it, with black gaps between their feet: a structure whose darkest values
    are pure black (5.5% of the values at 0)."""
    gen = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side].astype(np.float64)
    img = np.zeros((side, side, 3))
    top = np.full((side, side), -np.inf)  # the row of the tile drawn at each pixel (later rows overlap)
    for r in range(-1, int(side / height) + 2):
        for c in range(-1, int(side / width) + 2):
            cx = c * width + (width / 2.0 if r % 2 else 0.0)
            cy = r * height
            foot = ((xx - cx) / (width / 2.0)) ** 2 + ((yy - cy - 0.2 * height) / (0.9 * height)) ** 2 < 1.0
            on = foot & (yy >= cy - 0.2 * height) & (cy > top)
            tone = np.array([0.55, 0.28, 0.18]) * gen.uniform(0.8, 1.15)
            shade = 0.7 + 0.3 * np.clip((yy[on] - cy) / height, 0.0, 1.0)
            img[on] = tone * shade[:, None]
            top[on] = cy
    img *= (1.0 + 0.04 * _noise((side, side), gen, 1.0))[:, :, None]
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def lawn() -> np.ndarray:
    """The lawn at the bottom right of scikit-image's ``camera()`` (132 x 132, grey), with the foot of
    the tripod at its lower left: a photo of grass holding one object."""
    return _skimage("camera")[380:512, 380:512]


def pebbles(side: int = 256) -> np.ndarray:
    """Large stones: scikit-image's gravel, its top-left 80 x 80 magnified 3.2 times (cubic), so that its
    stones are 30 to 60 pixels across, cut to ``side`` (a small photo of pebbles whose stones are larger than
    a quilt's overlap; softer than a photo, as any magnification is)."""
    from scipy import ndimage

    return np.clip(ndimage.zoom(_skimage("gravel")[:80, :80], 3.2, order=3), 0.0, 1.0)[:side, :side].astype(np.float32)


def planks(side: int = 512, board: float = 46.0, rng=5) -> np.ndarray:
    """A floor of wooden boards, RGB: rows ``board`` pixels high, each row's boards of random lengths
    (2 to 6 rows long) with dark joints, each board its own brown with a grain of fine streaks along the
    rows: a structure periodic across the rows only."""
    gen = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side].astype(np.float64)
    row = (yy // board).astype(int)
    img = np.zeros((side, side, 3))
    joint = np.zeros((side, side), bool)
    for r in range(int(side / board) + 1):
        on_row = row == r
        x = -gen.uniform(0.0, 5.0 * board)
        while x < side:
            length = gen.uniform(2.0, 6.0) * board
            on = on_row & (xx >= x) & (xx < x + length)
            tone = np.array([0.55, 0.36, 0.2]) * gen.uniform(0.75, 1.2) + gen.normal(0.0, 0.02, 3)
            phase = gen.uniform(0.0, 2.0 * np.pi)
            streak = 0.5 + 0.5 * np.sin(yy[on] * gen.uniform(0.5, 0.9) + 3.0 * np.sin(xx[on] / gen.uniform(40, 90))
                                        + phase)
            img[on] = tone * (0.85 + 0.2 * streak)[:, None]
            joint |= on & (np.abs(xx - x) < 1.5)
            x += length
    grain = 1.0 + 0.06 * _noise((side, side), gen, (0.6, 6.0))
    img *= grain[:, :, None]
    joint |= (yy % board) < 2.0
    img[joint] *= 0.35
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def ashlar(side: int = 512, heights=(28.0, 44.0, 64.0), rng=12) -> np.ndarray:
    """A wall of coursed ashlar, RGB: courses of the given heights in a random order (so no period across
    them), each course's stones of random lengths (1 to 3 times its height), each stone its own sandstone
    tone with a fine grain and edges a little darker, set in light mortar 3 pixels wide."""
    gen = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side].astype(np.float64)
    img = np.empty((side, side, 3))
    img[:] = (0.78, 0.76, 0.72)  # the mortar
    top = -gen.uniform(0.0, max(heights))
    while top < side:
        height = float(gen.choice(heights))
        x = -gen.uniform(0.0, 3.0 * height)
        while x < side:
            length = gen.uniform(1.0, 3.0) * height
            on = (yy >= top + 1.5) & (yy < top + height - 1.5) & (xx >= x + 1.5) & (xx < x + length - 1.5)
            tone = np.array([0.62, 0.55, 0.44]) * gen.uniform(0.8, 1.15) + gen.normal(0.0, 0.025, 3)
            # the stone's edges a little darker (a worn bevel), its face grained
            edge = np.minimum(np.minimum(yy[on] - top, top + height - yy[on]),
                              np.minimum(xx[on] - x, x + length - xx[on]))
            img[on] = tone * (0.88 + 0.12 * np.clip(edge / 6.0, 0.0, 1.0))[:, None]
            x += length
        top += height
    grain = 1.0 + 0.07 * _noise((side, side), gen, (0.7, 3.0))
    img *= grain[:, :, None]
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def weave(side: int = 512, strand: int = 16, rng=9) -> np.ndarray:
    """A basket weave, RGB: pairs of straw-coloured strands ``strand`` pixels wide going over and under
    each other in 2 x 2 checks, each strand shaded round across its width, with fibres along it: a regular
    pattern (period ``4 strand``)."""
    gen = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side].astype(np.float64)
    cy, cx = (yy // (2 * strand)).astype(int), (xx // (2 * strand)).astype(int)
    horizontal = (cy + cx) % 2 == 0
    across = np.where(horizontal, yy % strand, xx % strand) / strand  # 0-1 across the strand
    dome = np.sin(np.pi * across) ** 0.7
    fibres = np.where(horizontal, _noise((side, side), gen, (0.5, 8.0)), _noise((side, side), gen, (8.0, 0.5)))
    tone = 0.35 + 0.5 * dome + 0.05 * fibres
    img = tone[:, :, None] * np.array([0.85, 0.72, 0.45])
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def ripples(side: int = 512, wavelength: float = 38.0, rng=4, scale: float = 1.0) -> np.ndarray:
    """Sand ripples, RGB: crests about ``wavelength`` pixels apart running across the photo at about 20
    degrees, meandering, forking and varying in height, lit from one side (steep lee faces darker), with
    sand grain: quasi-periodic across one direction, not a lattice. ``scale``: the meanders' and heights'
    sizes times this (the ripples drawn larger; the grain stays a pixel's)."""
    gen = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side].astype(np.float64)
    a = np.deg2rad(20.0)
    u = xx * np.cos(a) + yy * np.sin(a)
    phase = (2.0 * np.pi * u / wavelength + 2.5 * _noise((side, side), gen, 60.0 * scale)
             + 1.5 * _noise((side, side), gen, 20.0 * scale))
    saw = (phase / (2.0 * np.pi)) % 1.0
    height = np.where(saw < 0.75, saw / 0.75, (1.0 - saw) / 0.25)  # a gentle stoss slope, a steep lee face
    amp = 0.75 + 0.25 * _noise((side, side), gen, 40.0 * scale)
    shade = 0.62 + 0.22 * amp * np.where(saw < 0.75, 1.0, -1.2) * 0.5 + 0.08 * height
    grain = 0.05 * _noise((side, side), gen, 0.7)
    img = (shade + grain)[:, :, None] * np.array([0.92, 0.8, 0.6])
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def hexagons(side: int = 512, across: float = 40.0, rng=21) -> np.ndarray:
    """Hexagonal floor tiles, RGB: ``across`` pixels between the centres of neighbouring tiles (a hexagonal
    lattice, rows along x), each tile its own shade of terracotta with fine grain, light grout about 2
    pixels wide. Its rectangular period is ``across`` by ``across * sqrt(3)``; no straight cut follows
    its grout."""
    gen = np.random.default_rng(rng)
    yy, xx = np.mgrid[0:side, 0:side].astype(np.float64)
    b1, b2 = np.array([across, 0.0]), np.array([across / 2.0, across * np.sqrt(3.0) / 2.0])
    to_lattice = np.linalg.inv(np.stack([b1, b2], axis=1))
    pts = np.stack([xx.ravel(), yy.ravel()])
    frac = to_lattice @ pts
    best = np.full(pts.shape[1], np.inf)
    second = np.full(pts.shape[1], np.inf)
    cell = np.zeros(pts.shape[1], dtype=np.int64)
    for di in (-1, 0, 1, 2):
        for dj in (-1, 0, 1, 2):
            i, j = np.floor(frac[0]) + di, np.floor(frac[1]) + dj
            d = np.hypot(*(pts - (np.outer(b1, i) + np.outer(b2, j))))
            nearer = d < best
            second = np.where(nearer, best, np.minimum(second, d))
            cell = np.where(nearer, (i + 1000).astype(np.int64) * 4096 + (j + 1000).astype(np.int64), cell)
            best = np.where(nearer, d, best)
    edge = ((second - best) / 2.0).reshape(side, side)  # distance to the tile's border
    _, ids = np.unique(cell, return_inverse=True)
    shade = gen.uniform(0.0, 1.0, ids.max() + 1)[ids].reshape(side, side)
    colour = (np.stack([0.55 + 0.25 * shade, 0.45 + 0.15 * shade, 0.35 + 0.1 * shade], axis=2)
              + 0.03 * _noise((side, side), gen, 1.0)[:, :, None])
    grout = np.clip(2.0 - edge, 0.0, 1.0)[:, :, None]
    img = colour * (1.0 - grout) + grout * np.array([0.85, 0.84, 0.8])
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def wood(side: int = 512, wavelength: float = 14.0, rng=6) -> np.ndarray:
    """Wood grain, RGB: light and dark stripes along x, ``wavelength`` pixels apart, whose phase meanders by
    several radians over about 40 pixels (the grain bends around knots), with fine grain: lines that run
    across the photo without a period a lattice could follow."""
    gen = np.random.default_rng(rng)
    yy = np.mgrid[0:side, 0:side][0].astype(np.float64)
    phase = 2.0 * np.pi * yy / wavelength + 4.0 * _noise((side, side), gen, 40.0) + 0.6 * _noise((side, side), gen, 8.0)
    stripe = (0.5 + 0.5 * np.sin(phase)) ** 3
    img = (np.array([0.62, 0.42, 0.25]) * (0.8 + 0.35 * stripe[:, :, None])
           + 0.03 * _noise((side, side), gen, 0.7)[:, :, None])
    return np.clip(img, 0.0, 1.0).astype(np.float32)


def _own_photo(path: str) -> np.ndarray:
    """A photo file as :func:`load` gives it: float32 in [0, 1], grey or RGB (an alpha band dropped)."""
    from spectex.io import read_image

    image = read_image(path, name="photo")
    if image.ndim == 3 and image.shape[2] in (2, 4):  # grey or RGB with alpha: the colour bands
        image = image[..., :-1] if image.shape[2] == 4 else image[..., 0]
    return image


def load(name: str) -> np.ndarray:
    """One exemplar by name (see :data:`NAMES`), or a photo of your own by its path (any name holding
    a ``/`` or ending in an image suffix: read by :func:`spectex.io.read_image`, an alpha band dropped),
    so that ``bench_fit_quality.py --only my/photos/a.jpg,my/photos/b.png`` measures your photos."""
    if "/" in name or name.lower().endswith((".png", ".jpg", ".jpeg", ".tif", ".tiff", ".npy")):
        return _own_photo(name)
    if name in ("gravel", "brick", "grass", "moon"):
        return _skimage(name)
    if name == "tissue":
        return _skimage("immunohistochemistry")
    if name == "deep_field":
        return _skimage("hubble_deep_field")[180:692, 240:752]
    if name == "paving":
        return paving()
    if name == "tiles":
        return tiles()
    if name == "gravel_leaf":
        return with_leaf(_skimage("gravel")[:256, :256], 150, 100)
    if name == "grass_leaf":
        return with_leaf(_skimage("grass")[:256, :256], 90, 170, r=24.0)
    if name == "gravel_lit":
        return lit(_skimage("gravel"))
    if name == "paving_lit":
        return lit(paving())
    if name == "page":
        return _skimage("page")
    if name == "coins":
        return _skimage("coins")
    made = {"scales": scales, "roof": roof, "pebbles": pebbles, "planks": planks, "weave": weave, "ripples": ripples,
            "hexagons": hexagons, "wood": wood, "ashlar": ashlar,
            "wall_turned": lambda: turned(running_bond(), 14.0),
            "tiles_turned": lambda: turned(tiles(side=800, period=48), 25.0)}
    if name in made:
        return made[name]()
    if name.endswith("_oblique") and name[:-8] in ("gravel", "paving", "grass"):
        return oblique(load(name[:-8]))
    raise ValueError(f"unknown exemplar {name!r}; one of {', '.join(NAMES + EXTRA)}")


def exemplars(quick: bool = False):
    """``[(name, image), ...]``: all of :data:`NAMES`, or :data:`QUICK` with ``quick``."""
    return [(name, load(name)) for name in (QUICK if quick else NAMES)]
