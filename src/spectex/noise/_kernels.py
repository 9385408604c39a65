"""Numba kernels for lattice noise (compiled on first use, cached on disk).

Layout for speed: the points are cut into fixed blocks of ``BLOCK``; a
parallel loop runs over blocks, the octave loop over each block, and the
innermost loop over the block's points. That innermost loop is straight-line
code (lattice wrapping and gradient choice are arithmetic selects, not
branches), so LLVM vectorises it with SIMD gathers for the permutation table.
Block boundaries do not depend on the number of threads, and every element
gets the same operations, so results are bit-identical whatever the thread
count.

float32 inputs have their own kernels: float32 arithmetic and 32-bit lattice
indices (the ``_32`` point functions below, 16 lanes per AVX-512 vector), and
for Perlin noise in 2-D and 3-D without a period, 16 points per call of an
LLVM-IR intrinsic (``_lanes``). float64 inputs keep the 64-bit functions.

Constants arrive in the tuple ``K`` typed like the output (float32 or
float64), so float32 inputs are computed in float32 throughout:
``K = (0, 1, 2, 3, 6, 10, 15, scale1, scale2, scale3, c0, c1, c2, c3)`` with
``c_k = cos((k + 0.5) * pi / 8)`` for the 2-D gradients.

The point functions are inlined by LLVM (``forceinline``), not by numba's IR
inliner (``inline="always"``, which retypes the kernel with every callee in
it): the float64 3-D fBm kernel compiles in 2.6 s instead of 6.0, value noise
in 1.3 instead of 2.5, the same values to the bit and the same speed
(``bench_noise.py``; 2026-11-27).

Fast-math is limited to flags that cannot turn a NaN into a number or change
a value beyond rounding (``nsz``, ``arcp``, ``contract``): NaN coordinates
give NaN, and Perlin's 3-D reference is matched to rounding.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
from numba import njit, prange

from . import _lanes
from ._bits import grad2 as _grad2_32
from ._bits import grad3 as _grad3_32

FASTMATH = {"nsz", "arcp", "contract"}
BLOCK = 2048

# Interpolation modes.
LINEAR, CUBIC, QUINTIC = 0, 1, 2
# Bases.
PERLIN, VALUE = 0, 1


@njit(forceinline=True)
def _u(i):
    # Unsigned indices skip numba's negative-index wraparound, which would
    # otherwise turn contiguous loads into gathers and block vectorisation.
    return np.uint64(i)


@njit(forceinline=True)
def _fade(t, mode, K):
    quintic = t * t * t * (t * (t * K[4] - K[6]) + K[5])
    cubic = t * t * (K[3] - K[2] * t)
    return quintic if mode == QUINTIC else (cubic if mode == CUBIC else t)


@njit(forceinline=True)
def _lerp(t, a, b):
    return a + t * (b - a)


@njit(forceinline=True)
def _bilerp(u, v, c00, c10, c01, c11):
    """Corner values of a lattice cell blended by the faded fractions ``u`` (x) and ``v`` (y)."""
    return _lerp(v, _lerp(u, c00, c10), _lerp(u, c01, c11))


@njit(forceinline=True)
def _trilerp(u, v, w, c000, c100, c010, c110, c001, c101, c011, c111):
    """:func:`_bilerp` of the cell's two z faces, blended by ``w`` (z)."""
    return _lerp(w, _bilerp(u, v, c000, c100, c010, c110), _bilerp(u, v, c001, c101, c011, c111))


