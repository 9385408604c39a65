"""Public noise functions: argument checks, dtype rules, broadcasting."""

from __future__ import annotations

import numbers

import numpy as np

from .._validate import check_choice, check_float, check_int, check_seed
from . import _tables

_INTERPOLATIONS = {"linear": 0, "cubic": 1, "quintic": 2}
_BASES = {"perlin": 0, "value": 1}
_MAX_PERIOD = 2**24


def _coords(x, y, z):
    """Validate and broadcast coordinates; return (dtype, shape, flat arrays)."""
    given = [("x", x)] + [(n, c) for n, c in (("y", y), ("z", z)) if c is not None]
    if y is None and z is not None:
        raise ValueError("z was given without y: pass x, y and z for 3-D noise")
    if (y is None and isinstance(x, tuple) and len(x) in (2, 3)
            and all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) for v in x)):
        # fbm((64, 64)) would be 1-D noise at x = 64 and x = 64: two equal numbers, not an image
        raise TypeError(f"x must be coordinates (a number or an array), got the tuple {x!r}, which looks like a "
                        "shape; the noise functions take coordinates, not a shape: for an image, pass a grid, "
                        "e.g. y, x = numpy.mgrid[0:64, 0:64] / 16.0, then fbm(x, y)")
    arrays = []
    for name, c in given:
        if c is None:
            raise TypeError(f"{name} must be an array or a number, got None")
        a = c if isinstance(c, np.ndarray) else np.asarray(c)
        if a.dtype == object or not (np.issubdtype(a.dtype, np.floating)
                                     or np.issubdtype(a.dtype, np.integer)
                                     or a.dtype == np.bool_):
            raise TypeError(f"{name} must hold real numbers, got dtype {a.dtype}")
        arrays.append(a)
    # float32 stays float32, float64 stays float64, anything else -> float64.
    # Python numbers are weak (as in NumPy 2): they take the arrays' dtype.
    typed = [a for (_, c), a in zip(given, arrays) if not isinstance(c, (int, float))]
    dtype = np.float32 if typed and all(a.dtype == np.float32 for a in typed) else np.float64
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays))
    except ValueError:
        shapes = ", ".join(f"{n}={a.shape}" for (n, _), a in zip(given, arrays))
        raise ValueError(f"coordinates do not broadcast together: {shapes}") from None
    flat = []
    for a in arrays:
        a = a.astype(dtype, copy=False)
        if a.shape != shape:
            a = np.broadcast_to(a, shape).copy()
        # Writable, C-contiguous 1-D arrays: one kernel signature for all inputs.
        flat.append(np.require(a, requirements=("C", "W")).reshape(-1))
    return dtype, shape, flat


def _periods(period, dims):
    """Return (periodic, int64 array of length dims)."""
    if period is None:
        return False, np.full(dims, 256, dtype=np.int64)
    if isinstance(period, numbers.Integral) and not isinstance(period, bool):
        period = (period,) * dims
    if not isinstance(period, (tuple, list, np.ndarray)) or len(period) != dims:
        raise ValueError(f"period must be an int or a tuple of {dims} ints for {dims}-D noise, got {period!r}")
    values = [check_int(f"period[{i}]", p, minimum=1, maximum=_MAX_PERIOD) for i, p in enumerate(period)]
    return True, np.array(values, dtype=np.int64)


def _constants(dtype):
    cosines = np.cos(_tables.GRAD2_ANGLES)
    return tuple(dtype(c) for c in (0.0, 1.0, 2.0, 3.0, 6.0, 10.0, 15.0,
                                    _tables.SCALE1, _tables.SCALE2, 1.0, *cosines))


def _finish(out, shape):
    out = out.reshape(shape)
    return out[()] if out.ndim == 0 else out


