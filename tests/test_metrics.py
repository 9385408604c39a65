"""spectex.metrics: reference values, independent routes, and controls that fail."""

import numpy as np
import pytest
import skimage.data

from spectex import metrics


@pytest.fixture(scope="module")
def gravel():
    return (skimage.data.gravel()[:128, :128] / 255.0).astype(np.float32)


def _periodic_noise(n, seed, smooth=4.0):
    """Band-limited noise built in the Fourier domain: exactly periodic."""
    rng = np.random.default_rng(seed)
    f = np.fft.fftfreq(n)
    r = np.sqrt(f[:, None] ** 2 + f[None, :] ** 2)
    spec = np.fft.fft2(rng.standard_normal((n, n))) * np.exp(-(r * n / smooth) ** 2 / 50.0)
    field = np.real(np.fft.ifft2(spec))
    field = (field - field.min()) / (field.max() - field.min())
    return field.astype(np.float32)


# ---------------------------------------------------------------- histogram W1

def test_w1_reference_values():
    zeros = np.zeros((8, 8))
    ones = np.ones((4, 6))
    assert metrics.histogram_w1(zeros, ones) == pytest.approx([1.0])
    a = np.random.default_rng(0).random((16, 16))
    assert metrics.histogram_w1(a, a + 0.1) == pytest.approx([0.1], abs=1e-6)
    assert metrics.histogram_w1(a, a[::-1, ::-1]) == pytest.approx([0.0], abs=1e-12)


def test_w1_agrees_with_scipy():
    from scipy.stats import wasserstein_distance

    rng = np.random.default_rng(1)
    a = rng.random((20, 30, 3)) ** 2
    b = rng.random((17, 11, 3))
    ours = metrics.histogram_w1(a, b)
    for c in range(3):
        ref = wasserstein_distance(a[:, :, c].ravel(), b[:, :, c].ravel())
        assert ours[c] == pytest.approx(ref, rel=1e-5)


def test_w1_channel_mismatch_names_both():
    with pytest.raises(ValueError, match="same number of channels"):
        metrics.histogram_w1(np.zeros((4, 4)), np.zeros((4, 4, 3)))


# ---------------------------------------------------------------- band power

def test_band_power_of_white_noise_matches_band_areas():
    # White noise of variance s2 puts s2 * (band area / total area) in each band.
    rng = np.random.default_rng(2)
    s2 = 0.01
    noise = 0.5 + rng.standard_normal((512, 512)) * np.sqrt(s2)
    bands, power_db = metrics.band_power(noise)
    assert len(bands) == 6  # lowest band: 1/128 cycles per pixel, 4 cycles across
    areas = []
    for k, (lo, hi) in enumerate(bands):
        outer = 1.0 if k == 0 else np.pi * hi * hi
        areas.append(outer - np.pi * lo * lo)
    expected = 10 * np.log10(s2 * np.array(areas))
    # the estimate's own scatter grows as the bands narrow (about 0.7 dB for
    # the lowest); a forgotten window normalisation would be 8.5 dB off
    assert np.max(np.abs(power_db[:5] - expected[:5])) < 0.5
    assert abs(power_db[5] - expected[5]) < 1.5


def test_band_power_is_size_independent_and_scales_by_6db(gravel):
    _, p128 = metrics.band_power(gravel)
    _, p64 = metrics.band_power(gravel[32:96, 32:96])
    assert np.max(np.abs(p128[:len(p64)] - p64)) < 2.0
    half = 0.5 + 0.5 * (gravel - gravel.mean())
    assert metrics.band_power_distance(gravel, half) == pytest.approx(20 * np.log10(2), abs=1e-6)
    assert metrics.band_power_distance(gravel, gravel) == 0.0


def test_band_power_too_small_is_an_error():
    with pytest.raises(ValueError, match="at least 32 pixels"):
        metrics.band_power(np.zeros((20, 20)))


def test_white_noise_fails_band_power_but_passes_w1(gravel):
    # The control for the band-power check: a shuffled exemplar has exactly
    # the exemplar's histogram and none of its spectrum.
    shuffled = np.random.default_rng(3).permutation(gravel.ravel()).reshape(gravel.shape)
    assert metrics.histogram_w1(gravel, shuffled)[0] < 1e-9
    assert metrics.band_power_distance(gravel, shuffled) > 1.5


# ---------------------------------------------------------------- seams and wrap