@njit(forceinline=True)
def _cell(x, pf, ip, K, periodic):
    """Lattice cell of ``x``: ``(i0, i1, frac)``, indices reduced to 0..255.

    Not periodic: ``i0 = floor(x) & 255`` as in Perlin's reference (the cast
    is to int64, exact for every float64 coordinate below 2**63; NaN and
    larger values map to a valid index, and the fraction stays NaN or 0).
    Periodic with period ``pf`` (a float; ``ip = 1/pf``): the lattice index
    is reduced modulo ``pf`` first, ``m = fl - pf * floor(fl * ip)``,
    corrected by one period where rounding of ``fl * ip`` lands on the wrong
    side, and the far end wraps to 0 at ``pf``.
    ``periodic`` is a compile-time constant at every call site, so each kernel
    loop holds only one of the two paths.
    """
    fl = np.floor(x)
    if periodic:
        m = fl - pf * np.floor(fl * ip)
        m = m + pf if m < K[0] else m
        m = m - pf if m >= pf else m
        i0 = np.int64(m)
        i1 = i0 + 1
        i1 = 0 if m + K[1] >= pf else i1
        return i0 & 255, i1 & 255, x - fl
    i = np.int64(fl)
    return i & 255, (i + 1) & 255, x - fl


@njit(forceinline=True)
def _grad2(h, x, y, K):
    # Four angles from bits 0-1 (sin(a_k) = cos(a_{3-k})), signs from bits 2-3.
    c = (K[13] if h & 2 else K[11]) if h & 1 else (K[12] if h & 2 else K[10])
    s = (K[10] if h & 2 else K[12]) if h & 1 else (K[11] if h & 2 else K[13])
    gx = -c if h & 4 else c
    gy = -s if h & 8 else s
    return gx * x + gy * y


@njit(forceinline=True)
def _grad3(h, x, y, z):
    # Ken Perlin's grad() with the 2003 fix; (h | 2) == 14 means h is 12 or 14.
    u = x if h < 8 else y
    v = y if h < 4 else (x if (h | 2) == 14 else z)
    return (-u if h & 1 else u) + (-v if h & 2 else v)


# ---------------------------------------------------------------- point functions

@njit(forceinline=True)
def _perlin1(x, p, ip, P, b, G, K, periodic):
    X0, X1, fx = _cell(x, p, ip, K, periodic)
    g0 = G[_u(P[_u(b + X0)] & 15)] * fx
    g1 = G[_u(P[_u(b + X1)] & 15)] * (fx - K[1])
    return _lerp(_fade(fx, QUINTIC, K), g0, g1) * K[7]


@njit(forceinline=True)
def _hash2(X0, X1, Y0, Y1, P, b):
    """Hashes ``P[P[X] + Y]`` (0..255) of a 2-D cell's corners 00, 10, 01, 11."""
    a0 = P[_u(b + X0)] & 255
    a1 = P[_u(b + X1)] & 255
    return (P[_u(b + a0 + Y0)] & 255, P[_u(b + a1 + Y0)] & 255,
            P[_u(b + a0 + Y1)] & 255, P[_u(b + a1 + Y1)] & 255)


@njit(forceinline=True)
def _hash3(X0, X1, Y0, Y1, Z0, Z1, P, b):
    """Hashes ``P[P[P[X] + Y] + Z]`` (0..255) of a 3-D cell's corners
    000, 100, 010, 110, 001, 101, 011, 111."""
    b00, b10, b01, b11 = _hash2(X0, X1, Y0, Y1, P, b)
    return (P[_u(b + b00 + Z0)] & 255, P[_u(b + b10 + Z0)] & 255,
            P[_u(b + b01 + Z0)] & 255, P[_u(b + b11 + Z0)] & 255,
            P[_u(b + b00 + Z1)] & 255, P[_u(b + b10 + Z1)] & 255,
            P[_u(b + b01 + Z1)] & 255, P[_u(b + b11 + Z1)] & 255)


@njit(forceinline=True)
def _perlin2(x, y, px, ipx, py, ipy, P, b, K, periodic):
    X0, X1, fx = _cell(x, px, ipx, K, periodic)
    Y0, Y1, fy = _cell(y, py, ipy, K, periodic)
    h00, h10, h01, h11 = _hash2(X0, X1, Y0, Y1, P, b)
    gx = fx - K[1]
    gy = fy - K[1]
    n00 = _grad2(h00 & 15, fx, fy, K)
    n10 = _grad2(h10 & 15, gx, fy, K)
    n01 = _grad2(h01 & 15, fx, gy, K)
    n11 = _grad2(h11 & 15, gx, gy, K)
    u = _fade(fx, QUINTIC, K)
    v = _fade(fy, QUINTIC, K)
    return _bilerp(u, v, n00, n10, n01, n11) * K[8]


