"""Tests of spectex.noise: reference values, invariants, dtype rules, errors."""

import math

import numba
import numpy as np
import pytest

from spectex import noise
from spectex.noise import _tables

# ---------------------------------------------------------------- an independent reference
# Ken Perlin's Improved Noise (2002, with the 2003 gradient fix), transcribed
# from the published Java algorithm as plain scalar Python.

_P = list(_tables.PERLIN_PERMUTATION) * 2


def _fade(t):
    return t * t * t * (t * (t * 6 - 15) + 10)


def _lerp(t, a, b):
    return a + t * (b - a)


def _grad(hash_, x, y, z):
    h = hash_ & 15
    u = x if h < 8 else y
    v = y if h < 4 else (x if h == 12 or h == 14 else z)
    return (u if (h & 1) == 0 else -u) + (v if (h & 2) == 0 else -v)


def reference_noise(x, y, z):
    X = math.floor(x) & 255
    Y = math.floor(y) & 255
    Z = math.floor(z) & 255
    x -= math.floor(x)
    y -= math.floor(y)
    z -= math.floor(z)
    u, v, w = _fade(x), _fade(y), _fade(z)
    A = _P[X] + Y
    AA = _P[A] + Z
    AB = _P[A + 1] + Z
    B = _P[X + 1] + Y
    BA = _P[B] + Z
    BB = _P[B + 1] + Z
    return _lerp(w, _lerp(v, _lerp(u, _grad(_P[AA], x, y, z), _grad(_P[BA], x - 1, y, z)),
                          _lerp(u, _grad(_P[AB], x, y - 1, z), _grad(_P[BB], x - 1, y - 1, z))),
                 _lerp(v, _lerp(u, _grad(_P[AA + 1], x, y, z - 1), _grad(_P[BA + 1], x - 1, y, z - 1)),
                       _lerp(u, _grad(_P[AB + 1], x, y - 1, z - 1), _grad(_P[BB + 1], x - 1, y - 1, z - 1))))


def test_perlin_published_value():
    # The value the Java reference prints for noise(3.14, 42, 7).
    assert noise.perlin(3.14, 42.0, 7.0) == pytest.approx(0.13691995878400012, abs=1e-15)


@pytest.mark.parametrize("scale", [1.0, 10.0, 1000.0, 1e6])
def test_perlin_3d_matches_reference(scale):
    rng = np.random.default_rng(int(scale))
    pts = rng.uniform(-scale, scale, size=(3, 400))
    got = noise.perlin(pts[0], pts[1], pts[2])
    want = np.array([reference_noise(*p) for p in pts.T])
    assert np.max(np.abs(got - want)) <= 1e-12
    assert np.std(want) > 0.05  # the comparison is not between zeros


def test_perlin_3d_matches_reference_near_lattice():
    base = np.array([-2.0, -1.0, 0.0, 1.0, 255.0, 256.0, 1e6])
    eps = np.array([-1e-9, 0.0, 1e-9, 0.5, 0.999999])
    x = (base[:, None] + eps[None, :]).ravel()
    X, Y, Z = np.meshgrid(x, x[::3], x[::5], indexing="ij")
    got = noise.perlin(X, Y, Z)
    want = np.vectorize(reference_noise)(X, Y, Z)
    assert np.max(np.abs(got - want)) <= 1e-12


@pytest.mark.parametrize("dims", [1, 2, 3])
@pytest.mark.parametrize("seed", [None, 0, 7])
def test_perlin_zero_on_lattice(dims, seed):
    ints = np.arange(-20, 21, dtype=np.float64)
    coords = np.meshgrid(*([ints] * dims), indexing="ij")
    assert np.all(noise.perlin(*coords, seed=seed) == 0.0)
    # ... and not zero in general
    off = [c + 0.37 for c in coords]
    assert np.mean(noise.perlin(*off, seed=seed) != 0.0) > 0.9


@pytest.mark.parametrize("fn", ["perlin", "value", "fbm", "turbulence"])
@pytest.mark.parametrize("dims", [1, 2, 3])
def test_periodic(fn, dims):
    period = (3, 5, 7)[:dims]
    rng = np.random.default_rng(dims)
    pts = [rng.uniform(-20, 20, 500) for _ in range(dims)]
    f = getattr(noise, fn)
    base = f(*pts, period=period, seed=3)
    assert np.std(base) > 0.01
    for axis in range(dims):
        shifted = [p + (period[axis] if i == axis else 0) for i, p in enumerate(pts)]
        np.testing.assert_allclose(f(*shifted, period=period, seed=3), base, atol=1e-9, rtol=0)
        # A shift by something else than the period changes the noise.
        wrong = [p + (1 if i == axis else 0) for i, p in enumerate(pts)]
        assert np.max(np.abs(f(*wrong, period=period, seed=3) - base)) > 0.1