def perlin(x, y=None, z=None, *, seed=None, period=None):
    """Gradient (Perlin) noise in 1, 2 or 3 dimensions.

    Parameters
    ----------
    x, y, z : array_like
        Coordinates in lattice units (one unit = one cell); they broadcast
        together. Give ``x`` for 1-D, ``x, y`` for 2-D, ``x, y, z`` for 3-D.
        float32 inputs give float32, float64 give float64, anything else
        (integers, float16, Python numbers) float64.
    seed : int or None
        ``None`` uses Ken Perlin's permutation: then 3-D noise equals his
        Improved Noise reference (Perlin 2002, with the 2003 gradient fix)
        to rounding, at any coordinates. An integer gives another permutation,
        deterministically.
    period : int or tuple of int, optional
        Make the noise exactly periodic: ``noise(p) == noise(p + period)``
        along each axis (lattice units, 1 to 2**24).

    Returns
    -------
    ndarray or scalar
        The broadcast shape of the inputs. Values: 1-D and 2-D are scaled
        to lie in [-1, 1]; 3-D is Perlin's reference, unscaled, whose
        extremes are about +-1.04 (it stays within +-1.1). NaN coordinates
        give NaN.

    Notes
    -----
    The lattice hash is Perlin's ``P[P[P[X] + Y] + Z]`` with the 256-entry
    permutation doubled, and the quintic fade ``6t^5 - 15t^4 + 10t^3``.
    Gradients: 3-D uses the reference's twelve cube-edge vectors (sixteen
    hash slots); 2-D uses sixteen unit vectors evenly spaced on the circle and
    rotated by half a step, a proper 2-D set that is more isotropic than the
    ``z = 0`` slice of the 3-D set (whose gradients there are axis-aligned
    or zero); 1-D uses slopes +-1/8 ... +-1. The integer lattice coordinate
    is ``floor(x)`` in the input precision and the fraction ``x - floor(x)``
    is exact, so the noise keeps its quality far from the origin (float64 at
    1e6 and beyond; float32 inputs carry only float32's resolution there).

    References
    ----------
    K. Perlin, "Improving Noise", ACM Transactions on Graphics 21(3), 2002.
    """
    return _fractal(x, y, z, basis="perlin", octaves=1, lacunarity=2.0, gain=1.0, seed=seed,
                    period=period, interpolation="quintic", normalize=False, turbulent=False)


def _fractal(x, y, z, *, basis, octaves, lacunarity, gain, seed, period, interpolation,
             normalize, turbulent):
    basis = check_choice("basis", basis, tuple(_BASES))
    interpolation = check_choice("interpolation", interpolation, tuple(_INTERPOLATIONS))
    octaves = check_int("octaves", octaves, minimum=1, maximum=32)
    lacunarity = check_float("lacunarity", lacunarity, minimum=0.0, exclusive_minimum=True)
    gain = check_float("gain", gain, minimum=0.0, exclusive_minimum=True)
    seed = check_seed("seed", seed)
    if not isinstance(normalize, (bool, np.bool_)):
        raise TypeError(f"normalize must be True or False, got {normalize!r}")
    dtype, shape, flat = _coords(x, y, z)
    dims = len(flat)
    periodic, p = _periods(period, dims)
    if periodic and lacunarity != round(lacunarity):
        raise ValueError(f"lacunarity must be a whole number when period is given, got {lacunarity}")
    with np.errstate(over="ignore", under="ignore"):  # said below in one line, not as a warning too
        freq = lacunarity ** np.arange(octaves, dtype=np.float64)
    if not np.all(np.isfinite(freq)):
        raise ValueError(f"lacunarity={lacunarity} with octaves={octaves} overflows the frequency")
    pf = np.empty((octaves, dims), dtype=np.float64)
    for o in range(octaves):
        if periodic:
            scaled = [int(pi) * int(round(lacunarity)) ** o for pi in p]
            if max(scaled) > _MAX_PERIOD:
                raise ValueError(f"period {tuple(int(v) for v in p)} times lacunarity**{o} is over "
                                 f"the limit of 2**24 lattice cells")
            pf[o] = scaled
        else:
            pf[o] = 256.0
    with np.errstate(over="ignore", under="ignore"):
        amp = gain ** np.arange(octaves, dtype=np.float64)
    if not np.all(np.isfinite(amp)) or amp[-1] == 0:
        raise ValueError(f"gain={gain} with octaves={octaves} overflows or underflows the amplitude")
    if normalize:
        amp = amp / amp.sum()
    from . import _kernels  # numba: after every check, so that a refusal imports none of it

    tables = [_tables.octave_tables(seed, o) for o in range(octaves)]
    P, W, P8, V = (np.concatenate([t[k] for t in tables]) for k in range(4))
    V = V.astype(dtype)
    K = _constants(dtype)
    out = np.empty(flat[0].size, dtype=dtype)
    if out.size:
        pf3 = np.full((octaves, 3), 256.0)
        pf3[:, :dims] = pf
        mode = _INTERPOLATIONS[interpolation] if basis == "value" else _kernels.QUINTIC
        kernel = _kernels.fractal_kernel(dims, _BASES[basis], bool(periodic), dtype == np.float32)
        xs = flat + [flat[0]] * (3 - dims)
        kernel(xs[0], xs[1], xs[2], out, P, W, P8, V, _tables.GRAD1.astype(dtype),
               freq.astype(dtype), amp.astype(dtype), pf3.astype(dtype),
               (1.0 / pf3).astype(dtype), mode, bool(turbulent), K)
    return _finish(out, shape)


