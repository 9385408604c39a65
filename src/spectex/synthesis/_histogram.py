"""Simple statistics: independent sampling and exact histogram matching."""

from __future__ import annotations

import numpy as np

from .._validate import check_image, check_int, check_rng, check_shape


def sample_histogram(exemplar, shape, *, joint: bool = True, rng=0) -> np.ndarray:
    """A texture whose pixels are drawn independently from the exemplar's.

    Seed 002's first model ("assume every pixel is independent: if the sample
    has 1/20 of its pixels with intensity 117, a new pixel has intensity 117
    with probability 1/20"): every output pixel is an exemplar pixel drawn
    uniformly at random, with replacement. The result has the exemplar's
    colour distribution and no spatial structure at all (white noise), the
    baseline the Markov models improve on.

    Parameters
    ----------
    exemplar : ndarray, shape (h, w) or (h, w, C)
        Float in [0, 1] (integers are scaled by their dtype's maximum).
    shape : int or (int, int)
        Output ``(height, width)``.
    joint : bool
        True: draw whole pixels, so the joint colour distribution is kept.
        False: draw each channel independently, keeping only the per-channel
        histograms (the colours decorrelate).
    rng : int, numpy.random.Generator or None
        Randomness (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, the same int the same result; a
        Generator is used (and advanced); None draws fresh randomness.

    Returns
    -------
    ndarray of float32, shape ``shape`` or ``shape + (C,)``

    References
    ----------
    .. [1] A. A. Efros and T. K. Leung, "Texture synthesis by non-parametric
       sampling", ICCV 1999, section 1 (the independent-pixel model their
       Markov model replaces).
    """
    ex = check_image("exemplar", exemplar, unit=True)
    h, w = check_shape("shape", shape)
    rng = check_rng(rng)
    flat = ex.reshape(ex.shape[0] * ex.shape[1], -1)
    if joint or flat.shape[1] == 1:
        out = flat[rng.integers(flat.shape[0], size=h * w)]
    else:
        idx = rng.integers(flat.shape[0], size=(h * w, flat.shape[1]))
        out = np.take_along_axis(flat, idx, axis=0)
    out = out.reshape((h, w) + ex.shape[2:])
    return np.ascontiguousarray(out, dtype=np.float32)


def _match_1d(values: np.ndarray, target_sorted: np.ndarray, rng) -> np.ndarray:
    """Exact 1-D matching: the k-th smallest value gets the k-th target quantile.

    Ties in ``values`` are broken at random (a flat image still gets the
    whole target histogram). With ``m`` target values and ``n`` inputs the
    k-th input gets ``target_sorted[floor((k + 1/2) m / n)]``, so for
    ``n == m`` the output is a permutation of the target.
    """
    n = values.size
    m = target_sorted.size
    order = np.lexsort((rng.random(n), values))
    idx = ((np.arange(n) + 0.5) * (m / n)).astype(np.int64)
    out = np.empty(n, dtype=np.float64)
    out[order] = target_sorted[np.minimum(idx, m - 1)]
    return out


def match_histogram(image, exemplar, *, joint: bool = False, iterations: int = 30,
                    rng=0) -> np.ndarray:
    """Give ``image`` the exemplar's histogram exactly, keeping its order.

    Per channel (``joint=False``), each channel's values are ranked and the
    k-th smallest gets the exemplar's k-th quantile: the output's histogram
    *is* the exemplar's (a permutation of its values when the sizes are
    equal, its quantiles otherwise), and the order of the values, hence the
    image's structure, is kept. This is the step of Heeger and Bergen's
    pyramid synthesis.

    With ``joint=True`` the colours are matched as vectors: sliced optimal
    transport (Pitie et al.'s iterative distribution transfer) repeats, for
    ``iterations`` random orthonormal colour bases, an exact 1-D matching of
    the projections onto each axis, which moves the joint colour distribution
    towards the exemplar's (so a colour the exemplar does not have, such as
    red on a green-grey exemplar, does not survive as a mix of marginals).
    A final per-channel pass makes the per-channel histograms exact too.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)
        The image to change.
    exemplar : ndarray, shape (h, w) or (h, w, C)
        The image whose histogram is wanted; same number of channels.
    joint : bool
        Match the joint colour distribution (see above), not only the
        per-channel ones. Ignored for one channel.
    iterations : int
        Random bases for the joint matching, >= 1.
    rng : int, numpy.random.Generator or None
        For tie breaking and the random bases.
        Randomness (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, the same int the same result; a
        Generator is used (and advanced); None draws fresh randomness.

    Returns
    -------
    ndarray of float32, the shape of ``image``

    References
    ----------
    .. [1] D. J. Heeger and J. R. Bergen, "Pyramid-based texture
       analysis/synthesis", SIGGRAPH 1995 (histogram matching).
    .. [2] F. Pitie, A. C. Kokaram, R. Dahyot, "N-dimensional probability
       density function transfer and its application to colour transfer",
       ICCV 2005.
    .. [3] J. Rabin, G. Peyre, J. Delon, M. Bernot, "Wasserstein barycenter
       and its application to texture mixing", SSVM 2011 (sliced transport).
    """
    img = check_image("image", image, unit=True)
    ex = check_image("exemplar", exemplar, unit=True)
    iterations = check_int("iterations", iterations, minimum=1)
    rng = check_rng(rng)
    ci = 1 if img.ndim == 2 else img.shape[2]
    ce = 1 if ex.ndim == 2 else ex.shape[2]
    if ci != ce:
        raise ValueError(f"image and exemplar must have the same number of channels, got shapes "
                         f"{img.shape} and {ex.shape}")
    src = img.reshape(-1, ci).astype(np.float64)
    tgt = ex.reshape(-1, ce).astype(np.float64)
    if joint and ci > 1:
        cur = src.copy()
        for _ in range(iterations):
            q, r = np.linalg.qr(rng.standard_normal((ci, ci)))
            q = q * np.sign(np.diag(r))  # a uniformly random rotation
            p_cur = cur @ q
            p_tgt = tgt @ q
            for k in range(ci):
                p_cur[:, k] = _match_1d(p_cur[:, k], np.sort(p_tgt[:, k]), rng)
            cur = p_cur @ q.T
        src = cur
    out = np.empty_like(src)
    for k in range(ci):
        out[:, k] = _match_1d(src[:, k], np.sort(tgt[:, k]), rng)
    return out.reshape(img.shape).astype(np.float32)
