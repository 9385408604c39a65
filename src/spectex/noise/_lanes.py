"""Float32 Perlin noise 16 points at a time, written as LLVM vector IR.

The loop vectoriser widens the float32 point functions of ``_kernels`` to 16
lanes, but every table look-up then becomes a gather, and on Zen 4 the
gathers were the bottleneck. Here the 16 lanes are explicit ``<16 x float>``
/ ``<16 x i32>`` values, so that, with AVX-512 F, BW and VBMI:

* the permutation sits in four 64-byte registers and is read with
  ``vpermi2b`` (``llvm.x86.avx512.vpermi2var.qi.512``): one look-up gives 64
  bytes, four corners of 16 points; the 3-D hash of a cell takes 4 look-ups;
* a gradient component is one ``vpermps`` of a 16-entry register table
  (``llvm.x86.avx512.permvar.sf.512``), as FastNoiseSIMD does.

Other targets get generic IR instead (gathers from the pair table, gradients
by selects, ``fptosi`` after mapping out-of-range values to 0), which LLVM
splits into 8- or 4-lane registers; the results are bit-identical (tested).

One intrinsic call computes all octaves of fBm (or turbulence) for up to 16
consecutive points, keeps the sum in a register and stores it once; lanes
past the end are masked off (masked load and store), so every point, the last
ones of a block included, goes through the same instructions and the result
never depends on a point's position or the thread count.

Arithmetic is that of the float32 point functions: the same lattice index
(``floor(x) & 255`` through an int32, 0 from 2**31 on and for NaN), the same
hash, gradient products that are exact (components are -1, 0, 1 or the
float32 2-D cosines), the quintic fade and ``a + t (b - a)`` lerps.
"""

from __future__ import annotations

import functools

import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils, config
from numba.extending import intrinsic

from . import _tables

LANES = 16
STEP = LANES  # points per call of an intrinsic
_F32 = ir.FloatType()
_I32 = ir.IntType(32)
_VF = ir.VectorType(_F32, LANES)
_VI = ir.VectorType(_I32, LANES)
_VM = ir.VectorType(ir.IntType(1), LANES)
_I8 = ir.IntType(8)
_VB = ir.VectorType(_I8, 4 * LANES)
_FLAGS = ("nsz", "arcp", "contract")


@functools.lru_cache(maxsize=None)
def has_permute() -> bool:
    """Whether numba compiles for a CPU with AVX-512F, BW and VBMI (``vpermps``
    and ``vpermi2b`` on 512-bit registers)."""
    features = config.CPU_FEATURES
    if not features:
        if config.CPU_NAME and config.CPU_NAME != "host":
            return False  # a named target's features are not known here: generic IR
        import llvmlite.binding as llvm
        features = llvm.get_host_cpu_features().flatten()
    have = set(features.split(","))
    return {"+avx512f", "+avx512bw", "+avx512vbmi"} <= have


def _f32(values):
    return [float(np.float32(v)) for v in values]


# Gradient tables (16 entries, indexed by the low 4 bits of a hash), float32.
_G3 = [_f32(_tables.GRAD3[:, k]) for k in range(3)]
_COS = _f32(np.cos(_tables.GRAD2_ANGLES))
# 2-D: angle k = h & 3 has cosine c_k and sine c_{3-k} (as in _kernels._grad2);
# bit 2 flips x, bit 3 flips y.
_G2 = ([(-1.0 if h & 4 else 1.0) * _COS[h & 3] for h in range(16)],
       [(-1.0 if h & 8 else 1.0) * _COS[3 - (h & 3)] for h in range(16)])
_SCALE2 = float(np.float32(_tables.SCALE2))


class _VectorGEP(ir.instructions.Instruction):
    """``getelementptr T, ptr %base, <16 x i32> %idx``: 16 addresses from one
    base (llvmlite's builder only types scalar indices). A gather from such a
    vector keeps 32-bit indices: ``vpgatherdd``."""

    def __init__(self, parent, ptr, idx, element):
        super().__init__(parent, ir.VectorType(ptr.type, idx.type.count), "getelementptr",
                         [ptr, idx])
        self.element = element

    def descr(self, buf):
        p, i = self.operands
        buf.append(f"getelementptr {self.element}, {p.type} {p.get_reference()}, "
                   f"{i.type} {i.get_reference()}\n")