def value(x, y=None, z=None, *, seed=0, interpolation="cubic", period=None):
    """Lattice value noise in 1, 2 or 3 dimensions.

    Random values in [-1, 1] at the integer lattice points, interpolated.

    Parameters
    ----------
    x, y, z : array_like
        Coordinates in lattice units; they broadcast together (see
        :func:`perlin` for the dtype rules).
    seed : int
        Picks the permutation and the lattice values (``None`` means 0).
    interpolation : {"linear", "cubic", "quintic"}
        ``"linear"``: C0; ``"cubic"``: the Hermite weight ``3t^2 - 2t^3``
        (seed 002), C1; ``"quintic"``: ``6t^5 - 15t^4 + 10t^3``, C2.
    period : int or tuple of int, optional
        Make the noise exactly periodic (lattice units).

    Returns
    -------
    ndarray or scalar
        Values in [-1, 1], equal to the lattice value at integer points.
    """
    return _fractal(x, y, z, basis="value", octaves=1, lacunarity=2.0, gain=1.0, seed=seed,
                    period=period, interpolation=interpolation, normalize=False, turbulent=False)


def fbm(x, y=None, z=None, *, basis="perlin", octaves=6, lacunarity=2.0, gain=0.5, seed=0,
        period=None, interpolation="cubic", normalize=True):
    """Fractal Brownian motion: a sum of octaves of noise.

    ``sum_o gain**o * noise_o(lacunarity**o * p)``; with the defaults this is
    seed 002's fractal sum ``sum noise(f p) / f`` over doubling frequencies.

    Parameters
    ----------
    x, y, z : array_like
        Coordinates in lattice units of the first octave.
    basis : {"perlin", "value"}
        The noise summed.
    octaves : int
        Number of octaves, 1 to 32.
    lacunarity : float
        Frequency ratio between octaves (> 0). Must be a whole number when
        ``period`` is given, so that every octave shares the period.
    gain : float
        Amplitude ratio between octaves (> 0). The power spectrum falls as
        ``f ** (2 log(gain) / log(lacunarity))`` (slope -2 for the defaults).
    seed : int or None
        Octave ``o`` uses the permutation (and lattice values) drawn from
        ``[seed, o]``, so octaves are independent; ``None`` uses Ken
        Perlin's permutation for every octave.
    period : int or tuple of int, optional
        Periodic noise (in first-octave lattice units).
    interpolation : {"linear", "cubic", "quintic"}
        For ``basis="value"`` only (Perlin noise always uses the quintic fade).
    normalize : bool
        Divide by the sum of the amplitudes, so the result stays within the
        basis's range ([-1, 1]; Perlin 3-D about +-1.04).

    Returns
    -------
    ndarray or scalar
    """
    return _fractal(x, y, z, basis=basis, octaves=octaves, lacunarity=lacunarity, gain=gain,
                    seed=seed, period=period, interpolation=interpolation, normalize=normalize,
                    turbulent=False)


def turbulence(x, y=None, z=None, *, basis="perlin", octaves=6, lacunarity=2.0, gain=0.5, seed=0,
               period=None, interpolation="cubic", normalize=True):
    """Perlin's turbulence: the fractal sum of ``|noise|`` (seed 002).

    ``sum_o gain**o * |noise_o(lacunarity**o * p)|``, creased where each
    octave crosses zero. Parameters as for :func:`fbm`; with ``normalize``
    the result lies in [0, 1].
    """
    return _fractal(x, y, z, basis=basis, octaves=octaves, lacunarity=lacunarity,
                    gain=gain, seed=seed, period=period, interpolation=interpolation,
                    normalize=normalize, turbulent=True)
