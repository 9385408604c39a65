"""The magnification kernels of :mod:`spectex.spectral._octaves`, discretised.

The definition (one axis, phases, the normalisation ``S_r``) and the cost
model are in that module's docstring. The CPU route (``_octaves``) and the
OpenGL route (``_magnify_gl``) both build on these, so neither imports the
other.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from .._validate import check_choice, check_float, check_int

FILTERS = ("box", "tent", "bspline", "catmull-rom", "gaussian")

#: Gaussian truncation radius, in standard deviations.
GAUSSIAN_TRUNCATE = 3.0


def _kernel(name: str, sigma: float):
    """Return ``(f, radius)``: the continuous filter and its support radius."""
    if name == "box":
        return (lambda t: ((t >= -0.5) & (t < 0.5)).astype(np.float64)), 0.5
    if name == "tent":
        return (lambda t: np.maximum(0.0, 1.0 - np.abs(t))), 1.0
    if name == "bspline":
        def f(t):
            a = np.abs(t)
            return np.where(a < 1.0, (4.0 - 6.0 * a**2 + 3.0 * a**3) / 6.0,
                            np.where(a < 2.0, (2.0 - a) ** 3 / 6.0, 0.0))
        return f, 2.0
    if name == "catmull-rom":
        def f(t):
            a = np.abs(t)
            return np.where(a < 1.0, 1.5 * a**3 - 2.5 * a**2 + 1.0,
                            np.where(a < 2.0, -0.5 * a**3 + 2.5 * a**2 - 4.0 * a + 2.0, 0.0))
        return f, 2.0
    radius = GAUSSIAN_TRUNCATE * sigma
    return (lambda t: np.where(np.abs(t) < radius, np.exp(-0.5 * (t / sigma) ** 2), 0.0)), radius


def _check_filter(kernel, sigma):
    kernel = check_choice("kernel", kernel, FILTERS)
    sigma = check_float("sigma", sigma, minimum=0.05, maximum=64.0)
    return kernel, sigma


def _phase_weights(filter: str, factor: int, sigma: float):
    """Polyphase weights.

    Returns ``(weights, first)``: ``weights[r, t]`` is the weight of input
    texel ``q + first[r] + t`` in output texel ``q m + r``; ``first`` holds at
    most two distinct, consecutive values, non-decreasing in ``r``.
    """
    f, radius = _kernel(filter, sigma)
    m = factor
    phi = (np.arange(m) + 0.5) / m - 0.5
    # Input texels k with |q + phi - k| < radius: k - q in (phi - R, phi + R).
    first = np.floor(phi - radius).astype(np.int64) + 1
    taps = int(math.ceil(2.0 * radius))
    k = first[:, None] + np.arange(taps)[None, :]
    w = f(phi[:, None] - k)
    w = w / w.sum(axis=1, keepdims=True)
    return w, first


def filter_passes(kernel: str = "bspline", *, sigma: float = 0.5) -> int:
    """Number of passes per axis that :func:`magnify` makes with ``kernel``.

    It is the number of input texels under the kernel's footprint,
    ``ceil(2 * radius)``, independent of the input size and of the
    magnification (see the module's cost model).
    """
    kernel, sigma = _check_filter(kernel, sigma)
    return int(math.ceil(2.0 * _kernel(kernel, sigma)[1]))


def discrete_filter(kernel, factor, *, sigma: float = 0.5):
    """The magnification kernel discretised for magnification by ``factor``.

    Parameters
    ----------
    kernel : {'box', 'tent', 'bspline', 'catmull-rom', 'gaussian'}
    factor : int
        Magnification ``m`` (output texels per input texel), >= 1.
    sigma : float
        Standard deviation of the Gaussian, in input texels (truncated at
        ``3 sigma``); ignored by the other filters.

    Returns
    -------
    taps : ndarray of float64, shape (L,)
        ``h[j]`` for ``j = start, start + 1, ..., start + L - 1``: the weight
        that a zero-stuffed input sample puts on the output ``j`` texels
        after it (see the module docstring).
    start : int
        The offset of ``taps[0]``.
    """
    kernel, sigma = _check_filter(kernel, sigma)
    m = check_int("factor", factor, minimum=1)
    w, first = _phase_weights(kernel, m, sigma)
    # Output q m + r reads input q + first[r] + t, i.e. j = p - k m
    # = r - (first[r] + t) m.
    js = np.arange(m)[:, None] - (first[:, None] + np.arange(w.shape[1])[None, :]) * m
    start = int(js.min())
    taps = np.zeros(int(js.max()) - start + 1)
    np.add.at(taps, (js - start).ravel(), w.ravel())
    return taps, start


def _factors(factor):
    if isinstance(factor, numbers.Integral) and not isinstance(factor, bool):
        factor = (factor, factor)
    if not isinstance(factor, (tuple, list)) or len(factor) != 2:
        raise ValueError(f"factor must be an int or a (rows, columns) pair of ints, got {factor!r}")
    return (check_int("factor[0]", factor[0], minimum=1, maximum=1 << 14),
            check_int("factor[1]", factor[1], minimum=1, maximum=1 << 14))


def _check_image(image) -> np.ndarray:
    """The image as a float32 or float64 array of shape (H, W) or (H, W, C)."""
    x = np.asarray(image)
    if x.ndim not in (2, 3):
        raise ValueError(f"image must have shape (H, W) or (H, W, C), got shape {x.shape}")
    if x.shape[0] < 1 or x.shape[1] < 1 or (x.ndim == 3 and x.shape[2] < 1):
        raise ValueError(f"image must not be empty, got shape {x.shape}")
    if x.dtype not in (np.float32, np.float64):
        x = x.astype(np.float64)
    if not np.all(np.isfinite(x)):
        raise ValueError("image must hold finite values, got NaN or infinity")
    return x
