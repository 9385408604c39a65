"""Non-parametric sampling, pixel by pixel (Efros and Leung 1999)."""

from __future__ import annotations

import math

import numba
import numpy as np

from .._limits import check_efros_leung
from .._validate import check_choice, check_float, check_image, check_rng

_METHODS = ("fast", "exhaustive")


# --------------------------------------------------------------------------
# numba kernels (compiled on first use, cached on disk)
# --------------------------------------------------------------------------

@numba.njit(cache=True, nogil=True, inline="always")
def _filled_at(filled, yy, xx, tileable):
    """Whether pixel ``(yy, xx)`` is filled: wrapped around when ``tileable``, else False outside."""
    h, w = filled.shape
    if tileable:
        return filled[yy % h, xx % w]
    if yy < 0 or yy >= h or xx < 0 or xx >= w:
        return False
    return filled[yy, xx]


@numba.njit(cache=True, nogil=True, inline="always")
def _filled_count(filled, y, x, half, tileable):
    """How many pixels of the ``(2 half + 1)^2`` window around ``(y, x)`` are filled."""
    c = 0
    for dy in range(-half, half + 1):
        for dx in range(-half, half + 1):
            if _filled_at(filled, y + dy, x + dx, tileable):
                c += 1
    return c


@numba.njit(cache=True, nogil=True)
def _frontier(filled, half, tileable):
    """Unfilled pixels with a filled 8-neighbour, and their filled-window counts.

    Returns ``(ys, xs, counts)``; ``counts`` is the number of filled pixels
    in the ``(2 half + 1)^2`` window, the ordering key of Efros and Leung.
    """
    h, w = filled.shape
    n = 0
    ys = np.empty(h * w, dtype=np.int64)
    xs = np.empty(h * w, dtype=np.int64)
    for y in range(h):
        for x in range(w):
            if not filled[y, x] and _filled_count(filled, y, x, 1, tileable) > 0:
                ys[n] = y
                xs[n] = x
                n += 1
    counts = np.zeros(n, dtype=np.int64)
    for i in range(n):
        counts[i] = _filled_count(filled, ys[i], xs[i], half, tileable)
    return ys[:n].copy(), xs[:n].copy(), counts


@numba.njit(cache=True, nogil=True, inline="always")
def _add_candidate(p, mark, stamp, cand, nc):
    """Append candidate ``p`` to ``cand[:nc]`` unless already stamped with ``mark``.

    ``stamp[p] == mark`` means ``p`` is already in this pixel's list (marks
    grow with every pixel, so the array never needs clearing). Returns the
    new count.
    """
    if stamp[p] != mark:
        stamp[p] = mark
        cand[nc] = p
        nc += 1
    return nc


@numba.njit(cache=True, nogil=True, inline="always")
def _gather_window(ex_shape, out, filled, src, y, x, gauss, half, tileable, ky, kx, kw, kv, ks):
    """Step 1 of a pixel: the filled pixels of its window, into ``ky, kx, kw, kv, ks``.

    Offsets, Gaussian weights, values, and for each the candidate exemplar
    centre (raster index among the valid centres, -1 if none) that puts this
    neighbour's source at the same offset. Returns ``(count, total weight)``.
    """
    h, w, nch = out.shape
    eh, ew = ex_shape
    vw = ew - 2 * half
    nk = 0
    total_w = 0.0
    for dy in range(-half, half + 1):
        for dx in range(-half, half + 1):
            yy = y + dy
            xx = x + dx
            if tileable:
                yy %= h
                xx %= w
            elif yy < 0 or yy >= h or xx < 0 or xx >= w:
                continue
            if not filled[yy, xx]:
                continue
            ky[nk] = dy
            kx[nk] = dx
            kw[nk] = gauss[dy + half, dx + half]
            for c in range(nch):
                kv[nk, c] = out[yy, xx, c]
            cy = src[yy, xx, 0] - dy
            cx = src[yy, xx, 1] - dx
            if cy >= half and cy < eh - half and cx >= half and cx < ew - half:
                ks[nk] = (cy - half) * vw + (cx - half)
            else:
                ks[nk] = -1
            total_w += kw[nk]
            nk += 1
    return nk, total_w