def _random_blocks(ex, n, block, seed):
    rng = np.random.default_rng(seed)
    out = np.zeros((n, n), dtype=np.float32)
    for y in range(0, n, block):
        for x in range(0, n, block):
            sy, sx = rng.integers(0, ex.shape[0] - block + 1, size=2)
            out[y:y + block, x:x + block] = ex[sy:sy + block, sx:sx + block]
    return out


def test_seam_energy_control(gravel):
    assert metrics.seam_energy(gravel, 32) == pytest.approx(1.0, abs=0.3)
    assert metrics.seam_energy(_random_blocks(gravel, 128, 32, 0), 32) > 2.0


def test_seam_energy_checks_arguments(gravel):
    with pytest.raises(ValueError, match="overlap must be smaller than block=8, got 8"):
        metrics.seam_energy(gravel, 8, 8)


def test_tileability_periodic_vs_crop():
    field = _periodic_noise(128, 4)
    assert metrics.tileability(field) == pytest.approx(1.0, abs=0.35)
    crop = field[:80, :80]  # not periodic any more
    assert metrics.tileability(crop) > 3.0
    assert metrics.tileability(field, axis=0) <= metrics.tileability(field) + 1e-12


# ---------------------------------------------------------------- copies

def test_verbatim_copy_reference_values(gravel):
    assert metrics.verbatim_copy(gravel[10:90, 20:100], gravel) == pytest.approx(1.0)
    tiled = np.tile(gravel, (2, 2))
    assert metrics.verbatim_copy(tiled, gravel) == pytest.approx(0.25, abs=0.02)
    mosaic = _random_blocks(gravel, 128, 32, 1)
    assert metrics.verbatim_copy(mosaic, gravel) == pytest.approx(1 / 16, abs=0.02)
    noise = np.random.default_rng(5).random((64, 64)).astype(np.float32)
    assert metrics.verbatim_copy(noise, gravel) == 0.0


def test_repetition_tiling_vs_noise(gravel):
    tiled = np.tile(gravel[:64, :64], (3, 3))
    assert metrics.repetition(tiled, 64) == pytest.approx(1.0)
    assert metrics.repetition(gravel, (64, 64)) == 0.0
    with pytest.raises(ValueError, match="patch must be odd, got 4"):
        metrics.repetition(gravel, 8, patch=4)


def test_compare_collects_everything(gravel):
    result = metrics.compare(gravel, reference=gravel[:64, :64], block=32)
    assert isinstance(result, metrics.Comparison)
    assert result.verbatim_copy > 0.2  # the reference is a crop of the image
    assert result.seam_energy is not None and len(result.histogram_w1) == 1
    assert result.repeat_peak_image == pytest.approx(metrics.repeat_peak(gravel))
    assert set(result.as_dict()) >= {"histogram_w1", "band_power_distance_db", "tileability_image",
                                     "verbatim_copy", "repeat_peak_image", "exact_repetition", "seam_energy"}


def test_compare_repetition_sees_a_filtered_repeat(gravel):
    """A tiled crop, blurred a little (no exact 8-bit copy survives): the
    exact repetition misses it, the repeat peak (the compare report's number)
    sees it; the untiled image reads as not repeating."""
    from scipy import ndimage

    noise = np.random.default_rng(1).normal(0.0, 0.01, (192, 192))
    tiled = np.clip(ndimage.gaussian_filter(np.tile(gravel[:64, :64], (3, 3)), 0.7) + noise, 0.0, 1.0)
    r = metrics.compare(tiled, reference=gravel[:64, :64])
    assert r.exact_repetition < 0.05
    assert r.repeat_peak_image > 0.5
    assert metrics.compare(gravel, reference=gravel[:64, :64]).repeat_peak_image < 0.1


def test_compare_takes_the_reference_by_name_only(gravel):
    crop = gravel[:64, :64]
    with pytest.raises(TypeError, match="reference"):
        metrics.compare(gravel)
    with pytest.raises(TypeError, match="positional"):
        metrics.compare(gravel, crop)  # never guessed which one is the reference
    assert metrics.compare(gravel, reference=crop).verbatim_copy is not None  # the control


