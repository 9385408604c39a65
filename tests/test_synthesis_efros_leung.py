"""Efros-Leung on real exemplars; the search kernel against a NumPy reference."""

import numpy as np
import pytest
import skimage.data

from spectex import metrics
from spectex.synthesis import efros_leung
from spectex.synthesis._efros_leung import _fill_round, _gaussian


def _exemplar(name, size=64, at=(0, 0)):
    if name == "brick":  # a 2x downscaled crop holds more bricks
        full = skimage.data.brick()[:2 * size, :2 * size] / 255.0
        return full.reshape(size, 2, size, 2).mean(axis=(1, 3)).astype(np.float32)
    img = getattr(skimage.data, name)() / 255.0
    return img[at[0]:at[0] + size, at[1]:at[1] + size].astype(np.float32)


@pytest.mark.parametrize("name", ["brick", "grass", "gravel"])
def test_fast_default_matches_the_exemplar(name):
    ex = _exemplar(name)
    out = efros_leung(ex, (96, 96), window=11, rng=0)
    assert out.shape == (96, 96) and out.dtype == np.float32
    assert np.isin(out, ex).all()  # every pixel is copied from the exemplar
    assert metrics.histogram_w1(ex, out)[0] <= 0.03
    assert metrics.band_power_distance(ex, out) <= 1.5
    assert metrics.repetition(out, ex.shape) <= 0.01


def test_exhaustive_matches_the_exemplar_too():
    ex = _exemplar("grass", 48)
    out = efros_leung(ex, (56, 56), window=9, method="exhaustive", rng=1)
    assert metrics.histogram_w1(ex, out)[0] <= 0.03
    assert metrics.band_power_distance(ex, out) <= 1.5


def test_white_noise_control_fails_band_power():
    from spectex.synthesis import sample_histogram

    ex = _exemplar("gravel")
    noise = sample_histogram(ex, (96, 96), rng=0)
    assert metrics.histogram_w1(ex, noise)[0] <= 0.03
    assert metrics.band_power_distance(ex, noise) > 1.5


def test_tileable_when_asked():
    ex = _exemplar("gravel", at=(200, 300))
    plain = efros_leung(ex, (72, 72), window=9, rng=2)
    torus = efros_leung(ex, (72, 72), window=9, rng=2, tileable=True)
    assert metrics.tileability(torus) <= 2.0
    assert metrics.tileability(plain) > 2.5


def test_colour_and_determinism():
    ex = np.stack([_exemplar("gravel", 40), _exemplar("grass", 40), _exemplar("brick", 40)], axis=2)
    a = efros_leung(ex, (44, 50), window=7, rng=5)
    b = efros_leung(ex, (44, 50), window=7, rng=5)
    c = efros_leung(ex, (44, 50), window=7, rng=6)
    assert a.shape == (44, 50, 3)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    # whole colours are copied: every output colour is an exemplar colour
    colours = {tuple(p) for p in ex.reshape(-1, 3)}
    assert all(tuple(p) in colours for p in a.reshape(-1, 3))


def _kernel_state(seed=0):
    rng = np.random.default_rng(seed)
    ex = rng.random((14, 15, 2)).astype(np.float32)
    out = np.zeros((9, 9, 2), dtype=np.float32)
    filled = np.zeros((9, 9), dtype=np.bool_)
    src = np.full((9, 9, 2), -1, dtype=np.int64)
    for y, x in [(3, 3), (3, 4), (4, 3), (2, 5), (5, 5), (4, 6)]:
        sy, sx = rng.integers(0, 14), rng.integers(0, 15)
        out[y, x] = ex[sy, sx]
        src[y, x] = sy, sx
        filled[y, x] = True
    return ex, out, filled, src


