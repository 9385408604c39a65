"""Image quilting on real exemplars: the metrics, the controls, the pieces."""

import itertools

import numpy as np
import pytest
import skimage.data

from spectex import metrics
from spectex._seams import min_cut_path
from spectex.synthesis import quilt
from spectex.synthesis._quilting import _overlap_errors


def _exemplar(name, size=128):
    if name == "brick":  # large bricks: a 2x downscaled crop holds more of them
        full = skimage.data.brick()[:2 * size, :2 * size] / 255.0
        return full.reshape(size, 2, size, 2).mean(axis=(1, 3)).astype(np.float32)
    return (getattr(skimage.data, name)()[:size, :size] / 255.0).astype(np.float32)


@pytest.fixture(scope="module", params=["brick", "grass", "gravel"])
def case(request):
    ex = _exemplar(request.param)
    out = quilt(ex, (256, 256), block=32, rng=0)
    return request.param, ex, out


def test_histogram_and_band_power_match(case):
    name, ex, out = case
    assert out.shape == (256, 256) and out.dtype == np.float32
    assert metrics.histogram_w1(ex, out)[0] <= 0.03
    assert metrics.band_power_distance(ex, out) <= 1.5


def test_no_repetition_at_the_exemplar_period_and_tiling_fails(case):
    name, ex, out = case
    assert metrics.repetition(out, ex.shape) <= 0.01
    assert metrics.verbatim_copy(out, ex) <= 0.1
    tiled = np.tile(ex, (2, 2))  # the control: plain tiling
    assert metrics.repetition(tiled, ex.shape) > 0.9
    assert metrics.verbatim_copy(tiled, ex) > 0.2


@pytest.mark.parametrize("name", ["brick", "grass", "gravel"])
def test_seams_like_the_interior_and_random_blocks_fail(name):
    ex = _exemplar(name)
    out = quilt(ex, (256, 256), block=32, overlap=5, rng=1)
    assert metrics.seam_energy(out, 32, 5) <= 1.2
    # the control: blocks chosen at random and pasted without overlap or cut
    rng = np.random.default_rng(1)
    mosaic = np.zeros_like(out)
    for y, x in itertools.product(range(0, 256, 32), repeat=2):
        sy, sx = rng.integers(0, 97, size=2)
        mosaic[y:y + 32, x:x + 32] = ex[sy:sy + 32, sx:sx + 32]
    assert metrics.seam_energy(mosaic, 32) > 1.5


@pytest.mark.parametrize("name", ["brick", "grass", "gravel"])
def test_tileable_when_asked(name):
    ex = _exemplar(name)
    plain = quilt(ex, (160, 192), block=32, rng=2)
    tiled = quilt(ex, (160, 192), block=32, rng=2, tileable=True)
    assert tiled.shape == (160, 192)
    assert metrics.tileability(tiled) <= 2.0  # interior row steps spread over 0.4 to 2.1
    assert metrics.tileability(plain) > 2.5
    assert metrics.histogram_w1(ex, tiled)[0] <= 0.03
    # the wrap edge is no worse than the seams inside: a 2 x 2 tiling of the
    # tile has its seams at the tile size, with the tile's own seam energy
    assert metrics.band_power_distance(ex, np.tile(tiled, (2, 2))) <= 1.5


def test_same_seed_same_output_colour():
    ex = np.stack([_exemplar("gravel", 64), _exemplar("grass", 64), _exemplar("brick", 64)], axis=2)
    a = quilt(ex, (80, 100), block=16, rng=7)
    b = quilt(ex, (80, 100), block=16, rng=7)
    c = quilt(ex, (80, 100), block=16, rng=8)
    assert a.shape == (80, 100, 3)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    assert np.all(metrics.histogram_w1(ex, a) <= 0.05)


def test_batched_blocks_give_the_block_by_block_quilt(monkeypatch):
    import spectex.synthesis._quilting as module

    ex = np.stack([_exemplar("gravel", 64), _exemplar("grass", 64), _exemplar("brick", 64)], axis=2)
    batched = quilt(ex, (90, 110), block=16, overlap=3, rng=4)
    monkeypatch.setattr(module, "_BATCH", False)
    np.testing.assert_array_equal(batched, quilt(ex, (90, 110), block=16, overlap=3, rng=4))


