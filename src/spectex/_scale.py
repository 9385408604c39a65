"""A photo taken at an angle: the drift of its texture's scale, and the blotches it leaves (issue 22).

The private home of :func:`spectex.metrics.scale_blotches` and of the
estimate the fit levels an oblique photo of unstructured ground with
(``spectex.fitting._perspective.level``; structured photos are rectified
from their lines instead).

A photo of ground taken standing, the camera pitched down, sees the far
side of the ground smaller: its stones, blades and grains shrink towards
the top of the photo. A texture made of pieces of such a photo draws large
stones beside small ones, patch by patch (scale blotches, seamed along the
patches' borders), which no band-power, histogram or structure measure of
the whole sees.

The texture's local scale is read as its local frequency: per block, the
RMS frequency of the luma (lightly smoothed, so that pixel noise is not
read as detail), ``sqrt(mean |grad|^2 / variance)``. On a plane seen in
perspective its logarithm changes across the photo by the log of the local
magnification, which a plane's homography makes linear to first order
(``-1.5 log(1 + a x + b y)``: the geometric mean of the two axes'
foreshortening). A plane in the photo's coordinates is least-squares fitted
to the blocks' log frequencies; its drift is a tilt where it is several
times what the blocks' scatter gives a plane by chance and the grain shrinks
faster along the drift than across it (a plane seen at an angle is
foreshortened along the tilt: content that changes scale does so alike in
every direction).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._results import AsDict
from ._validate import check_float, check_image
from .color import luma

#: Blocks along each side of the photo whose local frequency is read.
SCALE_BLOCKS = 8
#: Smallest photo side the scale drift is read on (blocks of at least 16 pixels).
MIN_SCALE_SIDE = 16 * SCALE_BLOCKS
#: Least ratio of the local frequency at one side of the photo to the other's (along the drift, corner
#: to corner of the fitted plane) taken for a tilt: under it the mixed scales do not show.
MIN_SPREAD = 1.2
#: ... and this many times the drift a plane fitted to the blocks' scatter gives by chance (evenly seen
#: gravel, grass, moon, tissue, deep field, paving and floor tiles: 0.1-1.7; gravel, grass and paving seen
#: at an angle, 5.1-22 where the spread is over 1.2; photos whose content, not the view, changes scale
#: across them: 3.1-4.4, scikit-image's cell, retina, coins, a crop of chelsea's fur and of coffee's wood) ...
SCALE_SIGNIFICANCE = 5.0
#: ... and the grain shrinking at least this many times as fast along the drift as across it: a plane
#: seen at an angle is foreshortened along the tilt twice as fast as across it (measured 1.4-2.6 on the
#: photos seen at an angle, the far side's blur pulling it down; content changing scale 0.1-1.2, coins 3.7).
MIN_FORESHORTENING = 1.25
#: Visible scale blotches: the RMS of a view's blocks' log local frequency over the photo's own (its tilt
#: taken out) by more than this (calibrated in ``docs/fitting.md``, "Measuring a fit").
SCALE_EXCESS = 0.025
#: The view is measured over at most this many pixels a side (its top-left corner): bounded work.
_MAX_VIEW = 4096


def _gradients(image: np.ndarray):
    """``(y, gx, gy)``: the luma smoothed by a Gaussian of one pixel (pixel noise is not detail), float64,
    and its gradients along x and y."""
    from scipy import ndimage

    y = ndimage.gaussian_filter(luma(image, dtype=np.float64), 1.0, mode="reflect")
    gy, gx = np.gradient(y)
    return y, gx, gy


def _block_means(a: np.ndarray, block: int) -> np.ndarray:
    """Means of ``a`` over its whole ``block`` x ``block`` blocks."""
    ny, nx = a.shape[0] // block, a.shape[1] // block
    return a[:ny * block, :nx * block].reshape(ny, block, nx, block).mean(axis=(1, 3))


def _log_frequency(image: np.ndarray, block: int, gradients=None) -> np.ndarray:
    """Per ``block`` x ``block`` block (whole blocks only), the log of the luma's RMS frequency
    (radians per pixel): ``log sqrt(mean |grad|^2 / variance)`` on :func:`_gradients` (``gradients``,
    where already made). Blocks without variance get the mean of the others."""
    y, gx, gy = _gradients(image) if gradients is None else gradients
    energy = _block_means(gx * gx + gy * gy, block)
    var = _block_means(y * y, block) - _block_means(y, block) ** 2
    ok = var > 1e-10
    out = np.zeros(var.shape)
    out[ok] = 0.5 * np.log(np.maximum(energy[ok], 1e-20) / var[ok])
    if not ok.all():
        out[~ok] = out[ok].mean() if ok.any() else 0.0
    return out


def _plane(f, block, shape):
    """Least-squares plane of the blocks' values ``f`` in the photo's coordinates (-1 to 1 over it):
    ``(coefficients (c, along x, along y), design matrix)``."""
    h, w = shape
    ny, nx = f.shape
    v, u = np.meshgrid((np.arange(ny) + 0.5) * block / h * 2.0 - 1.0, (np.arange(nx) + 0.5) * block / w * 2.0 - 1.0,
                       indexing="ij")
    a = np.stack([np.ones(u.size), u.ravel(), v.ravel()], axis=1)
    return np.linalg.lstsq(a, f.ravel(), rcond=None)[0], a


def scale_drift(photo: np.ndarray):
    """``(slope, spread, significance, foreshortening)``: the photo's scale drift (see the module's docstring).

    ``slope`` is ``(along x, along y)``: the change of the log local
    frequency from the photo's centre to its right and bottom edges (a
    photo whose top shows the ground smaller has a negative y slope);
    ``spread`` the ratio of the local frequency at the two ends of the
    plane's steepest line across the photo (``exp(2 |slope|)``, 1 for
    none); ``significance`` the drift's RMS over the RMS a plane fitted to
    the blocks' scatter has by chance; ``foreshortening`` how many times as
    fast the frequency of the luma's gradients along the drift changes as
    that of those across it (about 2 for a plane seen at an angle, about 1
    for content that changes scale alike in every direction).

    Parameters
    ----------
    photo : ndarray, shape (h, w) or (h, w, C)
        At least :data:`MIN_SCALE_SIDE` pixels a side.
    """
    photo = check_image("photo", photo, min_size=MIN_SCALE_SIDE)
    block = min(photo.shape[:2]) // SCALE_BLOCKS
    gradients = _gradients(photo)
    f = _log_frequency(photo, block, gradients)
    coef, a = _plane(f, block, photo.shape[:2])
    residual = float(np.sqrt(np.mean((f.ravel() - a @ coef) ** 2)))
    chance = residual * float(np.sqrt(2.0 / a.shape[0]))
    rms = float(np.std(a[:, 1:] @ coef[1:]))
    slope = (float(coef[1]), float(coef[2]))
    norm = float(np.hypot(*slope))
    foreshortening = 1.0
    if norm > 1e-9:
        # the gradients' energy along the drift and across it, per block, each its own plane
        gdir = np.array(slope) / norm
        y, gx, gy = gradients
        var = np.maximum(_block_means(y * y, block) - _block_means(y, block) ** 2, 1e-20)
        rates = []
        for g in (gx * gdir[0] + gy * gdir[1], gy * gdir[0] - gx * gdir[1]):
            c, _ = _plane(0.5 * np.log(np.maximum(_block_means(g * g, block), 1e-20) / var), block, photo.shape[:2])
            rates.append(float(c[1] * gdir[0] + c[2] * gdir[1]))
        # (across the drift changing the other way than along it, the ratio is negative: no plane seen at an
        # angle does that)
        foreshortening = rates[0] / rates[1] if abs(rates[1]) > 1e-9 else float("inf")
    return slope, float(np.exp(2.0 * norm)), rms / max(chance, 1e-12), foreshortening


def is_oblique(spread: float, significance: float, foreshortening: float) -> bool:
    """Whether a scale drift (:func:`scale_drift`) is a tilt, not chance or content: a ``spread`` of at
    least :data:`MIN_SPREAD`, :data:`SCALE_SIGNIFICANCE` times chance, and foreshortened along the drift
    (:data:`MIN_FORESHORTENING`)."""
    return spread >= MIN_SPREAD and significance >= SCALE_SIGNIFICANCE and foreshortening >= MIN_FORESHORTENING


@dataclass(frozen=True, eq=False)
class ScaleBlotches(AsDict):
    """A photo's scale drift, and the scale blotches of a view of a texture (:func:`scale_blotches`).

    Attributes
    ----------
    spread : float
        The photo's scale drift (:func:`scale_drift`): the ratio of its
        local frequency at its two ends along the drift (1 for none).
    oblique : bool
        Whether that drift is a tilt, not chance (:func:`is_oblique`).
    photo_scatter : float
        RMS of the photo's blocks' log local frequency about their plane
        where ``oblique``, about their mean otherwise: how much its texture's
        scale varies by itself.
    view_scatter : float
        The same of the view's blocks (the photo's block size at the view's
        scale), about their mean.
    excess : float
        ``sqrt(view_scatter**2 - photo_scatter**2)``, 0 where the view
        varies less.
    threshold : float
        Excess from which blotches of large and small grain show.
    within : bool
        ``excess <= threshold``.
    """

    spread: float
    oblique: bool
    photo_scatter: float
    view_scatter: float
    excess: float
    threshold: float
    within: bool


def scale_blotches(view, reference, *, zoom: float = 1.0, threshold: float = SCALE_EXCESS) -> ScaleBlotches:
    """Patches of large and small grain in a view of a texture, against the photo's own variation of scale.

    A texture made of pieces of a photo taken at an angle draws the near
    side's large stones beside the far side's small ones (see
    :func:`scale_drift`). This measure reads the local frequency of the
    view in blocks of the photo's block size (1/8 of its shorter side, at
    the view's scale) and compares their scatter with the photo's blocks'
    about the photo's own tilt: a faithful texture of ground seen square-on
    varies in scale no more than the photo does once its tilt is taken out.

    Parameters
    ----------
    view : ndarray, shape (H, W) or (H, W, C)
        The texture rendered at ``zoom`` times the photo's pixel size over
        several photo areas (e.g. ``bake(texture, (1448, 1448),
        pixel_size=p)``); its top-left 4096 x 4096 pixels at most.
    reference : ndarray, shape (h, w) or (h, w, C)
        The photo, at least 128 pixels a side.
    zoom : float
        The view's pixel size over the photo's (1 to the photo's block side
        over 8: blocks of at least 8 view pixels).
    threshold : float
        Visible excess (RMS of natural log frequency, > 0).

    Returns
    -------
    ScaleBlotches
    """
    reference = check_image("reference", reference, min_size=MIN_SCALE_SIDE)
    block = min(reference.shape[:2]) // SCALE_BLOCKS
    zoom = check_float("zoom", zoom, minimum=1.0, maximum=max(1.0, block / 8.0))
    threshold = check_float("threshold", threshold, minimum=0.0, exclusive_minimum=True)
    view_block = max(8, int(round(block / zoom)))
    view = check_image("view", view, min_size=2 * view_block)
    slope, spread, significance, foreshortening = scale_drift(reference)
    oblique = is_oblique(spread, significance, foreshortening)
    f = _log_frequency(reference, block)
    if oblique:
        coef, a = _plane(f, block, reference.shape[:2])
        f = f.ravel() - a[:, 1:] @ coef[1:]
    own = float(np.std(f))
    seen = float(np.std(_log_frequency(view[:_MAX_VIEW, :_MAX_VIEW], view_block)))
    excess = float(np.sqrt(max(seen * seen - own * own, 0.0)))
    return ScaleBlotches(spread=spread, oblique=oblique, photo_scatter=own, view_scatter=seen, excess=excess,
                         threshold=threshold, within=excess <= threshold)
