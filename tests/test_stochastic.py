"""spectex.stochastic: histogram-preserving tiling and blending against a direct NumPy route, and controls."""

import math

import numpy as np
import pytest
from scipy.special import ndtr

from spectex import metrics
from spectex.sampling import MipTexture, quantize, sample
from spectex.shading.constants import WEIGHT_SQUARINGS
from spectex.shading.stochastic import (
    GAUSS_SCALE,
    LUT_SIZE,
    StochasticTables,
    decorrelation,
    gaussianize,
    layer_key,
    lowbias32,
    sample_stochastic,
    stochastic_tables,
    triangle_grid_matrix,
)
from spectex.tiles import make_tile


@pytest.fixture(scope="module")
def tile():
    return quantize(make_tile(128, rng=3), 8)


@pytest.fixture(scope="module")
def tables(tile):
    return stochastic_tables(tile)


# ---------------------------------------------------------------- a direct NumPy route

def _np_level(level, s, t):
    """Bilinear REPEAT sampling of one level (OpenGL's texel centres), written out in NumPy."""
    h, w = level.shape[:2]
    u = s * w - 0.5
    v = t * h - 0.5
    i0 = np.floor(u).astype(np.int64)
    j0 = np.floor(v).astype(np.int64)
    a = (u - i0)[..., None]
    b = (v - j0)[..., None]
    i1, j1 = (i0 + 1) % w, (j0 + 1) % h
    i0, j0 = i0 % w, j0 % h
    return ((1 - a) * (1 - b) * level[j0, i0] + a * (1 - b) * level[j0, i1]
            + (1 - a) * b * level[j1, i0] + a * b * level[j1, i1])


def _np_stochastic(tables, s, t, lod, patch, seed):
    """Heitz and Neyret's formulas, trilinear, from the tables' arrays, without any spectex kernel."""
    levels = [lv.astype(np.float64) for lv in tables.gaussian]
    q = len(levels) - 1
    # triangle grid: skewed coordinates, cell, the triangle's vertices and barycentric weights
    kx = (s - t / math.sqrt(3.0)) / patch
    ky = (2.0 * t / math.sqrt(3.0)) / patch
    ci, cj = np.floor(kx), np.floor(ky)
    fx, fy = kx - ci, ky - cj
    lower = fx + fy < 1.0
    verts = [(np.where(lower, ci, ci + 1), np.where(lower, cj, cj + 1), np.where(lower, 1 - fx - fy, fx + fy - 1)),
             (np.where(lower, ci + 1, ci), np.where(lower, cj, cj + 1), np.where(lower, fx, 1 - fx)),
             (np.where(lower, ci, ci + 1), np.where(lower, cj + 1, cj), np.where(lower, fy, 1 - fy))]
    key = np.uint32(lowbias32(np.uint32(seed)))
    lam = np.clip(lod, 0.0, q)
    # the sharpened weights: w^(2^e) renormalised to sum 1, e = clamp(log2(patch in texels) - lambda, 0,
    # WEIGHT_SQUARINGS) (2^e the patch's width in pixels), the linear mix of the two whole powers about it
    e = np.clip(math.log2(levels[0].shape[1] * patch) - lam, 0.0, WEIGHT_SQUARINGS)
    ke = np.floor(e)

    def powered(k):
        total = sum(w ** (2.0 ** k) for _, _, w in verts)
        return [w ** (2.0 ** k) / total for _, _, w in verts]

    lo, hi = powered(ke), powered(ke + 1)
    verts = [(vi, vj, a + (e - ke) * (b - a)) for (vi, vj, _), a, b in zip(verts, lo, hi)]
    d1 = np.minimum(np.floor(lam).astype(np.int64), q)
    beta = (lam - d1)[..., None]
    acc = 0.0
    norm = 0.0
    sources = []
    for vi, vj, w in verts:
        h = lowbias32(vi.astype(np.int64).astype(np.uint32) ^ lowbias32(vj.astype(np.int64).astype(np.uint32) ^ key))
        w0, h0 = levels[0].shape[1], levels[0].shape[0]
        ox = np.floor((h & 0xFFFF) / 65536.0 * w0) / w0
        oy = np.floor((h >> 16) / 65536.0 * h0) / h0
        g = np.empty(s.shape + (4,))
        for d in range(q + 1):
            sel = d1 == d
            if sel.any():
                lo = _np_level(levels[d], s[sel] + ox[sel], t[sel] + oy[sel])
                hi = _np_level(levels[min(d + 1, q)], s[sel] + ox[sel], t[sel] + oy[sel])
                g[sel] = lo + beta[sel] * (hi - lo)
        acc = acc + w[..., None] * (g - 0.5)
        norm = norm + w * w
        sources.append(g)
    # kept per channel between the three patches' values (stochastic.keep_between)
    gb = np.clip(0.5 + acc / np.sqrt(norm)[..., None], np.minimum.reduce(sources), np.maximum.reduce(sources))
    # the expanded table: nearest of 8 rows per level step, nearest of LUT_SIZE entries
    table = tables.expanded()
    row = np.floor(lam * 8 + 0.5).astype(np.int64)
    entry = np.floor(np.clip(gb, 0.0, 1.0) * (LUT_SIZE - 1) + 0.5).astype(np.int64)
    v = np.stack([table[row, entry[:, c], c] for c in range(4)], axis=1).astype(np.float64)
    rgb = tables.origin + v[:, :3] @ tables.basis.T
    return np.clip(np.concatenate([rgb, v[:, 3:]], axis=1), 0.0, 1.0)


