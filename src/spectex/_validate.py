"""Input checks shared by the public functions.

Every check raises ``ValueError`` or ``TypeError`` with a one-line message
that names the parameter and the value received, so that the command line
can print it as it is.
"""

from __future__ import annotations

import math
import numbers

import numpy as np


def _show(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def check_int(name: str, value, *, minimum=None, maximum=None) -> int:
    """Return ``value`` as an int, or raise naming ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {_show(value)}")
    value = int(value)
    if minimum is not None and value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    if maximum is not None and value > maximum:
        raise ValueError(f"{name} must be <= {maximum}, got {value}")
    return value


def check_float(name: str, value, *, minimum=None, maximum=None,
                exclusive_minimum=False, allow_inf=False) -> float:
    """Return ``value`` as a finite float, or raise naming ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a number, got {_show(value)}")
    try:
        value = float(value)
    except OverflowError:  # an int (or Fraction) beyond a double: 10**400
        raise ValueError(f"{name} must be finite (at most about 1.8e308 in size), got {_show(value)}") from None
    if math.isnan(value) or (math.isinf(value) and not allow_inf):
        raise ValueError(f"{name} must be finite, got {value}")
    if minimum is not None:
        if exclusive_minimum and value <= minimum:
            raise ValueError(f"{name} must be > {minimum}, got {value}")
        if not exclusive_minimum and value < minimum:
            raise ValueError(f"{name} must be >= {minimum}, got {value}")
    if maximum is not None and value > maximum:
        raise ValueError(f"{name} must be <= {maximum}, got {value}")
    return value


#: The world lengths the library takes (metres): a micrometre to a million kilometres. Layer sizes and
#: pixel sizes outside it are not physical, and their reciprocals leave float32 (all-black bakes).
MIN_LENGTH = 1e-6
MAX_LENGTH = 1e9


def check_length(name: str, value) -> float:
    """Return ``value``, a world length in metres within [:data:`MIN_LENGTH`, :data:`MAX_LENGTH`]."""
    value = check_float(name, value)
    if not MIN_LENGTH <= value <= MAX_LENGTH:
        raise ValueError(f"{name} must be between {MIN_LENGTH:g} and {MAX_LENGTH:g} metres, got {value:g}")
    return value


def check_choice(name: str, value, choices) -> str:
    """Return ``value`` if it is one of ``choices``, or raise naming ``name``."""
    if not isinstance(value, str) or value not in choices:
        listed = ", ".join(repr(c) for c in choices)
        raise ValueError(f"{name} must be one of {listed}, got {_show(value)}")
    return value


def check_seed(name: str, value, *, allow_none=True):
    """Return a seed: ``None`` (where allowed) or a non-negative int."""
    if value is None:
        if allow_none:
            return None
        raise TypeError(f"{name} must be an integer, got None")
    return check_int(name, value, minimum=0, maximum=2**63 - 1)


def check_rng(rng) -> np.random.Generator:
    """Return a :class:`numpy.random.Generator` from ``rng`` (scikit-image's SPEC 7).

    ``rng`` is an int (``numpy.random.default_rng(rng)``: the same int gives
    the same result), a Generator (used as it is, and advanced), or None (fresh
    randomness from the operating system).
    """
    name = "rng"
    if isinstance(rng, np.random.Generator):
        return rng
    if rng is None:
        return np.random.default_rng()
    if isinstance(rng, (bool, np.bool_)) or not isinstance(rng, numbers.Integral):
        raise TypeError(f"{name} must be an int, a numpy.random.Generator or None, got {_show(rng)}")
    return np.random.default_rng(check_int(name, rng, minimum=0, maximum=2**63 - 1))


def check_shape(name: str, value, *, maximum_pixels: int = 1 << 28) -> tuple[int, int]:
    """Return ``(height, width)`` from an int or a pair of ints."""
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        value = (value, value)
    if not isinstance(value, (tuple, list)) or len(value) != 2:
        raise ValueError(f"{name} must be an int or a (height, width) pair, got {_show(value)}")
    h = check_int(f"{name}[0]", value[0], minimum=1)
    w = check_int(f"{name}[1]", value[1], minimum=1)
    if h * w > maximum_pixels:
        raise ValueError(f"{name} of {h}x{w} is over the limit of {maximum_pixels} pixels")
    return h, w


#: How far a float image may stray outside [0, 1] (rounding) and still be taken, clipped, as an image in range.
UNIT_TOLERANCE = 1e-4


def check_image(name: str, image, *, channels=(None, 1, 2, 3, 4), min_size: int = 1,
                unit: bool = False) -> np.ndarray:
    """Return ``image`` as a float32 ``(H, W)`` or ``(H, W, C)`` array.

    Integer images are scaled to [0, 1] by their dtype's maximum (uint8 by
    255, uint16 by 65535); float images are taken as they are and must be
    finite. With ``unit=True`` (an image to be matched, synthesised from or
    made a tile of) float values must lie in [0, 1] as well (up to
    :data:`UNIT_TOLERANCE`, clipped): anything else is refused, not guessed at.
    """
    if not isinstance(image, np.ndarray):
        try:
            image = np.asarray(image)
        except Exception as exc:  # pragma: no cover - numpy's message is enough
            raise TypeError(f"{name} must be an array, got {type(image).__name__}") from exc
    if image.ndim not in (2, 3):
        raise ValueError(f"{name} must have shape (H, W) or (H, W, C), got shape {image.shape}")
    nch = None if image.ndim == 2 else image.shape[2]
    if nch not in channels:
        raise ValueError(f"{name} must have {' or '.join(str(c) for c in channels if c)} channels, "
                         f"got shape {image.shape}")
    if min(image.shape[:2]) < min_size:
        raise ValueError(f"{name} must be at least {min_size}x{min_size} pixels, got "
                         f"{image.shape[1]}x{image.shape[0]}")
    if image.dtype == np.bool_:
        image = image.astype(np.float32)
    elif np.issubdtype(image.dtype, np.integer):
        info = np.iinfo(image.dtype)
        if info.min < 0:
            raise TypeError(f"{name} must be unsigned integers or floats, got dtype {image.dtype}")
        image = image.astype(np.float32) / np.float32(info.max)
    elif np.issubdtype(image.dtype, np.floating):
        image = image.astype(np.float32, copy=False)
        if not np.all(np.isfinite(image)):
            raise ValueError(f"{name} must hold finite values, got NaN or infinity")
        if unit:
            image = check_unit_range(name, image, remedy="divide it by its maximum, or rescale it, first")
    else:
        raise TypeError(f"{name} must be a numeric array, got dtype {image.dtype}")
    return image


def check_unit_range(name: str, image: np.ndarray, *, remedy: str = "rescale it to [0, 1] first") -> np.ndarray:
    """Return the float image ``image`` if its values lie in [0, 1] (clipped within rounding), or raise."""
    lo, hi = float(image.min(initial=0.0)), float(image.max(initial=0.0))
    if lo < -UNIT_TOLERANCE or hi > 1.0 + UNIT_TOLERANCE:
        raise ValueError(f"{name} holds values from {lo:.4g} to {hi:.4g}; a float image must be in [0, 1] "
                         f"({remedy})")
    if lo < 0.0 or hi > 1.0:
        image = np.clip(image, 0.0, 1.0)
    return image


def normalize_image(image: np.ndarray) -> np.ndarray:
    """``image`` with its minimum..maximum mapped to 0..1 (a constant image becomes 0.5), float32."""
    image = np.asarray(image, dtype=np.float32)
    lo, hi = float(image.min()), float(image.max())
    if hi - lo <= 0.0:
        return np.full_like(image, 0.5)
    return ((image.astype(np.float64) - lo) / (hi - lo)).astype(np.float32)


def check_relative_name(name: str, value: str) -> str:
    """Return ``value``, a file name relative to a folder that stays inside it.

    Refuses absolute paths, drive letters, ``..`` parts and empty names: a
    file that names other files (a texture file's tiles) must not reach
    outside its own folder.
    """
    from pathlib import PurePosixPath, PureWindowsPath

    if not isinstance(value, str) or not value.strip() or "\x00" in value:
        raise ValueError(f"{name} must be a file name, got {_show(value)}")
    posix, windows = PurePosixPath(value), PureWindowsPath(value)
    if posix.is_absolute() or windows.is_absolute() or windows.drive or value.startswith(("/", "\\")):
        raise ValueError(f"{name} must be a file name relative to the texture file's folder, got the "
                         f"absolute path {_show(value)}")
    if ".." in posix.parts or ".." in windows.parts:
        raise ValueError(f"{name} must stay inside the texture file's folder, got {_show(value)} (with '..')")
    return value


def check_tile_shape(name: str, shape, *, maximum_side: int = 8192) -> None:
    """Refuse a tile with a side over ``maximum_side`` texels (its mip chain would be unbounded)."""
    h, w = int(shape[0]), int(shape[1])
    if max(h, w) > maximum_side:
        raise ValueError(f"{name} is {w}x{h} texels; a tile side must be at most {maximum_side}")


def check_snap(name: str, value) -> tuple[int, int]:
    """A stochastic layer's ``snap``: a pair ``(nx, ny)`` of whole numbers 0 to ``MAX_SNAP``."""
    from .shading.constants import MAX_SNAP

    if (not isinstance(value, (tuple, list, np.ndarray)) or len(value) != 2
            or any(isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Integral) for v in value)
            or not all(0 <= int(v) <= MAX_SNAP for v in value)):
        raise ValueError(f"{name} must be a pair (nx, ny) of whole numbers 0 to {MAX_SNAP} (0: off along "
                         f"that axis), got {_show(value)}")
    return int(value[0]), int(value[1])