def test_period_256_is_the_plain_noise():
    rng = np.random.default_rng(0)
    pts = rng.uniform(-600, 600, size=(3, 300))
    np.testing.assert_array_equal(noise.perlin(*pts, period=256), noise.perlin(*pts))


def test_periodic_fbm_needs_whole_lacunarity():
    with pytest.raises(ValueError, match=r"^lacunarity must be a whole number when period is given, got 2\.5$"):
        noise.fbm(0.5, 0.5, period=4, lacunarity=2.5)


@pytest.mark.parametrize("dims,bound,tight", [(1, 1.0, 0.8), (2, 1.0, 0.85), (3, 1.1, 0.95)])
def test_perlin_range(dims, bound, tight):
    rng = np.random.default_rng(1)
    pts = rng.uniform(-50, 50, size=(dims, 400_000))
    v = noise.perlin(*pts)
    assert np.max(np.abs(v)) <= bound
    assert np.max(np.abs(v)) >= tight  # the bound is not vacuous


def test_value_noise_range_and_lattice_values():
    rng = np.random.default_rng(2)
    pts = rng.uniform(-50, 50, size=(2, 100_000))
    for interp in ("linear", "cubic", "quintic"):
        v = noise.value(*pts, interpolation=interp, seed=4)
        assert v.min() >= -1.0 and v.max() <= 1.0
    # At integer points every interpolation gives the lattice value.
    ints = np.arange(-10, 10, dtype=np.float64)
    X, Y = np.meshgrid(ints, ints)
    lat = noise.value(X, Y, interpolation="linear", seed=4)
    for interp in ("cubic", "quintic"):
        np.testing.assert_array_equal(noise.value(X, Y, interpolation=interp, seed=4), lat)


def test_fbm_and_turbulence_ranges():
    rng = np.random.default_rng(3)
    pts = rng.uniform(-50, 50, size=(2, 100_000))
    f = noise.fbm(*pts, octaves=8)
    t = noise.turbulence(*pts, octaves=8)
    assert f.min() >= -1 and f.max() <= 1 and f.std() > 0.1
    assert t.min() >= 0 and t.max() <= 1 and t.std() > 0.05
    # without normalisation the sum is sum(gain**o) times larger
    raw = noise.fbm(*pts, octaves=8, normalize=False)
    np.testing.assert_allclose(raw, f * sum(0.5 ** o for o in range(8)), rtol=1e-12, atol=1e-12)


def test_fbm_seed_none_is_the_fractal_sum_of_reference_noise():
    rng = np.random.default_rng(5)
    pts = rng.uniform(-20, 20, size=(3, 200))
    got = noise.fbm(*pts, octaves=4, seed=None, normalize=False)
    want = sum(noise.perlin(*(pts * 2.0 ** o)) / 2.0 ** o for o in range(4))
    np.testing.assert_allclose(got, want, atol=1e-12)


def _one_sided(f, x0, k, h=1e-3):
    """k-th derivative of f at x0 from the left and from the right (O(h^2) stencils)."""
    def at(i):
        return f(x0 + i * h)
    if k == 1:
        left = (3 * at(0) - 4 * at(-1) + at(-2)) / (2 * h)
        right = (-3 * at(0) + 4 * at(1) - at(2)) / (2 * h)
    else:
        left = (2 * at(0) - 5 * at(-1) + 4 * at(-2) - at(-3)) / h**2
        right = (2 * at(0) - 5 * at(1) + 4 * at(2) - at(3)) / h**2
    return left, right


@pytest.mark.parametrize("interp,order", [("cubic", 1), ("quintic", 2)])
def test_value_noise_continuity_across_cells(interp, order):
    # Across integer cell borders: cubic is C1 (first derivatives agree),
    # quintic C2 (second derivatives agree); the next derivative up jumps
    # (for linear the first, for cubic the second), which is the control.
    x0 = np.arange(-5, 6, dtype=np.float64)

    def f(x, interp=interp):
        return noise.value(x, 0.3, interpolation=interp, seed=9)

    for k in range(1, order + 1):
        left, right = _one_sided(f, x0, k)
        scale = max(1.0, np.max(np.abs(left)))
        assert np.max(np.abs(left - right)) < 1e-3 * scale
    control = "linear" if order == 1 else "cubic"
    left, right = _one_sided(lambda x: f(x, control), x0, order)
    assert np.max(np.abs(left - right)) > 0.05


