"""Tests for spectex.spectrum, the one home of spectrum estimation (issue 18).

Reference values were computed on main before the estimators had one home
(``metrics.band_power``, ``analysis.octave_power`` and
``spectral.radial_power_spectrum`` each with its own FFT), so they say that
the move changed no number. The other tests compare two routes to the same
quantity.
"""

import numpy as np
import pytest

from spectex import spectrum
from spectex.spectrum import band_power, hann_window, power_spectrum, radial_power_spectrum, spectral_slope


def _image(seed, shape):
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:shape[0], 0:shape[1]]
    base = 0.5 + 0.2 * np.sin(2 * np.pi * x / 11.0) * np.cos(2 * np.pi * y / 7.0)
    return np.clip(base[..., None] + 0.1 * rng.standard_normal(shape + (3,)), 0, 1)


A = _image(1, (96, 80))
B = _image(2, (64, 128))


# --------------------------------------------------------------------------
# The numbers of main
# --------------------------------------------------------------------------

def test_band_power_reference_values_of_main():
    from spectex.metrics import band_power_distance

    np.testing.assert_allclose(band_power(A)[1], [-23.933291007830842, -19.617052029296847, -37.8494999604365],
                               rtol=0, atol=1e-10)
    np.testing.assert_allclose(band_power(B, segment=(48, 64))[1], [-23.638639194005975, -19.708428889513637],
                               rtol=0, atol=1e-10)
    assert band_power(B)[0].tolist() == [[0.25, 0.5], [0.125, 0.25], [0.0625, 0.125]]
    assert band_power_distance(A, B) == pytest.approx(1.3670277969415547, abs=1e-10)


def test_octave_power_reference_values_of_main():
    from spectex.analysis import octave_power

    op = octave_power(A)
    assert op.slope_db == pytest.approx(-6.9581044763028315, abs=1e-10)
    assert op.intercept_db == pytest.approx(-20.17517652288523, abs=1e-10)


@pytest.mark.parametrize("window, total, ring3, last", [
    (None, [0.00014810184591837176, 0.0001499135954091092, 0.00014958662812689997],
     [1.0388161831685810e-06, 1.1713746108743787e-06, 1.6677256513469647e-06],
     [1.3928408777446408e-06, 1.3081726778894893e-06, 1.2508613371558234e-06]),
    ("hann", [0.00015138501760491324, 0.0001491634707950015, 0.00014610194698902476],
     [1.3514108072546260e-06, 6.8693642183959771e-07, 1.5708960309577142e-06],
     [1.2898779417052179e-06, 1.5465394065010536e-06, 1.3258501778794587e-06]),
    ("periodic", [0.00015070279390554667, 0.00015356307265694603, 0.00015322108145732357],
     [1.2048820320315077e-06, 1.6516148699350706e-06, 1.8676174033086766e-06],
     [1.3408695354701303e-06, 1.2861911543876018e-06, 1.2346841549895792e-06]),
])
def test_radial_power_spectrum_reference_values_of_main(window, total, ring3, last):
    freqs, power = radial_power_spectrum(A, window=window)
    assert freqs.shape == (40,) and float(freqs.sum()) == pytest.approx(10.263763292346734, rel=1e-12)
    np.testing.assert_allclose(power.sum(axis=0), total, rtol=1e-10)
    np.testing.assert_allclose(power[3], ring3, rtol=1e-10)
    np.testing.assert_allclose(power[-1], last, rtol=1e-10)
    fit = spectral_slope(*radial_power_spectrum(A[:, :, 0]))
    assert fit.slope == pytest.approx(0.2291579397179043, abs=1e-10)
    assert fit.intercept == pytest.approx(-5.576321467287088, abs=1e-10)


def test_spectra_and_the_decomposition_have_one_home():
    from spectex import metrics, periodic, spectral

    assert metrics.band_power is spectrum.band_power  # a measure of metrics' table, estimated here
    for name in ("radial_power_spectrum", "spectral_slope", "SlopeFit", "hann_window"):
        assert hasattr(spectrum, name) and not hasattr(spectral, name)
    assert hasattr(periodic, "periodic_smooth_decomposition")
    assert not hasattr(spectral, "periodic_smooth_decomposition")


# --------------------------------------------------------------------------
# One normalisation, two routes
# --------------------------------------------------------------------------

@pytest.mark.parametrize("shape", [(64, 64), (48, 80), (33, 50)])
def test_parseval_the_periodogram_sums_to_the_variance(shape):
    x = _image(3, shape).astype(np.float32).astype(np.float64)  # images are analysed as float32 values
    ps = power_spectrum(x)
    total = np.einsum("ij,ijc->c", ps.weight, ps.power)
    np.testing.assert_allclose(total, x.reshape(-1, 3).var(axis=0), rtol=1e-10)
    # the weights count the full plane once
    assert ps.weight.sum() == shape[0] * shape[1]
    # a control: without the weights the half plane misses about half the variance
    assert np.all(ps.power.sum(axis=(0, 1)) < 0.75 * x.reshape(-1, 3).var(axis=0))


def test_hann_window_keeps_the_variance_of_white_noise_on_average():
    x = np.random.default_rng(0).standard_normal((128, 128))
    ps = power_spectrum(x, window="hann")
    assert float((ps.weight * ps.power).sum()) == pytest.approx(x.var(), rel=0.05)
    # Welch segments: the same estimate from crops, averaged
    seg = power_spectrum(x, window="hann", segment=(64, 64))
    assert seg.power.shape == (64, 33) and float((seg.weight * seg.power).sum()) == pytest.approx(x.var(), rel=0.05)


