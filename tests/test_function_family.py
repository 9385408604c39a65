"""The colour-science test family (issue 18) for the public functions of
``spectex.color``, ``spectex.procedural``, ``spectex.tiles``, ``spectex.spectral``,
``spectex.metrics``, ``spectex.analysis``, ``spectex.synthesis``, ``spectex.figures``,
``spectex.io.to_uint`` and the parameters of ``Layer`` and ``Camera``.

Three tables, one test each:

* ``REFERENCES``: values worked out by hand or from the standard behind the
  function (Rec. 709, IEC 61966-2-1, the Hann window's sin^2 form, ...); an
  entry's optional fourth item is its tolerance (default 2e-6).
* ``ND``: functions of arrays of points or values give the same numbers for an
  n-dimensional input as for its flattened form.
* ``SWEEP``: each numeric parameter given -1, 0, 1, +inf, -inf and NaN (in the
  array, for array parameters) either gives a defined result or raises a
  ``ValueError``/``TypeError`` of one line that names the parameter; never
  another exception, a warning (pytest turns them into errors) or a hang.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from spectex import analysis, color, figures, io, metrics, periodic, procedural, spectral, spectrum, synthesis, tiles
from spectex.render import Camera
from spectex.texture import Layer

# ----------------------------------------------------------------- references

_WHITE = np.ones((1, 1, 3), np.float32)


def _rgb(r, g, b):
    return np.array([[[r, g, b]]], np.float32)


def _noise(n=32, seed=0):
    return np.random.default_rng(seed).random((n, n))


def _sinusoid(a, cycles, n):
    y, x = np.mgrid[0:n, 0:n]
    return 0.5 + a * np.sin(2 * np.pi * (cycles * x + 3 * y) / n)


def _ramp():
    y, x = np.mgrid[0:32, 0:32]
    return (x + y) / 62.0


def _two_colours():
    img = np.empty((8, 8, 3))
    img[:, :4] = (0.2, 0.3, 0.4)
    img[:, 4:] = (0.8, 0.5, 0.2)
    return img


REFERENCES = [
    # Rec. 709 luma weights, and white is 1
    ("luma red", lambda: color.luma(_rgb(1, 0, 0))[0, 0], 0.2126),
    ("luma green", lambda: color.luma(_rgb(0, 1, 0))[0, 0], 0.7152),
    ("luma blue", lambda: color.luma(_rgb(0, 0, 1))[0, 0], 0.0722),
    ("luma white", lambda: color.luma(_WHITE)[0, 0], 1.0),
    ("luma grey+alpha is the grey", lambda: color.luma(np.array([[[0.3, 0.9]]], np.float32))[0, 0], 0.3),
    # IEC 61966-2-1: the ends, the joint of the two pieces, and mid-grey
    ("srgb_to_linear 0", lambda: color.srgb_to_linear(0.0), 0.0),
    ("srgb_to_linear 1", lambda: color.srgb_to_linear(1.0), 1.0),
    ("srgb_to_linear joint", lambda: color.srgb_to_linear(0.04045), 0.04045 / 12.92),
    ("srgb_to_linear 0.5", lambda: color.srgb_to_linear(0.5), ((0.5 + 0.055) / 1.055) ** 2.4),
    ("srgb_to_linear 0.5 (value)", lambda: color.srgb_to_linear(0.5), 0.21404114),
    ("linear_to_srgb 0.21404114", lambda: color.linear_to_srgb(0.21404114), 0.5),
    ("linear_to_srgb joint", lambda: color.linear_to_srgb(0.0031308), 0.0031308 * 12.92),
    ("linear_to_srgb 1", lambda: color.linear_to_srgb(1.0), 1.0),
    # the grey ramp from vmin to vmax
    ("apply_colormap grey -1", lambda: color.apply_colormap(-1.0, "grey")[0], 0.0),
    ("apply_colormap grey 0", lambda: color.apply_colormap(0.0, "grey")[1], 0.5),
    ("apply_colormap grey 1", lambda: color.apply_colormap(1.0, "grey")[2], 1.0),
    ("apply_colormap blue keeps blue", lambda: color.apply_colormap(-1.0, "blue")[2], 1.0),
    # fit_range: unchanged inside [0, 1], affine onto it otherwise
    ("fit_range inside", lambda: tiles.fit_range([0.2, 0.7]), [0.2, 0.7]),
    ("fit_range outside", lambda: tiles.fit_range([-1.0, 0.0, 1.0]), [0.0, 0.5, 1.0]),
    # the Hann window as sin^2 of the (n + 2)-point window without its zeros
    ("hann_window 1x3", lambda: spectrum.hann_window((1, 3))[0], [0.5, 1.0, 0.5]),
    ("octave_amplitudes 1/f", lambda: spectral.octave_amplitudes([4, 8, 16]), [1.0, 0.5, 0.25]),
    ("spectral_slope of 3 f^-2.5", lambda: spectrum.spectral_slope(
        np.array([0.1, 0.2, 0.4]), 3.0 * np.array([0.1, 0.2, 0.4]) ** -2.5).slope, -2.5),
    # a constant image is its own periodic component (Moisan): the smooth part is zero
    ("smooth component of a constant", lambda: float(np.abs(
        periodic.periodic_smooth_decomposition(np.full((16, 24), 0.3))[1]).max()), 0.0),
    ("periodic + smooth is the image", lambda: float(np.abs(
        np.sum(periodic.periodic_smooth_decomposition(_periodic()), axis=0) - _periodic()).max()), 0.0),
    # a constant stays constant under band limiting and magnification
    ("band_limit of a constant", lambda: spectral.band_limit(np.full((8, 8), 0.25), high=0.2)[3, 5], 0.25),
    ("magnify of a constant", lambda: spectral.magnify(np.full((4, 4), 0.75), 2)[5, 2], 0.75),
    # a sinusoid of 3 and 4 cycles across 32 pixels: its power is in the ring at 5/32
    ("radial power of a sinusoid peaks at its ring", lambda: _sinusoid_peak(), math.hypot(3, 4) / 32),
    # procedural value ranges
    ("value_range clouds", lambda: procedural.value_range("clouds"), [-1.0, 1.0]),
    # metrics: W1 between all-black and all-white is 1, identical images 0
    ("histogram_w1 black/white", lambda: metrics.histogram_w1(np.zeros((4, 4)), np.ones((6, 6))), [1.0]),
    ("histogram_w1 of a shift by 0.25", lambda: metrics.histogram_w1(_noise(), _noise() + 0.25), [0.25]),
    # band powers of a sinusoid sum to its variance a^2/2 (the Hann window's mean square divided out)
    ("band_power of a sinusoid sums to a^2/2", lambda: float(np.sum(10.0 ** (
        metrics.band_power(_sinusoid(0.3, 8, 64)).power_db / 10.0))), 0.3 ** 2 / 2, 0.02 * 0.045),
    ("band_power_distance to itself", lambda: metrics.band_power_distance(_noise(64), _noise(64)), 0.0),
    # all steps equal (a diagonal ramp): block boundaries look like the interior
    ("seam_energy of a diagonal ramp", lambda: metrics.seam_energy(_ramp(), 8), 1.0, 1e-6),
    # a checkerboard: the wrap step is like every other step
    ("tileability of a checkerboard", lambda: metrics.tileability(np.indices((8, 8)).sum(0) % 2.0), 1.0),
    ("verbatim_copy of a crop", lambda: metrics.verbatim_copy(_noise(64)[8:40, 16:48], _noise(64)), 1.0),
    ("repetition of a tiling", lambda: metrics.repetition(np.tile(_noise(), (2, 2)), 32), 1.0),
    ("repeat_peak of a tiling", lambda: metrics.repeat_peak(np.tile(_noise(), (2, 2))), 1.0, 1e-9),
    ("compare: repeat_peak of a tiling", lambda: metrics.compare(
        np.tile(_noise(), (2, 2)), reference=_noise()).repeat_peak_image, 1.0, 1e-9),
    # analysis: white noise loses 4x the bins, 6.02 dB, per octave coarser; two colours' mean
    ("octave_power slope of white noise", lambda: np.mean([analysis.octave_power(
        np.random.default_rng(s).random((256, 256))).slope_db for s in range(4)]), -6.02, 0.3),
    ("colour_stats mean of two colours", lambda: analysis.colour_stats(_two_colours()).mean, [0.5, 0.4, 0.3]),
    ("colour_stats principal colours", lambda: analysis.colour_stats(_two_colours()).principal_colours,
     [[0.2, 0.3, 0.4], [0.8, 0.5, 0.2]]),
    ("dog_bands sum to the image less its blur", lambda: float(np.abs(np.sum(analysis.dog_bands(_noise(), 3), axis=0)
     - (_noise() - __import__("scipy.ndimage").ndimage.gaussian_filter(_noise(), 4.0, mode="reflect"))).max()),
     0.0, 1e-6),  # float32 inside
    # synthesis: matching a histogram gives the exemplar's values exactly (same size: a permutation)
    ("match_histogram gives the exemplar's values", lambda: np.sort(synthesis.match_histogram(
        _noise(), _noise(seed=5) ** 2).ravel()), np.sort((_noise(seed=5) ** 2).ravel()), 1e-7),
    ("sample_histogram draws the exemplar's values", lambda: float(np.isin(synthesis.sample_histogram(
        _noise(8), (16, 16), rng=1), _noise(8).astype(np.float32)).mean()), 1.0),
    # io: 8-bit quantisation rounds half up, clips, and maps NaN to 0
    ("to_uint 8", lambda: io.to_uint(np.array([0.0, 0.5 / 255, 1.0, 2.0, -1.0, np.nan]), 8), [0, 1, 255, 255, 0, 0]),
    ("to_uint 16", lambda: io.to_uint(np.array([1.0, 0.5]), 16), [65535, 32768]),
    # figures: the montage's size, the images in place
    ("montage shape", lambda: figures.montage([np.zeros((4, 5)), np.ones((6, 3, 3))], gap=2).shape, [6, 10, 3]),
    ("montage places the second image", lambda: figures.montage([np.zeros((4, 5)), np.ones((6, 3, 3))],
                                                                 gap=2)[5, 7:10, 1], [1.0, 1.0, 1.0]),
]


def _periodic():
    y, x = np.mgrid[0:16, 0:24]
    return (0.5 + 0.2 * np.sin(2 * np.pi * (2 * x / 24 + y / 16)) + 0.1 * np.cos(2 * np.pi * 3 * y / 16))


def _sinusoid_peak():
    y, x = np.mgrid[0:32, 0:32]
    freqs, power = spectrum.radial_power_spectrum(np.sin(2 * np.pi * (3 * x + 4 * y) / 32))
    return freqs[np.argmax(power)]


@pytest.mark.parametrize("entry", REFERENCES, ids=[r[0] for r in REFERENCES])
def test_reference_values(entry):
    name, call, expected = entry[:3]
    got = np.asarray(call(), dtype=np.float64)
    tol = entry[3] if len(entry) > 3 else (0.5 / 32 if "ring" in name else 2e-6)
    np.testing.assert_allclose(got, np.asarray(expected, dtype=np.float64), rtol=0, atol=tol)


# ----------------------------------------------------- n-dimensional inputs

_VALUES = np.linspace(-0.2, 1.2, 24).reshape(2, 3, 4)


def _image_nd(f):
    """f applied to (2, 3, 4, 3) pixels laid out as an image of 6 x 4 and of 24 x 1."""
    px = np.random.default_rng(1).random((2, 3, 4, 3)).astype(np.float32)
    return f(px.reshape(6, 4, 3)).reshape(2, 3, 4), f(px.reshape(24, 1, 3)).reshape(2, 3, 4)


ND = [
    ("srgb_to_linear", color.srgb_to_linear),
    ("linear_to_srgb", color.linear_to_srgb),
    ("apply_colormap", lambda v: color.apply_colormap(v, "earth", vmin=0.0, vmax=1.0)),
    ("fit_range", tiles.fit_range),
    ("ring_profile", lambda v: procedural.ring_profile(v * 7.0, 0.3)),
]


@pytest.mark.parametrize("name, f", ND, ids=[n for n, _ in ND])
def test_nd_input_gives_the_numbers_of_its_flattened_form(name, f):
    nd = np.asarray(f(_VALUES))
    flat = np.asarray(f(_VALUES.ravel()))
    assert nd.shape[:3] == _VALUES.shape
    np.testing.assert_array_equal(nd.reshape(flat.shape), flat)
    assert not np.array_equal(nd.reshape(flat.shape), np.asarray(f(_VALUES.ravel()[::-1])))  # a control


def test_nd_luma_is_per_pixel():
    a, b = _image_nd(color.luma)
    np.testing.assert_array_equal(a, b)


ND_VALUES = [
    ("to_uint 8", lambda v: io.to_uint(v, 8)),
    ("to_uint 16", lambda v: io.to_uint(v, 16)),
]


@pytest.mark.parametrize("name, f", ND_VALUES, ids=[n for n, _ in ND_VALUES])
def test_nd_values_give_the_numbers_of_their_flattened_form(name, f):
    nd = np.asarray(f(_VALUES))
    flat = np.asarray(f(_VALUES.ravel()))
    assert nd.shape == _VALUES.shape
    np.testing.assert_array_equal(nd.ravel(), flat)


#: Functions of an image's pixels that do not depend on where the pixels are: the same
#: numbers for the pixels laid out as 6 x 4 and as 24 x 1 (their flattened form).
ND_LAYOUT = [
    ("histogram_w1", lambda px: metrics.histogram_w1(px, np.full((3, 3, 3), 0.4, np.float32))),
    ("colour_stats mean", lambda px: analysis.colour_stats(px).mean),
    ("colour_stats covariance", lambda px: analysis.colour_stats(px).covariance),
    ("colour_stats histograms", lambda px: analysis.colour_stats(px).histograms),
]


@pytest.mark.parametrize("name, f", ND_LAYOUT, ids=[n for n, _ in ND_LAYOUT])
def test_pixel_statistics_do_not_depend_on_the_layout(name, f):
    px = np.random.default_rng(1).random((2, 3, 4, 3)).astype(np.float32)
    a = np.asarray(f(px.reshape(6, 4, 3)))
    b = np.asarray(f(px.reshape(24, 1, 3)))
    np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)
    assert not np.allclose(a, np.asarray(f(px.reshape(6, 4, 3)[::-1] ** 2)))  # a control


def test_nd_match_histogram_is_per_pixel():
    """match_histogram ranks pixels wherever they are: the 6 x 4 and the 24 x 1 layouts of the
    same pixels get the same values, pixel for pixel."""
    px = np.random.default_rng(3).random((2, 3, 4, 3)).astype(np.float32)
    ex = np.random.default_rng(4).random((5, 5, 3)).astype(np.float32) ** 2
    a = synthesis.match_histogram(px.reshape(6, 4, 3), ex).reshape(2, 3, 4, 3)
    b = synthesis.match_histogram(px.reshape(24, 1, 3), ex).reshape(2, 3, 4, 3)
    np.testing.assert_array_equal(a, b)


def test_nd_power_spectrum_channels_are_independent():
    x = np.random.default_rng(2).random((16, 20, 3))
    freqs, power = spectrum.radial_power_spectrum(x)
    for c in range(3):
        np.testing.assert_array_equal(spectrum.radial_power_spectrum(x[:, :, c])[1], power[:, c])
    fit = spectrum.spectral_slope(freqs, power)
    for c in range(3):
        assert fit.slope[c] == spectrum.spectral_slope(freqs, power[:, c]).slope


# ------------------------------------------------------ the hostile sweep

SPECIAL = [-1.0, 0.0, 1.0, math.inf, -math.inf, math.nan]


def _img(v, shape=(16, 16), channels=None):
    """A small image with one pixel set to v."""
    x = np.random.default_rng(0).random(shape if channels is None else shape + (channels,)).astype(np.float32)
    x[3, 5] = v
    return x


_TILE = None


def _tile(v):
    global _TILE
    if _TILE is None:
        _TILE = tiles.make_tile(16, rng=0)
    t = _TILE.copy()
    t[2, 3, 0] = v
    return t


_F = np.array([0.1, 0.2, 0.3, 0.4])

# (function, parameter named in its errors, call with the value)
SWEEP = [
    # color
    ("luma", "image", lambda v: color.luma(_img(v, channels=3))),
    ("srgb_to_linear", None, lambda v: color.srgb_to_linear(np.array([0.2, v]))),
    ("linear_to_srgb", None, lambda v: color.linear_to_srgb(np.array([0.2, v]))),
    ("apply_colormap values", None, lambda v: color.apply_colormap(np.array([0.2, v]))),
    ("apply_colormap vmin", "vmin", lambda v: color.apply_colormap(0.5, vmin=v, vmax=2.0)),
    ("apply_colormap vmax", "vmax", lambda v: color.apply_colormap(0.5, vmin=-2.0, vmax=v)),
    # tiles
    ("make_tile cutoff", "cutoff", lambda v: tiles.make_tile(16, cutoff=v)),
    ("make_tile beta", "beta", lambda v: tiles.make_tile(16, beta=v)),
    ("make_tile low", "low", lambda v: tiles.make_tile(16, low=v)),
    ("make_tile octaves", "octaves", lambda v: tiles.make_tile(16, method="noise", octaves=v)),
    ("make_tile noise_scale", "noise_scale", lambda v: tiles.make_tile(16, method="noise", noise_scale=v)),
    ("make_tile azimuth", "azimuth", lambda v: tiles.make_tile(16, azimuth=v)),
    ("make_tile strength", "strength", lambda v: tiles.make_tile(16, strength=v)),
    ("make_tile alpha_value", "alpha_value", lambda v: tiles.make_tile(16, alpha="none", alpha_value=v)),
    ("make_tile shape", "shape", lambda v: tiles.make_tile(v)),
    ("make_seamless image", "image", lambda v: tiles.make_seamless(_img(v, (24, 24), 3))),
    ("make_seamless cutoff", "cutoff", lambda v: tiles.make_seamless(_img(0.5, (24, 24), 3), cutoff=v)),
    ("make_seamless strength", "strength",
     lambda v: tiles.make_seamless(_img(0.5, (24, 24), 3), alpha="emboss", strength=v)),
    ("make_seamless alpha_value", "alpha_value",
     lambda v: tiles.make_seamless(_img(0.5, (24, 24), 3), alpha_value=v)),
    ("emboss image", "image", lambda v: tiles.emboss(_img(v))),
    ("emboss azimuth", "azimuth", lambda v: tiles.emboss(_img(0.5), azimuth=v)),
    ("emboss strength", "strength", lambda v: tiles.emboss(_img(0.5), strength=v)),
    ("fit_range", "values", lambda v: tiles.fit_range(np.array([0.2, v]))),
    ("mip_chain", "tile", lambda v: tiles.mip_chain(_tile(v))),
    ("mip_chain linear", "tile", lambda v: tiles.mip_chain(_tile(v), space="linear")),
    ("preview tile", "tile", lambda v: tiles.preview(_tile(v))),
    ("preview repeat", "repeat", lambda v: tiles.preview(_tile(0.5), repeat=v)),
    ("preview max_side", "max_side", lambda v: tiles.preview(_tile(0.5), max_side=v)),
    # spectral
    ("spectral_noise beta", "beta", lambda v: spectral.spectral_noise(16, beta=v, rng=0)),
    ("spectral_noise low", "low", lambda v: spectral.spectral_noise(16, low=v, rng=0)),
    ("spectral_noise high", "high", lambda v: spectral.spectral_noise(16, high=v, rng=0)),
    ("band_limit image", "image", lambda v: spectral.band_limit(_img(v), high=0.2)),
    ("band_limit high", "high", lambda v: spectral.band_limit(_img(0.5), high=v)),
    ("band_limit low", "low", lambda v: spectral.band_limit(_img(0.5), low=v)),
    ("octave_amplitudes", "amplitudes", lambda v: spectral.octave_amplitudes([4, 8], v)),
    ("octave_amplitudes cells", "cells", lambda v: spectral.octave_amplitudes([4, v])),
    ("octave_sum amplitudes", "amplitudes", lambda v: spectral.octave_sum(16, amplitudes=v, rng=0)),
    ("octave cells", "cells", lambda v: spectral.octave(16, v, rng=0)),
    ("octave sigma", "sigma", lambda v: spectral.octave(16, 4, kernel="gaussian", sigma=v, rng=0)),
    ("magnify image", "image", lambda v: spectral.magnify(_img(v, (8, 8)), 2)),
    ("magnify factor", "factor", lambda v: spectral.magnify(_img(0.5, (8, 8)), v)),
    ("magnify sigma", "sigma", lambda v: spectral.magnify(_img(0.5, (8, 8)), 2, kernel="gaussian", sigma=v)),
    ("filter_passes sigma", "sigma", lambda v: spectral.filter_passes("gaussian", sigma=v)),
    ("discrete_filter factor", "factor", lambda v: spectral.discrete_filter("bspline", v)),
    ("hann_window shape", "shape", lambda v: spectrum.hann_window((4, v))),
    ("periodic_smooth_decomposition", "image", lambda v: periodic.periodic_smooth_decomposition(_img(v))),
    ("radial_power_spectrum", "image", lambda v: spectrum.radial_power_spectrum(_img(v))),
    ("correlation_length image", "image", lambda v: spectrum.correlation_length(_img(v, (32, 32)))),
    ("correlation_length level", "level", lambda v: spectrum.correlation_length(_img(0.5, (32, 32)), level=v)),
    ("correlation_length detail", "detail", lambda v: spectrum.correlation_length(_img(0.5, (32, 32)), detail=v)),
    ("spectral_slope power", None, lambda v: spectrum.spectral_slope(_F, np.array([1.0, 0.5, v, 0.1]))),
    ("spectral_slope freqs", None, lambda v: spectrum.spectral_slope(np.array([0.1, v, 0.3, 0.4]),
                                                                      np.array([1.0, 0.5, 0.3, 0.1]))),
    ("spectral_slope fmin", "fmin", lambda v: spectrum.spectral_slope(_F, 1.0 / _F, fmin=v)),
    ("spectral_slope fmax", "fmax", lambda v: spectrum.spectral_slope(_F, 1.0 / _F, fmax=v)),
    # procedural
    ("noise_image scale", "scale", lambda v: procedural.noise_image(16, scale=v)),
    ("noise_image octaves", "octaves", lambda v: procedural.noise_image(16, octaves=v)),
    ("noise_image lacunarity", "lacunarity", lambda v: procedural.noise_image(16, lacunarity=v)),
    ("noise_image gain", "gain", lambda v: procedural.noise_image(16, gain=v)),
    ("noise_image time", "time", lambda v: procedural.noise_image(16, time=v)),
    ("marble stripes", "stripes", lambda v: procedural.marble(16, stripes=v)),
    ("marble strength", "strength", lambda v: procedural.marble(16, strength=v)),
    ("wood rings", "rings", lambda v: procedural.wood(16, rings=v)),
    ("wood strength", "strength", lambda v: procedural.wood(16, strength=v)),
    ("stripes frequency", "frequency", lambda v: procedural.stripes(16, frequency=v)),
    ("clouds cover", "cover", lambda v: procedural.clouds(16, cover=v)),
    ("clouds sharpness", "sharpness", lambda v: procedural.clouds(16, sharpness=v)),
    ("ring_profile t", None, lambda v: procedural.ring_profile(np.array([0.3, v]), 0.2)),
    ("ring_profile width", "width", lambda v: procedural.ring_profile(np.array([0.3, 1.7]), v)),
    ("contrast_range", "field", lambda v: procedural.contrast_range(_img(v))),
    ("colorize field", "field", lambda v: procedural.colorize(_img(v), "earth")),
    ("colorize vrange", "vrange", lambda v: procedural.colorize(_img(0.5), "earth", vrange=(v, 2.0))),
    ("animate speed", "speed", lambda v: procedural.animate("fbm", 8, 2, speed=v)),
    # metrics
    ("histogram_w1 a", "a", lambda v: metrics.histogram_w1(_img(v), _img(0.5))),
    ("histogram_w1 b", "b", lambda v: metrics.histogram_w1(_img(0.5), _img(v))),
    ("band_power image", "image", lambda v: metrics.band_power(_img(v, (32, 32)), min_cycles=2)),
    ("band_power min_cycles", "min_cycles", lambda v: metrics.band_power(_img(0.5, (32, 32)), min_cycles=v)),
    ("band_power_distance", "a", lambda v: metrics.band_power_distance(_img(v, (32, 32)), _img(0.5, (32, 32)),
                                                                        min_cycles=2)),
    ("seam_energy image", "image", lambda v: metrics.seam_energy(_img(v), 8)),
    ("seam_energy block", "block", lambda v: metrics.seam_energy(_img(0.5), v)),
    ("seam_energy overlap", "overlap", lambda v: metrics.seam_energy(_img(0.5), 8, v)),
    ("tileability", "image", lambda v: metrics.tileability(_img(v))),
    ("tileability axis", "axis", lambda v: metrics.tileability(_img(0.5), axis=v)),
    ("verbatim_copy image", "image", lambda v: metrics.verbatim_copy(_img(v), _img(0.5))),
    ("verbatim_copy patch", "patch", lambda v: metrics.verbatim_copy(_img(0.5), _img(0.5), patch=v)),
    ("repetition image", "image", lambda v: metrics.repetition(_img(v), 8)),
    ("repetition period", "period", lambda v: metrics.repetition(_img(0.5), v)),
    ("repeat_peak image", "image", lambda v: metrics.repeat_peak(_img(v), min_lag=4)),
    ("repeat_peak min_lag", "min_lag", lambda v: metrics.repeat_peak(_img(0.5), min_lag=v)),
    ("repeat_peak sigma", "sigma", lambda v: metrics.repeat_peak(_img(0.5), min_lag=4, sigma=v)),
    ("compare image", "image", lambda v: metrics.compare(_img(v), reference=_img(0.5))),
    ("compare reference", "reference", lambda v: metrics.compare(_img(0.5), reference=_img(v))),
    ("compare block", "block", lambda v: metrics.compare(_img(0.5), reference=_img(0.5), block=v)),
    # analysis
    ("octave_power image", "image", lambda v: analysis.octave_power(_img(v, (32, 32)), min_cycles=2)),
    ("colour_stats image", "image", lambda v: analysis.colour_stats(_img(v, channels=3))),
    ("colour_stats bins", "bins", lambda v: analysis.colour_stats(_img(0.5, channels=3), bins=v)),
    ("dog_bands image", "image", lambda v: analysis.dog_bands(_img(v), 2)),
    ("dog_bands levels", "levels", lambda v: analysis.dog_bands(_img(0.5), v)),
    ("cross_scale image", "image", lambda v: analysis.cross_scale(_img(v, (64, 64)))),
    ("cross_scale step", "step", lambda v: analysis.cross_scale(_img(0.5, (64, 64)), step=v)),
    ("analyse image", "image", lambda v: analysis.analyse(_img(v, (32, 32), 3))),
    # synthesis
    ("sample_histogram exemplar", "exemplar", lambda v: synthesis.sample_histogram(_img(v), (8, 8))),
    ("sample_histogram shape", "shape", lambda v: synthesis.sample_histogram(_img(0.5), (8, v))),
    ("match_histogram image", "image", lambda v: synthesis.match_histogram(_img(v), _img(0.5))),
    ("match_histogram exemplar", "exemplar", lambda v: synthesis.match_histogram(_img(0.5), _img(v))),
    ("match_histogram iterations", "iterations",
     lambda v: synthesis.match_histogram(_img(0.5, channels=3), _img(0.5, channels=3), joint=True, iterations=v)),
    ("quilt exemplar", "exemplar", lambda v: synthesis.quilt(_img(v), (16, 16), block=8)),
    ("quilt block", "block", lambda v: synthesis.quilt(_img(0.5), (16, 16), block=v)),
    ("quilt overlap", "overlap", lambda v: synthesis.quilt(_img(0.5), (16, 16), block=8, overlap=v)),
    ("quilt tolerance", "tolerance", lambda v: synthesis.quilt(_img(0.5), (16, 16), block=8, tolerance=v)),
    ("efros_leung window", "window", lambda v: synthesis.efros_leung(_img(0.5), (8, 8), window=v)),
    ("efros_leung epsilon", "epsilon", lambda v: synthesis.efros_leung(_img(0.5), (8, 8), window=5, epsilon=v)),
    # figures and io
    ("montage image", "images[0]", lambda v: figures.montage([_img(v)])),
    ("montage gap", "gap", lambda v: figures.montage([_img(0.5)], gap=v)),
    ("montage background", "background", lambda v: figures.montage([_img(0.5)], background=v)),
    ("to_uint", None, lambda v: io.to_uint(np.array([0.2, v]))),
    # the texture's layers and the camera
    ("Layer size", "size", lambda v: Layer(size=v)),
    ("Layer rotation", "rotation", lambda v: Layer(size=1.0, rotation=v)),
    ("Layer opacity", "opacity", lambda v: Layer(size=1.0, opacity=v)),
    ("Layer offset", "offset", lambda v: Layer(size=1.0, offset=(v, 0.0))),
    ("Layer patch", "patch", lambda v: Layer(size=1.0, tiling="stochastic", patch=v)),
    ("Camera z", "z", lambda v: Camera((0.0, 0.0, v))),
    ("Camera x", "x", lambda v: Camera((v, 0.0, 1.0))),
    ("Camera yaw", "yaw", lambda v: Camera((0.0, 0.0, 1.0), yaw=v)),
    ("Camera pitch", "pitch", lambda v: Camera((0.0, 0.0, 1.0), pitch=v)),
    ("Camera fov", "fov", lambda v: Camera((0.0, 0.0, 1.0), fov=v)),
]


@pytest.mark.parametrize("value", SPECIAL, ids=["-1", "0", "1", "inf", "-inf", "nan"])
@pytest.mark.parametrize("name, param, call", SWEEP, ids=[s[0] for s in SWEEP])
def test_special_values_give_a_result_or_a_named_one_line_error(name, param, call, value):
    try:
        call(value)
    except (ValueError, TypeError) as exc:
        text = str(exc)
        assert "\n" not in text.strip(), text
        if param is not None:
            assert param in text, f"the error does not name {param!r}: {text}"
        else:
            pytest.fail(f"{name} takes any value, but {value} raised: {text}")