@numba.njit(cache=True, nogil=True, inline="always")
def _candidates(exhaustive, npos, ks, nk, knn, randoms, mark, stamp, cand):
    """Step 2: every valid centre, or the k-coherence set (each neighbour's
    coherent centre, its ``knn`` and the random ones). Returns the count."""
    nc = 0
    if exhaustive:
        for p in range(npos):
            cand[nc] = p
            nc += 1
        return nc
    for k in range(nk):
        p = ks[k]
        if p < 0:
            continue
        nc = _add_candidate(p, mark, stamp, cand, nc)
        for j in range(knn.shape[1]):
            nc = _add_candidate(knn[p, j], mark, stamp, cand, nc)
    for j in range(randoms.size):
        nc = _add_candidate(randoms[j], mark, stamp, cand, nc)
    return nc


@numba.njit(cache=True, nogil=True, inline="always")
def _errors(ex, cand, nc, ky, kx, kw, kv, nk, vw, half, norm, epsilon, err):
    """Step 3: the normalised weighted SSD of each candidate into ``err``, with
    an early exit (``inf``) once one cannot be within ``1 + epsilon`` of the
    best so far. Returns the best."""
    nch = kv.shape[1]
    best = np.inf
    for j in range(nc):
        p = cand[j]
        cy = p // vw + half
        cx = p % vw + half
        limit = best * (1.0 + epsilon) / norm
        s = 0.0
        for k in range(nk):
            wk = kw[k]
            ey = cy + ky[k]
            ex_ = cx + kx[k]
            d2 = 0.0
            for c in range(nch):
                d = kv[k, c] - ex[ey, ex_, c]
                d2 += d * d
            s += wk * d2
            if s > limit:
                break
        if s > limit:
            err[j] = np.inf
        else:
            e = s * norm
            err[j] = e
            if e < best:
                best = e
    return best


@numba.njit(cache=True, nogil=True, inline="always")
def _choose(err, nc, best, epsilon, u, pool):
    """Step 4: a candidate picked with ``u`` in [0, 1) among those within
    ``1 + epsilon`` of the best; -1 if none has a finite error."""
    cut = best * (1.0 + epsilon)
    npool = 0
    for j in range(nc):
        if err[j] <= cut:
            pool[npool] = j
            npool += 1
    if npool == 0:
        return -1
    return pool[min(int(u * npool), npool - 1)]


@numba.njit(cache=True, nogil=True)
def _fill_round(ex, out, filled, src, order_y, order_x, gauss, half, tileable, knn, exhaustive,
                uniform, random_cands, epsilon, threshold, stamp, stamp_base):
    """Fill the pixels of one round in order; return how many were filled.

    For each pixel: gather the filled pixels of its window (offsets, Gaussian
    weights, values), build the candidate list (all valid exemplar centres,
    or the k-coherence set), compute the normalised weighted SSD of each,
    and pick at random (``uniform``) among those within ``1 + epsilon`` of
    the best; the pixel is filled only if that error is at most
    ``threshold``.
    """
    nch = out.shape[2]
    eh, ew = ex.shape[0], ex.shape[1]
    win = 2 * half + 1
    vw = ew - 2 * half  # valid centres per row
    npos = (eh - 2 * half) * vw
    ky = np.empty(win * win, dtype=np.int64)
    kx = np.empty(win * win, dtype=np.int64)
    kw = np.empty(win * win, dtype=np.float64)
    kv = np.empty((win * win, nch), dtype=np.float64)
    ks = np.empty(win * win, dtype=np.int64)
    cand = np.empty(npos, dtype=np.int64)
    err = np.empty(npos, dtype=np.float64)
    pool = np.empty(npos, dtype=np.int64)
    done = 0
    for i in range(order_y.size):
        y = order_y[i]
        x = order_x[i]
        nk, total_w = _gather_window((eh, ew), out, filled, src, y, x, gauss, half, tileable, ky, kx, kw, kv, ks)
        nc = _candidates(exhaustive, npos, ks, nk, knn, random_cands[i], stamp_base + i + 1, stamp, cand)
        best = _errors(ex, cand, nc, ky, kx, kw, kv, nk, vw, half, 1.0 / (total_w * nch), epsilon, err)
        pick = _choose(err, nc, best, epsilon, uniform[i], pool)
        if pick < 0:  # no finite error (cannot happen with finite inputs): leave the pixel
            continue
        if err[pick] <= threshold:
            p = cand[pick]
            cy = p // vw + half
            cx = p % vw + half
            for c in range(nch):
                out[y, x, c] = ex[cy, cx, c]
            src[y, x, 0] = cy
            src[y, x, 1] = cx
            filled[y, x] = True
            done += 1
    return done