def test_kernel_agrees_with_the_direct_numpy_formulas(tables):
    rng = np.random.default_rng(1)
    n = 3000
    s = rng.uniform(-40.0, 40.0, n)
    t = rng.uniform(-40.0, 40.0, n)
    lod = rng.uniform(-1.0, len(tables.gaussian) + 0.5, n)
    for patch, seed in ((0.5, 0), (0.3, 12345)):
        ours = sample_stochastic(tables, s, t, lod=lod, patch=patch, seed=seed)
        ref = _np_stochastic(tables, s, t, lod, patch, seed)
        diff = np.abs(ours - ref)
        # Kept between its sources, the blended value often equals a quantised texel's exactly,
        # where the table's nearest entry is a tie: the float32 kernel and this float64 route may
        # take neighbouring entries there (1 sample in 6000, in alpha). Anywhere else: the same.
        step = float(np.abs(np.diff(tables.expanded(), axis=1)).max())
        assert np.mean(diff > 2e-4) <= 1e-3 and diff.max() <= step + 2e-4, (np.mean(diff > 2e-4), diff.max())


def test_a_grid_vertex_shows_the_tile_texel_its_offset_points_to(tile, tables):
    # at a vertex, one patch has weight 1: the blend is that patch's Gaussian value, and the
    # level-0 table inverts it: the tile's own texel comes back (to the table's resolution)
    grid = triangle_grid_matrix(0.5)
    ij = np.random.default_rng(2).integers(-1000, 1000, size=(4000, 2))
    st = ij @ np.linalg.inv(grid).T
    out = sample_stochastic(tables, st[:, 0], st[:, 1], patch=0.5, seed=7, lod=0.0, filter="nearest")
    key = np.uint32(layer_key(7))
    h = lowbias32(ij[:, 0].astype(np.uint32) ^ lowbias32(ij[:, 1].astype(np.uint32) ^ key))
    # offsets are whole texels: floor(u * 128) / 128
    col = (np.floor(st[:, 0] * 128).astype(np.int64) + np.floor((h & 0xFFFF) / 65536.0 * 128).astype(np.int64)) % 128
    row = (np.floor(st[:, 1] * 128).astype(np.int64) + np.floor((h >> 16) / 65536.0 * 128).astype(np.int64)) % 128
    err = np.abs(out - tile[row, col])
    assert err.max() < 3.0 / 255.0
    assert err.mean() < 0.3 / 255.0
    # control: the texel the un-offset coordinates point to is not it
    plain = tile[np.floor(st[:, 1] * 128).astype(np.int64) % 128, np.floor(st[:, 0] * 128).astype(np.int64) % 128]
    assert np.abs(out - plain).mean() > 20.0 / 255.0


# ---------------------------------------------------------------- the tables

