"""Shared fixtures: a session-wide headless GL context (moderngl's own test
style) and full-contrast seamless RGBA test tiles."""

import os
import shutil

import numpy as np
import pytest


@pytest.fixture(scope="session")
def _gl_context():
    try:
        import moderngl
    except ImportError:
        if os.environ.get("CI"):
            pytest.fail("moderngl is required in CI (the GL tests never skip there)")
        pytest.skip("moderngl is not installed")
    try:
        ctx = moderngl.create_standalone_context(backend="egl", require=330)
    except Exception as exc:  # no EGL / no GL 3.3 here: skip the GL tests only
        if os.environ.get("CI"):
            pytest.fail(f"no headless EGL OpenGL 3.3 context in CI: {exc}")
        pytest.skip(f"no headless EGL OpenGL 3.3 context: {exc}")
    yield ctx
    ctx.release()


@pytest.fixture
def gl(_gl_context):
    """The session's EGL context, made current (moderngl sends calls to the current
    context, and another test may have made its own); the GL error state must be
    clean before and after."""
    _gl_context.__enter__()
    assert _gl_context.error == "GL_NO_ERROR"
    yield _gl_context
    assert _gl_context.error == "GL_NO_ERROR"


def make_test_tile(n=256, seed=0, *, cutoff=0.25, beta=1.5):
    """A seamless, full-contrast RGBA tile: FFT-filtered noise, each channel
    stretched to [0, 1]; alpha is an emboss (wrap-around directional
    difference) of the luminance, like the paper's."""
    rng = np.random.default_rng(seed)
    f = np.fft.fftfreq(n)
    r = np.hypot(f[:, None], f[None, :])
    r[0, 0] = 1.0
    amp = r ** -beta * (r < cutoff * 0.5)
    amp[0, 0] = 0.0

    def field():
        x = np.real(np.fft.ifft2(np.fft.fft2(rng.standard_normal((n, n))) * amp))
        return (x - x.min()) / (x.max() - x.min())

    lum = field()
    hue = field()
    col = np.stack([lum, 0.7 * lum + 0.3 * hue, 0.5 * lum + 0.5 * (1 - hue)], axis=-1)
    col = (col - col.min(axis=(0, 1))) / (col.max(axis=(0, 1)) - col.min(axis=(0, 1)))
    emb = (np.roll(lum, 1, 1) - np.roll(lum, -1, 1)) + (np.roll(lum, 1, 0) - np.roll(lum, -1, 0))
    alpha = np.clip(0.5 + emb / (4.0 * emb.std()), 0.0, 1.0)
    return np.concatenate([col, alpha[..., None]], axis=-1).astype(np.float32)


@pytest.fixture(scope="session")
def tile():
    return make_test_tile(256, 0)


@pytest.fixture(scope="session")
def tile_maker():
    return make_test_tile


def glslang_validator() -> str:
    """Path of Debian's ``glslangValidator`` (glslang-tools): a skip without it, a failure under CI=true."""
    path = shutil.which("glslangValidator")
    if path is None:
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail("glslangValidator is missing: CI must have it (apt-get install glslang-tools)")
        pytest.skip("glslangValidator is missing (apt-get install glslang-tools)")
    return path
