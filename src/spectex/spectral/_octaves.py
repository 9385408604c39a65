"""Octaves by filtering under magnification (Blythe et al., 1999, 6.21.3).

An octave of ``N x N`` texels is made from a small ``n x n`` random image by
magnifying it ``m = N / n`` times with a reconstruction filter: every input
texel spreads its value over the ``m x m`` output texels around it, weighted
by the filter, and everything wraps around so that the octave tiles.

Definition (one axis; the 2-D filter is the product of two of these)
--------------------------------------------------------------------
Input texel ``k`` has its centre at ``k + 1/2`` in input-texel units and
output texel ``p`` at ``(p + 1/2) / m``, the convention of OpenGL texture
coordinates. Output texel ``p = q m + r`` (``r`` its *phase*, ``0 <= r < m``)
therefore sits at ``q + phi_r`` input texels from the centre of texel ``q``,
with ``phi_r = (r + 1/2) / m - 1/2`` in ``(-1/2, 1/2)``, and::

    y[q m + r] = sum_k x[k mod n] f(q + phi_r - k) / S_r,
    S_r        = sum_k f(phi_r - k)

``S_r`` makes a constant input give a constant output. It is exactly 1 for
box, tent, cubic B-spline and Catmull-Rom (they form a partition of unity)
and close to 1 for the truncated Gaussian, for which it removes a faint
ripple at the input grid's frequency.

Equivalently, ``y`` is the circular convolution of the *zero-stuffed* input
``u`` (``u[k m] = x[k]``, zero elsewhere, length ``N``) with the discretised
filter ``h[j] = f((j + 1/2 - m/2) / m) / S_(j mod m)``; :func:`discrete_filter`
returns ``h``. The tests check :func:`magnify` against that direct
convolution.

With the tent filter the result is exactly OpenGL's bilinear magnification
(``GL_LINEAR``, ``GL_REPEAT``) of the small texture, and with the box filter
exactly ``GL_NEAREST``.

Cost model (the seed's point)
-----------------------------
Output phase ``r`` draws on the ``T`` input texels that the filter's
footprint covers, ``T = ceil(2 R)`` for a filter of radius ``R`` input
texels: box 1, tent 2, cubic B-spline 4, Catmull-Rom 4, Gaussian
``ceil(2 * truncate * sigma)`` (3 with the default ``sigma = 0.5``). The
implementation makes ``T`` *passes* per axis, as the accumulation-buffer
algorithm of the seed does: pass ``t`` shifts the (small) input by one texel
and adds it, weighted by the ``t``-th tap of each phase, into every output
texel. The number of passes depends only on the filter's footprint in input
texels, not on the input size ``n`` or on the magnification ``m``; each pass
costs one multiply-add per output texel, so a separable 2-D octave costs
``T`` passes over an ``N0 x n1`` array and ``T`` passes over the ``N0 x N1``
result: about ``T N0 (n1 + N1)`` multiply-adds. (The seed's non-separable
version makes ``T^2`` passes; 4 for its 2 x 2 footprint.)
"""

from __future__ import annotations

import numbers

import numpy as np

from .._validate import check_choice, check_int, check_rng
from ._filters import _check_filter, _check_image, _factors, _phase_weights

#: Where :func:`magnify` computes: NumPy, or OpenGL through moderngl.
BACKENDS = ("cpu", "gl")

def _union_weights(w: np.ndarray, first: np.ndarray):
    """Polyphase weights over the union of the phases' taps: ``(W, lo)``.

    ``W[r, s]`` is the weight of input texel ``q + lo + s`` in output texel
    ``q m + r`` (zero where phase ``r`` does not reach that texel).
    """
    lo = int(first.min())
    width = int(first.max()) - lo + w.shape[1]
    out = np.zeros((w.shape[0], width))
    for r in range(w.shape[0]):
        s0 = int(first[r]) - lo
        out[r, s0:s0 + w.shape[1]] = w[r]
    return out, lo


def _magnify_last(x: np.ndarray, m: int, w: np.ndarray, first: np.ndarray) -> np.ndarray:
    """Magnify along the last axis (wrapping) with polyphase weights.

    The shifted copies of the input are stacked on a new last axis and
    multiplied by the ``(taps, m)`` weight matrix: one multiply-add per tap
    and output texel, as many taps as the footprint covers.
    """
    wu, lo = _union_weights(w, first)
    n = x.shape[-1]
    # stack[..., q, s] = x[..., (q + lo + s) mod n]
    idx = (np.arange(n)[:, None] + lo + np.arange(wu.shape[1])[None, :]) % n
    stack = x[..., idx]
    out = stack @ wu.T.astype(x.dtype)  # (..., n, m)
    return out.reshape(x.shape[:-1] + (n * m,))