@numba.njit(cache=True, nogil=True)
def _nearest(features, k, exclude_radius, vw, stride):
    """The ``k`` nearest feature vectors of each row (squared distance).

    Rows are exemplar positions in raster order, ``vw`` per row. Positions
    within ``exclude_radius`` pixels (Chebyshev) of the point itself are
    skipped: they are the trivial shifted copies that the coherent
    candidates already provide. Only positions on a grid of ``stride``
    pixels are searched. The features are principal components, largest
    variance first, so most candidates are rejected after the first four
    (exact, just faster).
    """
    n, d = features.shape
    vh = n // vw
    out = np.empty((n, k), dtype=np.int64)
    dist = np.empty(k, dtype=np.float64)
    for i in range(n):
        iy = i // vw
        ix = i % vw
        m = 0
        for jy in range(0, vh, stride):
            near_row = abs(jy - iy) <= exclude_radius
            for jx in range(0, vw, stride):
                if near_row and abs(jx - ix) <= exclude_radius:
                    continue
                j = jy * vw + jx
                bound = dist[k - 1] if m == k else np.inf
                s = 0.0
                for t in range(min(4, d)):
                    diff = features[i, t] - features[j, t]
                    s += diff * diff
                if s >= bound:
                    continue
                for t in range(4, d):
                    diff = features[i, t] - features[j, t]
                    s += diff * diff
                if s >= bound:
                    continue
                pos = m if m < k else k - 1
                if m < k:
                    m += 1
                while pos > 0 and dist[pos - 1] > s:
                    dist[pos] = dist[pos - 1]
                    out[i, pos] = out[i, pos - 1]
                    pos -= 1
                dist[pos] = s
                out[i, pos] = j
        for t in range(m, k):  # fewer than k positions far enough: repeat the last
            out[i, t] = out[i, m - 1] if m > 0 else i
    return out


# --------------------------------------------------------------------------
# Python driver
# --------------------------------------------------------------------------

def _gaussian(window: int) -> np.ndarray:
    """The window's Gaussian weights, sigma = window / 6.4 (Efros and Leung)."""
    sigma = window / 6.4
    r = np.arange(window) - window // 2
    g = np.exp(-(r[:, None] ** 2 + r[None, :] ** 2) / (2.0 * sigma * sigma))
    return g / g.sum()


