"""Tests for spectex.spectral: octaves by magnification, spectral synthesis, and their spectra."""

import numpy as np
import pytest

from spectex.periodic import periodic_smooth_decomposition
from spectex.spectral import (
    FILTERS,
    band_limit,
    discrete_filter,
    filter_passes,
    magnify,
    octave,
    octave_amplitudes,
    octave_sum,
    spectral_noise,
)
from spectex.spectrum import hann_window, radial_power_spectrum, spectral_slope

# Independent formulas for the continuous filters (input-texel units).
REFERENCE = {
    "box": lambda t: ((t >= -0.5) & (t < 0.5)).astype(float),
    "tent": lambda t: np.clip(1 - np.abs(t), 0, None),
    "bspline": lambda t: np.select(
        [np.abs(t) < 1, np.abs(t) < 2],
        [2 / 3 - t**2 + np.abs(t) ** 3 / 2, (2 - np.abs(t)) ** 3 / 6], 0.0),
    "catmull-rom": lambda t: np.select(
        [np.abs(t) < 1, np.abs(t) < 2],
        [1.5 * np.abs(t) ** 3 - 2.5 * t**2 + 1, -0.5 * np.abs(t) ** 3 + 2.5 * t**2 - 4 * np.abs(t) + 2], 0.0),
}


def direct_convolution(x, m, taps, start):
    """Circular 2-D convolution of the zero-stuffed ``x`` with the separable filter."""
    n0, n1 = x.shape
    u = np.zeros((n0 * m, n1 * m))
    u[::m, ::m] = x
    y = np.zeros_like(u)
    for a, ha in enumerate(taps):
        for b, hb in enumerate(taps):
            if ha * hb != 0:
                y += ha * hb * np.roll(u, (a + start, b + start), axis=(0, 1))
    return y


@pytest.mark.parametrize("filt", FILTERS)
@pytest.mark.parametrize("m", [1, 2, 3, 8])
def test_magnify_matches_direct_convolution_of_zero_stuffed_input(filt, m):
    x = np.random.default_rng(m).standard_normal((4, 6))
    taps, start = discrete_filter(filt, m)
    want = direct_convolution(x, m, taps, start)
    got = magnify(x, m, kernel=filt)
    assert got.dtype == np.float64 and got.shape == (4 * m, 6 * m)
    np.testing.assert_allclose(got, want, atol=1e-6, rtol=0)
    got32 = magnify(x.astype(np.float32), m, kernel=filt)
    assert got32.dtype == np.float32
    np.testing.assert_allclose(got32, want, atol=1e-5, rtol=0)


def test_magnify_matches_fft_route():
    # Circular convolution by FFT: a second, independent route.
    x = np.random.default_rng(0).standard_normal((8, 8))
    m = 4
    taps, start = discrete_filter("catmull-rom", m)
    u = np.zeros((32, 32))
    u[::m, ::m] = x
    h1 = np.zeros(32)
    for j, t in enumerate(taps):
        h1[(j + start) % 32] += t
    want = np.real(np.fft.ifft2(np.fft.fft2(u) * np.fft.fft2(np.outer(h1, h1))))
    np.testing.assert_allclose(magnify(x, m, kernel="catmull-rom"), want, atol=1e-9)


@pytest.mark.parametrize("filt", ["box", "tent", "bspline", "catmull-rom"])
@pytest.mark.parametrize("m", [2, 5, 8])
def test_discrete_filter_samples_the_continuous_filter(filt, m):
    taps, start = discrete_filter(filt, m)
    j = start + np.arange(len(taps))
    np.testing.assert_allclose(taps, REFERENCE[filt]((j + 0.5 - m / 2) / m), atol=1e-12)


