"""Shared fixtures: a session-wide headless GL context (moderngl's own test
style) and full-contrast seamless RGBA test tiles. Plain helpers (no fixtures)
are in ``helpers.py``, imported as ``from helpers import ...``."""

import os

import pytest

from helpers import make_test_tile


@pytest.fixture(scope="session")
def _gl_context():
    from spectex._gl import GLUnavailable, create_context

    try:
        ctx = create_context(what="the GL tests")  # the library's one way to make a context
    except GLUnavailable as exc:  # no moderngl, no EGL or no GL 3.3 here: skip the GL tests only
        if os.environ.get("CI"):
            pytest.fail(f"the GL tests never skip in CI: {exc}")
        pytest.skip(str(exc))
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


@pytest.fixture(scope="session")
def tile():
    return make_test_tile(256, 0)


@pytest.fixture(scope="session")
def tile_maker():
    return make_test_tile