def test_perlin_c2_across_cells():
    x0 = np.arange(-3, 4, dtype=np.float64)
    h = 1e-4

    def d2(x):
        return (noise.perlin(x + h, 0.4, 0.6) - 2 * noise.perlin(x, 0.4, 0.6) + noise.perlin(x - h, 0.4, 0.6)) / h**2

    left = d2(x0 - 3 * h)
    right = d2(x0 + 3 * h)
    assert np.max(np.abs(left - right)) < 0.05 * max(1.0, np.max(np.abs(left)))


def _radial_slope(field, lo, hi):
    n = field.shape[0]
    power = np.abs(np.fft.fft2(field - field.mean())) ** 2
    f = np.fft.fftfreq(n) * n
    r = np.sqrt(f[None, :] ** 2 + f[:, None] ** 2)
    bins = np.unique(np.round(np.geomspace(lo, hi, 25)))
    k = np.digitize(r.ravel(), bins)
    counts = np.maximum(np.bincount(k, minlength=len(bins) + 1), 1)
    p = np.bincount(k, power.ravel(), minlength=len(bins) + 1) / counts
    rc = np.bincount(k, r.ravel(), minlength=len(bins) + 1) / counts
    idx = np.arange(1, len(bins))
    return np.polyfit(np.log(rc[idx]), np.log(p[idx]), 1)[0]


@pytest.mark.parametrize("gain", [0.35, 0.5, 0.7])
def test_fbm_spectrum_slope_follows_gain(gain):
    # Octave o carries gain**(2o) of the power at frequency 2**o; spread over
    # a 2-D annulus whose area grows as f**2, the radially averaged power
    # density falls as f ** (2 log(gain) / log(2) - 2).
    n, cells, octaves = 512, 4, 7
    x = (np.arange(n) + 0.5) * cells / n
    slopes = []
    for seed in range(3):
        field = noise.fbm(x[None, :], x[:, None], octaves=octaves, gain=gain, seed=seed,
                          period=(cells, cells))
        slopes.append(_radial_slope(field, cells * 2, cells * 2 ** (octaves - 2)))
    expected = 2 * np.log(gain) / np.log(2.0) - 2
    assert abs(np.mean(slopes) - expected) < 0.15


def test_determinism_and_seeds():
    rng = np.random.default_rng(6)
    pts = rng.uniform(-100, 100, size=(2, 10_001)).astype(np.float32)
    a = noise.fbm(*pts, seed=11)
    b = noise.fbm(*pts, seed=11)
    assert a.tobytes() == b.tobytes()
    c = noise.fbm(*pts, seed=12)
    assert np.mean(a != c) > 0.9
    assert np.mean(noise.perlin(*pts, seed=1) != noise.perlin(*pts, seed=2)) > 0.9


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_bit_identical_whatever_the_thread_count(dtype):
    rng = np.random.default_rng(7)
    pts = rng.uniform(-1000, 1000, size=(3, 50_003)).astype(dtype)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = [noise.fbm(*pts, octaves=5).tobytes(), noise.perlin(*pts[:2]).tobytes()]
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = [noise.fbm(*pts, octaves=5).tobytes(), noise.perlin(*pts[:2]).tobytes()]
    finally:
        numba.set_num_threads(before)
    assert one == many


def test_far_from_origin_no_collapse():
    # Non-periodic noise repeats every 256 cells; far away it must be the same
    # function (to rounding), not stripes or a constant.
    rng = np.random.default_rng(8)
    pts = rng.uniform(0, 10, size=(2, 2000))
    near = noise.perlin(*pts)
    far = noise.perlin(pts[0] + 256 * 3906, pts[1] - 256 * 3906)  # about 1e6 away
    np.testing.assert_allclose(far, near, atol=1e-8)
    assert np.std(far) > 0.15


def test_nan_and_inf_coordinates():
    x = np.array([np.nan, 0.5, np.inf, -np.inf, 1e300])
    for f in (noise.perlin, noise.value, noise.fbm, noise.turbulence):
        v = f(x, 0.25)
        assert np.isnan(v[0]) and np.isnan(v[2]) and np.isnan(v[3])
        assert np.isfinite(v[1]) and np.isfinite(v[4])
        v32 = f(x[:4].astype(np.float32), np.float32(0.25))
        assert np.isnan(v32[0]) and np.isfinite(v32[1])