def test_tent_is_gl_bilinear_and_box_is_gl_nearest():
    rng = np.random.default_rng(3)
    x = rng.random((4, 5))
    m = 4
    y = magnify(x, m, kernel="tent")
    # GL_LINEAR with GL_REPEAT at the output texel centres.
    u = (np.arange(5 * m) + 0.5) / m - 0.5
    v = (np.arange(4 * m) + 0.5) / m - 0.5
    i0, j0 = np.floor(v).astype(int), np.floor(u).astype(int)
    a, b = (v - i0)[:, None], (u - j0)[None, :]
    I0, I1, J0, J1 = i0 % 4, (i0 + 1) % 4, j0 % 5, (j0 + 1) % 5
    want = ((1 - a) * (1 - b) * x[np.ix_(I0, J0)] + (1 - a) * b * x[np.ix_(I0, J1)]
            + a * (1 - b) * x[np.ix_(I1, J0)] + a * b * x[np.ix_(I1, J1)])
    np.testing.assert_allclose(y, want, atol=1e-12)
    np.testing.assert_array_equal(magnify(x, m, kernel="box"), np.kron(x, np.ones((m, m))))


@pytest.mark.parametrize("filt", ["tent", "catmull-rom"])
def test_interpolating_filters_pass_through_the_input(filt):
    x = np.random.default_rng(1).standard_normal((6, 6))
    y = magnify(x, 3, kernel=filt)  # odd factor: texel centres coincide
    np.testing.assert_allclose(y[1::3, 1::3], x, atol=1e-12)


@pytest.mark.parametrize("filt", FILTERS)
def test_constant_stays_constant_and_output_tiles(filt):
    np.testing.assert_allclose(magnify(np.full((3, 3), 0.7), 6, kernel=filt), 0.7, atol=1e-12)
    x = np.random.default_rng(2).standard_normal((4, 4))
    # Shifting the input by one texel shifts the output by m texels: periodic.
    np.testing.assert_allclose(magnify(np.roll(x, 1, axis=1), 5, kernel=filt),
                               np.roll(magnify(x, 5, kernel=filt), 5, axis=1), atol=1e-12)


def test_passes_depend_on_footprint_only():
    assert [filter_passes(f) for f in ("box", "tent", "bspline", "catmull-rom")] == [1, 2, 4, 4]
    assert filter_passes("gaussian", sigma=0.5) == 3
    for filt in FILTERS:
        passes = filter_passes(filt)
        for m in (2, 3, 8, 64):
            taps, start = discrete_filter(filt, m)
            # each output phase reads at most `passes` input texels, whatever m
            per_phase = [np.count_nonzero(taps[(r - start) % m::m]) for r in range(m)]
            assert max(per_phase) <= passes
            if filt in ("box", "tent", "bspline"):  # positive on their open support
                assert max(per_phase) == passes


def test_magnify_channels_and_rectangular_factors():
    x = np.random.default_rng(4).standard_normal((3, 5, 2))
    y = magnify(x, (2, 3))
    assert y.shape == (6, 15, 2)
    np.testing.assert_allclose(y[:, :, 1], magnify(x[:, :, 1], (2, 3)), atol=1e-12)


def test_octave_shape_checks_and_determinism():
    a = octave(64, 8, rng=5)
    assert a.shape == (64, 64) and a.dtype == np.float32
    np.testing.assert_array_equal(a, octave(64, 8, rng=5))
    with pytest.raises(ValueError, match="multiple of cells"):
        octave(60, 8)
    with pytest.raises(ValueError, match="^kernel must be"):
        magnify(np.ones((2, 2)), 2, kernel="lanczos")
    with pytest.raises(ValueError, match="factor"):
        magnify(np.ones((2, 2)), 0)
    with pytest.raises(ValueError, match="finite"):
        magnify(np.array([[np.nan, 0.0], [0.0, 0.0]]), 2)


# --------------------------------------------------------------------------
# Spectral synthesis
# --------------------------------------------------------------------------

@pytest.mark.parametrize("beta", [1.0, 2.0, 3.0])
def test_fft_noise_slope_is_minus_beta(beta):
    slopes = []
    for seed in range(4):
        x = spectral_noise(512, beta=beta, rng=seed)
        freqs, power = radial_power_spectrum(x)
        slopes.append(spectral_slope(freqs, power).slope)
    assert abs(np.mean(slopes) + beta) < 0.05


def test_fft_noise_is_real_periodic_normalised_and_deterministic():
    x = spectral_noise((64, 96), beta=2.0, rng=1)
    assert x.shape == (64, 96) and x.dtype == np.float32
    assert abs(float(x.mean())) < 1e-5 and abs(float(x.std()) - 1) < 1e-4
    np.testing.assert_array_equal(x, spectral_noise((64, 96), beta=2.0, rng=1))
    assert not np.array_equal(x, spectral_noise((64, 96), beta=2.0, rng=2))
    assert spectral_noise(32, dtype=np.float64, rng=0).dtype == np.float64