class _Emit:
    """Small helpers that emit 16-lane IR."""

    def __init__(self, builder, permute):
        self.b = builder
        self.permute = permute

    def fc(self, v):
        return ir.Constant(_VF, [float(v)] * LANES)

    def ic(self, v):
        return ir.Constant(_VI, [int(v)] * LANES)

    def splat(self, s, vty):
        v = self.b.insert_element(ir.Constant(vty, ir.Undefined), s, ir.Constant(_I32, 0))
        return self.b.shuffle_vector(v, ir.Constant(vty, ir.Undefined),
                                     ir.Constant(_VI, [0] * LANES))

    def fn(self, name, ret, args):
        return cgutils.get_or_insert_function(self.b.module, ir.FunctionType(ret, args), name)

    def add(self, a, c):
        return self.b.fadd(a, c, flags=_FLAGS)

    def sub(self, a, c):
        return self.b.fsub(a, c, flags=_FLAGS)

    def mul(self, a, c):
        return self.b.fmul(a, c, flags=_FLAGS)

    def fma(self, a, c, d):
        """``a * c + d`` with one rounding (``llvm.fma``): the same bits
        whichever way LLVM would otherwise have contracted the expression."""
        return self.b.call(self.fn("llvm.fma.v16f32", _VF, [_VF, _VF, _VF]), [a, c, d])

    def unary(self, name, a):
        return self.b.call(self.fn(f"llvm.{name}.v16f32", _VF, [_VF]), [a])

    def load(self, ptr, mask):
        p = self.b.bitcast(ptr, _VF.as_pointer())
        f = self.fn("llvm.masked.load.v16f32.p0", _VF, [_VF.as_pointer(), _I32, _VM, _VF])
        return self.b.call(f, [p, ir.Constant(_I32, 4), mask, self.fc(0.0)])

    def store(self, v, ptr, mask):
        p = self.b.bitcast(ptr, _VF.as_pointer())
        f = self.fn("llvm.masked.store.v16f32.p0", ir.VoidType(), [_VF, _VF.as_pointer(), _I32,
                                                                  _VM])
        self.b.call(f, [v, p, ir.Constant(_I32, 4), mask])

    def gather(self, base, idx):
        g = _VectorGEP(self.b.block, base, idx, _I32)
        self.b._insert(g)
        f = self.fn("llvm.masked.gather.v16i32.v16p0", _VI, [g.type, _I32, _VM, _VI])
        return self.b.call(f, [g, ir.Constant(_I32, 4), ir.Constant(_VM, [1] * LANES),
                               self.ic(0)])

    def signed(self, d, g, h):
        """``g[h & 15] * d`` for a table of -1, 0, 1, as bit logic: a permute
        fetches a mask (0, 0x7fffffff, 0xffffffff) and one ``vpternlogd``
        keeps the magnitude bits of ``d`` under it and XORs the sign bit."""
        b = self.b
        masks = [0 if v == 0 else (0x7FFFFFFF if v > 0 else -1) for v in g]
        f = self.fn("llvm.x86.avx512.permvar.si.512", _VI, [_VI, _VI])
        m = b.call(f, [ir.Constant(_VI, masks), h])
        # Bitwise f(d, m, s) = s ? d ^ m : d & m, with s set on the sign bit
        # only: truth table 0x68 for (d, m, s).
        tern = self.fn("llvm.x86.avx512.pternlog.d.512", _VI, [_VI, _VI, _VI, _I32])
        bits = b.call(tern, [b.bitcast(d, _VI), m, self.ic(-0x80000000), ir.Constant(_I32, 0x68)])
        return b.bitcast(bits, _VF)

    def lookup(self, table, h):
        """``table[h & 15]`` per lane: one ``vpermps`` (permute path only)."""
        f = self.fn("llvm.x86.avx512.permvar.sf.512", _VF, [_VF, _VI])
        return self.b.call(f, [ir.Constant(_VF, table), h])

    # -- the permutation as four 64-byte registers (permute path) -------------

    def bytes_(self, v):
        return self.b.bitcast(v, _VB)

    def dwords(self, v):
        return self.b.bitcast(v, _VI)

    def spread(self, v, pattern):
        """Byte k of every 32-bit lane from byte ``pattern[k]`` of that lane."""
        mask = [4 * d + pattern[k] for d in range(LANES) for k in range(4)]
        return self.dwords(self.b.shuffle_vector(self.bytes_(v), ir.Constant(_VB, ir.Undefined),
                                                 ir.Constant(ir.VectorType(_I32, 4 * LANES), mask)))

    def byte_add(self, a, c):
        return self.dwords(self.b.add(self.bytes_(a), self.bytes_(c)))

    def bc(self, pattern):
        """A constant with bytes ``pattern`` (4 values) in every 32-bit lane."""
        return ir.Constant(_VB, [pattern[k] for _ in range(LANES) for k in range(4)])

    def perm_lookup(self, tables, idx):
        """``P[byte]`` for each of the 64 bytes of ``idx``: two 128-entry
        two-register permutes (``vpermi2b``), chosen by bit 7."""
        b = self.b
        f = self.fn("llvm.x86.avx512.vpermi2var.qi.512", _VB, [_VB, _VB, _VB])
        i8 = self.bytes_(idx)
        low = b.call(f, [tables[0], i8, tables[1]])
        high = b.call(f, [tables[2], i8, tables[3]])
        top = b.icmp_signed("<", i8, ir.Constant(_VB, [0] * (4 * LANES)))
        return self.dwords(b.select(top, high, low))

    def flip(self, f, sign):
        """``f`` with its sign bit XORed with bit 31 of ``sign``."""
        b = self.b
        return b.bitcast(b.xor(b.bitcast(f, _VI), sign), _VF)

    def grad3_select(self, h, dx, dy, dz):
        """Perlin's grad() with selects and sign flips (no table)."""
        b = self.b
        zero = self.ic(0)
        u = b.select(b.icmp_unsigned("==", b.and_(h, self.ic(8)), zero), dx, dy)
        below4 = b.icmp_unsigned("==", b.and_(h, self.ic(12)), zero)
        is12or14 = b.icmp_unsigned("==", b.and_(h, self.ic(13)), self.ic(12))
        v = b.select(below4, dy, b.select(is12or14, dx, dz))
        u = self.flip(u, b.shl(h, self.ic(31)))
        v = self.flip(v, b.shl(b.and_(h, self.ic(2)), self.ic(30)))
        return self.add(u, v)

    def grad2_select(self, h, dx, dy):
        """The 2-D gradient product with selects and sign flips (no table):
        angle ``k = h & 3`` has cosine ``c_k`` and sine ``c_{3-k}``."""
        b = self.b
        zero = self.ic(0)
        odd = b.icmp_unsigned("!=", b.and_(h, self.ic(1)), zero)
        high = b.icmp_unsigned("!=", b.and_(h, self.ic(2)), zero)
        k = [self.fc(c) for c in _COS]
        c = b.select(odd, b.select(high, k[3], k[1]), b.select(high, k[2], k[0]))
        s = b.select(odd, b.select(high, k[0], k[2]), b.select(high, k[1], k[3]))
        xs = self.flip(dx, b.shl(b.and_(h, self.ic(4)), self.ic(29)))
        ys = self.flip(dy, b.shl(b.and_(h, self.ic(8)), self.ic(28)))
        return self.fma(c, xs, self.b.fmul(s, ys))

    def cell(self, x):
        """``(X, frac)``: ``X = floor(x) & 255`` in the low byte (0 from 2**31
        on and for NaN)."""
        b = self.b
        fl = self.unary("floor", x)
        if self.permute:
            # AVX-512's conversion is defined for every input: NaN and values
            # out of the int32 range give 0x80000000, whose low byte is 0; the
            # byte look-ups read only the low byte.
            f = self.fn("llvm.x86.avx512.mask.cvttps2dq.512", _VI,
                        [_VF, _VI, ir.IntType(16), _I32])
            X = b.call(f, [fl, self.ic(0), ir.Constant(ir.IntType(16), 0xFFFF),
                           ir.Constant(_I32, 4)])
            return X, self.sub(x, fl)
        # Generic IR: fptosi is undefined out of range, so those inputs are
        # mapped to 0 before the conversion.
        ok = b.fcmp_ordered("<", self.unary("fabs", fl), self.fc(2147483648.0))
        m = b.select(ok, fl, self.fc(0.0))
        return b.and_(b.fptosi(m, _VI), self.ic(255)), self.sub(x, fl)

    def fade(self, t):
        inner = self.add(self.mul(t, self.add(self.mul(t, self.fc(6.0)), self.fc(-15.0))),
                         self.fc(10.0))
        return self.mul(self.mul(self.mul(t, t), t), inner)

    def lerp(self, t, a, c):
        return self.add(a, self.mul(t, self.sub(c, a)))

    def hi(self, w):
        return self.b.lshr(w, self.ic(16))

    def pair(self, base, w, offset):
        """The pair ``W[(w + offset) & 511]``."""
        return self.gather(base, self.b.and_(self.b.add(w, offset), self.ic(511)))


