"""spectex.analysis statistics: octave power and its slope, colour statistics,
cross-scale dependence (the statistics spectex.fit matches)."""

import numpy as np
import pytest
from scipy import ndimage

from spectex.analysis import analyse, colour_stats, cross_scale, dog_bands, octave_power


def _modulated(m, n=192, seed=0):
    """Fine noise whose amplitude follows a coarse sinusoid: 1 + m * coarse."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:n, 0:n]
    coarse = np.sin(2 * np.pi * x / 24.0) * np.sin(2 * np.pi * y / 32.0)
    fine = rng.standard_normal((n, n))
    fine -= ndimage.gaussian_filter(fine, 1.0)
    img = 0.5 + 0.15 * coarse + 0.08 * (1.0 + m * coarse) * fine
    return np.clip(img, 0.0, 1.0)


@pytest.mark.parametrize("m, sign", [(0.9, 1), (-0.9, -1)])
def test_analysis_cross_scale_sign_follows_the_modulation(m, sign):
    value = cross_scale(_modulated(m)).value
    assert sign * value > 0.5


def test_analysis_cross_scale_is_small_without_modulation():
    assert abs(cross_scale(_modulated(0.0)).value) < 0.15


def test_analysis_cross_scale_amplitude_coupling():
    rng = np.random.default_rng(1)
    n = 192
    y, x = np.mgrid[0:n, 0:n]
    coarse = np.sin(2 * np.pi * x / 24.0) * np.sin(2 * np.pi * y / 32.0)
    fine = rng.standard_normal((n, n))
    fine -= ndimage.gaussian_filter(fine, 1.0)
    coupled = 0.5 + 0.15 * coarse + 0.08 * np.abs(coarse) * fine
    plain = 0.5 + 0.15 * coarse + 0.08 * fine
    with_coupling = cross_scale(coupled).amplitude
    without = cross_scale(plain).amplitude
    assert with_coupling > 0.5
    # without: only what the coarse band leaks into the fine bands' envelopes
    assert without < with_coupling - 0.25


def test_analysis_dog_bands_telescope():
    img = np.random.default_rng(2).random((64, 64)).astype(np.float32)
    bands = dog_bands(img, 4)
    rest = ndimage.gaussian_filter(img.astype(np.float64), 8.0, mode="reflect")
    np.testing.assert_allclose(sum(bands) + rest, img, atol=1e-6)


def test_analysis_octave_power_slope_of_white_noise():
    # white noise: each coarser octave holds a quarter of the frequencies, -6.02 dB
    img = np.random.default_rng(3).random((256, 256))
    assert octave_power(img).slope_db == pytest.approx(-6.02, abs=0.4)


def test_analysis_octave_power_slope_of_brown_noise():
    from spectex.spectral import spectral_noise

    slopes = [octave_power(spectral_noise((256, 256), beta=2.0, rng=s)).slope_db for s in range(3)]
    assert np.mean(slopes) == pytest.approx(0.0, abs=1.0)


def test_analysis_colour_stats_two_colours():
    a, b = np.array([0.2, 0.3, 0.1]), np.array([0.8, 0.6, 0.5])
    img = np.empty((32, 32, 3))
    img[:, :16] = a
    img[:, 16:] = b
    st = colour_stats(img)
    np.testing.assert_allclose(st.mean, (a + b) / 2, atol=1e-6)
    np.testing.assert_allclose(st.covariance, np.cov(img.reshape(-1, 3), rowvar=False, bias=True), atol=1e-6)
    np.testing.assert_allclose(st.principal_colours, np.stack([a, b]), atol=1e-5)
    np.testing.assert_allclose(st.histograms.sum(axis=1), 1.0)
    assert st.principal_std[1] == pytest.approx(0.0, abs=1e-6)


def test_analysis_exemplars_have_their_signs():
    skdata = pytest.importorskip("skimage.data")
    brick = analyse(skdata.brick()[:128, :128])
    gravel = analyse(skdata.gravel()[:128, :128])
    assert brick.cross.value > 0.3  # mortar lines: fine detail where the coarse band is bright
    assert gravel.cross.value < -0.2  # gaps between stones: fine detail where it is dark
    assert set(brick.summary()) >= {"power_db", "slope_db_per_octave", "cross_scale_value"}


@pytest.mark.parametrize("call, match", [
    (lambda: analyse(np.zeros((16, 16))), "at least 32x32"),
    (lambda: cross_scale(np.zeros((20, 20))), "at least"),
    (lambda: cross_scale(np.zeros((64, 64)), step=0), "step must be >= 1"),
    (lambda: cross_scale(np.zeros((64, 64)), fine=()), "fine must name"),
    (lambda: colour_stats(np.zeros((8, 8)), bins=1), "bins must be >= 2"),
])
def test_analysis_bad_input(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_results_are_typed():
    from spectex.analysis import ColourStats, CrossScale, OctavePower
    from spectex.metrics import BandPower, band_power
    from spectex.spectral import spectral_noise
    from spectex.spectrum import RadialSpectrum, radial_power_spectrum

    img = spectral_noise((128, 128), beta=2.0, rng=1)
    op = octave_power(img)
    assert isinstance(op, OctavePower)
    with pytest.raises(TypeError, match="not subscriptable"):  # a result, not a dict
        op["slope_db"]
    assert set(op.as_dict()) == {"bands", "power_db", "slope_db", "intercept_db"}
    assert isinstance(colour_stats(img), ColourStats) and isinstance(cross_scale(img), CrossScale)
    bands, power = bp = band_power(img)  # named tuples still unpack as the old tuples
    assert isinstance(bp, BandPower) and bp.power_db is power and bp[0] is bands
    freqs, p = rs = radial_power_spectrum(img)
    assert isinstance(rs, RadialSpectrum) and rs.freqs is freqs and rs.power is p