# ---------------------------------------------------------------- the float32 path
# float32 inputs run 32-bit kernels (pair table, 16-lane IR for Perlin 2-D and
# 3-D); they must give the float64 path's noise on the same coordinates, to
# float32 rounding: same lattice hash, same gradients.

_F32_CASES = {
    "perlin": lambda *c: noise.perlin(*c),
    "perlin-periodic": lambda *c: noise.perlin(*c, period=(5, 300, 1000)[:len(c)]),
    "value": lambda *c: noise.value(*c, interpolation="quintic"),
    "value-periodic": lambda *c: noise.value(*c, period=(3, 9, 1000)[:len(c)]),
    "fbm": lambda *c: noise.fbm(*c, octaves=4, seed=3),
    "turbulence": lambda *c: noise.turbulence(*c, octaves=3, seed=4),
}


# Each float32 kernel costs a compile (cached on disk afterwards): the cases
# cover every float32 code path (16-lane Perlin 2-D and 3-D, point-loop Perlin
# 1-D, value noise, periodic lattices) without compiling every combination.
# The periodic ones are the 2-D kernels that tileable textures run (compiled by
# test_procedural and test_periodic anyway), not a 1-D kernel only this test uses.
@pytest.mark.parametrize("kind,dims", [
    ("perlin", 1), ("perlin", 2), ("perlin", 3), ("fbm", 3), ("turbulence", 2),
    ("value", 1), ("value", 2), ("perlin-periodic", 2), ("value-periodic", 2),
])
def test_float32_path_agrees_with_float64(kind, dims):
    rng = np.random.default_rng(9)
    pts = rng.uniform(-1e4, 1e4, size=(dims, 3001)).astype(np.float32)
    pts[:, :1000] = rng.uniform(-600, 600, size=(dims, 1000))  # many cells, both signs
    got = _F32_CASES[kind](*pts)
    want = _F32_CASES[kind](*pts.astype(np.float64))
    assert got.dtype == np.float32
    assert np.max(np.abs(got - want)) < 2e-6
    assert np.std(want) > 0.05


def test_float32_huge_coordinates_take_lattice_index_zero():
    # From 2**31 on every float32 is a multiple of 256; the float32 path
    # converts floor(x) through an int32 and must not overflow there.
    x = np.float32([2.0**31, 2.0**40, -2.0**31, -3e38, 3e38, 5.5])
    y = np.full_like(x, 0.3)
    for f in (noise.value, noise.perlin):
        got = f(x, y)
        want = f(x.astype(np.float64), y.astype(np.float64))
        assert np.max(np.abs(got - want)) < 1e-6
    assert np.all(noise.value(x[:5], np.float32(0.0)) == noise.value(np.float32([0.0]), np.float32(0.0)))


def test_float32_lanes_do_not_depend_on_position():
    # The 16-lane kernels mask the last lanes of a block; a point must give
    # the same bits wherever it sits in the array, alone or among others.
    rng = np.random.default_rng(10)
    pts = rng.uniform(-300, 300, size=(3, 4099)).astype(np.float32)
    for dims in (2, 3):
        whole = noise.fbm(*pts[:dims], octaves=3, seed=2)
        for i in (0, 15, 16, 2047, 2048, 4098):
            single = noise.fbm(*(c[i:i + 1] for c in pts[:dims]), octaves=3, seed=2)
            assert single.tobytes() == whole[i:i + 1].tobytes()


def test_float32_lanes_generic_ir_matches_the_permute_path():
    # Without AVX-512 (VBMI) the 16-lane kernels use generic vector IR: gathers
    # from the pair table and selects for the gradients. Same bits expected.
    from spectex.noise import _kernels, _lanes
    from spectex.noise._api import _constants

    if not _lanes.has_permute():
        pytest.skip("this CPU runs the generic path only")
    rng = np.random.default_rng(11)
    pts = rng.uniform(-700, 700, size=(3, 1000)).astype(np.float32)
    f32 = np.float32
    P, W, P8, V = (np.array(t) for t in _tables.octave_tables(5, 0))  # writable, as in _api
    # kernel(x, y, z, out, P, W, P8, V, G1, freq, amp, pf, ip, mode, turbulent, K)
    rest = (P, W, P8, V.astype(f32), _tables.GRAD1.astype(f32), np.ones(1, f32), np.ones(1, f32),
            np.full((1, 3), 256, f32), np.full((1, 3), 1 / 256, f32), _kernels.QUINTIC, False,
            _constants(f32))
    for dims in (2, 3):
        out = []
        for permute in (True, False):
            o = np.empty(1000, np.float32)
            _kernels.fractal_kernel(dims, _kernels.PERLIN, False, True, permute)(*pts, o, *rest)
            out.append(o)
        assert out[0].tobytes() == out[1].tobytes()
        assert np.array_equal(out[0], noise.perlin(*pts[:dims], seed=5))