def test_gaussianize_gives_the_normal_quantiles_and_keeps_ties():
    values = np.random.default_rng(3).random(10000) ** 3
    g = gaussianize(values)
    z = (g - 0.5) / GAUSS_SCALE
    assert np.all(np.diff(g[np.argsort(values)]) > 0)
    assert abs(z.mean()) < 1e-9 and z.std() == pytest.approx(1.0, abs=0.01)
    # Kolmogorov distance to the standard normal
    zs = np.sort(z)
    assert np.max(np.abs(ndtr(zs) - (np.arange(zs.size) + 0.5) / zs.size)) < 1e-6
    tied = gaussianize(np.array([0.2, 0.7, 0.2, 0.7, 0.2]))
    assert tied[0] == tied[2] == tied[4] and tied[1] == tied[3] and tied[0] < tied[1]
    assert np.all(gaussianize(np.full(7, 0.4)) == 0.5)


def test_decorrelation_is_orthonormal_and_decorrelates(tile):
    basis, origin = decorrelation(tile)
    assert np.allclose(basis.T @ basis, np.eye(3), atol=1e-12)
    v = (tile[:, :, :3].reshape(-1, 3) - origin) @ basis
    cov = np.cov(v.T)
    assert np.max(np.abs(cov - np.diag(np.diag(cov)))) < 1e-9
    assert np.all(np.diff(np.diag(cov)) <= 0)
    assert np.allclose(origin, tile[:, :, :3].reshape(-1, 3).mean(axis=0, dtype=np.float64), atol=1e-12)


def test_tables_are_deterministic_monotone_and_end_at_the_mean(tile, tables):
    again = stochastic_tables(tile.copy())
    assert np.array_equal(again.lut, tables.lut)
    assert all(np.array_equal(a, b) for a, b in zip(again.gaussian, tables.gaussian))
    assert isinstance(tables, StochasticTables) and tables.lut.shape == (8, LUT_SIZE, 4)
    assert np.all(np.diff(tables.lut, axis=1) >= 0)
    # half floats: what an RGBA16F texture holds
    for level in tables.gaussian:
        assert np.array_equal(level, level.astype(np.float16).astype(np.float32))
    # the last level: one texel, the table maps everything to the tile's mean
    mean = tile.reshape(-1, 4).mean(axis=0)
    last = tables.origin + tables.lut[-1, :, :3] @ tables.basis.T
    assert np.allclose(last, mean[:3], atol=5e-4)
    assert np.allclose(tables.lut[-1, :, 3], mean[3], atol=5e-4)
    out = sample_stochastic(tables, np.linspace(-3, 3, 50), np.linspace(5, -1, 50), lod=20.0)
    assert np.allclose(out, mean, atol=5e-4)


def test_tables_pool_half_float_values_as_np_unique_does(tile, tables, monkeypatch):
    # the tables' pooling of equal Gaussian values counts half floats' bit patterns instead of sorting:
    # the same keys, inverse and counts as np.unique (ties, 0 and -0 included), np.unique itself where
    # a value is no half float; and the same tables to the bit as with np.unique
    import spectex.shading.stochastic as st

    gen = np.random.default_rng(3)
    half = np.clip(0.5 + 0.16 * gen.standard_normal(20000), 0.0, 1.0).astype(np.float16).astype(np.float64)
    half[:4] = [0.0, -0.0, 1.0, 0.5]
    for g in (half, half + 1e-9, half[:100]):
        ours, reference = st._pooled(g), np.unique(g, return_inverse=True, return_counts=True)
        assert all(np.array_equal(a.ravel(), b.ravel()) for a, b in zip(ours, reference))
    assert len(np.unique(half)) < 20000 / 4  # the control: many ties to pool
    monkeypatch.setattr(st, "_pooled", lambda g: np.unique(g, return_inverse=True, return_counts=True))
    before = stochastic_tables(tile.copy())
    assert np.array_equal(before.lut, tables.lut)