def _make(dims, permute):
    """The intrinsic ``perlin{dims}_lanes(x, y, z, out, i, e, freq, amp, W, P8,
    turbulent)``: all octaves of fBm for points ``i`` to ``min(i + 16, e) - 1``.

    The coordinates are loaded once and the sum stays in a register across the
    octaves (an IR loop); ``out`` is stored once. Octave ``o`` reads its
    tables at ``W[512 o:]`` (pair table) or ``P8[256 o:]`` (bytes).
    """
    def typer(typingctx, x, y, z, out, i, e, freq, amp, W, P8, turbulent):
        sig = types.void(x, y, z, out, i, e, freq, amp, W, P8, turbulent)

        def codegen(context, builder, signature, args):
            em = _Emit(builder, permute)
            data = [context.make_array(signature.args[k])(context, builder, args[k]).data
                    for k in (0, 1, 2, 3, 6, 7, 8, 9)]
            xp, yp, zp, outp, fp, ap, wp, pp = data
            i, e, turb = args[4], args[5], args[10]
            n_oct = context.make_array(signature.args[6])(context, builder, args[6]).nitems
            lane = ir.Constant(_VI, list(range(LANES)))
            rem = builder.trunc(builder.sub(e, i), _I32)
            mask = builder.icmp_signed("<", lane, em.splat(rem, _VI))
            raw = [em.load(builder.gep(p, [i]), mask) for p in (xp, yp, zp)[:dims]]
            i64 = ir.IntType(64)
            pre = builder.block
            body = builder.append_basic_block("octave")
            done = builder.append_basic_block("octaves.done")
            builder.branch(body)
            builder.position_at_end(body)
            o = builder.phi(i64)
            acc = builder.phi(_VF)
            o.add_incoming(ir.Constant(i64, 0), pre)
            acc.add_incoming(em.fc(-0.0), pre)
            fv = em.splat(builder.load(builder.gep(fp, [o])), _VF)
            cells = [em.cell(em.mul(c, fv)) for c in raw]
            if permute:
                base = builder.bitcast(builder.gep(pp, [builder.mul(o, ir.Constant(i64, 256))]),
                                       _VB.as_pointer())
                tables = [builder.load(builder.gep(base, [ir.Constant(_I32, k)]), align=1)
                          for k in range(4)]
                hashes = (_hash3_bytes if dims == 3 else _hash2_bytes)(em, tables, cells)
            else:
                base = builder.gep(wp, [builder.mul(o, ir.Constant(i64, 512))])
                hashes = (_hash3_pairs if dims == 3 else _hash2_pairs)(em, base, cells)
            value = (_perlin3 if dims == 3 else _perlin2)(em, hashes, cells)
            value = builder.select(turb, em.unary("fabs", value), value)
            amp = em.splat(builder.load(builder.gep(ap, [o])), _VF)
            total = em.add(acc, em.mul(value, amp))
            o_next = builder.add(o, ir.Constant(i64, 1))
            o.add_incoming(o_next, builder.block)
            acc.add_incoming(total, builder.block)
            builder.cbranch(builder.icmp_signed("<", o_next, n_oct), body, done)
            builder.position_at_end(done)
            em.store(total, builder.gep(outp, [i]), mask)
            return context.get_dummy_value()

        return sig, codegen

    typer.__name__ = f"perlin{dims}_lanes{'_permute' if permute else ''}"
    return intrinsic(typer)


