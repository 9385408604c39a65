"""Periodic images: Moisan's periodic-plus-smooth decomposition.

An image taken as one period of a periodic function jumps at its wrap edges
(right edge to left, bottom to top). Moisan's decomposition ``image = p + s``
moves those jumps into a smooth image ``s``, which leaves ``p``, the
*periodic component*: it keeps the image's detail, its step across the wrap
edges is like any interior step, and its Fourier transform is free of the
cross of leakage that the edges put into the transform of the image.

Two uses in spectex, one home:

* spectrum estimation (:func:`spectex.spectrum.radial_power_spectrum` with
  ``window='periodic'``), a leak-free alternative to windowing;
* photographs made into seamless tiles (:func:`spectex.tiles.make_seamless`),
  which also uses the pieces underneath: :func:`wrap_step_source`, the
  Laplacian of prescribed steps across the wrap edges, and
  :func:`solve_periodic_poisson`.

References
----------
L. Moisan, "Periodic plus smooth image decomposition", Journal of
Mathematical Imaging and Vision 39(2), 161-179, 2011.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ._parallel import fft_workers
from ._validate import check_image


class PeriodicSmooth(NamedTuple):
    """The two parts of :func:`periodic_smooth_decomposition` (unpacks as ``periodic, smooth``)."""

    periodic: np.ndarray  #: periodic-looking part, the image's mean kept
    smooth: np.ndarray    #: smooth part, zero mean

__all__ = ["PeriodicSmooth", "periodic_smooth_decomposition", "solve_periodic_poisson", "wrap_step_source"]


def periodic_smooth_decomposition(image):
    """Moisan's periodic-plus-smooth decomposition ``image = p + s``.

    ``s`` is the smooth image (a discrete harmonic function inside) whose
    Laplacian equals that of the image's jumps across the wrap edges; ``p``
    is periodic-looking: its step across the wrap edge is like any interior
    step, and its Fourier transform is free of the cross of leakage that the
    edges put into the transform of ``image``. ``s`` has zero mean, so ``p``
    keeps the image's mean.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C)

    Returns
    -------
    periodic, smooth : ndarray, float32, each the shape of ``image``

    References
    ----------
    L. Moisan, "Periodic plus smooth image decomposition", Journal of
    Mathematical Imaging and Vision 39(2), 161-179, 2011.
    """
    image = check_image("image", image, min_size=2)
    u = (image[:, :, None] if image.ndim == 2 else image).astype(np.float64)
    s = solve_periodic_poisson(wrap_step_source(u.shape, u[0] - u[-1], u[:, 0] - u[:, -1]))
    p = u - s
    if image.ndim == 2:
        p, s = p[:, :, 0], s[:, :, 0]
    return PeriodicSmooth(p.astype(np.float32), s.astype(np.float32))


def wrap_step_source(shape, row_step, col_step) -> np.ndarray:
    """The boundary source of prescribed steps across the wrap edges.

    The zero-mean periodic solution ``s`` of ``Laplacian s = source``
    (:func:`solve_periodic_poisson`) has (about) the steps ``row_step`` from
    the last row to the first and ``col_step`` from the last column to the
    first, and is smooth elsewhere. With an image's own jumps
    (``u[0] - u[-1]``, ``u[:, 0] - u[:, -1]``) it is Moisan's smooth
    component.

    Parameters
    ----------
    shape : (int, int, int)
        ``(H, W, C)`` of the image.
    row_step : array_like, shape (W, C)
        Step from the last row to the first.
    col_step : array_like, shape (H, C)
        Step from the last column to the first.

    Returns
    -------
    ndarray, float64, shape (H, W, C)
        Non-zero on the four border lines only.
    """
    h, w, c = (int(n) for n in shape)
    row_step = np.asarray(row_step, dtype=np.float64)
    col_step = np.asarray(col_step, dtype=np.float64)
    if row_step.shape != (w, c) or col_step.shape != (h, c):
        raise ValueError(f"row_step must have shape {(w, c)} and col_step {(h, c)} for shape {(h, w, c)}, "
                         f"got {row_step.shape} and {col_step.shape}")
    v = np.zeros((h, w, c), dtype=np.float64)
    v[0] -= row_step
    v[-1] += row_step
    v[:, 0] -= col_step
    v[:, -1] += col_step
    return v


def solve_periodic_poisson(laplacian) -> np.ndarray:
    """The zero-mean periodic image whose 5-point Laplacian is ``laplacian``.

    Solved exactly by FFT: the 5-point Laplacian of a periodic image is
    diagonal in Fourier space, with eigenvalue ``2 cos(2 pi kx / W) + 2
    cos(2 pi ky / H) - 4`` at frequency ``(ky, kx)``. The mean of
    ``laplacian`` (the one component a periodic Laplacian cannot have) is
    ignored.

    Parameters
    ----------
    laplacian : ndarray, shape (H, W, C)

    Returns
    -------
    ndarray, float64, shape (H, W, C)
    """
    import scipy.fft as sfft

    v = np.asarray(laplacian, dtype=np.float64)
    if v.ndim != 3:
        raise ValueError(f"laplacian must have shape (H, W, C), got shape {v.shape}")
    h, w = v.shape[:2]
    vh = sfft.rfft2(v, axes=(0, 1), workers=fft_workers(v.size))
    cy = np.cos(2.0 * np.pi * np.arange(h) / h)[:, None]
    cx = np.cos(2.0 * np.pi * np.arange(w // 2 + 1) / w)[None, :]
    den = 2.0 * cx + 2.0 * cy - 4.0
    den[0, 0] = 1.0
    vh /= den[:, :, None]
    vh[0, 0] = 0.0
    return sfft.irfft2(vh, s=(h, w), axes=(0, 1), workers=fft_workers(v.size))
