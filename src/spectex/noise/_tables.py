"""Lattice tables: Ken Perlin's permutation, gradient sets, seeded tables.

One written-down specification for every port of the noise (CPU kernels here,
GLSL later): a permutation ``P`` of 0..255, doubled to 512 entries, hashes a
lattice point ``(X, Y, Z)`` (each in 0..255) as ``P[P[P[X] + Y] + Z]``; the low
four bits of the hash pick a gradient from the tables below.
"""

from __future__ import annotations

import functools

import numpy as np

# Ken Perlin's permutation from the Improved Noise reference (2002).
PERLIN_PERMUTATION = np.array([
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30,
    69, 142, 8, 99, 37, 240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94,
    252, 219, 203, 117, 35, 11, 32, 57, 177, 33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171,
    168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146, 158, 231, 83, 111, 229, 122, 60,
    211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25, 63, 161, 1, 216,
    80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100,
    109, 198, 173, 186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82,
    85, 212, 207, 206, 59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248,
    152, 2, 44, 154, 163, 70, 221, 153, 101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108,
    110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246, 97, 228, 251, 34, 242, 193, 238, 210,
    144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49, 192, 214, 31, 181, 199,
    106, 157, 184, 84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93, 222, 114,
    67, 29, 24, 72, 243, 141, 128, 195, 78, 66, 215, 61, 156, 180,
], dtype=np.int64)
PERLIN_PERMUTATION.setflags(write=False)


def _grad3_table() -> np.ndarray:
    """The 16 gradients of Perlin's ``grad(hash, x, y, z)`` (2003 fix), as rows.

    Derived from the reference branch code: ``u = x if h < 8 else y``;
    ``v = y if h < 4 else (x if h in (12, 14) else z)``; the result is
    ``(+-u) + (+-v)`` with signs from bits 0 and 1. The twelve cube-edge
    directions, with (1,1,0), (0,-1,1), (-1,1,0), (0,-1,-1) repeated (as
    hashes 12..15).
    """
    table = np.zeros((16, 3))
    for h in range(16):
        u = 0 if h < 8 else 1
        v = 1 if h < 4 else (0 if h in (12, 14) else 2)
        table[h, u] += -1.0 if h & 1 else 1.0
        table[h, v] += -1.0 if h & 2 else 1.0
    return table


GRAD3 = _grad3_table()
GRAD3.setflags(write=False)

# 2-D: sixteen unit vectors evenly spaced on the circle, none on an axis or a
# diagonal (more isotropic than the z = 0 slice of the 3-D set, whose
# gradients there are axis-aligned or zero). Hash bits 0-1 pick one of four
# angles 11.25, 33.75, 56.25, 78.75 degrees; bit 2 flips x, bit 3 flips y.
GRAD2_ANGLES = (np.arange(4) + 0.5) * (np.pi / 8.0)
GRAD2 = np.array([[(-1.0 if h & 4 else 1.0) * np.cos(GRAD2_ANGLES[h & 3]),
                   (-1.0 if h & 8 else 1.0) * np.sin(GRAD2_ANGLES[h & 3])] for h in range(16)])
GRAD2.setflags(write=False)

# 1-D: slopes +-1/8 .. +-8/8 (Perlin's original 1-D noise used random slopes in [-1, 1]).
GRAD1 = np.concatenate([np.arange(1, 9), -np.arange(1, 9)]) / 8.0
GRAD1.setflags(write=False)

# Factors that scale each dimension's gradient noise to [-1, 1]. The maximum
# of gradient noise with unit gradients is sqrt(n)/2 (at a cell centre); the
# 1-D set reaches 1/2; 3-D is Perlin's reference, left unscaled (its extreme
# values are about +-1.04; see the docstring of ``perlin``).
SCALE1 = 2.0
SCALE2 = float(np.sqrt(2.0))


def permutation(seed, octave: int = 0) -> np.ndarray:
    """The doubled (512-entry) permutation table for ``seed`` and ``octave``.

    ``seed=None`` gives Ken Perlin's permutation (for every octave); an integer
    seed gives a permutation drawn with ``np.random.default_rng([seed, octave])``.
    """
    if seed is None:
        base = PERLIN_PERMUTATION
    else:
        base = np.random.default_rng([int(seed), int(octave)]).permutation(256).astype(np.int64)
    return np.concatenate([base, base])


def lattice_values(seed, octave: int = 0) -> np.ndarray:
    """The 256 lattice values of value noise, uniform in [-1, 1], for ``seed``."""
    s = 0 if seed is None else int(seed)
    rng = np.random.default_rng([s, int(octave), 0x5EED])
    return rng.uniform(-1.0, 1.0, 256)


def pair_table(perm: np.ndarray) -> np.ndarray:
    """The pair table of a doubled (512-entry) permutation, as int32.

    ``W[i] = P[i] | P[i + 1] << 16`` (``P[512]`` wrapping to ``P[0]``): one
    look-up gives the hashes of two neighbouring lattice points, exactly the
    reference's ``P[A]`` and ``P[A + 1]``. The float32 kernels hash with it.
    """
    perm = np.asarray(perm, dtype=np.int64)
    return (perm | (np.roll(perm, -1) << 16)).astype(np.int32)


@functools.lru_cache(maxsize=256)
def octave_tables(seed, octave: int):
    """The kernels' tables for ``seed`` and ``octave``, read-only and cached:
    ``(P, W, P8, V)`` = the doubled permutation (int32), its pair table
    (int32), the permutation as 256 bytes, and the lattice values (float64).
    """
    perm = permutation(seed, octave)
    out = (perm.astype(np.int32), pair_table(perm), perm[:256].astype(np.uint8),
           lattice_values(seed, octave))
    for a in out:
        a.setflags(write=False)
    return out