# Corner hashes. Each function returns the hashes as 32-bit lanes whose low
# 4 bits are the hash's (higher bits are ignored by the gradient look-up).

def _hash3_pairs(em, base, cells):
    """Gathers from the pair table: 7 per 16 points."""
    X, Y, Z = (c[0] for c in cells)
    w = em.gather(base, X)
    q0 = em.pair(base, w, Y)
    q1 = em.pair(base, em.hi(w), Y)
    c00 = em.pair(base, q0, Z)
    c10 = em.pair(base, q1, Z)
    c01 = em.pair(base, em.hi(q0), Z)
    c11 = em.pair(base, em.hi(q1), Z)
    return (c00, c10, c01, c11, em.hi(c00), em.hi(c10), em.hi(c01), em.hi(c11))


def _hash2_pairs(em, base, cells):
    X, Y = (c[0] for c in cells)
    w = em.gather(base, X)
    q0 = em.pair(base, w, Y)
    q1 = em.pair(base, em.hi(w), Y)
    return (q0, q1, em.hi(q0), em.hi(q1))


def _hash_bytes_xy(em, tables, X, Y):
    """``[P[A], P[A + 1], P[B], P[B + 1]]`` in bytes 0-3 of each lane, with
    ``A = P[X] + Y`` and ``B = P[X + 1] + Y`` (all indices mod 256, as the
    doubled table reads them)."""
    # [P[X], P[X], P[X + 1], P[X + 1]], then + [Y, Y + 1, Y, Y + 1].
    r1 = em.perm_lookup(tables, em.byte_add(em.spread(X, (0, 0, 0, 0)), em.bc((0, 0, 1, 1))))
    ab = em.byte_add(r1, em.byte_add(em.spread(Y, (0, 0, 0, 0)), em.bc((0, 1, 0, 1))))
    return em.perm_lookup(tables, ab)