def test_fft_noise_band_edges_hold_no_power_outside():
    x = spectral_noise(256, beta=1.0, low=0.05, high=0.2, rng=0).astype(np.float64)
    f = np.sqrt(np.fft.fftfreq(256)[:, None] ** 2 + np.fft.fftfreq(256)[None, :] ** 2)
    p = np.abs(np.fft.fft2(x)) ** 2
    inside = (f >= 0.05) & (f <= 0.2)
    assert p[~inside].sum() < 1e-10 * p[inside].sum()
    freqs, power = radial_power_spectrum(x)
    fit = spectral_slope(freqs, power, fmin=0.06, fmax=0.19)
    assert abs(fit.slope + 1.0) < 0.1
    with pytest.raises(ValueError, match="high must be greater than low"):
        spectral_noise(64, low=0.3, high=0.2)
    with pytest.raises(ValueError, match="holds no frequency"):
        spectral_noise(8, low=0.2, high=0.24)


def test_octave_sum_amplitudes_give_the_slope():
    # equal amplitudes per octave give beta = 2 in 2-D (see octave_amplitudes)
    slopes = []
    for seed in range(3):
        x = octave_sum(256, amplitudes=2.0, rng=seed)
        freqs, power = radial_power_spectrum(x)
        slopes.append(spectral_slope(freqs, power, fmax=0.12).slope)
    assert abs(np.mean(slopes) + 2.0) < 0.25
    # seed 002's fractalsum, noise(x f) / f: power ~ f^-4 in 2-D
    x = octave_sum(256, rng=0)
    freqs, power = radial_power_spectrum(x)
    assert abs(spectral_slope(freqs, power, fmax=0.12).slope + 4.0) < 0.4


def test_octave_amplitudes_forms():
    np.testing.assert_allclose(octave_amplitudes([4, 8, 16]), [1, 0.5, 0.25])
    np.testing.assert_allclose(octave_amplitudes([4, 8, 16], 2.0), [1, 1, 1])
    np.testing.assert_allclose(octave_amplitudes([4, 8, 16], 0.0), [1, 2, 4])
    np.testing.assert_allclose(octave_amplitudes([4, 8], [0.3, 0.1]), [0.3, 0.1])
    with pytest.raises(ValueError, match="one value per octave"):
        octave_amplitudes([4, 8], [1.0])
    with pytest.raises(ValueError, match="amplitudes"):
        octave_amplitudes([4, 8], "pink")


def test_octave_sum_sizes_it_cannot_do():
    with pytest.raises(ValueError, match="multiple of"):
        octave_sum(100, octaves=5)
    assert octave_sum(96, octaves=3, rng=0).shape == (96, 96)
    x = octave_sum(64, amplitudes=[1.0, 0.0, 0.0], rng=0)
    y = octave_sum(64, amplitudes=[1.0, 0.5, 0.0], rng=0)
    assert not np.allclose(x, y)


def test_band_limit_is_exact_and_upsamples():
    rng = np.random.default_rng(0)
    x = rng.random((32, 40))
    y = band_limit(x, high=0.2).astype(np.float64)
    f = np.sqrt(np.fft.fftfreq(32)[:, None] ** 2 + np.fft.fftfreq(40)[None, :] ** 2)
    X, Y = np.fft.fft2(x), np.fft.fft2(y)
    assert np.abs(Y[f > 0.2]).max() < 1e-4
    np.testing.assert_allclose(Y[f <= 0.2], X[f <= 0.2], atol=1e-4)
    # Fourier interpolation: the coarse samples come back (less the Nyquist lines).
    X[16, :] = 0
    X[:, 20] = 0
    up = band_limit(x, shape=(64, 80))
    np.testing.assert_allclose(up[::2, ::2], np.real(np.fft.ifft2(X)), atol=1e-5)
    with pytest.raises(ValueError, match="shape must be at least"):
        band_limit(x, shape=(16, 16))