@pytest.mark.parametrize("args,expected", [
    ((np.float32(0.5),), np.float32),
    ((np.float32([0.5]), np.float32([0.2])), np.float32),
    ((np.float32([0.5]), 0.25), np.float32),  # Python scalars are weak
    ((np.float64([0.5]), np.float32([0.2])), np.float64),
    ((np.array([1, 2]),), np.float64),
    ((np.float16([0.5]),), np.float64),
    ((0.5, 0.5), np.float64),
    ((np.array([True]),), np.float64),
])
def test_dtype_rules(args, expected):
    for f in (noise.perlin, noise.value, noise.fbm):
        assert f(*args).dtype == expected


def test_broadcasting_and_scalars():
    x = np.linspace(0, 3, 5)[None, :]
    y = np.linspace(0, 2, 4)[:, None]
    v = noise.perlin(x, y)
    assert v.shape == (4, 5)
    np.testing.assert_array_equal(v[2], noise.perlin(x[0], y[2, 0]))
    s = noise.perlin(0.3, 0.7)
    assert isinstance(s, np.float64) and np.ndim(s) == 0
    assert noise.perlin(np.zeros((0, 3))).shape == (0, 3)


def test_gradient_sets():
    g2 = _tables.GRAD2
    np.testing.assert_allclose(np.hypot(g2[:, 0], g2[:, 1]), 1.0)
    angles = np.sort(np.mod(np.degrees(np.arctan2(g2[:, 1], g2[:, 0])), 360))
    np.testing.assert_allclose(np.diff(angles), 22.5, atol=1e-9)  # evenly spaced
    assert np.min(np.abs(g2)) > 0.19  # none on an axis
    assert sorted(_tables.PERLIN_PERMUTATION.tolist()) == list(range(256))
    # 3-D: the twelve cube edges, the four repeats being the paper's.
    edges = {tuple(r) for r in _tables.GRAD3.astype(int).tolist()}
    assert len(edges) == 12 and all(sorted(map(abs, e)) == [0, 1, 1] for e in edges)


@pytest.mark.parametrize("call,exc,message", [
    (lambda: noise.perlin(0.5, seed=-1), ValueError, "seed must be >= 0, got -1"),
    (lambda: noise.perlin(0.5, seed=1.5), TypeError, "seed must be an integer, got 1.5"),
    (lambda: noise.fbm(0.5, octaves=0), ValueError, "octaves must be >= 1, got 0"),
    (lambda: noise.fbm(0.5, octaves=33), ValueError, "octaves must be <= 32, got 33"),
    (lambda: noise.fbm(0.5, basis="simplex"), ValueError,
     "basis must be one of 'perlin', 'value', got 'simplex'"),
    (lambda: noise.value(0.5, interpolation="cosine"), ValueError,
     "interpolation must be one of 'linear', 'cubic', 'quintic', got 'cosine'"),
    (lambda: noise.fbm(0.5, gain=0), ValueError, "gain must be > 0.0, got 0.0"),
    (lambda: noise.fbm(0.5, lacunarity=float("nan")), ValueError, "lacunarity must be finite, got nan"),
    (lambda: noise.perlin(0.5, 0.5, period=(4,)), ValueError,
     "period must be an int or a tuple of 2 ints for 2-D noise, got (4,)"),
    (lambda: noise.perlin(0.5, period=0), ValueError, "period[0] must be >= 1, got 0"),
    (lambda: noise.perlin(0.5, 0.5, period=(4, 2.5)), TypeError, "period[1] must be an integer, got 2.5"),
    (lambda: noise.perlin(0.5, None, 0.5), ValueError,
     "z was given without y: pass x, y and z for 3-D noise"),
    (lambda: noise.perlin(np.array([1 + 2j])), TypeError, "x must hold real numbers, got dtype complex128"),
    (lambda: noise.perlin(np.array(["a"])), TypeError, "x must hold real numbers, got dtype <U1"),
    (lambda: noise.perlin(np.zeros(3), np.zeros(4)), ValueError,
     "coordinates do not broadcast together: x=(3,), y=(4,)"),
    (lambda: noise.fbm(0.5, normalize="yes"), TypeError, "normalize must be True or False, got 'yes'"),
])
def test_error_messages(call, exc, message):
    with pytest.raises(exc) as info:
        call()
    assert str(info.value) == message