@njit(forceinline=True)
def _perlin3(x, y, z, px, ipx, py, ipy, pz, ipz, P, b, K, periodic):
    X0, X1, fx = _cell(x, px, ipx, K, periodic)
    Y0, Y1, fy = _cell(y, py, ipy, K, periodic)
    Z0, Z1, fz = _cell(z, pz, ipz, K, periodic)
    h000, h100, h010, h110, h001, h101, h011, h111 = _hash3(X0, X1, Y0, Y1, Z0, Z1, P, b)
    gx = fx - K[1]
    gy = fy - K[1]
    gz = fz - K[1]
    n000 = _grad3(h000 & 15, fx, fy, fz)
    n100 = _grad3(h100 & 15, gx, fy, fz)
    n010 = _grad3(h010 & 15, fx, gy, fz)
    n110 = _grad3(h110 & 15, gx, gy, fz)
    n001 = _grad3(h001 & 15, fx, fy, gz)
    n101 = _grad3(h101 & 15, gx, fy, gz)
    n011 = _grad3(h011 & 15, fx, gy, gz)
    n111 = _grad3(h111 & 15, gx, gy, gz)
    u = _fade(fx, QUINTIC, K)
    v = _fade(fy, QUINTIC, K)
    w = _fade(fz, QUINTIC, K)
    return _trilerp(u, v, w, n000, n100, n010, n110, n001, n101, n011, n111) * K[9]


@njit(forceinline=True)
def _value1(x, p, ip, P, b, V, vb, mode, K, periodic):
    X0, X1, fx = _cell(x, p, ip, K, periodic)
    return _lerp(_fade(fx, mode, K), V[_u(vb + (P[_u(b + X0)] & 255))], V[_u(vb + (P[_u(b + X1)] & 255))])


@njit(forceinline=True)
def _value2(x, y, px, ipx, py, ipy, P, b, V, vb, mode, K, periodic):
    X0, X1, fx = _cell(x, px, ipx, K, periodic)
    Y0, Y1, fy = _cell(y, py, ipy, K, periodic)
    h00, h10, h01, h11 = _hash2(X0, X1, Y0, Y1, P, b)
    u = _fade(fx, mode, K)
    v = _fade(fy, mode, K)
    return _bilerp(u, v, V[_u(vb + h00)], V[_u(vb + h10)], V[_u(vb + h01)], V[_u(vb + h11)])


@njit(forceinline=True)
def _value3(x, y, z, px, ipx, py, ipy, pz, ipz, P, b, V, vb, mode, K, periodic):
    X0, X1, fx = _cell(x, px, ipx, K, periodic)
    Y0, Y1, fy = _cell(y, py, ipy, K, periodic)
    Z0, Z1, fz = _cell(z, pz, ipz, K, periodic)
    h000, h100, h010, h110, h001, h101, h011, h111 = _hash3(X0, X1, Y0, Y1, Z0, Z1, P, b)
    u = _fade(fx, mode, K)
    v = _fade(fy, mode, K)
    w = _fade(fz, mode, K)
    return _trilerp(u, v, w, V[_u(vb + h000)], V[_u(vb + h100)], V[_u(vb + h010)], V[_u(vb + h110)],
                    V[_u(vb + h001)], V[_u(vb + h101)], V[_u(vb + h011)], V[_u(vb + h111)])