# --------------------------------------------------------------------------
# Analysis
# --------------------------------------------------------------------------

def test_radial_power_spectrum_parseval_and_sinusoid():
    h = w = 64
    yy, xx = np.mgrid[0:h, 0:w]
    img = np.sin(2 * np.pi * (5 * xx / w + 3 * yy / h))
    freqs, power = radial_power_spectrum(img)
    k = np.argmax(power)
    assert abs(freqs[k] - np.hypot(5, 3) / 64) < 0.5 / 64  # within its ring
    x = np.random.default_rng(0).random((64, 64))
    freqs, power = radial_power_spectrum(x)
    assert np.all(np.diff(freqs) > 0) and freqs[-1] <= 0.5
    # white noise: flat spectrum at level variance / (H W) per frequency
    assert abs(spectral_slope(freqs, power).slope) < 0.15
    np.testing.assert_allclose(power.mean(), x.var() / (64 * 64), rtol=0.1)


def test_radial_power_spectrum_channels_and_windows():
    x = np.random.default_rng(0).random((48, 64, 3))
    freqs, power = radial_power_spectrum(x)
    assert power.shape == (len(freqs), 3)
    _, p1 = radial_power_spectrum(x[:, :, 1])
    np.testing.assert_allclose(power[:, 1], p1)
    fit = spectral_slope(freqs, power)
    assert fit.slope.shape == (3,)
    with pytest.raises(ValueError, match="window"):
        radial_power_spectrum(x, window="kaiser")


def test_hann_window_reference_values():
    # sin^2 form of the (n + 2)-point Hann window without its zero end points
    h, w = 5, 8
    ry = np.sin(np.pi * np.arange(1, h + 1) / (h + 1)) ** 2
    rx = np.sin(np.pi * np.arange(1, w + 1) / (w + 1)) ** 2
    win = hann_window((h, w))
    assert win.shape == (h, w) and win.dtype == np.float64
    np.testing.assert_allclose(win, ry[:, None] * rx[None, :], rtol=1e-12, atol=1e-15)
    assert win.min() > 0 and win[2, :].max() <= 1.0
    assert win[2, 3] == win[2, 4]  # symmetric about the centre
    np.testing.assert_allclose(hann_window(7), np.outer(hann_window((7, 1))[:, 0], hann_window((1, 7))[0]))
    np.testing.assert_allclose(hann_window(3)[1, 1], 1.0)
    with pytest.raises(ValueError, match=r"shape\[1\] must be >= 1, got 0"):
        hann_window((4, 0))


def test_windows_remove_edge_leakage_from_a_non_periodic_crop():
    # A crop of beta = 4 noise is not periodic: its edges leak a 1/f^2 cross
    # that flattens the measured slope; Hann or the periodic component fix it.
    slopes = {None: [], "hann": [], "periodic": []}
    for seed in range(3):
        crop = spectral_noise(512, beta=4.0, rng=seed).astype(np.float64)[:200, 100:300]
        for window in slopes:
            freqs, power = radial_power_spectrum(crop, window=window)
            # from 2 cycles across, as the spectrum command fits: the lowest ring is the window's own
            slopes[window].append(spectral_slope(freqs, power, fmin=2 / 200, fmax=0.25).slope)
    assert np.mean(slopes[None]) > -3.4
    assert abs(np.mean(slopes["hann"]) + 4.0) < 0.3
    assert abs(np.mean(slopes["periodic"]) + 4.0) < 0.3


def test_periodic_smooth_decomposition():
    rng = np.random.default_rng(0)
    yy, xx = np.mgrid[0:40, 0:50]
    u = 0.5 + 0.4 * xx / 50 + 0.05 * rng.standard_normal((40, 50))  # a ramp: big seam
    p, s = periodic_smooth_decomposition(u)
    np.testing.assert_allclose(p + s, u, atol=1e-5)
    assert abs(float(s.mean())) < 1e-6
    # s is harmonic inside: its discrete Laplacian vanishes away from the edges
    lap = s[:-2, 1:-1] + s[2:, 1:-1] + s[1:-1, :-2] + s[1:-1, 2:] - 4 * s[1:-1, 1:-1]
    assert np.abs(lap[1:-1, 1:-1]).max() < 1e-5
    wrap = np.abs(p[:, 0] - p[:, -1]).mean()
    inner = np.abs(np.diff(p, axis=1)).mean()
    assert wrap < 1.3 * inner
    assert np.abs(u[:, 0] - u[:, -1]).mean() > 4 * np.abs(np.diff(u, axis=1)).mean()