def _coherence_sets(ex: np.ndarray, window: int, k: int) -> np.ndarray:
    """k-coherence sets: for every valid centre, the k most similar others.

    Similarity is the Gaussian-weighted distance between full windows,
    approximated in the space of the leading principal components (at most
    24) of the weighted window vectors.
    """
    half = window // 2
    eh, ew, nch = ex.shape
    vh, vw = eh - 2 * half, ew - 2 * half
    n = vh * vw
    if k == 0 or n < 2:
        return np.zeros((n, 0), dtype=np.int64)
    from numpy.lib.stride_tricks import sliding_window_view

    wins = sliding_window_view(ex, (window, window), axis=(0, 1))  # (vh, vw, C, win, win)
    wins = wins.reshape(n, nch, window, window)  # a view: rows in raster order
    weights = np.sqrt(_gaussian(window)).astype(np.float32)

    def vectors(rows):
        return (wins[rows] * weights).reshape(len(rows), -1).astype(np.float32)

    # principal axes from (at most 20000 evenly spaced) windows, then the
    # projection in chunks, so a large exemplar never holds all its windows
    sample = vectors(np.linspace(0, n - 1, min(n, 20000)).astype(np.int64))
    mean = sample.mean(axis=0)
    sample -= mean
    cov = (sample.T @ sample).astype(np.float64) / len(sample)
    dims = min(24, cov.shape[0], n)
    axes = np.linalg.eigh(cov)[1][:, ::-1][:, :dims].astype(np.float32)
    feats = np.empty((n, dims), dtype=np.float64)
    for a in range(0, n, 16384):
        rows = np.arange(a, min(a + 16384, n))
        feats[rows] = (vectors(rows) - mean) @ axes
    radius = max(1, half // 2)
    # Large exemplars: look for neighbours on a sparser grid of positions,
    # so that the all-pairs search stays below about 3e8 distance checks
    # (all pairs up to 128 x 128 exemplars with window 11).
    stride = max(1, math.ceil(math.sqrt(n * n / 3e8)))
    return _nearest(feats, min(k, n - 1), radius, vw, stride)


def efros_leung(exemplar, shape, *, window: int = 11, rng=0, method: str = "fast",
                epsilon: float = 0.1, max_error: float = 0.3, tileable: bool = False, k: int = 4,
                progress=None) -> np.ndarray:
    """Grow a texture pixel by pixel by non-parametric sampling (Efros and Leung 1999).

    A 3 x 3 patch from a random place in the exemplar seeds the output
    (at its centre). Then, round after round, the unfilled pixels next to
    filled ones are visited, those with the most filled pixels in their
    window first. For each, the Gaussian-weighted sum of squared
    differences (sigma = window / 6.4) between its filled neighbours and
    every candidate window of the exemplar is computed, normalised by the
    total weight of the filled neighbours and by the number of channels;
    one candidate is drawn at random among those within ``1 + epsilon`` of
    the best, and its centre pixel copied, if its error is at most the
    current threshold (``max_error`` at first, raised by 10% after a round
    in which no pixel could be filled).

    Two searches give the candidates:

    * ``method='exhaustive'``: every exemplar window that fits inside the
      exemplar, the exact method of the paper (numba, with an early exit
      for candidates that already exceed ``(1 + epsilon)`` times the best
      error, which changes nothing in the result);
    * ``method='fast'`` (default): the k-coherence candidate set of Tong et
      al. (2002), after Ashikhmin (2001): for every filled neighbour, the
      exemplar window that continues its source at the same offset, plus
      the ``k`` exemplar windows most similar to that one (precomputed once),
      plus two random windows. The same error and the same near-best rule
      pick among them; typically 20 to 200 candidates instead of thousands.

    Parameters
    ----------
    exemplar : ndarray, shape (h, w) or (h, w, C)
        Float in [0, 1] (integers are scaled by their dtype's maximum); grey
        or colour, any channel count (alpha is matched and copied like a
        colour). At least ``window`` pixels in each direction.
    shape : int or (int, int)
        Output ``(height, width)``.
    window : int
        Odd neighbourhood size, >= 3 (the paper's results use 5 to 21).
    rng : int, numpy.random.Generator or None
        Randomness (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, the same int the same result; a
        Generator is used (and advanced); None draws fresh randomness.
    method : {'fast', 'exhaustive'}
        Candidate search, see above.
    epsilon : float
        Relative tolerance of the near-best set (the paper: 0.1).
    max_error : float
        Initial error threshold for accepting a match (the paper: 0.3),
        in mean squared difference per channel of values in [0, 1].
    tileable : bool
        Toroidal output: windows wrap around the output's edges, so the
        result tiles seamlessly.
    k : int
        Size of the k-coherence sets (``method='fast'`` only), 0 to 32.
    progress : callable, optional
        Called as ``progress(done, total)`` with counts of pixels after
        every round.

    Returns
    -------
    ndarray of float32, shape ``shape`` or ``shape + (C,)``
        Every pixel is a copy of an exemplar pixel.

    Raises
    ------
    ValueError
        If ``window`` is even or smaller than 3, or larger than the
        exemplar.

    References
    ----------
    .. [1] A. A. Efros and T. K. Leung, "Texture synthesis by non-parametric
       sampling", ICCV 1999, pp. 1033-1038.
    .. [2] M. Ashikhmin, "Synthesizing natural textures", I3D 2001.
    .. [3] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo, H.-Y. Shum,
       "Synthesis of bidirectional texture functions on arbitrary surfaces",
       SIGGRAPH 2002 (k-coherence).
    """
    ex = check_image("exemplar", exemplar, unit=True)
    rng = check_rng(rng)
    epsilon = check_float("epsilon", epsilon, minimum=0.0)
    max_error = check_float("max_error", max_error, minimum=0.0, exclusive_minimum=True)
    tileable = bool(tileable)
    method = check_choice("method", method, _METHODS)
    eh, ew = ex.shape[:2]
    out_h, out_w, window, k = check_efros_leung(ex.shape, shape, window=window, k=k, method=method,
                                                channels=1 if ex.ndim == 2 else ex.shape[2])
    grey = ex.ndim == 2
    e3 = np.ascontiguousarray(ex[:, :, None] if grey else ex, dtype=np.float32)
    nch = e3.shape[2]
    half = window // 2
    vh, vw = eh - 2 * half, ew - 2 * half

    exhaustive = method == "exhaustive"
    knn = (np.zeros((vh * vw, 0), dtype=np.int64) if exhaustive
           else _coherence_sets(e3, window, k))
    gauss = _gaussian(window)

    out = np.zeros((out_h, out_w, nch), dtype=np.float32)
    filled = np.zeros((out_h, out_w), dtype=np.bool_)
    src = np.full((out_h, out_w, 2), -1, dtype=np.int64)
    # the 3 x 3 seed, from a random place, at the centre of the output
    sy = int(rng.integers(0, eh - 2))
    sx = int(rng.integers(0, ew - 2))
    oy, ox = (out_h - 3) // 2, (out_w - 3) // 2
    for dy in range(3):
        for dx in range(3):
            y, x = oy + dy, ox + dx
            if 0 <= y < out_h and 0 <= x < out_w:
                out[y, x] = e3[sy + dy, sx + dx]
                src[y, x] = sy + dy, sx + dx
                filled[y, x] = True

    total = out_h * out_w
    count = int(filled.sum())
    stamp = np.zeros(vh * vw, dtype=np.int64)
    stamp_base = 0
    threshold = max_error
    n_random = 0 if exhaustive else 2
    while count < total:
        ys, xs, counts = _frontier(filled, half, tileable)
        # most filled neighbours first, ties in random order
        order = np.lexsort((rng.random(ys.size), -counts))
        ys, xs = ys[order], xs[order]
        uniform = rng.random(ys.size)
        random_cands = rng.integers(0, vh * vw, size=(ys.size, n_random))
        done = _fill_round(e3, out, filled, src, ys, xs, gauss, half, tileable, knn, exhaustive,
                           uniform, random_cands, epsilon, threshold, stamp, stamp_base)
        stamp_base += ys.size
        count += done
        if done == 0:
            threshold *= 1.1
            if not math.isfinite(threshold):  # pragma: no cover - cannot happen with finite errors
                raise RuntimeError("efros_leung: error threshold overflowed")
        if progress is not None:
            progress(count, total)
    return out[:, :, 0] if grey else out