# ---------------------------------------------------------------- float32 point functions
# float32 inputs: the same lattice hash, gradients and interpolation as the
# float64 functions above, in float32 arithmetic with 32-bit integer lattice
# indices, so that a 512-bit vector holds 16 lanes and every table look-up is
# a gather with 32-bit indices (vpgatherdd on AVX-512).
#
# The hash reads a pair table W (int32, 512 entries per octave) with
# W[i] = P[i] | P[i + 1] << 16: one look-up gives the hashes of two
# neighbouring corners, exactly the reference's P[A] and P[A + 1]. Without a
# period, a 3-D cell takes 7 look-ups instead of 14 (2-D: 3 instead of 6). An
# index is written ``(w + Y) & 511`` with ``w`` the whole pair: the high half
# is unknown to LLVM, so the mask stays and the index remains one 32-bit
# vector. ``(P[X] + Y) & 511`` with P[X] known to be below 256 made LLVM drop
# the mask and split the address into two vector additions of 64-bit
# pointers, which cannot be a 32-bit-index gather.

_U = np.uint32


@njit(forceinline=True)
def _pair(W, b, i):
    """``W[b + (i & 511)]``: P[i] in the low half, P[i + 1] in the high half."""
    return _U(W[b + (i & np.uint64(511))])


@njit(forceinline=True)
def _hi(w):
    return _U(w >> np.uint64(16))


@njit(forceinline=True)
def _cell32(x, pf, ip, periodic):
    """Lattice cell of float32 ``x``: ``(X0, X1, frac)``, indices 0..255 as uint64.

    Not periodic: ``X0 = floor(x) & 255`` through an int32, which is exact
    below 2**31; from 2**31 on every float32 is a multiple of 256, index 0,
    and that is what those coordinates get (NaN and infinities too, with a
    NaN fraction), so no coordinate meets an out-of-range conversion. ``X1``
    is not needed (the pair table holds it). Periodic: as :func:`_cell`.
    """
    fl = np.floor(x)
    zero = np.float32(0.0)
    if periodic:
        m = fl - pf * np.floor(fl * ip)
        m = m + pf if m < zero else m
        m = m - pf if m >= pf else m
        m = m if m >= zero else zero
        i0 = np.uint64(np.int32(m)) & np.uint64(255)
        i1 = np.uint64(0) if m + np.float32(1.0) >= pf else (i0 + np.uint64(1)) & np.uint64(255)
        return i0, i1, x - fl
    m = fl if abs(fl) < np.float32(2147483648.0) else zero
    i0 = np.uint64(np.int32(m)) & np.uint64(255)
    return i0, i0, x - fl


@njit(forceinline=True)
def _hash2_32(X0, X1, Y0, Y1, W, b, periodic):
    """Hashes of a 2-D cell's corners 00, 10, 01, 11 (low 8 bits; higher bits
    may hold another corner's hash)."""
    if periodic:
        a0 = _pair(W, b, X0)
        a1 = _pair(W, b, X1)
        return (_pair(W, b, a0 + Y0), _pair(W, b, a1 + Y0),
                _pair(W, b, a0 + Y1), _pair(W, b, a1 + Y1))
    w = _pair(W, b, X0)
    q0 = _pair(W, b, w + Y0)
    q1 = _pair(W, b, _hi(w) + Y0)
    return q0, q1, _hi(q0), _hi(q1)


@njit(forceinline=True)
def _hash3_32(X0, X1, Y0, Y1, Z0, Z1, W, b, periodic):
    """Hashes of a 3-D cell's corners 000, 100, 010, 110, 001, 101, 011, 111
    (low 8 bits, as :func:`_hash2_32`)."""
    q00, q10, q01, q11 = _hash2_32(X0, X1, Y0, Y1, W, b, periodic)
    if periodic:
        return (_pair(W, b, q00 + Z0), _pair(W, b, q10 + Z0),
                _pair(W, b, q01 + Z0), _pair(W, b, q11 + Z0),
                _pair(W, b, q00 + Z1), _pair(W, b, q10 + Z1),
                _pair(W, b, q01 + Z1), _pair(W, b, q11 + Z1))
    c00 = _pair(W, b, q00 + Z0)
    c10 = _pair(W, b, q10 + Z0)
    c01 = _pair(W, b, q01 + Z0)
    c11 = _pair(W, b, q11 + Z0)
    return c00, c10, c01, c11, _hi(c00), _hi(c10), _hi(c01), _hi(c11)