def test_every_pixel_comes_from_the_exemplar():
    ex = _exemplar("gravel", 48)
    out = quilt(ex, (70, 70), block=12, overlap=3, rng=3)
    assert np.isin(out, ex).all()


def test_fft_overlap_error_equals_direct_sum():
    rng = np.random.default_rng(0)
    ex = rng.random((20, 23, 2)).astype(np.float32)
    b = 6
    known = np.zeros((b, b), dtype=bool)
    known[:, :2] = True
    known[:2, :] = True
    tmpl = rng.random((b, b, 2)).astype(np.float32)
    masked = tmpl * known[:, :, None]
    import scipy.fft as sfft

    fh, fw = 20, 24
    f_ex = sfft.rfft2(np.moveaxis(ex, 2, 0), s=(fh, fw), axes=(1, 2))
    f_sq = sfft.rfft2(np.sum(ex.astype(np.float64) ** 2, axis=2).astype(np.float32), s=(fh, fw))
    pad = np.zeros((fh, fw), dtype=np.float32)
    pad[:b, :b] = known
    term = f_sq * np.conj(sfft.rfft2(pad))
    err = _overlap_errors(f_ex, term[None], masked[None], (fh, fw), (20 - b + 1, 23 - b + 1))[0]
    direct = np.empty_like(err)
    for y in range(err.shape[0]):
        for x in range(err.shape[1]):
            d = (ex[y:y + b, x:x + b] - tmpl) ** 2
            direct[y, x] = np.sum(d * known[:, :, None])
    np.testing.assert_allclose(err, direct, atol=1e-4)


def test_min_cut_is_the_cheapest_path():
    rng = np.random.default_rng(4)
    cost = rng.random((5, 4))
    best = np.inf
    for start in range(4):
        for moves in itertools.product((-1, 0, 1), repeat=4):
            path = [start]
            for m in moves:
                path.append(path[-1] + m)
            if min(path) < 0 or max(path) > 3:
                continue
            best = min(best, sum(cost[i, p] for i, p in enumerate(path)))
    path = min_cut_path(cost)
    assert np.all(np.abs(np.diff(path)) <= 1)
    assert cost[np.arange(5), path].sum() == pytest.approx(best)


@pytest.mark.parametrize("kwargs, message", [
    ({"block": 200}, "exemplar of 128x128 pixels is smaller than block=200"),
    ({"block": 32, "overlap": 32}, "overlap must be smaller than block=32, got 32"),
    ({"block": 32, "overlap": 0}, "overlap must be >= 1, got 0"),
    ({"block": 32, "overlap": 16, "tileable": True}, "overlap must be smaller than block/2=16"),
    ({"tolerance": -1.0}, "tolerance must be >= 0.0, got -1.0"),
    ({"rng": -3}, "rng must be >= 0, got -3"),
])
def test_bad_arguments_name_parameter_and_value(kwargs, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        quilt(_exemplar("grass"), (64, 64), **kwargs)


def test_tileable_output_too_small_is_an_error():
    with pytest.raises(ValueError, match="width=20 is too small for a tileable quilt"):
        quilt(_exemplar("grass"), (64, 20), block=32, tileable=True)


def test_reuse_penalty_keeps_any_source_cell_from_dominating(monkeypatch):
    # issue 22 (5): count the source positions the quilt picks (cells of half a block); with the
    # reuse penalty the most-used cell supplies under 6% of the blocks; the control (no penalty)
    # lets one cell supply over 10% (26 of 168 blocks on this grass crop)
    import collections

    import spectex.synthesis._cut as cut

    ex = skimage.data.grass()[:96, :96].astype(np.float32) / 255.0
    original = cut.place_block
    shares = {}
    used = []

    def record(*args):
        used.append(original(*args))
        return used[-1]

    monkeypatch.setattr(cut, "place_block", record)
    for reuse in (0.0, 1.0):
        used.clear()
        quilt(ex, (256, 256), block=24, tileable=True, rng=0, reuse=reuse)
        cells = collections.Counter((y // 12, x // 12) for y, x in used)
        shares[reuse] = cells.most_common(1)[0][1] / len(used)
    assert shares[1.0] < 0.06
    assert shares[0.0] > 0.10
    with pytest.raises(ValueError, match="reuse"):
        quilt(ex, (64, 64), block=24, reuse=-1.0)
