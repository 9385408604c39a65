"""Colour: ramps and colormaps, Rec. 709 luma and the sRGB transfer functions.

The one home of the colour conventions: :data:`LUMA_REC709` and :func:`luma`
(how a colour image becomes one channel, for spectra, emboss alpha and
measures), :func:`srgb_to_linear` and :func:`linear_to_srgb` (IEC 61966-2-1,
for mip-maps averaged in linear light).

Ramps: a procedural texture is a scalar field pushed through a colour
mapping (Perlin's "map intensities to colour"). A *ramp* here is a piecewise-linear list of colour stops; named
ramps tuned for natural textures are built in, and any Matplotlib colormap
name works too.
"""

from __future__ import annotations

import numpy as np

from ._validate import check_float, check_image

__all__ = ["LUMA_REC709", "RAMPS", "apply_colormap", "get_ramp", "linear_to_srgb", "luma", "ramp_names",
           "srgb_to_linear"]

#: Rec. 709 (ITU-R BT.709) luma weights of R, G and B, applied to the stored values.
LUMA_REC709 = (0.2126, 0.7152, 0.0722)

# Named ramps: (position in [0, 1], (r, g, b) in [0, 1]).
RAMPS: dict[str, tuple[tuple[float, tuple[float, float, float]], ...]] = {
    "grey": ((0.0, (0.0, 0.0, 0.0)), (1.0, (1.0, 1.0, 1.0))),
    "earth": ((0.0, (0.20, 0.16, 0.11)), (0.35, (0.42, 0.34, 0.24)), (0.6, (0.55, 0.50, 0.38)),
              (0.8, (0.40, 0.45, 0.28)), (1.0, (0.80, 0.78, 0.70))),
    "stone": ((0.0, (0.18, 0.18, 0.19)), (0.4, (0.42, 0.41, 0.40)), (0.75, (0.62, 0.60, 0.57)),
              (1.0, (0.86, 0.85, 0.82))),
    "sand": ((0.0, (0.55, 0.45, 0.30)), (0.5, (0.78, 0.68, 0.50)), (1.0, (0.95, 0.89, 0.74))),
    "moss": ((0.0, (0.08, 0.12, 0.05)), (0.45, (0.24, 0.34, 0.12)), (0.8, (0.46, 0.55, 0.25)),
             (1.0, (0.70, 0.72, 0.45))),
    "marble": ((0.0, (0.28, 0.26, 0.30)), (0.25, (0.62, 0.60, 0.62)), (0.6, (0.90, 0.89, 0.87)),
               (1.0, (0.98, 0.97, 0.95))),
    "wood": ((0.0, (0.36, 0.20, 0.09)), (0.5, (0.60, 0.38, 0.18)), (1.0, (0.80, 0.58, 0.33))),
    "clouds": ((0.0, (0.20, 0.40, 0.85)), (0.45, (0.45, 0.62, 0.92)), (0.7, (0.92, 0.93, 0.96)),
               (1.0, (1.0, 1.0, 1.0))),
    "fire": ((0.0, (0.0, 0.0, 0.0)), (0.35, (0.60, 0.05, 0.0)), (0.65, (0.95, 0.45, 0.05)),
             (0.9, (1.0, 0.85, 0.30)), (1.0, (1.0, 1.0, 0.85))),
    "lava": ((0.0, (0.05, 0.02, 0.02)), (0.5, (0.35, 0.05, 0.02)), (0.8, (0.95, 0.35, 0.05)),
             (1.0, (1.0, 0.85, 0.4))),
    "ocean": ((0.0, (0.0, 0.05, 0.20)), (0.5, (0.0, 0.30, 0.55)), (0.85, (0.25, 0.65, 0.80)),
              (1.0, (0.85, 0.95, 1.0))),
    "rust": ((0.0, (0.22, 0.09, 0.04)), (0.45, (0.55, 0.24, 0.09)), (0.8, (0.75, 0.42, 0.18)),
             (1.0, (0.85, 0.65, 0.45))),
    "blue": ((0.0, (0.0, 0.0, 1.0)), (1.0, (1.0, 1.0, 1.0))),  # blue at full, the others from the field
}


def ramp_names() -> list[str]:
    """Names of the built-in ramps."""
    return sorted(RAMPS)