def _numpy_errors(ex, out, filled, y, x, window):
    """Normalised Gaussian-weighted SSD of every valid window, the slow way."""
    half = window // 2
    g = _gaussian(window)
    errs = []
    for cy in range(half, ex.shape[0] - half):
        for cx in range(half, ex.shape[1] - half):
            s = wsum = 0.0
            for dy in range(-half, half + 1):
                for dx in range(-half, half + 1):
                    yy, xx = y + dy, x + dx
                    if 0 <= yy < out.shape[0] and 0 <= xx < out.shape[1] and filled[yy, xx]:
                        w = g[dy + half, dx + half]
                        s += w * np.sum((out[yy, xx].astype(np.float64) - ex[cy + dy, cx + dx]) ** 2)
                        wsum += w
            errs.append(s / (wsum * ex.shape[2]))
    return np.array(errs)


@pytest.mark.parametrize("uniform", [0.0, 0.999999])
def test_exhaustive_kernel_picks_from_the_numpy_near_best_set(uniform):
    ex, out, filled, src = _kernel_state()
    window, half, y, x = 5, 2, 4, 4
    errs = _numpy_errors(ex, out, filled, y, x, window)
    near = np.flatnonzero(errs <= errs.min() * 1.1)
    expected = near[0] if uniform == 0.0 else near[-1]
    vw = ex.shape[1] - 2 * half
    done = _fill_round(ex, out, filled, src, np.array([y]), np.array([x]), _gaussian(window), half, False,
                       np.zeros((1, 0), np.int64), True, np.array([uniform]), np.zeros((1, 0), np.int64),
                       0.1, 0.3, np.zeros(1, np.int64), 0)
    assert done == 1 and filled[y, x]
    assert tuple(src[y, x]) == (expected // vw + half, expected % vw + half)
    np.testing.assert_array_equal(out[y, x], ex[src[y, x, 0], src[y, x, 1]])


def test_kernel_respects_the_error_threshold():
    ex, out, filled, src = _kernel_state(1)
    done = _fill_round(ex, out, filled, src, np.array([4]), np.array([4]), _gaussian(5), 2, False,
                       np.zeros((1, 0), np.int64), True, np.array([0.5]), np.zeros((1, 0), np.int64),
                       0.1, 1e-9, np.zeros(1, np.int64), 0)
    assert done == 0 and not filled[4, 4]


def test_fast_kernel_finds_the_exact_continuation():
    # Neighbours copied coherently from one exemplar place: the fast search's
    # coherent candidate has error 0, as the exhaustive search finds.
    ex, out, filled, src = _kernel_state(2)
    filled[:] = False
    for y in range(2, 5):
        for x in range(2, 7):
            out[y, x] = ex[y + 4, x + 3]
            src[y, x] = y + 4, x + 3
            filled[y, x] = True
    half, vw = 2, ex.shape[1] - 4
    for exhaustive in (True, False):
        o, f, s = out.copy(), filled.copy(), src.copy()
        stamp = np.zeros((ex.shape[0] - 4) * vw, np.int64)
        _fill_round(ex, o, f, s, np.array([5]), np.array([4]), _gaussian(5), half, False,
                    np.zeros((stamp.size, 0), np.int64), exhaustive, np.array([0.3]),
                    np.zeros((1, 1), np.int64), 0.1, 0.3, stamp, 0)
        assert tuple(s[5, 4]) == (9, 7)


@pytest.mark.parametrize("kwargs, message", [
    ({"window": 10}, "window must be odd, got 10"),
    ({"window": 1}, "window must be >= 3, got 1"),
    ({"window": 41}, r"window=41 is larger than the exemplar \(40x40 pixels\)"),
    ({"method": "slow"}, "method must be one of 'fast', 'exhaustive', got 'slow'"),
    ({"epsilon": -0.1}, "epsilon must be >= 0.0, got -0.1"),
])
def test_bad_arguments_name_parameter_and_value(kwargs, message):
    with pytest.raises(ValueError, match=message):
        efros_leung(_exemplar("grass", 40), (16, 16), **kwargs)