def test_spectral_slope_checks():
    f = np.array([0.1, 0.2, 0.4])
    fit = spectral_slope(f, 3.0 * f ** -2.5)
    assert abs(fit.slope + 2.5) < 1e-12 and abs(fit.intercept - np.log10(3.0)) < 1e-12
    with pytest.raises(ValueError, match="fmax must be greater"):
        spectral_slope(f, f, fmin=0.3, fmax=0.2)
    with pytest.raises(ValueError, match="fewer than two"):
        spectral_slope(f, np.array([1.0, 0.0, 0.0]))


# --------------------------------------------------------------------------
# The slope fit counts every octave alike (issue 18)
# --------------------------------------------------------------------------

def _octave_means(freqs, power, lo, hi):
    """Mean log10 f and log10 P of each octave of [lo, hi]: one point per octave (the second route)."""
    edges = lo * 2.0 ** np.arange(0, np.log2(hi / lo) + 1e-9)
    xs, ys = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        sel = (freqs >= a) & (freqs < b)
        if sel.any():
            xs.append(np.log10(np.sqrt(a * b)))
            ys.append(np.mean(np.log10(power[sel])))
    return np.array(xs), np.array(ys)


def test_slope_fit_of_a_bent_spectrum_follows_the_octaves():
    # Rings evenly spaced in f as radial_power_spectrum gives them (512 pixels): power ~ f^-1 for three
    # octaves, then ~ f^-3 for three more. Each octave counts alike: the slope is near the mean, -2,
    # and a line through one mean point per octave agrees. The old unweighted fit (control) follows
    # the top octaves, and misses the lowest ring by about 10x.
    freqs = np.arange(1, 257) / 512.0
    lo, hi, bend = 2 / 512, 0.25, 2 / 512 * 8
    power = np.where(freqs < bend, (freqs / bend) ** -1.0, (freqs / bend) ** -3.0)
    fit = spectral_slope(freqs, power, fmin=lo, fmax=hi)
    old = spectral_slope(freqs, power, fmin=lo, fmax=hi, weighting="none")
    assert abs(fit.slope + 2.0) < 0.1
    xs, ys = _octave_means(freqs, power, lo, hi)
    a, _ = np.polyfit(xs, ys, 1)
    assert abs(fit.slope - a) < 0.1
    assert old.slope < -2.3  # the control follows the top octaves
    k = np.argmin(np.abs(freqs - lo))
    miss_new = abs(np.log10(power[k]) - (fit.slope * np.log10(freqs[k]) + fit.intercept))
    miss_old = abs(np.log10(power[k]) - (old.slope * np.log10(freqs[k]) + old.intercept))
    assert miss_old > 0.95 and miss_new < 0.5  # 10^0.99, about 10x; 10^0.45 (the bend's own, at both ends)


@pytest.mark.parametrize("beta", [1.5, 2.5])
def test_slope_fit_of_noise_with_a_known_slope(beta):
    slopes = []
    for seed in range(4):
        x = spectral_noise(256, beta=beta, rng=seed)
        freqs, power = radial_power_spectrum(x)
        slopes.append(spectral_slope(freqs, power, fmin=2 / 256, fmax=0.25).slope)
    assert abs(np.mean(slopes) + beta) < 0.1


def test_slope_weighting_is_uniform_on_log_spaced_points_and_checked():
    # On points evenly spaced in log f, every point stands for the same stretch (bar the trapezoid's
    # half-weight ends): the weighted fit of an exact power law is exact.
    f = np.geomspace(0.01, 0.5, 12)
    fit = spectral_slope(f, 2.0 * f ** -1.7)
    assert abs(fit.slope + 1.7) < 1e-12 and abs(fit.intercept - np.log10(2.0)) < 1e-12
    with pytest.raises(ValueError, match="weighting"):
        spectral_slope(f, f, weighting="linear")