def _parse_stops(name, stops):
    try:
        pos = np.array([float(p) for p, _ in stops], dtype=np.float64)
        col = np.array([[float(c) for c in rgb] for _, rgb in stops], dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a sequence of (position, (r, g, b)) stops, got {stops!r}"[:200]) from None
    if len(pos) < 2 or col.ndim != 2 or col.shape[1] not in (3, 4):
        raise ValueError(f"{name} must have at least two (position, (r, g, b)) stops, got {len(pos)}")
    if not (np.all(np.isfinite(pos)) and np.all(np.isfinite(col))):
        raise ValueError(f"{name} must hold finite numbers")
    if np.any(np.diff(pos) < 0):
        raise ValueError(f"{name} positions must be non-decreasing, got {pos.tolist()}")
    return pos, col


def get_ramp(cmap) -> tuple[np.ndarray, np.ndarray]:
    """Return ``(positions, colours)`` for a ramp name, a Matplotlib name or stops.

    Parameters
    ----------
    cmap : str or sequence of (float, (r, g, b))
        A built-in ramp (:func:`ramp_names`), any Matplotlib colormap name
        (``"viridis"``, ``"terrain"``, ...), or explicit stops.
    """
    if isinstance(cmap, str):
        if cmap in RAMPS:
            return _parse_stops("colormap", RAMPS[cmap])
        import matplotlib

        try:
            mpl = matplotlib.colormaps[cmap]
        except KeyError:
            raise ValueError(f"colormap must be one of {', '.join(ramp_names())} or a Matplotlib "
                             f"colormap name, got '{cmap}'") from None
        pos = np.linspace(0.0, 1.0, 256)
        return pos, np.asarray(mpl(pos), dtype=np.float64)[:, :3]
    return _parse_stops("colormap", cmap)


def apply_colormap(values, cmap="grey", *, vmin: float = -1.0, vmax: float = 1.0) -> np.ndarray:
    """Map a scalar field through a colour ramp.

    Parameters
    ----------
    values : array_like, any shape
        Scalar field; NaN maps to NaN.
    cmap : str or sequence of (float, (r, g, b))
        See :func:`get_ramp`.
    vmin, vmax : float
        The values mapped to the ramp's ends (clipped outside).

    Returns
    -------
    ndarray, shape ``values.shape + (3,)``, float32 in [0, 1]
    """
    vmin = check_float("vmin", vmin)
    vmax = check_float("vmax", vmax)
    if not vmax > vmin:
        raise ValueError(f"vmax must be greater than vmin, got vmin={vmin}, vmax={vmax}")
    pos, col = get_ramp(cmap)
    v = np.asarray(values, dtype=np.float32)
    t = (v - np.float32(vmin)) * np.float32(1.0 / (vmax - vmin))
    t = np.clip(t, 0.0, 1.0)
    out = np.empty(v.shape + (col.shape[1],), dtype=np.float32)
    for c in range(col.shape[1]):
        out[..., c] = np.interp(t, pos, col[:, c])
    nan = np.isnan(v)
    if nan.any():
        out[nan] = np.nan
    return out[..., :3] if col.shape[1] == 4 else out


# --------------------------------------------------------------------------
# Luma and the sRGB transfer functions
# --------------------------------------------------------------------------

def luma(image, *, dtype=np.float32) -> np.ndarray:
    """Rec. 709 luma of the stored values: ``(H, W)``, float32 by default.

    Grey images are returned as they are; grey with alpha gives its grey;
    RGB and RGBA give ``0.2126 R + 0.7152 G + 0.0722 B`` (alpha ignored). The
    weights (:data:`LUMA_REC709`) apply to the values as stored (gamma-encoded
    for sRGB pictures): luma, not relative luminance.

    Parameters
    ----------
    image : ndarray, shape (H, W) or (H, W, C), C in 1..4
        Finite values; integers are scaled by their dtype's maximum.
    dtype : float32 or float64
        The result's type and the precision of the sum. With float64, a
        float64 image is used at full precision (the measures of
        :mod:`spectex.metrics` and :mod:`spectex.analysis` work so).

    Returns
    -------
    ndarray, shape (H, W)

    References
    ----------
    ITU-R Recommendation BT.709-6, "Parameter values for the HDTV standards for
    production and international programme exchange", 2015, item 3.2.
    """
    dtype = np.dtype(dtype)
    if dtype not in (np.float32, np.float64):
        raise ValueError(f"dtype must be float32 or float64, got {dtype}")
    if dtype == np.float64 and isinstance(image, np.ndarray) and image.dtype == np.float64:
        if image.ndim not in (2, 3) or (image.ndim == 3 and image.shape[2] not in (1, 2, 3, 4)):
            raise ValueError(f"image must have shape (H, W) or (H, W, C), C in 1..4, got shape {image.shape}")
        if not np.all(np.isfinite(image)):
            raise ValueError("image must hold finite values, got NaN or infinity")
    else:
        image = check_image("image", image)
    if dtype == np.float64:
        if image.ndim == 2:
            return image.astype(np.float64)
        if image.shape[2] in (1, 2):
            return image[:, :, 0].astype(np.float64)
        return image[:, :, :3].astype(np.float64) @ np.array(LUMA_REC709, dtype=np.float64)
    if image.ndim == 2:
        return image
    if image.shape[2] in (1, 2):
        return np.ascontiguousarray(image[:, :, 0])
    r, g, b = (np.float32(k) for k in LUMA_REC709)
    return (r * image[:, :, 0] + g * image[:, :, 1] + b * image[:, :, 2]).astype(np.float32, copy=False)


def srgb_to_linear(values) -> np.ndarray:
    """sRGB transfer function, decoding (IEC 61966-2-1): float32.

    ``v / 12.92`` up to 0.04045, ``((v + 0.055) / 1.055) ** 2.4`` above.
    Values are expected in [0, 1] (below 0 the linear piece goes on; NaN stays
    NaN); any shape.
    """
    v = np.asarray(values, dtype=np.float32)
    upper = np.maximum(v, np.float32(0.04045))  # the power only where it is used: no power of a negative
    return np.where(v <= 0.04045, v / np.float32(12.92),
                    ((upper + np.float32(0.055)) / np.float32(1.055)) ** np.float32(2.4)).astype(np.float32)


def linear_to_srgb(values) -> np.ndarray:
    """sRGB transfer function, encoding (IEC 61966-2-1): float32 in [0, 1].

    Values are clipped to [0, 1] first; ``12.92 v`` up to 0.0031308,
    ``1.055 v ** (1 / 2.4) - 0.055`` above. Any shape.
    """
    v = np.clip(np.asarray(values, dtype=np.float32), 0.0, 1.0)
    return np.where(v <= 0.0031308, v * np.float32(12.92),
                    np.float32(1.055) * v ** np.float32(1.0 / 2.4) - np.float32(0.055)).astype(np.float32)