@njit(forceinline=True)
def _perlin1_32(x, p, ip, W, b, G, K, periodic):
    X0, X1, fx = _cell32(x, p, ip, periodic)
    w0 = _pair(W, b, X0)
    w1 = _pair(W, b, X1) if periodic else _hi(w0)
    g0 = G[w0 & np.uint64(15)] * fx
    g1 = G[w1 & np.uint64(15)] * (fx - K[1])
    return _lerp(_fade(fx, QUINTIC, K), g0, g1) * K[7]


@njit(forceinline=True)
def _perlin2_32(x, y, px, ipx, py, ipy, W, b, K, periodic):
    X0, X1, fx = _cell32(x, px, ipx, periodic)
    Y0, Y1, fy = _cell32(y, py, ipy, periodic)
    h00, h10, h01, h11 = _hash2_32(X0, X1, Y0, Y1, W, b, periodic)
    gx = fx - K[1]
    gy = fy - K[1]
    n00 = _grad2_32(h00, fx, fy, K[10], K[11], K[12], K[13])
    n10 = _grad2_32(h10, gx, fy, K[10], K[11], K[12], K[13])
    n01 = _grad2_32(h01, fx, gy, K[10], K[11], K[12], K[13])
    n11 = _grad2_32(h11, gx, gy, K[10], K[11], K[12], K[13])
    u = _fade(fx, QUINTIC, K)
    v = _fade(fy, QUINTIC, K)
    return _bilerp(u, v, n00, n10, n01, n11) * K[8]


@njit(forceinline=True)
def _perlin3_32(x, y, z, px, ipx, py, ipy, pz, ipz, W, b, K, periodic):
    X0, X1, fx = _cell32(x, px, ipx, periodic)
    Y0, Y1, fy = _cell32(y, py, ipy, periodic)
    Z0, Z1, fz = _cell32(z, pz, ipz, periodic)
    h000, h100, h010, h110, h001, h101, h011, h111 = _hash3_32(X0, X1, Y0, Y1, Z0, Z1, W, b,
                                                               periodic)
    gx = fx - K[1]
    gy = fy - K[1]
    gz = fz - K[1]
    n000 = _grad3_32(h000, fx, fy, fz)
    n100 = _grad3_32(h100, gx, fy, fz)
    n010 = _grad3_32(h010, fx, gy, fz)
    n110 = _grad3_32(h110, gx, gy, fz)
    n001 = _grad3_32(h001, fx, fy, gz)
    n101 = _grad3_32(h101, gx, fy, gz)
    n011 = _grad3_32(h011, fx, gy, gz)
    n111 = _grad3_32(h111, gx, gy, gz)
    u = _fade(fx, QUINTIC, K)
    v = _fade(fy, QUINTIC, K)
    w = _fade(fz, QUINTIC, K)
    return _trilerp(u, v, w, n000, n100, n010, n110, n001, n101, n011, n111) * K[9]


@njit(forceinline=True)
def _v32(V, c, h):
    return V[c + (h & np.uint64(255))]


@njit(forceinline=True)
def _value1_32(x, p, ip, W, b, V, c, mode, K, periodic):
    X0, X1, fx = _cell32(x, p, ip, periodic)
    w0 = _pair(W, b, X0)
    w1 = _pair(W, b, X1) if periodic else _hi(w0)
    return _lerp(_fade(fx, mode, K), _v32(V, c, w0), _v32(V, c, w1))


@njit(forceinline=True)
def _value2_32(x, y, px, ipx, py, ipy, W, b, V, c, mode, K, periodic):
    X0, X1, fx = _cell32(x, px, ipx, periodic)
    Y0, Y1, fy = _cell32(y, py, ipy, periodic)
    h00, h10, h01, h11 = _hash2_32(X0, X1, Y0, Y1, W, b, periodic)
    u = _fade(fx, mode, K)
    v = _fade(fy, mode, K)
    return _bilerp(u, v, _v32(V, c, h00), _v32(V, c, h10), _v32(V, c, h01), _v32(V, c, h11))