def magnify(image, factor, *, kernel: str = "bspline", sigma: float = 0.5,
            backend: str = "cpu") -> np.ndarray:
    """Magnify a small periodic image with a reconstruction kernel, wrapping around.

    Separable and vectorised: ``T`` passes per axis, ``T`` the number of
    input texels under the filter (:func:`filter_passes`), whatever the sizes.

    Parameters
    ----------
    image : ndarray, shape (n0, n1) or (n0, n1, C)
        The small image, taken as one period of a periodic signal. float32
        stays float32 and float64 stays float64; other dtypes become float64.
    factor : int or (int, int)
        Magnification ``m`` along rows and columns.
    kernel : {'box', 'tent', 'bspline', 'catmull-rom', 'gaussian'}
        The magnification kernel (the reconstruction filter; ``filter``
        elsewhere in spectex means OpenGL's texture filter). Box is
        ``GL_NEAREST``, tent is ``GL_LINEAR``; the cubic B-spline is
        smooth and approximating, Catmull-Rom interpolating (it passes through
        the input values and can overshoot), the Gaussian has standard
        deviation ``sigma`` input texels, truncated at 3 sigma.
    sigma : float
        The Gaussian's standard deviation in input texels.
    backend : {'cpu', 'gl'}
        ``'cpu'``: NumPy, separable, ``T`` passes per axis. ``'gl'``: the
        seed's non-separable multi-pass method on OpenGL 3.3 (moderngl,
        headless EGL), ``T^2`` passes computed in float32 and equal to the
        CPU route to float32 precision; see
        :func:`~spectex.spectral.magnify_gl`, which also reports the passes.

    Returns
    -------
    ndarray, shape (n0 m0, n1 m1) or (n0 m0, n1 m1, C)
        The magnified image; it tiles with period ``(n0 m0, n1 m1)``.

    Raises
    ------
    OSError
        With ``backend='gl'``, if moderngl or a headless OpenGL 3.3 context
        (EGL) is missing; the message says what to install.

    References
    ----------
    D. Blythe et al., "Advanced Graphics Programming Techniques Using
    OpenGL", SIGGRAPH 1999 course, section 6.21.3.
    """
    backend = check_choice("backend", backend, BACKENDS)
    if backend == "gl":
        from ._magnify_gl import magnify_gl

        return magnify_gl(image, factor, kernel=kernel, sigma=sigma).image
    kernel, sigma = _check_filter(kernel, sigma)
    m0, m1 = _factors(factor)
    x = _check_image(image)
    w0, f0 = _phase_weights(kernel, m0, sigma)
    w1, f1 = (w0, f0) if m1 == m0 else _phase_weights(kernel, m1, sigma)
    planes = x[None] if x.ndim == 2 else np.moveaxis(x, 2, 0)  # (C, n0, n1)
    # Rows first, on the small input (transposed so that rows are the last
    # axis), then columns on the (C, N0, n1) result.
    y = _magnify_last(np.swapaxes(planes, 1, 2), m0, w0, f0)  # (C, n1, N0)
    y = _magnify_last(np.ascontiguousarray(np.swapaxes(y, 1, 2)), m1, w1, f1)  # (C, N0, N1)
    return y[0] if x.ndim == 2 else np.ascontiguousarray(np.moveaxis(y, 0, 2))


def octave(shape, cells, *, kernel: str = "bspline", sigma: float = 0.5, rng=None,
           dtype=np.float32) -> np.ndarray:
    """One octave: a random ``cells`` image magnified to ``shape``, tiling.

    Parameters
    ----------
    shape : int or (int, int)
        Output ``(height, width)``; each must be a multiple of the cells.
    cells : int or (int, int)
        Size of the random input image (its texels are independent standard
        normal values), so the octave holds about ``cells / 2`` cycles per
        period along each axis.
    kernel, sigma
        See :func:`magnify`.
    rng : int, numpy.random.Generator or None
        Randomness (SPEC 7): an int gives ``numpy.random.default_rng(rng)``;
        a Generator is used and advanced; None (the default) draws fresh
        randomness.
    dtype : float32 or float64

    Returns
    -------
    ndarray, shape (H, W)
    """
    from .._validate import check_shape

    h, w = check_shape("shape", shape)
    if isinstance(cells, numbers.Integral):
        c0 = c1 = check_int("cells", cells, minimum=1)
    else:
        try:
            c0, c1 = _factors(cells)
        except ValueError:
            raise ValueError(f"cells must be an int or a (rows, columns) pair of ints >= 1, got {cells!r}") from None
    if h % c0 or w % c1:
        raise ValueError(f"shape {h}x{w} (rows x columns) must be a multiple of cells {c0}x{c1}")
    rng = check_rng(rng)
    dtype = np.dtype(dtype)
    if dtype not in (np.float32, np.float64):
        raise ValueError(f"dtype must be float32 or float64, got {dtype}")
    x = rng.standard_normal((c0, c1)).astype(dtype)
    return magnify(x, (h // c0, w // c1), kernel=kernel, sigma=sigma)