def test_coarse_rows_regress_the_filtered_colour_on_the_filtered_gaussian(tile, tables):
    # level 3: the table predicts each filtered colour texel from its filtered Gaussian texel
    # better than the level-0 table applied to it (the unfiltered look-up: the paper's colour shift)
    from spectex.tiles import mip_chain

    d = 3
    v = np.concatenate([(tile[:, :, :3] - tables.origin) @ tables.basis, tile[:, :, 3:]], axis=2)
    target = mip_chain(v.astype(np.float32))[d].reshape(-1, 4)
    g = tables.gaussian[d].reshape(-1, 4)
    grid = np.linspace(0.0, 1.0, LUT_SIZE)
    own = np.stack([np.interp(g[:, c], grid, tables.lut[d, :, c]) for c in range(4)], axis=1)
    unfiltered = np.stack([np.interp(g[:, c], grid, tables.lut[0, :, c]) for c in range(4)], axis=1)
    err_own = np.mean((own - target) ** 2)
    err_unf = np.mean((unfiltered - target) ** 2)
    assert err_own < 0.5 * err_unf


# ---------------------------------------------------------------- what it is for

def _bake(tables, n, px, patch=0.5, seed=0):
    r, c = np.mgrid[0:n, 0:n]
    return sample_stochastic(tables, (c + 0.5) / px, (r + 0.5) / px, patch=patch, seed=seed,
                             dsdx=1.0 / px, dtdx=0.0, dsdy=0.0, dtdy=1.0 / px)


def test_no_repeat_where_plain_tiling_repeats():
    tile = quantize(make_tile(512, rng=1), 8)
    tables = stochastic_tables(tile)
    stochastic = _bake(tables, 1024, 64)
    assert metrics.repeat_peak(stochastic) <= 0.1
    r, c = np.mgrid[0:1024, 0:1024]
    periodic = sample(MipTexture.from_image(tile, bits=None), (c + 0.5) / 64, (r + 0.5) / 64,
                      dsdx=1 / 64, dtdx=0.0, dsdy=0.0, dtdy=1 / 64)
    assert metrics.repeat_peak(periodic) > 0.99


def test_histogram_preserved_where_a_linear_blend_is_not():
    # a bimodal tile (dark blobs on a light ground): the histogram-preserving blend keeps its two
    # modes; the same triangle grid with a plain linear blend of the colours fills the gap between them
    from scipy import ndimage

    rng = np.random.default_rng(4)
    field = ndimage.gaussian_filter(rng.standard_normal((128, 128)), 3.0, mode="wrap")
    grey = np.where(field > 0, 0.8, 0.2) + 0.03 * rng.standard_normal((128, 128))
    tile = quantize(np.repeat(np.clip(grey, 0, 1)[:, :, None], 3, axis=2), 8)
    tables = stochastic_tables(tile)
    out = _bake(tables, 512, 128, patch=0.5)
    w1 = metrics.histogram_w1(out[:, :, :3], tile)
    assert np.all(w1 < 0.02)
    # control: a linear blend of the three patches (no Gaussianisation, no variance correction)
    r, c = np.mgrid[0:512, 0:512]
    s, t = (c + 0.5) / 128, (r + 0.5) / 128
    linear = _linear_blend(tile, s, t, 0.5)
    assert np.all(metrics.histogram_w1(linear, tile) > 5.0 * w1)


def _linear_blend(tile, s, t, patch):
    """Tiling and blending with the same grid and offsets, colours blended linearly."""
    kx = (s - t / math.sqrt(3.0)) / patch
    ky = (2.0 * t / math.sqrt(3.0)) / patch
    ci, cj = np.floor(kx), np.floor(ky)
    fx, fy = kx - ci, ky - cj
    lower = fx + fy < 1.0
    verts = [(np.where(lower, ci, ci + 1), np.where(lower, cj, cj + 1), np.where(lower, 1 - fx - fy, fx + fy - 1)),
             (np.where(lower, ci + 1, ci), np.where(lower, cj, cj + 1), np.where(lower, fx, 1 - fx)),
             (np.where(lower, ci, ci + 1), np.where(lower, cj + 1, cj), np.where(lower, fy, 1 - fy))]
    key = np.uint32(layer_key(0))
    out = 0.0
    for vi, vj, w in verts:
        h = lowbias32(vi.astype(np.int64).astype(np.uint32) ^ lowbias32(vj.astype(np.int64).astype(np.uint32) ^ key))
        out = out + w[..., None] * _np_level(tile[:, :, :3].astype(np.float64), s + (h & 0xFFFF) / 65536.0,
                                             t + (h >> 16) / 65536.0)
    return out