def _hash3_bytes(em, tables, cells):
    """Byte-table look-ups from registers: 4 per 16 points, no gathers."""
    X, Y, Z = (c[0] for c in cells)
    r2 = _hash_bytes_xy(em, tables, X, Y)         # AA - Z, AB - Z, BA - Z, BB - Z
    zz = em.byte_add(em.spread(Z, (0, 0, 0, 0)), em.bc((0, 1, 0, 1)))
    lo = em.perm_lookup(tables, em.byte_add(em.spread(r2, (0, 0, 1, 1)), zz))
    hi = em.perm_lookup(tables, em.byte_add(em.spread(r2, (2, 2, 3, 3)), zz))
    # lo: P[AA], P[AA + 1], P[AB], P[AB + 1]; hi: the same for BA, BB.
    sh = [em.ic(8), em.ic(16), em.ic(24)]
    b = em.b
    return (lo, hi, b.lshr(lo, sh[1]), b.lshr(hi, sh[1]),
            b.lshr(lo, sh[0]), b.lshr(hi, sh[0]), b.lshr(lo, sh[2]), b.lshr(hi, sh[2]))


def _hash2_bytes(em, tables, cells):
    X, Y = (c[0] for c in cells)
    r = _hash_bytes_xy(em, tables, X, Y)          # P[A], P[A + 1], P[B], P[B + 1]
    b = em.b
    return (r, b.lshr(r, em.ic(16)), b.lshr(r, em.ic(8)), b.lshr(r, em.ic(24)))


def _perlin3(em, hashes, cells):
    (_, fx), (_, fy), (_, fz) = cells
    h000, h100, h010, h110, h001, h101, h011, h111 = hashes
    one = em.fc(1.0)
    gx, gy, gz = em.sub(fx, one), em.sub(fy, one), em.sub(fz, one)

    def grad(h, dx, dy, dz):
        if not em.permute:
            return em.grad3_select(h, dx, dy, dz)
        # The first product as bit logic moves work off the multiply pipes
        # (fBm 3-D 15.7 -> 15.0 ns); the other two stay fused multiply-adds.
        r = em.signed(dx, _G3[0], h)
        r = em.add(r, em.mul(em.lookup(_G3[1], h), dy))
        return em.add(r, em.mul(em.lookup(_G3[2], h), dz))

    n000 = grad(h000, fx, fy, fz)
    n100 = grad(h100, gx, fy, fz)
    n010 = grad(h010, fx, gy, fz)
    n110 = grad(h110, gx, gy, fz)
    n001 = grad(h001, fx, fy, gz)
    n101 = grad(h101, gx, fy, gz)
    n011 = grad(h011, fx, gy, gz)
    n111 = grad(h111, gx, gy, gz)
    u, v, t = em.fade(fx), em.fade(fy), em.fade(fz)
    return em.lerp(t,
                   em.lerp(v, em.lerp(u, n000, n100), em.lerp(u, n010, n110)),
                   em.lerp(v, em.lerp(u, n001, n101), em.lerp(u, n011, n111)))


def _perlin2(em, hashes, cells):
    (_, fx), (_, fy) = cells
    h00, h10, h01, h11 = hashes
    one = em.fc(1.0)
    gx, gy = em.sub(fx, one), em.sub(fy, one)

    def grad(h, dx, dy):
        if not em.permute:
            return em.grad2_select(h, dx, dy)
        return em.fma(em.lookup(_G2[0], h), dx, em.b.fmul(em.lookup(_G2[1], h), dy))

    n00 = grad(h00, fx, fy)
    n10 = grad(h10, gx, fy)
    n01 = grad(h01, fx, gy)
    n11 = grad(h11, gx, gy)
    u, v = em.fade(fx), em.fade(fy)
    value = em.lerp(v, em.lerp(u, n00, n10), em.lerp(u, n01, n11))
    return em.mul(value, em.fc(_SCALE2))


perlin2_lanes = _make(2, False)
perlin3_lanes = _make(3, False)
perlin2_lanes_permute = _make(2, True)
perlin3_lanes_permute = _make(3, True)