@njit(forceinline=True)
def _value3_32(x, y, z, px, ipx, py, ipy, pz, ipz, W, b, V, c, mode, K, periodic):
    X0, X1, fx = _cell32(x, px, ipx, periodic)
    Y0, Y1, fy = _cell32(y, py, ipy, periodic)
    Z0, Z1, fz = _cell32(z, pz, ipz, periodic)
    h000, h100, h010, h110, h001, h101, h011, h111 = _hash3_32(X0, X1, Y0, Y1, Z0, Z1, W, b,
                                                               periodic)
    u = _fade(fx, mode, K)
    v = _fade(fy, mode, K)
    w = _fade(fz, mode, K)
    return _trilerp(u, v, w, _v32(V, c, h000), _v32(V, c, h100), _v32(V, c, h010), _v32(V, c, h110),
                    _v32(V, c, h001), _v32(V, c, h101), _v32(V, c, h011), _v32(V, c, h111))


# ---------------------------------------------------------------- kernels
# One kernel per (dims, basis, periodic, float32), made by ``fractal_kernel``
# on first use: those choices are compile-time constants (closure
# variables), so each kernel's innermost loop is one straight-line path that
# LLVM vectorises. Numba's disk cache keys closures by the values they
# capture, so every variant is cached separately.
#
# Arguments: coordinate arrays x, y, z (1-D, same length; unused ones may be
# any array), out, P (one 512-entry int32 permutation per octave), W (its
# pair table, 512 int32 per octave, used by the float32 kernels), V (one
# 256-entry value table per octave), G1 (1-D slopes), and per octave: freq,
# amp, pf (periods as floats, shape (octaves, 3)), ip (their inverses).

_KERNELS: dict = {}


def _dependency_key() -> int:
    """A number that changes with the source of ``_lanes`` and ``_bits``.

    Numba's disk cache checks the timestamp of this file only; the kernels
    capture this key, so editing the intrinsics they inline recompiles them.
    """
    digest = hashlib.sha1()
    for name in ("_lanes.py", "_bits.py"):
        digest.update((Path(__file__).parent / name).read_bytes())
    return int.from_bytes(digest.digest()[:4], "little")


_DEPENDENCIES = _dependency_key()


def fractal_kernel(dims: int, basis: int, periodic: bool, single: bool = False,
                   permute: bool | None = None):
    """Return the (lazily compiled) kernel for one combination of choices.

    ``single`` selects the float32 kernel (32-bit lattice arithmetic, pair
    table); the float64 kernel keeps 64-bit indices. ``permute`` (default:
    whether the CPU has AVX-512F) makes float32 Perlin noise in 2-D and 3-D
    look gradients up with a register permute (see ``_lanes``); ``False``
    gives the generic vector IR, the same values.
    """
    lanes = single and basis == PERLIN and dims >= 2 and not periodic
    if permute is None:
        permute = lanes and _lanes.has_permute()
    permute = bool(permute) and lanes
    key = (dims, basis, periodic, single, permute)
    kernel = _KERNELS.get(key)
    if kernel is None:
        kernel = _make_kernel(dims, basis, periodic, single, permute)
        _KERNELS[key] = kernel
    return kernel