def test_band_power_segments_compare_sizes_at_one_resolution():
    # The same brick wall at two sizes: compared at the smaller size (Welch
    # segments) the lowest band no longer depends on where the brick period
    # falls against the window's resolution.
    full = skimage.data.brick() / 255.0
    full = full.reshape(256, 2, 256, 2).mean(axis=(1, 3))
    crop = full[:128, :128]
    _, p_crop = metrics.band_power(crop)
    _, p_full = metrics.band_power(full)
    naive = np.sqrt(np.mean((p_crop - p_full[:4]) ** 2))
    assert metrics.band_power_distance(crop, full) < naive - 0.4
    bands, p_seg = metrics.band_power(full, segment=(128, 128))
    assert len(bands) == 4
    with pytest.raises(ValueError, match="segment\\[0\\] must be <= 128, got 200"):
        metrics.band_power(crop, segment=(200, 64))


# ---------------------------------------------------------------- repeat_peak

def _smooth_noise_tile(n, seed):
    from scipy import ndimage

    tile = ndimage.gaussian_filter(np.random.default_rng(seed).random((n, n)), 1.0, mode="wrap")
    return ((tile - tile.min()) / (tile.max() - tile.min())).astype(np.float32)


def test_repeat_peak_plain_tiling_is_one_and_white_noise_is_near_zero():
    tile = _smooth_noise_tile(64, 0)
    assert metrics.repeat_peak(np.tile(tile, (8, 8))) == pytest.approx(1.0, abs=1e-9)
    # a period shorter than min_lag is still seen at its multiples
    assert metrics.repeat_peak(np.tile(_smooth_noise_tile(16, 1), (32, 32))) == pytest.approx(1.0, abs=1e-9)
    noise = np.random.default_rng(2).random((1024, 1024)).astype(np.float32)
    peak = metrics.repeat_peak(noise)
    assert 0.002 < peak < 0.008  # sqrt(2 ln N / N) = 0.0051


def test_repeat_peak_sees_a_rotated_and_offset_tiling_that_repetition_misses():
    from scipy import ndimage

    tile = _smooth_noise_tile(64, 3)
    rotated = ndimage.rotate(np.tile(tile, (16, 16)), 30.0, reshape=False, order=1, mode="wrap")[200:712, 217:729]
    peak = metrics.repeat_peak(rotated)
    assert 0.65 < peak < 0.95
    # the axis-aligned exact-copy measure sees nothing here (the reason for repeat_peak)
    assert metrics.repetition(rotated, 64) < 0.01


def test_repeat_peak_is_blind_to_coarse_variation_over_a_tiling():
    # coarse modulation dilutes the raw autocorrelation but not the detail's
    tile = _smooth_noise_tile(64, 4)
    y, x = np.mgrid[0:512, 0:512]
    coarse = 0.5 + 0.4 * np.sin(2 * np.pi * x / 512.0) * np.cos(2 * np.pi * y / 512.0)
    image = 0.7 * coarse + 0.3 * np.tile(tile, (8, 8))
    assert metrics.repeat_peak(image) > 0.95


def test_repeat_peak_agrees_with_a_direct_correlation_at_each_lag():
    from scipy import ndimage

    rng = np.random.default_rng(5)
    image = rng.random((64, 80, 3)).astype(np.float32)
    lum = image[:, :, :3].astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])
    d = lum - ndimage.gaussian_filter(lum, 2.0, mode="wrap")
    d -= d.mean()
    best = -np.inf
    for dy in range(-32, 32):
        for dx in range(-40, 40):
            if dy * dy + dx * dx >= 10 * 10:
                best = max(best, np.sum(d * np.roll(d, (dy, dx), axis=(0, 1))) / np.sum(d * d))
    assert metrics.repeat_peak(image, min_lag=10, sigma=2.0) == pytest.approx(best, rel=1e-9, abs=1e-12)


def test_repeat_peak_flat_and_hostile_inputs():
    assert np.isnan(metrics.repeat_peak(np.full((64, 64), 0.5)))
    with pytest.raises(ValueError, match="min_lag"):
        metrics.repeat_peak(np.zeros((40, 40)), min_lag=24)
    with pytest.raises(ValueError, match="sigma"):
        metrics.repeat_peak(np.zeros((64, 64)), sigma=0.0)
    with pytest.raises(TypeError, match="min_lag"):
        metrics.repeat_peak(np.zeros((64, 64)), min_lag=2.5)
    with pytest.raises(ValueError, match="finite"):
        metrics.repeat_peak(np.full((64, 64), np.nan))