def test_band_power_is_the_sum_of_the_periodogram_over_the_band():
    # route 1: band_power; route 2: the periodogram of the luma summed over |f| in each band by hand,
    # on the full FFT plane (no half-plane weights)
    lum = A.astype(np.float32).astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])  # float32 values
    win = hann_window(lum.shape)
    p = np.abs(np.fft.fft2((lum - lum.mean()) * win)) ** 2 / (lum.size ** 2 * np.mean(win ** 2))
    r = np.hypot(np.fft.fftfreq(lum.shape[0])[:, None], np.fft.fftfreq(lum.shape[1])[None, :])
    bands, db = band_power(A)
    for (lo, hi), value in zip(bands, db):
        sel = (r >= lo) if lo == 0.25 else (r >= lo) & (r < hi)
        assert value == pytest.approx(10 * np.log10(p[sel].sum()), abs=1e-9)


def test_octave_power_from_the_radial_spectrum_agrees_with_the_band_sums():
    # route 1: the periodogram summed over the frequencies of an octave band (band_power's
    # reduction); route 2: the radial spectrum's ring means times the frequencies per ring, summed
    # over the band's rings. Ring k holds k - 1/2 <= f n < k + 1/2, so with band edges on ring
    # edges the two routes must agree to rounding.
    from spectex.spectral import spectral_noise

    x = spectral_noise((256, 192), beta=3.0, rng=1).astype(np.float64)
    ps = power_spectrum(x)
    freqs, ring_power = radial_power_spectrum(x)
    n = 192
    fn = ps.frequency * n
    counts = np.bincount(np.rint(fn).astype(int).ravel(), weights=ps.weight.ravel())[1:n // 2 + 1]
    assert counts.shape == freqs.shape
    np.testing.assert_allclose(np.sqrt(counts[:8]), np.sqrt(np.pi * 2 * np.arange(1, 9) * 256 / 192), rtol=0.3)
    wrong = []
    for k in range(4):
        lo, hi = n * 2.0 ** -(k + 2), n * 2.0 ** -(k + 1)  # in cycles across: 48-96, 24-48, ...
        direct = float((ps.weight * ps.power)[(fn >= lo - 0.5) & (fn < hi - 0.5)].sum())
        rings = (np.arange(1, n // 2 + 1) >= lo) & (np.arange(1, n // 2 + 1) < hi)
        assert float((ring_power * counts)[rings].sum()) == pytest.approx(direct, rel=1e-10)
        wrong.append(float(ring_power[rings].sum()) / direct)
    # a control: the ring means summed without their counts are not the band's power
    assert all(abs(10 * np.log10(r)) > 10 for r in wrong)


def test_power_spectrum_checks():
    with pytest.raises(ValueError, match="window"):
        power_spectrum(A, window="kaiser")
    with pytest.raises(ValueError, match="segment"):
        power_spectrum(A, segment=(8,))
    with pytest.raises(ValueError, match=r"segment\[0\]"):
        power_spectrum(A, segment=(200, 8))
    grey = power_spectrum(A[:, :, 0])
    assert grey.power.shape == grey.frequency.shape == (96, 41)


def test_correlation_length_of_smoothed_noise_matches_its_gaussian_autocorrelation():
    """White noise smoothed by a Gaussian of sigma s has the autocorrelation exp(-r^2 / (4 s^2)), which falls to a
    quarter at r = 2 s sqrt(ln 4) (the analytic route); the estimate agrees within 5 %, and at 0.5 too."""
    from scipy import ndimage

    from spectex.spectrum import correlation_length

    rng = np.random.default_rng(3)
    for sigma in (2.0, 4.0):
        x = ndimage.gaussian_filter(rng.standard_normal((512, 512)), sigma, mode="wrap")
        x = 0.5 + 0.1 * x / x.std()
        for level in (0.25, 0.5):
            expected = 2.0 * sigma * np.sqrt(np.log(1.0 / level))
            assert correlation_length(x, level=level) == pytest.approx(expected, rel=0.05)


def test_correlation_length_follows_a_magnification():
    """A photo magnified 2 and 4 times has a grain 2 and 4 times as long (within 10 %); the light across it (a
    gradient added) is left out with its largest shapes."""
    import skimage.data
    from scipy import ndimage

    from spectex.spectrum import correlation_length

    gravel = skimage.data.gravel().astype(np.float64) / 255.0
    base = correlation_length(gravel)
    assert 3.0 < base < 8.0
    for zoom in (2, 4):
        assert correlation_length(ndimage.zoom(gravel, zoom, order=3)) == pytest.approx(zoom * base, rel=0.1)
    lit = gravel * np.linspace(0.6, 1.0, 512)[None, :]
    assert correlation_length(lit) == pytest.approx(base, rel=0.1)


@pytest.mark.parametrize("kwargs, words", [({"level": 0.0}, "level must be > 0"), ({"level": 1.0}, "level must be < 1"),
                                           ({"detail": 1.0}, "detail must be >= 2")])
def test_correlation_length_refuses_out_of_range_options(kwargs, words):
    from spectex.spectrum import correlation_length

    with pytest.raises(ValueError, match=words):
        correlation_length(np.random.default_rng(0).random((32, 32)), **kwargs)


def test_correlation_length_refuses_a_tiny_image():
    from spectex.spectrum import correlation_length

    with pytest.raises(ValueError, match="image"):
        correlation_length(np.zeros((8, 8)))
