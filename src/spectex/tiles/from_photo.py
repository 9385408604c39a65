"""Photographs made into seamless RGBA tiles: :func:`make_seamless`.

The photograph is replaced by a periodic image that keeps its interior detail
and changes only by a smooth image, the harmonic image that takes up the jumps
across the wrap edges (Moisan's periodic-plus-smooth decomposition,
:mod:`spectex.periodic`), with the seams' detail put back (``seam='matched'``).
See :func:`make_seamless` and ``docs/tiles.md``.

References
----------
L. Moisan, "Periodic plus smooth image decomposition", JMIV 39(2), 2011.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import check_choice, check_float, check_image, check_rng, check_shape
from ..color import luma
from .from_noise import ALPHAS, MAX_SIZE, _to_unit
from .ops import fit_range

__all__ = ["SEAM_BAND", "make_seamless"]

#: Pixels on each side of a wrap edge that make the seam's local reference.
SEAM_BAND = 8
_MAX_GAIN = 3.0


def _edge_ratio(q: np.ndarray, band: int) -> float:
    """Mean |step| across the wrap of (H, W) ``q``'s columns over the mean
    |step| within ``band`` columns on either side."""
    w = q.shape[1]
    idx = np.r_[w - band - 1:w, 0:band + 1]
    steps = np.abs(np.diff(q[:, idx], axis=1))
    inner = np.delete(steps, band, axis=1).mean()
    return float(steps[:, band].mean() / inner) if inner > 0 else 1.0


def _seamless(u: np.ndarray, seam: str, band: int = SEAM_BAND) -> np.ndarray:
    """Periodic version of (H, W, C) ``u``: Moisan's, or with matched seams.

    ``'moisan'``: the periodic component. ``'matched'``: the periodic image
    whose steps across the wrap edges are ``lambda`` times the natural
    step there (the mean of the two steps beside the edge) and otherwise
    as close to the image's as Moisan's, which is Moisan's periodic
    component plus ``lambda`` times the solution for that step alone
    (linear). ``lambda`` in [0, 3], per channel and edge, is set by
    bisection so that the mean step across the edge equals the mean step
    within ``band`` pixels of it (the seam looks like its neighbourhood);
    where Moisan's seam is already as rough as its neighbourhood, lambda
    is 0.
    """
    from ..periodic import solve_periodic_poisson, wrap_step_source

    u = u.astype(np.float64)
    p = u - solve_periodic_poisson(wrap_step_source(u.shape, u[0] - u[-1], u[:, 0] - u[:, -1]))
    h, w = u.shape[:2]
    if seam == "moisan" or min(h, w) < 2 * band + 2:
        return p
    zero_r, zero_c = np.zeros((w, u.shape[2])), np.zeros((h, u.shape[2]))
    d_row = 0.5 * ((u[1] - u[0]) + (u[-1] - u[-2]))
    d_col = 0.5 * ((u[:, 1] - u[:, 0]) + (u[:, -1] - u[:, -2]))
    p_row = -solve_periodic_poisson(wrap_step_source(u.shape, d_row, zero_c))
    p_col = -solve_periodic_poisson(wrap_step_source(u.shape, zero_r, d_col))
    for c in range(u.shape[2]):
        gains = [0.0, 0.0]  # rows (top/bottom edge), columns (left/right edge)
        for _sweep in range(2):
            for axis in (1, 0):
                other = gains[1 - axis] * (p_row if axis == 1 else p_col)[:, :, c]
                base = p[:, :, c] + other
                extra = (p_col if axis == 1 else p_row)[:, :, c]
                if axis == 0:
                    base, extra = base.T, extra.T

                def ratio(g, base=base, extra=extra):
                    return _edge_ratio(base + g * extra, band)

                if ratio(0.0) >= 1.0:
                    g = 0.0
                elif ratio(_MAX_GAIN) <= 1.0:
                    g = _MAX_GAIN
                else:
                    lo, hi = 0.0, _MAX_GAIN
                    for _ in range(24):
                        mid = 0.5 * (lo + hi)
                        lo, hi = (mid, hi) if ratio(mid) < 1.0 else (lo, mid)
                    g = 0.5 * (lo + hi)
                gains[axis] = g
        p[:, :, c] += gains[0] * p_row[:, :, c] + gains[1] * p_col[:, :, c]
    return p


def make_seamless(image, *, shape=None, alpha: str = "none", cutoff: float | None = None, rng=0,
                  seam: str = "matched", azimuth: float = 135.0, strength: float = 1.0,
                  alpha_value: float = 1.0) -> np.ndarray:
    """Make a photograph into a seamless RGBA tile.

    The photograph (cropped about its centre to ``shape`` if given) is
    replaced by a periodic image that keeps its interior detail and changes
    only by a smooth image, the harmonic image that takes up the jumps
    across the wrap edges: Moisan's periodic-plus-smooth decomposition
    (:func:`spectex.periodic.periodic_smooth_decomposition`).

    ``seam='moisan'`` is that periodic component. It removes the step, but
    it also removes the pixel-scale detail across the edge: the seam becomes
    a soft line, its mean step 0.4 to 0.76 of the steps beside it on
    scikit-image's pictures. ``seam='matched'`` (default) puts the detail
    back: it asks for ``lambda`` times the natural step at the edge (the
    mean of the two steps beside it) instead of no step, which by linearity
    adds ``lambda`` times one more smooth solution, and sets ``lambda`` in
    [0, 3] per channel and edge by bisection so that the mean step across
    the edge equals the mean step within 8 pixels of it (the seam looks like
    its neighbourhood; ``lambda = 0`` where Moisan's seam is already as
    rough). Measured (see ``docs/tiles.md``): edge-to-neighbourhood ratios
    of 1.00 instead of 0.41 to 0.76, and the issue's global metric (wrap
    step over all interior steps) 0.99 and 1.06 instead of 0.65 and 0.67 on
    the stationary textures grass and gravel.

    Conversions: grey is repeated into R, G and B; a photograph's own alpha
    channel (grey + alpha, RGBA) is dropped unless ``alpha='keep'``; integer
    images are scaled by their dtype's maximum (so 16-bit images keep their
    precision). Values that the decomposition pushes out of [0, 1] are
    clipped, or, when ``cutoff`` is given, compressed by :func:`fit_range`
    so that the band limit holds. ``alpha='emboss'`` embosses the
    photograph (see :func:`emboss`; one-sided differences at its edges) and
    makes that seamless the same way; ``'luminance'`` is the luma of the
    seamless colour.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C), C in 1..4
        At least 8 x 8.
    shape : None, int or (int, int)
        Tile ``(height, width)`` cropped from the centre; the photograph
        must be at least that large (it is never upsampled).
    alpha : {'none', 'emboss', 'luminance', 'noise', 'keep'}
        As in :func:`make_tile`; ``'keep'`` makes the photograph's own alpha
        channel seamless too (and needs one). ``'none'`` gives
        ``alpha_value`` (default 1, opaque).
    cutoff : float or None
        Optional low-pass, cycles per pixel (see :func:`make_tile`).
    rng : int, numpy.random.Generator or None
        For ``alpha='noise'``.
        Randomness (scikit-image's SPEC 7): an int gives
        ``numpy.random.default_rng(rng)``, the same int the same result; a
        Generator is used (and advanced); None draws fresh randomness.
    seam : {'matched', 'moisan'}
        How the wrap edges are joined (see above).
    azimuth, strength, alpha_value
        As in :func:`make_tile`.

    Returns
    -------
    ndarray, shape (h, w, 4), float32 in [0, 1]
    """
    from ..spectral import band_limit, spectral_noise

    image = check_image("image", image, channels=(None, 1, 2, 3, 4), min_size=8, unit=True)
    alpha = check_choice("alpha", alpha, ALPHAS + ("keep",))
    seam = check_choice("seam", seam, ("matched", "moisan"))
    rng = check_rng(rng)
    if cutoff is not None:
        cutoff = check_float("cutoff", cutoff, minimum=0.0, maximum=0.5, exclusive_minimum=True)
    azimuth = check_float("azimuth", azimuth)
    strength = check_float("strength", strength, minimum=0.0, maximum=1e6)
    alpha_value = check_float("alpha_value", alpha_value, minimum=0.0, maximum=1.0)
    img = image[:, :, None] if image.ndim == 2 else image
    nch = img.shape[2]
    own_alpha = img[:, :, nch - 1] if nch in (2, 4) else None
    colour = img[:, :, :3] if nch >= 3 else np.repeat(img[:, :, :1], 3, axis=2)
    if alpha == "keep" and own_alpha is None:
        raise ValueError(f"alpha='keep' needs an image with an alpha channel, got {nch} channel(s)")
    H, W = img.shape[:2]
    if shape is not None:
        th, tw = check_shape("shape", shape)
        if th > H or tw > W:
            raise ValueError(f"image of {W}x{H} is smaller than the tile of {tw}x{th} asked for "
                             f"(shape=, --size); the image is never upsampled")
        if min(th, tw) < 8:
            raise ValueError(f"shape must be at least 8x8, got {tw}x{th}")
        y0, x0 = (H - th) // 2, (W - tw) // 2
        colour = colour[y0:y0 + th, x0:x0 + tw]
        if own_alpha is not None:
            own_alpha = own_alpha[y0:y0 + th, x0:x0 + tw]
        H, W = th, tw
    if max(H, W) > MAX_SIZE:
        raise ValueError(f"image of {W}x{H} is larger than {MAX_SIZE} on a side; pass shape= "
                         f"(--size) to crop a tile from it")

    def finish(channel_stack):
        p = _seamless(channel_stack[:, :, None] if channel_stack.ndim == 2 else channel_stack, seam)
        p = (p[:, :, 0] if channel_stack.ndim == 2 else p).astype(np.float32)
        if cutoff is None:
            return np.clip(p, 0.0, 1.0)
        p = band_limit(p, high=cutoff)
        if p.ndim == 2:
            return fit_range(p)
        return np.stack([fit_range(p[:, :, c]) for c in range(p.shape[2])], axis=2)

    out = np.empty((H, W, 4), dtype=np.float32)
    out[:, :, :3] = finish(colour)
    if alpha == "keep":
        out[:, :, 3] = finish(own_alpha)
    elif alpha == "emboss":
        # Emboss the photograph itself (one-sided differences at its edges,
        # no wrap), then make the result seamless like the colour: the
        # gradient of the periodic component jumps at the wrap edge.
        lum = luma(colour)
        a = math.radians(azimuth)
        gy, gx = np.gradient(lum.astype(np.float64))
        g = -(math.cos(a) * gx - math.sin(a) * gy)  # y up: d/dy = -d/d(row)
        top = float(np.abs(g).max())
        g = 0.5 + (0.5 * strength / top) * g if top > 0 and strength > 0 else np.full(g.shape, 0.5)
        out[:, :, 3] = finish(g.astype(np.float32))
    elif alpha == "luminance":
        out[:, :, 3] = luma(out[:, :, :3])
    elif alpha == "noise":
        field = spectral_noise((H, W), beta=2.0, rng=rng, high=cutoff)
        a = _to_unit(field)
        out[:, :, 3] = a if cutoff is None else fit_range(band_limit(a, high=cutoff))
    else:
        out[:, :, 3] = alpha_value
    return out