def test_seed_changes_the_layout_and_inputs_are_checked(tables):
    s = np.linspace(0, 5, 200)
    a = sample_stochastic(tables, s, s[::-1], lod=0.0, seed=1)
    b = sample_stochastic(tables, s, s[::-1], lod=0.0, seed=2)
    assert np.abs(a - b).mean() > 0.02
    assert np.array_equal(a, sample_stochastic(tables, s, s[::-1], lod=0.0, seed=1))
    with pytest.raises(ValueError, match="patch"):
        sample_stochastic(tables, 0.0, 0.0, patch=0.0)
    with pytest.raises(ValueError, match="seed"):
        sample_stochastic(tables, 0.0, 0.0, seed=-1)
    with pytest.raises(TypeError, match="tables"):
        sample_stochastic(np.zeros((4, 4, 4)), 0.0, 0.0)
    with pytest.raises(ValueError, match="finite"):
        sample_stochastic(tables, np.nan, 0.0)
    with pytest.raises(ValueError, match="derivatives"):
        sample_stochastic(tables, 0.0, 0.0, dsdx=1.0)


def test_expanded_table_rows_interpolate_the_levels(tables):
    from spectex.shading.stochastic import expand_lut

    table = expand_lut(tables.lut)
    assert table.shape == ((tables.levels - 1) * 8 + 1, LUT_SIZE, 4)
    assert np.array_equal(table[::8], tables.lut)
    mid = 0.625 * tables.lut[2] + 0.375 * tables.lut[3]
    assert np.allclose(table[2 * 8 + 3], mid, atol=1e-3)
    assert np.array_equal(table, table.astype(np.float16).astype(np.float32))


def test_weights_follow_the_patch_width_in_pixels():
    """The blend's weights are the barycentric ones to the power 2^e, e = log2(patch texels) - lambda
    clamped to [0, WEIGHT_SQUARINGS]: the power 8 while a patch is 8 pixels wide or more, 1 (barycentric)
    once it spans a pixel, continuous in lambda (no popping). The rule before 2026-11-26 dropped to the
    barycentric weights by lambda = 3 whatever the patch: a 256-texel patch, 32 pixels wide there, was a
    cross-fade of three (the control)."""
    from spectex.shading.stochastic import sharpen_weights

    w = (0.5, 0.3, 0.2)
    power = 2 ** WEIGHT_SQUARINGS
    sharp = np.array(w) ** power / np.sum(np.array(w) ** power)
    plod = 8.0  # a 256-texel patch
    for lam in (-1.0, 0.0, 3.0, plod - WEIGHT_SQUARINGS):
        np.testing.assert_allclose(sharpen_weights(*w, lam, plod), sharp, rtol=1e-12)
    for lam in (plod, plod + 2.0):
        np.testing.assert_allclose(sharpen_weights(*w, lam, plod), w, rtol=1e-12)
    # the power 2^e between: e = 1.5 mixes the squares and the fourth powers, each renormalised
    sq, qu = np.array(w) ** 2 / np.sum(np.array(w) ** 2), np.array(w) ** 4 / np.sum(np.array(w) ** 4)
    np.testing.assert_allclose(sharpen_weights(*w, plod - 1.5, plod), 0.5 * (sq + qu), rtol=1e-12)
    # continuous: no step across the whole powers
    lams = np.linspace(plod - WEIGHT_SQUARINGS - 0.5, plod + 0.5, 801)
    ws = np.array([sharpen_weights(*w, lam, plod) for lam in lams])
    assert np.abs(np.diff(ws, axis=0)).max() < 0.01
    np.testing.assert_allclose(ws.sum(axis=1), 1.0, rtol=1e-12)
    # the control: at lambda = 3 the old rule's weights were barycentric, these are still the power 8
    assert np.abs(np.array(sharpen_weights(*w, 3.0, plod)) - np.array(w)).max() > 0.2