def _make_kernel(dims, basis, periodic, single, permute):
    # The closure captures plain constants only (numba's disk cache keys a
    # closure by the pickled values it captures; a captured dispatcher pickles
    # differently in every process, a cache miss every run). Written as
    # branches on those constants in the kernel body itself, so numba prunes
    # the dead ones before typing: each kernel compiles one noise body.
    # Each octave is written to a scratch buffer by a store-only loop (a
    # read-modify-write of ``out`` in the same loop as the table gathers does
    # not vectorise), then added to ``out`` by a second loop. ``mode`` and
    # ``turbulent`` are loop-invariant selects. float32 Perlin noise in 2-D
    # and 3-D without a period runs 16 points per call of a ``_lanes``
    # intrinsic instead of the auto-vectorised point loop.
    lanes = single and basis == PERLIN and dims >= 2 and not periodic
    dependencies = _DEPENDENCIES  # part of the cache key (see _dependency_key)

    @njit(parallel=True, cache=True, fastmath=FASTMATH)
    def kernel(x, y, z, out, P, W, P8, V, G1, freq, amp, pf, ip, mode, turbulent, K):
        n = out.size + 0 * dependencies
        n_oct = freq.size
        for blk in prange((n + BLOCK - 1) // BLOCK):
            s = blk * BLOCK
            e = min(s + BLOCK, n)
            if lanes:
                # All octaves of 16 points per call (see _lanes).
                for i in range(s, e, _lanes.STEP):
                    if dims == 3:
                        if permute:
                            _lanes.perlin3_lanes_permute(x, y, z, out, i, e, freq, amp, W, P8,
                                                         turbulent)
                        else:
                            _lanes.perlin3_lanes(x, y, z, out, i, e, freq, amp, W, P8, turbulent)
                    else:
                        if permute:
                            _lanes.perlin2_lanes_permute(x, y, z, out, i, e, freq, amp, W, P8,
                                                         turbulent)
                        else:
                            _lanes.perlin2_lanes(x, y, z, out, i, e, freq, amp, W, P8, turbulent)
            else:
                tmp = np.empty(e - s, dtype=out.dtype)
                for o in range(n_oct):
                    f = freq[o]
                    a = amp[o]
                    px = pf[o, 0]
                    py = pf[o, 1]
                    pz = pf[o, 2]
                    qx = ip[o, 0]
                    qy = ip[o, 1]
                    qz = ip[o, 2]
                    b = 512 * o
                    c = 256 * o
                    bu = np.uint64(b)
                    cu = np.uint64(c)
                    for i in range(s, e):
                        u = _u(i)
                        xf = x[u] * f
                        yf = y[u] * f
                        zf = z[u] * f
                        if single:
                            if dims == 1:
                                if basis == PERLIN:
                                    v = _perlin1_32(xf, px, qx, W, bu, G1, K, periodic)
                                else:
                                    v = _value1_32(xf, px, qx, W, bu, V, cu, mode, K, periodic)
                            elif dims == 2:
                                if basis == PERLIN:
                                    v = _perlin2_32(xf, yf, px, qx, py, qy, W, bu, K, periodic)
                                else:
                                    v = _value2_32(xf, yf, px, qx, py, qy, W, bu, V, cu, mode, K,
                                                   periodic)
                            else:
                                if basis == PERLIN:
                                    v = _perlin3_32(xf, yf, zf, px, qx, py, qy, pz, qz, W, bu, K,
                                                    periodic)
                                else:
                                    v = _value3_32(xf, yf, zf, px, qx, py, qy, pz, qz, W, bu, V, cu,
                                                   mode, K, periodic)
                        elif dims == 1:
                            if basis == PERLIN:
                                v = _perlin1(xf, px, qx, P, b, G1, K, periodic)
                            else:
                                v = _value1(xf, px, qx, P, b, V, c, mode, K, periodic)
                        elif dims == 2:
                            if basis == PERLIN:
                                v = _perlin2(xf, yf, px, qx, py, qy, P, b, K, periodic)
                            else:
                                v = _value2(xf, yf, px, qx, py, qy, P, b, V, c, mode, K, periodic)
                        else:
                            if basis == PERLIN:
                                v = _perlin3(xf, yf, zf, px, qx, py, qy, pz, qz, P, b, K, periodic)
                            else:
                                v = _value3(xf, yf, zf, px, qx, py, qy, pz, qz, P, b, V, c, mode, K,
                                            periodic)
                        v = abs(v) if turbulent else v
                        tmp[_u(i - s)] = a * v
                    if o == 0:
                        for i in range(s, e):
                            out[_u(i)] = tmp[_u(i - s)]
                    else:
                        for i in range(s, e):
                            out[_u(i)] += tmp[_u(i - s)]

    return kernel
