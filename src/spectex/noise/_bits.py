"""32-bit gradient selection for the float32 kernels, written as LLVM IR.

Numba types every integer operation at 64 bits (``uint32 & uint32`` is a
``uint64``). LLVM narrows most of that back, but not the bit tests that pick
a gradient: they stayed 64-bit compares on the hash, which split each
16-lane vector into two halves (``vptestnmq`` and mask unpacking, 345
instructions per 16 points instead of 201 for 3-D Perlin). These intrinsics
state the gradient functions directly on 32-bit integers: the hash is an
``i32``, the bit tests are ``i32`` compares, and the sign flips are XORs on
the float's bits (``h << 31`` puts bit 0 of the hash on the sign bit).

The functions are plain scalar IR that the loop vectoriser widens like any
other; nothing here is specific to one instruction set. They are compiled
into the kernels that call them, never at import.
"""

from __future__ import annotations

from llvmlite import ir
from numba import types
from numba.extending import intrinsic

_I32 = ir.IntType(32)
# The kernels' fast-math flags (see _kernels.FASTMATH): rounding-level only.
_FLAGS = ("nsz", "arcp", "contract")


def _k(v):
    return ir.Constant(_I32, v)


def _flip(builder, f, sign):
    """``f`` with its sign bit XORed with bit 31 of ``sign``."""
    bits = builder.xor(builder.bitcast(f, _I32), sign)
    return builder.bitcast(bits, ir.FloatType())


@intrinsic
def grad3(typingctx, h, x, y, z):
    """Perlin's ``grad(h, x, y, z)`` (2003 fix) for float32, bits 0-3 of ``h``.

    ``u = h < 8 ? x : y``; ``v = h < 4 ? y : (h in (12, 14) ? x : z)``;
    ``(h & 1 ? -u : u) + (h & 2 ? -v : v)``. Bits above 3 are ignored.
    """
    if not (isinstance(h, types.Integer) and h.bitwidth == 32 and x == y == z == types.float32):
        return None
    sig = types.float32(h, x, y, z)

    def codegen(context, builder, signature, args):
        hv, xv, yv, zv = args
        u = builder.select(builder.icmp_unsigned("==", builder.and_(hv, _k(8)), _k(0)), xv, yv)
        below4 = builder.icmp_unsigned("==", builder.and_(hv, _k(12)), _k(0))
        is12or14 = builder.icmp_unsigned("==", builder.and_(hv, _k(13)), _k(12))
        v = builder.select(below4, yv, builder.select(is12or14, xv, zv))
        u = _flip(builder, u, builder.shl(hv, _k(31)))
        v = _flip(builder, v, builder.shl(builder.and_(hv, _k(2)), _k(30)))
        return builder.fadd(u, v, flags=_FLAGS)

    return sig, codegen


@intrinsic
def grad2(typingctx, h, x, y, c0, c1, c2, c3):
    """The 2-D gradient dot product for float32, from bits 0-3 of ``h``.

    ``k = h & 3`` picks the angle ``(k + 0.5) pi / 8``, whose cosine is
    ``c_k`` and sine ``c_{3-k}``; bit 2 flips the x component, bit 3 the y
    component. Returns ``gx * x + gy * y``.
    """
    ok = (isinstance(h, types.Integer) and h.bitwidth == 32
          and all(t == types.float32 for t in (x, y, c0, c1, c2, c3)))
    if not ok:
        return None
    sig = types.float32(h, x, y, c0, c1, c2, c3)

    def codegen(context, builder, signature, args):
        hv, xv, yv, k0, k1, k2, k3 = args
        odd = builder.icmp_unsigned("!=", builder.and_(hv, _k(1)), _k(0))
        high = builder.icmp_unsigned("!=", builder.and_(hv, _k(2)), _k(0))
        c = builder.select(odd, builder.select(high, k3, k1), builder.select(high, k2, k0))
        s = builder.select(odd, builder.select(high, k0, k2), builder.select(high, k1, k3))
        xs = _flip(builder, xv, builder.shl(builder.and_(hv, _k(4)), _k(29)))
        ys = _flip(builder, yv, builder.shl(builder.and_(hv, _k(8)), _k(28)))
        return builder.fadd(builder.fmul(c, xs, flags=_FLAGS), builder.fmul(s, ys, flags=_FLAGS),
                            flags=_FLAGS)

    return sig, codegen
